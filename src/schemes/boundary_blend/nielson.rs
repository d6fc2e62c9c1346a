//! `nielson`: Nielson's side-vertex blend [FM, "Nielson's Method"] of three quartic
//! sub-surfaces per face with the weights `b_j b_k / Σ b_j b_k` (Nielson 1987).
//!
//! # Why only `t = 1`
//!
//! The poster's power variant `(b_j b_k)^t / Σ (b_j b_k)^t` (after Hagen and Pottmann) reaches
//! order `t` only when the sub-surfaces also carry matching higher-order cross-boundary data.
//! With `t = 2` the weights' first derivatives vanish on the edges, so the blend's second
//! derivatives there are the owning sub-surface's, but these sub-surfaces carry tangent-plane
//! data only: measured, `t = 2` stays G¹ with relative curvature jumps of 0.72
//! (deformed-icosahedron) and 2.0 (mixed-valence). A parameter value that does not give what
//! its name promises is refused ([`build`]); `fang-mann` with `t = 2` is curvature continuous.
//!
//! # The sub-surfaces
//!
//! Nielson's conditions 1–5 ask that the three sub-surfaces of a face share all three
//! boundary curves and that `S_i` carry the tangent planes along the edge opposite corner
//! `i`. With the edge frames of [`super`] (boundary curve `C`, transversal field `W(s)`,
//! both shared by the two faces of an edge), `S_i` is the quartic Bézier triangle with
//! * the three boundary curves `C` of the face's edges, elevated to degree four, on its
//!   boundary (so the three sub-surfaces share them bit for bit);
//! * along its own edge (corner `i+1` to `i+2`, parameter `τ`), the derivative towards
//!   corner `i` along `d(τ) = e_i − ((1−τ) e_{i+1} + τ e_{i+2})` equal to
//!   `D(τ) = α(τ) W(τ) + β(τ) C'(τ)` with `α, β` linear. `α(0), β(0)` write the tangent of
//!   the boundary curve from corner `i+1` to corner `i` in the basis `W, C'` of the tangent
//!   plane at corner `i+1` (exact, because both lie in it), and likewise at `τ = 1`. `D` is
//!   cubic, and the derivative of a quartic along `d(τ)` on the edge is `4 (R(τ) − C(τ))`
//!   with `R` the cubic of its second row, so the second row is `R = C + D/4`: its end
//!   points are the boundary curves' second points, consistent with the other edges;
//! * its one remaining point `b(2,1,1)` (local indices) at the mean of its two neighbours
//!   on the other boundary rows, which keeps linear precision.
//!
//! # Why two faces join with G¹
//!
//! On the edge `b_i = 0`, `W_i = 1`, the other weights vanish and so does every difference
//! `S_j − S_i` (shared boundary curves), so `∂S = ∂S_i + Σ_j (∂W_j (S_j − S_i) + W_j ∂(S_j −
//! S_i)) = ∂S_i`: the blend's tangent plane is the owner's, spanned by `C'(τ)` and `D(τ)`,
//! i.e. by `C'` and `W`, with `α > 0` keeping the orientation. The face on the other side
//! builds its owner from the same `C` and `W`, so its tangent plane is the same plane at every
//! point of the edge. At a vertex, all three sub-surfaces of a face share the two boundary
//! curves through it and therefore their first derivatives: the blend is `C¹` there with the
//! vertex normal. Second derivatives are not matched: the curvature jumps across edges.

use glam::DVec3;

use crate::bezier::{CurveBezier, TriangleBezier};
use crate::blend::WeightFamily;
use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::schemes::boundary_blend::{EdgeFrames, blend_params, build_blend};
use crate::schemes::{Params, SchemeSpec};
use crate::surface::Surface;

/// Registry entry.
pub(crate) const SPEC: SchemeSpec = SchemeSpec {
    name: "nielson",
    summary: "Nielson 1987 side-vertex blend of three quartic sub-surfaces per face, G1 (FM)",
    params: &blend_params(
        "power of the weights; only 1 (Nielson's): higher powers stay G1 here (use fang-mann)",
    ),
    needs_closed_mesh: false,
    bytes_per_face: 3600.0,
    sharp_edges: crate::schemes::SharpEdgeSupport::Builds,
    build,
};

