//! Piper 1987, *Visually smooth interpolation with triangular Bézier patches*, as explained
//! step by step in [Piper87 §3.8] (Lamberts 1997): a G¹ surface through the mesh vertices
//! with the given vertex normals, made of three quartic Bézier triangles per face
//! (a Clough–Tocher split at the centroid).
//!
//! The five steps of [Piper87 §3.8]:
//! 1. per face, a candidate cubic net: corners at the vertices, each boundary point the far
//!    end of its edge projected into the near vertex's tangent plane and scaled (with a
//!    guard against the two points of an edge crossing), the centre by Farin's C⁰ rule
//!    ([`cubic_net::candidate_net`]);
//! 2. the net split at the centroid into three cubic sub-nets ([`cubic_net::split_at_centroid`]);
//! 3. per shared edge, the centre points of the two sub-nets beside it made coplanar with the
//!    edge's inner points, the taller triangle moving more ([`cubic_net::coplanar_centres`]);
//! 4. the sub-nets elevated to degree four ([`cubic_net::elevate`]);
//! 5. per shared edge, the two rows beside it and the edge's middle point moved as little as
//!    possible to satisfy Piper's G¹ conditions, eqs. (17)–(20) and the system `A x = b`
//!    including its dependent-rows case ([`g1_solve`]); then per face the points M, N, O reset so
//!    that the three pieces join C¹ ([`c1_restore`]).
//!
//! Only steps 3 and 5 look across an edge, and only at the face on the other side: the
//! construction is local, so open meshes work as they are — a boundary edge has no neighbour,
//! its sub-net keeps its candidate points, and every interior edge is G¹.
//!
//! Sharp edges (`--crease-angle`, or marked in the file) are kept sharp the same way: each
//! vertex cut by sharp edges has one normal per sector ([`Mesh::corner_normals`]), a sharp
//! edge's boundary points leave each end along the crease of the two sectors there (step 1,
//! [`cubic_net::candidate_net`]), so both faces build one boundary curve (G⁰), and steps 3
//! and 5 skip it as they skip a boundary edge. The thesis has no crease rule; this is the
//! boundary rule applied on both sides of the edge.
//!
//! Where this differs from the thesis, and why:
//! * edge scaling (`scaling=`): the thesis's factor `1/3 + ‖q − b‖/9` measures a length in
//!   the mesh's units, so the surface changes shape when the mesh is scaled, and the thesis
//!   says it must be tuned by trial. It is available as `scaling=thesis`. The default,
//!   `scaling=circle`, gives the leg the length of the cubic that best fits a circular arc
//!   (`2‖chord‖ / (3(1 + cos Θ))`): invariant under similarities, planes reproduced with a
//!   uniform parametrisation, spheres approximated to fourth order. `scaling=farin` is
//!   Farin's 2-D rule of [Piper87 §2] ([`crate::bezier::hermite2d`]) in the plane of the
//!   chord and the projected edge (same invariance and precision, longer legs on steep
//!   edges); `scaling=relative` is the thesis's factor with the distance in chord lengths
//!   (scale invariant; 4/9 of the chord on flat data, so only second order on spheres, but
//!   the calmest zebra stripes on coarse, spiky meshes). Every rule is capped at the edge's
//!   midpoint, the crossing guard ([`cubic_net::edge_point_along`]). A leg that swerves
//!   across its face, seen from either face of its edge (its angle off the chord, towards the
//!   face, exceeds the face's angle at the vertex: thin fan triangles under a normal that
//!   leans off them), is in addition no longer than the `relative` rule's ([`swerving_legs`]);
//!   long legs there leave the face edge-on and steps 3–5 turn it over. Both faces decide
//!   alike, so they build the same boundary curve; regular meshes never trigger it;
//! * step 3: the thesis's projection-and-scaling makes the four points coplanar only to first
//!   order; here both centres are projected onto one plane between the two, weighted by the
//!   same heights — exactly coplanar (this only changes the starting point of step 5);
//! * step 5: `C0 = C4 = 0` are solved in the tangent plane instead of by dropping a
//!   coordinate; the underdetermined `A e = b − A y` is solved for the least change; the
//!   middle row of `A` is rewritten in the weight differences so that the dependent-rows case
//!   is decided robustly (see [`g1_solve`]).
//!
//! Parameters: `normals=estimate|obj` (the mesh's vertex normals or the file's),
//! `scaling=circle|farin|relative|thesis`.

