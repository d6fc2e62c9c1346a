//! Bézier curves of any degree: de Casteljau evaluation, blossom, derivative (hodograph),
//! splitting, sub-segments, degree elevation, control bounds.
//!
//! Standard facts from Farin, *Curves and Surfaces for CAGD*, ch. 3–5 (de Casteljau,
//! blossoms, hodograph, subdivision, degree elevation); the same recursions in one variable as
//! the triangular ones of [`crate::bezier::triangle`].

use glam::DVec3;

use crate::geom::Aabb;

/// One de Casteljau step in place on a curve net of degree `m ≥ 1`:
/// `p'_i = (1−t) p_i + t p_{i+1}`, `i = 0..m−1` (reads `p_{i+1}` before it is overwritten).
#[inline(always)]
fn de_casteljau_step(net: &mut [DVec3], m: usize, t: f64) {
    for i in 0..m {
        net[i] = net[i].lerp(net[i + 1], t);
    }
}

/// Highest degree whose evaluation runs on a stack array (no heap allocation).
const MAX_STACK_DEGREE: usize = 15;

/// Runs `f` on a mutable copy of `points`, on the stack up to [`MAX_STACK_DEGREE`].
#[inline(always)]
fn with_working_net<R>(points: &[DVec3], f: impl FnOnce(&mut [DVec3]) -> R) -> R {
    if points.len() <= MAX_STACK_DEGREE + 1 {
        let mut net = [DVec3::ZERO; MAX_STACK_DEGREE + 1];
        net[..points.len()].copy_from_slice(points);
        f(&mut net[..points.len()])
    } else {
        f(&mut points.to_vec())
    }
}

/// A Bézier curve `C(t) = Σ p_i B_i^d(t)`, `t ∈ [0, 1]`.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveBezier {
    points: Vec<DVec3>,
}

impl CurveBezier {
    /// A curve from its control points (at least one; panics on none).
    pub fn new(points: Vec<DVec3>) -> Self {
        assert!(!points.is_empty(), "a Bézier curve needs a control point");
        CurveBezier { points }
    }

    /// Degree (number of control points − 1).
    pub fn degree(&self) -> usize {
        self.points.len() - 1
    }

    /// Control points.
    pub fn points(&self) -> &[DVec3] {
        &self.points
    }

    /// Point at `t` (de Casteljau, Farin CAGD §3.1). Allocation-free up to degree 15.
    pub fn eval(&self, t: f64) -> DVec3 {
        let degree = self.degree();
        with_working_net(&self.points, |net| {
            for m in (1..=degree).rev() {
                de_casteljau_step(net, m, t);
            }
            net[0]
        })
    }

    /// The blossom (polar form) at `d` parameters: symmetric, affine in each, equal to the
    /// curve on the diagonal (Farin CAGD §3.4). Panics unless `args.len() == d`.
    pub fn blossom(&self, args: &[f64]) -> DVec3 {
        let d = self.degree();
        assert_eq!(
            args.len(),
            d,
            "the blossom of a degree-{d} curve takes {d} arguments"
        );
        with_working_net(&self.points, |net| {
            for (m, &t) in (1..=d).rev().zip(args) {
                de_casteljau_step(net, m, t);
            }
            net[0]
        })
    }

    /// The derivative curve (degree d−1; a single zero point for d = 0): the hodograph
    /// `C'(t) = d Σ (p_{i+1} − p_i) B_i^{d−1}(t)` (Farin CAGD §5.3).
    pub fn derivative(&self) -> CurveBezier {
        let d = self.degree();
        if d == 0 {
            return CurveBezier::new(vec![DVec3::ZERO]);
        }
        let points = self
            .points
            .windows(2)
            .map(|pair| d as f64 * (pair[1] - pair[0]))
            .collect();
        CurveBezier::new(points)
    }

    /// The two halves at `t`: the curve over `[0, t]` and over `[t, 1]`, each reparametrised
    /// to `[0, 1]`. Their control points are the two outer edges of the de Casteljau scheme
    /// (Farin CAGD §5.4).
    pub fn split(&self, t: f64) -> (CurveBezier, CurveBezier) {
        let d = self.degree();
        let mut net = self.points.clone();
        let mut left = Vec::with_capacity(d + 1);
        let mut right = vec![DVec3::ZERO; d + 1];
        left.push(net[0]);
        right[d] = net[d];
        for m in (1..=d).rev() {
            de_casteljau_step(&mut net, m, t);
            left.push(net[0]);
            right[m - 1] = net[m - 1];
        }
        (CurveBezier::new(left), CurveBezier::new(right))
    }

