//! Anti-aliased stripes. The stripe modes (zebra, highlight lines, isophotes) are a periodic
//! square wave of a *phase* that depends on the hit point, its normal and the view direction.
//! Near a pole of the phase (where all stripes meet) or on a strongly curved part the phase
//! changes by more than one period within a pixel, and point samples alias into moiré however
//! many there are. Here the square wave is box-filtered analytically over the phase interval
//! that one sample's screen cell covers: the first-order change of point, normal and view
//! across the cell (ray differentials transferred to the tangent plane and through the
//! Weingarten map, as pbrt does for specular reflection) gives the phase's screen-space
//! derivative, and the integral of the square wave over that interval is closed-form. Stripes
//! stay crisp where they are wide on screen and fade to their mean where they are not.

use glam::DVec3;
use rayon::prelude::*;

use crate::render::interaction::ShadingPoint;
use crate::render::intersect::{IntersectCounters, Ray64};
use crate::render::modes::Setup;
use crate::render::trace::SurfaceTracer;

/// The first-order change of the shading inputs across one sample cell on screen, along the
/// image's x and y directions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Footprint {
    /// Change of the hit point.
    pub dp: [DVec3; 2],
    /// Change of the facing normal (tangent to the surface).
    pub dn: [DVec3; 2],
    /// Change of the unit ray direction.
    pub dv: [DVec3; 2],
}

impl Footprint {
    /// The footprint of the hit `sp` of ray `ray`, from the rays `offsets` one sample cell to
    /// the right and one down: each offset ray meets the tangent plane at the hit; the change
    /// of point is solved for a change of `(u, v)`, which moves the normal through the
    /// derivatives of `Su × Sv`. None at grazing angles or singular points, where no
    /// first-order footprint exists.
    pub fn new(sp: &ShadingPoint, ray: &Ray64, offsets: [&Ray64; 2]) -> Option<Footprint> {
        let jet = &sp.jet;
        let n = sp.facing_normal;
        let m = jet.du.cross(jet.dv);
        let len = m.length();
        let (e, f, g) = (jet.du.dot(jet.du), jet.du.dot(jet.dv), jet.dv.dot(jet.dv));
        let det = e * g - f * f;
        if !(len > 0.0 && det > 0.0 && len.is_finite() && det.is_finite()) {
            return None;
        }
        let n0 = m / len;
        let sign = if n0.dot(n) < 0.0 { -1.0 } else { 1.0 };
        // Derivatives of the unit normal: (m' − n (n·m')) / |m|.
        let unit_derivative = |dm: DVec3| sign * (dm - n0 * n0.dot(dm)) / len;
        let n_u = unit_derivative(jet.duu.cross(jet.dv) + jet.du.cross(jet.duv));
        let n_v = unit_derivative(jet.duv.cross(jet.dv) + jet.du.cross(jet.dvv));
        let mut out = Footprint {
            dp: [DVec3::ZERO; 2],
            dn: [DVec3::ZERO; 2],
            dv: [DVec3::ZERO; 2],
        };
        for (k, other) in offsets.into_iter().enumerate() {
            let denom = other.dir.dot(n);
            if denom.abs() < 1e-9 {
                return None;
            }
            let t = (jet.p - other.origin).dot(n) / denom;
            let dp = other.origin + other.dir * t - jet.p;
            let (a, b) = (jet.du.dot(dp), jet.dv.dot(dp));
            let du = (g * a - f * b) / det;
            let dv = (e * b - f * a) / det;
            out.dp[k] = dp;
            out.dn[k] = n_u * du + n_v * dv;
            out.dv[k] = other.dir - ray.dir;
        }
        let finite = out
            .dp
            .iter()
            .chain(&out.dn)
            .chain(&out.dv)
            .all(|d| d.is_finite());
        finite.then_some(out)
    }