pub(crate) mod c1_restore;
pub(crate) mod cubic_net;
pub(crate) mod g1_solve;

use glam::DVec3;
use rayon::prelude::*;

use crate::bezier::TriangleBezier;
use crate::bezier::triangle::index;
use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::schemes::vertex_rings::FaceFrame;
use crate::schemes::{AtFoldedVertex, ParamSpec, Params, SchemeSpec};
use crate::surface::{Patch, PatchGeometry, Surface};
use cubic_net::{Cubic, EdgeScaling, Quartic};
use g1_solve::EdgeNet;

/// Registry entry.
pub(crate) const SPEC: SchemeSpec = SchemeSpec {
    name: "piper",
    summary: "Piper 1987: Clough-Tocher split, 3 quartic Bezier triangles per face, G1 (Piper87)",
    params: &[
        crate::schemes::NORMALS_PARAM,
        ParamSpec {
            name: "scaling",
            default: "circle",
            help: "edge legs: circle (arc fit) | farin (2-D rule) | relative (thesis factor in chord lengths) | thesis (1/3 + |q-b|/9, depends on the mesh size)",
        },
    ],
    needs_closed_mesh: false,
    bytes_per_face: 3900.0,
    sharp_edges: crate::schemes::SharpEdgeSupport::Builds,
    build,
};

/// Reads the `scaling` parameter.
fn edge_scaling(params: &Params) -> Result<EdgeScaling> {
    Ok(
        match params.choice("scaling", &["circle", "farin", "relative", "thesis"])? {
            "farin" => EdgeScaling::Farin,
            "relative" => EdgeScaling::Relative,
            "thesis" => EdgeScaling::Thesis,
            _ => EdgeScaling::Circle,
        },
    )
}

/// The rows of two quartic pieces at their shared outer edge, in P's direction and P's frame
/// (`to_p`: Q's frame origin minus P's). Piece rows: `S_i = p(4−i, i, 0)`,
/// `R_i = p(3−i, i, 1)`; Q runs the other way, so `T_i = Q's R_{3−i} = q(i, 3−i, 1)`.
fn edge_net(quartic_p: &Quartic, quartic_q: &Quartic, to_p: DVec3) -> EdgeNet {
    EdgeNet {
        s: std::array::from_fn(|i| quartic_p[index(4, 4 - i, i)]),
        r: std::array::from_fn(|i| quartic_p[index(4, 3 - i, i)]),
        t: std::array::from_fn(|i| quartic_q[index(4, i, 3 - i)] + to_p),
    }
}

/// A piece of a face: `(face, k)`, the piece over the face's edge `k`.
type PieceId = (usize, usize);

/// The data of steps 3–5: the cubic sub-nets of every face (steps 1–2), each in its face's
/// frame ([`FaceFrame`]: points relative to the face's first corner, so that they keep the
/// precision of the face's size wherever it lies).
struct Construction<'a> {
    mesh: &'a Mesh,
    cubic_pieces: Vec<[Cubic; 3]>,
    /// What choosing the vertex normals changed ([`crate::schemes::scheme_normals`]).
    warnings: Vec<String>,
}

