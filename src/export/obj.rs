//! Tessellated OBJ: every patch sampled on a regular grid of `tess` subdivisions per edge,
//! `(tess+1)(tess+2)/2` vertices shared by the triangles of that patch, each with the
//! patch's exact unit normal `Su × Sv / |Su × Sv|` as `vn` (not an average of facet normals),
//! so shading in any viewer shows the true normal field, jumps included. Patches do not share
//! vertices with each other: a gap or kink between patches stays visible.
//!
//! Triangles are wound counter-clockwise in the patch's `(u, v)` domain, so they face the
//! way the patch normal points.

use std::fmt::Write;

use glam::{DVec2, DVec3};

use crate::error::{Error, Result};
use crate::surface::{Patch, Surface};

/// Number of grid vertices of one patch at `tess` subdivisions per edge.
pub const fn grid_vertex_count(tess: usize) -> usize {
    (tess + 1) * (tess + 2) / 2
}

/// Index of grid vertex `(i, j)` (`u = i/tess`, `v = j/tess`, `i + j ≤ tess`) within its
/// patch: rows of constant i, j increasing.
pub const fn grid_index(tess: usize, i: usize, j: usize) -> usize {
    // Rows 0..i hold (tess+1) + tess + … + (tess+2−i) vertices.
    i * (tess + 1) - i * (i.saturating_sub(1)) / 2 + j
}

/// The unit normal of `patch` at `uv`. Where `Su × Sv = 0` (a singular point, typically a
/// corner where the parametrisation degenerates) the normal is the limit from inside: it is
/// taken at points moved towards the patch centre by growing steps until one is regular.
pub fn exact_normal(patch: &Patch, uv: DVec2) -> DVec3 {
    let centre = DVec2::splat(1.0 / 3.0);
    for step in [0.0, 1e-9, 1e-6, 1e-3] {
        let at = uv + (centre - uv) * step;
        let n = patch.jet(at.x, at.y).normal();
        if n != DVec3::ZERO {
            return n;
        }
    }
    DVec3::ZERO
}

pub use crate::budget::MAX_TESS;

/// Bytes of the OBJ text of `patches` patches at `tess` subdivisions per edge, estimated
/// from the records' typical lengths (a `v` and a `vn` line of about 60 bytes each per
/// vertex, an `f` line of about 40 bytes per triangle).
pub fn estimated_bytes(patches: usize, tess: usize) -> f64 {
    let (vertices, triangles) = (grid_vertex_count(tess) as f64, (tess * tess) as f64);
    patches as f64 * (120.0 * vertices + 40.0 * triangles)
}

