//! Farin's 2-D cubic Hermite curves [Piper87 §2; Farin, *CAGD* §8.2]: a C¹ piecewise cubic
//! through points `p_0 … p_n` of the plane with given unit tangents `v_0 … v_n`.
//!
//! Between `p_i` and `p_{i+1}` the two inner Bézier points are `t1 = p_i + α v_i` and
//! `t2 = p_{i+1} − β v_{i+1}` [Piper87 eq. 1]. The lengths are chosen so that `t1` and `t2`
//! project onto the chord at its thirds: `α = ‖Δp‖ / (3 cos Θ)` with `Θ` the angle between the
//! chord `Δp = p_{i+1} − p_i` and `v_i` [Piper87 eq. 2], which is `‖Δp‖² / (3 v_i·Δp)`
//! [Piper87 eqs. 3–4]. For `|Θ| > 60°` that length grows without bound, so Farin switches to
//! `α = ⅔‖Δp‖`; both branches give `⅔‖Δp‖` at 60°, so the rule is continuous. The same for `β`
//! with `Ψ`, the angle between `Δp` and `v_{i+1}`.
//!
//! With either branch the chord projection of `t1` is at most a third of the chord (and that of
//! `t2` at least two thirds), so the inner points never cross; the 3-D scheme
//! ([`crate::schemes::piper`]) uses [`tangent_length`] for its edge curves for this reason.
//!
//! Points on the curve are found with the de Casteljau algorithm [Piper87 eq. 5]. A segment
//! is a polynomial, so cutting it at `t = ½` gives two cubics that describe the same points and
//! join C¹ [Piper87 §2, after Schwartz].

/// `cos 60°`: below it Farin's rule switches to the fixed length `⅔‖Δp‖`.
const COS_SIXTY_DEGREES: f64 = 0.5;

/// Length of the inner Bézier leg at one end of a chord of length `chord_length`, for a unit
/// tangent making an angle with cosine `cos_theta` with the chord [Piper87 eqs. 3–4]:
/// `chord_length / (3 cos Θ)` when `cos Θ ≥ ½` (`|Θ| ≤ 60°`), `⅔ chord_length` otherwise.
///
/// Dimension free: only the chord length and the angle enter, so the same rule serves the
/// plane curves of this module and the edge curves of 3-D schemes.
pub(crate) fn tangent_length(chord_length: f64, cos_theta: f64) -> f64 {
    if cos_theta >= COS_SIXTY_DEGREES {
        chord_length / (3.0 * cos_theta)
    } else {
        2.0 / 3.0 * chord_length
    }
}

/// Test-only items: used by the unit tests of this and other modules, compiled only for them.
#[cfg(test)]
pub(crate) mod test_support {
    use super::*;

    use glam::DVec2;

    use crate::error::{Error, Result};

    /// One cubic segment of a Hermite curve in the plane, `C(t) = Σ b_i B³_i(t)`, `t ∈ [0, 1]`.
    #[derive(Clone, Copy, Debug, PartialEq)]
    pub(crate) struct CubicSegment2d {
        /// The Bézier points `p_i, t1, t2, p_{i+1}`.
        pub points: [DVec2; 4],
    }

    impl CubicSegment2d {
        /// The segment from `p0` with unit tangent `v0` to `p1` with unit tangent `v1`
        /// [Piper87 eqs. 1, 3, 4]. The caller guarantees `p0 ≠ p1` and unit tangents
        /// ([`hermite_curve`] checks user data).
        pub fn new(p0: DVec2, v0: DVec2, p1: DVec2, v1: DVec2) -> Self {
            let chord = p1 - p0;
            let length = chord.length();
            let alpha = tangent_length(length, v0.dot(chord) / length);
            let beta = tangent_length(length, v1.dot(chord) / length);
            CubicSegment2d {
                points: [p0, p0 + alpha * v0, p1 - beta * v1, p1],
            }
        }

        /// Point at `t` by the de Casteljau algorithm [Piper87 eq. 5].
        pub fn eval(&self, t: f64) -> DVec2 {
            let mut net = self.points;
            for m in (1..=3).rev() {
                for i in 0..m {
                    net[i] = net[i].lerp(net[i + 1], t);
                }
            }
            net[0]
        }

        /// Derivative `C'(t) = 3 Σ (b_{i+1} − b_i) B²_i(t)`.
        pub fn derivative(&self, t: f64) -> DVec2 {
            let b = self.points;
            let (d0, d1, d2) = (b[1] - b[0], b[2] - b[1], b[3] - b[2]);
            let s = 1.0 - t;
            3.0 * (s * s * d0 + 2.0 * s * t * d1 + t * t * d2)
        }

