//! Bivariate Taylor polynomials truncated at total order [`ORDER`], as a [`Scalar`]: the
//! blending weights evaluated in this arithmetic give all their partial derivatives up to
//! that order at once, so a blend can report exact partials of any order the continuity
//! measure asks for (`crate::metrics::continuity`), not only the second-order jet.
//!
//! Coefficient `c[i,j]` is that of `x^i y^j` (`x = u − u₀`, `y = v − v₀`), i.e.
//! `∂^{i+j} f / ∂u^i ∂v^j / (i! j!)`; stored by total order `m`, then `i` from `m` down to 0
//! (the order of `crate::bezier::TriangleBezier::partials`).

use std::ops::{Add, Div, Mul, Sub};

use glam::DVec3;

use crate::blend::scalar_jet::Scalar;

/// Highest total order kept.
pub(crate) const ORDER: usize = 5;
/// Number of coefficients up to [`ORDER`].
pub(crate) const TERMS: usize = (ORDER + 1) * (ORDER + 2) / 2;

/// Index of the coefficient of `x^i y^j`.
pub(crate) const fn term(i: usize, j: usize) -> usize {
    let m = i + j;
    m * (m + 1) / 2 + (m - i)
}

/// `(i, j)` of every index, in storage order.
const PAIRS: [(usize, usize); TERMS] = {
    let mut out = [(0, 0); TERMS];
    let mut m = 0;
    let mut n = 0;
    while m <= ORDER {
        let mut i = m;
        loop {
            out[n] = (i, m - i);
            n += 1;
            if i == 0 {
                break;
            }
            i -= 1;
        }
        m += 1;
    }
    out
};

/// `i! j!` of every index: the factor between coefficients and partial derivatives.
fn factorials(n: usize) -> f64 {
    let (i, j) = PAIRS[n];
    let f = |k: usize| (1..=k).map(|x| x as f64).product::<f64>();
    f(i) * f(j)
}

/// A scalar Taylor polynomial truncated at total order [`ORDER`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Taylor(pub [f64; TERMS]);

impl Taylor {
    /// The affine function `value + du·x + dv·y`.
    pub(crate) fn affine(value: f64, du: f64, dv: f64) -> Taylor {
        let mut c = [0.0; TERMS];
        c[0] = value;
        c[term(1, 0)] = du;
        c[term(0, 1)] = dv;
        Taylor(c)
    }

    /// `1/g` by the geometric series: `g = g₀(1 + h)`, `1/g = (1/g₀) Σ (−h)^k`, exact to the
    /// truncation order since `h` has no constant term.
    fn recip(self) -> Taylor {
        let g0 = self.0[0];
        let mut h = self.scale(1.0 / g0);
        h.0[0] = 0.0;
        let mut sum = Taylor::constant(1.0);
        let mut power = Taylor::constant(1.0);
        for _ in 0..ORDER {
            power = power * h.scale(-1.0);
            sum = sum + power;
        }
        sum.scale(1.0 / g0)
    }
}

impl Add for Taylor {
    type Output = Taylor;
    fn add(self, o: Taylor) -> Taylor {
        Taylor(std::array::from_fn(|n| self.0[n] + o.0[n]))
    }
}

impl Sub for Taylor {
    type Output = Taylor;
    fn sub(self, o: Taylor) -> Taylor {
        Taylor(std::array::from_fn(|n| self.0[n] - o.0[n]))
    }
}

impl Mul for Taylor {
    type Output = Taylor;
    /// The truncated product (a convolution of the coefficients).
    fn mul(self, o: Taylor) -> Taylor {
        let mut c = [0.0; TERMS];
        for (a, &(ia, ja)) in PAIRS.iter().enumerate() {
            if self.0[a] == 0.0 {
                continue;
            }
            for (b, &(ib, jb)) in PAIRS.iter().enumerate() {
                if ia + ja + ib + jb <= ORDER {
                    c[term(ia + ib, ja + jb)] += self.0[a] * o.0[b];
                }
            }
        }
        Taylor(c)
    }
}

