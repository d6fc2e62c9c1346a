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

impl Analytic {
    /// Gaussian curvature `K` and mean curvature `H` of the surface at the point nearest to `p`
    /// (to first order: `p` projected along the level sets), `H` with respect to the outward
    /// normal, so negative on convex parts (the convention of [`crate::geom::Jet::curvature`]
    /// for outward-oriented patches).
    pub fn curvature(&self, p: DVec3) -> (f64, f64) {
        match *self {
            Analytic::Sphere { radius } => (1.0 / (radius * radius), -1.0 / radius),
            Analytic::Ellipsoid { radii } => {
                // The point scaled onto the ellipsoid; K = 1 / (a²b²c² h⁴) and
                // H = (|x|² − a² − b² − c²) / (2 a²b²c² h³), h² = Σ x_i² / a_i⁴.
                let q = p / (p / radii).length();
                let abc2 = (radii.x * radii.y * radii.z).powi(2);
                let h = (q / (radii * radii)).length();
                let k = 1.0 / (abc2 * h.powi(4));
                let mean = (q.length_squared() - radii.length_squared()) / (2.0 * abc2 * h.powi(3));
                (k, mean)
            }
            Analytic::Torus { major, minor } => {
                // Tube angle v: cos v = (ρ − R) / |(ρ − R, z)|; κ = 1/r around the tube and
                // cos v / (R + r cos v) along it.
                let rho = p.truncate().length();
                let cos_v = (rho - major) / (rho - major).hypot(p.z).max(f64::MIN_POSITIVE);
                let (k_tube, k_ring) = (1.0 / minor, cos_v / (major + minor * cos_v));
                (k_tube * k_ring, -0.5 * (k_tube + k_ring))
            }
        }
    }
}

/// Errors of the Gaussian and mean curvature of a surface against the analytic surface, each
/// relative to the largest `|K|` resp. `|H|` of the analytic surface over the samples.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CurvatureError {
    /// Largest `|K − K_true| / max |K_true|`.
    pub gaussian_max_rel: f64,
    /// Root mean square of `|K − K_true| / max |K_true|`.
    pub gaussian_rms_rel: f64,
    /// Largest `|H − H_true| / max |H_true|`.
    pub mean_max_rel: f64,
    /// Root mean square of `|H − H_true| / max |H_true|`.
    pub mean_rms_rel: f64,
}

/// Per-sample `(K − K_true, H − H_true, |K_true|, |H_true|)`: `H` taken with respect to the
/// outward analytic normal (the patch normal flipped where it points inwards).
fn curvature_difference(jet: &crate::geom::Jet, analytic: &Analytic) -> Option<[f64; 4]> {
    let k = jet.curvature()?;
    let (k_true, h_true) = analytic.curvature(jet.p);
    let outward = jet.normal().dot(analytic.normal(jet.p)) >= 0.0;
    let mean = if outward { k.mean } else { -k.mean };
    Some([
        k.gaussian - k_true,
        mean - h_true,
        k_true.abs(),
        h_true.abs(),
    ])
}

fn reduce_curvature(samples: &[[f64; 4]]) -> CurvatureError {
    let (k_scale, h_scale) = samples
        .iter()
        .fold((0.0_f64, 0.0_f64), |(a, b), s| (a.max(s[2]), b.max(s[3])));
    let count = samples.len().max(1) as f64;
    let rel = |x: f64, scale: f64| if scale > 0.0 { x / scale } else { x };
    let (mut out, mut k2, mut h2) = (CurvatureError::default(), 0.0, 0.0);
    for s in samples {
        let (dk, dh) = (rel(s[0].abs(), k_scale), rel(s[1].abs(), h_scale));
        out.gaussian_max_rel = out.gaussian_max_rel.max(dk);
        out.mean_max_rel = out.mean_max_rel.max(dh);
        k2 += dk * dk;
        h2 += dh * dh;
    }
    out.gaussian_rms_rel = (k2 / count).sqrt();
    out.mean_rms_rel = (h2 / count).sqrt();
    out
}

/// Curvature errors of `surface` against `analytic` at the quadrature points of
/// [`surface_error`] (singular samples left out).
pub fn curvature_error(surface: &Surface, analytic: &Analytic) -> CurvatureError {
    let points = split_points(6);
    let per_patch: Vec<Vec<[f64; 4]>> = surface
        .patches
        .par_iter()
        .map(|patch| {
            points
                .iter()
                .filter_map(|c| curvature_difference(&patch.jet(c.x, c.y), analytic))
                .collect()
        })
        .collect();
    reduce_curvature(&per_patch.concat())
}

/// Curvature errors of `surface` against `analytic` at the patch corners on mesh vertices,
/// and the smallest and largest `|H|` there (absolute, in the surface's units).
pub fn vertex_curvature_error(
    surface: &Surface,
    faces: &[[u32; 3]],
    analytic: &Analytic,
) -> (CurvatureError, f64, f64) {
    let corners = surface.vertex_corners(faces);
    let samples: Vec<(f64, [f64; 4])> = corners
        .par_iter()
        .filter_map(|vc| {
            let uv = crate::surface::UV_CORNERS[vc.corner as usize];
            let jet = surface.patches[vc.patch as usize].jet(uv.x, uv.y);
            let h = jet.curvature()?.mean.abs();
            Some((h, curvature_difference(&jet, analytic)?))
        })
        .collect();
    let (lo, hi) = samples
        .iter()
        .fold((f64::INFINITY, 0.0_f64), |(lo, hi), (h, _)| {
            (lo.min(*h), hi.max(*h))
        });
    let diffs: Vec<[f64; 4]> = samples.iter().map(|s| s.1).collect();
    (
        reduce_curvature(&diffs),
        if samples.is_empty() { 0.0 } else { lo },
        hi,
    )
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

    /// Curvatures at known points: the sphere, the outer and inner equator of the torus, an
    /// ellipsoid that is a sphere, and an ellipsoid's vertex (principal radii b²/a and c²/a).
    #[test]
    fn analytic_curvatures() {
        let (k, h) = Analytic::Sphere { radius: 2.0 }.curvature(DVec3::X);
        assert_eq!((k, h), (0.25, -0.5));
        let torus = Analytic::Torus {
            major: 1.0,
            minor: 0.25,
        };
        let (k, h) = torus.curvature(DVec3::new(1.25, 0.0, 0.0));
        assert!((k - 4.0 / 1.25).abs() < 1e-14 && (h + 0.5 * (4.0 + 0.8)).abs() < 1e-14);
        let (k, h) = torus.curvature(DVec3::new(0.0, 0.75, 0.0));
        assert!((k + 4.0 / 0.75).abs() < 1e-14 && (h + 0.5 * (4.0 - 4.0 / 3.0)).abs() < 1e-14);
        let round = Analytic::Ellipsoid {
            radii: DVec3::splat(2.0),
        };
        let (k, h) = round.curvature(DVec3::new(0.0, 1.2, 1.6));
        assert!((k - 0.25).abs() < 1e-15 && (h + 0.5).abs() < 1e-15);
        let (a, b, c) = (2.0, 1.0, 1.5);
        let e = Analytic::Ellipsoid {
            radii: DVec3::new(a, b, c),
        };
        let (k, h) = e.curvature(DVec3::new(a, 0.0, 0.0));
        let (k1, k2) = (a / (b * b), a / (c * c));
        assert!((k - k1 * k2).abs() < 1e-14 && (h + 0.5 * (k1 + k2)).abs() < 1e-14);
    }
}
