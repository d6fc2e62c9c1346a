//! The blending weights of the two families, as functions of the barycentric coordinates
//! `(b0, b1, b2)` of a face, evaluated with exact derivatives through [`Scalar`].
//!
//! * Nielson's side-vertex weights [FM, "Nielson's Method"], with the power `t` of the
//!   poster's higher-order variant: `W_i = (b_j b_k)^t / Σ_{pairs} (b_j b_k)^t`. On the edge
//!   `b_i = 0` the weight of sub-surface `i` is one.
//! * Fang–Mann's weights [FM, "The new blending functions"]:
//!   `f_{t,0} = βγ (1/(α+β) + 1/(α+γ)) / (α+β+γ)` and cyclic, with `α = b0^{t+1}`,
//!   `β = b1^{t+1}`, `γ = b2^{t+1}`. Writing `βγ/((α+β)(α+β+γ))` as
//!   `γ/(α+β+γ) · β/(α+β)` shows the weights sum to one and each is a sum of products of
//!   ratios in `[0, 1]`, which is how they are computed here:
//!   `f_i = ρ₃(k) ρ(j, i) + ρ₃(j) ρ(k, i)` with `ρ(j, i) = b_j^p / (b_j^p + b_i^p)` and
//!   `ρ₃(k) = b_k^p / (b_0^p + b_1^p + b_2^p)`, `p = t + 1`.
//!
//! Every ratio is computed from coordinates divided by the largest one involved, a factor
//! that cancels in the quotient: no power underflows to 0/0 near a corner. Near a corner both
//! families are undefined in the limit; callers evaluate weights only at points at least
//! [`crate::blend::CORNER_RADIUS`] away from every corner and handle the corners themselves.

use crate::blend::scalar_jet::Scalar;

/// Which weights blend the three sub-surfaces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WeightFamily {
    /// Nielson's side-vertex weights raised to `power` (1 = Nielson 1987).
    Nielson {
        /// The exponent `t` of `(b_j b_k)^t`.
        power: u32,
    },
    /// Fang–Mann's `f_{t,0..2}`: the blend agrees with the sub-surface that owns an edge to
    /// order `t` there.
    FangMann {
        /// The continuity order `t` (`α = b0^{t+1}`).
        t: u32,
    },
}

/// `(x^p / (x^p + y^p), y^p / (x^p + y^p))` for `x, y ≥ 0` not both zero, from `x/m` and
/// `y/m` with `m = max(x, y)`, so the denominator is at least one. Both shares are computed
/// as quotients (not one as `1 −` the other), so a share that is tiny keeps its relative
/// accuracy — it is the weight that must vanish to order `t+1` at an edge.
fn ratios<S: Scalar>(x: S, y: S, p: u32) -> (S, S) {
    let m = x.value().max(y.value());
    let (xs, ys) = (x.scale(1.0 / m).powi(p), y.scale(1.0 / m).powi(p));
    let total = xs + ys;
    (xs / total, ys / total)
}

/// `(b_0, b_1, b_2)^p / max(b)^p`: each in `[0, 1]`, the largest exactly one.
fn scaled_powers<S: Scalar>(b: [S; 3], p: u32) -> [S; 3] {
    let m = b[0].value().max(b[1].value()).max(b[2].value());
    b.map(|x| x.scale(1.0 / m).powi(p))
}

