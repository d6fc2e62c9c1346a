//! The boundary-blending schemes \[FM\]: per face, three sub-surfaces `S_0, S_1, S_2`, `S_i`
//! owning the edge opposite corner `i`, blended by [`crate::blend::BlendPatch`] —
//! [`nielson`] (Nielson's side-vertex weights, quartic sub-surfaces that share the face's
//! boundary curves, G¹) and [`fang_mann`] (Fang–Mann's weights, cubic sub-surfaces cut
//! from one shared "edge surface" per mesh edge, `C^t`).
//!
//! Both start from the same per-edge data, [`EdgeFrame`], computed once per mesh edge from
//! the positions of its two vertices, their normals and the apexes of its (one or two)
//! faces, so that the two faces of an edge see bit-identical data:
//! * the **boundary curve** `C(s)`, the cubic through the two vertices whose inner control
//!   points are the edge's thirds projected into the end tangent planes (as in PN triangles):
//!   `C'(0) = π_a(P_b − P_a)`, `C'(1) = π_b(P_b − P_a)` with `π_x` the projection onto the
//!   plane orthogonal to `N_x`;
//! * a **transversal field** `D(s) = (1−s) D_a + s D_b`, `D_x = π_x(f̄)`, where `f̄` is the
//!   mean of the faces' in-plane perpendiculars to the edge (each of length `|P_b − P_a|`,
//!   pointing to the left of `a → b`). For a flat pair of faces this is their common
//!   perpendicular; for a pair folded symmetrically about the vertex tangent plane the
//!   projections of both faces' perpendiculars agree, so the transversal derivative at a
//!   vertex is what the neighbouring edges' boundary curves predict there;
//! * each face's **apex** in the edge's own plane `(s, h)`: the vertex opposite the edge,
//!   written as `P_a + σ (P_b − P_a) + h f` with `h > 0` for the face that runs `a → b`
//!   (on the left) and `h < 0` for the face that runs `b → a`.

pub(crate) mod fang_mann;
pub(crate) mod nielson;
#[cfg(test)]
mod tests;

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use crate::bezier::CurveBezier;
use crate::bezier::TriangleBezier;
use crate::blend::{BlendPatch, WeightFamily};
use crate::error::{Error, Result};
use crate::mesh::{Mesh, crease_tangent};
use crate::schemes::vertex_rings::FaceFrame;
use crate::schemes::{AtFoldedVertex, NORMALS_PARAM, ParamSpec, Params};
use crate::surface::{Patch, PatchGeometry, Surface};

/// Smallest `|π(e) × D| / |e|²` accepted at an edge end: below it the vertex normal is
/// (nearly) in the plane of the boundary tangent and the transversal, and the sub-surfaces
/// would be singular there.
pub(crate) const MIN_FRAME_AREA: f64 = 1e-8;

/// The data of one mesh edge `a → b` (`a < b`) shared by the faces on both sides.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct EdgeFrame {
    /// First vertex (the smaller index).
    pub a: u32,
    /// Second vertex.
    pub b: u32,
    /// `P_a`: the curve's points and the apexes are stored relative to it, so that they keep
    /// the precision of the edge's size wherever the edge lies.
    pub origin: DVec3,
    /// The boundary curve from `P_a` to `P_b` (cubic), relative to `origin`.
    pub curve: CurveBezier,
    /// The same curve elevated to degree four (computed once for both faces).
    pub curve_quartic: CurveBezier,
    /// Transversal derivative at `a` and at `b` (in the tangent planes there), pointing to
    /// the left of `a → b`.
    pub transversal: [DVec3; 2],
    /// The apex of the face on the left (runs `a → b`; `h > 0`) and on the right (runs
    /// `b → a`; `h < 0`) in edge coordinates `(σ, h)`, with its vertex relative to `origin`.
    pub apex: [Option<(DVec2, DVec3)>; 2],
}

impl EdgeFrame {
    /// The domain point of the apex of the face that runs `a → b` (`left = true`) or
    /// `b → a`. Panics if that side has no face (callers ask only for their own face).
    pub(crate) fn apex_point(&self, left: bool) -> DVec2 {
        self.apex[usize::from(!left)]
            .expect("the face asking for its apex lies on that side")
            .0
    }
}

