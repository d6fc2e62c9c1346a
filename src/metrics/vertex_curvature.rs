//! Curvature of the built surface at the mesh vertices, against the curvature the mesh implies
//! there.
//!
//! A vertex-local G¹ scheme fixes the first and second derivatives of every boundary curve at a
//! mesh vertex from the vertex's one-ring alone [HB00 §6, eqs. 11–15]. If the second-derivative
//! points lie in the tangent plane (HB00's `γ2 = 0`), every normal curvature there vanishes and
//! the vertex is a *flat point* of the surface, however curved the mesh is around it. This module
//! counts such vertices and compares the surface's mean curvature at each vertex with the mesh's
//! discrete one.
//!
//! The mesh's discrete normal curvature towards a neighbour `p` of `v` is the curvature of the
//! circle through `v` and `p` tangent to the vertex's plane: `κ(p) = 2 (p − v)·N / |p − v|²`
//! (exact when the mesh vertices lie on a sphere), with `N` the angle-weighted normal of the
//! incident faces. Its mean over the ring (each neighbour counted once per incident face) is
//! the discrete mean curvature `H_mesh`; the largest `|κ(p)|` is the vertex's curvature scale.
//!
//! The surface's curvature at a vertex is taken at every patch corner on it
//! ([`Surface::vertex_corners`]); a corner whose parametrisation is singular there (e.g. a
//! blended patch, whose curvature has no limit at its corners) is left out.

use glam::DVec3;
use rayon::prelude::*;

use crate::surface::{Surface, UV_CORNERS};

/// A vertex is *curved* in the mesh when its curvature scale times its mean edge length
/// exceeds this: a mesh bend of about a micro-radian per edge (planar vertices are left out).
pub(crate) const MESH_CURVED: f64 = 1e-6;

/// A curved vertex is a *flat point* of the surface when both principal curvatures at every
/// patch corner on it are at most this fraction of the mesh's curvature scale there.
pub(crate) const FLAT_FRACTION: f64 = 1e-3;

/// `(κ1, κ2, H)` at one patch corner.
pub(crate) type CornerCurvature = (f64, f64, f64);

/// The vertex figures of one surface.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct VertexCurvature {
    /// Curved mesh vertices (see [`MESH_CURVED`]) at which the surface has a flat point.
    pub flat_points: usize,
    /// Curved mesh vertices measured.
    pub curved_vertices: usize,
    /// Smallest `|H| / |H_mesh|` over the curved vertices with `H_mesh ≠ 0` (`|H|` averaged over
    /// the patch corners on the vertex); `None` if there are none.
    pub mean_ratio_min: Option<f64>,
    /// Largest `|H| / |H_mesh|`.
    pub mean_ratio_max: Option<f64>,
}

/// The discrete curvature of the mesh at every vertex: `(H_mesh, curvature scale, mean edge
/// length)`, each 0 for a vertex without faces.
pub(crate) fn mesh_vertex_curvature(
    faces: &[[u32; 3]],
    positions: &[DVec3],
) -> Vec<(f64, f64, f64)> {
    let n = positions.len();
    let mut normal = vec![DVec3::ZERO; n];
    for f in faces {
        let p = f.map(|v| positions[v as usize]);
        let face_normal = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
        for k in 0..3 {
            let (a, b) = (p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]);
            let angle = a.cross(b).length().atan2(a.dot(b));
            normal[f[k] as usize] += angle * face_normal;
        }
    }
    let normal: Vec<DVec3> = normal.iter().map(|m| m.normalize_or_zero()).collect();
    // (Σ κ, max |κ|, Σ edge length, count) over the (vertex, neighbour) pairs of every face.
    let mut acc = vec![(0.0, 0.0_f64, 0.0, 0usize); n];
    for f in faces {
        for k in 0..3 {
            let v = f[k] as usize;
            for step in [1, 2] {
                let d = positions[f[(k + step) % 3] as usize] - positions[v];
                let len2 = d.length_squared();
                if len2 > 0.0 {
                    let kappa = 2.0 * d.dot(normal[v]) / len2;
                    let a = &mut acc[v];
                    a.0 += kappa;
                    a.1 = a.1.max(kappa.abs());
                    a.2 += len2.sqrt();
                    a.3 += 1;
                }
            }
        }
    }
    acc.iter()
        .map(|&(sum, max, len, count)| {
            if count == 0 {
                (0.0, 0.0, 0.0)
            } else {
                (sum / count as f64, max, len / count as f64)
            }
        })
        .collect()
}

/// Principal curvatures `(κ1, κ2, H)` of the surface at every patch corner on a mesh vertex,
/// grouped by vertex (corners with a singular parametrisation left out).
pub(crate) fn surface_vertex_curvature(
    surface: &Surface,
    faces: &[[u32; 3]],
    vertex_count: usize,
) -> Vec<Vec<CornerCurvature>> {
    let corners = surface.vertex_corners(faces);
    let measured: Vec<Option<(u32, CornerCurvature)>> = corners
        .par_iter()
        .map(|vc| {
            let uv = UV_CORNERS[vc.corner as usize];
            let k = surface.patches[vc.patch as usize]
                .jet(uv.x, uv.y)
                .curvature()?;
            (k.k1.is_finite() && k.k2.is_finite()).then_some((vc.vertex, (k.k1, k.k2, k.mean)))
        })
        .collect();
    let mut out = vec![Vec::new(); vertex_count];
    for (v, k) in measured.into_iter().flatten() {
        if let Some(slot) = out.get_mut(v as usize) {
            slot.push(k);
        }
    }
    out
}

