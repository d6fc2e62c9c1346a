//! Small geometric value types shared by every layer: axis-aligned boxes and the second-order
//! jet (position, first and second partial derivatives) of a parametric surface, with the
//! differential geometry computed from it (normal, fundamental forms, curvatures).

use glam::DVec3;

/// An axis-aligned bounding box in f64.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Smallest corner.
    pub min: DVec3,
    /// Largest corner.
    pub max: DVec3,
}

impl Aabb {
    /// The empty box (union identity).
    pub const EMPTY: Aabb = Aabb {
        min: DVec3::INFINITY,
        max: DVec3::NEG_INFINITY,
    };

    /// The smallest box containing all `points`.
    pub fn from_points<'a>(points: impl IntoIterator<Item = &'a DVec3>) -> Aabb {
        points
            .into_iter()
            .fold(Aabb::EMPTY, |b, p| b.union_point(*p))
    }

    /// This box grown to contain `p`.
    pub fn union_point(self, p: DVec3) -> Aabb {
        Aabb {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    /// The smallest box containing both.
    pub fn union(self, other: Aabb) -> Aabb {
        Aabb {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// True when the box contains no point.
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x || self.min.y > self.max.y || self.min.z > self.max.z
    }

    /// Length of the diagonal (0 for an empty box).
    pub fn diagonal(&self) -> f64 {
        if self.is_empty() {
            0.0
        } else {
            (self.max - self.min).length()
        }
    }

    /// Centre of the box.
    pub fn center(&self) -> DVec3 {
        0.5 * (self.min + self.max)
    }

    /// True when `p` lies in the box grown by `tol` on every side.
    pub fn contains(&self, p: DVec3, tol: f64) -> bool {
        p.cmpge(self.min - DVec3::splat(tol)).all() && p.cmple(self.max + DVec3::splat(tol)).all()
    }
}

/// Position and partial derivatives up to order two of a surface `S(u, v)` at one parameter
/// point. Every patch kind produces one; metrics and shading read only this.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Jet {
    /// `S`
    pub p: DVec3,
    /// `∂S/∂u`
    pub du: DVec3,
    /// `∂S/∂v`
    pub dv: DVec3,
    /// `∂²S/∂u²`
    pub duu: DVec3,
    /// `∂²S/∂u∂v`
    pub duv: DVec3,
    /// `∂²S/∂v²`
    pub dvv: DVec3,
}

/// Curvatures of a surface at a point (with respect to [`Jet::normal`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Curvature {
    /// Gaussian curvature K = κ1 κ2.
    pub gaussian: f64,
    /// Mean curvature H = (κ1 + κ2) / 2.
    pub mean: f64,
    /// Larger principal curvature.
    pub k1: f64,
    /// Smaller principal curvature.
    pub k2: f64,
}

impl Jet {
    /// `∂S/∂u × ∂S/∂v` (not normalised; its length is the area element).
    pub fn cross(&self) -> DVec3 {
        self.du.cross(self.dv)
    }

    /// Unit normal `Su × Sv / |Su × Sv|` (zero where the parametrisation is singular).
    pub fn normal(&self) -> DVec3 {
        self.cross().normalize_or_zero()
    }

    /// Gaussian, mean and principal curvatures from the first and second fundamental forms.
    /// Returns `None` where the parametrisation is singular (`|Su × Sv| = 0`).
    pub fn curvature(&self) -> Option<Curvature> {
        let n = self.cross();
        let len = n.length();
        if len.is_nan() || len <= 0.0 || !len.is_finite() {
            return None;
        }
        let n = n / len;
        let (e, f, g) = (
            self.du.dot(self.du),
            self.du.dot(self.dv),
            self.dv.dot(self.dv),
        );
        let (l, m, nn) = (self.duu.dot(n), self.duv.dot(n), self.dvv.dot(n));
        let det1 = e * g - f * f;
        if det1.is_nan() || det1 <= 0.0 {
            return None;
        }
        let gaussian = (l * nn - m * m) / det1;
        let mean = (e * nn - 2.0 * f * m + g * l) / (2.0 * det1);
        let disc = (mean * mean - gaussian).max(0.0).sqrt();
        Some(Curvature {
            gaussian,
            mean,
            k1: mean + disc,
            k2: mean - disc,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Sphere of radius r parametrised by longitude/latitude: K = 1/r², |H| = 1/r.
    #[test]
    fn sphere_curvature_is_exact() {
        let r = 2.5;
        let (u, v) = (0.3_f64, 0.7_f64);
        let p = |u: f64, v: f64| DVec3::new(v.cos() * u.cos(), v.cos() * u.sin(), v.sin()) * r;
        let jet = Jet {
            p: p(u, v),
            du: DVec3::new(-v.cos() * u.sin(), v.cos() * u.cos(), 0.0) * r,
            dv: DVec3::new(-v.sin() * u.cos(), -v.sin() * u.sin(), v.cos()) * r,
            duu: DVec3::new(-v.cos() * u.cos(), -v.cos() * u.sin(), 0.0) * r,
            duv: DVec3::new(v.sin() * u.sin(), -v.sin() * u.cos(), 0.0) * r,
            dvv: DVec3::new(-v.cos() * u.cos(), -v.cos() * u.sin(), -v.sin()) * r,
        };
        let c = jet.curvature().expect("regular point");
        assert!(
            (c.gaussian - 1.0 / (r * r)).abs() < 1e-14,
            "K = {}",
            c.gaussian
        );
        assert!((c.mean.abs() - 1.0 / r).abs() < 1e-14, "H = {}", c.mean);
        assert!((c.k1 - c.k2).abs() < 1e-7, "umbilic: {} {}", c.k1, c.k2);
    }

    #[test]
    fn aabb_union_and_diagonal() {
        let b = Aabb::from_points(&[DVec3::ZERO, DVec3::new(3.0, 4.0, 0.0)]);
        assert_eq!(b.diagonal(), 5.0);
        assert!(Aabb::EMPTY.is_empty());
        assert_eq!(Aabb::EMPTY.union(b), b);
        assert!(b.contains(DVec3::new(1.0, 1.0, 0.0), 0.0));
        assert!(!b.contains(DVec3::new(1.0, 1.0, 0.1), 0.0));
    }
}
