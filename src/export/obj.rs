//! Tessellated OBJ: every patch sampled on a regular grid of `tess` subdivisions per edge,
//! `(tess+1)(tess+2)/2` vertices shared by the triangles of that patch, each with the
//! patch's exact unit normal `Su × Sv / |Su × Sv|` as `vn` (not an average of facet normals),
//! so shading in any viewer shows the true normal field, jumps included. The vertices are
//! welded: grid vertices of neighbouring patches closer than the G0 contract
//! ([`crate::tolerance::G0_GAP_REL`] of the diagonal) are one `v`, so the file is one connected
//! mesh that MeshLab or Blender need not weld, while a wider gap stays open. Normals are shared
//! where they agree to [`crate::tolerance::NORMAL_RAD`] and kept one per side where they do not, so
//! a kink stays visible in shading.
//!
//! Triangles are wound counter-clockwise in the patch's `(u, v)` domain, so they face the
//! way the patch normal points.

use std::fmt::Write;

use glam::{DVec2, DVec3};

use crate::error::{Error, Result};
use crate::mesh::PointWelder;
use crate::surface::{Patch, Surface};

/// Number of grid vertices of one patch at `tess` subdivisions per edge.
pub(crate) const fn grid_vertex_count(tess: usize) -> usize {
    (tess + 1) * (tess + 2) / 2
}

/// Index of grid vertex `(i, j)` (`u = i/tess`, `v = j/tess`, `i + j ≤ tess`) within its
/// patch: rows of constant i, j increasing.
pub(crate) const fn grid_index(tess: usize, i: usize, j: usize) -> usize {
    // Rows 0..i hold (tess+1) + tess + … + (tess+2−i) vertices.
    i * (tess + 1) - i * (i.saturating_sub(1)) / 2 + j
}