impl Construction<'_> {
    /// Height of face `f` over its edge `k` (twice the area over the edge length).
    fn height(&self, (f, k): PieceId) -> f64 {
        let p = self.mesh.faces()[f].map(|v| self.mesh.positions()[v as usize]);
        (p[1] - p[0]).cross(p[2] - p[0]).length() / (p[(k + 1) % 3] - p[k]).length()
    }

    /// The origin of face `f`'s frame.
    fn origin(&self, f: usize) -> DVec3 {
        self.mesh.positions()[self.mesh.faces()[f][0] as usize]
    }

    /// Steps 3–4 at the edge shared by pieces `p` and `q`: both sub-nets with their centres
    /// made coplanar, as quartics, each in its face's frame; `to_p` takes a point of Q's
    /// frame into P's, where the two centres are compared.
    fn edge_quartics(&self, p: PieceId, q: PieceId, to_p: DVec3) -> (Quartic, Quartic) {
        let mut cubic_p = self.cubic_pieces[p.0][p.1];
        let mut cubic_q = self.cubic_pieces[q.0][q.1];
        let centre = index(3, 1, 1);
        let (centre_p, centre_q) = cubic_net::coplanar_centres(
            cubic_p[index(3, 2, 1)],
            cubic_p[index(3, 1, 2)],
            cubic_p[centre],
            cubic_q[centre] + to_p,
            self.height(p),
            self.height(q),
        );
        cubic_p[centre] = centre_p;
        cubic_q[centre] = centre_q - to_p;
        (cubic_net::elevate(&cubic_p), cubic_net::elevate(&cubic_q))
    }

    /// Steps 3–5 at the edge shared by pieces `p` and `q` (`p` < `q`, so that both faces get
    /// the same result bit for bit): the two quartic pieces after the G¹ solve, each in its
    /// face's frame (the solve runs in P's).
    fn solve_edge(&self, p: PieceId, q: PieceId) -> Result<(Quartic, Quartic)> {
        let to_p = self.origin(q.0) - self.origin(p.0);
        let (mut quartic_p, mut quartic_q) = self.edge_quartics(p, q, to_p);
        let net = edge_net(&quartic_p, &quartic_q, to_p);
        let face = self.mesh.faces()[p.0];
        let (start, end) = (face[p.1] as usize, face[(p.1 + 1) % 3] as usize);
        let fold = |a: usize, b: usize| Error::DegenerateEdge {
            scheme: SPEC.name.to_string(),
            a,
            b,
            reason: format!(
                "at vertex {} the control points of both faces are in line with the edge \
                 (the faces fold onto each other)",
                self.mesh.input_vertex(a as u32)
            ),
            also: Vec::new(),
        };
        let (w1, w2) = g1_solve::end_weights(&net);
        let w1 = w1.ok_or_else(|| fold(start, end))?;
        let w2 = w2.ok_or_else(|| fold(end, start))?;
        let x = g1_solve::solve_edge(&net, w1, w2);
        quartic_p[index(4, 2, 1)] = x.r[0];
        quartic_p[index(4, 1, 2)] = x.r[1];
        quartic_p[index(4, 2, 2)] = x.s2;
        quartic_q[index(4, 1, 2)] = x.t[0] - to_p;
        quartic_q[index(4, 2, 1)] = x.t[1] - to_p;
        quartic_q[index(4, 2, 2)] = x.s2 - to_p;
        Ok((quartic_p, quartic_q))
    }

    /// The three final quartic nets of face `f`.
    fn face_nets(&self, f: usize) -> Result<[Quartic; 3]> {
        let mut pieces = [[glam::DVec3::ZERO; 15]; 3];
        for (k, piece) in pieces.iter_mut().enumerate() {
            *piece = match self.mesh.neighbor(f as u32, k) {
                // A boundary edge, or a sharp one: no G¹ solve across it.
                Some((g, kg)) if !self.mesh.is_sharp(f as u32, k) => {
                    let other = (g as usize, kg);
                    if f < other.0 {
                        self.solve_edge((f, k), other)?.0
                    } else {
                        self.solve_edge(other, (f, k))?.1
                    }
                }
                _ => cubic_net::elevate(&self.cubic_pieces[f][k]),
            };
        }
        c1_restore::restore_c1(&mut pieces);
        Ok(pieces)
    }
}

/// Builds Piper's surface: 3 quartic patches per face, piece `k` over the sub-triangle
/// (corner k, corner k+1, centroid) of the face.
fn build(mesh: &Mesh, params: &Params) -> Result<Surface> {
    let construction = candidates(mesh, params)?;
    // Steps 3–5, per face (each shared edge is solved by both of its faces, identically).
    let nets = (0..mesh.face_count())
        .into_par_iter()
        .map(|f| construction.face_nets(f))
        .collect::<Vec<Result<_>>>();
    let nets = crate::error::collect_in_order(nets)?;
    let (positions, faces) = (mesh.positions(), mesh.faces());
    let patches = nets
        .into_iter()
        .enumerate()
        .flat_map(|(f, pieces)| {
            pieces.into_iter().enumerate().map(move |(k, net)| Patch {
                face: f as u32,
                piece: k as u8,
                domain: cubic_net::piece_domain(k),
                geometry: PatchGeometry::Bezier(TriangleBezier::with_origin(
                    4,
                    positions[faces[f][0] as usize],
                    net.to_vec(),
                )),
            })
        })
        .collect();
    let mut surface = params.surface(SPEC.name, patches);
    surface.warnings = construction.warnings;
    Ok(surface)
}