    /// The width (in periods) of the phase interval the cell covers: `|∂φ/∂x| + |∂φ/∂y|`,
    /// the phase `phase(point, unit normal, unit view)` differentiated by central differences
    /// along the footprint. Whole periods between the two ends are invisible in a square wave,
    /// so each difference is taken modulo one period.
    pub fn phase_width(
        &self,
        sp: &ShadingPoint,
        phase: impl Fn(DVec3, DVec3, DVec3) -> f64,
    ) -> f64 {
        const H: f64 = 1e-4;
        let (p, n, v) = (sp.jet.p, sp.facing_normal, sp.view);
        let mut width = 0.0;
        for k in 0..2 {
            let at = |s: f64| {
                phase(
                    p + self.dp[k] * s,
                    (n + self.dn[k] * s).normalize_or(n),
                    (v + self.dv[k] * s).normalize_or(v),
                )
            };
            let diff = at(H) - at(-H);
            let diff = diff - diff.round();
            width += (diff / (2.0 * H)).abs();
        }
        if width.is_finite() { width } else { 1.0 }
    }
}

/// The largest phase magnitude (in periods) at which f64 still places a stripe edge to
/// 1/256 of a period: 2^52 / 256. Beyond it the rounding of the phase alone moves the edges by
/// a visible fraction of a period, so where a stripe is cannot be known and
/// [`filtered_square_wave`] gives the mean.
pub const MAX_RESOLVED_PHASE: f64 = 4_503_599_627_370_496.0 / 256.0;

/// The bright fraction of the square wave `fract(t) < duty` averaged over
/// `[phase − width/2, phase + width/2]` (a box filter; `width = 0` is the point sample).
/// The mean `duty` where the phase is not finite or beyond [`MAX_RESOLVED_PHASE`] (a stripe
/// count so high that the arithmetic cannot place its stripes) and where the interval covers
/// a million periods or more.
pub fn filtered_square_wave(phase: f64, width: f64, duty: f64) -> f64 {
    let duty = duty.clamp(0.0, 1.0);
    if !phase.is_finite() || phase.abs() > MAX_RESOLVED_PHASE {
        return duty;
    }
    if width.is_nan() || width <= 1e-12 {
        return if super::fract(phase) < duty { 1.0 } else { 0.0 };
    }
    if width >= 1.0e6 {
        return duty;
    }
    // The integral of the indicator from 0 to t.
    let integral = |t: f64| t.floor() * duty + super::fract(t).min(duty);
    let half = 0.5 * width;
    ((integral(phase + half) - integral(phase - half)) / width).clamp(0.0, 1.0)
}

/// The narrowest stripe period, in pixels, that an automatic stripe count allows on the
/// median pixel of the surface: a bright and a dark stripe of 6 pixels each. Narrower
/// stripes are filtered to their mean grey (see [`filtered_square_wave`]), which on a
/// detailed scan seen small turns the whole surface into noise.
pub const READABLE_PERIOD_PX: f64 = 12.0;

/// The fewest stripes per turn an automatic stripe count goes down to.
pub const MIN_AUTO_STRIPES: f64 = 4.0;

/// Side of the grid of pixel centres (at most this many each way) through which
/// [`readable_stripes`] looks at the surface.
const PROBE_GRID: u32 = 64;

/// The stripe count of a view: `most` where the stripes at `most` per turn are at least
/// [`READABLE_PERIOD_PX`] wide on the median surface pixel, otherwise the largest whole count
/// that makes them so, but never below [`MIN_AUTO_STRIPES`] (nor above `most`).
///
/// `turns(n, v)` is the mode's phase at one stripe per turn for the unit normal `n` seen along
/// the unit view `v`. Its change across one pixel of the `setup.width` × `setup.height` image
/// is measured as the stripe filter measures it ([`Footprint::phase_width`]), at the centres
/// of a grid of at most 64 × 64 pixels that hit the surface. Deterministic: the same count for
/// any thread count.
pub fn readable_stripes<T: SurfaceTracer>(
    setup: &Setup<'_, T>,
    most: f64,
    turns: impl Fn(DVec3, DVec3) -> f64 + Sync,
) -> f64 {
    let mut rates = phase_rates(setup, &turns);
    if rates.is_empty() {
        return most;
    }
    let mid = rates.len() / 2;
    let (_, median, _) = rates.select_nth_unstable_by(mid, f64::total_cmp);
    let median = *median;
    if !(median > 0.0 && median.is_finite()) || most * median * READABLE_PERIOD_PX <= 1.0 {
        return most;
    }
    (1.0 / (READABLE_PERIOD_PX * median))
        .floor()
        .clamp(MIN_AUTO_STRIPES.min(most), most)
}

