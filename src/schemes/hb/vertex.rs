//! What HB00 computes around one mesh vertex `v` from its one-ring alone (locality): the first
//! three control points of every boundary-curve piece leaving `v` [HB00 §6, eqs. 9–15], the
//! twists of the macro-patches at `v` [HB00 eq. 17], and the first two control points of the
//! quadratic piece of the cross-boundary function `V_i` next to `v` [HB00 eqs. 19–23].
//!
//! Notation follows HB00 §2: `v` has order `n`, neighbours `p_1..p_n` ordered so that
//! `(v, p_i, p_{i+1})` is a face (macro-patch `M^i(u_i, u_{i+1})`), `θ = 2π/n`. Indices in code
//! start at 0.
//!
//! Two places of the OCR text are re-derived here instead of transcribed:
//! * eq. 14 prints `r²_i = 12(b2 − 2b1 + b0)`, but the boundary piece is a cubic in `2u`, so
//!   `M_{u_i u_i}(0,0) = 4 · 6 (b2 − 2b1 + b0) = 24(…)`, which is also the factor the paper's own
//!   twist derivation (`24Φ⁰(b2 − 2b1 + b0)`) uses.
//! * eq. 23 (`v¹`) is garbled; `v¹ = v⁰ + V'(0)/4` follows from eq. 22 and the quadratic being
//!   written in the local parameter `2u` (so `V'(0) = 4(v¹ − v⁰)`). The twists are solved from
//!   (II_T) through the preimages `b̃` of §6 rather than read off eq. 17; the unit tests check
//!   (II_T), (19) and (21) numerically.

use std::f64::consts::PI;

use glam::DVec3;

use crate::schemes::vertex_rings::{PsiRule, RingFourier, front_facing_plane, psi0, swerve_cap};

/// The shape parameters of HB00: α (eq. 9), β (eq. 12), γ0, γ1, γ2 (eq. 15, γ0+γ1+γ2 = 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ShapeParams {
    /// α: 1 interpolates the mesh vertices, other values pull `b0` towards the ring centroid.
    pub alpha: f64,
    /// β: magnitude of the boundary-curve tangents (eq. 12).
    pub beta: f64,
    /// γ0, γ1, γ2: weights of `b0`, `b1` and Loop's point `d` in `b2` (eq. 15).
    pub gamma: [f64; 3],
}

/// How the shape parameters of one vertex are chosen: HB00 §6 leaves β, γ1, γ2 free *per
/// vertex* ("for each vertex a set of three free shape parameters β, γ1, γ2 is available").
/// `None` means: chosen for the vertex from its one-ring by [`adaptive_shape`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ShapeRule {
    /// α of eq. 9, the same at every vertex.
    pub alpha: f64,
    /// β of eq. 12, or `None` for the per-vertex choice of [`adaptive_shape`].
    pub beta: Option<f64>,
    /// (γ0, γ1, γ2) of eq. 15, or `None` for the per-vertex choice of [`adaptive_shape`].
    pub gamma: Option<[f64; 3]>,
    /// Which plane the tangents span.
    pub plane: PlaneRule,
    /// How far the boundary curves may swerve off their edges when β is chosen per vertex
    /// ([`swerve_cap`]): `hb::build` starts with a loose cap and takes
    /// [`HB_SWERVE`](crate::schemes::vertex_rings::HB_SWERVE) at the corners of folding faces.
    pub swerve: f64,
    /// How `Ψ` runs along each edge (`Ψ(½)`, and so `Ψ'(0)` in eq. 22).
    pub psi: PsiRule,
}

/// The tangent plane of the surface at a mesh vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PlaneRule {
    /// eq. 12: the plane of the ring's first Fourier sums `C`, `S`.
    Fourier,
    /// The plane normal to Max's vertex normal `Σ e_i × e_{i+1} / (|e_i|² |e_{i+1}|²)`
    /// (`e_i = p_i − v`; N. Max, *Weights for computing vertex normals from facet normals*,
    /// 1999), exact when the one-ring lies on a sphere through `v`. The first Fourier sums are
    /// projected into it, so eq. 12's tangents and eq. 17's twists keep their form.
    Max,
}

impl PlaneRule {
    /// The first Fourier sums of `ring` whose plane is this rule's tangent plane at `v`.
    pub(crate) fn ring_fourier(self, v: DVec3, ring: &[DVec3]) -> RingFourier {
        let fourier = RingFourier::new(ring);
        match self {
            PlaneRule::Fourier => fourier,
            PlaneRule::Max => match max_normal(v, ring) {
                Some(normal) => fourier.in_plane(normal),
                None => fourier,
            },
        }
    }
}

/// Max's vertex normal at `v` with the closed one-ring `ring` (see [`PlaneRule::Max`]); `None`
/// when the weighted sum vanishes or is not finite. The edges are divided by the longest first,
/// so that the fourth powers neither overflow nor underflow at extreme scales.
pub(crate) fn max_normal(v: DVec3, ring: &[DVec3]) -> Option<DVec3> {
    let n = ring.len();
    let scale = ring.iter().map(|p| (*p - v).length()).fold(0.0, f64::max);
    if !(scale > 0.0 && scale.is_finite()) {
        return None;
    }
    let sum: DVec3 = (0..n)
        .map(|i| {
            let (a, b) = ((ring[i] - v) / scale, (ring[(i + 1) % n] - v) / scale);
            a.cross(b) / (a.length_squared() * b.length_squared())
        })
        .sum();
    sum.try_normalize()
}