/// Builds the frame of edge `(a, b)`, `a < b`, from the apexes of its faces (`left`: the
/// face that runs `a → b`; `right`: the face that runs `b → a`), with the normals `[na, nb]`
/// at its ends and, for a sharp edge, the crease tangents `crease` of its boundary curve.
#[allow(clippy::too_many_arguments)]
fn edge_frame(
    scheme: &str,
    a: u32,
    b: u32,
    mesh: &Mesh,
    [na, nb]: [DVec3; 2],
    crease: Option<[DVec3; 2]>,
    left: Option<u32>,
    right: Option<u32>,
) -> Result<EdgeFrame> {
    let positions = mesh.positions();
    let (pa, pb) = (positions[a as usize], positions[b as usize]);
    let e = pb - pa;
    let ee = e.length_squared();
    let project = |n: DVec3, x: DVec3| x - x.dot(n) * n;
    // The apex as (σ, h) and the face's perpendicular f (|f| = |e|, left of a → b).
    let place = |apex: u32, sign: f64| {
        let p = positions[apex as usize] - pa;
        let sigma = p.dot(e) / ee;
        let perp = p - sigma * e;
        let h = perp.length() / ee.sqrt();
        (DVec2::new(sigma, sign * h), sign * perp / h, p)
    };
    let sides = [left.map(|v| place(v, 1.0)), right.map(|v| place(v, -1.0))];
    let perps: Vec<DVec3> = sides.iter().flatten().map(|s| s.1).collect();
    let mean_perp = perps.iter().sum::<DVec3>() / perps.len() as f64;
    let transversal = [project(na, mean_perp), project(nb, mean_perp)];
    let tangents = crease.unwrap_or([project(na, e), project(nb, e)]);
    for (end, (n, (t, d))) in [na, nb]
        .iter()
        .zip(tangents.iter().zip(&transversal))
        .enumerate()
    {
        let area = t.cross(*d).dot(*n);
        if area.is_nan() || area <= MIN_FRAME_AREA * ee {
            let vertex = if end == 0 { a } else { b };
            return Err(Error::DegenerateEdge {
                scheme: scheme.to_string(),
                a: vertex as usize,
                b: if end == 0 { b } else { a } as usize,
                reason: format!(
                    "the normal of vertex {} is (nearly) tangent to the edge or its faces \
                     (frame area {:.1e} of |e|²)",
                    mesh.input_vertex(vertex),
                    area / ee
                ),
                also: Vec::new(),
            });
        }
    }
    let curve = CurveBezier::new(vec![
        DVec3::ZERO,
        tangents[0] / 3.0,
        e - tangents[1] / 3.0,
        e,
    ]);
    Ok(EdgeFrame {
        a,
        b,
        origin: pa,
        curve_quartic: curve.elevate(),
        curve,
        transversal,
        apex: sides.map(|s| s.map(|(x, _, p)| (x, p))),
    })
}

/// Every edge's frame, and for every face and each of its edges `e` (from corner `e` to
/// corner `e+1`) the index of that edge's frame.
pub(crate) struct EdgeFrames {
    /// One frame per undirected mesh edge.
    pub frames: Vec<EdgeFrame>,
    /// `face_edges[f][e]`: frame of edge `e` of face `f`.
    pub face_edges: Vec<[usize; 3]>,
    /// The origin of each face's frame ([`FaceFrame`]): its sub-surfaces are built relative
    /// to it and stored with it.
    pub face_origins: Vec<DVec3>,
}

