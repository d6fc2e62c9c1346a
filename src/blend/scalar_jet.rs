//! Scalar functions of `(u, v)` carried with their first and second partial derivatives, so
//! that the blending weights — quotients of polynomials — are differentiated exactly by the
//! chain and quotient rules instead of by finite differences.
//!
//! [`Scalar`] abstracts over a plain `f64` (value only, for [`crate::blend::BlendPatch::eval`])
//! and [`ScalarJet`] (value and derivatives up to order two, for the jet Newton and curvature
//! read). Both are `Copy` and stack-only, so weight evaluation never allocates.

use std::ops::{Add, Div, Mul, Sub};

/// The arithmetic the weight formulas need: a field with constants, integer powers and a
/// value to branch on.
pub(crate) trait Scalar:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self>
{
    /// The constant `c` (all derivatives zero).
    fn constant(c: f64) -> Self;
    /// The function's value.
    fn value(&self) -> f64;
    /// `self^n` for `n ≥ 1`.
    fn powi(self, n: u32) -> Self;
    /// `self · c` for a constant `c`.
    fn scale(self, c: f64) -> Self;
    /// `self` where its value is ≥ 0, else the constant 0 (a barycentric coordinate that
    /// rounding or a Newton step put outside the triangle is frozen on its edge).
    fn nonnegative(self) -> Self {
        if self.value() < 0.0 {
            Self::constant(0.0)
        } else {
            self
        }
    }
}

impl Scalar for f64 {
    fn constant(c: f64) -> Self {
        c
    }
    fn value(&self) -> f64 {
        *self
    }
    fn powi(self, n: u32) -> Self {
        f64::powi(self, n as i32)
    }
    fn scale(self, c: f64) -> Self {
        self * c
    }
}

/// A scalar `f(u, v)` with `f, ∂f/∂u, ∂f/∂v, ∂²f/∂u², ∂²f/∂u∂v, ∂²f/∂v²` at one point.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct ScalarJet {
    /// `f`
    pub v: f64,
    /// `∂f/∂u`
    pub du: f64,
    /// `∂f/∂v`
    pub dv: f64,
    /// `∂²f/∂u²`
    pub duu: f64,
    /// `∂²f/∂u∂v`
    pub duv: f64,
    /// `∂²f/∂v²`
    pub dvv: f64,
}

impl ScalarJet {
    /// The affine function `value + du·(u − u₀) + dv·(v − v₀)` at `(u₀, v₀)`; the barycentric
    /// coordinates of a patch are of this kind (`1 − u − v`, `u`, `v`).
    pub(crate) const fn affine(value: f64, du: f64, dv: f64) -> Self {
        ScalarJet {
            v: value,
            du,
            dv,
            duu: 0.0,
            duv: 0.0,
            dvv: 0.0,
        }
    }

    /// `1 / self` by the chain rule: `(1/g)' = −g'/g²`, `(1/g)'' = −g''/g² + 2 g'g'/g³`.
    pub(crate) fn recip(self) -> Self {
        let r = 1.0 / self.v;
        let r2 = r * r;
        let r3 = 2.0 * r2 * r;
        ScalarJet {
            v: r,
            du: -self.du * r2,
            dv: -self.dv * r2,
            duu: -self.duu * r2 + r3 * self.du * self.du,
            duv: -self.duv * r2 + r3 * self.du * self.dv,
            dvv: -self.dvv * r2 + r3 * self.dv * self.dv,
        }
    }
}

impl Add for ScalarJet {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        ScalarJet {
            v: self.v + o.v,
            du: self.du + o.du,
            dv: self.dv + o.dv,
            duu: self.duu + o.duu,
            duv: self.duv + o.duv,
            dvv: self.dvv + o.dvv,
        }
    }
}

impl Sub for ScalarJet {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        self + o.scale(-1.0)
    }
}

