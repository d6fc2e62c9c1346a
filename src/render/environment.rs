//! The light of the path tracer: an environment at infinity, either the built-in studio (a dim
//! sky gradient plus three soft-box strips) or a lat-long EXR map, with what the integrator
//! needs for next-event estimation: radiance along a direction, a direction sampled in
//! proportion to the light ([`Environment::sample`]) and the density of that sampling at any
//! direction ([`Environment::pdf`]), so that light and BRDF samples can be combined by multiple
//! importance sampling.
//!
//! The studio is sampled analytically as a mixture of emitters: each soft box uniformly in the
//! two angles that define it (density `1 / (4 α β cos³θ sec²x sec²y)` per solid angle, within
//! a factor 1.6 of uniform over the widest box), the sky cosine-weighted about the shading
//! normal. The emitter is chosen in proportion to its power times a bound of its cosine at the
//! shading point (zero for a box wholly below the horizon, which no BRDF sample can reach
//! either), as pbrt-v4's light sampler weighs lights by their orientation bounds. A map is sampled through
//! a piecewise-constant 2-D distribution over its texels (luminance × `sin θ`, marginal over
//! rows, conditional within a row), density `p(u, v) / (2π² sin θ)` per solid angle.

use std::f64::consts::{PI, TAU};
use std::path::Path;
use std::sync::Arc;

use glam::DVec3;

use crate::error::{Error, Result};

/// A lat-long (equirectangular) environment map in linear RGB; +Y is up, u = 0 at −Z.
#[derive(Clone, Debug)]
pub struct LatLongMap {
    width: usize,
    height: usize,
    texels: Vec<[f32; 3]>,
    /// Sampling distribution over texels; None for a black map.
    distribution: Option<Distribution2D>,
    /// Mean luminance over the sphere.
    mean_luminance: f64,
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
        LatLongMap::from_texels(width, height, texels)
            .map_err(|e| Error::Invalid(format!("{}: {e}", path.display())))
    }

    /// A map of `width × height` texels in row-major order from the top (+Y) row.
    pub fn from_texels(width: usize, height: usize, texels: Vec<[f32; 3]>) -> Result<LatLongMap> {
        if width == 0 || height == 0 || texels.len() != width * height {
            return Err(Error::Invalid(format!(
                "environment map is empty or its {} texels are not {width}×{height}",
                texels.len()
            )));
        }
        if let Some(i) = texels
            .iter()
            .position(|t| t.iter().any(|x| !x.is_finite() || *x < 0.0))
        {
            return Err(Error::Invalid(format!(
                "environment map texel ({}, {}) is negative or not finite: {:?}",
                i % width,
                i / width,
                texels[i]
            )));
        }
        let weights: Vec<f64> = texels
            .iter()
            .enumerate()
            .map(|(i, t)| {
                let theta = ((i / width) as f64 + 0.5) / height as f64 * PI;
                luminance(texel(t)) * theta.sin()
            })
            .collect();
        let distribution = Distribution2D::new(&weights, width, height);
        // Texel solid angles are ∝ sin θ: the mean is Σ L sin θ / Σ sin θ.
        let sines: f64 = (0..height)
            .map(|y| ((y as f64 + 0.5) / height as f64 * PI).sin())
            .sum::<f64>()
            * width as f64;
        let mean_luminance = weights.iter().sum::<f64>() / sines;
        Ok(LatLongMap {
            width,
            height,
            texels,
            distribution,
            mean_luminance,
        })
    }

    /// Texel index of direction `d` (unit).
    fn index(&self, d: DVec3) -> usize {
        let (u, v) = direction_to_uv(d);
        let x = ((u * self.width as f64) as usize).min(self.width - 1);
        let y = ((v * self.height as f64) as usize).min(self.height - 1);
        y * self.width + x
    }

    fn lookup(&self, d: DVec3) -> DVec3 {
        texel(&self.texels[self.index(d)])
    }

    fn sample(&self, r: [f64; 3]) -> Option<(DVec3, f64)> {
        let dist = self.distribution.as_ref()?;
        let (u, v) = dist.sample(r[1], r[2]);
        let d = uv_to_direction(u, v);
        let pdf = self.pdf(d);
        (pdf > 0.0).then_some((d, pdf))
    }

    fn pdf(&self, d: DVec3) -> f64 {
        let Some(dist) = &self.distribution else {
            return 0.0;
        };
        let sin = (1.0 - d.y * d.y).max(0.0).sqrt();
        if sin == 0.0 {
            return 0.0;
        }
        dist.density(self.index(d)) / (2.0 * PI * PI * sin)
    }
}

