//! The blending weights of the two families, as functions of the barycentric coordinates
//! `(b0, b1, b2)` of a face, evaluated with exact derivatives through [`Scalar`].
//!
//! * Nielson's side-vertex weights [FM, "Nielson's Method"], with the power `t` of the
//!   poster's higher-order variant: `W_i = (b_j b_k)^t / Σ_{pairs} (b_j b_k)^t`. On the edge
//!   `b_i = 0` the weight of sub-surface `i` is one.
//! * Fang–Mann's weights [FM, "The new blending functions"]:
//!   `f_{t,0} = βγ (1/(α+β) + 1/(α+γ)) / (α+β+γ)` and cyclic, with `α = b0^{t+1}`,
//!   `β = b1^{t+1}`, `γ = b2^{t+1}`. Since `βγ/(α+β) + γα/(β+α) = γ`, the weights sum to one.
//!
//! The powers are taken of the coordinates divided by the largest one, a factor that cancels
//! in every quotient, so nothing underflows to 0/0 short of the corners. Near a corner both
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

/// `(b_0, b_1, b_2)^p / max(b)^p`: each in `[0, 1]`, the largest exactly one.
fn scaled_powers<S: Scalar>(b: [S; 3], p: u32) -> [S; 3] {
    let m = b[0].value().max(b[1].value()).max(b[2].value());
    b.map(|x| x.scale(1.0 / m).powi(p))
}

/// The three weights at barycentric coordinates `b` (non-negative, summing to one, at least
/// [`crate::blend::CORNER_RADIUS`] away from every corner). They are non-negative and sum
/// to one up to rounding.
pub(crate) fn weights<S: Scalar>(family: WeightFamily, b: [S; 3]) -> [S; 3] {
    match family {
        WeightFamily::Nielson { power } => {
            let q = scaled_powers(b, power);
            let pairs = [q[1] * q[2], q[2] * q[0], q[0] * q[1]];
            let total = pairs[0] + pairs[1] + pairs[2];
            pairs.map(|pair| pair / total)
        }
        WeightFamily::FangMann { t } => {
            // f_0 = q1 q2 (1/(q0+q1) + 1/(q0+q2)) / (q0+q1+q2) and cyclic, q = (b/max b)^{t+1}:
            // four reciprocals in all. Away from the corners (where callers do not come) every
            // pair sum is at least (CORNER_RADIUS/2)^{t+1}, far from underflow, and the tiny
            // weights near an edge are products of accurately computed factors, not
            // differences.
            let q = scaled_powers(b, t + 1);
            let one = S::constant(1.0);
            let total = one / (q[0] + q[1] + q[2]);
            let r01 = one / (q[0] + q[1]);
            let r02 = one / (q[0] + q[2]);
            let r12 = one / (q[1] + q[2]);
            [
                q[1] * q[2] * (r01 + r02) * total,
                q[2] * q[0] * (r12 + r01) * total,
                q[0] * q[1] * (r02 + r12) * total,
            ]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::blend::scalar_jet::ScalarJet;
    use crate::testing::Rng;

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
        let mut rng = Rng::new(5);
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