impl ShapeRule {
    /// Fills `out[i]` with the data of edge `v → ring[i]` at an interior vertex by this rule
    /// (eqs. 9–23); `ring_step[i]` is the angle step at `ring[i]` (`2π` over its order) of the
    /// face on the "+" side of the edge, `ring_step_minus[i]` of the face on the "−" side.
    /// The two differ only on the sharp edge of a dart whose far end is cut into sectors;
    /// there the "−" side gets its own `V'(0)` ([`HalfEdgeData::minus`]).
    pub(crate) fn half_edges(
        &self,
        v: DVec3,
        ring: &[DVec3],
        ring_step: &[f64],
        ring_step_minus: &[f64],
        out: &mut [HalfEdgeData],
    ) {
        let (fourier, _) = front_facing_plane(v, ring, self.plane.ring_fourier(v, ring));
        let shape = self.at_vertex(v, ring, &fourier);
        let edge_curvature = self.gamma.is_none();
        let s = psi0(ring.len());
        let psi_slope: Vec<f64> = ring_step
            .iter()
            .map(|t| self.psi.slope(s, t.sin()))
            .collect();
        half_edges(v, ring, &psi_slope, &fourier, &shape, edge_curvature, out);
        for ((slot, plus), minus) in out.iter_mut().zip(ring_step).zip(ring_step_minus) {
            if plus != minus {
                // (21) on the "−" side, t_{i−1} = R_i − Ψ'_− V(0) − Ψ V'_−(0), with (II_T)
                // t_i + t_{i−1} = 2 R_i and (21) on the "+" side: V'_− = V'_+ + (Ψ'_+ − Ψ'_−) V(0) / Ψ.
                let difference = self.psi.slope_difference(s, plus.sin(), minus.sin());
                let shift = difference * slot.v0 / slot.psi0;
                slot.minus = Some(CrossSide {
                    v1: slot.v1 + shift / 4.0,
                    ..slot.side(false)
                });
            }
        }
    }

    /// The parameters of the vertex `v` with one-ring `ring` and its first Fourier sums
    /// `fourier` (in the vertex's tangent plane).
    pub(crate) fn at_vertex(&self, v: DVec3, ring: &[DVec3], fourier: &RingFourier) -> ShapeParams {
        match (self.beta, self.gamma) {
            (Some(beta), Some(gamma)) => ShapeParams {
                alpha: self.alpha,
                beta,
                gamma,
            },
            _ => {
                let adaptive = adaptive_shape(v, ring, fourier, self.alpha, self.beta, self.swerve);
                ShapeParams {
                    gamma: self.gamma.unwrap_or(adaptive.gamma),
                    ..adaptive
                }
            }
        }
    }
}

/// Relative weight of the planar fallback in [`adaptive_shape`]'s choice of γ2: it decides only
/// where the ring's heights over the tangent plane are below ~1e-8 of its edge lengths.
const PLANAR_FALLBACK: f64 = 1e-16;

/// The per-vertex β is kept in this range: 1/3 (linear precision) to 1/2 covers the arcs of
/// rings up to a quarter circle; beyond, a ring is too coarse for a circle to be a guide, and
/// longer tangents lower the regularity of the macro-patches.
pub(crate) const BETA_RANGE: [f64; 2] = [0.25, 0.5];

/// The per-vertex γ2 is kept in this range: 0 (the tangent line) to twice its value 1/8 on a
/// regular ring of a sphere. The fit divides by the ring's heights over the tangent plane, which
/// can nearly cancel at a saddle.
pub(crate) const GAMMA2_RANGE: [f64; 2] = [0.0, 0.25];