impl Mul for ScalarJet {
    type Output = Self;
    /// Leibniz rule up to order two.
    fn mul(self, o: Self) -> Self {
        ScalarJet {
            v: self.v * o.v,
            du: self.du * o.v + self.v * o.du,
            dv: self.dv * o.v + self.v * o.dv,
            duu: self.duu * o.v + 2.0 * self.du * o.du + self.v * o.duu,
            duv: self.duv * o.v + self.du * o.dv + self.dv * o.du + self.v * o.duv,
            dvv: self.dvv * o.v + 2.0 * self.dv * o.dv + self.v * o.dvv,
        }
    }
}

impl Div for ScalarJet {
    type Output = Self;
    /// Quotient rule, as `self · (1/o)`.
    #[allow(clippy::suspicious_arithmetic_impl)]
    fn div(self, o: Self) -> Self {
        self * o.recip()
    }
}

impl Scalar for ScalarJet {
    fn constant(c: f64) -> Self {
        ScalarJet::affine(c, 0.0, 0.0)
    }
    fn value(&self) -> f64 {
        self.v
    }
    /// `(x^n)' = n x^{n−1} x'`, `(x^n)'' = n(n−1) x^{n−2} x'x' + n x^{n−1} x''`. The powers
    /// are taken only where their coefficient is nonzero, so `0^n` never meets `0^{−1}`.
    fn powi(self, n: u32) -> Self {
        if n == 0 {
            return ScalarJet::constant(1.0);
        }
        let nf = n as f64;
        let first = nf * self.v.powi(n as i32 - 1);
        let second = if n >= 2 {
            nf * (nf - 1.0) * self.v.powi(n as i32 - 2)
        } else {
            0.0
        };
        ScalarJet {
            v: self.v.powi(n as i32),
            du: first * self.du,
            dv: first * self.dv,
            duu: second * self.du * self.du + first * self.duu,
            duv: second * self.du * self.dv + first * self.duv,
            dvv: second * self.dv * self.dv + first * self.dvv,
        }
    }
    fn scale(self, c: f64) -> Self {
        ScalarJet {
            v: self.v * c,
            du: self.du * c,
            dv: self.dv * c,
            duu: self.duu * c,
            duv: self.duv * c,
            dvv: self.dvv * c,
        }
    }
}

/// A scalar `f(u, v)` with its value and first partial derivatives only: the cheaper
/// arithmetic for evaluations that need no curvature (Newton's point and tangents).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct ScalarJet1 {
    /// `f`
    pub v: f64,
    /// `∂f/∂u`
    pub du: f64,
    /// `∂f/∂v`
    pub dv: f64,
}

impl Add for ScalarJet1 {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        ScalarJet1 {
            v: self.v + o.v,
            du: self.du + o.du,
            dv: self.dv + o.dv,
        }
    }
}

impl Sub for ScalarJet1 {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        ScalarJet1 {
            v: self.v - o.v,
            du: self.du - o.du,
            dv: self.dv - o.dv,
        }
    }
}

impl Mul for ScalarJet1 {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        ScalarJet1 {
            v: self.v * o.v,
            du: self.du * o.v + self.v * o.du,
            dv: self.dv * o.v + self.v * o.dv,
        }
    }
}

impl Div for ScalarJet1 {
    type Output = Self;
    /// `(f/g)' = (f' − (f/g) g') / g`.
    fn div(self, o: Self) -> Self {
        let r = 1.0 / o.v;
        let q = self.v * r;
        ScalarJet1 {
            v: q,
            du: (self.du - q * o.du) * r,
            dv: (self.dv - q * o.dv) * r,
        }
    }
}