/// Flat points and mean-curvature ratios of `surface` at the vertices of the mesh `faces` over
/// `positions`.
pub fn vertex_curvature(
    surface: &Surface,
    faces: &[[u32; 3]],
    positions: &[DVec3],
) -> VertexCurvature {
    let mesh = mesh_vertex_curvature(faces, positions);
    let at_vertex = surface_vertex_curvature(surface, faces, positions.len());
    let mut out = VertexCurvature::default();
    for (&(h_mesh, scale, edge), corners) in mesh.iter().zip(&at_vertex) {
        if scale * edge <= MESH_CURVED || corners.is_empty() {
            continue;
        }
        out.curved_vertices += 1;
        let largest = corners
            .iter()
            .map(|&(k1, k2, _)| k1.abs().max(k2.abs()))
            .fold(0.0, f64::max);
        if largest <= FLAT_FRACTION * scale {
            out.flat_points += 1;
        }
        if h_mesh.abs() * edge > MESH_CURVED {
            let h = corners.iter().map(|c| c.2.abs()).sum::<f64>() / corners.len() as f64;
            let ratio = h / h_mesh.abs();
            out.mean_ratio_min = Some(out.mean_ratio_min.map_or(ratio, |m| m.min(ratio)));
            out.mean_ratio_max = Some(out.mean_ratio_max.map_or(ratio, |m| m.max(ratio)));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::surfaces::{octahedron_faces, octahedron_sphere};

    /// On an octahedron with its vertices on a sphere of radius 2, the discrete mean curvature
    /// is the sphere's: every neighbour lies on the sphere, so `κ(p) = −1/2` exactly.
    #[test]
    fn discrete_curvature_of_points_on_a_sphere_is_the_spheres() {
        let faces: Vec<[u32; 3]> = vec![
            [0, 2, 4],
            [2, 1, 4],
            [1, 3, 4],
            [3, 0, 4],
            [2, 0, 5],
            [1, 2, 5],
            [3, 1, 5],
            [0, 3, 5],
        ];
        let r = 2.0;
        let positions: Vec<DVec3> = [
            DVec3::X,
            -DVec3::X,
            DVec3::Y,
            -DVec3::Y,
            DVec3::Z,
            -DVec3::Z,
        ]
        .map(|p| r * p)
        .to_vec();
        for (h, scale, edge) in mesh_vertex_curvature(&faces, &positions) {
            assert!((h + 1.0 / r).abs() < 1e-15, "{h}");
            assert!((scale - 1.0 / r).abs() < 1e-15);
            assert!((edge - r * 2f64.sqrt()).abs() < 1e-15);
        }
    }

    /// The flat surface (the mesh itself) has a flat point at every curved vertex; a sphere
    /// made of octants (octahedron faces mapped to the sphere) has none, and its `|H|` at the
    /// vertices is the sphere's to the accuracy of the degree-4 octants.
    #[test]
    fn flat_points_of_the_mesh_itself_and_none_on_a_sphere() {
        let corners = octahedron_faces();
        let mut positions: Vec<DVec3> = Vec::new();
        let mut faces = Vec::new();
        for tri in &corners {
            let f = tri.map(|p| {
                let k = positions
                    .iter()
                    .position(|q| (*q - p).length() < 1e-12)
                    .unwrap_or_else(|| {
                        positions.push(p);
                        positions.len() - 1
                    });
                k as u32
            });
            faces.push(f);
        }
        let flat = Surface {
            scheme: "flat".into(),
            warnings: Vec::new(),
            spike_face_pairs: Vec::new(),
            params: Vec::new(),
            patches: faces
                .iter()
                .enumerate()
                .map(|(f, fv)| crate::surface::Patch {
                    face: f as u32,
                    piece: 0,
                    domain: [DVec3::X, DVec3::Y, DVec3::Z],
                    geometry: crate::surface::PatchGeometry::Bezier(
                        crate::bezier::TriangleBezier::new(
                            1,
                            fv.map(|v| positions[v as usize]).to_vec(),
                        ),
                    ),
                })
                .collect(),
        };
        let m = vertex_curvature(&flat, &faces, &positions);
        assert_eq!((m.flat_points, m.curved_vertices), (6, 6), "{m:?}");
        assert_eq!(m.mean_ratio_max, Some(0.0));
        let sphere = octahedron_sphere(4, 1.0, 0);
        let m = vertex_curvature(&sphere, &faces, &positions);
        assert_eq!((m.flat_points, m.curved_vertices), (0, 6), "{m:?}");
        let (lo, hi) = (m.mean_ratio_min.unwrap(), m.mean_ratio_max.unwrap());
        assert!(lo > 0.5 && hi < 2.0, "{m:?}");
    }
}