/// Per-vertex shape parameters chosen from the one-ring so that the boundary curves leaving `v`
/// start like the circles the mesh implies [HB00 §6: β, γ1, γ2 free per vertex]:
///
/// * the vertex's tangent plane is the plane of the tangents `r¹_i` (eq. 12; its normal `N` is
///   `C × S` of the ring's first Fourier sums, independent of β);
/// * **β** (eq. 12): least squares fit of the ratios `|r¹_i| / ℓ_i` to 1, where `ℓ_i =
///   c_i Θ_i / sin Θ_i` is the length of the circular arc from `v` to `p_i` tangent to that plane
///   (`c_i = |p_i − v|`, `Θ_i` the angle between chord and plane) — the speed of the arc
///   parametrised uniformly. Fitting ratios rather than lengths keeps the tangents of a ring's
///   short edges from overshooting (measured min regularity on the genus-2 scene: 0.31, against
///   0.03 with a fit of the lengths). On a planar regular ring this is β = 1/3 (linear
///   precision);
/// * **γ2** (eq. 15) sets the normal part of `r²_i = 24(b2 − 2b1 + b0)` (eq. 14, factor
///   re-derived): only Loop's point `d_i` leaves the tangent plane, so
///   `r²_i · N = 24 γ2 (d_i − b0) · N`. γ2 is the least squares fit of that to
///   `κ_i |r¹_i|²`, the normal acceleration of the circle with the mesh's normal curvature
///   `κ_i = 2 (p_i − v) · N / c_i²` towards `p_i`. (With `γ2 = 0`, the old global default,
///   every normal curvature at `v` vanishes: a flat point.) On a regular ring this is
///   `γ2 = |r¹|² / (8 c²) ≈ 1/8` whatever the curvature, which is also the fallback for a planar
///   ring;
/// * **γ1** (eq. 15) removes the tangential part of `r²_i` in the least squares sense (a curve
///   of uniform speed), and γ0 = 1 − γ1 − γ2.
///
/// With `beta = Some(β)`, β is kept and only the γ are chosen; otherwise β is capped by
/// [`swerve_cap`] with `swerve`.
pub(crate) fn adaptive_shape(
    v: DVec3,
    ring: &[DVec3],
    fourier: &RingFourier,
    alpha: f64,
    beta: Option<f64>,
    swerve: f64,
) -> ShapeParams {
    let n = ring.len();
    let nf = n as f64;
    let b0 = alpha * v + (1.0 - alpha) * fourier.mean();
    let normal = fourier.normal();
    // r¹_i for β = 1 (eq. 12).
    let unit_tangent: Vec<DVec3> = (0..n).map(|i| (6.0 / nf) * fourier.cos_sum(i)).collect();
    // Loop's point d_i (eq. 15).
    let loop_point =
        |i: usize| (2.0 * v + ring[(i + n - 1) % n] + 2.0 * ring[i] + ring[(i + 1) % n]) / 6.0;
    ShapeParams {
        alpha,
        ..fit_shape(
            v,
            ring,
            b0,
            beta,
            swerve,
            &unit_tangent,
            normal,
            true,
            loop_point,
        )
    }
}

/// The fits of [`adaptive_shape`] over the edges `v → ring[i]`, given the vertex point `b0`,
/// the tangents `unit_tangent[i]` for β = 1, the tangent plane's `normal` and Loop's point
/// `loop_point(i)` of each edge; shared by interior and boundary vertices (`closed`: the ring
/// goes all round `v`; `swerve`: the cap on a fitted β, [`swerve_cap`]). The returned α is
/// 1: the caller's α goes in its place.
#[allow(clippy::too_many_arguments)]
pub(crate) fn fit_shape(
    v: DVec3,
    ring: &[DVec3],
    b0: DVec3,
    beta: Option<f64>,
    swerve: f64,
    unit_tangent: &[DVec3],
    normal: DVec3,
    closed: bool,
    loop_point: impl Fn(usize) -> DVec3,
) -> ShapeParams {
    let n = ring.len();
    let nf = n as f64;
    let chords: Vec<DVec3> = ring.iter().map(|&p| p - v).collect();
    let beta = beta.unwrap_or_else(|| {
        let (mut num, mut den) = (0.0, 0.0);
        for (t, c) in unit_tangent.iter().zip(&chords) {
            let q = t.length() / arc_length(*c, normal).max(f64::MIN_POSITIVE);
            num += q;
            den += q * q;
        }
        let fitted = if den > 0.0 { num / den } else { 1.0 / 3.0 };
        // b¹ − b⁰ = β r¹/6 (eq. 11): no boundary curve swerves off its edge.
        let cap = swerve_cap(v, ring, normal, swerve, closed, |i| unit_tangent[i] / 6.0);
        fitted.clamp(BETA_RANGE[0], BETA_RANGE[1]).min(cap)
    });
    let (mut num, mut den, mut reference, mut scale) = (0.0, 0.0, 0.0, 0.0);
    let mut tangential = Vec::with_capacity(n);
    for i in 0..n {
        let r1 = beta * unit_tangent[i];
        let c2 = chords[i].length_squared().max(f64::MIN_POSITIVE);
        let kappa = 2.0 * chords[i].dot(normal) / c2;
        let w = loop_point(i) - b0;
        let w_normal = w.dot(normal);
        // 24 γ2 w·N ≈ κ |r¹|²
        let target = kappa * r1.length_squared() / 24.0;
        num += w_normal * target;
        den += w_normal * w_normal;
        reference += r1.length_squared() / (8.0 * c2);
        scale += c2;
        tangential.push((r1 / 6.0, w - w_normal * normal));
    }
    let reference = reference / nf;
    // Both `den` and the weight are squared lengths: the choice does not depend on the scale.
    let weight = PLANAR_FALLBACK * scale / nf;
    let g2 = ((num + weight * reference) / (den + weight)).clamp(GAMMA2_RANGE[0], GAMMA2_RANGE[1]);
    // (γ1 − 2)(b1 − b0) + γ2 (d − b0)ᵀ ≈ 0 over the edges.
    let (mut uu, mut uw) = (0.0, 0.0);
    for (u, w) in &tangential {
        uu += u.length_squared();
        uw += u.dot(*w);
    }
    let g1 = if uu > 0.0 { 2.0 - g2 * uw / uu } else { 2.0 };
    ShapeParams {
        alpha: 1.0,
        beta,
        gamma: [1.0 - g1 - g2, g1, g2],
    }
}

