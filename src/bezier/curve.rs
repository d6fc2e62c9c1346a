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

    /// Point at `t` (de Casteljau, Farin CAGD §3.1).
    pub fn eval(&self, t: f64) -> DVec3 {
        let mut net = self.points.clone();
        for m in (1..=self.degree()).rev() {
            de_casteljau_step(&mut net, m, t);
        }
        net[0]
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
        let mut net = self.points.clone();
        for (m, &t) in (1..=d).rev().zip(args) {
            de_casteljau_step(&mut net, m, t);
        }
        net[0]
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
}
