//! The `shaded` mode: a small unidirectional path tracer on the exact surface. Material: a
//! Lambert base under a glossy clear coat (Schlick Fresnel, index 1.5). Light: an environment,
//! either the built-in studio (dim gradient plus three soft-box strips) or a lat-long EXR map.
//! Russian roulette after two bounces; every random number is a hash of
//! (seed, pixel, sample, dimension), so images are deterministic.

use std::f64::consts::{PI, TAU};
use std::path::Path;
use std::sync::Arc;

use glam::DVec3;

use crate::error::{Error, Result};
use crate::render::interaction::ShadingPoint;
use crate::render::intersect::{IntersectCounters, Ray64};
use crate::render::sampler::uniform;
use crate::render::trace::SurfaceTracer;

/// A lat-long (equirectangular) environment map in linear RGB; +Y is up, u = 0 at −Z.
#[derive(Clone, Debug)]
pub struct LatLongMap {
    width: usize,
    height: usize,
    texels: Vec<[f32; 3]>,
}

impl LatLongMap {
    /// Reads the first RGB(A) layer of an EXR file.
    pub fn load(path: &Path) -> Result<LatLongMap> {
        let image = exr::prelude::read_first_rgba_layer_from_file(
            path,
            |resolution, _| {
                (
                    resolution.width(),
                    resolution.height(),
                    vec![[0.0f32; 3]; resolution.width() * resolution.height()],
                )
            },
            |(w, _, texels): &mut (usize, usize, Vec<[f32; 3]>),
             pos,
             (r, g, b, _a): (f32, f32, f32, f32)| {
                texels[pos.y() * *w + pos.x()] = [r, g, b];
            },
        )
        .map_err(|e| {
            Error::Invalid(format!(
                "{}: cannot read environment map: {e}",
                path.display()
            ))
        })?;
        let (width, height, texels) = image.layer_data.channel_data.pixels;
        if width == 0 || height == 0 || texels.iter().flatten().any(|x| !x.is_finite()) {
            return Err(Error::Invalid(format!(
                "{}: environment map is empty or has non-finite texels",
                path.display()
            )));
        }
        Ok(LatLongMap {
            width,
            height,
            texels,
        })
    }

    fn lookup(&self, d: DVec3) -> DVec3 {
        let u = 0.5 + d.x.atan2(-d.z) / TAU;
        let v = d.y.clamp(-1.0, 1.0).acos() / PI;
        let x = ((u * self.width as f64) as usize).min(self.width - 1);
        let y = ((v * self.height as f64) as usize).min(self.height - 1);
        let t = self.texels[y * self.width + x];
        DVec3::new(f64::from(t[0]), f64::from(t[1]), f64::from(t[2]))
    }
}

/// Where light comes from.
#[derive(Clone, Debug)]
pub enum Environment {
    /// Built-in studio: dark gradient and three soft-box strips.
    Studio,
    /// A lat-long map.
    Map(Arc<LatLongMap>),
}

impl PartialEq for Environment {
    fn eq(&self, other: &Self) -> bool {
        match (self, other) {
            (Environment::Studio, Environment::Studio) => true,
            (Environment::Map(a), Environment::Map(b)) => Arc::ptr_eq(a, b),
            _ => false,
        }
    }
}

/// Soft box: unit direction to its centre, half-extents (radians) along its two axes, radiance.
const SOFT_BOXES: [(DVec3, f64, f64, f64); 3] = [
    (DVec3::new(0.0, 1.0, 0.0), 0.9, 0.12, 3.0),
    (DVec3::new(0.8, 0.3, 0.52), 0.08, 0.6, 4.0),
    (DVec3::new(-0.85, 0.2, 0.49), 0.06, 0.5, 2.0),
];

impl Environment {
    /// Radiance arriving from direction `d` (unit).
    pub fn radiance(&self, d: DVec3) -> DVec3 {
        match self {
            Environment::Map(map) => map.lookup(d),
            Environment::Studio => {
                let sky = 0.02 + 0.10 * smoothstep(-0.2, 1.0, d.y);
                let mut l = DVec3::splat(sky);
                for (centre, half_a, half_b, power) in SOFT_BOXES {
                    let c = centre.normalize();
                    let (a, b) = c.any_orthonormal_pair();
                    let cos = d.dot(c);
                    if cos <= 0.0 {
                        continue;
                    }
                    // Angular offsets of d from the box centre along its two axes.
                    let x = d.dot(a).atan2(cos).abs();
                    let y = d.dot(b).atan2(cos).abs();
                    let inside = (1.0 - smoothstep(half_a * 0.85, half_a, x))
                        * (1.0 - smoothstep(half_b * 0.85, half_b, y));
                    l += DVec3::splat(power * inside);
                }
                l
            }
        }
    }
}