/// Length of the circular arc from the origin to `chord` that is tangent at the origin to the
/// plane with unit `normal`.
fn arc_length(chord: DVec3, normal: DVec3) -> f64 {
    let len = chord.length();
    let sin = (chord.dot(normal).abs() / len.max(f64::MIN_POSITIVE)).min(1.0);
    if sin > 0.0 {
        len * sin.asin() / sin
    } else {
        len
    }
}

/// The curve and cross-boundary data of one directed edge `v → p_i` that `v` determines alone.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct HalfEdgeData {
    /// `b0, b1, b2` of the cubic boundary piece on `[0, ½]` (eqs. 10, 13, 15).
    pub b: [DVec3; 3],
    /// `v⁰ = V_i(0)` (eq. 23).
    pub v0: DVec3,
    /// `v¹`, second control point of the quadratic piece of `V_i` on `[0, ½]` (from eq. 22).
    pub v1: DVec3,
    /// `Φ_i(0) = cos(2π/n)` (eq. 6).
    pub phi0: f64,
    /// `Ψ_i(0) = sin(2π/n)` (eq. 20).
    pub psi0: f64,
    /// On a sharp edge, the cross-boundary data of the face on the "−" side
    /// (`(v, p_{i−1}, p_i)`); the fields above are then those of the "+" side
    /// (`(v, p_i, p_{i+1})`). `None` elsewhere: both sides (or the one face of a boundary edge)
    /// share the fields above.
    pub minus: Option<CrossSide>,
}

/// The cross-boundary data of one side of a directed edge ([`HalfEdgeData`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct CrossSide {
    /// `V(0)`.
    pub v0: DVec3,
    /// `v¹`.
    pub v1: DVec3,
    /// `Φ(0)`.
    pub phi0: f64,
    /// `Ψ(0)`.
    pub psi0: f64,
}

impl HalfEdgeData {
    /// The cross-boundary data of the face on the "−" side (`minus`) or the "+" side.
    pub(crate) fn side(&self, minus: bool) -> CrossSide {
        match (minus, self.minus) {
            (true, Some(side)) => side,
            _ => CrossSide {
                v0: self.v0,
                v1: self.v1,
                phi0: self.phi0,
                psi0: self.psi0,
            },
        }
    }
}

/// Fills `out[i]` with the data of edge `v → ring[i]` for every neighbour (eqs. 9–23).
/// `psi_slope[i]` is `Ψ'_i(0)` of that edge (eq. 22; [`PsiRule::slope`] of `sin(2π/n)` here
/// and `sin(2π/n_i)` at `ring[i]`).
pub(crate) fn half_edges(
    v: DVec3,
    ring: &[DVec3],
    psi_slope: &[f64],
    fourier: &RingFourier,
    shape: &ShapeParams,
    edge_curvature: bool,
    out: &mut [HalfEdgeData],
) {
    let n = ring.len();
    let nf = n as f64;
    let theta = 2.0 * PI / nf;
    let (c, s) = (theta.cos(), theta.sin());
    let ShapeParams { alpha, beta, gamma } = *shape;

    // eq. 9/10: b0, the same for every edge at v.
    let b0 = alpha * v + (1.0 - alpha) * fourier.mean();
    // eq. 12: r¹_i = M_{u_i}(0,0) = (6β/n) Σ cos(θ(j−i)) p_j; eq. 11: b1 = b0 + r¹/6.
    let r1 = |i: usize| (6.0 * beta / nf) * fourier.cos_sum(i % n);
    // Φ on [0, ½] is cos θ (1 − 2u) + u (eq. 8): Φ⁰ = cos θ, Φ¹ = Φ'(0) = 1 − 2cos θ.
    let (phi_0, phi_1) = (c, 1.0 - 2.0 * c);
    let [g0, g1, g2] = gamma;
    // eq. 15 with Loop's point d_i = (2v + p_{i−1} + 2p_i + p_{i+1}) / 6.
    let loop_point =
        |i: usize| (2.0 * v + ring[(i + n - 1) % n] + 2.0 * ring[i] + ring[(i + 1) % n]) / 6.0;
    let b2_eq15 = |i: usize| g0 * b0 + g1 * (b0 + r1(i) / 6.0) + g2 * loop_point(i);
    // Per-edge normal heights added to eq. 15's b2, and their preimages under the twist map T.
    let (heights, heights_pre) = if edge_curvature {
        let heights = edge_heights(v, ring, b0, fourier.normal(), r1, b2_eq15);
        let pre = solve_twists(&heights);
        (heights, pre)
    } else {
        (Vec::new(), Vec::new())
    };

    for i in 0..n {
        let next = ring[(i + 1) % n];
        let r1_i = r1(i);
        let b1 = b0 + r1_i / 6.0;
        let b2 = b2_eq15(i) + heights.get(i).copied().unwrap_or_default();
        // Second derivative of the boundary curve at v (eq. 14, factor re-derived: 24).
        let r2_i = 24.0 * (b2 - 2.0 * b1 + b0);

        // Twist t_i = M^i_{u_i u_{i+1}}(0,0) from (II_T): ½(t_i + t_{i−1}) = Φ¹ r¹_i + Φ⁰ r²_i.
        // The right side is T applied to the same combination of the preimages
        // b̃1_i = b0 + (β/n) Σ [cos(θ(j−i)) + tan(θ/2) sin(θ(j−i))] p_j and
        // b̃2_i = γ0 b0 + γ1 b̃1_i + γ2 (v + p_i + p_{i+1}) / 3 (HB00 §6), hence eq. 17:
        let b1_pre = b0 + (beta / nf) * fourier.twist_preimage_sum(i);
        let b2_pre = g0 * b0
            + g1 * b1_pre
            + g2 * (v + ring[i] + next) / 3.0
            + heights_pre.get(i).copied().unwrap_or_default();
        let twist = (24.0 * phi_0 - 6.0 * phi_1) * b0
            + (6.0 * phi_1 - 48.0 * phi_0) * b1_pre
            + 24.0 * phi_0 * b2_pre;

        // eq. 19: r¹_{i+1} = Φ⁰ r¹_i + Ψ⁰ V_i(0).
        let v0 = (r1(i + 1) - c * r1_i) / s;
        // eq. 22 with Ψ'_i(0) (sin(2π/n_i) − sin(2π/n) when Ψ is linear over [0,1], eq. 20).
        let psi_1 = psi_slope[i];
        let v_prime = (twist - phi_1 * r1_i - phi_0 * r2_i - psi_1 * v0) / s;
        out[i] = HalfEdgeData {
            b: [b0, b1, b2],
            v0,
            v1: v0 + v_prime / 4.0,
            phi0: c,
            psi0: s,
            minus: None,
        };
    }
}

