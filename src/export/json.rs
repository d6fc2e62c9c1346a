//! The patch JSON of docs/guide/contracts.md:
//!
//! ```text
//! {"format":"smoothlab-patches","version":1,"scheme":"hb","params":{...},
//!  "patches":[{"face":12,"piece":0,"degree":5,"points":[[x,y,z],...]}, ...]}
//! ```
//!
//! `points` are in smoothlab's order of multi-indices (i from d down to 0, then j from d−i
//! down to 0; `b(d,0,0)` first, at barycentric (1,0,0)). A blended patch
//! ([`crate::blend::BlendPatch`]) is written as `"kind":"blend"` with its weight family
//! (`"weights":"nielson"` or `"fang-mann"`, and `"t"`) and the three sub-surfaces' points one
//! after the other in `points` (`3 (d+1)(d+2)/2` of them; sub-surface `i` owns the edge
//! opposite corner `i`). Numbers are written in the shortest
//! form that reads back to the same f64, and read back exactly, so a round trip reproduces
//! the surface bit for bit.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::bezier::TriangleBezier;
use crate::blend::WeightFamily;
use crate::error::{Error, Result};
use crate::surface::{PatchGeometry, Surface};

/// Value of the `kind` field of a blended patch.
pub(crate) const BLEND_KIND: &str = "blend";

/// Value of the `format` field.
pub(crate) const FORMAT_NAME: &str = "smoothlab-patches";
/// Value of the `version` field.
pub(crate) const FORMAT_VERSION: u32 = 1;

/// One patch record.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub(crate) struct PatchRecord {
    /// The mesh face the patch belongs to.
    pub face: u32,
    /// Which piece of the face it is.
    pub piece: u8,
    /// Polynomial degree (of the sub-surfaces, for a blend).
    pub degree: usize,
    /// Absent for a Bézier patch; [`BLEND_KIND`] for a blend.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kind: Option<String>,
    /// A blend's weight family: `nielson` or `fang-mann`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub weights: Option<String>,
    /// A blend's order `t` (Fang–Mann) or power (Nielson).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub t: Option<u32>,
    /// Control points in smoothlab's order (a blend: its three sub-surfaces in turn).
    pub points: Vec<[f64; 3]>,
}

impl PatchRecord {}

fn record(face: u32, piece: u8, geometry: &PatchGeometry) -> PatchRecord {
    let xyz = |b: &TriangleBezier| b.control_points().map(|p| p.to_array()).collect::<Vec<_>>();
    match geometry {
        PatchGeometry::Bezier(b) => PatchRecord {
            face,
            piece,
            degree: b.degree(),
            kind: None,
            weights: None,
            t: None,
            points: xyz(b),
        },
        PatchGeometry::Blend(blend) => {
            let (name, t) = match blend.family() {
                WeightFamily::Nielson { power } => ("nielson", power),
                WeightFamily::FangMann { t } => ("fang-mann", t),
            };
            PatchRecord {
                face,
                piece,
                degree: blend.degree(),
                kind: Some(BLEND_KIND.to_string()),
                weights: Some(name.to_string()),
                t: Some(t),
                points: blend.sub_surfaces().iter().flat_map(xyz).collect(),
            }
        }
    }
}

/// A whole patch file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub(crate) struct PatchFile {
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
    /// The records of `surface`.
    pub(crate) fn from_surface(surface: &Surface) -> Result<PatchFile> {
        let patches = surface
            .patches
            .iter()
            .map(|patch| record(patch.face, patch.piece, &patch.geometry))
            .collect();
        Ok(PatchFile {
            format: FORMAT_NAME.to_string(),
            version: FORMAT_VERSION,
            scheme: surface.scheme.clone(),
            params: surface.params.iter().cloned().collect(),
            patches,
        })
    }
}

/// The patch JSON text of `surface`.
pub fn to_json(surface: &Surface) -> Result<String> {
    let file = PatchFile::from_surface(surface)?;
    serde_json::to_string(&file).map_err(|e| Error::Invalid(format!("patch JSON: {e}")))
}

/// Test-only items: used by the unit tests of this and other modules, compiled only for them.
#[cfg(test)]
pub(crate) mod test_support {
    use super::*;
    use crate::bezier::triangle::point_count;
    use crate::blend::BlendPatch;

    impl PatchRecord {
        /// How many nets the record holds: one, or three for a blend.
        fn nets(&self) -> usize {
            if self.kind.is_some() { 3 } else { 1 }
        }

        /// The patch geometry the record describes (checked by [`PatchFile::parse`]).
        pub(crate) fn geometry(&self) -> PatchGeometry {
            let n = point_count(self.degree);
            let net = |k: usize| {
                let points = self.points[k * n..(k + 1) * n].iter().map(|&p| p.into());
                TriangleBezier::new(self.degree, points.collect())
            };
            match (self.weights.as_deref(), self.t) {
                (Some(family), Some(t)) if self.kind.is_some() => {
                    let family = if family == "nielson" {
                        WeightFamily::Nielson { power: t }
                    } else {
                        WeightFamily::FangMann { t }
                    };
                    PatchGeometry::Blend(Box::new(BlendPatch::new(
                        family,
                        [net(0), net(1), net(2)],
                    )))
                }
                _ => PatchGeometry::Bezier(net(0)),
            }
        }
    }