fn smoothstep(a: f64, b: f64, x: f64) -> f64 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Material and light of the path tracer.
#[derive(Clone, Debug, PartialEq)]
pub struct ShadedParams {
    /// Lambert albedo of the base (linear RGB).
    pub base_colour: DVec3,
    /// Clear-coat reflectance at normal incidence (0.04 ≈ index 1.5).
    pub coat_f0: f64,
    /// Half-angle (radians) of the cone the coat reflection is spread over.
    pub coat_roughness: f64,
    /// Longest path.
    pub max_bounces: u32,
    /// The light.
    pub environment: Environment,
}

impl Default for ShadedParams {
    fn default() -> Self {
        ShadedParams {
            base_colour: DVec3::new(0.55, 0.12, 0.08),
            coat_f0: 0.04,
            coat_roughness: 0.02,
            max_bounces: 6,
            environment: Environment::Studio,
        }
    }
}

/// Identity of one path's random numbers, and its ray counts.
#[derive(Clone, Copy, Debug)]
pub struct PathState {
    /// Render seed.
    pub seed: u64,
    /// Pixel index.
    pub pixel: u64,
    /// Sample index in the pixel.
    pub sample: u32,
    /// Secondary rays traced.
    pub rays: u64,
    /// Secondary rays that hit.
    pub hits: u64,
}

/// Radiance along the camera ray whose closest hit is `first` (linear RGB).
pub fn trace_path<T: SurfaceTracer>(
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
    let mut sp = *first;
    let mut throughput = DVec3::ONE;
    for bounce in 0..params.max_bounces {
        let dim = 2 + 5 * bounce;
        let rnd = |k: u32| uniform(state.seed, state.pixel, state.sample, dim + k);
        let n = sp.facing_normal;
        let wo = -sp.view;
        let cos_o = n.dot(wo).clamp(0.0, 1.0);
        let fresnel = params.coat_f0 + (1.0 - params.coat_f0) * (1.0 - cos_o).powi(5);
        // Choose coat with probability F, base with 1 − F: the weights cancel.
        let dir = if rnd(0) < fresnel {
            let mirror = sp.view - 2.0 * sp.view.dot(n) * n;
            let d = cone_sample(mirror, params.coat_roughness, rnd(1), rnd(2));
            if d.dot(n) <= 0.0 {
                break;
            }
            d
        } else {
            throughput *= params.base_colour;
            cosine_sample(n, rnd(1), rnd(2))
        };
        let ray = Ray64 {
            origin: sp.jet.p + n * epsilon,
            dir,
        };
        state.rays += 1;
        match tracer.closest_hit(&ray, epsilon, f64::INFINITY, counters) {
            None => return throughput * params.environment.radiance(dir),
            Some(hit) => {
                state.hits += 1;
                sp = tracer.shading_point(&hit, &ray);
            }
        }
        if bounce >= 2 {
            let survive = throughput.max_element().clamp(0.05, 0.95);
            if rnd(3) >= survive {
                break;
            }
            throughput /= survive;
        }
    }
    DVec3::ZERO
}

/// Cosine-weighted direction about `n`.
fn cosine_sample(n: DVec3, r1: f64, r2: f64) -> DVec3 {
    let (a, b) = n.any_orthonormal_pair();
    let phi = TAU * r1;
    let r = r2.sqrt();
    (a * (r * phi.cos()) + b * (r * phi.sin()) + n * (1.0 - r2).max(0.0).sqrt()).normalize()
}

/// Uniform direction in the cone of half-angle `half` about `axis`.
fn cone_sample(axis: DVec3, half: f64, r1: f64, r2: f64) -> DVec3 {
    let (a, b) = axis.any_orthonormal_pair();
    let cos_t = 1.0 - r2 * (1.0 - half.cos());
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    let phi = TAU * r1;
    (a * (sin_t * phi.cos()) + b * (sin_t * phi.sin()) + axis * cos_t).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_lie_in_their_hemisphere_and_cone() {
        let n = DVec3::new(0.3, -0.5, 0.8).normalize();
        for i in 0..1000u32 {
            let (r1, r2) = (uniform(1, 0, i, 0), uniform(1, 0, i, 1));
            let d = cosine_sample(n, r1, r2);
            assert!((d.length() - 1.0).abs() < 1e-12 && d.dot(n) >= 0.0, "{d}");
            let c = cone_sample(n, 0.1, r1, r2);
            assert!(c.dot(n) >= 0.1f64.cos() - 1e-12, "{c}");
        }
    }

    #[test]
    fn studio_is_brighter_in_a_soft_box() {
        let env = Environment::Studio;
        let key = env.radiance(DVec3::Y);
        let floor = env.radiance(-DVec3::Y);
        assert!(key.x > 1.0 && floor.x < 0.05, "key {key} floor {floor}");
    }
}