/// The phase change per pixel (in turns, at one stripe per turn) at the grid's pixel centres
/// that hit the surface and have a footprint, row by row.
fn phase_rates<T: SurfaceTracer>(
    setup: &Setup<'_, T>,
    turns: &(impl Fn(DVec3, DVec3) -> f64 + Sync),
) -> Vec<f64> {
    let (tracer, camera) = (setup.tracer, setup.camera);
    let (w, h) = (f64::from(setup.width), f64::from(setup.height));
    let (gw, gh) = (setup.width.min(PROBE_GRID), setup.height.min(PROBE_GRID));
    let aspect = w / h;
    let ndc = |px: f64, py: f64| (2.0 * px / w - 1.0, 1.0 - 2.0 * py / h);
    let rows: Vec<Vec<f64>> = (0..gh)
        .into_par_iter()
        .map(|j| {
            let mut counters = IntersectCounters::default();
            let mut row = Vec::new();
            let py = ((f64::from(j) + 0.5) * h / f64::from(gh)).floor() + 0.5;
            for i in 0..gw {
                let px = ((f64::from(i) + 0.5) * w / f64::from(gw)).floor() + 0.5;
                let (sx, sy) = ndc(px, py);
                let ray = camera.ray(sx, sy, aspect);
                let Some(hit) = tracer.closest_hit(&ray, 0.0, f64::INFINITY, &mut counters) else {
                    continue;
                };
                let sp = tracer.shading_point(&hit, &ray);
                let (fx, fy) = ndc(px + 1.0, py + 1.0);
                let right = camera.ray(fx, sy, aspect);
                let down = camera.ray(sx, fy, aspect);
                if let Some(f) = Footprint::new(&sp, &ray, [&right, &down]) {
                    let rate = f.phase_width(&sp, |_, n, v| turns(n, v));
                    if rate.is_finite() {
                        row.push(rate);
                    }
                }
            }
            row
        })
        .collect();
    rows.into_iter().flatten().collect()
}

/// `--no-stripe-filter`: declared by every stripe mode (zebra, highlight, isophote); one flag
/// on the command line sets `filter = false` in each of their sections.
pub const NO_STRIPE_FILTER: crate::render::modes::Flag = crate::render::modes::Flag::off(
    "no-stripe-filter",
    "filter",
    "Point-sample the zebra, highlight and isophote stripes instead of box-filtering them over each pixel's footprint.",
);

