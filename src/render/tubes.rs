//! Thin tubes around polylines, ray-traced together with the surface (or alone): the curve
//! network overlay of [HB00 Figs. 2 and 14].
//!
//! A tube is the set of points within `radius` of a polyline, i.e. the union of one capsule
//! (cylinder plus two end spheres) per segment. Rays are intersected by a two-level brute
//! force: segments are grouped in runs of [`CHUNK`] consecutive segments of one polyline, each
//! run with a box padded by the radius; a ray tests the run boxes (slab test) and only the
//! capsules of the boxes it crosses. A network has a few hundred runs, so this costs far less
//! than the patch BVH and needs no second acceleration structure. The union's first hit is the
//! smallest entry distance over its capsules; a capsule's is the smallest of its cylinder body
//! (axial parameter inside the segment) and its two spheres.

use glam::DVec3;

use crate::geom::Aabb;
use crate::render::intersect::Ray64;

/// What a polyline shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CurveKind {
    /// A boundary curve sampled densely.
    Network,
    /// A Bézier control polygon.
    ControlPolygon,
}

/// A polyline of the overlay.
#[derive(Clone, Debug, PartialEq)]
pub struct Polyline {
    /// Which mesh edge it belongs to (index into [`crate::mesh::Mesh::edges`]).
    pub edge: usize,
    /// Network curve or control polygon.
    pub kind: CurveKind,
    /// Its points, in order.
    pub points: Vec<DVec3>,
}

/// Segments per run (one box test guards this many capsule tests).
pub(crate) const CHUNK: usize = 8;

/// Linear RGB of network curves (blue) and control polygons (red), as in [HB00 Fig. 14].
pub(crate) const NETWORK_COLOUR: DVec3 = DVec3::new(0.02, 0.10, 0.85);
/// Linear RGB of control polygons.
pub(crate) const POLYGON_COLOUR: DVec3 = DVec3::new(0.85, 0.03, 0.02);

/// One segment of a tube.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Segment {
    a: DVec3,
    b: DVec3,
    kind: CurveKind,
}

/// A run of consecutive segments with its padded box.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Run {
    bounds: Aabb,
    start: u32,
    end: u32,
}

/// The first hit of a ray on the tubes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TubeHit {
    /// Distance along the ray.
    pub t: f64,
    /// Unit outward normal of the tube there.
    pub normal: DVec3,
    /// What the tube shows.
    pub kind: CurveKind,
}

/// Tubes of one radius around a set of polylines.
#[derive(Clone, Debug, PartialEq)]
pub struct Tubes {
    radius: f64,
    segments: Vec<Segment>,
    runs: Vec<Run>,
}

impl Tubes {
    /// Tubes of radius `radius` (> 0) around `polylines`.
    pub fn new(polylines: &[Polyline], radius: f64) -> crate::Result<Tubes> {
        if !(radius > 0.0 && radius.is_finite()) {
            let text = format!("{radius} must be a positive number");
            return Err(crate::Error::config(
                "tube radius",
                crate::Problem::Other { text },
            ));
        }
        let mut segments = Vec::new();
        let mut runs = Vec::new();
        for line in polylines {
            for chunk in line.points.windows(2).collect::<Vec<_>>().chunks(CHUNK) {
                let start = segments.len() as u32;
                let mut bounds = Aabb::EMPTY;
                for pair in chunk {
                    segments.push(Segment {
                        a: pair[0],
                        b: pair[1],
                        kind: line.kind,
                    });
                    bounds = bounds.union_point(pair[0]).union_point(pair[1]);
                }
                let pad = DVec3::splat(radius);
                bounds.min -= pad;
                bounds.max += pad;
                runs.push(Run {
                    bounds,
                    start,
                    end: segments.len() as u32,
                });
            }
        }
        Ok(Tubes {
            radius,
            segments,
            runs,
        })
    }

    /// Number of segments.
    pub fn segment_count(&self) -> usize {
        self.segments.len()
    }

