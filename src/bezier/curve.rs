//! Bézier curves of any degree: de Casteljau evaluation, derivative (hodograph), splitting,
//! degree elevation, control bounds.

use glam::DVec3;

use crate::geom::Aabb;

/// A Bézier curve `C(t) = Σ p_i B_i^d(t)`, `t ∈ [0, 1]`.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveBezier {
    points: Vec<DVec3>,
}

impl CurveBezier {
    /// A curve from its control points (at least one).
    pub fn new(points: Vec<DVec3>) -> Self {
        todo!()
    }
    /// Degree (number of control points − 1).
    pub fn degree(&self) -> usize {
        self.points.len() - 1
    }
    /// Control points.
    pub fn points(&self) -> &[DVec3] {
        &self.points
    }
    /// Point at `t` (de Casteljau).
    pub fn eval(&self, t: f64) -> DVec3 {
        todo!()
    }
    /// The derivative curve (degree d−1; a single zero point for d = 0).
    pub fn derivative(&self) -> CurveBezier {
        todo!()
    }
    /// The two halves at `t`.
    pub fn split(&self, t: f64) -> (CurveBezier, CurveBezier) {
        todo!()
    }
    /// The same curve with degree d+1.
    pub fn elevate(&self) -> CurveBezier {
        todo!()
    }
    /// Bounding box of the control points.
    pub fn control_bounds(&self) -> Aabb {
        Aabb::from_points(&self.points)
    }
}
