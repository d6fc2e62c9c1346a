//! The `shaded` mode: a unidirectional path tracer on the exact surface. Material: a Lambert
//! base under a glossy clear coat (Schlick Fresnel, index 1.5, reflection spread uniformly over
//! a narrow cone about the mirror direction). Light: an environment ([`Environment`]), either
//! the built-in studio or a lat-long EXR map.
//!
//! The estimator follows the path integrators of pbrt-v4 and Mitsuba 3: at every vertex,
//! next-event estimation (a direction drawn from the light, tested by an any-hit shadow ray)
//! and a BRDF sample (coat or base, chosen by Fresnel; its density is that of the whole
//! mixture), the two combined by multiple importance sampling with the power heuristic; Russian
//! roulette from bounce [`ShadedParams::rr_depth`] on. Random numbers come from Owen-scrambled
//! Sobol' points padded per bounce ([`sobol_4d`]), each a function of (seed, pixel, sample,
//! dimension), so images are deterministic for any thread count.

use std::f64::consts::{PI, TAU};

use glam::DVec3;

pub(crate) use crate::render::environment::Environment;
use crate::render::environment::luminance;
use crate::render::interaction::ShadingPoint;
use crate::render::intersect::{IntersectCounters, Ray64};
use crate::render::sampler::sobol_4d;
use crate::render::trace::SurfaceTracer;

/// Material and light of the path tracer.
#[derive(Clone, Debug, PartialEq)]
pub struct ShadedParams {
    /// Lambert albedo of the base (linear RGB).
    pub base_colour: DVec3,
    /// Clear-coat reflectance at normal incidence (0.04 ≈ index 1.5).
    pub coat_f0: f64,
    /// Half-angle (radians) of the cone the coat reflection is spread over.
    pub coat_roughness: f64,
    /// Longest path (surface bounces).
    pub max_bounces: u32,
    /// The light.
    pub environment: Environment,
    /// Next-event estimation with multiple importance sampling (true), or BRDF sampling only
    /// (false: the plain estimator, for comparison).
    pub light_sampling: bool,
    /// First bounce (0-based) after which Russian roulette may end a path.
    pub rr_depth: u32,
}

impl Default for ShadedParams {
    fn default() -> Self {
        ShadedParams {
            base_colour: DVec3::new(0.55, 0.12, 0.08),
            coat_f0: 0.04,
            coat_roughness: 0.02,
            max_bounces: 6,
            environment: Environment::Studio,
            light_sampling: true,
            rr_depth: 3,
        }
    }
}

/// Identity of one path's random numbers, and its ray counts.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PathState {
    /// Render seed.
    pub seed: u64,
    /// Pixel index.
    pub pixel: u64,
    /// Sample index in the pixel.
    pub sample: u32,
    /// Secondary rays traced (BRDF rays and shadow rays).
    pub rays: u64,
    /// Secondary rays that hit (BRDF rays that met the surface, occluded shadow rays).
    pub hits: u64,
}

/// The clear-coat material at one shading point, for one outgoing direction.
///
/// `f(wi) cos θi = F δ_cone(wi) / Ω_cone + (1 − F) ρ cos θi / π` for `wi` above the surface
/// (zero below), with `F` the Schlick Fresnel of the viewing angle and `δ_cone` the indicator
/// of the cone of half-angle `coat_roughness` about the mirror direction; sampling picks the
/// coat with probability `c` (uniform in the cone; see [`coat_probability`]) and the base with
/// `1 − c` (cosine-weighted), so the density of a direction is
/// `c / Ω_cone · δ_cone + (1 − c) cos θi / π`.
#[derive(Clone, Copy, Debug)]
struct CoatBrdf {
    normal: DVec3,
    mirror: DVec3,
    fresnel: f64,
    /// Probability of sampling the coat.
    coat: f64,
    cone_cos: f64,
    /// `1 / Ω_cone`.
    cone_density: f64,
    albedo: DVec3,
}

