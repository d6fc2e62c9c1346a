//! Rays in f64 and the two-plane form of the Newton system that the intersection code uses.

use glam::{DVec2, DVec3};

/// A ray in f64. `dir` has unit length, so `t` is a distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray64 {
    /// Start point.
    pub origin: DVec3,
    /// Unit direction.
    pub dir: DVec3,
}

impl Ray64 {
    /// A ray from `origin` along `dir` (normalised here).
    pub fn new(origin: DVec3, dir: DVec3) -> Ray64 {
        Ray64 {
            origin,
            dir: dir.normalize(),
        }
    }

    /// The point at distance `t`.
    pub fn at(&self, t: f64) -> DVec3 {
        self.origin + self.dir * t
    }
}

/// The ray as two planes through it, for the 2×2 Newton system.
#[derive(Clone, Copy, Debug)]
pub struct RayPlanes {
    n1: DVec3,
    n2: DVec3,
    d1: f64,
    d2: f64,
}

impl RayPlanes {
    /// The planes of `ray` (normals orthonormal and perpendicular to the direction).
    pub fn new(ray: &Ray64) -> RayPlanes {
        let (n1, n2) = ray.dir.any_orthonormal_pair();
        RayPlanes {
            n1,
            n2,
            d1: n1.dot(ray.origin),
            d2: n2.dot(ray.origin),
        }
    }

    /// Signed distances of `p` from the two planes (zero on the ray's line).
    pub fn residual(&self, p: DVec3) -> DVec2 {
        DVec2::new(self.n1.dot(p) - self.d1, self.n2.dot(p) - self.d2)
    }

    /// The Newton step `Δ` of the two-plane system at residual `f` with surface tangents
    /// `su`, `sv`: the solution of `[project(su) project(sv)] Δ = f` by Cramer's rule, or None
    /// when that Jacobian is singular or not finite. The next iterate is `(u, v) − Δ`.
    #[inline]
    pub fn newton_step(&self, f: DVec2, su: DVec3, sv: DVec3) -> Option<DVec2> {
        let (ju, jv) = (self.project(su), self.project(sv));
        let det = ju.perp_dot(jv);
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        Some(DVec2::new(f.perp_dot(jv), ju.perp_dot(f)) / det)
    }

    /// A tangent vector in plane coordinates.
    pub fn project(&self, v: DVec3) -> DVec2 {
        DVec2::new(self.n1.dot(v), self.n2.dot(v))
    }
}