        /// The two halves at `t` (the outer edges of the de Casteljau scheme), each over `[0, 1]`:
        /// the first reparametrises the segment by `t·u`, the second by `t + (1 − t)u`
        /// [Piper87 §2, after Schwartz].
        pub fn split(&self, t: f64) -> (CubicSegment2d, CubicSegment2d) {
            let b = self.points;
            let level1 = [b[0].lerp(b[1], t), b[1].lerp(b[2], t), b[2].lerp(b[3], t)];
            let level2 = [level1[0].lerp(level1[1], t), level1[1].lerp(level1[2], t)];
            let on_curve = level2[0].lerp(level2[1], t);
            (
                CubicSegment2d {
                    points: [b[0], level1[0], level2[0], on_curve],
                },
                CubicSegment2d {
                    points: [on_curve, level2[1], level1[2], b[3]],
                },
            )
        }
    }

    /// Farin's C¹ cubic Hermite curve through `points` with the tangent directions `tangents`
    /// (one per point, any non-zero length: each is normalised, as the scheme assumes unit
    /// tangents): one [`CubicSegment2d`] per pair of consecutive points [Piper87 §2].
    ///
    /// Errors ([`Error::HermiteData`], naming the point): fewer than two points, a different
    /// number of tangents, a non-finite coordinate, two consecutive points that coincide, a zero
    /// tangent — the two constraints of [Piper87 §2].
    pub(crate) fn hermite_curve(
        points: &[DVec2],
        tangents: &[DVec2],
    ) -> Result<Vec<CubicSegment2d>> {
        let bad = |point: usize, reason: &str| Error::HermiteData {
            point,
            reason: reason.to_string(),
        };
        if points.len() < 2 {
            return Err(bad(points.len(), "a curve needs at least two points"));
        }
        if tangents.len() != points.len() {
            return Err(bad(
                tangents.len().min(points.len()),
                "there must be exactly one tangent per point",
            ));
        }
        let mut unit = Vec::with_capacity(tangents.len());
        for (i, (p, v)) in points.iter().zip(tangents).enumerate() {
            if !p.is_finite() || !v.is_finite() {
                return Err(bad(i, "non-finite coordinate"));
            }
            let length = v.length();
            if length == 0.0 || !length.is_finite() {
                return Err(bad(i, "the tangent is the zero vector"));
            }
            unit.push(*v / length);
        }
        for (i, pair) in points.windows(2).enumerate() {
            if (pair[1] - pair[0]).length() == 0.0 {
                return Err(bad(i + 1, "coincides with the point before it"));
            }
        }
        Ok((0..points.len() - 1)
            .map(|i| CubicSegment2d::new(points[i], unit[i], points[i + 1], unit[i + 1]))
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::test_support::*;
    use super::*;
    use crate::error::Error;
    use glam::DVec2;

    fn close(a: DVec2, b: DVec2, scale: f64) -> bool {
        (a - b).length() <= 1e-12 * scale
    }

    /// Points on a circle with their exact unit tangents, some chords at more than 60° to
    /// the tangents (the second branch) and some at less.
    fn sample_data() -> (Vec<DVec2>, Vec<DVec2>) {
        let angles = [0.0_f64, 0.4, 1.1, 3.6, 3.9];
        let points = angles
            .iter()
            .map(|a| DVec2::new(a.cos(), a.sin()))
            .collect();
        let tangents = angles
            .iter()
            .map(|a| DVec2::new(-a.sin(), a.cos()))
            .collect();
        (points, tangents)
    }

    /// The curve passes through the data and leaves/arrives along the given tangents, with
    /// the same direction on both sides of every inner point (C¹ up to the length, G¹ exactly).
    #[test]
    fn interpolates_points_and_tangent_directions() {
        let (points, tangents) = sample_data();
        let curve = hermite_curve(&points, &tangents).expect("valid data");
        assert_eq!(curve.len(), points.len() - 1);
        for (i, segment) in curve.iter().enumerate() {
            assert!(
                close(segment.eval(0.0), points[i], 1.0),
                "segment {i} start"
            );
            assert!(
                close(segment.eval(1.0), points[i + 1], 1.0),
                "segment {i} end"
            );
            let (d0, d1) = (segment.derivative(0.0), segment.derivative(1.0));
            let angle0 = d0.perp_dot(tangents[i]).atan2(d0.dot(tangents[i]));
            let angle1 = d1.perp_dot(tangents[i + 1]).atan2(d1.dot(tangents[i + 1]));
            assert!(
                angle0.abs() <= 1e-12,
                "segment {i} start tangent off by {angle0}"
            );
            assert!(
                angle1.abs() <= 1e-12,
                "segment {i} end tangent off by {angle1}"
            );
        }
    }

    /// Inner points project onto the chord at its thirds when `|Θ| ≤ 60°`, and at most at a
    /// third (never crossing) when the 60° branch is taken, where the leg is ⅔ of the chord.
    #[test]
    fn inner_points_follow_the_sixty_degree_case_split() {
        let (p0, p1) = (DVec2::ZERO, DVec2::new(3.0, 0.0));
        // 30°: first branch, projection exactly at 1.
        let v30 = DVec2::new(30f64.to_radians().cos(), 30f64.to_radians().sin());
        let s = CubicSegment2d::new(p0, v30, p1, v30);
        crate::assert_near!(s.points[1].x, 1.0, 1e-15);
        crate::assert_near!(s.points[2].x, 2.0, 1e-15);
        assert!(((s.points[1] - p0).length() - 1.0 / 30f64.to_radians().cos()).abs() <= 1e-15);
        // 75°: second branch, leg 2, projection 2 cos 75° < 1.
        let v75 = DVec2::new(75f64.to_radians().cos(), 75f64.to_radians().sin());
        let s = CubicSegment2d::new(p0, v75, p1, v75);
        crate::assert_near!((s.points[1] - p0).length(), 2.0, 1e-15);
        crate::assert_near!((s.points[2] - p1).length(), 2.0, 1e-15);
        assert!(s.points[1].x < s.points[2].x, "inner points crossed");
        // The two branches meet at 60°.
        crate::assert_near!(tangent_length(3.0, 0.5), 2.0, 1e-15);
        crate::assert_near!(tangent_length(3.0, 0.5 - 1e-15), 2.0, 1e-14);
    }

    /// Straight data (tangents along the chord) gives the chord parametrised uniformly.
    #[test]
    fn collinear_data_gives_the_uniform_line() {
        let (p0, p1) = (DVec2::new(1.0, 2.0), DVec2::new(4.0, 6.0));
        let v = (p1 - p0).normalize();
        let s = CubicSegment2d::new(p0, v, p1, v);
        for t in [0.0, 0.25, 0.5, 0.8, 1.0] {
            assert!(close(s.eval(t), p0.lerp(p1, t), 5.0), "t = {t}");
        }
    }

    /// Cutting a segment at t = ½ gives two cubics that trace the same points: the first
    /// half at u is the curve at u/2, the second at (1 + u)/2; their inner joint is C¹ (the
    /// derivative halves with the parameter range).
    #[test]
    fn splitting_at_one_half_reproduces_the_curve() {
        let (points, tangents) = sample_data();
        for segment in hermite_curve(&points, &tangents).expect("valid data") {
            let (left, right) = segment.split(0.5);
            for step in 0..=16 {
                let u = step as f64 / 16.0;
                assert!(
                    close(left.eval(u), segment.eval(0.5 * u), 1.0),
                    "left at {u}"
                );
                assert!(
                    close(right.eval(u), segment.eval(0.5 + 0.5 * u), 1.0),
                    "right at {u}"
                );
                assert!(close(
                    left.derivative(u),
                    0.5 * segment.derivative(0.5 * u),
                    1.0
                ));
            }
            assert_eq!(left.points[3], right.points[0], "halves meet");
            assert!(close(left.derivative(1.0), right.derivative(0.0), 1.0));
        }
    }

    /// The two constraints of [Piper87 §2] and malformed input are typed errors naming the
    /// point at fault.
    #[test]
    fn bad_data_is_a_typed_error_naming_the_point() {
        let p = [DVec2::ZERO, DVec2::X, DVec2::X];
        let v = [DVec2::Y; 3];
        match hermite_curve(&p, &v) {
            Err(Error::HermiteData { point: 2, .. }) => {}
            other => panic!("coincident points: {other:?}"),
        }
        let p = [DVec2::ZERO, DVec2::X];
        match hermite_curve(&p, &[DVec2::Y, DVec2::ZERO]) {
            Err(Error::HermiteData { point: 1, .. }) => {}
            other => panic!("zero tangent: {other:?}"),
        }
        assert!(hermite_curve(&p[..1], &[DVec2::Y]).is_err());
        assert!(hermite_curve(&p, &[DVec2::Y]).is_err());
        assert!(hermite_curve(&[DVec2::ZERO, DVec2::NAN], &[DVec2::Y; 2]).is_err());
        // Tangents of any length are normalised.
        let long = hermite_curve(&p, &[DVec2::new(2.0, 2.0), DVec2::new(5.0, -5.0)]).unwrap();
        let unit = hermite_curve(
            &p,
            &[
                DVec2::new(1.0, 1.0).normalize(),
                DVec2::new(1.0, -1.0).normalize(),
            ],
        )
        .unwrap();
        assert!(close(long[0].points[1], unit[0].points[1], 1.0));
    }
}