impl CoatBrdf {
    fn new(sp: &ShadingPoint, params: &ShadedParams) -> CoatBrdf {
        let n = sp.facing_normal;
        let cos_o = n.dot(-sp.view).clamp(0.0, 1.0);
        let fresnel = params.coat_f0 + (1.0 - params.coat_f0) * (1.0 - cos_o).powi(5);
        let cone_cos = params.coat_roughness.cos();
        let mirror = sp.view - 2.0 * sp.view.dot(n) * n;
        CoatBrdf {
            normal: n,
            mirror,
            fresnel,
            coat: coat_probability(fresnel, mirror, params),
            cone_cos,
            cone_density: 1.0 / (TAU * (1.0 - cone_cos)),
            albedo: params.base_colour,
        }
    }

    fn in_cone(&self, wi: DVec3) -> bool {
        wi.dot(self.mirror) >= self.cone_cos
    }

    /// `f(wi) cos θi`.
    fn eval(&self, wi: DVec3) -> DVec3 {
        let cos_i = wi.dot(self.normal);
        if cos_i <= 0.0 {
            return DVec3::ZERO;
        }
        let coat = if self.in_cone(wi) {
            self.fresnel * self.cone_density
        } else {
            0.0
        };
        DVec3::splat(coat) + self.albedo * ((1.0 - self.fresnel) * cos_i / PI)
    }

    /// Solid-angle density of [`CoatBrdf::sample`] at `wi`.
    fn pdf(&self, wi: DVec3) -> f64 {
        let cos_i = wi.dot(self.normal);
        if cos_i <= 0.0 {
            return 0.0;
        }
        let coat = if self.in_cone(wi) {
            self.coat * self.cone_density
        } else {
            0.0
        };
        coat + (1.0 - self.coat) * cos_i / PI
    }

    /// A direction from `lobe` (chooses coat or base) and `(r1, r2)`.
    fn sample(&self, lobe: f64, r1: f64, r2: f64) -> DVec3 {
        if lobe < self.coat {
            cone_sample(self.mirror, self.cone_cos, r1, r2)
        } else {
            cosine_sample(self.normal, r1, r2)
        }
    }
}

/// Bounds of the probability of sampling the coat, so that neither lobe is starved.
const COAT_SELECTION: (f64, f64) = (0.3, 0.9);

/// The probability of sampling the coat rather than the base: the share of the coat in an
/// estimate of the light each reflects, `F L(mirror)` against `(1 − F) ρ L̄` (`L̄` the mean
/// radiance of the environment, luminances), clamped to [`COAT_SELECTION`]. The coat reflects
/// a few per cent of the light but carries the highlights, the brightest pixels: choosing it
/// with probability `F` (≈ 0.04) would give a highlight pixel of 16 samples no coat sample or
/// one. Where the mirror direction sees a soft box the coat gets most samples (stratified over
/// the pixel's samples); where it sees the dim sky the base gets 70 %: the estimate ignores
/// that the mirror direction may meet the surface itself, and a lower bound of 0.3 rather than
/// 0.1 lowered the 16-spp noise by 3–4 % on the torus in the studio and in its map (measured).
fn coat_probability(fresnel: f64, mirror: DVec3, params: &ShadedParams) -> f64 {
    if fresnel <= 0.0 {
        return 0.0;
    }
    let env = &params.environment;
    let coat = fresnel * luminance(env.radiance(mirror));
    let base = (1.0 - fresnel) * luminance(params.base_colour) * env.mean_luminance();
    let share = if coat + base > 0.0 {
        coat / (coat + base)
    } else {
        0.5
    };
    share.clamp(COAT_SELECTION.0, COAT_SELECTION.1)
}

/// The power heuristic (β = 2) weight of a strategy of density `a` against one of density `b`.
fn power_heuristic(a: f64, b: f64) -> f64 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 > 0.0 { a2 / (a2 + b2) } else { 0.0 }
}