/// The OBJ text of `surface` tessellated with `1 ≤ tess ≤` [`MAX_TESS`] subdivisions per
/// patch edge. The size of the text is estimated first and refused when it exceeds the
/// available memory ([`crate::budget::check_memory`]); a position or normal that is not
/// finite, or a patch without a normal, is an error naming the patch.
pub fn to_obj(surface: &Surface, tess: usize) -> Result<String> {
    if !(1..=MAX_TESS).contains(&tess) {
        return Err(Error::Invalid(format!(
            "--tess {tess} must be in 1..={MAX_TESS} (subdivisions per patch edge)"
        )));
    }
    crate::budget::check_memory(
        &format!(
            "the OBJ of {} patches at --tess {tess}",
            surface.patches.len()
        ),
        estimated_bytes(surface.patches.len(), tess),
        "lower --tess",
    )?;
    let mut out = String::new();
    // Writing into a String cannot fail.
    let _ = writeln!(
        out,
        "# smoothlab tessellation: scheme {}, {} patches, {tess} subdivisions per edge",
        surface.scheme,
        surface.patches.len()
    );
    let per_patch = grid_vertex_count(tess);
    for (index, patch) in surface.patches.iter().enumerate() {
        let _ = writeln!(
            out,
            "g patch{index}_face{}_piece{}",
            patch.face, patch.piece
        );
        for i in 0..=tess {
            for j in 0..=tess - i {
                let uv = DVec2::new(i as f64, j as f64) / tess as f64;
                let p = patch.eval(uv.x, uv.y);
                let n = exact_normal(patch, uv);
                if !p.is_finite() || !n.is_finite() || n == DVec3::ZERO {
                    return Err(Error::NonFiniteResult {
                        what: format!(
                            "the normal of patch {index} (face {}) at (u, v) = ({}, {})",
                            patch.face, uv.x, uv.y
                        ),
                        value: if p.is_finite() {
                            n.length()
                        } else {
                            p.length()
                        },
                    });
                }
                let _ = writeln!(out, "v {} {} {}", p.x, p.y, p.z);
                let _ = writeln!(out, "vn {} {} {}", n.x, n.y, n.z);
            }
        }
        // OBJ indices are 1-based and global; vertex and normal indices coincide.
        let base = index * per_patch + 1;
        let id = |i, j| base + grid_index(tess, i, j);
        for i in 0..tess {
            for j in 0..tess - i {
                let (a, b, c) = (id(i, j), id(i + 1, j), id(i, j + 1));
                let _ = writeln!(out, "f {a}//{a} {b}//{b} {c}//{c}");
                if i + j + 1 < tess {
                    let d = id(i + 1, j + 1);
                    let _ = writeln!(out, "f {b}//{b} {d}//{d} {c}//{c}");
                }
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bezier::TriangleBezier;
    use crate::surface::PatchGeometry;

    #[test]
    fn grid_index_enumerates_rows() {
        for tess in 1..6 {
            let mut n = 0;
            for i in 0..=tess {
                for j in 0..=tess - i {
                    assert_eq!(grid_index(tess, i, j), n, "tess {tess} ({i},{j})");
                    n += 1;
                }
            }
            assert_eq!(n, grid_vertex_count(tess));
        }
    }

    fn quadratic_surface() -> Surface {
        let b = TriangleBezier::from_fn(2, |i, j, k| {
            DVec3::new(j as f64, k as f64, if i == 1 { 0.5 } else { 0.0 })
        });
        Surface {
            scheme: "test".into(),
            warnings: Vec::new(),
            params: vec![],
            patches: vec![Patch {
                face: 0,
                piece: 0,
                domain: crate::surface::WHOLE_FACE,
                geometry: PatchGeometry::Bezier(b),
            }],
        }
    }

    /// Vertices lie on the patch, normals are the exact normals there, faces are wound so
    /// that their facet normal agrees with the vertex normals.
    #[test]
    fn vertices_normals_and_faces_agree_with_the_patch() {
        let surface = quadratic_surface();
        let tess = 4;
        let text = to_obj(&surface, tess).expect("tessellates");
        let parse = |prefix: &str| -> Vec<DVec3> {
            text.lines()
                .filter_map(|l| l.strip_prefix(prefix))
                .map(|rest| {
                    let x: Vec<f64> = rest
                        .split_whitespace()
                        .map(|t| t.parse().expect("number"))
                        .collect();
                    DVec3::new(x[0], x[1], x[2])
                })
                .collect()
        };
        let (vs, ns) = (parse("v "), parse("vn "));
        assert_eq!(vs.len(), grid_vertex_count(tess));
        assert_eq!(ns.len(), vs.len());
        let patch = &surface.patches[0];
        let (u, v) = (0.25, 0.5);
        let k = grid_index(tess, 1, 2);
        assert_eq!(vs[k], patch.eval(u, v));
        assert_eq!(ns[k], patch.jet(u, v).normal());
        let faces: Vec<[usize; 3]> = text
            .lines()
            .filter_map(|l| l.strip_prefix("f "))
            .map(|rest| {
                let idx: Vec<usize> = rest
                    .split_whitespace()
                    .map(|t| {
                        t.split("//")
                            .next()
                            .and_then(|s| s.parse().ok())
                            .expect("index")
                    })
                    .collect();
                [idx[0] - 1, idx[1] - 1, idx[2] - 1]
            })
            .collect();
        assert_eq!(faces.len(), tess * tess);
        for f in faces {
            let facet = (vs[f[1]] - vs[f[0]]).cross(vs[f[2]] - vs[f[0]]);
            for c in f {
                assert!(
                    facet.dot(ns[c]) > 0.0,
                    "face {f:?} wound against its normals"
                );
            }
        }
    }

    #[test]
    fn zero_subdivisions_is_an_error() {
        let err = to_obj(&quadratic_surface(), 0).expect_err("tess 0");
        assert!(err.to_string().contains("--tess"), "{err}");
    }
}