    /// The tube radius.
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// The closest hit with `t ∈ (0, t_max)`.
    pub fn closest_hit(&self, ray: &Ray64, t_max: f64) -> Option<TubeHit> {
        let inv = DVec3::ONE / ray.dir;
        let mut best: Option<TubeHit> = None;
        let mut limit = t_max;
        for run in &self.runs {
            if !slab_hit(&run.bounds, ray.origin, inv, limit) {
                continue;
            }
            for s in &self.segments[run.start as usize..run.end as usize] {
                if let Some((t, normal)) = capsule_hit(ray, s.a, s.b, self.radius, limit) {
                    limit = t;
                    best = Some(TubeHit {
                        t,
                        normal,
                        kind: s.kind,
                    });
                }
            }
        }
        best
    }

    /// Linear RGB of a tube hit: the curve's colour, lit from the eye so tubes read as round.
    pub fn shade(&self, hit: &TubeHit, ray: &Ray64) -> DVec3 {
        let base = match hit.kind {
            CurveKind::Network => NETWORK_COLOUR,
            CurveKind::ControlPolygon => POLYGON_COLOUR,
        };
        let facing = hit.normal.dot(-ray.dir).max(0.0);
        base * (0.3 + 0.7 * facing) + DVec3::splat(0.25 * facing.powi(24))
    }
}

/// True if the ray enters `bounds` before `t_max` (and after 0).
fn slab_hit(bounds: &Aabb, origin: DVec3, inv: DVec3, t_max: f64) -> bool {
    let t0 = (bounds.min - origin) * inv;
    let t1 = (bounds.max - origin) * inv;
    let near = t0.min(t1).max_element().max(0.0);
    let far = t0.max(t1).min_element().min(t_max);
    // NaN (a ray in a box face plane) is incomparable: treat as a hit to stay conservative.
    near.partial_cmp(&far) != Some(std::cmp::Ordering::Greater)
}

