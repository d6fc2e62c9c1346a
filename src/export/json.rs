//! The patch JSON of DESIGN.md:
//!
//! ```text
//! {"format":"smoothlab-patches","version":1,"scheme":"hb","params":{...},
//!  "patches":[{"face":12,"piece":0,"degree":5,"points":[[x,y,z],...]}, ...]}
//! ```
//!
//! `points` are in smoothlab's order of multi-indices (i from d down to 0, then j from d−i
//! down to 0; `b(d,0,0)` first, at barycentric (1,0,0)). Numbers are written in the shortest
//! form that reads back to the same f64, and read back exactly, so a round trip reproduces
//! the surface bit for bit.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::bezier::TriangleBezier;
use crate::bezier::triangle::point_count;
use crate::error::{Error, Result};
use crate::surface::Surface;

/// Value of the `format` field.
pub const FORMAT_NAME: &str = "smoothlab-patches";
/// Value of the `version` field.
pub const FORMAT_VERSION: u32 = 1;

/// One patch record.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PatchRecord {
    /// The mesh face the patch belongs to.
    pub face: u32,
    /// Which piece of the face it is.
    pub piece: u8,
    /// Polynomial degree.
    pub degree: usize,
    /// Control points in smoothlab's order.
    pub points: Vec<[f64; 3]>,
}

/// A whole patch file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PatchFile {
    /// Always [`FORMAT_NAME`].
    pub format: String,
    /// Always [`FORMAT_VERSION`].
    pub version: u32,
    /// The scheme that built the surface.
    pub scheme: String,
    /// Its parameters, defaults filled in.
    pub params: BTreeMap<String, String>,
    /// The patches, in the surface's order (so `patch_id` of the renderer indexes this list).
    pub patches: Vec<PatchRecord>,
}