fn texel(t: &[f32; 3]) -> DVec3 {
    DVec3::new(f64::from(t[0]), f64::from(t[1]), f64::from(t[2]))
}

/// Rec. 709 luminance of linear RGB.
pub fn luminance(c: DVec3) -> f64 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

/// Lat-long coordinates in `[0, 1]²` of unit direction `d`: `u = ½ + atan2(x, −z) / 2π`,
/// `v = acos(y) / π`.
fn direction_to_uv(d: DVec3) -> (f64, f64) {
    (
        0.5 + d.x.atan2(-d.z) / TAU,
        d.y.clamp(-1.0, 1.0).acos() / PI,
    )
}

/// The unit direction of lat-long coordinates `(u, v)` (inverse of [`direction_to_uv`]).
fn uv_to_direction(u: f64, v: f64) -> DVec3 {
    let (phi, theta) = ((u - 0.5) * TAU, v * PI);
    let (sin_t, cos_t) = theta.sin_cos();
    DVec3::new(sin_t * phi.sin(), cos_t, -sin_t * phi.cos())
}

/// A piecewise-constant density over `[0, 1]²` on a `width × height` grid of cells, sampled by
/// inverting the marginal CDF of the rows and then the conditional CDF within the row.
#[derive(Clone, Debug)]
struct Distribution2D {
    width: usize,
    height: usize,
    /// Per row, the CDF over its cells (`width + 1` entries from 0 to 1).
    conditional: Vec<f64>,
    /// The CDF over rows (`height + 1` entries from 0 to 1).
    marginal: Vec<f64>,
    /// Density (over the unit square) of each cell.
    density: Vec<f64>,
}

impl Distribution2D {
    /// The distribution of non-negative `weights` (row-major), None when they sum to zero.
    fn new(weights: &[f64], width: usize, height: usize) -> Option<Distribution2D> {
        let total: f64 = weights.iter().sum();
        if !(total > 0.0 && total.is_finite()) {
            return None;
        }
        let mut conditional = Vec::with_capacity(height * (width + 1));
        let mut marginal = Vec::with_capacity(height + 1);
        marginal.push(0.0);
        let mut running = 0.0;
        for row in weights.chunks(width) {
            let row_sum: f64 = row.iter().sum();
            let mut acc = 0.0;
            conditional.push(0.0);
            for (i, w) in row.iter().enumerate() {
                acc += w;
                // Rows of zero weight are never chosen; give them a uniform CDF anyway.
                conditional.push(if row_sum > 0.0 {
                    acc / row_sum
                } else {
                    (i + 1) as f64 / width as f64
                });
            }
            running += row_sum;
            marginal.push(running / total);
        }
        let cells = (width * height) as f64;
        let density = weights.iter().map(|w| w / total * cells).collect();
        Some(Distribution2D {
            width,
            height,
            conditional,
            marginal,
            density,
        })
    }

    /// Density over the unit square in cell `index`.
    fn density(&self, index: usize) -> f64 {
        self.density[index]
    }

    /// A point of the unit square from two uniform numbers: the row by the marginal CDF, the
    /// column by the row's CDF, each continuous within its cell.
    fn sample(&self, r1: f64, r2: f64) -> (f64, f64) {
        let (y, fy) = invert_cdf(&self.marginal, r1);
        let row = &self.conditional[y * (self.width + 1)..(y + 1) * (self.width + 1)];
        let (x, fx) = invert_cdf(row, r2);
        (
            (x as f64 + fx) / self.width as f64,
            (y as f64 + fy) / self.height as f64,
        )
    }
}