/// The unit normal of `patch` at `uv`. Where `Su × Sv = 0` (a singular point, typically a
/// corner where the parametrisation degenerates) the normal is the limit from inside: it is
/// taken at points moved towards the patch centre by growing steps until one is regular.
pub(crate) fn exact_normal(patch: &Patch, uv: DVec2) -> DVec3 {
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
pub(crate) fn estimated_bytes(patches: usize, tess: usize) -> f64 {
    let (vertices, triangles) = (grid_vertex_count(tess) as f64, (tess * tess) as f64);
    patches as f64 * (120.0 * vertices + 40.0 * triangles)
}

/// The OBJ text of `surface` tessellated with `1 ≤ tess ≤` [`MAX_TESS`] subdivisions per
/// patch edge. The size of the text is estimated first and refused when it exceeds the
/// available memory ([`crate::budget::check_memory`]); a position or normal that is not
/// finite, or a patch without a normal, is an error naming the patch and its face as
/// `input_face` numbers it.
pub(crate) fn to_obj(
    surface: &Surface,
    tess: usize,
    input_face: &dyn Fn(u32) -> usize,
) -> Result<String> {
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
    let per_patch = grid_vertex_count(tess);
    let bounds = surface.bounds();
    let tolerance = crate::tolerance::G0_GAP_REL * (bounds.max - bounds.min).length();
    let mut welder = PointWelder::new(bounds, tolerance, surface.patches.len() * per_patch);
    let mut normals = NormalsPerVertex::default();
    // Per patch grid vertex: its welded position and normal numbers.
    let mut corners = Vec::with_capacity(surface.patches.len() * per_patch);
    for (index, patch) in surface.patches.iter().enumerate() {
        for i in 0..=tess {
            for j in 0..=tess - i {
                let uv = DVec2::new(i as f64, j as f64) / tess as f64;
                let p = patch.eval(uv.x, uv.y);
                let n = exact_normal(patch, uv);
                if !p.is_finite() || !n.is_finite() || n == DVec3::ZERO {
                    return Err(Error::NonFiniteResult {
                        what: format!(
                            "the normal of patch {index} (face {}) at (u, v) = ({}, {})",
                            input_face(patch.face),
                            uv.x,
                            uv.y
                        ),
                        value: if p.is_finite() {
                            n.length()
                        } else {
                            p.length()
                        },
                    });
                }
                let v = welder.weld(p);
                corners.push((v, normals.weld(v, n)));
            }
        }
    }
    let mut faces = String::new();
    let mut collapsed = 0;
    for (index, patch) in surface.patches.iter().enumerate() {
        // Writing into a String cannot fail.
        let _ = writeln!(
            faces,
            "g patch{index}_face{}_piece{}",
            patch.face, patch.piece
        );
        let grid = &corners[index * per_patch..(index + 1) * per_patch];
        let mut triangle = |a: (usize, usize), b: (usize, usize), c: (usize, usize)| {
            let [a, b, c] = [a, b, c].map(|(i, j)| grid[grid_index(tess, i, j)]);
            if a.0 == b.0 || b.0 == c.0 || c.0 == a.0 {
                collapsed += 1;
                return;
            }
            // OBJ indices are 1-based.
            let _ = writeln!(
                faces,
                "f {}//{} {}//{} {}//{}",
                a.0 + 1,
                a.1 + 1,
                b.0 + 1,
                b.1 + 1,
                c.0 + 1,
                c.1 + 1
            );
        };
        for i in 0..tess {
            for j in 0..tess - i {
                triangle((i, j), (i + 1, j), (i, j + 1));
                if i + j + 1 < tess {
                    triangle((i + 1, j), (i + 1, j + 1), (i, j + 1));
                }
            }
        }
    }
    let mut out = String::with_capacity(faces.len() * 2);
    let _ = writeln!(
        out,
        "# smoothlab tessellation: scheme {}, {} patches, {tess} subdivisions per edge",
        surface.scheme,
        surface.patches.len()
    );
    let _ = writeln!(
        out,
        "# welded within {:e} of the diagonal: {} vertices, {} normals; {collapsed} triangles \
         dropped (corners welded into one)",
        crate::tolerance::G0_GAP_REL,
        welder.positions.len(),
        normals.directions.len()
    );
    for p in &welder.positions {
        let _ = writeln!(out, "v {} {} {}", p.x, p.y, p.z);
    }
    for n in &normals.directions {
        let _ = writeln!(out, "vn {} {} {}", n.x, n.y, n.z);
    }
    out.push_str(&faces);
    Ok(out)
}

/// The distinct normals at each welded vertex: a normal within
/// [`crate::tolerance::NORMAL_RAD`] of one already recorded at the same vertex is that one,
/// so a G¹ joint shares its normals and a kink keeps one normal per side.
#[derive(Default)]
struct NormalsPerVertex {
    /// The recorded unit normals, in order of first use.
    directions: Vec<DVec3>,
    /// Per welded vertex, its first normal (`u32::MAX`: none yet).
    first: Vec<u32>,
    /// Per normal, the next normal of the same vertex (`u32::MAX` ends the chain).
    next: Vec<u32>,
}

impl NormalsPerVertex {
    /// The number of unit normal `n` at welded vertex `v`, recorded if new there.
    fn weld(&mut self, v: u32, n: DVec3) -> u32 {
        let v = v as usize;
        if v >= self.first.len() {
            self.first.resize(v + 1, u32::MAX);
        }
        let mut at = self.first[v];
        while at != u32::MAX {
            let m = self.directions[at as usize];
            if m.dot(n) > 0.0 && m.cross(n).length() <= crate::tolerance::NORMAL_RAD {
                return at;
            }
            at = self.next[at as usize];
        }
        let id = self.directions.len() as u32;
        self.directions.push(n);
        self.next.push(self.first[v]);
        self.first[v] = id;
        id
    }
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
            spike_face_pairs: Vec::new(),
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
        let text = to_obj(&surface, tess, &|t| t as usize).expect("tessellates");
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

    /// Two flat triangles `(a, b, c)` and `(b, d, c)` sharing the edge `b c`, the second one
    /// moved by `gap` along z.
    fn two_triangles(d: DVec3, gap: f64) -> Surface {
        let linear = |corners: [DVec3; 3]| {
            PatchGeometry::Bezier(TriangleBezier::from_fn(1, |i, j, _| {
                corners[if i == 1 {
                    0
                } else if j == 1 {
                    1
                } else {
                    2
                }]
            }))
        };
        let (a, b, c) = (DVec3::ZERO, DVec3::X, DVec3::Y);
        let shift = DVec3::new(0.0, 0.0, gap);
        let patch = |face, geometry| Patch {
            face,
            piece: 0,
            domain: crate::surface::WHOLE_FACE,
            geometry,
        };
        Surface {
            scheme: "test".into(),
            warnings: Vec::new(),
            spike_face_pairs: Vec::new(),
            params: vec![],
            patches: vec![
                patch(0, linear([a, b, c])),
                patch(1, linear([b + shift, d + shift, c + shift])),
            ],
        }
    }

    fn count(text: &str, prefix: &str) -> usize {
        text.lines().filter(|l| l.starts_with(prefix)).count()
    }

    /// Grid vertices on a shared edge are one vertex; normals are shared across a flat joint
    /// and kept one per side across a kink; a gap wider than the G0 contract stays open.
    #[test]
    fn patches_share_the_vertices_of_their_common_edge() {
        let tess = 5;
        let grid = grid_vertex_count(tess);
        let flat = to_obj(&two_triangles(DVec3::new(1.0, 1.0, 0.0), 0.0), tess, &|t| {
            t as usize
        })
        .unwrap();
        assert_eq!(count(&flat, "v "), 2 * grid - (tess + 1));
        assert_eq!(count(&flat, "vn "), 2 * grid - (tess + 1));
        assert_eq!(count(&flat, "f "), 2 * tess * tess);
        let kink = to_obj(&two_triangles(DVec3::new(1.0, 1.0, 0.5), 0.0), tess, &|t| {
            t as usize
        })
        .unwrap();
        assert_eq!(count(&kink, "v "), 2 * grid - (tess + 1));
        assert_eq!(count(&kink, "vn "), 2 * grid);
        // 1e-6 of the diagonal: a thousand times the G0 contract.
        let open = to_obj(
            &two_triangles(DVec3::new(1.0, 1.0, 0.0), 1.5e-6),
            tess,
            &|t| t as usize,
        )
        .unwrap();
        assert_eq!(count(&open, "v "), 2 * grid);
        assert!(flat.contains(&format!("{} vertices", 2 * grid - (tess + 1))));
        assert!(flat.contains("0 triangles dropped"));
    }

    #[test]
    fn zero_subdivisions_is_an_error() {
        let err = to_obj(&quadratic_surface(), 0, &|t| t as usize).expect_err("tess 0");
        assert!(err.to_string().contains("--tess"), "{err}");
    }
}