/// Radiance along the camera ray whose closest hit is `first` (linear RGB).
pub(crate) fn trace_path<T: SurfaceTracer>(
    tracer: &T,
    params: &ShadedParams,
    first: &ShadingPoint,
    state: &mut PathState,
    counters: &mut IntersectCounters,
) -> DVec3 {
    let epsilon = 1e-7
        * tracer
            .bounds()
            .diagonal()
            .max(crate::tolerance::DIVISION_GUARD);
    let env = &params.environment;
    let mut sp = *first;
    let mut radiance = DVec3::ZERO;
    let mut throughput = DVec3::ONE;
    for bounce in 0..params.max_bounces {
        // Two sets of four dimensions per bounce: the BRDF sample (direction, lobe, roulette)
        // and the light sample (position, emitter).
        let [b1, b2, lobe, roulette] = sobol_4d(state.seed, state.pixel, state.sample, 2 * bounce);
        let [l1, l2, emitter, _] = sobol_4d(state.seed, state.pixel, state.sample, 2 * bounce + 1);
        let brdf = CoatBrdf::new(&sp, params);
        let origin = sp.jet.p + brdf.normal * epsilon;
        // Next-event estimation: a direction towards the light, weighted against the BRDF's
        // density for it.
        if params.light_sampling
            && let Some(light) = env.sample(brdf.normal, [emitter, l1, l2])
        {
            let f = brdf.eval(light.dir);
            if f != DVec3::ZERO {
                let shadow = Ray64 {
                    origin,
                    dir: light.dir,
                };
                state.rays += 1;
                if tracer.occluded(&shadow, epsilon, f64::INFINITY, counters) {
                    state.hits += 1;
                } else {
                    let weight = power_heuristic(light.pdf, brdf.pdf(light.dir));
                    radiance += throughput * f * light.radiance * (weight / light.pdf);
                }
            }
        }
        // The BRDF sample continues the path.
        let dir = brdf.sample(lobe, b1, b2);
        let pdf = brdf.pdf(dir);
        if pdf <= 0.0 {
            break;
        }
        throughput *= brdf.eval(dir) / pdf;
        let ray = Ray64 { origin, dir };
        state.rays += 1;
        match tracer.closest_hit(&ray, epsilon, f64::INFINITY, counters) {
            None => {
                let weight = if params.light_sampling {
                    power_heuristic(pdf, env.pdf(brdf.normal, dir))
                } else {
                    1.0
                };
                radiance += throughput * env.radiance(dir) * weight;
                break;
            }
            Some(hit) => {
                state.hits += 1;
                sp = tracer.shading_point(&hit, &ray);
            }
        }
        if bounce >= params.rr_depth {
            let survive = throughput.max_element().clamp(0.05, 0.95);
            if roulette >= survive {
                break;
            }
            throughput /= survive;
        }
    }
    radiance
}

/// Cosine-weighted direction about `n`.
fn cosine_sample(n: DVec3, r1: f64, r2: f64) -> DVec3 {
    let (a, b) = n.any_orthonormal_pair();
    let phi = TAU * r1;
    let r = r2.sqrt();
    (a * (r * phi.cos()) + b * (r * phi.sin()) + n * (1.0 - r2).max(0.0).sqrt()).normalize()
}

