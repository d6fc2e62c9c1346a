//! Edge samples (`smoothlab sample`, a contract of docs/guide/contracts.md): for every mesh edge with two faces, points
//! and unit normals of the surface at the same points of the edge, evaluated once from each
//! face's patches. Any scheme — polynomial or blended — can so be checked from outside
//! without knowing how its patches are represented:
//!
//! ```text
//! {"edges":[{"faces":[f0,f1],"side0":[{"point":[x,y,z],"normal":[x,y,z]},...],"side1":[...]}]}
//! ```
//!
//! The points are at the fractions of [`crate::surface::joint_fractions`] along the
//! edge from its smaller to its larger vertex (near, not at, the ends, where a parametrisation
//! may be singular). On each side, the patch of that face whose domain contains the point is
//! found by inverting the patch's domain map.

use glam::{DMat3, DVec3};
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::surface::joint_fractions;
use crate::surface::{Patch, Surface};
use crate::tolerance::DOMAIN_ZERO;

/// One sample: a surface point and its unit normal (zero where the patch is singular).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub(crate) struct SamplePoint {
    /// Position.
    pub point: [f64; 3],
    /// Unit normal `Su × Sv / |Su × Sv|`.
    pub normal: [f64; 3],
}

/// The samples of one edge from its two faces.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub(crate) struct EdgeSamples {
    /// The two faces (`side0` is evaluated on the first, `side1` on the second).
    pub faces: [u32; 2],
    /// Samples from the first face.
    pub side0: Vec<SamplePoint>,
    /// The same edge points from the second face, in the same order.
    pub side1: Vec<SamplePoint>,
}

/// The whole file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub(crate) struct SampleFile {
    /// One entry per edge with two faces.
    pub edges: Vec<EdgeSamples>,
}

/// The `(u, v)` of `patch` at the face-barycentric point `target`, if its domain contains it.
fn patch_uv(patch: &Patch, target: DVec3) -> Option<(f64, f64)> {
    let [d0, d1, d2] = patch.domain;
    let map = DMat3::from_cols(d0, d1, d2);
    if map.determinant().abs() < 1e-14 {
        return None;
    }
    let lambda = map.inverse() * target;
    (lambda.min_element() >= -DOMAIN_ZERO).then_some((lambda.y, lambda.z))
}

/// The point and normal of a face's `patches` at the face-barycentric point `target`; errors
/// name the face as the input numbers it (`input_face`).
fn sample_face(
    surface: &Surface,
    patches: &[usize],
    input_face: usize,
    target: DVec3,
) -> Result<SamplePoint> {
    let (patch, (u, v)) = patches
        .iter()
        .find_map(|&p| patch_uv(&surface.patches[p], target).map(|uv| (p, uv)))
        .ok_or_else(|| {
            Error::Invalid(format!(
                "scheme '{}': no patch of face {input_face} covers barycentric point {target}",
                surface.scheme
            ))
        })?;
    let jet = surface.patches[patch].jet(u, v);
    Ok(SamplePoint {
        point: jet.p.to_array(),
        normal: jet.normal().to_array(),
    })
}

/// The edge samples of `surface`, built from `mesh`.
pub(crate) fn edge_samples(surface: &Surface, mesh: &Mesh) -> Result<SampleFile> {
    let mut by_face = vec![Vec::new(); mesh.face_count()];
    for (i, patch) in surface.patches.iter().enumerate() {
        if let Some(list) = by_face.get_mut(patch.face as usize) {
            list.push(i);
        }
    }
    let faces = mesh.faces();
    let mut edges = Vec::new();
    for edge in mesh.edges() {
        let (f0, Some(f1)) = edge.faces else {
            continue;
        };
        let side = |f: u32| -> Result<Vec<SamplePoint>> {
            let corners = faces[f as usize];
            let at =
                |v: u32| DVec3::from_array(std::array::from_fn(|c| f64::from(corners[c] == v)));
            let (a, b) = (at(edge.a), at(edge.b));
            joint_fractions()
                .iter()
                .map(|&s| {
                    let target = (1.0 - s) * a + s * b;
                    sample_face(surface, &by_face[f as usize], mesh.input_face(f), target)
                })
                .collect()
        };
        edges.push(EdgeSamples {
            faces: [f0, f1],
            side0: side(f0)?,
            side1: side(f1)?,
        });
    }
    Ok(SampleFile { edges })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::{Metrics, normal_angle};
    use crate::testing::mesh;

    /// For every scheme with one patch per face, the largest normal angle in the samples is
    /// the metrics' G1 figure (same points, same evaluation); for hb (four patches per face)
    /// the samples still find a patch for every point and agree to G1 precision.
    #[test]
    fn samples_reproduce_the_metrics() {
        let mesh = mesh(crate::mesh::generate::deformed_icosahedron());
        for scheme in crate::schemes::names() {
            let surface = crate::schemes::build(scheme, &mesh, &[]).expect("builds");
            let file = edge_samples(&surface, &mesh).expect("every point covered");
            assert_eq!(file.edges.len(), mesh.edges().len(), "{scheme}");
            let (mut angle, mut gap) = (0.0_f64, 0.0_f64);
            for e in &file.edges {
                assert_eq!(e.side0.len(), e.side1.len());
                for (p, q) in e.side0.iter().zip(&e.side1) {
                    let n = |x: [f64; 3]| DVec3::from_array(x);
                    angle = angle.max(normal_angle(n(p.normal), n(q.normal)));
                    gap = gap.max((n(p.point) - n(q.point)).length());
                }
            }
            let m = Metrics::measure(&surface, &mesh, 0.0);
            let g1 = m.g1_between_faces_max_rad.expect("joints between faces");
            eprintln!("{scheme}: samples {angle:.3e} rad, gap {gap:.1e}; metrics {g1:.3e}");
            assert!(
                gap <= 1e-12 * mesh.bounds().diagonal(),
                "{scheme}: gap {gap}"
            );
            if surface.patches.len() == mesh.face_count() {
                assert!((angle - g1).abs() <= 1e-15, "{scheme}: {angle} vs {g1}");
            } else {
                assert!(angle <= 1e-9 && g1 <= 1e-9, "{scheme}: {angle} vs {g1}");
            }
        }
    }
}