    /// The curve over `[t0, t1]` reparametrised to `[0, 1]` (`t0 > t1` reverses it):
    /// `q_i = blossom(t0^{d−i}, t1^i)` (Farin CAGD §4.2). Shares the first `d−i` de Casteljau
    /// steps at `t0` between all points with the same `i`.
    pub fn subsegment(&self, t0: f64, t1: f64) -> CurveBezier {
        let d = self.degree();
        let mut after_t0 = self.points.clone();
        let mut scratch = Vec::with_capacity(d + 1);
        let mut points = vec![DVec3::ZERO; d + 1];
        // q_i needs d−i steps at t0 then i steps at t1; walk i from d down to 0 so that the
        // steps at t0 accumulate.
        for i in (0..=d).rev() {
            let steps_t0 = d - i;
            if steps_t0 > 0 {
                de_casteljau_step(&mut after_t0, d - steps_t0 + 1, t0);
            }
            scratch.clear();
            scratch.extend_from_slice(&after_t0[..=i]);
            for m in (1..=i).rev() {
                de_casteljau_step(&mut scratch, m, t1);
            }
            points[i] = scratch[0];
        }
        CurveBezier::new(points)
    }

    /// The same curve with degree d+1 (Farin CAGD §5.1):
    /// `p'_i = (i/(d+1)) p_{i−1} + (1 − i/(d+1)) p_i`.
    pub fn elevate(&self) -> CurveBezier {
        let d = self.degree();
        let n = (d + 1) as f64;
        let points = (0..=d + 1)
            .map(|i| {
                let a = i as f64 / n;
                match i {
                    0 => self.points[0],
                    _ if i == d + 1 => self.points[d],
                    _ => a * self.points[i - 1] + (1.0 - a) * self.points[i],
                }
            })
            .collect();
        CurveBezier::new(points)
    }

    /// Bounding box of the control points (contains the curve: convex-hull property).
    pub fn control_bounds(&self) -> Aabb {
        Aabb::from_points(&self.points)
    }

    /// The product `f(t) C(t)` with the scalar Bernstein polynomial `f` of coefficients `scalar`
    /// (degree m = len − 1), a curve of degree d + m:
    /// `c_k = Σ_{i+j=k} C(m,i) C(d,j) / C(m+d,k) f_i p_j`.
    pub fn times_scalar_polynomial(&self, scalar: &[f64]) -> CurveBezier {
        let (m, d) = (scalar.len().saturating_sub(1), self.degree());
        let binomial = |n: usize, k: usize| -> f64 {
            (1..=k).map(|i| (n + 1 - i) as f64 / i as f64).product()
        };
        let points = (0..=m + d)
            .map(|k| {
                let lo = k.saturating_sub(d);
                (lo..=k.min(m))
                    .map(|i| {
                        let j = k - i;
                        binomial(m, i) * binomial(d, j) / binomial(m + d, k)
                            * scalar[i]
                            * self.points[j]
                    })
                    .sum()
            })
            .collect();
        CurveBezier::new(points)
    }
}

#[cfg(test)]
mod tests {
    use crate::bezier::CurveBezier;
    use crate::bezier::test_support::{curve_bernstein_sum, rel_err, scale_of};
    use crate::testing::Rng;
    use glam::DVec3;

    /// 1..=7 as specified, plus 0 and degrees on the heap path.
    const DEGREES: [usize; 10] = [0, 1, 2, 3, 4, 5, 6, 7, 16, 20];

    fn params() -> Vec<f64> {
        (0..=20).map(|n| -0.1 + 1.2 * n as f64 / 20.0).collect()
    }

    #[test]
    fn eval_equals_the_bernstein_sum() {
        let mut rng = Rng::new(20);
        for d in DEGREES {
            let curve = rng.curve(d);
            let scale = scale_of(curve.points());
            for t in params() {
                let err = rel_err(curve.eval(t), curve_bernstein_sum(&curve, t), scale);
                assert!(err <= 1e-12, "d={d} t={t}: rel err {err:e}");
            }
            assert_eq!(curve.eval(0.0), curve.points()[0]);
            assert_eq!(curve.eval(1.0), curve.points()[d]);
        }
    }

    #[test]
    fn blossom_is_symmetric_and_the_curve_on_the_diagonal() {
        let mut rng = Rng::new(21);
        for d in DEGREES {
            let curve = rng.curve(d);
            let scale = scale_of(curve.points());
            for t in params() {
                let err = rel_err(curve.blossom(&vec![t; d]), curve.eval(t), scale);
                assert!(err <= 1e-12, "d={d} t={t}: rel err {err:e}");
            }
            let mut args: Vec<f64> = (0..d).map(|_| rng.range(-0.5, 1.5)).collect();
            let value = curve.blossom(&args);
            args.reverse();
            let err = rel_err(curve.blossom(&args), value, scale);
            assert!(err <= 1e-12, "d={d} reversed: rel err {err:e}");
        }
    }

