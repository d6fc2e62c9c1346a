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
//! either), as pbrt-v4's light sampler weighs lights by their orientation bounds. A map is
//! sampled in two levels (`MapSampler`): a block of texels from a distribution that depends on
//! the shading normal (the block's power times a bound of its cosine with the normal, so blocks
//! below the horizon are not drawn), then a texel of the block in proportion to its power
//! (luminance × `sin θ`); density `p(u, v) / (2π² sin θ)` per solid angle.

use std::f64::consts::{FRAC_PI_2, PI, TAU};
use std::path::Path;
use std::sync::Arc;

use glam::DVec3;

use crate::error::{Error, Result};

/// A lat-long (equirectangular) environment map in linear RGB; +Y is up, u = 0 at −Z.
#[derive(Clone, Debug)]
pub struct LatLongMap {
    width: usize,
    height: usize,
    /// Per texel its R, G, B and (last) the entry of the map sampler's CDF over the texels of
    /// its row within its block ([`MapSampler`]), so that sampling a texel brings its radiance
    /// into the cache.
    texels: Vec<[f32; 4]>,
    /// Sampling distributions; None for a black map.
    sampler: Option<MapSampler>,
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
            // A missing map is most often the studio map of a scene that compares renderers:
            // say how to write it.
            let hint = if path.exists() {
                String::new()
            } else {
                format!(
                    " (no such file; `cargo run --release --example studio_map -- {}` writes the \
                     built-in studio as a lat-long map there)",
                    path.display()
                )
            };
            Error::Invalid(format!(
                "{}: cannot read environment map: {e}{hint}",
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
        // Texel solid angles are ∝ sin θ: a texel's power is ∝ L sin θ.
        let sines: Vec<f64> = (0..height)
            .map(|y| ((y as f64 + 0.5) / height as f64 * PI).sin())
            .collect();
        let weights: Vec<f64> = texels
            .iter()
            .enumerate()
            .map(|(i, t)| luminance(texel(t)) * sines[i / width])
            .collect();
        let total: f64 = weights.iter().sum();
        let mut texels: Vec<[f32; 4]> = texels.iter().map(|&[r, g, b]| [r, g, b, 0.0]).collect();
        let sampler = (total > 0.0 && total.is_finite())
            .then(|| MapSampler::new(&weights, width, height, &mut texels));
        // The mean is Σ L sin θ / Σ sin θ.
        let mean_luminance = total / (sines.iter().sum::<f64>() * width as f64);
        Ok(LatLongMap {
            width,
            height,
            texels,
            sampler,
            mean_luminance,
        })
    }

    /// Texel column and row of direction `d` (unit).
    fn cell(&self, d: DVec3) -> (usize, usize) {
        let (u, v) = direction_to_uv(d);
        let x = ((u * self.width as f64) as usize).min(self.width - 1);
        let y = ((v * self.height as f64) as usize).min(self.height - 1);
        (x, y)
    }

    fn lookup(&self, d: DVec3) -> DVec3 {
        let (x, y) = self.cell(d);
        let [r, g, b, _] = self.texels[y * self.width + x];
        texel(&[r, g, b])
    }

    fn sample(&self, normal: DVec3, r: [f64; 3]) -> Option<(DVec3, f64)> {
        let (u, v) = self
            .sampler
            .as_ref()?
            .sample(&self.texels, normal, r[1], r[2])?;
        let d = uv_to_direction(u, v);
        let pdf = self.pdf(normal, d);
        (pdf > 0.0).then_some((d, pdf))
    }

    fn pdf(&self, normal: DVec3, d: DVec3) -> f64 {
        let Some(sampler) = &self.sampler else {
            return 0.0;
        };
        let sin = (1.0 - d.y * d.y).max(0.0).sqrt();
        if sin == 0.0 {
            return 0.0;
        }
        let (x, y) = self.cell(d);
        sampler.density(&self.texels, normal, x, y) / (2.0 * PI * PI * sin)
    }
}

fn texel(t: &[f32; 3]) -> DVec3 {
    DVec3::new(f64::from(t[0]), f64::from(t[1]), f64::from(t[2]))
}

/// Rec. 709 luminance of linear RGB.
pub(crate) fn luminance(c: DVec3) -> f64 {
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

/// Blocks of texels the map's sampling chooses among first (at most this many columns × rows).
const BLOCK_GRID: (usize, usize) = (64, 32);

/// Cells per edge of each cube face in the grid of normal directions ([`normal_bin`]).
const NORMAL_BINS_PER_EDGE: usize = 16;

/// Normal bins in all: six cube faces.
const NORMAL_BINS: usize = 6 * NORMAL_BINS_PER_EDGE * NORMAL_BINS_PER_EDGE;

/// The sampling of a lat-long map, in two levels and aware of the shading point's horizon.
///
/// The texels are grouped into at most [`BLOCK_GRID`] blocks. For each of [`NORMAL_BINS`] cones
/// of normal directions (a cube map of the sphere) a 2-D distribution over the blocks (marginal
/// over block rows, conditional within a block row) weighs each block by its power times a
/// bound of the cosine between any normal of the cone and any direction of the block (zero for
/// a block below the horizon of every normal of the cone). Within the chosen block a texel is
/// drawn in proportion to its power (a marginal over the block's rows, then the row's texels),
/// and the point is uniform in the texel. The numbers are split hierarchically (the remainder of
/// each choice places the next), so the mapping of the unit square is continuous within each
/// cell and keeps the stratification of the samples.
///
/// All CDFs are `f32` (inclusive running sums, last entry 1), and a cell's probability is the
/// difference of its two CDF entries taken in `f64`: the density [`MapSampler::density`]
/// returns is exactly the one [`MapSampler::sample`] draws from (for exact uniform numbers).
/// The CDFs within the blocks' rows are the texels' fourth entries ([`LatLongMap`]), passed in.
#[derive(Clone, Debug)]
struct MapSampler {
    width: usize,
    height: usize,
    /// Texel column (row) edges of the block columns (rows): `blocks + 1` entries.
    col_edges: Vec<usize>,
    row_edges: Vec<usize>,
    /// The block column of each texel column, the block row of each texel row.
    block_of_col: Vec<u32>,
    block_of_row: Vec<u32>,
    /// Per block column and texel row, the CDF over the rows of the block (index
    /// `bx · height + y`).
    block_rows_cdf: Vec<f32>,
    /// Per normal bin, the marginal CDF over block rows then the conditional CDF of each
    /// block row over its blocks (`bh + bh · bw` entries); empty bins are all NaN.
    bins: Vec<f32>,
}

impl MapSampler {
    /// The distributions of the non-negative texel `weights` (power, row-major), whose sum is
    /// positive and finite; the CDFs within the rows of the blocks go to the last entry of
    /// `texels`.
    fn new(weights: &[f64], width: usize, height: usize, texels: &mut [[f32; 4]]) -> MapSampler {
        let (bw, bh) = (BLOCK_GRID.0.min(width), BLOCK_GRID.1.min(height));
        let edges = |n: usize, blocks: usize| -> Vec<usize> {
            (0..=blocks).map(|b| b * n / blocks).collect()
        };
        let (col_edges, row_edges) = (edges(width, bw), edges(height, bh));
        let owner = |edges: &[usize], n: usize| -> Vec<u32> {
            let mut out = vec![0u32; n];
            for (b, w) in edges.windows(2).enumerate() {
                out[w[0]..w[1]].fill(b as u32);
            }
            out
        };
        let (block_of_col, block_of_row) = (owner(&col_edges, width), owner(&row_edges, height));
        // Within each block row segment: the CDF over its texels, and its sum.
        let mut segment_sums = vec![0f64; bw * height];
        let mut segment_cdf = Vec::new();
        for y in 0..height {
            for bx in 0..bw {
                let (x0, x1) = (col_edges[bx], col_edges[bx + 1]);
                let row = &weights[y * width + x0..y * width + x1];
                segment_cdf.resize(row.len(), 0.0);
                segment_sums[bx * height + y] = fill_cdf(row, &mut segment_cdf);
                for (t, c) in texels[y * width + x0..y * width + x1]
                    .iter_mut()
                    .zip(&segment_cdf)
                {
                    t[3] = *c;
                }
            }
        }
        // Within each block: the CDF over its rows, and the block's power.
        let mut block_rows_cdf = vec![0f32; bw * height];
        let mut block_power = vec![0f64; bw * bh];
        for bx in 0..bw {
            for by in 0..bh {
                let (y0, y1) = (bx * height + row_edges[by], bx * height + row_edges[by + 1]);
                block_power[by * bw + bx] =
                    fill_cdf(&segment_sums[y0..y1], &mut block_rows_cdf[y0..y1]);
            }
        }
        // The cones of directions of the blocks: the centre and a bound of the angle from it
        // to any point (along the meridian, then along the parallel, whose length is sin θ ·
        // Δφ).
        let block_cones: Vec<(DVec3, f64, (f64, f64))> = (0..bh)
            .flat_map(|by| (0..bw).map(move |bx| (bx, by)))
            .map(|(bx, by)| {
                let (x0, x1) = (col_edges[bx] as f64, col_edges[bx + 1] as f64);
                let (y0, y1) = (row_edges[by] as f64, row_edges[by + 1] as f64);
                let (w, h) = (width as f64, height as f64);
                let centre = uv_to_direction((x0 + x1) / (2.0 * w), (y0 + y1) / (2.0 * h));
                let (t0, t1) = (y0 / h * PI, y1 / h * PI);
                let max_sin = if t0 <= FRAC_PI_2 && FRAC_PI_2 <= t1 {
                    1.0
                } else {
                    t0.sin().max(t1.sin())
                };
                let radius = (t1 - t0) / 2.0 + max_sin * (x1 - x0) / w * PI;
                (centre, radius, radius.sin_cos())
            })
            .collect();
        let stride = bh + bh * bw;
        let mut bins = vec![0f32; NORMAL_BINS * stride];
        let mut block_weight = vec![0f64; bw * bh];
        let mut row_sums = vec![0f64; bh];
        for (bin, out) in bins.chunks_mut(stride).enumerate() {
            let (normal, normal_radius) = normal_bin_cone(bin);
            let (sin_n, cos_n) = normal_radius.sin_cos();
            for ((w, &p), &(centre, radius, (sin_b, cos_b))) in
                block_weight.iter_mut().zip(&block_power).zip(&block_cones)
            {
                // With θ the angle between the centres and R the sum of the radii, the bound
                // is cos(θ − R) when θ > R, else 1; no inverse cosine needed.
                let cos_t = normal.dot(centre).clamp(-1.0, 1.0);
                let cos_r = cos_n * cos_b - sin_n * sin_b;
                *w = if normal_radius + radius >= PI || cos_t >= cos_r {
                    p
                } else {
                    let sin_t = (1.0 - cos_t * cos_t).sqrt();
                    let sin_r = sin_n * cos_b + cos_n * sin_b;
                    p * (cos_t * cos_r + sin_t * sin_r).max(0.0)
                };
            }
            let (marginal, conditional) = out.split_at_mut(bh);
            for by in 0..bh {
                row_sums[by] = fill_cdf(
                    &block_weight[by * bw..(by + 1) * bw],
                    &mut conditional[by * bw..(by + 1) * bw],
                );
            }
            if fill_cdf(&row_sums, marginal) == 0.0 {
                out.fill(f32::NAN);
            }
        }
        MapSampler {
            width,
            height,
            col_edges,
            row_edges,
            block_of_col,
            block_of_row,
            block_rows_cdf,
            bins,
        }
    }

    fn block_grid(&self) -> (usize, usize) {
        (self.col_edges.len() - 1, self.row_edges.len() - 1)
    }

    /// The marginal CDF over block rows and the conditional CDFs of normal `bin`.
    fn bin(&self, bin: usize) -> (&[f32], &[f32]) {
        let (bw, bh) = self.block_grid();
        let stride = bh + bh * bw;
        self.bins[bin * stride..(bin + 1) * stride].split_at(bh)
    }

    /// A point `(u, v)` of the unit square, drawn for a shading point of unit normal `normal`
    /// from two uniform numbers; None when no light reaches that normal's bin.
    fn sample(&self, texels: &[[f32; 4]], normal: DVec3, r1: f64, r2: f64) -> Option<(f64, f64)> {
        let (bw, _) = self.block_grid();
        let (marginal, conditional) = self.bin(normal_bin(normal));
        if marginal[0].is_nan() {
            return None;
        }
        let (by, f1) = invert_cdf(marginal, r1);
        let (bx, f2) = invert_cdf(&conditional[by * bw..(by + 1) * bw], r2);
        let (y0, y1) = (self.row_edges[by], self.row_edges[by + 1]);
        let (x0, x1) = (self.col_edges[bx], self.col_edges[bx + 1]);
        let (dy, fy) = invert_cdf(
            &self.block_rows_cdf[bx * self.height + y0..bx * self.height + y1],
            f1,
        );
        let y = y0 + dy;
        let (dx, fx) = invert_cdf(&texels[y * self.width + x0..y * self.width + x1], f2);
        Some((
            ((x0 + dx) as f64 + fx) / self.width as f64,
            (y as f64 + fy) / self.height as f64,
        ))
    }

    /// The density over the unit square of [`MapSampler::sample`] in texel `(x, y)` for a
    /// shading point of unit normal `normal`.
    fn density(&self, texels: &[[f32; 4]], normal: DVec3, x: usize, y: usize) -> f64 {
        let (bw, _) = self.block_grid();
        let (marginal, conditional) = self.bin(normal_bin(normal));
        if marginal[0].is_nan() {
            return 0.0;
        }
        let (bx, by) = (self.block_of_col[x] as usize, self.block_of_row[y] as usize);
        let (y0, x0) = (self.row_edges[by], self.col_edges[bx]);
        let block = cell_probability(marginal, by)
            * cell_probability(&conditional[by * bw..(by + 1) * bw], bx);
        if block == 0.0 {
            return 0.0;
        }
        let rows =
            &self.block_rows_cdf[bx * self.height + y0..bx * self.height + self.row_edges[by + 1]];
        let cols = &texels[y * self.width + x0..y * self.width + self.col_edges[bx + 1]];
        block
            * cell_probability(rows, y - y0)
            * cell_probability(cols, x - x0)
            * (self.width * self.height) as f64
    }
}

/// Fills `cdf` with the inclusive running sums of `weights` divided by their total, rounded to
/// `f32` (the last entry exactly 1; a uniform CDF when the total is zero), and returns the total.
fn fill_cdf(weights: &[f64], cdf: &mut [f32]) -> f64 {
    let total: f64 = weights.iter().sum();
    let n = weights.len();
    let mut acc = 0.0;
    for (i, (c, w)) in cdf.iter_mut().zip(weights).enumerate() {
        acc += w;
        *c = if total > 0.0 {
            (acc / total) as f32
        } else {
            (i + 1) as f32 / n as f32
        };
    }
    cdf[n - 1] = 1.0;
    total
}

/// An entry of an inclusive CDF: an `f32`, or the last of a texel's four.
trait CdfEntry {
    /// The CDF's value.
    fn cdf(&self) -> f32;
}

impl CdfEntry for f32 {
    fn cdf(&self) -> f32 {
        *self
    }
}

impl CdfEntry for [f32; 4] {
    fn cdf(&self) -> f32 {
        self[3]
    }
}

/// The probability of cell `i` of an inclusive CDF: the difference of its entries in `f64`.
fn cell_probability<T: CdfEntry>(cdf: &[T], i: usize) -> f64 {
    let below = if i == 0 {
        0.0
    } else {
        f64::from(cdf[i - 1].cdf())
    };
    f64::from(cdf[i].cdf()) - below
}

/// The cell `i` of an inclusive CDF with `cdf[i − 1] ≤ r < cdf[i]` (so never an empty cell) and
/// where in it `r` lies, in `[0, 1)`.
fn invert_cdf<T: CdfEntry>(cdf: &[T], r: f64) -> (usize, f64) {
    let i = cdf
        .partition_point(|c| f64::from(c.cdf()) <= r)
        .min(cdf.len() - 1);
    let below = if i == 0 {
        0.0
    } else {
        f64::from(cdf[i - 1].cdf())
    };
    let width = f64::from(cdf[i].cdf()) - below;
    let f = if width > 0.0 {
        ((r - below) / width).clamp(0.0, 1.0 - f64::EPSILON)
    } else {
        0.5
    };
    (i, f)
}

/// The bin of unit direction `n` in a cube map of [`NORMAL_BINS_PER_EDGE`]² cells per face:
/// the face of the largest component, then the cell of the other two divided by it.
fn normal_bin(n: DVec3) -> usize {
    let a = n.abs();
    let (face, s, t, m) = if a.x >= a.y && a.x >= a.z {
        (usize::from(n.x < 0.0), n.y, n.z, a.x)
    } else if a.y >= a.z {
        (2 + usize::from(n.y < 0.0), n.x, n.z, a.y)
    } else {
        (4 + usize::from(n.z < 0.0), n.x, n.y, a.z)
    };
    let edge = NORMAL_BINS_PER_EDGE;
    let cell = |c: f64| (((c / m + 1.0) * 0.5 * edge as f64) as usize).min(edge - 1);
    (face * edge + cell(s)) * edge + cell(t)
}

/// The cone of the normals of `bin`: the direction of the cell's centre and the largest angle
/// from it to a corner (the farthest point of a cell, which is convex on the cube's face).
fn normal_bin_cone(bin: usize) -> (DVec3, f64) {
    let edge = NORMAL_BINS_PER_EDGE;
    let (face, i, j) = (bin / (edge * edge), bin / edge % edge, bin % edge);
    let point = |s: f64, t: f64| -> DVec3 {
        let sign = if face % 2 == 0 { 1.0 } else { -1.0 };
        match face / 2 {
            0 => DVec3::new(sign, s, t),
            1 => DVec3::new(s, sign, t),
            _ => DVec3::new(s, t, sign),
        }
        .normalize()
    };
    let coord = |k: f64| 2.0 * k / edge as f64 - 1.0;
    let (i, j) = (i as f64, j as f64);
    let centre = point(coord(i + 0.5), coord(j + 0.5));
    let radius = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)]
        .iter()
        .map(|&(a, b)| {
            centre
                .dot(point(coord(i + a), coord(j + b)))
                .clamp(-1.0, 1.0)
                .acos()
        })
        .fold(0.0, f64::max);
    // A margin for the rounding of the bin of a normal on a cell's edge.
    (centre, radius + 1e-9)
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
        *s = if closest < FRAC_PI_2 {
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
            Environment::Map(map) => map.sample(normal, r)?,
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
            Environment::Map(map) => map.pdf(normal, d),
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

fn smoothstep(a: f64, b: f64, x: f64) -> f64 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A direction uniform on the unit sphere.
    fn uniform_sphere(r1: f64, r2: f64) -> DVec3 {
        let z = 1.0 - 2.0 * r1;
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = TAU * r2;
        DVec3::new(r * phi.cos(), r * phi.sin(), z)
    }
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
        for map in [test_map(), blocky_map()] {
            let env = Environment::Map(Arc::new(map));
            for normal in NORMALS.into_iter().chain(more_normals(20)) {
                let integral = integral_of_pdf(&env, normal);
                assert!(
                    (integral - 1.0).abs() < 0.01,
                    "map at {normal}: ∫pdf = {integral}"
                );
            }
        }
    }