/// Uniform direction in the cone `d · axis ≥ cos_half` about `axis`.
fn cone_sample(axis: DVec3, cos_half: f64, r1: f64, r2: f64) -> DVec3 {
    let (a, b) = axis.any_orthonormal_pair();
    let cos_t = 1.0 - r2 * (1.0 - cos_half);
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    let phi = TAU * r1;
    (a * (sin_t * phi.cos()) + b * (sin_t * phi.sin()) + axis * cos_t).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::intersect::Hit;
    use crate::render::sampler::uniform;

    #[test]
    fn samples_lie_in_their_hemisphere_and_cone() {
        let n = DVec3::new(0.3, -0.5, 0.8).normalize();
        for i in 0..1000u32 {
            let (r1, r2) = (uniform(1, 0, i, 0), uniform(1, 0, i, 1));
            let d = cosine_sample(n, r1, r2);
            assert!((d.length() - 1.0).abs() < 1e-12 && d.dot(n) >= 0.0, "{d}");
            let c = cone_sample(n, 0.1f64.cos(), r1, r2);
            assert!(c.dot(n) >= 0.1f64.cos() - 1e-12, "{c}");
        }
    }

    /// A shading point on the plane z = 0 seen along `view`.
    fn plane_point(view: DVec3) -> ShadingPoint {
        let jet = crate::geom::Jet {
            p: DVec3::ZERO,
            du: DVec3::X,
            dv: DVec3::Y,
            duu: DVec3::ZERO,
            duv: DVec3::ZERO,
            dvv: DVec3::ZERO,
        };
        let hit = Hit {
            t: 1.0,
            patch: 0,
            u: 0.0,
            v: 0.0,
        };
        ShadingPoint::new(hit, 0, 0, jet, &Ray64::new(-view, view))
    }

    /// The BRDF's density integrates to 1 over the sphere (less the part of the cone below the
    /// horizon, which carries none), and `f cos / pdf` averaged over
    /// its own samples equals `∫ f cos dω` by quadrature (the directional albedo), for a
    /// grazing and a steep view.
    #[test]
    fn brdf_sampling_matches_its_density() {
        let params = ShadedParams {
            coat_roughness: 0.3,
            ..ShadedParams::default()
        };
        for view in [DVec3::new(0.3, 0.1, -1.0), DVec3::new(1.0, 0.2, -0.15)] {
            let brdf = CoatBrdf::new(&plane_point(view.normalize()), &params);
            let n = 1500;
            let (mut pdf_sum, mut albedo_quad) = (0.0, DVec3::ZERO);
            for i in 0..n {
                for j in 0..n {
                    // Uniform in (cos θ, φ) over the upper hemisphere: dω = dcosθ dφ.
                    let z = (i as f64 + 0.5) / n as f64;
                    let phi = TAU * (j as f64 + 0.5) / n as f64;
                    let r = (1.0 - z * z).sqrt();
                    let wi = DVec3::new(r * phi.cos(), r * phi.sin(), z);
                    pdf_sum += brdf.pdf(wi);
                    albedo_quad += brdf.eval(wi);
                }
            }
            let cell = TAU / (n * n) as f64;
            let total = pdf_sum * cell;
            // Cone directions below the horizon carry no density: the hemisphere holds
            // 1 − c × (share of the cone below the horizon).
            let below = (0..100_000u32)
                .filter(|&k| {
                    let d = cone_sample(
                        brdf.mirror,
                        brdf.cone_cos,
                        uniform(2, 0, k, 0),
                        uniform(2, 0, k, 1),
                    );
                    d.dot(brdf.normal) <= 0.0
                })
                .count() as f64
                / 100_000.0;
            let expected = 1.0 - brdf.coat * below;
            assert!(
                (total - expected).abs() < 3e-3,
                "view {view}: ∫pdf = {total}, expected {expected} (coat {}, {below} of the cone below)",
                brdf.coat
            );
            let albedo_quad = albedo_quad * cell;
            let m = 200_000u32;
            let mut albedo_mc = DVec3::ZERO;
            for k in 0..m {
                let (r1, r2, lobe) = (
                    uniform(9, 0, k, 0),
                    uniform(9, 0, k, 1),
                    uniform(9, 0, k, 2),
                );
                let wi = brdf.sample(lobe, r1, r2);
                let pdf = brdf.pdf(wi);
                if pdf > 0.0 {
                    albedo_mc += brdf.eval(wi) / pdf;
                }
            }
            let albedo_mc = albedo_mc / f64::from(m);
            let rel = ((albedo_mc - albedo_quad).abs() / albedo_quad).max_element();
            assert!(
                rel < 0.01,
                "view {view}: sampled {albedo_mc}, quadrature {albedo_quad}"
            );
        }
    }

    #[test]
    fn power_heuristic_weights_sum_to_one() {
        for (a, b) in [(1.0, 3.0), (0.2, 0.0), (5.0, 5.0)] {
            let sum = power_heuristic(a, b) + power_heuristic(b, a);
            assert!((sum - 1.0).abs() < 1e-15, "{a} {b}: {sum}");
        }
        assert_eq!(power_heuristic(0.0, 0.0), 0.0);
    }
}
