//! The one seeded generator of the test suites and benchmarks, so every property test sees
//! the same pseudo-random inputs on every run and on every machine.

use glam::DVec3;

use crate::bezier::{CurveBezier, TriangleBezier};

/// SplitMix64: a tiny, well-mixed, seeded generator, so every property test sees the same
/// pseudo-random inputs on every run.
pub struct Rng(u64);

impl Rng {
    /// The generator started at `seed`.
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }

    /// A point with coordinates uniform in `[-1, 1)`, shifted by `offset` in every coordinate.
    pub fn point(&mut self, offset: f64) -> DVec3 {
        DVec3::new(
            self.range(-1.0, 1.0),
            self.range(-1.0, 1.0),
            self.range(-1.0, 1.0),
        ) + DVec3::splat(offset)
    }

    /// A barycentric point (sums to one) inside the domain triangle.
    pub fn bary_inside(&mut self) -> DVec3 {
        let (mut u, mut v) = (self.range(0.0, 1.0), self.range(0.0, 1.0));
        if u + v > 1.0 {
            (u, v) = (1.0 - u, 1.0 - v);
        }
        DVec3::new(1.0 - u - v, u, v)
    }

    /// A random control net of the given degree (coordinates in `[-1, 1)` plus `offset`).
    pub fn triangle(&mut self, degree: usize, offset: f64) -> TriangleBezier {
        TriangleBezier::from_fn(degree, |_, _, _| self.point(offset))
    }

    /// A random curve of the given degree.
    pub fn curve(&mut self, degree: usize) -> CurveBezier {
        CurveBezier::new((0..=degree).map(|_| self.point(0.0)).collect())
    }
}

/// `n! / (n − a)! · x^(n−a)`: the `a`-th derivative of `x^n` (zero for `a > n`).
pub fn power_derivative(x: f64, n: usize, a: usize) -> f64 {
    if a > n {
        return 0.0;
    }
    let falling: f64 = ((n - a + 1)..=n).map(|f| f as f64).product();
    falling * x.powi((n - a) as i32)
}
