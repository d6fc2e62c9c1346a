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

use crate::schemes::vertex_rings::{RingFourier, psi0};

/// The shape parameters of HB00: α (eq. 9), β (eq. 12), γ0, γ1, γ2 (eq. 15, γ0+γ1+γ2 = 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeParams {
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
pub struct ShapeRule {
    /// α of eq. 9, the same at every vertex.
    pub alpha: f64,
    /// β of eq. 12, or `None` for the per-vertex choice of [`adaptive_shape`].
    pub beta: Option<f64>,
    /// (γ0, γ1, γ2) of eq. 15, or `None` for the per-vertex choice of [`adaptive_shape`].
    pub gamma: Option<[f64; 3]>,
}

impl ShapeRule {
    /// The parameters of the vertex `v` with one-ring `ring`.
    pub fn at_vertex(&self, v: DVec3, ring: &[DVec3]) -> ShapeParams {
        match (self.beta, self.gamma) {
            (Some(beta), Some(gamma)) => ShapeParams {
                alpha: self.alpha,
                beta,
                gamma,
            },
            _ => {
                let adaptive = adaptive_shape(v, ring, self.alpha, self.beta);
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
pub const BETA_RANGE: [f64; 2] = [0.25, 0.5];

/// The per-vertex γ2 is kept in this range: 0 (the tangent line) to twice its value 1/8 on a
/// regular ring of a sphere. The fit divides by the ring's heights over the tangent plane, which
/// can nearly cancel at a saddle.
pub const GAMMA2_RANGE: [f64; 2] = [0.0, 0.25];

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
/// With `beta = Some(β)`, β is kept and only the γ are chosen.
pub fn adaptive_shape(v: DVec3, ring: &[DVec3], alpha: f64, beta: Option<f64>) -> ShapeParams {
    let n = ring.len();
    let nf = n as f64;
    let fourier = RingFourier::new(ring);
    let b0 = alpha * v + (1.0 - alpha) * fourier.mean();
    let normal = fourier
        .cos_sum(0)
        .cross(fourier.sin_sum(0))
        .normalize_or_zero();
    // r¹_i for β = 1 (eq. 12).
    let unit_tangent: Vec<DVec3> = (0..n).map(|i| (6.0 / nf) * fourier.cos_sum(i)).collect();
    // Loop's point d_i (eq. 15).
    let loop_point =
        |i: usize| (2.0 * v + ring[(i + n - 1) % n] + 2.0 * ring[i] + ring[(i + 1) % n]) / 6.0;
    ShapeParams {
        alpha,
        ..fit_shape(v, ring, b0, beta, &unit_tangent, normal, loop_point)
    }
}

/// The fits of [`adaptive_shape`] over the edges `v → ring[i]`, given the vertex point `b0`,
/// the tangents `unit_tangent[i]` for β = 1, the tangent plane's `normal` and Loop's point
/// `loop_point(i)` of each edge; shared by interior and boundary vertices. The returned α is
/// 1: the caller's α goes in its place.
pub(crate) fn fit_shape(
    v: DVec3,
    ring: &[DVec3],
    b0: DVec3,
    beta: Option<f64>,
    unit_tangent: &[DVec3],
    normal: DVec3,
    loop_point: impl Fn(usize) -> DVec3,
) -> ShapeParams {
    let n = ring.len();
    let nf = n as f64;
    let chords: Vec<DVec3> = ring.iter().map(|&p| p - v).collect();
    let beta = beta.unwrap_or_else(|| {
        let (mut num, mut den) = (0.0, 0.0);
        for (t, c) in unit_tangent.iter().zip(&chords) {
            let len = c.length();
            let sin = (c.dot(normal).abs() / len.max(f64::MIN_POSITIVE)).min(1.0);
            let angle = sin.asin();
            let arc = if sin > 0.0 { len * angle / sin } else { len };
            let q = t.length() / arc.max(f64::MIN_POSITIVE);
            num += q;
            den += q * q;
        }
        let fitted = if den > 0.0 { num / den } else { 1.0 / 3.0 };
        fitted.clamp(BETA_RANGE[0], BETA_RANGE[1])
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
    let weight = PLANAR_FALLBACK * (scale / nf).powi(2);
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

/// The curve and cross-boundary data of one directed edge `v → p_i` that `v` determines alone.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HalfEdgeData {
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
}

/// Fills `out[i]` with the data of edge `v → ring[i]` for every neighbour (eqs. 9–23).
/// `ring_valence[i]` is the order of `ring[i]` (it enters `Ψ'_i(0)`, eq. 22).
pub fn half_edges(
    v: DVec3,
    ring: &[DVec3],
    ring_valence: &[usize],
    shape: &ShapeParams,
    out: &mut [HalfEdgeData],
) {
    let n = ring.len();
    let nf = n as f64;
    let theta = 2.0 * PI / nf;
    let (c, s) = (theta.cos(), theta.sin());
    let ShapeParams { alpha, beta, gamma } = *shape;

    let fourier = RingFourier::new(ring);
    // eq. 9/10: b0, the same for every edge at v.
    let b0 = alpha * v + (1.0 - alpha) * fourier.mean();
    // eq. 12: r¹_i = M_{u_i}(0,0) = (6β/n) Σ cos(θ(j−i)) p_j; eq. 11: b1 = b0 + r¹/6.
    let r1 = |i: usize| (6.0 * beta / nf) * fourier.cos_sum(i % n);
    // Φ on [0, ½] is cos θ (1 − 2u) + u (eq. 8): Φ⁰ = cos θ, Φ¹ = Φ'(0) = 1 − 2cos θ.
    let (phi_0, phi_1) = (c, 1.0 - 2.0 * c);
    let [g0, g1, g2] = gamma;

    for i in 0..n {
        let (prev, next) = (ring[(i + n - 1) % n], ring[(i + 1) % n]);
        let r1_i = r1(i);
        let b1 = b0 + r1_i / 6.0;
        // eq. 15 with Loop's point d_i = (2v + p_{i−1} + 2p_i + p_{i+1}) / 6.
        let d = (2.0 * v + prev + 2.0 * ring[i] + next) / 6.0;
        let b2 = g0 * b0 + g1 * b1 + g2 * d;
        // Second derivative of the boundary curve at v (eq. 14, factor re-derived: 24).
        let r2_i = 24.0 * (b2 - 2.0 * b1 + b0);

        // Twist t_i = M^i_{u_i u_{i+1}}(0,0) from (II_T): ½(t_i + t_{i−1}) = Φ¹ r¹_i + Φ⁰ r²_i.
        // The right side is T applied to the same combination of the preimages
        // b̃1_i = b0 + (β/n) Σ [cos(θ(j−i)) + tan(θ/2) sin(θ(j−i))] p_j and
        // b̃2_i = γ0 b0 + γ1 b̃1_i + γ2 (v + p_i + p_{i+1}) / 3 (HB00 §6), hence eq. 17:
        let b1_pre = b0 + (beta / nf) * fourier.twist_preimage_sum(i);
        let b2_pre = g0 * b0 + g1 * b1_pre + g2 * (v + ring[i] + next) / 3.0;
        let twist = (24.0 * phi_0 - 6.0 * phi_1) * b0
            + (6.0 * phi_1 - 48.0 * phi_0) * b1_pre
            + 24.0 * phi_0 * b2_pre;

        // eq. 19: r¹_{i+1} = Φ⁰ r¹_i + Ψ⁰ V_i(0).
        let v0 = (r1(i + 1) - c * r1_i) / s;
        // eq. 22 with Ψ'_i(0) = sin(2π/n_i) − sin(2π/n) (Ψ linear over [0,1], eq. 20).
        let psi_1 = psi0(ring_valence[i]) - s;
        let v_prime = (twist - phi_1 * r1_i - phi_0 * r2_i - psi_1 * v0) / s;
        out[i] = HalfEdgeData {
            b: [b0, b1, b2],
            v0,
            v1: v0 + v_prime / 4.0,
            phi0: c,
            psi0: s,
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::schemes::vertex_rings::phi0;

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

    /// The twists solve (II_T) and V satisfies (19) and (21): the three conditions the paper
    /// derives its formulas from, checked for orders 3..16 and several shapes.
    #[test]
    fn twists_and_cross_boundary_data_satisfy_the_g1_conditions_at_the_vertex() {
        for n in 3..=16 {
            for (k, shape) in SHAPES.iter().enumerate() {
                let v = DVec3::new(0.1, -0.05, 0.3);
                let p = ring(n, (n * 7 + k) as u64);
                let valences: Vec<usize> = (0..n).map(|i| 3 + (i * 5 + n) % 10).collect();
                let mut he = vec![HalfEdgeData::default(); n];
                half_edges(v, &p, &valences, shape, &mut he);
                let (phi_0, phi_1) = (phi0(n), 1.0 - 2.0 * phi0(n));
                let r1 = |i: usize| 6.0 * (he[i % n].b[1] - he[i % n].b[0]);
                let r2 = |i: usize| 24.0 * (he[i].b[2] - 2.0 * he[i].b[1] + he[i].b[0]);
                // Twist from (21): t_i = Φ¹ r¹_i + Φ⁰ r²_i + Ψ' V(0) + Ψ⁰ V'(0).
                let twist = |i: usize| {
                    let psi_1 = psi0(valences[i]) - psi0(n);
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

    /// Tangent vectors of a Fourier one-ring satisfy r¹_{i+1} + r¹_{i−1} = 2 cos θ r¹_i, the
    /// homogeneous system (5) with Φ⁰ = cos(2π/n) (eq. 6).
    #[test]
    fn tangents_solve_the_homogeneous_vertex_system() {
        for n in 3..=16 {
            let p = ring(n, n as u64);
            let mut he = vec![HalfEdgeData::default(); n];
            half_edges(DVec3::ZERO, &p, &vec![6; n], &SHAPES[0], &mut he);
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
            half_edges(DVec3::ZERO, &p, &[6; 6], shape, &mut he);
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
