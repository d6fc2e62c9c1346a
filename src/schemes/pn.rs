//! `pn`: curved PN triangles (Vlachos, Peters, Boyd, Mitchell 2001, "Curved PN Triangles"),
//! one cubic Bézier patch per face from the corner positions and vertex normals alone.
//!
//! Each boundary control point is the edge's third point projected into the tangent plane of
//! the nearer corner, so the patch is tangent to the vertex normal at every corner, but the
//! cross-boundary tangents of two neighbours are not coordinated: the surface is C⁰ with a
//! normal jump along edges — the baseline that shows what "not G1" looks like in every metric
//! and picture. Works on open meshes (it is purely local).

use glam::DVec3;

use crate::bezier::TriangleBezier;
use crate::error::Result;
use crate::mesh::Mesh;
use crate::schemes::{AtFoldedVertex, Params, SchemeSpec};
use crate::surface::{Patch, PatchGeometry, Surface};

/// Registry entry.
pub const SPEC: SchemeSpec = SchemeSpec {
    name: "pn",
    summary: "PN triangles (Vlachos et al. 2001): cubic per face from vertex normals, C0",
    params: &[crate::schemes::NORMALS_PARAM],
    needs_closed_mesh: false,
    bytes_per_face: 600.0,
    build,
};

fn build(mesh: &Mesh, params: &Params) -> Result<Surface> {
    let (normals, warnings) =
        crate::schemes::scheme_normals(mesh, params, SPEC.name, AtFoldedVertex::Warn)?;
    let positions = mesh.positions();
    let patches = mesh
        .faces()
        .iter()
        .enumerate()
        .map(|(f, corners)| {
            let p = corners.map(|v| positions[v as usize]);
            let n = corners.map(|v| normals[v as usize]);
            Patch {
                face: f as u32,
                piece: 0,
                domain: crate::surface::WHOLE_FACE,
                geometry: PatchGeometry::Bezier(pn_triangle(p, n)),
            }
        })
        .collect();
    let mut surface = params.surface(SPEC.name, patches);
    surface.warnings = warnings;
    Ok(surface)
}

/// The cubic PN triangle of corners `p` with unit vertex normals `n`.
///
/// Edge points: `b210 = (2 P1 + P2 − w12 N1) / 3` with `w_ij = (Pj − Pi)·Ni`, i.e. the point a
/// third along the edge projected into the tangent plane at P1; centre `b111 = E + (E − V)/2`
/// with E the mean of the six edge points and V the mean of the corners (this choice
/// reproduces quadratics). In smoothlab's indexing corner `p[0]` is `b(3,0,0)`, `p[1]` is
/// `b(0,3,0)`, `p[2]` is `b(0,0,3)`.
pub fn pn_triangle(p: [DVec3; 3], n: [DVec3; 3]) -> TriangleBezier {
    // Third point of edge (a → b) next to corner a, moved into a's tangent plane.
    let edge_point = |a: usize, b: usize| {
        let w = (p[b] - p[a]).dot(n[a]);
        (2.0 * p[a] + p[b] - w * n[a]) / 3.0
    };
    let b210 = edge_point(0, 1);
    let b120 = edge_point(1, 0);
    let b021 = edge_point(1, 2);
    let b012 = edge_point(2, 1);
    let b102 = edge_point(2, 0);
    let b201 = edge_point(0, 2);
    let e = (b210 + b120 + b021 + b012 + b102 + b201) / 6.0;
    let v = (p[0] + p[1] + p[2]) / 3.0;
    let b111 = e + (e - v) / 2.0;
    TriangleBezier::from_fn(3, |i, j, k| match (i, j, k) {
        (3, 0, 0) => p[0],
        (0, 3, 0) => p[1],
        (0, 0, 3) => p[2],
        (2, 1, 0) => b210,
        (1, 2, 0) => b120,
        (0, 2, 1) => b021,
        (0, 1, 2) => b012,
        (1, 0, 2) => b102,
        (2, 0, 1) => b201,
        _ => b111,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat triangle with normals perpendicular to its plane stays the flat triangle
    /// (linear precision), parametrised linearly.
    #[test]
    fn flat_input_gives_the_plane() {
        let p = [
            DVec3::ZERO,
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.5, 1.5, 0.0),
        ];
        let patch = pn_triangle(p, [DVec3::Z; 3]);
        for (u, v) in [(0.2, 0.3), (0.0, 0.7), (0.5, 0.5), (1.0 / 3.0, 1.0 / 3.0)] {
            let expected = (1.0 - u - v) * p[0] + u * p[1] + v * p[2];
            let got = patch.eval(DVec3::new(1.0 - u - v, u, v));
            assert!(
                (got - expected).length() < 1e-15,
                "({u},{v}): {got} vs {expected}"
            );
        }
    }

    /// At every corner the patch interpolates the vertex and its tangent plane is the plane
    /// orthogonal to the given normal (the defining property of PN triangles).
    #[test]
    fn corners_interpolate_positions_and_normals() {
        let p = [
            DVec3::new(1.0, 0.0, 0.1),
            DVec3::new(0.0, 1.0, -0.2),
            DVec3::new(-0.7, -0.6, 0.3),
        ];
        let n = [
            DVec3::new(0.3, 0.1, 1.0).normalize(),
            DVec3::new(-0.2, 0.4, 1.0).normalize(),
            DVec3::new(0.1, -0.3, 1.0).normalize(),
        ];
        let patch = pn_triangle(p, n);
        for (c, uv) in crate::surface::UV_CORNERS.iter().enumerate() {
            let jet = patch.jet(uv.x, uv.y);
            assert!((jet.p - p[c]).length() < 1e-15, "corner {c}");
            let angle = jet
                .normal()
                .cross(n[c])
                .length()
                .atan2(jet.normal().dot(n[c]));
            assert!(angle < 1e-12, "corner {c}: normal off by {angle} rad");
        }
    }

    /// Vertices X, Y, Z of the unit sphere with the sphere's normals: the centre point follows
    /// E + (E − V)/2, and the edge midpoint is the hand-computed (5/8)(X + Y) (edge points
    /// X + Y/3 and Y + X/3, Bernstein weights 1/8, 3/8, 3/8, 1/8).
    #[test]
    fn centre_point_follows_the_formula() {
        let p = [DVec3::X, DVec3::Y, DVec3::Z];
        let patch = pn_triangle(p, p);
        let third = |a: DVec3, b: DVec3| (2.0 * a + b - (b - a).dot(a) * a) / 3.0;
        let e = (third(p[0], p[1])
            + third(p[1], p[0])
            + third(p[1], p[2])
            + third(p[2], p[1])
            + third(p[2], p[0])
            + third(p[0], p[2]))
            / 6.0;
        let v = (p[0] + p[1] + p[2]) / 3.0;
        assert!((patch.point(1, 1) - (1.5 * e - 0.5 * v)).length() < 1e-15);
        let mid = patch.eval(DVec3::new(0.5, 0.5, 0.0));
        assert!(
            (mid - 0.625 * (DVec3::X + DVec3::Y)).length() < 1e-15,
            "{mid}"
        );
    }
}