    #[test]
    fn split_halves_reproduce_the_curve() {
        let mut rng = Rng::new(22);
        for d in DEGREES {
            let curve = rng.curve(d);
            let scale = scale_of(curve.points());
            for t in [0.0, 0.3, 0.5, 0.77, 1.0] {
                let (left, right) = curve.split(t);
                assert_eq!((left.degree(), right.degree()), (d, d));
                for n in 0..=10 {
                    let s = n as f64 / 10.0;
                    let err_left = rel_err(left.eval(s), curve.eval(s * t), scale);
                    let err_right = rel_err(right.eval(s), curve.eval(t + s * (1.0 - t)), scale);
                    assert!(
                        err_left <= 1e-12,
                        "d={d} t={t} s={s}: left rel err {err_left:e}"
                    );
                    assert!(
                        err_right <= 1e-12,
                        "d={d} t={t} s={s}: right rel err {err_right:e}"
                    );
                }
                // The halves meet at the split point, bit for bit.
                assert_eq!(left.points()[d], right.points()[0], "d={d} t={t}");
            }
        }
    }

    #[test]
    fn subsegment_reproduces_the_curve_and_can_reverse_it() {
        let mut rng = Rng::new(23);
        for d in DEGREES {
            let curve = rng.curve(d);
            let scale = scale_of(curve.points());
            for (t0, t1) in [(0.0, 1.0), (0.2, 0.9), (0.8, 0.1), (0.4, 0.45)] {
                let piece = curve.subsegment(t0, t1);
                assert_eq!(piece.degree(), d);
                for n in 0..=10 {
                    let s = n as f64 / 10.0;
                    let err = rel_err(piece.eval(s), curve.eval(t0 + s * (t1 - t0)), scale);
                    assert!(err <= 1e-12, "d={d} [{t0},{t1}] s={s}: rel err {err:e}");
                }
            }
            assert_eq!(curve.subsegment(0.0, 1.0), curve, "d={d}");
        }
    }

    /// The hodograph against the derivative of the explicit Bernstein sum (via central
    /// differences with second-order truncation: halving h divides the error by ~4).
    #[test]
    fn derivative_matches_central_differences() {
        let mut rng = Rng::new(24);
        for d in DEGREES {
            let curve = rng.curve(d);
            let derivative = curve.derivative();
            assert_eq!(derivative.degree(), d.saturating_sub(1));
            let scale = scale_of(curve.points()) * d.max(1) as f64;
            let central = |t: f64, h: f64| (curve.eval(t + h) - curve.eval(t - h)) / (2.0 * h);
            let h = 1e-2;
            for t in params() {
                let exact = derivative.eval(t);
                let err_coarse = (central(t, h) - exact).length();
                let err_fine = (central(t, h / 2.0) - exact).length();
                let rounding = 1e-12 * scale;
                if err_coarse > 1e3 * rounding {
                    let ratio = err_coarse / err_fine;
                    assert!(
                        (3.5..=4.5).contains(&ratio),
                        "d={d} t={t}: error ratio {ratio} ({err_coarse:e} → {err_fine:e})"
                    );
                } else {
                    assert!(err_fine <= 1e3 * rounding, "d={d} t={t}: {err_fine:e}");
                }
            }
        }
    }

    #[test]
    fn elevation_reproduces_the_curve() {
        let mut rng = Rng::new(25);
        for d in DEGREES {
            let curve = rng.curve(d);
            let elevated = curve.elevate();
            assert_eq!(elevated.degree(), d + 1);
            assert_eq!(elevated.points()[0], curve.points()[0]);
            assert_eq!(elevated.points()[d + 1], curve.points()[d]);
            let scale = scale_of(curve.points());
            for t in params() {
                let err = rel_err(elevated.eval(t), curve.eval(t), scale);
                assert!(err <= 1e-12, "d={d} t={t}: rel err {err:e}");
            }
        }
    }

    #[test]
    fn control_bounds_contain_the_curve() {
        let mut rng = Rng::new(26);
        for d in DEGREES {
            let curve = rng.curve(d);
            let bounds = curve.control_bounds();
            for n in 0..=100 {
                let p = curve.eval(n as f64 / 100.0);
                assert!(bounds.contains(p, 0.0), "d={d}: {p} outside {bounds:?}");
            }
        }
    }

    /// The product curve evaluates to f(t)·C(t).
    #[test]
    fn product_with_a_scalar_polynomial() {
        let curve = CurveBezier::new(vec![
            DVec3::new(0.0, 1.0, 2.0),
            DVec3::new(1.0, -1.0, 0.5),
            DVec3::new(2.0, 0.0, -1.0),
            DVec3::new(0.5, 3.0, 1.0),
        ]);
        let scalar = [0.3, -1.2, 2.0];
        let f = |t: f64| {
            scalar[0] * (1.0 - t).powi(2) + scalar[1] * 2.0 * t * (1.0 - t) + scalar[2] * t * t
        };
        let product = curve.times_scalar_polynomial(&scalar);
        assert_eq!(product.degree(), 5);
        for step in 0..=10 {
            let t = step as f64 / 10.0;
            let expected = f(t) * curve.eval(t);
            assert!((product.eval(t) - expected).length() < 1e-14, "t = {t}");
        }
    }
}
