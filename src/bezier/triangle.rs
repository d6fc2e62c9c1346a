//! Triangular Bézier patches of any degree: de Casteljau evaluation, blossom, derivatives,
//! subdivision over an arbitrary sub-triangle, degree elevation, edge curves, control-net bounds.

use glam::DVec3;

use crate::bezier::CurveBezier;
use crate::geom::{Aabb, Jet};

/// Number of control points of a triangular patch of degree `d`: (d+1)(d+2)/2.
pub const fn point_count(degree: usize) -> usize {
    (degree + 1) * (degree + 2) / 2
}

/// Position of `b(i,j,k)` in the point list of a degree-`d` patch (`i+j+k = d`).
pub const fn index(degree: usize, i: usize, j: usize) -> usize {
    todo!()
}

/// A triangular Bézier patch `B(w0,w1,w2) = Σ b(i,j,k) d!/(i!j!k!) w0^i w1^j w2^k`.
#[derive(Clone, Debug, PartialEq)]
pub struct TriangleBezier {
    degree: usize,
    points: Vec<DVec3>,
}

impl TriangleBezier {
    /// A patch from its control points in the module's order. Panics if the count is wrong.
    pub fn new(degree: usize, points: Vec<DVec3>) -> Self {
        todo!()
    }
    /// A patch whose point `b(i,j,k)` is `f(i, j, k)`.
    pub fn from_fn(degree: usize, f: impl FnMut(usize, usize, usize) -> DVec3) -> Self {
        todo!()
    }
    /// Polynomial degree.
    pub fn degree(&self) -> usize {
        self.degree
    }
    /// Control points in the module's order.
    pub fn points(&self) -> &[DVec3] {
        &self.points
    }
    /// Control point `b(i,j,k)` (k = d − i − j).
    pub fn point(&self, i: usize, j: usize) -> DVec3 {
        todo!()
    }
    /// Sets control point `b(i,j,k)`.
    pub fn set_point(&mut self, i: usize, j: usize, p: DVec3) {
        todo!()
    }
    /// Point at barycentric coordinates `bary` (need not sum to one for blossoms; here it should).
    pub fn eval(&self, bary: DVec3) -> DVec3 {
        todo!()
    }
    /// Position and first/second derivatives with respect to `(u, v)`, barycentric `(1−u−v, u, v)`.
    /// Allocation-free for degree ≤ 8.
    pub fn jet(&self, u: f64, v: f64) -> Jet {
        todo!()
    }
    /// The blossom (polar form) at `d` barycentric arguments.
    pub fn blossom(&self, args: &[DVec3]) -> DVec3 {
        todo!()
    }
    /// The same surface over the sub-triangle with barycentric corners `corners` (each a
    /// barycentric point of this patch's domain): the result's corner `b(d,0,0)` is at
    /// `corners[0]`, `b(0,d,0)` at `corners[1]`, `b(0,0,d)` at `corners[2]`.
    pub fn subdivide(&self, corners: [DVec3; 3]) -> TriangleBezier {
        todo!()
    }
    /// The same surface as a patch of degree d+1.
    pub fn elevate(&self) -> TriangleBezier {
        todo!()
    }
    /// Boundary curve `edge` (0: corner 0 → corner 1, where k = 0; 1: corner 1 → corner 2,
    /// where i = 0; 2: corner 2 → corner 0, where j = 0).
    pub fn edge_curve(&self, edge: usize) -> CurveBezier {
        todo!()
    }
    /// Bounding box of the control points (contains the patch: convex-hull property).
    pub fn control_bounds(&self) -> Aabb {
        Aabb::from_points(&self.points)
    }
    /// The patch with every control point mapped by `f` (exact for affine maps).
    pub fn map_points(&self, f: impl Fn(DVec3) -> DVec3) -> TriangleBezier {
        TriangleBezier {
            degree: self.degree,
            points: self.points.iter().map(|&p| f(p)).collect(),
        }
    }
}
