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
use crate::mesh::{Mesh, crease_tangent};
use crate::schemes::{AtFoldedVertex, Params, SchemeSpec};
use crate::surface::{Patch, PatchGeometry, Surface};

/// Registry entry.
pub(crate) const SPEC: SchemeSpec = SchemeSpec {
    name: "pn",
    summary: "PN triangles (Vlachos et al. 2001): cubic per face from vertex normals, C0",
    params: &[crate::schemes::NORMALS_PARAM],
    needs_closed_mesh: false,
    bytes_per_face: 600.0,
    sharp_edges: crate::schemes::SharpEdgeSupport::Builds,
    build,
};

fn build(mesh: &Mesh, params: &Params) -> Result<Surface> {
    let (normals, warnings) =
        crate::schemes::scheme_normals(mesh, params, SPEC.name, AtFoldedVertex::Warn)?;
    let positions = mesh.positions();
    let corner_normals = mesh.corner_normals(&normals);
    let patches = mesh
        .faces()
        .iter()
        .enumerate()
        .map(|(f, corners)| {
            let p = corners.map(|v| positions[v as usize]);
            let n = corner_normals[f];
            let mut patch = pn_triangle(p, n);
            let sharp: Vec<usize> = (0..3).filter(|&e| mesh.is_sharp(f as u32, e)).collect();
            for &e in &sharp {
                crease_edge(&mut patch, mesh, &corner_normals, f, e);
            }
            if !sharp.is_empty() {
                recentre(&mut patch);
            }
            Patch {
                face: f as u32,
                piece: 0,
                domain: crate::surface::WHOLE_FACE,
                geometry: PatchGeometry::Bezier(patch),
            }
        })
        .collect();
    let mut surface = params.surface(SPEC.name, patches);
    surface.warnings = warnings;
    Ok(surface)
}

/// Replaces the two edge points of sharp edge `e` of face `f` by the crease cubic's: at each
/// end the edge's third along [`crease_tangent`] of the normals of the two sectors there (this
/// face's and its neighbour's). The centre point keeps the plain formula: it is not on the edge.
fn crease_edge(
    patch: &mut TriangleBezier,
    mesh: &Mesh,
    corner_normals: &[[DVec3; 3]],
    f: usize,
    e: usize,
) {
    let Some((g, ge)) = mesh.neighbor(f as u32, e) else {
        return;
    };
    let face = mesh.faces()[f];
    let positions = mesh.positions();
    // Corner c of f is corner (ge + 1) of g, and corner c + 1 of f is corner ge of g.
    let ends = [(e, (ge + 1) % 3), ((e + 1) % 3, ge)];
    let point = |(c, cg): (usize, usize), other: usize| {
        let (pa, pb) = (positions[face[c] as usize], positions[face[other] as usize]);
        let t = crease_tangent(
            pb - pa,
            corner_normals[f][c],
            corner_normals[g as usize][cg],
        );
        pa + t / 3.0
    };
    let near_first = point(ends[0], ends[1].0);
    let near_second = point(ends[1], ends[0].0);
    // Edge e of the face runs from corner e to corner e + 1: its inner control points are
    // b(2,1,0), b(1,2,0) for e = 0, b(0,2,1), b(0,1,2) for e = 1, b(1,0,2), b(2,0,1) for e = 2.
    let index = |corner: usize, weight: usize| {
        let mut ijk = [0usize; 3];
        ijk[corner] = weight;
        ijk
    };
    debug_assert!(patch.degree() == 3, "PN triangles are cubic");
    let (a, b) = (e, (e + 1) % 3);
    let mut first = index(a, 2);
    first[b] = 1;
    let mut second = index(b, 2);
    second[a] = 1;
    patch.set_point(first[0], first[1], near_first);
    patch.set_point(second[0], second[1], near_second);
}

/// Sets the centre point `b(1,1,1)` from the patch's edge points by the PN rule
/// `E + (E − V)/2` (after edge points were moved onto a crease).
fn recentre(patch: &mut TriangleBezier) {
    let edge_points = [(2, 1), (1, 2), (0, 2), (0, 1), (1, 0), (2, 0)];
    let e = edge_points
        .iter()
        .map(|&(i, j)| patch.point(i, j))
        .sum::<DVec3>()
        / 6.0;
    let v = (patch.point(3, 0) + patch.point(0, 3) + patch.point(0, 0)) / 3.0;
    patch.set_point(1, 1, e + (e - v) / 2.0);
}

/// The cubic PN triangle of corners `p` with unit vertex normals `n`.
///
/// Edge points: `b210 = (2 P1 + P2 − w12 N1) / 3` with `w_ij = (Pj − Pi)·Ni`, i.e. the point a
/// third along the edge projected into the tangent plane at P1; centre `b111 = E + (E − V)/2`
/// with E the mean of the six edge points and V the mean of the corners (this choice
/// reproduces quadratics). In smoothlab's indexing corner `p[0]` is `b(3,0,0)`, `p[1]` is
/// `b(0,3,0)`, `p[2]` is `b(0,0,3)`.
pub(crate) fn pn_triangle(p: [DVec3; 3], n: [DVec3; 3]) -> TriangleBezier {
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

    /// A cube with its 12 edges sharp: every patch is its flat face (the sector normals are
    /// the face normals, the crease cubics are the straight edges), and the two sides of every
    /// edge have bit-identical boundary control points.
    #[test]
    fn sharp_cube_edges_stay_straight_and_sides_flat() {
        let (positions, faces) = crate::mesh::generate::cube();
        let options = crate::mesh::LoadOptions {
            crease_angle: Some(40.0),
            ..Default::default()
        };
        let (mesh, _) = Mesh::from_triangles_with(positions, faces, &options).unwrap();
        let surface = build(&mesh, &crate::testing::params(&SPEC, &[])).unwrap();
        let bezier = |f: usize| surface.patches[f].as_bezier().unwrap().clone();
        // The edge's four control points from corner e to corner e + 1.
        let edge = |b: &TriangleBezier, e: usize| -> [DVec3; 4] {
            let (a, c) = (e, (e + 1) % 3);
            std::array::from_fn(|k| {
                let mut ijk = [0usize; 3];
                ijk[a] = 3 - k;
                ijk[c] = k;
                b.point(ijk[0], ijk[1])
            })
        };
        for f in 0..mesh.face_count() {
            let b = bezier(f);
            let n = mesh.face_normal(f as u32);
            let p0 = b.point(3, 0);
            for p in b.control_points() {
                assert!((p - p0).dot(n).abs() < 1e-15, "face {f}: {p}");
            }
            for e in 0..3 {
                let (g, ge) = mesh.neighbor(f as u32, e).unwrap();
                let mut there = edge(&bezier(g as usize), ge);
                there.reverse();
                assert_eq!(edge(&b, e), there, "face {f} edge {e}");
            }
        }
    }
}