/// The `filter` key of a stripe mode.
pub const FILTER_KEY: crate::render::modes::Key = crate::render::modes::Key::new(
    "filter",
    "box-filter the stripes over each pixel's footprint (default true)",
);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::camera::Camera;
    use crate::render::intersect::Tracer;
    use crate::testing::surfaces::octahedron_sphere;

    /// The phase of one stripe per turn of the normal's polar angle, for the tests.
    fn polar_turns(n: DVec3, _: DVec3) -> f64 {
        n.y.clamp(-1.0, 1.0).acos() / std::f64::consts::TAU
    }

    /// A sphere seen large keeps the most stripes; seen small it gets the largest whole count
    /// whose median period, measured again at that count, is at least
    /// [`READABLE_PERIOD_PX`]; seen tiny it stops at [`MIN_AUTO_STRIPES`].
    #[test]
    fn automatic_stripe_count_keeps_the_median_period_readable() {
        let surface = octahedron_sphere(3, 1.0, 0);
        let tracer = Tracer::with_default_settings(&surface).expect("tracer");
        let camera =
            Camera::frame(&surface.bounds(), Camera::DEFAULT_VIEW, 35.0, 1.0).expect("camera");
        let at = |side: u32| Setup {
            tracer: &tracer,
            camera: &camera,
            width: side,
            height: side,
        };
        assert_eq!(readable_stripes(&at(2048), 16.0, polar_turns), 16.0);
        let small = at(48);
        let count = readable_stripes(&small, 16.0, polar_turns);
        assert!(count < 16.0 && count > MIN_AUTO_STRIPES, "{count}");
        assert_eq!(count, count.floor());
        let mut rates = phase_rates(&small, &polar_turns);
        rates.sort_by(f64::total_cmp);
        let median = rates[rates.len() / 2];
        let period = |n: f64| 1.0 / (n * median);
        assert!(period(count) >= READABLE_PERIOD_PX, "{}", period(count));
        assert!(
            period(count + 1.0) < READABLE_PERIOD_PX,
            "{}",
            period(count + 1.0)
        );
        assert_eq!(
            readable_stripes(&at(8), 16.0, polar_turns),
            MIN_AUTO_STRIPES
        );
        // Never more than asked for, and nothing in view keeps the count.
        assert_eq!(readable_stripes(&small, 3.0, polar_turns), 3.0);
        let away = Camera::look_at(
            DVec3::new(0.0, 0.0, 10.0),
            DVec3::new(0.0, 0.0, 20.0),
            DVec3::Y,
            crate::render::camera::Projection::Perspective { fov_deg: 30.0 },
        )
        .expect("camera");
        let empty = Setup {
            camera: &away,
            ..at(64)
        };
        assert_eq!(readable_stripes(&empty, 16.0, polar_turns), 16.0);
    }

    #[test]
    fn box_filtered_square_wave() {
        // Point samples.
        assert_eq!(filtered_square_wave(0.2, 0.0, 0.5), 1.0);
        assert_eq!(filtered_square_wave(0.7, 0.0, 0.5), 0.0);
        // A narrow filter inside a stripe changes nothing (up to rounding).
        assert!((filtered_square_wave(0.25, 0.1, 0.5) - 1.0).abs() < 1e-12);
        // Straddling an edge: half of it bright.
        assert!((filtered_square_wave(0.5, 0.2, 0.5) - 0.5).abs() < 1e-12);
        // Whole periods average to the duty cycle.
        for width in [1.0, 2.0, 7.0] {
            for phase in [0.0, 0.3, 0.77] {
                let got = filtered_square_wave(phase, width, 0.3);
                assert!((got - 0.3).abs() < 1e-12, "{phase} {width}: {got}");
            }
        }
        // Matches a brute-force average.
        let (phase, width, duty) = (1.37, 0.61, 0.4);
        let n = 100_000;
        let brute = (0..n)
            .filter(|i| {
                let t = phase - 0.5 * width + width * (f64::from(*i) + 0.5) / f64::from(n);
                super::super::fract(t) < duty
            })
            .count() as f64
            / f64::from(n);
        assert!((filtered_square_wave(phase, width, duty) - brute).abs() < 1e-4);
    }

    /// A phase whose rounding exceeds 1/256 of a period has no placeable stripe edges: the
    /// mean, whatever the filter width (point samples included).
    #[test]
    fn unresolvable_phases_give_the_mean() {
        for phase in [1e14, -3e15, 1e300] {
            for width in [0.0, 0.01, 0.7, 50.0] {
                assert_eq!(
                    filtered_square_wave(phase, width, 0.3),
                    0.3,
                    "{phase} {width}"
                );
            }
        }
        // Just inside the limit the stripes are still there.
        let edge = MAX_RESOLVED_PHASE - 1.0;
        assert_eq!(filtered_square_wave(edge + 0.125, 0.0, 0.5), 1.0);
        assert_eq!(filtered_square_wave(edge + 0.75, 0.0, 0.5), 0.0);
    }
}