/// Builds the surface; `t ≥ 2` is refused with the reason (see the module docs).
fn build(mesh: &Mesh, params: &Params) -> Result<Surface> {
    if let Ok(t) = params.text("t").trim().parse::<u32>()
        && t >= 2
    {
        return Err(Error::BadParam {
            name: "t".to_string(),
            reason: format!(
                "{t} is refused: nielson's sub-surfaces carry only tangent-plane data across the \
                 edges, so a higher power of the weights leaves the surface G1 (curvature jumps \
                 0.72-2.0 measured at t = 2); fang-mann t={t} is G{t}"
            ),
        });
    }
    build_blend(
        mesh,
        params,
        SPEC.name,
        1..=1,
        |power| WeightFamily::Nielson { power },
        sub_surface,
    )
}

/// `(α, β)` with `target = α w + β t`, for `target` in the plane of `w` and `t` (normal
/// equations of the 2×2 least-squares problem).
fn decompose(target: DVec3, w: DVec3, t: DVec3) -> (f64, f64) {
    let (ww, wt, tt) = (w.dot(w), w.dot(t), t.dot(t));
    let (rw, rt) = (target.dot(w), target.dot(t));
    let det = ww * tt - wt * wt;
    ((rw * tt - rt * wt) / det, (ww * rt - wt * rw) / det)
}

/// The quartic sub-surface of face `f` owning the edge opposite corner `c`, in the face's
/// corner order.
pub(crate) fn sub_surface(
    frames: &EdgeFrames,
    faces: &[[u32; 3]],
    f: usize,
    c: usize,
) -> Result<TriangleBezier> {
    let (next, far) = ((c + 1) % 3, (c + 2) % 3);
    let (frame, forward) = frames.opposite(faces, f, c);
    // Own edge next → far, and the two other boundary curves towards corner c.
    let own = CurveBezier::new(frames.curve_between(faces, f, next, far, false));
    let own_quartic = frames.curve_between(faces, f, next, far, true);
    let to_c_from_next = frames.curve_between(faces, f, next, c, false);
    let to_c_from_far = frames.curve_between(faces, f, far, c, false);
    let g = frames.curve_between(faces, f, next, c, true);
    let h = frames.curve_between(faces, f, far, c, true);
    // The transversal field in the face's direction, pointing into the face.
    let [w_a, w_b] = frame.transversal;
    let (w0, w1) = if forward { (w_a, w_b) } else { (-w_b, -w_a) };
    let tangent = own.derivative();
    let (t0, t1) = (tangent.points()[0], tangent.points()[2]);
    let (alpha0, beta0) = decompose(3.0 * (to_c_from_next[1] - to_c_from_next[0]), w0, t0);
    let (alpha1, beta1) = decompose(3.0 * (to_c_from_far[1] - to_c_from_far[0]), w1, t1);
    if !(alpha0 > 0.0 && alpha1 > 0.0) {
        let fv = faces[f];
        return Err(Error::DegenerateEdge {
            scheme: SPEC.name.to_string(),
            a: fv[next] as usize,
            b: fv[far] as usize,
            reason: format!(
                "face {f} folds back over the edge's tangent planes (transversal weights \
                 {alpha0:.2e}, {alpha1:.2e})"
            ),
            also: Vec::new(),
        });
    }
    // D(τ) = α(τ) W(τ) + β(τ) C'(τ), cubic.
    let along_w = CurveBezier::new(vec![w0, w1])
        .times_scalar_polynomial(&[alpha0, alpha1])
        .elevate();
    let along_t = tangent.times_scalar_polynomial(&[beta0, beta1]);
    let second_row: Vec<DVec3> = (0..4)
        .map(|m| own.points()[m] + (along_w.points()[m] + along_t.points()[m]) / 4.0)
        .collect();
    // Local net L(l0, l1, l2) with l0 at corner c, l1 at next, l2 at far.
    let local = |l0: usize, l1: usize, l2: usize| -> DVec3 {
        match (l0, l1, l2) {
            (0, _, m) => own_quartic[m],
            (l0, _, 0) => g[l0],
            (l0, 0, _) => h[l0],
            (1, _, m) => second_row[m],
            _ => 0.5 * (g[2] + h[2]),
        }
    };
    Ok(TriangleBezier::from_fn(4, |i, j, k| {
        let index = [i, j, k];
        local(index[c], index[next], index[far])
    }))
}