/// Entry distance and normal of the ray on the capsule of radius `r` around segment `a b`, if
/// it lies in `(0, t_max)`.
fn capsule_hit(ray: &Ray64, a: DVec3, b: DVec3, r: f64, t_max: f64) -> Option<(f64, DVec3)> {
    let mut best: Option<(f64, DVec3)> = None;
    let mut consider = |t: f64, centre: DVec3| {
        if t > 0.0 && t < best.map_or(t_max, |b| b.0) {
            let normal = (ray.at(t) - centre).normalize_or_zero();
            best = Some((t, normal));
        }
    };
    let axis = b - a;
    let length = axis.length();
    if length > 0.0 {
        // Cylinder body: the ray's component perpendicular to the axis reaches distance r.
        let w = axis / length;
        let o = ray.origin - a;
        let d_perp = ray.dir - w * ray.dir.dot(w);
        let o_perp = o - w * o.dot(w);
        let qa = d_perp.length_squared();
        let qb = d_perp.dot(o_perp);
        let qc = o_perp.length_squared() - r * r;
        let disc = qb * qb - qa * qc;
        if qa > 0.0 && disc >= 0.0 {
            let t = (-qb - disc.sqrt()) / qa;
            let s = (o + ray.dir * t).dot(w);
            if (0.0..=length).contains(&s) {
                consider(t, a + w * s);
            }
        }
    }
    for centre in [a, b] {
        // Sphere: |o + t d − c|² = r² with |d| = 1.
        let o = ray.origin - centre;
        let qb = o.dot(ray.dir);
        let disc = qb * qb - (o.length_squared() - r * r);
        if disc >= 0.0 {
            consider(-qb - disc.sqrt(), centre);
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::test_support::assert_config_error;

    #[test]
    fn a_radius_that_is_not_positive_is_a_config_error() {
        for radius in [0.0, -1.0, f64::NAN] {
            let Err(err) = Tubes::new(&[], radius) else {
                panic!("radius {radius} accepted");
            };
            assert_config_error(
                &err,
                "tube radius",
                |p| matches!(p, crate::Problem::Other { .. }),
                format!("tube radius {radius} must be a positive number"),
            );
        }
    }

    fn line(points: Vec<DVec3>) -> Polyline {
        Polyline {
            edge: 0,
            kind: CurveKind::Network,
            points,
        }
    }

    /// Distance from `p` to segment `a b`.
    fn segment_distance(p: DVec3, a: DVec3, b: DVec3) -> f64 {
        let ab = b - a;
        let s = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
        (p - (a + ab * s)).length()
    }

    #[test]
    fn hits_lie_on_the_tube_surface_and_nothing_is_closer() {
        let points: Vec<DVec3> = (0..=40)
            .map(|i| {
                let t = f64::from(i) / 40.0 * 6.0;
                DVec3::new(t.cos(), t.sin(), 0.2 * t)
            })
            .collect();
        let r = 0.05;
        let tubes = Tubes::new(&[line(points.clone())], r).expect("tubes");
        assert_eq!(tubes.segment_count(), 40);
        let distance = |p: DVec3| {
            points
                .windows(2)
                .map(|w| segment_distance(p, w[0], w[1]))
                .fold(f64::INFINITY, f64::min)
        };
        let mut hits = 0;
        for i in 0..60 {
            for j in 0..60 {
                let target = DVec3::new(
                    -1.2 + 2.4 * f64::from(i) / 59.0,
                    -1.2 + 2.4 * f64::from(j) / 59.0,
                    0.6,
                );
                let ray = Ray64::new(
                    DVec3::new(0.3, -0.2, 5.0),
                    target - DVec3::new(0.3, -0.2, 5.0),
                );
                match tubes.closest_hit(&ray, f64::INFINITY) {
                    Some(hit) => {
                        hits += 1;
                        let p = ray.at(hit.t);
                        assert!(
                            (distance(p) - r).abs() <= 1e-12,
                            "off the tube: {}",
                            distance(p)
                        );
                        assert!((hit.normal.length() - 1.0).abs() < 1e-12);
                        assert!(hit.normal.dot(ray.dir) <= 1e-12, "normal faces the ray");
                        // No point of the ray before the hit is inside the tube.
                        for k in 1..200 {
                            let q = ray.at(hit.t * f64::from(k) / 200.0);
                            assert!(distance(q) >= r - 1e-12, "entered earlier");
                        }
                    }
                    None => {
                        // A miss: the ray's closest approach (sampled) stays outside.
                        for k in 0..400 {
                            let q = ray.at(8.0 * f64::from(k) / 400.0);
                            assert!(distance(q) > r - 1e-3, "missed a tube point");
                        }
                    }
                }
            }
        }
        assert!(hits > 100 && hits < 3000, "{hits} hits");
    }

    #[test]
    fn the_surface_in_front_hides_the_tube_and_bad_radii_are_refused() {
        let tubes = Tubes::new(&[line(vec![DVec3::ZERO, DVec3::X])], 0.1).expect("tubes");
        let ray = Ray64::new(DVec3::new(0.5, 0.0, 3.0), -DVec3::Z);
        let hit = tubes.closest_hit(&ray, f64::INFINITY).expect("hit");
        assert!((hit.t - 2.9).abs() < 1e-12);
        assert!(tubes.closest_hit(&ray, 2.5).is_none());
        // End caps are round: a ray just past the end still hits the sphere.
        let cap = Ray64::new(DVec3::new(1.05, 0.0, 3.0), -DVec3::Z);
        let t = tubes.closest_hit(&cap, f64::INFINITY).expect("cap").t;
        assert!((t - (3.0 - (0.01f64 - 0.0025).sqrt())).abs() < 1e-12);
        assert!(Tubes::new(&[], 0.0).is_err());
        assert!(Tubes::new(&[], f64::NAN).is_err());
    }
}