/// The normal heights `λ_i N` added to eq. 15's `b2` on each edge at `v` so that the boundary
/// curves leaving `v` start with the normal curvatures of one second fundamental form fitted to
/// those the mesh implies, `r²_i · N = II(r¹_i)`, with `II` the least squares fit to
/// `κ_i = 2 (p_i − v) · N / |p_i − v|²` along the edges (the circle through `v` and `p_i`
/// tangent to the plane; for n = 3 the fit interpolates). HB00 §6 gives one set of shape
/// parameters per vertex, so eq. 15 alone can only give one normal curvature for all directions
/// (measured on the torus: |H| at the vertices 1.37–2.0 against the true 0.42–1.61). For even
/// n, (II_T) is solvable only if `Σ (−1)^i Φ⁰ r²_i = 0`: eq. 12's tangents, Loop's points and a
/// quadratic form meet this by symmetry for n ≠ 4, and at n = 4 `Φ⁰ = cos(π/2) = 0`; any rounding
/// left in the alternating part is removed. `b2(i)` is eq. 15's point, `r1(i)` the tangent of
/// edge `i`.
fn edge_heights(
    v: DVec3,
    ring: &[DVec3],
    b0: DVec3,
    normal: DVec3,
    r1: impl Fn(usize) -> DVec3,
    b2: impl Fn(usize) -> DVec3,
) -> Vec<DVec3> {
    let n = ring.len();
    let kappa = |i: usize| {
        let chord = ring[i] - v;
        2.0 * chord.dot(normal) / chord.length_squared().max(f64::MIN_POSITIVE)
    };
    let form = SecondForm::fit(normal, (0..n).map(|i| (r1(i), kappa(i))));
    let mut lambda: Vec<f64> = (0..n)
        .map(|i| {
            let r = r1(i);
            let target = match &form {
                Some(form) => form.at(r),
                None => kappa(i) * r.length_squared(),
            };
            let b1 = b0 + r / 6.0;
            let r2_normal = 24.0 * (b2(i) - 2.0 * b1 + b0).dot(normal);
            (target - r2_normal) / 24.0
        })
        .collect();
    if n.is_multiple_of(2) && n != 4 {
        let alternating = (0..n).map(|i| alternate(i) * lambda[i]).sum::<f64>() / n as f64;
        for (i, l) in lambda.iter_mut().enumerate() {
            *l -= alternate(i) * alternating;
        }
    }
    lambda.iter().map(|l| *l * normal).collect()
}

/// A quadratic form on the tangent plane at a vertex: the second fundamental form the one-ring
/// implies, `II(r) = a x² + 2b xy + c y²` in an orthonormal frame of the plane.
struct SecondForm {
    frame: [DVec3; 2],
    coefficients: [f64; 3],
}

impl SecondForm {
    /// The least squares fit of `II(r_i / |r_i|) ≈ κ_i` to the normal curvatures `κ_i` along
    /// the tangents `r_i`; `None` when the directions do not determine a form.
    fn fit(normal: DVec3, samples: impl Iterator<Item = (DVec3, f64)>) -> Option<SecondForm> {
        let e1 = normal.any_orthonormal_vector();
        let frame = [e1, normal.cross(e1)];
        let mut ata = vec![vec![0.0; 3]; 3];
        let mut atb = [0.0; 3];
        for (r, kappa) in samples {
            let (x, y) = (r.dot(frame[0]), r.dot(frame[1]));
            let w = 1.0 / r.length_squared().max(f64::MIN_POSITIVE);
            let row = [x * x * w, 2.0 * x * y * w, y * y * w];
            for a in 0..3 {
                atb[a] += row[a] * kappa;
                for b in 0..3 {
                    ata[a][b] += row[a] * row[b];
                }
            }
        }
        let inverse = crate::linalg::invert(&ata)?;
        let coefficients = std::array::from_fn(|a| (0..3).map(|b| inverse[a][b] * atb[b]).sum());
        Some(SecondForm {
            frame,
            coefficients,
        })
    }

