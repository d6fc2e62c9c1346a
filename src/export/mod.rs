//! Writing surfaces for other tools: the patch JSON of docs/guide/contracts.md ([`json`]), BezierView's
//! `.bv` files ([`bezierview`]), a tessellated OBJ with exact normals ([`obj`]) and the edge
//! samples of `smoothlab sample` ([`samples`]).
//!
//! Every writer returns the file's text; the caller decides where it goes.

pub(crate) mod bezierview;
pub(crate) mod json;
pub(crate) mod obj;
pub(crate) mod samples;

pub use json::to_json;
pub use obj::MAX_TESS;

use crate::error::{Error, Result};
use crate::surface::Surface;

/// An export format (`--format`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// `smoothlab-patches` JSON (Bézier control points of every patch).
    Json,
    /// BezierView type-3 triangular patch records.
    BezierView,
    /// Triangle mesh sampled from the patches, with exact normals.
    Obj,
}

impl Format {
    /// The formats' names for `export --format`, each with what `export --help` says of it.
    pub const CHOICES: [(&'static str, &'static str); 3] = [
        ("json", "smoothlab-patches JSON."),
        ("bv", "BezierView type-3 records."),
        (
            "obj",
            "Tessellated OBJ with exact normals, welded along patch edges.",
        ),
    ];

    /// The format a file name asks for by its extension (`.json`, `.bv`, `.obj`, any case), for
    /// `export -o FILE` without `--format`; an error naming the file otherwise.
    pub fn from_path(path: &std::path::Path) -> Result<Format> {
        let extension = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match extension.as_deref() {
            Some("json") => Ok(Format::Json),
            Some("bv") => Ok(Format::BezierView),
            Some("obj") => Ok(Format::Obj),
            _ => Err(Error::Invalid(format!(
                "{}: the export format cannot be told from the file name (.json, .bv or .obj): \
                 give --format json|bv|obj",
                path.display()
            ))),
        }
    }

    /// Parses a `--format` value.
    pub fn parse(name: &str) -> Result<Format> {
        match name {
            "json" => Ok(Format::Json),
            "bv" => Ok(Format::BezierView),
            "obj" => Ok(Format::Obj),
            _ => Err(Error::unknown_name(
                "export format",
                name,
                &crate::error::names(Self::CHOICES),
            )),
        }
    }
}

/// The text of `surface` in `format`; `tess` is the number of subdivisions per patch edge
/// for [`Format::Obj`] and is ignored otherwise.
///
/// A surface with a NaN or infinite control point is refused, naming the patch and its face
/// as `input_face` numbers it (the input's own face numbering,
/// [`crate::mesh::Mesh::input_face`]; `&|face| face as usize` for a surface's own numbering).
pub fn export(
    surface: &Surface,
    format: Format,
    tess: usize,
    input_face: &dyn Fn(u32) -> usize,
) -> Result<String> {
    if let Some(index) = surface.first_non_finite_patch() {
        return Err(Error::NonFiniteResult {
            what: format!(
                "a control point of patch {index} (face {})",
                input_face(surface.patches[index].face)
            ),
            value: surface.patches[index]
                .control_points()
                .map(|p| p.length())
                .find(|x| !x.is_finite())
                .unwrap_or(f64::NAN),
        });
    }
    match format {
        Format::Json => json::to_json(surface),
        Format::BezierView => bezierview::to_bv(surface, input_face),
        Format::Obj => obj::to_obj(surface, tess, input_face),
    }
}

/// Writes [`export`]'s text of `surface` in `format` to `path` as `smoothlab export` writes
/// it: the path checked first ([`check_writable`](crate::files::check_writable)), the file
/// written atomically ([`write_atomic`](crate::files::write_atomic): a complete file or the
/// old one, never a part); errors name faces as `input_face` numbers them.
pub fn write(
    surface: &Surface,
    format: Format,
    tess: usize,
    input_face: &dyn Fn(u32) -> usize,
    path: &std::path::Path,
) -> Result<()> {
    crate::files::check_writable(path)?;
    crate::files::write_atomic(path, export(surface, format, tess, input_face)?.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_parse_by_name() {
        assert_eq!(Format::parse("json").ok(), Some(Format::Json));
        assert_eq!(Format::parse("bv").ok(), Some(Format::BezierView));
        assert_eq!(Format::parse("obj").ok(), Some(Format::Obj));
        let err = Format::parse("stl").expect_err("unknown format");
        assert!(err.to_string().contains("'stl'"), "{err}");
    }

    #[test]
    fn formats_follow_the_file_extension() {
        use std::path::Path;
        assert_eq!(
            Format::from_path(Path::new("a/b.json")).ok(),
            Some(Format::Json)
        );
        assert_eq!(
            Format::from_path(Path::new("b.BV")).ok(),
            Some(Format::BezierView)
        );
        assert_eq!(
            Format::from_path(Path::new("b.obj")).ok(),
            Some(Format::Obj)
        );
        for name in ["b.stl", "b", "b.json.gz"] {
            let err = Format::from_path(Path::new(name)).expect_err("no format");
            assert!(err.to_string().contains("give --format"), "{name}: {err}");
        }
    }
}
