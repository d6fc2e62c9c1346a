//! Analytic reference surfaces of the benchmark meshes (sphere, ellipsoid, torus) and the
//! distance and normal errors of a built surface against them.

use glam::DVec3;
use rayon::prelude::*;

use crate::metrics::energy::split_points;
use crate::surface::Surface;

/// An analytic surface a benchmark mesh was sampled from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Analytic {
    /// Sphere of the given radius about the origin.
    Sphere {
        /// Radius.
        radius: f64,
    },
    /// Ellipsoid `Σ (x_i / a_i)² = 1`.
    Ellipsoid {
        /// Semi-axes (a, b, c).
        radii: DVec3,
    },
    /// Torus about the z axis.
    Torus {
        /// Distance of the tube centre from the axis.
        major: f64,
        /// Tube radius.
        minor: f64,
    },
}

impl Analytic {
    /// Distance of `p` from the surface: exact for the sphere and torus, first-order
    /// `|F| / |∇F|` for the ellipsoid (accurate to second order near the surface).
    pub fn distance(&self, p: DVec3) -> f64 {
        match *self {
            Analytic::Sphere { radius } => (p.length() - radius).abs(),
            Analytic::Ellipsoid { radii } => {
                let q = p / radii;
                let gradient = 2.0 * q / radii;
                (q.length_squared() - 1.0).abs() / gradient.length()
            }
            Analytic::Torus { major, minor } => {
                let rho = p.truncate().length();
                ((rho - major).hypot(p.z) - minor).abs()
            }
        }
    }

    /// Unit outward normal of the level set through `p` (the surface normal at the nearest point,
    /// to first order).
    pub fn normal(&self, p: DVec3) -> DVec3 {
        match *self {
            Analytic::Sphere { .. } => p.normalize_or_zero(),
            Analytic::Ellipsoid { radii } => (p / (radii * radii)).normalize_or_zero(),
            Analytic::Torus { major, .. } => {
                let rho = p.truncate().length();
                let centre = if rho > 0.0 {
                    DVec3::new(p.x / rho * major, p.y / rho * major, 0.0)
                } else {
                    DVec3::ZERO
                };
                (p - centre).normalize_or_zero()
            }
        }
    }
}

/// Largest and mean distance (absolute) and largest normal angle (rad) of `surface` from the
/// analytic surface, sampled at the degree-2 quadrature points of a 6² split of every patch.
pub fn surface_error(surface: &Surface, analytic: &Analytic) -> (f64, f64, f64) {
    let points = split_points(6);
    let per_patch: Vec<(f64, f64, f64)> = surface
        .patches
        .par_iter()
        .map(|patch| {
            let (mut max_d, mut sum_d, mut max_angle) = (0.0_f64, 0.0, 0.0_f64);
            for c in &points {
                let jet = patch.jet(c.x, c.y);
                let d = analytic.distance(jet.p);
                max_d = max_d.max(d);
                sum_d += d;
                let (n, m) = (jet.normal(), analytic.normal(jet.p));
                max_angle = max_angle.max(n.cross(m).length().atan2(n.dot(m)));
            }
            (max_d, sum_d, max_angle)
        })
        .collect();
    let samples = (points.len() * surface.patches.len()).max(1) as f64;
    per_patch
        .iter()
        .fold((0.0, 0.0, 0.0), |(a, b, c), (d, s, n)| {
            (a.max(*d), b + s / samples, c.max(*n))
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances_and_normals_of_points_on_and_off_the_surfaces() {
        let sphere = Analytic::Sphere { radius: 2.0 };
        assert!((sphere.distance(DVec3::new(0.0, 3.0, 0.0)) - 1.0).abs() < 1e-15);
        let torus = Analytic::Torus {
            major: 1.0,
            minor: 0.3,
        };
        let on = DVec3::new(1.3, 0.0, 0.0);
        assert!(torus.distance(on) < 1e-15);
        assert!((torus.normal(on) - DVec3::X).length() < 1e-15);
        assert!((torus.distance(DVec3::new(0.0, 1.0, 0.5)) - 0.2).abs() < 1e-15);
        let ellipsoid = Analytic::Ellipsoid {
            radii: DVec3::new(1.0, 0.8, 1.3),
        };
        assert!(ellipsoid.distance(DVec3::new(0.0, 0.0, 1.3)) < 1e-15);
        // Off the ellipsoid along an axis the first-order distance is close to the true one.
        assert!((ellipsoid.distance(DVec3::new(1.01, 0.0, 0.0)) - 0.01).abs() < 1e-4);
    }
}
