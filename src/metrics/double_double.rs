//! Double-double numbers: an unevaluated sum `hi + lo` of two f64 with `|lo| ≤ ulp(hi)/2`,
//! about 106 bits of significand, for the high-precision measure of a joint's order
//! ([`crate::metrics::continuity`], whose series arithmetic is generic over its `Real`
//! scalar: f64, or [`DoubleDouble`]). Compiled for the tests only: the measure in double-double
//! is how the tests check the f64 measure.
//!
//! Hand-written rather than a crate: the measure needs `+ − × ÷` and comparisons only, which
//! are a few error-free transformations (`two_sum`, and `two_prod` by a fused multiply-add,
//! which Rust rounds correctly on every target, so results are the same everywhere); the
//! double-double crate on crates.io (`twofloat` 0.8) brings a procedural-macro dependency
//! (`hexf` → `syn` 1) for its constants, a build cost the four operations do not need.
//! Algorithms: the accurate double-word addition, the FMA double-word product and the
//! double-word division of Joldeș, Muller and Popescu, "Tight and rigorous error bounds for
//! basic building blocks of double-word arithmetic" (ACM TOMS 44(2), 2017): relative errors
//! below `3u²`, `5u²` (FMA product: `4u²`) and `15u²` with `u = 2⁻⁵³`.

use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub};

use crate::metrics::continuity::Real;

/// `hi + lo`, normalised (`hi` is `hi + lo` rounded to f64). Derived comparisons are those
/// of the value: the high parts decide unless equal, then the low parts.
#[derive(Clone, Copy, Debug, Default, PartialEq, PartialOrd)]
pub struct DoubleDouble {
    hi: f64,
    lo: f64,
}

/// `a + b = s + e` exactly, `s = fl(a + b)` (Knuth's TwoSum, any order of magnitudes).
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let b_virtual = s - a;
    let a_virtual = s - b_virtual;
    (s, (a - a_virtual) + (b - b_virtual))
}

/// `a + b = s + e` exactly when `|a| ≥ |b|` or `a = 0` (Dekker's Fast2Sum).
fn fast_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    (s, b - (s - a))
}

/// `a · b = p + e` exactly (barring underflow), by a fused multiply-add.
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

impl DoubleDouble {
    /// The number `x` (exact).
    pub fn from_f64(x: f64) -> Self {
        DoubleDouble { hi: x, lo: 0.0 }
    }

    /// The absolute value.
    pub fn abs(self) -> Self {
        if self.hi < 0.0 || (self.hi == 0.0 && self.lo < 0.0) {
            -self
        } else {
            self
        }
    }

    /// The pair `hi + lo`, normalised.
    pub fn new(hi: f64, lo: f64) -> Self {
        let (hi, lo) = two_sum(hi, lo);
        DoubleDouble { hi, lo }
    }

    /// `self · b` for an f64 `b` (Joldeș–Muller–Popescu, DWTimesFP3: error below `2u²`).
    fn times_f64(self, b: f64) -> Self {
        let (ch, cl1) = two_prod(self.hi, b);
        let cl3 = self.lo.mul_add(b, cl1);
        let (hi, lo) = fast_two_sum(ch, cl3);
        DoubleDouble { hi, lo }
    }
}

impl Real for DoubleDouble {
    const ZERO: DoubleDouble = DoubleDouble { hi: 0.0, lo: 0.0 };
    fn to_f64(self) -> f64 {
        self.hi
    }
}

