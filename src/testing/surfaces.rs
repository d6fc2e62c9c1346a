//! Small surfaces with known geometry, for tests and benchmarks that must not depend on a
//! scheme: a closed sphere-like surface of eight Bézier triangles over the octahedron, and a
//! height-field patch whose vertical rays have exact answers.

use glam::DVec3;

use crate::bezier::TriangleBezier;
use crate::surface::{Patch, PatchGeometry, Surface};

/// The eight faces of the octahedron with corners ±X, ±Y, ±Z, counter-clockwise seen from
/// outside.
pub fn octahedron_faces() -> Vec<[DVec3; 3]> {
    let mut faces = Vec::new();
    for sx in [1.0, -1.0] {
        for sy in [1.0, -1.0] {
            for sz in [1.0, -1.0] {
                let (a, b, c) = (DVec3::X * sx, DVec3::Y * sy, DVec3::Z * sz);
                faces.push(if sx * sy * sz > 0.0 {
                    [a, b, c]
                } else {
                    [a, c, b]
                });
            }
        }
    }
    faces
}

/// A closed surface of eight degree-`degree` Bézier triangles approximating the sphere of
/// radius `radius`: control point `b(i,j,k)` of face (A, B, C) is the radial projection of
/// `(iA + jB + kC)/d`. Edge control points depend only on the edge's two corners, so
/// neighbouring patches share their boundary curves exactly: the surface is watertight.
/// Each face is split into `4^split_levels` patches (its control net subdivided), so the patch
/// count can be scaled for benchmarks.
pub fn octahedron_sphere(degree: usize, radius: f64, split_levels: u32) -> Surface {
    let mut patches = Vec::new();
    for (f, [a, b, c]) in octahedron_faces().into_iter().enumerate() {
        let net = TriangleBezier::from_fn(degree, |i, j, k| {
            (a * i as f64 + b * j as f64 + c * k as f64).normalize() * radius
        });
        let mut pieces = vec![(net, crate::surface::WHOLE_FACE)];
        for _ in 0..split_levels {
            pieces = pieces
                .into_iter()
                .flat_map(|(net, dom)| {
                    let mid = |p: usize, q: usize| 0.5 * (dom[p] + dom[q]);
                    let (m01, m12, m20) = (mid(0, 1), mid(1, 2), mid(2, 0));
                    let local = [
                        DVec3::X,
                        DVec3::Y,
                        DVec3::Z,
                        DVec3::new(0.5, 0.5, 0.0),
                        DVec3::new(0.0, 0.5, 0.5),
                        DVec3::new(0.5, 0.0, 0.5),
                    ];
                    let children = [
                        ([local[0], local[3], local[5]], [dom[0], m01, m20]),
                        ([local[3], local[1], local[4]], [m01, dom[1], m12]),
                        ([local[5], local[4], local[2]], [m20, m12, dom[2]]),
                        ([local[3], local[4], local[5]], [m01, m12, m20]),
                    ];
                    children
                        .into_iter()
                        .map(|(corners, domain)| (net.subdivide(corners), domain))
                        .collect::<Vec<_>>()
                })
                .collect();
        }
        for (piece, (net, domain)) in pieces.into_iter().enumerate() {
            patches.push(Patch {
                face: f as u32,
                piece: (piece % 256) as u8,
                domain,
                geometry: PatchGeometry::Bezier(net),
            });
        }
    }
    Surface {
        scheme: "octahedron-sphere".into(),
        warnings: Vec::new(),
        spike_face_pairs: Vec::new(),
        params: vec![],
        patches,
    }
}

/// A cubic height-field patch over the triangle (0,0), (1,0), (0,1) of the xy-plane with
/// `x = u`, `y = v` exactly (control points on the uniform planar grid: linear precision), and
/// heights `z(i, j, k)` chosen to make a curved, non-symmetric bump. A vertical ray through
/// `(x, y)` hits it at `(u, v) = (x, y)`.
pub fn height_field_patch() -> Surface {
    let d = 3usize;
    let net = TriangleBezier::from_fn(d, |i, j, k| {
        let (x, y) = (j as f64 / d as f64, k as f64 / d as f64);
        let z = 0.3 * (i as f64 * 1.3 - j as f64 * 0.7 + (k * k) as f64 * 0.25).sin();
        DVec3::new(x, y, z)
    });
    Surface {
        scheme: "height-field".into(),
        warnings: Vec::new(),
        spike_face_pairs: Vec::new(),
        params: vec![],
        patches: vec![Patch {
            face: 0,
            piece: 0,
            domain: crate::surface::WHOLE_FACE,
            geometry: PatchGeometry::Bezier(net),
        }],
    }
}