impl PatchFile {
    /// The records of `surface`. Fails on a patch with no Bézier form, naming it.
    pub fn from_surface(surface: &Surface) -> Result<PatchFile> {
        let patches = surface
            .patches
            .iter()
            .enumerate()
            .map(|(index, patch)| {
                let bezier = patch.as_bezier().ok_or_else(|| {
                    Error::Invalid(format!(
                        "patch {index} (face {}, piece {}) is not polynomial and has no \
                         Bézier control points to export",
                        patch.face, patch.piece
                    ))
                })?;
                Ok(PatchRecord {
                    face: patch.face,
                    piece: patch.piece,
                    degree: bezier.degree(),
                    points: bezier.points().iter().map(|p| p.to_array()).collect(),
                })
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(PatchFile {
            format: FORMAT_NAME.to_string(),
            version: FORMAT_VERSION,
            scheme: surface.scheme.clone(),
            params: surface.params.iter().cloned().collect(),
            patches,
        })
    }

    /// Parses and checks a patch file: format name, version, and for every patch the number
    /// of points its degree needs and finite coordinates (errors name the patch).
    pub fn parse(text: &str) -> Result<PatchFile> {
        let file: PatchFile =
            serde_json::from_str(text).map_err(|e| Error::Invalid(format!("patch JSON: {e}")))?;
        if file.format != FORMAT_NAME || file.version != FORMAT_VERSION {
            return Err(Error::Invalid(format!(
                "patch JSON: format '{}' version {} (expected '{FORMAT_NAME}' version \
                 {FORMAT_VERSION})",
                file.format, file.version
            )));
        }
        for (index, record) in file.patches.iter().enumerate() {
            if record.points.len() != point_count(record.degree) {
                return Err(Error::Invalid(format!(
                    "patch JSON: patch {index} has degree {} but {} points (expected {})",
                    record.degree,
                    record.points.len(),
                    point_count(record.degree)
                )));
            }
            if record.points.iter().flatten().any(|x| !x.is_finite()) {
                return Err(Error::Invalid(format!(
                    "patch JSON: patch {index} has a non-finite coordinate"
                )));
            }
        }
        Ok(file)
    }

    /// The Bézier triangles of the records (checked by [`PatchFile::parse`]).
    pub fn triangles(&self) -> Vec<TriangleBezier> {
        self.patches
            .iter()
            .map(|r| TriangleBezier::new(r.degree, r.points.iter().map(|&p| p.into()).collect()))
            .collect()
    }
}

/// The patch JSON text of `surface`.
pub fn to_json(surface: &Surface) -> Result<String> {
    let file = PatchFile::from_surface(surface)?;
    serde_json::to_string(&file).map_err(|e| Error::Invalid(format!("patch JSON: {e}")))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::{Patch, PatchGeometry};
    use glam::DVec3;

    /// Two patches with coordinates that have no short decimal form.
    fn sample_surface() -> Surface {
        let quadratic = TriangleBezier::from_fn(2, |i, j, k| {
            DVec3::new(
                (i as f64 + 0.1).sqrt(),
                (j as f64 * 0.7).sin() / 3.0,
                1e-17 + k as f64 * std::f64::consts::PI,
            )
        });
        let cubic = TriangleBezier::from_fn(3, |i, j, k| {
            DVec3::new(
                i as f64 / 7.0,
                -(j as f64).exp(),
                (k as f64 + 1.0).ln() * 1e5,
            )
        });
        let patch = |face, piece, b| Patch {
            face,
            piece,
            domain: [DVec3::X, DVec3::Y, DVec3::Z],
            geometry: PatchGeometry::Bezier(b),
        };
        Surface {
            scheme: "test".into(),
            params: vec![("alpha".into(), "0.5".into())],
            patches: vec![patch(4, 1, quadratic), patch(7, 0, cubic)],
        }
    }

    #[test]
    fn round_trip_reproduces_the_surface_exactly() {
        let surface = sample_surface();
        let text = to_json(&surface).expect("exportable");
        let file = PatchFile::parse(&text).expect("reads back");
        assert_eq!(file.scheme, "test");
        assert_eq!(file.params.get("alpha").map(String::as_str), Some("0.5"));
        let triangles = file.triangles();
        assert_eq!(triangles.len(), surface.patches.len());
        for ((record, read), patch) in file.patches.iter().zip(&triangles).zip(&surface.patches) {
            assert_eq!((record.face, record.piece), (patch.face, patch.piece));
            assert_eq!(Some(read), patch.as_bezier(), "control points bit for bit");
            for (u, v) in [(0.1, 0.2), (0.5, 0.25), (0.0, 1.0), (1.0 / 3.0, 1.0 / 3.0)] {
                let bary = DVec3::new(1.0 - u - v, u, v);
                assert_eq!(read.eval(bary), patch.eval(u, v), "at ({u}, {v})");
            }
        }
    }

    #[test]
    fn layout_follows_the_contract() {
        let text = to_json(&sample_surface()).expect("exportable");
        let value: serde_json::Value = serde_json::from_str(&text).expect("valid JSON");
        assert_eq!(value["format"], "smoothlab-patches");
        assert_eq!(value["version"], 1);
        assert_eq!(value["patches"][0]["face"], 4);
        assert_eq!(value["patches"][0]["piece"], 1);
        assert_eq!(value["patches"][0]["degree"], 2);
        assert_eq!(
            value["patches"][1]["points"].as_array().map(Vec::len),
            Some(10)
        );
        // b(2,0,0) first: x = sqrt(2.1).
        assert_eq!(value["patches"][0]["points"][0][0], 2.1_f64.sqrt());
    }

    #[test]
    fn wrong_point_count_names_the_patch() {
        let text = r#"{"format":"smoothlab-patches","version":1,"scheme":"x","params":{},
            "patches":[{"face":0,"piece":0,"degree":1,"points":[[0,0,0],[1,0,0],[0,1,0]]},
                       {"face":1,"piece":0,"degree":2,"points":[[0,0,0]]}]}"#;
        let err = PatchFile::parse(text).expect_err("bad count");
        assert!(err.to_string().contains("patch 1"), "{err}");
    }
}