/// The cell `i` with `cdf[i] ≤ r < cdf[i + 1]` (skipping empty cells) and where in it `r` lies,
/// in `[0, 1)`.
fn invert_cdf(cdf: &[f64], r: f64) -> (usize, f64) {
    let cells = cdf.len() - 1;
    // First entry greater than r, minus one: the last cell starting at or below r.
    let i = cdf.partition_point(|&c| c <= r).clamp(1, cells) - 1;
    let width = cdf[i + 1] - cdf[i];
    let f = if width > 0.0 {
        ((r - cdf[i]) / width).clamp(0.0, 1.0 - f64::EPSILON)
    } else {
        0.5
    };
    (i, f)
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

/// Share of the sky in the studio's light selection, relative to its power: the sky is dim
/// and smooth, so BRDF samples find most of it; the rest goes to the soft boxes.
const SKY_SELECTION: f64 = 0.25;

/// One soft box as an emitter: frame, its angular half-extents, the half-sides of the rectangle
/// they span on the tangent plane at unit distance, the angular area `4 α β`, the half-angle
/// of a cone about the centre holding the box, and its power (radiance × angular area).
struct SoftBox {
    centre: DVec3,
    spread: f64,
    power: f64,
    a: DVec3,
    b: DVec3,
    half_a: f64,
    half_b: f64,
    half_x: f64,
    half_y: f64,
    angular_area: f64,
}

impl SoftBox {
    fn new(k: usize) -> SoftBox {
        let (centre, half_a, half_b, _) = SOFT_BOXES[k];
        let c = centre.normalize();
        let (a, b) = c.any_orthonormal_pair();
        let (half_x, half_y) = (half_a.tan(), half_b.tan());
        let (_, _, _, radiance) = SOFT_BOXES[k];
        SoftBox {
            centre: c,
            // The corners are the farthest points from the centre.
            spread: (half_x * half_x + half_y * half_y).sqrt().atan(),
            power: radiance * 4.0 * half_a * half_b,
            a,
            b,
            half_a,
            half_b,
            half_x,
            half_y,
            angular_area: 4.0 * half_a * half_b,
        }
    }

    /// A direction uniform in the box's angles `x = atan(d·a / d·c)`, `y = atan(d·b / d·c)`.
    fn sample(&self, r1: f64, r2: f64) -> DVec3 {
        let x = ((2.0 * r1 - 1.0) * self.half_a).tan();
        let y = ((2.0 * r2 - 1.0) * self.half_b).tan();
        (self.centre + self.a * x + self.b * y).normalize()
    }

    /// Solid-angle density of [`SoftBox::sample`] at `d`, 0 outside the box: with `X = tan x`,
    /// `Y = tan y` the point on the tangent plane, `dω = dX dY cos³θ` and `dX = (1 + X²) dx`,
    /// so `p = 1 / (4 α β cos³θ (1 + X²) (1 + Y²))`.
    fn pdf(&self, d: DVec3) -> f64 {
        let cos = d.dot(self.centre);
        if cos <= 0.0 {
            return 0.0;
        }
        let (x, y) = (d.dot(self.a) / cos, d.dot(self.b) / cos);
        if x.abs() > self.half_x || y.abs() > self.half_y {
            return 0.0;
        }
        1.0 / (self.angular_area * cos * cos * cos * (1.0 + x * x) * (1.0 + y * y))
    }
}

fn soft_boxes() -> &'static [SoftBox; 3] {
    static BOXES: std::sync::OnceLock<[SoftBox; 3]> = std::sync::OnceLock::new();
    BOXES.get_or_init(|| [SoftBox::new(0), SoftBox::new(1), SoftBox::new(2)])
}

/// Selection probabilities of the three boxes and (last) the sky at a point of unit normal
/// `normal`: power × the largest cosine any direction of the emitter makes with the normal
/// (zero when the whole box is below the horizon); the sky's power is the mean sky over the
/// hemisphere times π, scaled by [`SKY_SELECTION`].
fn studio_selection(normal: DVec3) -> [f64; 4] {
    let mut select = [0.0; 4];
    for (s, b) in select.iter_mut().zip(soft_boxes()) {
        let angle = normal.dot(b.centre).clamp(-1.0, 1.0).acos();
        let closest = (angle - b.spread).max(0.0);
        *s = if closest < std::f64::consts::FRAC_PI_2 {
            b.power * closest.cos()
        } else {
            0.0
        };
    }
    select[3] = SKY_SELECTION * 0.07 * PI;
    let total: f64 = select.iter().sum();
    select.map(|s| s / total)
}