    /// A map of 130 × 70 texels, so that the sampling's blocks hold 2 or 3 texels each way:
    /// a gradient in both directions, a bright spot across a block edge, a black band.
    fn blocky_map() -> LatLongMap {
        let (w, h) = (130, 70);
        let mut texels = Vec::new();
        for y in 0..h {
            for x in 0..w {
                let v = if (40..44).contains(&y) {
                    0.0
                } else {
                    0.05 + 0.01 * (x % 17) as f32 + 0.002 * y as f32
                };
                texels.push([v, 0.8 * v, 0.3 * v]);
            }
        }
        for (x, y) in [(60, 10), (61, 10), (62, 11), (100, 55)] {
            texels[y * w + x] = [50.0, 40.0, 30.0];
        }
        LatLongMap::from_texels(w, h, texels).expect("map")
    }

    /// `count` unit directions spread over the sphere.
    fn more_normals(count: u32) -> impl Iterator<Item = DVec3> {
        (0..count).map(|i| uniform_sphere(uniform(11, 0, i, 0), uniform(11, 0, i, 1)))
    }

    /// The texel probabilities a normal's distribution assigns sum to 1 (up to the `f32`
    /// CDFs), and a histogram of the texels drawn by [`MapSampler::sample`] matches them: every
    /// count within 5 standard deviations (+ 3) of its expectation, none in a texel of
    /// probability 0.
    #[test]
    fn map_samples_follow_the_stated_density() {
        let map = blocky_map();
        let sampler = map.sampler.as_ref().expect("a lit map");
        let (w, h) = (map.width, map.height);
        for normal in NORMALS.into_iter().chain(more_normals(3)) {
            let probability: Vec<f64> = (0..w * h)
                .map(|i| sampler.density(&map.texels, normal, i % w, i / w) / (w * h) as f64)
                .collect();
            let total: f64 = probability.iter().sum();
            assert!((total - 1.0).abs() < 1e-5, "{normal}: Σp = {total}");
            let n = 1_000_000u32;
            let mut counts = vec![0u32; w * h];
            for i in 0..n {
                let (u, v) = sampler
                    .sample(
                        &map.texels,
                        normal,
                        uniform(12, 0, i, 0),
                        uniform(12, 0, i, 1),
                    )
                    .expect("a sample");
                let (x, y) = ((u * w as f64) as usize, (v * h as f64) as usize);
                counts[y * w + x] += 1;
            }
            for (i, (&c, &p)) in counts.iter().zip(&probability).enumerate() {
                let expected = p * f64::from(n);
                assert!(
                    (f64::from(c) - expected).abs() <= 5.0 * expected.sqrt() + 3.0,
                    "{normal}: texel ({}, {}) drawn {c} times, expected {expected:.1}",
                    i % w,
                    i / w
                );
            }
        }
    }