impl EdgeFrames {
    /// The frames of every edge of `mesh` with unit vertex `normals`.
    ///
    /// A sharp edge ([`crate::mesh::SharpEdges`]) gets one frame per face, each with its own
    /// face's apex, and its transversal in its own sector's tangent planes
    /// ([`Mesh::corner_normals`]); both share one boundary curve (computed once), whose end
    /// tangents follow the crease ([`crate::mesh::crease_tangent`]): the two faces join with
    /// G0 there, and each face is smooth up to the crease.
    pub(crate) fn build(mesh: &Mesh, normals: &[DVec3], scheme: &str) -> Result<EdgeFrames> {
        let faces = mesh.faces();
        let edges = mesh.edges();
        let corner_normals = mesh.corner_normals(normals);
        let corner_normal = |f: u32, v: u32| {
            let fv = faces[f as usize];
            let c = fv.iter().position(|&x| x == v).unwrap_or(0);
            corner_normals[f as usize][c]
        };
        let is_sharp = |f: u32, a: u32, b: u32| {
            let fv = faces[f as usize];
            (0..3).any(|e| {
                let (x, y) = (fv[e], fv[(e + 1) % 3]);
                ((x, y) == (a, b) || (x, y) == (b, a)) && mesh.is_sharp(f, e)
            })
        };
        let third = |f: u32, a: u32, b: u32| {
            let fv = faces[f as usize];
            fv.into_iter().find(|&v| v != a && v != b).unwrap_or(fv[0])
        };
        let runs_forward = |f: u32, a: u32, b: u32| {
            let fv = faces[f as usize];
            (0..3).any(|e| fv[e] == a && fv[(e + 1) % 3] == b)
        };
        // Per edge: its frame, or for a sharp edge the left face's and the right face's.
        let per_edge = edges
            .par_iter()
            .map(|edge| {
                let (mut left, mut right) = (None, None);
                for f in [Some(edge.faces.0), edge.faces.1].into_iter().flatten() {
                    let apex = third(f, edge.a, edge.b);
                    if runs_forward(f, edge.a, edge.b) {
                        left = Some((f, apex));
                    } else {
                        right = Some((f, apex));
                    }
                }
                let ends = |f: u32| [corner_normal(f, edge.a), corner_normal(f, edge.b)];
                let frame = |f: u32, crease, left, right| {
                    edge_frame(scheme, edge.a, edge.b, mesh, ends(f), crease, left, right)
                };
                match (left, right) {
                    (Some((fl, l)), Some((fr, r))) if is_sharp(fl, edge.a, edge.b) => {
                        let e =
                            mesh.positions()[edge.b as usize] - mesh.positions()[edge.a as usize];
                        let [la, lb] = ends(fl);
                        let [ra, rb] = ends(fr);
                        let crease = Some([crease_tangent(e, la, ra), crease_tangent(e, lb, rb)]);
                        let mut own_left = frame(fl, crease, Some(l), None)?;
                        let own_right = frame(fr, crease, None, Some(r))?;
                        // One curve for both faces, bit for bit.
                        own_left.curve = own_right.curve.clone();
                        own_left.curve_quartic = own_right.curve_quartic.clone();
                        Ok(vec![own_left, own_right])
                    }
                    _ => {
                        let f = left.or(right).map_or(edge.faces.0, |(f, _)| f);
                        Ok(vec![frame(
                            f,
                            None,
                            left.map(|(_, v)| v),
                            right.map(|(_, v)| v),
                        )?])
                    }
                }
            })
            .collect::<Vec<Result<Vec<EdgeFrame>>>>();
        let per_edge = crate::error::collect_in_order(per_edge)?;
        let mut first = Vec::with_capacity(per_edge.len());
        let mut frames = Vec::with_capacity(edges.len());
        for group in per_edge {
            first.push(frames.len());
            frames.extend(group);
        }
        // `Mesh::edges` lists each edge at its first half-edge, which is its number in
        // `Mesh::edge_ids`: the edge of a face edge by number, not by its two vertices (two
        // edges can join the same vertices after repairs).
        let edge_ids = mesh.edge_ids();
        let mut index = vec![usize::MAX; edge_ids.len()];
        let mut next = 0;
        for (he, &id) in edge_ids.iter().enumerate() {
            if id as usize == he {
                index[he] = next;
                next += 1;
            }
        }
        let face_edges = faces
            .iter()
            .enumerate()
            .map(|(f, fv)| {
                std::array::from_fn(|e| {
                    let (x, y) = (fv[e], fv[(e + 1) % 3]);
                    let i = index[edge_ids[3 * f + e] as usize];
                    // The right face's own frame follows the left face's.
                    let right_of_sharp = mesh.is_sharp(f as u32, e) && x > y;
                    first[i] + usize::from(right_of_sharp && mesh.neighbor(f as u32, e).is_some())
                })
            })
            .collect();
        let face_origins = faces
            .iter()
            .map(|&face| FaceFrame::of(mesh.positions(), face).origin)
            .collect();
        Ok(EdgeFrames {
            frames,
            face_edges,
            face_origins,
        })
    }