    /// `II(r)`: the normal acceleration of a curve leaving the vertex with velocity `r`.
    fn at(&self, r: DVec3) -> f64 {
        let (x, y) = (r.dot(self.frame[0]), r.dot(self.frame[1]));
        let [a, b, c] = self.coefficients;
        a * x * x + 2.0 * b * x * y + c * y * y
    }
}

/// `(−1)^i`.
fn alternate(i: usize) -> f64 {
    if i.is_multiple_of(2) { 1.0 } else { -1.0 }
}

/// Solves `½(x_i + x_{i−1}) = w_i` around a vertex (the map T of (II_T)): the unique solution
/// for odd n; for even n, where it needs `Σ (−1)^i w_i = 0`, the one with `Σ (−1)^i x_i = 0`,
/// as eq. 17's twists have it (n = 4 with a non-zero alternating sum: that solution of the
/// equations with i ≥ 1).
fn solve_twists(w: &[DVec3]) -> Vec<DVec3> {
    let n = w.len();
    if n % 2 == 1 {
        // x_i = Σ_k (−1)^k w_{i−k}.
        (0..n)
            .map(|i| (0..n).map(|k| alternate(k) * w[(i + n - k) % n]).sum())
            .collect()
    } else {
        let mut x = vec![DVec3::ZERO; n];
        for i in 1..n {
            x[i] = 2.0 * w[i] - x[i - 1];
        }
        let c = (0..n).map(|i| alternate(i) * x[i]).sum::<DVec3>() / n as f64;
        (0..n).map(|i| x[i] - alternate(i) * c).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::schemes::vertex_rings::{phi0, psi0};

    /// A deterministic, irregular one-ring: neighbours roughly around v, with noise.
    fn ring(n: usize, seed: u64) -> Vec<DVec3> {
        let mut rng = crate::testing::Rng::new(seed);
        let mut rnd = move || rng.next_f64() - 0.5;
        (0..n)
            .map(|j| {
                let a = 2.0 * PI * j as f64 / n as f64 + 0.3 * rnd();
                DVec3::new(a.cos() * (1.0 + 0.3 * rnd()), a.sin(), 0.4 * rnd())
            })
            .collect()
    }

    /// The default shape first, then others.
    const SHAPES: [ShapeParams; 4] = [
        ShapeParams {
            alpha: 1.0,
            beta: 1.0 / 3.0,
            gamma: [-1.0, 2.0, 0.0],
        },
        ShapeParams {
            alpha: 1.0,
            beta: 1.0 / 3.0,
            gamma: [1.0 / 3.0, 0.0, 2.0 / 3.0],
        },
        ShapeParams {
            alpha: 1.0,
            beta: 0.1,
            gamma: [-3.7, 4.6, 0.1],
        },
        ShapeParams {
            alpha: 0.6,
            beta: 0.45,
            gamma: [0.2, 0.5, 0.3],
        },
    ];

    /// `Ψ'(0)` by `rule` on each edge of a vertex of order `n` whose neighbours have
    /// `valences`.
    fn slopes(rule: PsiRule, n: usize, valences: &[usize]) -> Vec<f64> {
        valences
            .iter()
            .map(|&m| rule.slope(psi0(n), psi0(m)))
            .collect()
    }

    /// The twists solve (II_T) and V satisfies (19) and (21): the three conditions the paper
    /// derives its formulas from, checked for orders 3..16 (and 40, 64 beside neighbours of
    /// order 3..12), several shapes, both tangent planes, with and without the per-edge normal
    /// heights, and for both rules of `Ψ` along the edges.
    #[test]
    fn twists_and_cross_boundary_data_satisfy_the_g1_conditions_at_the_vertex() {
        let cases = SHAPES.iter().flat_map(|s| {
            [PsiRule::Linear, PsiRule::Harmonic]
                .into_iter()
                .flat_map(move |psi| {
                    [
                        (*s, PlaneRule::Fourier, false, psi),
                        (*s, PlaneRule::Max, true, psi),
                    ]
                })
        });
        for n in (3..=16).chain([40, 64]) {
            for (k, (shape, plane, edge_curvature, psi)) in cases.clone().enumerate() {
                let v = DVec3::new(0.1, -0.05, 0.3);
                let p = ring(n, (n * 7 + k) as u64);
                let valences: Vec<usize> = (0..n).map(|i| 3 + (i * 5 + n) % 10).collect();
                let psi_slope = slopes(psi, n, &valences);
                let mut he = vec![HalfEdgeData::default(); n];
                let fourier = plane.ring_fourier(v, &p);
                half_edges(v, &p, &psi_slope, &fourier, &shape, edge_curvature, &mut he);
                let (phi_0, phi_1) = (phi0(n), 1.0 - 2.0 * phi0(n));
                let r1 = |i: usize| 6.0 * (he[i % n].b[1] - he[i % n].b[0]);
                let r2 = |i: usize| 24.0 * (he[i].b[2] - 2.0 * he[i].b[1] + he[i].b[0]);
                // Twist from (21): t_i = Φ¹ r¹_i + Φ⁰ r²_i + Ψ' V(0) + Ψ⁰ V'(0), with Ψ' the
                // slope of Ψ from Ψ(0) = sin(2π/n) to the rule's Ψ(½).
                let twist = |i: usize| {
                    let middle = psi.middle(psi0(n), psi0(valences[i]));
                    let psi_1 = 2.0 * (middle - psi0(n));
                    phi_1 * r1(i)
                        + phi_0 * r2(i)
                        + psi_1 * he[i].v0
                        + psi0(n) * 4.0 * (he[i].v1 - he[i].v0)
                };
                for (i, h) in he.iter().enumerate() {
                    // (19)
                    let lhs = r1(i + 1);
                    let rhs = phi_0 * r1(i) + psi0(n) * h.v0;
                    assert!((lhs - rhs).length() < 1e-13, "eq. 19, n={n} i={i}");
                    // (II_T): ½ t_i + ½ t_{i−1} = Φ¹ r¹_i + Φ⁰ r²_i.
                    let lhs = 0.5 * (twist(i) + twist((i + n - 1) % n));
                    let rhs = phi_1 * r1(i) + phi_0 * r2(i);
                    assert!(
                        (lhs - rhs).length() < 1e-11 * (1.0 + rhs.length()),
                        "(II_T) n={n} shape={k} i={i}: {lhs} vs {rhs}"
                    );
                }
            }
        }
    }

    /// Max's normal is the sphere's normal when the one-ring lies on a sphere through `v`,
    /// however irregular the ring; the tangents of [`PlaneRule::Max`] lie in its plane.
    #[test]
    fn max_normal_is_exact_on_a_sphere() {
        let mut rng = crate::testing::Rng::new(11);
        for n in 3..=12 {
            let (centre, radius) = (DVec3::new(0.3, -0.2, 0.5), 1.7);
            let v = centre + radius * DVec3::new(0.2, 0.3, 0.9).normalize();
            let axis = (v - centre).normalize();
            let (e1, e2) = axis.any_orthonormal_pair();
            let p: Vec<DVec3> = (0..n)
                .map(|j| {
                    let a = 2.0 * PI * (j as f64 + 0.4 * (rng.next_f64() - 0.5)) / n as f64;
                    let polar = 0.1 + 0.4 * rng.next_f64();
                    let dir = polar.cos() * axis + polar.sin() * (a.cos() * e1 + a.sin() * e2);
                    centre + radius * dir
                })
                .collect();
            let normal = max_normal(v, &p).expect("a normal");
            assert!(
                normal.cross(axis).length() <= 1e-14,
                "n={n}: {normal} vs {axis}"
            );
            for scale in [1e-150, 1e150] {
                let scaled: Vec<DVec3> = p.iter().map(|q| *q * scale).collect();
                let at_scale = max_normal(v * scale, &scaled).expect("a normal at scale");
                assert!(
                    at_scale.cross(axis).length() <= 1e-14,
                    "n={n} scale {scale}"
                );
            }
            let fourier = PlaneRule::Max.ring_fourier(v, &p);
            for i in 0..n {
                assert!(fourier.cos_sum(i).dot(axis).abs() <= 1e-14, "n={n} i={i}");
            }
        }
    }

    /// With the per-edge normal heights the boundary curves leaving `v` start with the normal
    /// curvatures of one quadratic form (the second fundamental form fitted to the ring): on
    /// any ring, `r²_i · N / |r¹_i|²` are values of one form; for n = 3 they are the circles'
    /// curvatures `κ_i`; on a ring on a sphere every one is the sphere's curvature.
    #[test]
    fn edge_heights_give_the_edges_one_second_fundamental_form() {
        let mut rng = crate::testing::Rng::new(5);
        for n in 3..=12 {
            let (centre, radius) = (DVec3::new(0.0, 0.0, -1.3), 1.3);
            let on_sphere: Vec<DVec3> = (0..n)
                .map(|j| {
                    let a = 2.0 * PI * (j as f64 + 0.4 * (rng.next_f64() - 0.5)) / n as f64;
                    let polar = 0.2 + 0.3 * rng.next_f64();
                    let dir = DVec3::new(polar.sin() * a.cos(), polar.sin() * a.sin(), polar.cos());
                    centre + radius * dir
                })
                .collect();
            for (sphere, p) in [(true, on_sphere), (false, ring(n, 40 + n as u64))] {
                let v = DVec3::ZERO;
                let fourier = PlaneRule::Max.ring_fourier(v, &p);
                let shape = adaptive_shape(
                    v,
                    &p,
                    &fourier,
                    1.0,
                    None,
                    crate::schemes::vertex_rings::HB_SWERVE,
                );
                let mut he = vec![HalfEdgeData::default(); n];
                let psi_slope = slopes(PsiRule::Linear, n, &vec![6; n]);
                half_edges(v, &p, &psi_slope, &fourier, &shape, true, &mut he);
                let normal = fourier.normal();
                let samples: Vec<(DVec3, f64)> = he
                    .iter()
                    .map(|h| {
                        let r1 = 6.0 * (h.b[1] - h.b[0]);
                        let r2 = 24.0 * (h.b[2] - 2.0 * h.b[1] + h.b[0]);
                        (r1, r2.dot(normal) / r1.length_squared())
                    })
                    .collect();
                // At n = 4 eq. 12's tangents are ±A, ±B: two directions do not determine a
                // form, and each edge keeps its own κ_i.
                let form = SecondForm::fit(normal, samples.iter().copied());
                assert_eq!(form.is_none(), n == 4, "n={n}");
                for (i, (r1, curvature)) in samples.iter().enumerate() {
                    let chord = p[i] - v;
                    let kappa = 2.0 * chord.dot(normal) / chord.length_squared();
                    let label = format!("n={n} sphere={sphere} i={i}");
                    if let Some(form) = &form {
                        let of_form = form.at(*r1) / r1.length_squared();
                        assert!(
                            (curvature - of_form).abs() <= 1e-12,
                            "{label}: off the form"
                        );
                    }
                    if sphere {
                        assert!(
                            (kappa.abs() - 1.0 / radius).abs() <= 1e-12,
                            "{label}: {kappa}"
                        );
                    }
                    if sphere || n <= 4 {
                        assert!((curvature - kappa).abs() <= 1e-12, "{label}: {curvature}");
                    }
                }
            }
        }
    }

    /// `solve_twists` inverts the map T of (II_T): for odd n always, for even n on right sides
    /// with zero alternating sum, with the solution's alternating sum zero.
    #[test]
    fn twist_map_is_inverted() {
        let mut rng = crate::testing::Rng::new(3);
        let mut rnd = move || DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64());
        for n in 3..=12 {
            let mut w: Vec<DVec3> = (0..n).map(|_| rnd()).collect();
            if n % 2 == 0 {
                let gap = (0..n).map(|i| alternate(i) * w[i]).sum::<DVec3>() / n as f64;
                for (i, x) in w.iter_mut().enumerate() {
                    *x -= alternate(i) * gap;
                }
            }
            let x = solve_twists(&w);
            for i in 0..n {
                let res = 0.5 * (x[i] + x[(i + n - 1) % n]) - w[i];
                assert!(res.length() <= 1e-14, "n={n} i={i}: {res}");
            }
            if n % 2 == 0 {
                let alt: DVec3 = (0..n).map(|i| alternate(i) * x[i]).sum();
                assert!(alt.length() <= 1e-14, "n={n}: alternating sum {alt}");
            }
        }
    }

    /// Tangent vectors of a Fourier one-ring satisfy r¹_{i+1} + r¹_{i−1} = 2 cos θ r¹_i, the
    /// homogeneous system (5) with Φ⁰ = cos(2π/n) (eq. 6).
    #[test]
    fn tangents_solve_the_homogeneous_vertex_system() {
        for n in 3..=16 {
            let p = ring(n, n as u64);
            let mut he = vec![HalfEdgeData::default(); n];
            half_edges(
                DVec3::ZERO,
                &p,
                &slopes(PsiRule::Linear, n, &vec![6; n]),
                &RingFourier::new(&p),
                &SHAPES[0],
                false,
                &mut he,
            );
            let r1 = |i: usize| he[i % n].b[1] - he[i % n].b[0];
            for i in 0..n {
                let res = r1(i + n - 1) + r1(i + 1) - 2.0 * phi0(n) * r1(i);
                assert!(res.length() < 1e-14, "n={n} i={i}: {res}");
            }
        }
    }

    /// With the default shape (and with (1/3, 0, 2/3)), a regular planar hexagonal one-ring gives straight boundary
    /// pieces parametrised by arc length (linear precision): b_k = v + k e_i / 6, and zero twist.
    #[test]
    fn default_shape_has_linear_precision_on_a_regular_planar_ring() {
        let p: Vec<DVec3> = (0..6)
            .map(|j| {
                let a = PI / 3.0 * j as f64;
                DVec3::new(a.cos(), a.sin(), 0.0)
            })
            .collect();
        for shape in &SHAPES[..2] {
            let mut he = vec![HalfEdgeData::default(); 6];
            half_edges(
                DVec3::ZERO,
                &p,
                &slopes(PsiRule::Harmonic, 6, &[6; 6]),
                &RingFourier::new(&p),
                shape,
                false,
                &mut he,
            );
            for i in 0..6 {
                for k in 0..3 {
                    let expected = p[i] * k as f64 / 6.0;
                    assert!((he[i].b[k] - expected).length() < 1e-15, "b{k} of edge {i}");
                }
                // V constant: the cross derivative is e_{i+1} − ½ e_i everywhere.
                assert!((he[i].v1 - he[i].v0).length() < 1e-14, "V' ≠ 0 at edge {i}");
                let cross = 0.5 * p[i] + psi0(6) * he[i].v0;
                assert!((cross - p[(i + 1) % 6]).length() < 1e-15);
            }
        }
    }
}
