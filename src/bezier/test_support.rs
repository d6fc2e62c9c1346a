//! Test fixtures shared by the Bézier unit tests: a small seeded PRNG for reproducible random
//! control nets and parameters, and the explicit Bernstein sums (value and exact partial
//! derivatives) that the de Casteljau based code is checked against.

use glam::DVec3;

use super::{CurveBezier, TriangleBezier};

/// SplitMix64: a tiny, well-mixed, seeded generator, so every property test sees the same
/// pseudo-random inputs on every run.
pub(crate) struct Rng(u64);

impl Rng {
    pub(crate) fn new(seed: u64) -> Self {
        Rng(seed)
    }

    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `[lo, hi)`.
    pub(crate) fn range(&mut self, lo: f64, hi: f64) -> f64 {
        let unit = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * unit
    }

    /// A point with coordinates uniform in `[-1, 1)`, shifted by `offset` in every coordinate.
    pub(crate) fn point(&mut self, offset: f64) -> DVec3 {
        DVec3::new(
            self.range(-1.0, 1.0),
            self.range(-1.0, 1.0),
            self.range(-1.0, 1.0),
        ) + DVec3::splat(offset)
    }

    /// A barycentric point (sums to one) inside the domain triangle.
    pub(crate) fn bary_inside(&mut self) -> DVec3 {
        let (mut u, mut v) = (self.range(0.0, 1.0), self.range(0.0, 1.0));
        if u + v > 1.0 {
            (u, v) = (1.0 - u, 1.0 - v);
        }
        DVec3::new(1.0 - u - v, u, v)
    }

    /// A random control net of the given degree (coordinates in `[-1, 1)` plus `offset`).
    pub(crate) fn triangle(&mut self, degree: usize, offset: f64) -> TriangleBezier {
        TriangleBezier::from_fn(degree, |_, _, _| self.point(offset))
    }

    /// A random curve of the given degree.
    pub(crate) fn curve(&mut self, degree: usize) -> CurveBezier {
        CurveBezier::new((0..=degree).map(|_| self.point(0.0)).collect())
    }
}

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
