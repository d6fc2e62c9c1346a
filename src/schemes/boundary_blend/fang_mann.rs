//! `fang-mann`: Fang and Mann's modified boundary blend [FM, "The Modified Method"] with cubic
//! Bézier sub-surfaces and the weights `f_{t,0..2}` (`α = b0^{t+1}`, …), parameter `t`.
//!
//! # The sub-surfaces: one edge surface per mesh edge
//!
//! Every mesh edge `a → b` carries one cubic polynomial surface over the plane of its edge
//! coordinates `(s, h)` ([`super::EdgeFrame`]):
//!
//! `E(s, h) = C(s) + h D(s) + h² Q`
//!
//! with the boundary curve `C` (cubic), the linear transversal field `D` and a constant `Q`
//! (total degree three). `Q` is the least-squares choice that makes `E` pass near the apexes
//! of the edge's faces, `Q = Σ h_X² r_X / Σ h_X⁴` with `r_X = P_X − C(σ_X) − h_X D(σ_X)`, so
//! that `E` bends across the edge as the mesh does (with `Q = 0` the surface would have zero
//! normal curvature across every edge). The sub-surface `S_i` of a face that owns the edge
//! opposite corner `i` is `E` restricted to the face's triangle in that plane: corners
//! `a ↦ (0,0)`, `b ↦ (1,0)`, corner `i ↦` the face's apex `(σ, h)`. Its Bézier net is the
//! blossom of `E` at those three points.
//!
//! Conditions 3'–5' hold: `E(0,0) = P_a`, `E(1,0) = P_b`, and at each end `∂E/∂s = π(P_b −
//! P_a)` and `∂E/∂h = D` lie in the vertex's tangent plane (`π` the projection onto it), so
//! each sub-surface interpolates the positions and normals of the two vertices of its edge.
//! Its third corner `E(σ, h)` is free, as the poster notes, and near the apex `P_i` by the
//! choice of `Q`.
//!
//! # Why two faces join with `C^t`
//!
//! 1. *The blend agrees with the owner to order `t`.* `S = S_0 + f_1 (S_1 − S_0) + f_2 (S_2 −
//!    S_0)` since the weights sum to one. `f_1 = γα(1/(β+γ) + 1/(β+α))/(α+β+γ)` and `f_2 =
//!    αβ(1/(γ+α) + 1/(γ+β))/(α+β+γ)` both have the factor `α = b_0^{t+1}`, and at any point
//!    of the open edge `b_0 = 0` the remaining factors are smooth (every denominator is at
//!    least `β + γ > 0` there). So `S − S_0 = O(b_0^{t+1})`: all partial derivatives of
//!    order ≤ `t` of `S` and `S_0` coincide along the edge.
//! 2. *The two owners are one polynomial.* For faces `A` and `B` on the two sides of edge
//!    `a → b`, `S_0^A = E ∘ φ_A` and `S_0^B = E ∘ φ_B` with affine maps `φ_A`, `φ_B` from the
//!    faces' barycentric domains into the edge plane that agree on the common edge. With the
//!    affine map `ψ = φ_B⁻¹ ∘ φ_A` (the two domains unfolded side by side), `S_0^B ∘ ψ =
//!    E ∘ φ_A = S_0^A`: the owners are pieces of the same polynomial, and join with every
//!    order of continuity.
//!
//! Together: along the shared edge, the derivatives up to order `t` of `S^A` equal those of
//! `E ∘ φ_A`, and those of `S^B ∘ ψ` equal those of `E ∘ φ_B ∘ ψ = E ∘ φ_A`. The surfaces
//! join `C^t` in the unfolded parametrisation, hence `G^t`: for `t ≥ 1` the normals agree,
//! for `t ≥ 2` also the Gaussian and mean curvature. This holds for every `t` (the edge
//! surface agrees to infinite order); `t = 0` gives only `C⁰`. At the vertices the blend
//! interpolates the vertex and its normal, but its curvature has no limit there (the weights
//! have none), for every `t`.

use glam::{DVec2, DVec3};

use crate::bezier::TriangleBezier;
use crate::blend::WeightFamily;
use crate::error::Result;
use crate::mesh::Mesh;
use crate::schemes::boundary_blend::{EdgeFrame, EdgeFrames, blend_params, build_blend};
use crate::schemes::{Params, SchemeSpec};
use crate::surface::Surface;