impl Scalar for ScalarJet1 {
    fn constant(c: f64) -> Self {
        ScalarJet1 {
            v: c,
            du: 0.0,
            dv: 0.0,
        }
    }
    fn value(&self) -> f64 {
        self.v
    }
    fn powi(self, n: u32) -> Self {
        if n == 0 {
            return ScalarJet1::constant(1.0);
        }
        let first = n as f64 * self.v.powi(n as i32 - 1);
        ScalarJet1 {
            v: self.v.powi(n as i32),
            du: first * self.du,
            dv: first * self.dv,
        }
    }
    fn scale(self, c: f64) -> Self {
        ScalarJet1 {
            v: self.v * c,
            du: self.du * c,
            dv: self.dv * c,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn u_jet(u: f64) -> ScalarJet {
        ScalarJet::affine(u, 1.0, 0.0)
    }
    fn v_jet(v: f64) -> ScalarJet {
        ScalarJet::affine(v, 0.0, 1.0)
    }

    /// f = u²v³ / (1 + u + v²) against its derivatives worked out by hand.
    #[test]
    fn quotient_of_polynomials_matches_hand_derivatives() {
        let (u0, v0) = (0.3, 0.7);
        let (u, v) = (u_jet(u0), v_jet(v0));
        let one = ScalarJet::constant(1.0);
        let f = u.powi(2) * v.powi(3) / (one + u + v * v);
        // f = N/D with N = u²v³, D = 1 + u + v².
        let (n, nu, nv) = (
            u0 * u0 * v0.powi(3),
            2.0 * u0 * v0.powi(3),
            3.0 * u0 * u0 * v0 * v0,
        );
        let (nuu, nuv, nvv) = (2.0 * v0.powi(3), 6.0 * u0 * v0 * v0, 6.0 * u0 * u0 * v0);
        let (d, du, dv) = (1.0 + u0 + v0 * v0, 1.0, 2.0 * v0);
        let (duu, duv, dvv) = (0.0, 0.0, 2.0);
        let fu = (nu * d - n * du) / (d * d);
        let fv = (nv * d - n * dv) / (d * d);
        // Second derivatives of a quotient: (N'' D² − D(2N'D' + N D'') + 2 N D'D') / D³.
        let second = |nab: f64, na: f64, nb: f64, da: f64, db: f64, dab: f64| {
            (nab * d * d - d * (na * db + nb * da + n * dab) + 2.0 * n * da * db) / d.powi(3)
        };
        let expected = [
            n / d,
            fu,
            fv,
            second(nuu, nu, nu, du, du, duu),
            second(nuv, nu, nv, du, dv, duv),
            second(nvv, nv, nv, dv, dv, dvv),
        ];
        let got = [f.v, f.du, f.dv, f.duu, f.duv, f.dvv];
        for (g, e) in got.iter().zip(expected) {
            assert!(
                (g - e).abs() <= 1e-14 * e.abs().max(1.0),
                "{got:?} vs {expected:?}"
            );
        }
    }

    /// The first-order jet agrees with the first-order part of the full jet.
    #[test]
    fn first_order_jet_agrees_with_the_full_jet() {
        let (u0, v0) = (0.3, 0.7);
        let full = {
            let (u, v) = (u_jet(u0), v_jet(v0));
            (u.powi(3) * v - v.powi(2)) / (ScalarJet::constant(2.0) + u * v)
        };
        let first = {
            let u = ScalarJet1 {
                v: u0,
                du: 1.0,
                dv: 0.0,
            };
            let v = ScalarJet1 {
                v: v0,
                du: 0.0,
                dv: 1.0,
            };
            (u.powi(3) * v - v.powi(2)) / (ScalarJet1::constant(2.0) + u * v)
        };
        for (a, b) in [(full.v, first.v), (full.du, first.du), (full.dv, first.dv)] {
            assert!((a - b).abs() <= 1e-15 * a.abs().max(1.0), "{a} vs {b}");
        }
    }

    /// Powers at zero: (u^1)' = 1, (u^2)' = 0, (u^2)'' = 2, no NaN from 0^(n−2).
    #[test]
    fn powers_at_zero_are_finite() {
        let u = u_jet(0.0);
        assert_eq!(u.powi(1), u);
        let sq = u.powi(2);
        assert_eq!((sq.v, sq.du, sq.duu), (0.0, 0.0, 2.0));
        let cube = u.powi(3);
        assert_eq!((cube.v, cube.du, cube.duu), (0.0, 0.0, 0.0));
        assert_eq!(u.powi(0), ScalarJet::constant(1.0));
    }
}