/// The three weights at barycentric coordinates `b` (non-negative, summing to one, at least
/// [`crate::blend::CORNER_RADIUS`] away from every corner). They are non-negative and sum
/// to one up to rounding.
pub fn weights<S: Scalar>(family: WeightFamily, b: [S; 3]) -> [S; 3] {
    match family {
        WeightFamily::Nielson { power } => {
            let q = scaled_powers(b, power);
            let pairs = [q[1] * q[2], q[2] * q[0], q[0] * q[1]];
            let total = pairs[0] + pairs[1] + pairs[2];
            pairs.map(|pair| pair / total)
        }
        WeightFamily::FangMann { t } => {
            let p = t + 1;
            let q = scaled_powers(b, p);
            let total = q[0] + q[1] + q[2];
            let share = q.map(|x| x / total);
            // ρ(j, i) for every ordered pair.
            let (r10, r01) = ratios(b[1], b[0], p);
            let (r20, r02) = ratios(b[2], b[0], p);
            let (r21, r12) = ratios(b[2], b[1], p);
            [
                share[2] * r10 + share[1] * r20,
                share[2] * r01 + share[0] * r21,
                share[1] * r02 + share[0] * r12,
            ]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::blend::scalar_jet::ScalarJet;
    use crate::schemes::testing::Lcg;

    const FAMILIES: [WeightFamily; 6] = [
        WeightFamily::Nielson { power: 1 },
        WeightFamily::Nielson { power: 2 },
        WeightFamily::FangMann { t: 0 },
        WeightFamily::FangMann { t: 1 },
        WeightFamily::FangMann { t: 2 },
        WeightFamily::FangMann { t: 4 },
    ];

    /// The poster's formulas, written literally (fine away from edges and corners).
    fn literal(family: WeightFamily, b: [f64; 3]) -> [f64; 3] {
        match family {
            WeightFamily::Nielson { power } => {
                let q = b.map(|x| x.powi(power as i32));
                let s = q[0] * q[1] + q[1] * q[2] + q[2] * q[0];
                [q[1] * q[2] / s, q[2] * q[0] / s, q[0] * q[1] / s]
            }
            WeightFamily::FangMann { t } => {
                let [a, be, g] = b.map(|x| x.powi(t as i32 + 1));
                let s = a + be + g;
                [
                    be * g * (1.0 / (a + be) + 1.0 / (a + g)) / s,
                    g * a * (1.0 / (be + g) + 1.0 / (be + a)) / s,
                    a * be * (1.0 / (g + a) + 1.0 / (g + be)) / s,
                ]
            }
        }
    }

    fn bary(u: f64, v: f64) -> [ScalarJet; 3] {
        [
            ScalarJet::affine(1.0 - u - v, -1.0, -1.0),
            ScalarJet::affine(u, 1.0, 0.0),
            ScalarJet::affine(v, 0.0, 1.0),
        ]
    }

    #[test]
    fn match_the_poster_and_sum_to_one() {
        let mut rng = Lcg(5);
        for family in FAMILIES {
            for _ in 0..200 {
                let (u, v) = (rng.next_f64(), rng.next_f64());
                let (u, v) = if u + v > 1.0 {
                    (1.0 - u, 1.0 - v)
                } else {
                    (u, v)
                };
                let b = [1.0 - u - v, u, v];
                let w = weights(family, b);
                let expected = literal(family, b);
                for i in 0..3 {
                    assert!(w[i] >= 0.0, "{family:?} {b:?}: {w:?}");
                    assert!((w[i] - expected[i]).abs() <= 1e-13, "{family:?} {b:?}");
                }
                let sum: f64 = w.iter().sum();
                assert!(
                    (sum - 1.0).abs() <= 4.0 * f64::EPSILON,
                    "{family:?}: sum {sum}"
                );
            }
        }
    }

    /// On edge b_i = 0 the owning weight is exactly one, the others exactly zero.
    #[test]
    fn owning_weight_is_one_on_its_edge() {
        for family in FAMILIES {
            for s in [0.01, 0.25, 0.5, 0.9] {
                for i in 0..3 {
                    let mut b = [0.0; 3];
                    b[(i + 1) % 3] = s;
                    b[(i + 2) % 3] = 1.0 - s;
                    let w = weights(family, b);
                    // One up to the rounding of a sum of two shares; the others exactly 0.
                    assert!(
                        (w[i] - 1.0).abs() <= 2.0 * f64::EPSILON,
                        "{family:?}: {w:?}"
                    );
                    assert_eq!(w[(i + 1) % 3], 0.0, "{family:?} edge {i} at {s}: {w:?}");
                    assert_eq!(w[(i + 2) % 3], 0.0, "{family:?} edge {i} at {s}: {w:?}");
                }
            }
        }
    }

    /// The jet's derivatives against fourth-order central differences of the
    /// value path (first order) and of the jet's first derivatives (second order).
    #[test]
    fn derivatives_match_differences() {
        for family in FAMILIES {
            for (u, v) in [(0.2, 0.3), (0.6, 0.15), (0.05, 0.9), (0.33, 0.33)] {
                // A step of 1/1000 of the distance to the nearest edge, the weights' scale.
                let h = 1e-3 * f64::min(u, v).min(1.0 - u - v);
                let stencil = |f: &dyn Fn(f64) -> f64| {
                    (-f(2.0 * h) + 8.0 * f(h) - 8.0 * f(-h) + f(-2.0 * h)) / (12.0 * h)
                };
                let value = |u: f64, v: f64| weights(family, [1.0 - u - v, u, v]);
                let jet = |u: f64, v: f64| weights(family, bary(u, v));
                let here = jet(u, v);
                for (i, w) in here.iter().enumerate() {
                    let checks = [
                        (w.du, stencil(&|d| value(u + d, v)[i])),
                        (w.dv, stencil(&|d| value(u, v + d)[i])),
                        (w.duu, stencil(&|d| jet(u + d, v)[i].du)),
                        (w.duv, stencil(&|d| jet(u, v + d)[i].du)),
                        (w.dvv, stencil(&|d| jet(u, v + d)[i].dv)),
                    ];
                    assert!((w.v - value(u, v)[i]).abs() <= 1e-15);
                    for (n, (got, want)) in checks.into_iter().enumerate() {
                        let err = (got - want).abs() / want.abs().max(1.0);
                        assert!(
                            err <= 1e-8,
                            "{family:?} ({u},{v}) w{i} #{n}: {got} vs {want}"
                        );
                    }
                }
            }
        }
    }

    /// Fang–Mann weights of the non-owning sub-surfaces vanish to order t+1 at an edge:
    /// f_1(b0 = ε) / ε^{t+1} stays bounded as ε → 0, so the blend agrees with the owner to
    /// order t.
    #[test]
    fn fang_mann_weights_vanish_to_order_t_plus_one() {
        for t in 0..4u32 {
            let family = WeightFamily::FangMann { t };
            let ratios: Vec<f64> = [1e-2, 1e-3, 1e-4]
                .iter()
                .map(|&e| weights(family, [e, 0.4, 0.6 - e])[1] / e.powi(t as i32 + 1))
                .collect();
            // f_1 ≈ γα(1/(β+γ) + 1/β)/(β+γ) → the limit ratio is γ(1/(β+γ) + 1/β)/(β+γ).
            let (be, g) = (0.4_f64.powi(t as i32 + 1), 0.6_f64.powi(t as i32 + 1));
            let limit = g * (1.0 / (be + g) + 1.0 / be) / (be + g);
            let last = ratios[2];
            assert!(
                (last - limit).abs() <= 1e-3 * limit,
                "t={t}: {ratios:?} vs {limit}"
            );
        }
    }
}