/// Largest accepted `t` (the weights use powers `t + 1`; beyond this nothing new is shown and
/// the weight derivatives near corners grow like `r^{−(t+1)}`).
pub(crate) const MAX_T: u32 = 6;

/// Registry entry.
pub(crate) const SPEC: SchemeSpec = SchemeSpec {
    name: "fang-mann",
    summary: "Fang-Mann boundary blend: cubic sub-surfaces from one edge surface per edge, C^t",
    params: &blend_params("continuity order t (0..=6): weights f_{t,i} with alpha = u^(t+1)"),
    needs_closed_mesh: false,
    bytes_per_face: 2900.0,
    sharp_edges: crate::schemes::SharpEdgeSupport::Builds,
    build,
};

fn build(mesh: &Mesh, params: &Params) -> Result<Surface> {
    build_blend(
        mesh,
        params,
        SPEC.name,
        0..=MAX_T,
        |t| WeightFamily::FangMann { t },
        |frames, faces, f, c| Ok(sub_surface(frames, faces, f, c)),
    )
}

/// The cross-edge curvature term `Q` of the edge surface: least squares over the apexes.
pub(crate) fn cross_curvature(frame: &EdgeFrame) -> DVec3 {
    let (mut weighted, mut norm) = (DVec3::ZERO, 0.0);
    for (x, p) in frame.apex.iter().flatten() {
        let h2 = x.y * x.y;
        let residual = *p - edge_surface(frame, DVec3::ZERO, *x);
        weighted += h2 * residual;
        norm += h2 * h2;
    }
    if norm > 0.0 {
        weighted / norm
    } else {
        DVec3::ZERO
    }
}

/// `E(s, h)` with cross term `q`, relative to the frame's origin (`P_a`).
pub(crate) fn edge_surface(frame: &EdgeFrame, q: DVec3, x: DVec2) -> DVec3 {
    edge_surface_blossom(frame, q, [x, x, x])
}

/// The blossom of `E` (symmetric, affine in each argument, `E` on the diagonal), relative to
/// the frame's origin:
/// `c[s₁,s₂,s₃] + D_a (Σh)/3 + (D_b − D_a) Σ_{i≠j} h_i s_j / 6 + Q Σ_{i<j} h_i h_j / 3`,
/// the cubic blossoms of `C(s)`, `h`, `h·s` and `h²`.
pub(crate) fn edge_surface_blossom(frame: &EdgeFrame, q: DVec3, x: [DVec2; 3]) -> DVec3 {
    let c = frame.curve.blossom(&[x[0].x, x[1].x, x[2].x]);
    let [d_a, d_b] = frame.transversal;
    let h_sum = x[0].y + x[1].y + x[2].y;
    let mixed =
        x[0].y * (x[1].x + x[2].x) + x[1].y * (x[0].x + x[2].x) + x[2].y * (x[0].x + x[1].x);
    let h_pairs = x[0].y * x[1].y + x[0].y * x[2].y + x[1].y * x[2].y;
    c + d_a * (h_sum / 3.0) + (d_b - d_a) * (mixed / 6.0) + q * (h_pairs / 3.0)
}

/// The sub-surface of face `f` owning the edge opposite corner `c`: the edge surface over the
/// face's triangle in the edge plane, as a cubic net in the face's corner order and frame.
pub(crate) fn sub_surface(
    frames: &EdgeFrames,
    faces: &[[u32; 3]],
    f: usize,
    c: usize,
) -> TriangleBezier {
    let (frame, forward) = frames.opposite(faces, f, c);
    let q = cross_curvature(frame);
    let mut corners = [DVec2::ZERO; 3];
    corners[(c + 1) % 3] = if forward { DVec2::ZERO } else { DVec2::X };
    corners[(c + 2) % 3] = if forward { DVec2::X } else { DVec2::ZERO };
    corners[c] = frame.apex_point(forward);
    let shift = frames.to_face(frame, f);
    TriangleBezier::from_fn(3, |i, j, _| {
        let mut args = [DVec2::ZERO; 3];
        for (n, arg) in args.iter_mut().enumerate() {
            *arg = if n < i {
                corners[0]
            } else if n < i + j {
                corners[1]
            } else {
                corners[2]
            };
        }
        shift + edge_surface_blossom(frame, q, args)
    })
}