/// A direction sampled towards the light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    /// Unit direction towards the light.
    pub dir: DVec3,
    /// Radiance arriving from `dir`.
    pub radiance: DVec3,
    /// Solid-angle density with which `dir` was drawn ([`Environment::pdf`] at `dir`).
    pub pdf: f64,
}

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

    /// Mean luminance of the radiance over the sphere of directions.
    pub fn mean_luminance(&self) -> f64 {
        match self {
            Environment::Map(map) => map.mean_luminance,
            Environment::Studio => {
                // Midpoint quadrature over a 512 × 256 lat-long grid, once.
                static MEAN: std::sync::OnceLock<f64> = std::sync::OnceLock::new();
                *MEAN.get_or_init(|| {
                    let (w, h) = (512, 256);
                    let (mut sum, mut weight) = (0.0, 0.0);
                    for y in 0..h {
                        let v = (f64::from(y) + 0.5) / f64::from(h);
                        let sin = (v * PI).sin();
                        for x in 0..w {
                            let d = uv_to_direction((f64::from(x) + 0.5) / f64::from(w), v);
                            sum += luminance(self.radiance(d)) * sin;
                            weight += sin;
                        }
                    }
                    sum / weight
                })
            }
        }
    }

    /// A direction drawn in proportion to the light seen from a point of unit normal `normal`,
    /// from three uniform numbers (the first chooses the emitter for the studio, the last two
    /// place the direction), or None when the environment is black.
    pub fn sample(&self, normal: DVec3, r: [f64; 3]) -> Option<LightSample> {
        let (dir, pdf) = match self {
            Environment::Map(map) => map.sample(r)?,
            Environment::Studio => {
                let select = studio_selection(normal);
                let mut k = 0;
                let mut acc = select[0];
                while k < 3 && (r[0] >= acc || select[k] == 0.0) {
                    k += 1;
                    acc += select[k];
                }
                let dir = if k < 3 {
                    soft_boxes()[k].sample(r[1], r[2])
                } else {
                    cosine_hemisphere(normal, r[1], r[2])
                };
                (dir, self.pdf(normal, dir))
            }
        };
        (pdf > 0.0 && pdf.is_finite()).then(|| LightSample {
            dir,
            radiance: self.radiance(dir),
            pdf,
        })
    }

    /// Solid-angle density with which [`Environment::sample`] draws direction `d` (unit) at a
    /// point of unit normal `normal`.
    pub fn pdf(&self, normal: DVec3, d: DVec3) -> f64 {
        match self {
            Environment::Map(map) => map.pdf(d),
            Environment::Studio => {
                let select = studio_selection(normal);
                let boxes: f64 = soft_boxes()
                    .iter()
                    .zip(select)
                    .map(|(b, p)| if p > 0.0 { p * b.pdf(d) } else { 0.0 })
                    .sum();
                boxes + select[3] * normal.dot(d).max(0.0) / PI
            }
        }
    }
}

/// A cosine-weighted direction about unit `n`.
fn cosine_hemisphere(n: DVec3, r1: f64, r2: f64) -> DVec3 {
    let (a, b) = n.any_orthonormal_pair();
    let phi = TAU * r1;
    let r = r2.sqrt();
    (a * (r * phi.cos()) + b * (r * phi.sin()) + n * (1.0 - r2).max(0.0).sqrt()).normalize()
}

/// A direction uniform on the unit sphere.
#[cfg(test)]
fn uniform_sphere(r1: f64, r2: f64) -> DVec3 {
    let z = 1.0 - 2.0 * r1;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = TAU * r2;
    DVec3::new(r * phi.cos(), r * phi.sin(), z)
}

