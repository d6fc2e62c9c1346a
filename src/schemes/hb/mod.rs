//! Hahmann–Bonneau 2000, *Triangular G¹ interpolation by 4-splitting domain triangles* [HB00]:
//! a piecewise quintic G¹ surface with one macro-patch of four Bézier triangles per mesh face.
//!
//! The construction runs in three local passes, each parallel over its elements:
//! 1. per vertex ([`vertex`]): boundary-curve control points `b0, b1, b2` of every edge leaving
//!    the vertex (eqs. 9–15), the twists (eq. 17) and `v⁰, v¹` of the cross-boundary function
//!    (eqs. 19–23) — from the one-ring alone;
//! 2. per edge: the curve midpoint `b3 = (b2 + b̃2)/2` (eq. 16) and `v²`, chosen so that `V` is C¹
//!    at the midpoint (HB00 §7, the choice of §9);
//! 3. per face ([`macro_patch`]): the four quintic nets (eqs. 24–33 and the fill of Fig. 13).
//!
//! `V` changes sign with the edge direction: seen from the other end `w` of an edge `v → w`,
//! `Ψ̃(1−u) = Ψ(u)` and `Φ̃(1−u) = 1 − Φ(u)`, so (eq. 18) `Ṽ(1−u) = −V(u)`. Hence, with `v¹` and
//! `ṽ¹` computed at either end, C¹ continuity of `V` at `u = ½` gives `v² = (v¹ − ṽ¹)/2 = −ṽ²`.
//! (HB00 §9 writes `v² = ½v¹ + ½v¹_k` in a per-end sign convention.)
//!
//! Default shape parameters: α = 1 interpolates the vertices; β = 1/3 and (γ0, γ1, γ2) =
//! (1/3, 0, 2/3) give linear precision on regular meshes — for a planar ring of valence 6 the
//! boundary curves are the straight edges parametrised uniformly, the twists vanish and `V` is
//! constant (tested in [`vertex`]). The six free points default to the thin-plate minimiser
//! (`free=energy`, as in the paper's colour plate); `free=zero-twist` is the cheap alternative.

pub mod energy;
pub mod macro_patch;
pub mod vertex;

use rayon::prelude::*;

use crate::bezier::TriangleBezier;
use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::schemes::{ParamSpec, Params, SchemeSpec};
use crate::surface::{Patch, PatchGeometry, Surface};
use macro_patch::{FreeRule, HalfEdgeCurve, macro_patch, piece_domains};
use vertex::{HalfEdgeData, ShapeParams, half_edges, psi0};

/// Registry entry.
pub const SPEC: SchemeSpec = SchemeSpec {
    name: "hb",
    summary: "Hahmann-Bonneau 2000: quintic G1 interpolant, 4 Bezier triangles per face (HB00)",
    params: &[
        ParamSpec {
            name: "alpha",
            default: "1",
            help: "α of eq. 9: 1 interpolates the vertices, < 1 pulls towards the ring centroid",
        },
        ParamSpec {
            name: "beta",
            default: "0.333333333333333333",
            help: "β of eq. 12 (> 0): tangent length; 1/3 gives linear precision",
        },
        ParamSpec {
            name: "gamma0",
            default: "0.333333333333333333",
            help: "γ0 of eq. 15 (weight of b0 in b2)",
        },
        ParamSpec {
            name: "gamma1",
            default: "0",
            help: "γ1 of eq. 15 (weight of b1 in b2)",
        },
        ParamSpec {
            name: "gamma2",
            default: "auto",
            help: "γ2 of eq. 15 (weight of Loop's point d); auto = 1 − γ0 − γ1",
        },
        ParamSpec {
            name: "free",
            default: "energy",
            help: "six free points per face: energy (thin-plate minimiser) | zero-twist",
        },
    ],
    needs_closed_mesh: true,
    build,
};

/// Reads and checks the shape parameters.
fn shape_params(params: &Params) -> Result<(ShapeParams, FreeRule)> {
    let alpha = params.number("alpha")?;
    let beta = params.number("beta")?;
    if beta <= 0.0 {
        return Err(Error::BadParam {
            name: "beta".into(),
            reason: format!("must be > 0 (tangents vanish or flip), got {beta}"),
        });
    }
    let (g0, g1) = (params.number("gamma0")?, params.number("gamma1")?);
    let g2 = if params.text("gamma2") == "auto" {
        1.0 - g0 - g1
    } else {
        let g2 = params.number("gamma2")?;
        if (g0 + g1 + g2 - 1.0).abs() > 1e-9 {
            return Err(Error::BadParam {
                name: "gamma2".into(),
                reason: format!(
                    "γ0 + γ1 + γ2 must be 1 (eq. 15), got {g0} + {g1} + {g2} = {}",
                    g0 + g1 + g2
                ),
            });
        }
        g2
    };
    let free = match params.choice("free", &["energy", "zero-twist"])? {
        "zero-twist" => FreeRule::ZeroTwist,
        _ => FreeRule::Energy,
    };
    Ok((
        ShapeParams {
            alpha,
            beta,
            gamma: [g0, g1, g2],
        },
        free,
    ))
}