    /// Directions above the horizon of the normal that carry light have a positive density
    /// (the cosine bounds are conservative), and directions well below it have none.
    #[test]
    fn map_sampling_keeps_above_the_horizon() {
        let env = Environment::Map(Arc::new(blocky_map()));
        for normal in NORMALS.into_iter().chain(more_normals(20)) {
            let (mut above, mut below) = (0, 0);
            for i in 0..20_000u32 {
                let d = uniform_sphere(uniform(13, 0, i, 0), uniform(13, 0, i, 1));
                let pdf = env.pdf(normal, d);
                let cos = normal.dot(d);
                if cos > 0.0 && luminance(env.radiance(d)) > 0.0 {
                    assert!(pdf > 0.0, "{normal}: no density at {d} above the horizon");
                    above += 1;
                } else if cos < -0.6 {
                    assert_eq!(pdf, 0.0, "{normal}: density at {d} below the horizon");
                    below += 1;
                }
            }
            assert!(above > 8000 && below > 2000, "{above} {below}");
        }
    }

    /// The light-sampling estimate `L cos⁺ / pdf` of the irradiance `∫ L cos⁺ dω` at a point
    /// agrees with midpoint quadrature over the sphere in (z, φ) for each normal, and every
    /// sample's stated pdf is `Environment::pdf` at its direction.
    #[test]
    fn light_sampling_estimates_the_irradiance() {
        let envs = [
            ("studio", Environment::Studio),
            ("small map", Environment::Map(Arc::new(test_map()))),
            ("blocky map", Environment::Map(Arc::new(blocky_map()))),
        ];
        for (name, env) in envs {
            for normal in NORMALS {
                let n = 200_000u32;
                let mut sampled = DVec3::ZERO;
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
                }
                let m = 1000;
                let mut quadrature = DVec3::ZERO;
                for i in 0..m {
                    for j in 0..m {
                        let z = 1.0 - 2.0 * (i as f64 + 0.5) / m as f64;
                        let phi = TAU * (j as f64 + 0.5) / m as f64;
                        let r = (1.0 - z * z).sqrt();
                        let d = DVec3::new(r * phi.cos(), r * phi.sin(), z);
                        quadrature += env.radiance(d) * normal.dot(d).max(0.0);
                    }
                }
                let (a, b) = (
                    sampled / f64::from(n),
                    quadrature * 4.0 * PI / (m * m) as f64,
                );
                let rel = ((a - b).abs() / b).max_element();
                assert!(
                    rel < 0.01,
                    "{name} at {normal}: light sampling {a}, quadrature {b}"
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