    impl PatchFile {
        /// Parses and checks a patch file: format name, version, and for every patch the number
        /// of points its degree needs and finite coordinates (errors name the patch).
        pub(crate) fn parse(text: &str) -> Result<PatchFile> {
            let file: PatchFile = serde_json::from_str(text)
                .map_err(|e| Error::Invalid(format!("patch JSON: {e}")))?;
            if file.format != FORMAT_NAME || file.version != FORMAT_VERSION {
                return Err(Error::Invalid(format!(
                    "patch JSON: format '{}' version {} (expected '{FORMAT_NAME}' version \
                     {FORMAT_VERSION})",
                    file.format, file.version
                )));
            }
            for (index, record) in file.patches.iter().enumerate() {
                if let Some(kind) = record.kind.as_deref() {
                    let known = matches!(record.weights.as_deref(), Some("nielson" | "fang-mann"));
                    if kind != BLEND_KIND || !known || record.t.is_none() {
                        return Err(Error::Invalid(format!(
                            "patch JSON: patch {index} has kind '{kind}' without known weights \
                             and t (expected kind '{BLEND_KIND}', weights nielson or fang-mann)"
                        )));
                    }
                }
                let expected = record.nets() * point_count(record.degree);
                if record.points.len() != expected {
                    return Err(Error::Invalid(format!(
                        "patch JSON: patch {index} has degree {} but {} points (expected {expected})",
                        record.degree,
                        record.points.len(),
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

        /// The geometry of every record (checked by [`PatchFile::parse`]).
        pub(crate) fn geometries(&self) -> Vec<PatchGeometry> {
            self.patches.iter().map(PatchRecord::geometry).collect()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::blend::BlendPatch;
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
            domain: crate::surface::WHOLE_FACE,
            geometry: PatchGeometry::Bezier(b),
        };
        let blend = |family| Patch {
            face: 9,
            piece: 0,
            domain: crate::surface::WHOLE_FACE,
            geometry: PatchGeometry::Blend(Box::new(BlendPatch::new(
                family,
                [
                    cubic.clone(),
                    cubic.map_points(|p| p * 0.3),
                    cubic.map_points(|p| -p),
                ],
            ))),
        };
        Surface {
            scheme: "test".into(),
            warnings: Vec::new(),
            spike_face_pairs: Vec::new(),
            params: vec![("alpha".into(), "0.5".into())],
            patches: vec![
                patch(4, 1, quadratic),
                patch(7, 0, cubic.clone()),
                blend(WeightFamily::FangMann { t: 2 }),
                blend(WeightFamily::Nielson { power: 1 }),
            ],
        }
    }

    #[test]
    fn round_trip_reproduces_the_surface_exactly() {
        let surface = sample_surface();
        let text = to_json(&surface).expect("exportable");
        let file = PatchFile::parse(&text).expect("reads back");
        assert_eq!(file.scheme, "test");
        assert_eq!(file.params.get("alpha").map(String::as_str), Some("0.5"));
        let geometries = file.geometries();
        assert_eq!(geometries.len(), surface.patches.len());
        for ((record, read), patch) in file.patches.iter().zip(&geometries).zip(&surface.patches) {
            assert_eq!((record.face, record.piece), (patch.face, patch.piece));
            assert_eq!(read, &patch.geometry, "control points bit for bit");
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
        assert!(
            value["patches"][0].get("kind").is_none(),
            "Bézier records have no kind"
        );
        let blend = &value["patches"][2];
        assert_eq!(blend["kind"], "blend");
        assert_eq!(blend["weights"], "fang-mann");
        assert_eq!(blend["t"], 2);
        assert_eq!(blend["degree"], 3);
        assert_eq!(blend["points"].as_array().map(Vec::len), Some(30));
        assert_eq!(value["patches"][3]["weights"], "nielson");
    }

    #[test]
    fn wrong_point_count_names_the_patch() {
        let text = r#"{"format":"smoothlab-patches","version":1,"scheme":"x","params":{},
            "patches":[{"face":0,"piece":0,"degree":1,"points":[[0,0,0],[1,0,0],[0,1,0]]},
                       {"face":1,"piece":0,"degree":2,"points":[[0,0,0]]}]}"#;
        let err = PatchFile::parse(text).expect_err("bad count");
        assert!(err.to_string().contains("patch 1"), "{err}");
        let blend = r#"{"format":"smoothlab-patches","version":1,"scheme":"x","params":{},
            "patches":[{"face":0,"piece":0,"degree":1,"kind":"blend","weights":"nielson","t":1,
                        "points":[[0,0,0],[1,0,0],[0,1,0]]}]}"#;
        let err = PatchFile::parse(blend).expect_err("a blend needs three nets");
        assert!(err.to_string().contains("expected 9"), "{err}");
        let unknown = blend.replace("\"nielson\"", "\"coons\"");
        let err = PatchFile::parse(&unknown).expect_err("unknown weights");
        assert!(err.to_string().contains("patch 0"), "{err}");
    }
}