/// Pass 1 for the whole mesh: half-edge data in one flat array, vertex by vertex in one-ring
/// order (`offsets[v] + i` is the edge `v → one_ring(v)[i]`).
fn all_half_edges(mesh: &Mesh, shape: &ShapeParams) -> (Vec<usize>, Vec<HalfEdgeData>) {
    let nv = mesh.vertex_count();
    let mut offsets = Vec::with_capacity(nv + 1);
    let mut total = 0;
    for v in 0..nv {
        offsets.push(total);
        total += mesh.valence(v as u32);
    }
    offsets.push(total);
    let positions = mesh.positions();
    let mut data = vec![HalfEdgeData::default(); total];
    let mut slices: Vec<&mut [HalfEdgeData]> = Vec::with_capacity(nv);
    let mut rest = data.as_mut_slice();
    for v in 0..nv {
        let (head, tail) = rest.split_at_mut(offsets[v + 1] - offsets[v]);
        slices.push(head);
        rest = tail;
    }
    slices.into_par_iter().enumerate().for_each_init(
        || (Vec::new(), Vec::new()),
        |(ring_points, ring_valence), (v, out)| {
            let ring = mesh.one_ring(v as u32);
            ring_points.clear();
            ring_points.extend(ring.iter().map(|&p| positions[p as usize]));
            ring_valence.clear();
            ring_valence.extend(ring.iter().map(|&p| mesh.valence(p)));
            half_edges(positions[v], ring_points, ring_valence, shape, out);
        },
    );
    (offsets, data)
}

/// Position of `w` in the one-ring of `v`.
fn ring_index(mesh: &Mesh, v: u32, w: u32) -> usize {
    mesh.one_ring(v)
        .iter()
        .position(|&x| x == w)
        .expect("closed manifold mesh: every edge is in both one-rings")
}

/// Pass 2 for edge `x → y`: the half-edge data of `x` completed with the midpoint (eq. 16),
/// `v²` (C¹ `V`, see the module doc) and `Ψ(½)` (eq. 29).
fn half_edge_curve(
    mesh: &Mesh,
    offsets: &[usize],
    data: &[HalfEdgeData],
    x: u32,
    y: u32,
) -> HalfEdgeCurve {
    let here = &data[offsets[x as usize] + ring_index(mesh, x, y)];
    let there = &data[offsets[y as usize] + ring_index(mesh, y, x)];
    HalfEdgeCurve {
        b: [
            here.b[0],
            here.b[1],
            here.b[2],
            0.5 * (here.b[2] + there.b[2]),
        ],
        v: [here.v0, here.v1, 0.5 * (here.v1 - there.v1)],
        phi0: here.phi0,
        psi: [here.psi0, 0.5 * (here.psi0 + psi0(mesh.valence(y)))],
    }
}

/// The two half-edge curves leaving each corner of `face`: `(X→Y, X→Z)` for corner `X = a_k`.
fn face_corner_curves(
    mesh: &Mesh,
    offsets: &[usize],
    data: &[HalfEdgeData],
    face: [u32; 3],
) -> [(HalfEdgeCurve, HalfEdgeCurve); 3] {
    std::array::from_fn(|k| {
        let (x, y, z) = (face[k], face[(k + 1) % 3], face[(k + 2) % 3]);
        (
            half_edge_curve(mesh, offsets, data, x, y),
            half_edge_curve(mesh, offsets, data, x, z),
        )
    })
}

/// Builds the HB00 surface: 4 quintic patches per face, pieces 0–2 at the face corners, 3 in the
/// middle.
fn build(mesh: &Mesh, params: &Params) -> Result<Surface> {
    let (shape, free) = shape_params(params)?;
    let (offsets, data) = all_half_edges(mesh, &shape);
    let nets: Vec<macro_patch::MacroNets> = mesh
        .faces()
        .par_iter()
        .map(|face| macro_patch(&face_corner_curves(mesh, &offsets, &data, *face), free))
        .collect();
    let domains = piece_domains();
    let patches: Vec<Patch> = (0..4 * nets.len())
        .into_par_iter()
        .map(|i| {
            let (face, piece) = (i / 4, i % 4);
            Patch {
                face: face as u32,
                piece: piece as u8,
                domain: domains[piece],
                geometry: PatchGeometry::Bezier(TriangleBezier::new(5, nets[face][piece].to_vec())),
            }
        })
        .collect();
    Ok(Surface {
        scheme: SPEC.name.to_string(),
        params: params.values().to_vec(),
        patches,
    })
}

/// Largest disagreement between the two ways of computing the points two edges share at a
/// corner piece (twist compatibility, eq. 19), over all face corners; for tests and diagnostics.
pub fn max_corner_mismatch(mesh: &Mesh, params: &Params) -> Result<f64> {
    let (shape, _) = shape_params(params)?;
    let (offsets, data) = all_half_edges(mesh, &shape);
    Ok(mesh
        .faces()
        .iter()
        .flat_map(|face| face_corner_curves(mesh, &offsets, &data, *face))
        .map(|(to_y, to_z)| macro_patch::corner_mismatch(&to_y, &to_z))
        .fold(0.0, f64::max))
}

#[cfg(test)]
mod tests;