    /// What takes a point relative to `frame`'s origin into face `f`'s frame.
    pub(crate) fn to_face(&self, frame: &EdgeFrame, f: usize) -> DVec3 {
        frame.origin - self.face_origins[f]
    }

    /// The frame of the edge opposite corner `c` of face `f`, and whether the face runs along
    /// it from `a` to `b` (corner `c+1` is `a`).
    pub(crate) fn opposite(&self, faces: &[[u32; 3]], f: usize, c: usize) -> (&EdgeFrame, bool) {
        let frame = &self.frames[self.face_edges[f][(c + 1) % 3]];
        (frame, faces[f][(c + 1) % 3] == frame.a)
    }

    /// The boundary curve of the edge of face `f` from its vertex `from` to its vertex `to`,
    /// cubic or quartic, in that direction, in the face's frame (one curve for both faces,
    /// placed in each face's frame).
    pub(crate) fn curve_between(
        &self,
        faces: &[[u32; 3]],
        f: usize,
        from: usize,
        to: usize,
        quartic: bool,
    ) -> Vec<DVec3> {
        let fv = faces[f];
        let edge = if (from + 1) % 3 == to { from } else { to };
        let frame = &self.frames[self.face_edges[f][edge]];
        let curve = if quartic {
            &frame.curve_quartic
        } else {
            &frame.curve
        };
        let shift = self.to_face(frame, f);
        let mut points: Vec<DVec3> = curve.points().iter().map(|&p| shift + p).collect();
        if fv[from] != frame.a {
            points.reverse();
        }
        points
    }
}

/// The parameters of a blend scheme: the power `t` of its weights (default 1; `t_help` says
/// which values it takes and what they mean) and the vertex normals.
pub(crate) const fn blend_params(t_help: &'static str) -> [ParamSpec; 2] {
    [
        ParamSpec {
            name: "t",
            default: "1",
            help: t_help,
        },
        NORMALS_PARAM,
    ]
}

/// Builds one blend patch per face: the weights `family(t)` for the parameter `t` (an integer
/// in `orders`) over the three sub-surfaces `sub_surface(frames, faces, face, corner)`, the
/// one for `corner` owning the edge opposite it, each built in the face's frame
/// ([`EdgeFrames::face_origins`]) and stored with its origin.
pub(crate) fn build_blend(
    mesh: &Mesh,
    params: &Params,
    scheme: &str,
    orders: std::ops::RangeInclusive<u32>,
    family: impl Fn(u32) -> WeightFamily,
    sub_surface: impl Fn(&EdgeFrames, &[[u32; 3]], usize, usize) -> Result<TriangleBezier> + Sync,
) -> Result<Surface> {
    let family = family(order_param(params, orders)?);
    let (normals, warnings) =
        crate::schemes::scheme_normals(mesh, params, scheme, AtFoldedVertex::Refuse)?;
    let frames = EdgeFrames::build(mesh, &normals, scheme)?;
    let faces = mesh.faces();
    let patches = (0..mesh.face_count())
        .into_par_iter()
        .map(|f| {
            let origin = frames.face_origins[f];
            let subs = [
                sub_surface(&frames, faces, f, 0)?.placed_at(origin),
                sub_surface(&frames, faces, f, 1)?.placed_at(origin),
                sub_surface(&frames, faces, f, 2)?.placed_at(origin),
            ];
            Ok(Patch {
                face: f as u32,
                piece: 0,
                domain: crate::surface::WHOLE_FACE,
                geometry: PatchGeometry::Blend(Box::new(BlendPatch::new(family, subs))),
            })
        })
        .collect::<Vec<Result<_>>>();
    let patches = crate::error::collect_in_order(patches)?;
    let mut surface = params.surface(scheme, patches);
    surface.warnings = warnings;
    Ok(surface)
}

/// The integer parameter `t` in `range`.
fn order_param(params: &Params, range: std::ops::RangeInclusive<u32>) -> Result<u32> {
    let text = params.text("t");
    match text.trim().parse::<u32>() {
        Ok(t) if range.contains(&t) => Ok(t),
        _ => Err(Error::BadParam {
            name: "t".to_string(),
            reason: format!(
                "'{text}' is not an integer in {}..={}",
                range.start(),
                range.end()
            ),
        }),
    }
}