impl Neg for DoubleDouble {
    type Output = DoubleDouble;
    fn neg(self) -> DoubleDouble {
        DoubleDouble {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
}

impl Add for DoubleDouble {
    type Output = DoubleDouble;
    /// AccurateDWPlusDW (relative error below `3u² + 13u³`).
    fn add(self, y: DoubleDouble) -> DoubleDouble {
        let (sh, sl) = two_sum(self.hi, y.hi);
        let (th, tl) = two_sum(self.lo, y.lo);
        let (vh, vl) = fast_two_sum(sh, sl + th);
        let (hi, lo) = fast_two_sum(vh, tl + vl);
        DoubleDouble { hi, lo }
    }
}

impl AddAssign for DoubleDouble {
    fn add_assign(&mut self, y: DoubleDouble) {
        *self = *self + y;
    }
}

impl Sub for DoubleDouble {
    type Output = DoubleDouble;
    fn sub(self, y: DoubleDouble) -> DoubleDouble {
        self + -y
    }
}

impl Mul for DoubleDouble {
    type Output = DoubleDouble;
    /// DWTimesDW3 with fused multiply-adds (relative error below `4u²`).
    fn mul(self, y: DoubleDouble) -> DoubleDouble {
        let (ch, cl1) = two_prod(self.hi, y.hi);
        let tl0 = self.lo * y.lo;
        let tl1 = self.hi.mul_add(y.lo, tl0);
        let cl2 = self.lo.mul_add(y.hi, tl1);
        let (hi, lo) = fast_two_sum(ch, cl1 + cl2);
        DoubleDouble { hi, lo }
    }
}

impl Div for DoubleDouble {
    type Output = DoubleDouble;
    /// DWDivDW2 (relative error below `15u² + 56u³`).
    fn div(self, y: DoubleDouble) -> DoubleDouble {
        let th = self.hi / y.hi;
        let r = y.times_f64(th);
        let pi_h = self.hi - r.hi;
        let delta_l = self.lo - r.lo;
        let delta = pi_h + delta_l;
        let tl = delta / y.hi;
        let (hi, lo) = fast_two_sum(th, tl);
        DoubleDouble { hi, lo }
    }
}

mod tests {
    use super::*;

    /// A deterministic pseudo-random f64 in [−1, 1) times 2^e for e in −20..20.
    fn next(state: &mut u64) -> f64 {
        *state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let unit = (*state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
        let e = ((*state >> 3) % 40) as i32 - 20;
        unit * 2f64.powi(e)
    }

    /// The exact sum of f64 multiples of 2^-80, times 2^80, as an integer (enough for the
    /// exponents of the tests) to check the error-free transformations exactly.
    fn exact(parts: &[f64]) -> i128 {
        parts
            .iter()
            .map(|&x| {
                let scaled = x * 2f64.powi(80);
                assert_eq!(scaled.fract(), 0.0, "{x:e} is not a multiple of 2^-80");
                scaled as i128
            })
            .sum()
    }

    /// TwoSum, Fast2Sum and the FMA product are error-free: `s + e` (`p + e`) is the exact
    /// sum (product) of the arguments and `s` (`p`) its rounding.
    #[test]
    fn error_free_transformations_are_exact() {
        let mut state = 3;
        for _ in 0..10_000 {
            // Multiples of 2^-40 with at most 30 significant bits above: sums and products
            // stay exact in i128 at the scale 2^80.
            let a = (next(&mut state) * 2f64.powi(20)).round() * 2f64.powi(-40);
            let b = (next(&mut state) * 2f64.powi(20)).round() * 2f64.powi(-40);
            let (s, e) = two_sum(a, b);
            assert_eq!(exact(&[s, e]), exact(&[a, b]));
            assert_eq!(s, a + b);
            let (big, small) = if a.abs() >= b.abs() { (a, b) } else { (b, a) };
            let (s, e) = fast_two_sum(big, small);
            assert_eq!(exact(&[s, e]), exact(&[a, b]));
            let (p, e) = two_prod(a, b);
            assert_eq!(p, a * b);
            // a = ia 2^-40, b = ib 2^-40: a·b at the scale 2^80 is ia·ib.
            let (ia, ib) = ((a * 2f64.powi(40)) as i128, (b * 2f64.powi(40)) as i128);
            assert_eq!(exact(&[p, e]), ia * ib, "{a:e} · {b:e}");
        }
    }

    /// Double-double results are normalised and within the published error bounds of the
    /// true value, checked against the exact value of the pair where it is representable
    /// (sums) and against identities otherwise (`(x · y) / y = x`, `(x + y) − y = x`).
    #[test]
    fn arithmetic_is_accurate_to_double_double_precision() {
        let u = f64::EPSILON / 2.0;
        let mut state = 17;
        let value = |x: DoubleDouble| (x.hi, x.lo);
        for _ in 0..10_000 {
            let x = DoubleDouble::new(next(&mut state), next(&mut state) * 1e-17);
            let y = DoubleDouble::new(next(&mut state), next(&mut state) * 1e-17);
            for z in [x + y, x - y, x * y, x / y] {
                let (hi, lo) = value(z);
                assert_eq!(hi + lo, hi, "normalised: {z:?}");
            }
            let back = (x + y) - y;
            let err = (back - x).abs().hi;
            let scale = x.abs().hi.max(y.abs().hi);
            assert!(
                err <= 8.0 * u * u * scale,
                "(x + y) − y: {err:e} of {scale:e}"
            );
            let back = (x * y) / y;
            let err = (back - x).abs().hi;
            assert!(err <= 40.0 * u * u * x.abs().hi, "(x · y) / y: {err:e}");
            // 1/3 · 3 = 1 to double-double precision, where f64 is off by u.
            let third = DoubleDouble::from_f64(1.0) / DoubleDouble::from_f64(3.0);
            let one = third * DoubleDouble::from_f64(3.0) - DoubleDouble::from_f64(1.0);
            assert!(one.abs().hi <= 20.0 * u * u);
        }
        // The sum of numbers of very different size keeps the small one.
        let big = DoubleDouble::from_f64(1.0);
        let small = DoubleDouble::from_f64(1e-20);
        let sum = big + small;
        assert_eq!((sum.hi, sum.lo), (1.0, 1e-20));
        assert_eq!((sum - big).hi, 1e-20);
        assert!(small < sum && -sum < small && sum.abs() == sum && (-sum).abs() == sum);
    }
}