impl Div for Taylor {
    type Output = Taylor;
    #[allow(clippy::suspicious_arithmetic_impl)]
    fn div(self, o: Taylor) -> Taylor {
        self * o.recip()
    }
}

impl Scalar for Taylor {
    fn constant(c: f64) -> Self {
        Taylor::affine(c, 0.0, 0.0)
    }
    fn value(&self) -> f64 {
        self.0[0]
    }
    fn powi(self, n: u32) -> Self {
        (0..n).fold(Taylor::constant(1.0), |acc, _| acc * self)
    }
    fn scale(self, c: f64) -> Self {
        Taylor(self.0.map(|x| x * c))
    }
}

/// Partial derivatives (in [`Taylor`] storage order) to Taylor coefficients.
pub(crate) fn from_partials(partials: &[DVec3]) -> [DVec3; TERMS] {
    std::array::from_fn(|n| partials.get(n).copied().unwrap_or(DVec3::ZERO) / factorials(n))
}

/// Taylor coefficients back to partial derivatives, up to `max_order`.
pub(crate) fn to_partials(coefficients: &[DVec3; TERMS], max_order: usize) -> Vec<DVec3> {
    let count = (max_order.min(ORDER) + 1) * (max_order.min(ORDER) + 2) / 2;
    (0..count)
        .map(|n| coefficients[n] * factorials(n))
        .collect()
}

/// `acc += f · d` for a scalar series `f` and a vector series `d` (truncated).
pub(crate) fn add_product(acc: &mut [DVec3; TERMS], f: &Taylor, d: &[DVec3; TERMS]) {
    for (a, &(ia, ja)) in PAIRS.iter().enumerate() {
        if f.0[a] == 0.0 {
            continue;
        }
        for (b, &(ib, jb)) in PAIRS.iter().enumerate() {
            if ia + ja + ib + jb <= ORDER {
                acc[term(ia + ib, ja + jb)] += f.0[a] * d[b];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Coefficient of `x^i y^j` of `t`.
    fn coefficient(t: &Taylor, i: usize, j: usize) -> f64 {
        t.0[term(i, j)]
    }
    use crate::blend::scalar_jet::ScalarJet;

    /// The Taylor arithmetic agrees with the exact second-order jet on a quotient with
    /// powers, and its higher coefficients with the series of 1/(1 − x − y).
    #[test]
    fn agrees_with_jets_and_known_series() {
        let (u0, v0) = (0.3, 0.45);
        let f_t = {
            let (u, v) = (Taylor::affine(u0, 1.0, 0.0), Taylor::affine(v0, 0.0, 1.0));
            u.powi(3) * v / (Taylor::constant(1.0) + u * u + v)
        };
        let f_j = {
            let (u, v) = (
                ScalarJet::affine(u0, 1.0, 0.0),
                ScalarJet::affine(v0, 0.0, 1.0),
            );
            u.powi(3) * v / (ScalarJet::constant(1.0) + u * u + v)
        };
        let pairs = [
            (coefficient(&f_t, 0, 0), f_j.v),
            (coefficient(&f_t, 1, 0), f_j.du),
            (coefficient(&f_t, 0, 1), f_j.dv),
            (2.0 * coefficient(&f_t, 2, 0), f_j.duu),
            (coefficient(&f_t, 1, 1), f_j.duv),
            (2.0 * coefficient(&f_t, 0, 2), f_j.dvv),
        ];
        for (t, j) in pairs {
            assert!((t - j).abs() <= 1e-14 * j.abs().max(1.0), "{t} vs {j}");
        }
        // 1/(1 − x − y) = Σ (x + y)^m: coefficient of x^i y^j is C(i+j, i).
        let g = Taylor::constant(1.0) / Taylor::affine(1.0, -1.0, -1.0);
        for (n, &(i, j)) in PAIRS.iter().enumerate() {
            let binomial = factorials(term(i + j, 0)) / factorials(n);
            assert!((g.0[n] - binomial).abs() <= 1e-13, "({i},{j}): {}", g.0[n]);
        }
    }
}
