//! Mesh file formats other than OBJ (PLY, OFF, STL) and the choice of a reader by the file's
//! extension.
//!
//! Every reader turns its file into a [`PolygonMesh`](super::polygon::PolygonMesh) (positions and polygons in file order)
//! and hands it to [`polygon::assemble`], the path OBJ files take too: triangulation of convex
//! planar polygons, welding, validation and orientation are the same for every format.

mod off;
mod ply;
mod stl;

use std::path::Path;

use super::polygon;
use super::{LoadOptions, LoadReport, Mesh, obj};
use crate::error::{Error, Result};

/// A mesh file format, chosen by the file's extension (case-insensitive).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MeshFormat {
    /// Wavefront OBJ (`.obj`): positions, optional normals, polygons.
    Obj,
    /// Polygon File Format (`.ply`), ASCII or binary of either byte order.
    Ply,
    /// Object File Format (`.off`), ASCII.
    Off,
    /// Stereolithography (`.stl`), ASCII or binary: one separate triangle per facet.
    Stl,
}

impl MeshFormat {
    /// Every supported format, in the order the extensions are listed in messages.
    pub const ALL: [MeshFormat; 4] = [
        MeshFormat::Obj,
        MeshFormat::Ply,
        MeshFormat::Off,
        MeshFormat::Stl,
    ];

    /// The file extension, lower case, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            MeshFormat::Obj => "obj",
            MeshFormat::Ply => "ply",
            MeshFormat::Off => "off",
            MeshFormat::Stl => "stl",
        }
    }

    /// The format's name in messages (`OBJ`, `PLY`, `OFF`, `STL`).
    pub fn name(self) -> &'static str {
        match self {
            MeshFormat::Obj => "OBJ",
            MeshFormat::Ply => "PLY",
            MeshFormat::Off => "OFF",
            MeshFormat::Stl => "STL",
        }
    }

    /// The supported extensions as `.obj, .ply, .off, .stl`.
    pub fn supported_extensions() -> String {
        MeshFormat::ALL
            .iter()
            .map(|f| format!(".{}", f.extension()))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The format of `path` by its extension, ignoring case; [`Error::UnknownMeshFormat`]
    /// naming the file and the supported extensions for any other.
    pub fn from_path(path: &Path) -> Result<MeshFormat> {
        let extension = path.extension().map(|e| e.to_string_lossy().to_lowercase());
        MeshFormat::ALL
            .into_iter()
            .find(|f| extension.as_deref() == Some(f.extension()))
            .ok_or_else(|| Error::UnknownMeshFormat {
                path: path.to_path_buf(),
                extension: extension.map_or("(no extension)".to_string(), |e| format!("'.{e}'")),
                supported: MeshFormat::supported_extensions(),
            })
    }
}

/// Reads a mesh in `format` from the file's bytes; `origin` names the file in errors.
pub(super) fn parse(
    bytes: &[u8],
    format: MeshFormat,
    origin: &Path,
    options: &LoadOptions,
) -> Result<(Mesh, LoadReport)> {
    let polygons = match format {
        MeshFormat::Obj => {
            let text = std::str::from_utf8(bytes).map_err(|e| Error::MalformedObj {
                path: origin.to_path_buf(),
                message: format!("not UTF-8 text ({e})"),
            })?;
            return obj::parse(text, origin, options);
        }
        MeshFormat::Ply => ply::read(bytes, origin)?,
        MeshFormat::Off => off::read(bytes, origin)?,
        MeshFormat::Stl => stl::read(bytes, origin)?,
    };
    polygon::assemble(
        polygons,
        None,
        Err(format!(
            "the mesh was read from a {} file, which smoothlab reads no normals from",
            format.name()
        )),
        &[],
        options,
    )
}

/// The lines of a text file with their 1-based numbers. Any of LF, CR LF and CR (old Mac
/// files) ends a line, so that line numbers in messages are those an editor shows.
pub(super) fn numbered_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    let mut rest = Some(text);
    std::iter::from_fn(move || {
        let text = rest?;
        match text.find(['\n', '\r']) {
            Some(end) => {
                let after = if text[end..].starts_with("\r\n") {
                    end + 2
                } else {
                    end + 1
                };
                rest = (after < text.len()).then(|| &text[after..]);
                Some(&text[..end])
            }
            None => {
                rest = None;
                (!text.is_empty()).then_some(text)
            }
        }
    })
    .enumerate()
    .map(|(i, line)| (i + 1, line))
}

/// [`Error::MalformedMesh`] for a file in `format`.
fn malformed(origin: &Path, format: MeshFormat, message: String) -> Error {
    Error::MalformedMesh {
        path: origin.to_path_buf(),
        format: format.name(),
        message,
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::MeshFormat;
    use crate::error::Error;

    #[test]
    fn lines_end_at_lf_crlf_and_cr_alike() {
        for text in [
            "a\nb\n\nc",
            "a\r\nb\r\n\r\nc\r\n",
            "a\rb\r\rc\r",
            "a\nb\r\n\rc",
        ] {
            let lines: Vec<(usize, &str)> = super::numbered_lines(text).collect();
            assert_eq!(lines, [(1, "a"), (2, "b"), (3, ""), (4, "c")], "{text:?}");
        }
        assert_eq!(super::numbered_lines("").count(), 0);
    }

    #[test]
    fn extensions_choose_the_format_ignoring_case() {
        for (name, format) in [
            ("a.obj", MeshFormat::Obj),
            ("dir.v2/b.PLY", MeshFormat::Ply),
            ("c.Off", MeshFormat::Off),
            ("d.stl", MeshFormat::Stl),
        ] {
            assert_eq!(MeshFormat::from_path(Path::new(name)).unwrap(), format);
        }
    }

    #[test]
    fn an_unknown_extension_names_the_file_and_the_supported_ones() {
        for (name, shown) in [("mesh.gltf", "'.gltf'"), ("dir.obj/mesh", "(no extension)")] {
            let err = MeshFormat::from_path(Path::new(name)).unwrap_err();
            assert!(matches!(err, Error::UnknownMeshFormat { .. }), "{err:?}");
            assert_eq!(
                err.to_string(),
                format!(
                    "{name}: unknown mesh format {shown}; supported extensions: .obj, .ply, \
                     .off, .stl"
                )
            );
        }
    }
}