/// Steps 1–2 for every face, in parallel.
fn candidates<'a>(mesh: &'a Mesh, params: &Params) -> Result<Construction<'a>> {
    let scaling = edge_scaling(params)?;
    let (normals, warnings) =
        crate::schemes::scheme_normals(mesh, params, SPEC.name, AtFoldedVertex::Refuse)?;
    let positions = mesh.positions();
    let corner_normals = mesh.corner_normals(&normals);
    // Steps 1–2, per face.
    let cubic_pieces = (0..mesh.face_count())
        .into_par_iter()
        .map(|f| {
            let face = mesh.faces()[f];
            cubic_net::candidate_net(
                FaceFrame::of(positions, face).corners,
                corner_normals[f],
                creases(mesh, &corner_normals, f),
                swerving_legs(mesh, &corner_normals, f),
                scaling,
            )
            .map(|net| cubic_net::split_at_centroid(&net))
            .map_err(|(from, to)| Error::DegenerateEdge {
                scheme: SPEC.name.to_string(),
                a: face[from] as usize,
                b: face[to] as usize,
                reason: format!(
                    "the normal of vertex {} (or the crease of its sectors, on a sharp \
                         edge) lies across the edge, so the edge has no tangent direction there",
                    mesh.input_vertex(face[from])
                ),
                also: Vec::new(),
            })
        })
        .collect::<Vec<Result<_>>>();
    let cubic_pieces = crate::error::collect_in_order(cubic_pieces)?;
    Ok(Construction {
        mesh,
        cubic_pieces,
        warnings,
    })
}

/// For each edge `e` of face `f` and each end (0: at corner `e`, 1: at corner `e + 1`), true
/// when the leg there (the chord projected orthogonally into the vertex's tangent plane),
/// seen from either face of the edge, swerves across the face's far edge: its angle to the
/// chord, towards the face, exceeds the face's angle at the vertex. Decided from both faces
/// alike, so both build the same boundary curve.
fn swerving_legs(mesh: &Mesh, corner_normals: &[[glam::DVec3; 3]], f: usize) -> [[bool; 2]; 3] {
    let positions = mesh.positions();
    // Does the leg at corner `k` of face `g` towards corner `to` swerve past the face's wedge?
    let swerves = |g: usize, k: usize, to: usize| -> bool {
        let face = mesh.faces()[g];
        let third = 3 - k - to;
        let (a, b, c) = (
            positions[face[k] as usize],
            positions[face[to] as usize],
            positions[face[third] as usize],
        );
        let n = corner_normals[g][k];
        let chord = b - a;
        let leg = chord - chord.dot(n) * n;
        let face_normal = (b - a).cross(c - a);
        let mut inward = face_normal.cross(chord).normalize_or_zero();
        if inward.dot(c - a) < 0.0 {
            inward = -inward;
        }
        let swerve = leg.dot(inward).atan2(leg.dot(chord.normalize_or_zero()));
        swerve > chord.angle_between(c - a)
    };
    std::array::from_fn(|e| {
        if mesh.is_sharp(f as u32, e) {
            return [false; 2];
        }
        let other = mesh.neighbor(f as u32, e);
        std::array::from_fn(|end| {
            let (k, to) = if end == 0 {
                (e, (e + 1) % 3)
            } else {
                ((e + 1) % 3, e)
            };
            // In g, corner e of f is corner ge + 1, corner e + 1 of f is corner ge.
            swerves(f, k, to)
                || other.is_some_and(|(g, ge)| {
                    let (kg, tog) = if end == 0 {
                        ((ge + 1) % 3, ge)
                    } else {
                        (ge, (ge + 1) % 3)
                    };
                    swerves(g as usize, kg, tog)
                })
        })
    })
}

/// For each sharp edge `e` of face `f` (corner `e` → `e + 1`), the normals of the
/// neighbour's sectors at the edge's two ends ([`cubic_net::candidate_net`]).
fn creases(
    mesh: &Mesh,
    corner_normals: &[[glam::DVec3; 3]],
    f: usize,
) -> [Option<[glam::DVec3; 2]>; 3] {
    std::array::from_fn(|e| {
        let (g, ge) = mesh.neighbor(f as u32, e)?;
        // Corner e of f is corner ge + 1 of g, and corner e + 1 of f is corner ge of g.
        let other = corner_normals[g as usize];
        mesh.is_sharp(f as u32, e)
            .then(|| [other[(ge + 1) % 3], other[ge]])
    })
}

#[cfg(test)]
mod tests;