fn smoothstep(a: f64, b: f64, x: f64) -> f64 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::sampler::uniform;

    /// A small map with one bright texel, a gradient and a black row.
    fn test_map() -> LatLongMap {
        let (w, h) = (16, 8);
        let mut texels = Vec::new();
        for y in 0..h {
            for x in 0..w {
                let v = if y == 7 { 0.0 } else { 0.1 + 0.05 * x as f32 };
                texels.push([v, v * 0.5, 0.2 * v]);
            }
        }
        texels[2 * w + 5] = [40.0, 30.0, 20.0];
        LatLongMap::from_texels(w, h, texels).expect("map")
    }

    /// Shading normals the tests look from: up, down (the top box below the horizon), sideways.
    const NORMALS: [DVec3; 3] = [DVec3::Y, DVec3::NEG_Y, DVec3::new(0.6, 0.0, -0.8)];

    /// `∫ pdf dω = 1` by stratified quadrature over the sphere in (z, φ).
    fn integral_of_pdf(env: &Environment, normal: DVec3) -> f64 {
        let n = 1000;
        let mut sum = 0.0;
        for i in 0..n {
            for j in 0..n {
                let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
                let phi = TAU * (j as f64 + 0.5) / n as f64;
                let r = (1.0 - z * z).sqrt();
                sum += env.pdf(normal, DVec3::new(r * phi.cos(), r * phi.sin(), z));
            }
        }
        sum * 4.0 * PI / (n * n) as f64
    }

    #[test]
    fn densities_integrate_to_one() {
        for normal in NORMALS {
            let studio = integral_of_pdf(&Environment::Studio, normal);
            assert!(
                (studio - 1.0).abs() < 0.01,
                "studio at {normal}: ∫pdf = {studio}"
            );
        }
        let map = integral_of_pdf(&Environment::Map(Arc::new(test_map())), DVec3::Y);
        assert!((map - 1.0).abs() < 0.01, "map ∫pdf = {map}");
    }

    /// The light-sampling estimate `L cos⁺ / pdf` of the irradiance `∫ L cos⁺ dω` at a point
    /// agrees with uniform-sphere quadrature for each normal, and every sample's stated pdf is
    /// `Environment::pdf` at its direction.
    #[test]
    fn light_sampling_estimates_the_irradiance() {
        for env in [Environment::Studio, Environment::Map(Arc::new(test_map()))] {
            for normal in NORMALS {
                let n = 200_000u32;
                let (mut sampled, mut uniform_est) = (DVec3::ZERO, DVec3::ZERO);
                for i in 0..n {
                    let r = [
                        uniform(3, 0, i, 0),
                        uniform(3, 0, i, 1),
                        uniform(3, 0, i, 2),
                    ];
                    let s = env.sample(normal, r).expect("a sample");
                    assert!((s.dir.length() - 1.0).abs() < 1e-12);
                    assert_eq!(s.pdf, env.pdf(normal, s.dir));
                    sampled += s.radiance * normal.dot(s.dir).max(0.0) / s.pdf;
                    let d = uniform_sphere(uniform(4, 0, i, 0), uniform(4, 0, i, 1));
                    uniform_est += env.radiance(d) * normal.dot(d).max(0.0) * 4.0 * PI;
                }
                let (a, b) = (sampled / f64::from(n), uniform_est / f64::from(n));
                let rel = ((a - b).abs() / b).max_element();
                assert!(
                    rel < 0.02,
                    "{env:?} at {normal}: light sampling {a}, uniform {b}"
                );
            }
        }
    }

    /// The mean luminance is that of uniform directions.
    #[test]
    fn mean_luminance_is_the_average_over_the_sphere() {
        for env in [Environment::Studio, Environment::Map(Arc::new(test_map()))] {
            let n = 400_000u32;
            let sum: f64 = (0..n)
                .map(|i| {
                    luminance(
                        env.radiance(uniform_sphere(uniform(6, 0, i, 0), uniform(6, 0, i, 1))),
                    )
                })
                .sum();
            let mean = sum / f64::from(n);
            let rel = (env.mean_luminance() - mean).abs() / mean;
            assert!(
                rel < 0.03,
                "{env:?}: {} vs sampled {mean}",
                env.mean_luminance()
            );
        }
    }

    #[test]
    fn map_directions_round_trip() {
        for i in 0..1000u32 {
            let (u, v) = (uniform(1, 0, i, 0), 0.01 + 0.98 * uniform(1, 0, i, 1));
            let (u2, v2) = direction_to_uv(uv_to_direction(u, v));
            assert!((u - u2).abs() < 1e-12 && (v - v2).abs() < 1e-12, "{u} {v}");
        }
    }

    #[test]
    fn bad_map_texel_is_named() {
        let mut texels = vec![[0.5f32; 3]; 4];
        texels[3] = [0.0, f32::NAN, 0.0];
        let err = LatLongMap::from_texels(2, 2, texels).expect_err("NaN texel");
        assert!(err.to_string().contains("texel (1, 1)"), "{err}");
    }

    #[test]
    fn studio_is_brighter_in_a_soft_box() {
        let env = Environment::Studio;
        let key = env.radiance(DVec3::Y);
        let floor = env.radiance(-DVec3::Y);
        assert!(key.x > 1.0 && floor.x < 0.05, "key {key} floor {floor}");
    }
}
