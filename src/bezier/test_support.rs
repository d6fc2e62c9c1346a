//! Test fixtures shared by the Bézier unit tests (random nets come from
//! [`crate::testing::Rng`]): the explicit Bernstein sums (value and exact partial
//! derivatives) that the de Casteljau based code is checked against.

use glam::DVec3;

use super::gram::multi_indices;
use super::{CurveBezier, TriangleBezier};
use crate::linalg::Matrix;

/// `n! / (n − a)! · x^(n−a)`: the `a`-th derivative of `x^n` (zero for `a > n`).
pub(crate) fn power_derivative(x: f64, n: usize, a: usize) -> f64 {
    if a > n {
        return 0.0;
    }
    let falling: f64 = ((n - a + 1)..=n).map(|f| f as f64).product();
    falling * x.powi((n - a) as i32)
}

fn factorial(n: usize) -> f64 {
    (1..=n).map(|f| f as f64).product()
}

/// `∂^{a0+a1+a2} / ∂w0^a0 ∂w1^a1 ∂w2^a2` of the explicit Bernstein sum
/// `Σ b_ijk d!/(i!j!k!) w0^i w1^j w2^k`, term by term (no de Casteljau involved).
pub(crate) fn bernstein_partial(patch: &TriangleBezier, w: DVec3, a: [usize; 3]) -> DVec3 {
    let d = patch.degree();
    let mut sum = DVec3::ZERO;
    for i in 0..=d {
        for j in 0..=d - i {
            let k = d - i - j;
            let multinomial = factorial(d) / (factorial(i) * factorial(j) * factorial(k));
            let basis = multinomial
                * power_derivative(w.x, i, a[0])
                * power_derivative(w.y, j, a[1])
                * power_derivative(w.z, k, a[2]);
            sum += basis * patch.point(i, j);
        }
    }
    sum
}

/// The explicit Bernstein sum at `w`.
pub(crate) fn bernstein_sum(patch: &TriangleBezier, w: DVec3) -> DVec3 {
    bernstein_partial(patch, w, [0, 0, 0])
}

/// `Σ p_i C(d,i) (1−t)^(d−i) t^i`.
pub(crate) fn curve_bernstein_sum(curve: &CurveBezier, t: f64) -> DVec3 {
    let d = curve.degree();
    curve
        .points()
        .iter()
        .enumerate()
        .map(|(i, &p)| {
            factorial(d) / (factorial(i) * factorial(d - i))
                * (1.0 - t).powi((d - i) as i32)
                * t.powi(i as i32)
                * p
        })
        .sum()
}

/// Largest coordinate magnitude of a set of points (the scale for relative errors).
pub(crate) fn scale_of(points: &[DVec3]) -> f64 {
    points
        .iter()
        .fold(0.0_f64, |m, p| m.max(p.abs().max_element()))
}

/// Largest coordinate difference of `a` and `b`, relative to `scale`.
pub(crate) fn rel_err(a: DVec3, b: DVec3, scale: f64) -> f64 {
    (a - b).abs().max_element() / scale
}

/// The values of the degree-`d` Bernstein polynomials at the domain points `m/d`: row `i`
/// holds `B^d_α(m_i/d)` over the multi-indices α, both in storage order. Its inverse maps values
/// at the domain points to the interpolating Bézier net.
pub(crate) fn domain_point_collocation(d: usize) -> Matrix {
    let idx = multi_indices(d);
    idx.iter()
        .map(|at| {
            let l = at.map(|x| x as f64 / d as f64);
            idx.iter()
                .map(|m| {
                    super::gram::factorial(d)
                        / (super::gram::factorial(m[0])
                            * super::gram::factorial(m[1])
                            * super::gram::factorial(m[2]))
                        * l[0].powi(m[0] as i32)
                        * l[1].powi(m[1] as i32)
                        * l[2].powi(m[2] as i32)
                })
                .collect()
        })
        .collect()
}
