//! The render loop: tiles in parallel (rayon), stratified supersampling per pixel, and the
//! per-pixel geometry record (from the ray through the pixel centre) that the EXR stores.
//!
//! Determinism: every sample position and path-tracing decision is a hash of (seed, pixel,
//! sample, dimension); tiles are rendered independently, each straight into its own disjoint
//! row slices of the frame's buffers (no per-tile buffer, no copy), and the integer counters
//! are summed in tile order, so the image and statistics do not depend on the number of
//! threads.

use std::time::Instant;

use glam::DVec3;
use rayon::prelude::*;

use crate::render::bundle::{BUNDLE_SIDE, BundleScratch};
use crate::render::camera::Camera;
use crate::render::interaction::ShadingPoint;
use crate::render::intersect::{Hit, IntersectCounters, Ray64};
use crate::render::modes::{Footprint, Mode, Overlay, Sample, Setup};
use crate::render::sampler::pixel_offset;
use crate::render::stats::{MemoryParts, RenderStats};
use crate::render::theme::{Legend, LegendStyle, Theme};
use crate::render::trace::SurfaceTracer;
use crate::render::tubes::Tubes;

/// Side of a square tile in pixels.
const TILE: u32 = 16;

/// What to render and how.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderSettings {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Samples per pixel (stratified).
    pub spp: u32,
    /// Shading mode.
    pub mode: Mode,
    /// Boundary lines.
    pub overlay: Overlay,
    /// Linear RGB of rays that miss (and the ground of the legend strip).
    pub background: DVec3,
    /// Colours around the image: the legend's ink, the curvature mode's default map.
    pub theme: Theme,
    /// Seed of all sample positions.
    pub seed: u64,
    /// Show a progress bar on stderr (only ever when stderr is a terminal).
    pub progress: bool,
    /// Trace the surface (false: only the curve tubes are seen; the geometry record is empty).
    pub surface: bool,
    /// Tubes of the curve-network overlay, traced with the surface.
    pub curves: Option<std::sync::Arc<Tubes>>,
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            width: 640,
            height: 480,
            spp: 4,
            mode: Mode::default(),
            overlay: Overlay::default(),
            background: Theme::Dark.background(),
            theme: Theme::Dark,
            seed: 0,
            progress: true,
            surface: true,
            curves: None,
        }
    }
}

/// The geometry seen through one pixel centre: the exact hit (f64) and what the EXR's geometry
/// channels store of it.
///
/// Position, normal and Gaussian curvature are kept as the f32 the EXR channels hold (each the
/// f64 value as evaluated, rounded once); the exact point is `patch.eval(hit.u, hit.v)`. The mean
/// curvature stays f64 (the report's curvature thumbnails are coloured from it). 72 bytes, 80
/// with the miss tag, where a record of f64 vectors took 112.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelGeometry {
    /// The hit (f64 distance and patch parameters, as found).
    pub hit: Hit,
    /// Mesh face of the hit patch: the triangle from [`crate::render::film::render`], the input
    /// face (polygon) it was cut from once [`crate::render::RenderJob::render`] has mapped it.
    pub face: u32,
    /// Hit point `S(u, v)`, rounded to f32.
    pub position: [f32; 3],
    /// Unit patch normal at the hit (patch orientation, not turned to the viewer), rounded to
    /// f32.
    pub normal: [f32; 3],
    /// Gaussian curvature (0 where undefined), rounded to f32.
    pub gaussian: f32,
    /// Mean curvature (0 where undefined).
    pub mean: f64,
}

impl PixelGeometry {
    /// The record of `sp`, the shading point of a pixel-centre hit.
    pub fn new(sp: &ShadingPoint) -> PixelGeometry {
        let c = sp.curvature;
        PixelGeometry {
            hit: sp.hit,
            face: sp.face,
            position: sp.jet.p.as_vec3().to_array(),
            normal: sp.normal.as_vec3().to_array(),
            gaussian: c.map_or(0.0, |c| c.gaussian) as f32,
            mean: c.map_or(0.0, |c| c.mean),
        }
    }
}

/// A rendered image: linear RGB plus the per-pixel geometry, rows top to bottom, and the
/// mode's legend, which the PNG places right of the image (the EXR holds the image alone).
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Linear RGB per pixel.
    pub rgb: Vec<[f32; 3]>,
    /// Geometry through each pixel centre (None: the ray missed).
    pub geometry: Vec<Option<PixelGeometry>>,
    /// The mode's legend strip, as tall as the image ([`crate::render::modes::ModeKind::legend`]).
    pub legend: Option<Legend>,
}

impl Frame {
    /// A `width` × `height` frame of colour `rgb` where every ray missed, without legend.
    pub fn blank(width: u32, height: u32, rgb: [f32; 3]) -> Frame {
        let n = width as usize * height as usize;
        Frame {
            width,
            height,
            rgb: vec![rgb; n],
            geometry: vec![None; n],
            legend: None,
        }
    }

    /// Width of the PNG: the image and its legend strip.
    pub fn png_width(&self) -> u32 {
        self.width + self.legend.as_ref().map_or(0, |l| l.width)
    }

    /// The bytes of the buffers of a `width` × `height` frame: linear RGB and the geometry
    /// record of every pixel.
    pub fn bytes(width: u32, height: u32) -> f64 {
        let per_pixel =
            std::mem::size_of::<[f32; 3]>() + std::mem::size_of::<Option<PixelGeometry>>();
        per_pixel as f64 * f64::from(width) * f64::from(height)
    }
}

/// Refuses a `width` × `height` frame whose memory does not fit the memory limit
/// ([`crate::budget::check_memory`]): its buffers ([`Frame::bytes`]) plus `extra_per_pixel`
/// bytes a pixel for what is made of it (the output files' encodings). The error names the
/// size, the estimate, the limit and `--size`.
pub fn check_frame_memory(width: u32, height: u32, extra_per_pixel: f64) -> crate::Result<()> {
    let pixels = f64::from(width) * f64::from(height);
    crate::budget::check_memory(
        &format!("a {width}x{height} frame"),
        Frame::bytes(width, height) + extra_per_pixel * pixels,
        "lower --size (render.size)",
    )
}

/// One tile of the frame: its rows' slices of the frame's buffers, written in place.
struct Tile<'a> {
    x0: u32,
    y0: u32,
    rgb: Vec<&'a mut [[f32; 3]]>,
    geometry: Vec<&'a mut [Option<PixelGeometry>]>,
}

/// What a tile counted, summed later in tile order.
#[derive(Default)]
struct TileCounts {
    counters: IntersectCounters,
    rays: u64,
    hits: u64,
}

/// The frame's buffers cut into [`TILE`]-square tiles (row-major tile order), each a set of
/// disjoint row slices: tiles render in parallel straight into the frame.
fn tiles<'a>(
    w: u32,
    rgb: &'a mut [[f32; 3]],
    geometry: &'a mut [Option<PixelGeometry>],
) -> Vec<Tile<'a>> {
    let (w, band) = (w as usize, (w * TILE) as usize);
    let mut tiles = Vec::new();
    for (ty, (rgb, geometry)) in rgb
        .chunks_mut(band)
        .zip(geometry.chunks_mut(band))
        .enumerate()
    {
        let mut row_of_tiles: Vec<Tile<'a>> = (0..w.div_ceil(TILE as usize))
            .map(|tx| Tile {
                x0: tx as u32 * TILE,
                y0: ty as u32 * TILE,
                rgb: Vec::with_capacity(TILE as usize),
                geometry: Vec::with_capacity(TILE as usize),
            })
            .collect();
        for (rgb, geometry) in rgb.chunks_mut(w).zip(geometry.chunks_mut(w)) {
            let pieces = rgb
                .chunks_mut(TILE as usize)
                .zip(geometry.chunks_mut(TILE as usize));
            for (tile, (rgb, geometry)) in row_of_tiles.iter_mut().zip(pieces) {
                tile.rgb.push(rgb);
                tile.geometry.push(geometry);
            }
        }
        tiles.extend(row_of_tiles);
    }
    tiles
}

/// Renders `tracer` seen by `camera`.
pub fn render<T: SurfaceTracer>(
    tracer: &T,
    camera: &Camera,
    settings: &RenderSettings,
) -> crate::Result<(Frame, RenderStats)> {
    render_cancellable(tracer, camera, settings, &|| false)?
        .ok_or_else(|| crate::Error::Invalid("a render that cannot be cancelled was".into()))
}

/// Renders `tracer` seen by `camera` like [`render`], asking `cancelled` before each tile: once
/// it answers true the remaining tiles are skipped and the result is `None` (an interactive
/// view drops a frame whose camera has moved on). A frame that is returned is the one
/// [`render`] gives, bit for bit.
pub(crate) fn render_cancellable<T: SurfaceTracer>(
    tracer: &T,
    camera: &Camera,
    settings: &RenderSettings,
    cancelled: &(dyn Fn() -> bool + Sync),
) -> crate::Result<Option<(Frame, RenderStats)>> {
    if settings.width == 0 || settings.height == 0 || settings.spp == 0 {
        let message = format!(
            "image size {}x{} and samples per pixel {} must be positive",
            settings.width, settings.height, settings.spp
        );
        return Err(crate::Error::config(
            "render.size",
            crate::Problem::Stated { message },
        ));
    }
    let (w, h) = (settings.width, settings.height);
    check_frame_memory(w, h, 0.0)?;
    let start = Instant::now();
    let mut stats = RenderStats::default();
    let mode = settings.mode.themed(settings.theme).set_up(
        &Setup {
            tracer,
            camera,
            width: w,
            height: h,
        },
        &mut stats,
    );
    let mut frame = Frame::blank(w, h, [0.0; 3]);
    let tiles = tiles(w, &mut frame.rgb, &mut frame.geometry);
    let bar = progress_bar(settings, tiles.len() as u64);
    let skipped = std::sync::atomic::AtomicBool::new(false);
    let results: Vec<TileCounts> = tiles
        .into_par_iter()
        .map(|tile| {
            if skipped.load(std::sync::atomic::Ordering::Relaxed) || cancelled() {
                skipped.store(true, std::sync::atomic::Ordering::Relaxed);
                return TileCounts::default();
            }
            let counts = render_tile(tracer, camera, settings, &mode, tile);
            if let Some(bar) = &bar {
                bar.inc(1);
            }
            counts
        })
        .collect();
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    if skipped.into_inner() {
        return Ok(None);
    }
    let mut counters = IntersectCounters::default();
    for tile in results {
        counters.add(&tile.counters);
        stats.rays += tile.rays;
        stats.hits += tile.hits;
    }
    let style = LegendStyle::new(settings.theme, settings.background, h);
    frame.legend = mode.legend(h, &style);
    stats.misses = stats.rays - stats.hits;
    stats.set_newton(&counters);
    stats.render_ms = start.elapsed().as_secs_f64() * 1e3;
    stats.pixels = u64::from(w) * u64::from(h);
    stats.set_rates();
    stats.bvh_build_ms = tracer.build_ms();
    stats.leaves = tracer.leaf_count() as u64;
    stats.memory_parts = MemoryParts(
        tracer
            .memory_parts()
            .into_iter()
            .map(|(name, bytes)| (name, bytes as u64))
            .collect(),
    );
    stats.memory_bytes = stats.memory_parts.total();
    stats.patches = tracer.surface().patches.len() as u64;
    Ok(Some((frame, stats)))
}

/// A progress bar over the tiles on stderr when asked for and [`crate::progress::shown`].
fn progress_bar(settings: &RenderSettings, tiles: u64) -> Option<indicatif::ProgressBar> {
    (settings.progress && crate::progress::shown())
        .then(|| crate::progress::bar(tiles, "render {bar:40} {percent:>3}% {elapsed}"))
}

/// Renders one tile into its slices of the frame and returns what it counted.
///
/// The tile is rendered in square blocks of [`BUNDLE_SIDE`] pixels: the rays of one sample
/// index through all pixels of a block are traced together ([`SurfaceTracer::closest_hits`]:
/// a perspective camera's rays share the eye and walk the BVH once), then each pixel's sample
/// is shaded. Each pixel still sums its samples in sample order, so the image is the same as
/// ray by ray.
fn render_tile<T: SurfaceTracer>(
    tracer: &T,
    camera: &Camera,
    settings: &RenderSettings,
    mode: &Mode,
    mut tile: Tile<'_>,
) -> TileCounts {
    let (w, h) = (settings.width, settings.height);
    let aspect = f64::from(w) / f64::from(h);
    let rays = camera.rays(aspect);
    let mut counts = TileCounts::default();
    let ndc = |px: f64, py: f64| (2.0 * px / f64::from(w) - 1.0, 1.0 - 2.0 * py / f64::from(h));
    // The side of one sample's cell in pixels (the stratified grid of `pixel_offset`): the
    // stripe modes filter over it, so that the samples of a pixel together cover it.
    let cell = 1.0 / f64::from(settings.spp).sqrt();
    let filtered = mode.uses_footprint();
    // With one sample per pixel, that sample is the pixel centre and its ray is the geometry
    // ray: one ray per pixel, not two, and one shading point.
    let centre_only = settings.spp == 1;
    let (x0, y0) = (tile.x0, tile.y0);
    let rows = tile.rgb.len() as u32;
    let cols = tile.rgb.first().map_or(0, |row| row.len()) as u32;
    let mut scratch = BundleScratch::default();
    let mut block_pixels: Vec<(u32, u32)> = Vec::new();
    let mut block_rays: Vec<Ray64> = Vec::new();
    let mut block_hits: Vec<Option<Hit>> = Vec::new();
    let mut centre_sps: Vec<Option<ShadingPoint>> = Vec::new();
    let mut sums: Vec<DVec3> = Vec::new();
    let mut offsets: Vec<(f64, f64)> = Vec::new();
    let mut trace = |rays: &[Ray64], hits: &mut Vec<Option<Hit>>, counts: &mut TileCounts| {
        hits.clear();
        hits.resize(rays.len(), None);
        counts.rays += rays.len() as u64;
        if settings.surface {
            tracer.closest_hits(
                rays,
                0.0,
                f64::INFINITY,
                hits,
                &mut counts.counters,
                &mut scratch,
            );
        }
    };
    for by in (0..rows).step_by(BUNDLE_SIDE as usize) {
        for bx in (0..cols).step_by(BUNDLE_SIDE as usize) {
            block_pixels.clear();
            for dy in by..rows.min(by + BUNDLE_SIDE) {
                block_pixels.extend((bx..cols.min(bx + BUNDLE_SIDE)).map(|dx| (dx, dy)));
            }
            // Geometry channels: the rays through the pixel centres.
            block_rays.clear();
            block_rays.extend(block_pixels.iter().map(|&(dx, dy)| {
                let (cx, cy) = ndc(f64::from(x0 + dx) + 0.5, f64::from(y0 + dy) + 0.5);
                rays.at(cx, cy)
            }));
            trace(&block_rays, &mut block_hits, &mut counts);
            centre_sps.clear();
            for ((&(dx, dy), hit), ray) in block_pixels.iter().zip(&block_hits).zip(&block_rays) {
                let sp = hit.map(|hit| {
                    counts.hits += 1;
                    tracer.shading_point(&hit, ray)
                });
                tile.geometry[dy as usize][dx as usize] = sp.as_ref().map(PixelGeometry::new);
                centre_sps.push(sp);
            }
            // Colour: stratified supersampling (the centre ray alone at one sample per pixel).
            sums.clear();
            sums.resize(block_pixels.len(), DVec3::ZERO);
            for s in 0..settings.spp {
                let offset = |pixel: u64| {
                    if centre_only {
                        (0.5, 0.5)
                    } else {
                        pixel_offset(settings.seed, pixel, s, settings.spp)
                    }
                };
                let pixel_of =
                    |(dx, dy): (u32, u32)| u64::from(y0 + dy) * u64::from(w) + u64::from(x0 + dx);
                offsets.clear();
                offsets.extend(block_pixels.iter().map(|&p| offset(pixel_of(p))));
                if !centre_only {
                    block_rays.clear();
                    block_rays.extend(block_pixels.iter().zip(&offsets).map(|(&(dx, dy), o)| {
                        let (sx, sy) = ndc(f64::from(x0 + dx) + o.0, f64::from(y0 + dy) + o.1);
                        rays.at(sx, sy)
                    }));
                    trace(&block_rays, &mut block_hits, &mut counts);
                    counts.hits += block_hits.iter().filter(|hit| hit.is_some()).count() as u64;
                }
                for (i, &(dx, dy)) in block_pixels.iter().enumerate() {
                    let (x, y) = (x0 + dx, y0 + dy);
                    let pixel = pixel_of((dx, dy));
                    let (ox, oy) = offsets[i];
                    let (sx, sy) = ndc(f64::from(x) + ox, f64::from(y) + oy);
                    let (ray, hit) = (block_rays[i], block_hits[i]);
                    let tube = settings.curves.as_ref().and_then(|tubes| {
                        let t_max = hit.map_or(f64::INFINITY, |h| h.t);
                        tubes
                            .closest_hit(&ray, t_max)
                            .map(|th| tubes.shade(&th, &ray))
                    });
                    let colour = match (tube, hit) {
                        (Some(c), _) => c,
                        (None, None) => settings.background,
                        (None, Some(hit)) => {
                            // The centre ray's shading point is the same ray's, evaluated once.
                            let sp = match centre_sps[i] {
                                Some(sp) if centre_only => sp,
                                _ => tracer.shading_point(&hit, &ray),
                            };
                            let footprint = if filtered {
                                let (fx, fy) =
                                    ndc(f64::from(x) + ox + cell, f64::from(y) + oy + cell);
                                let right = rays.at(fx, sy);
                                let down = rays.at(sx, fy);
                                Footprint::new(&sp, &ray, [&right, &down])
                            } else {
                                None
                            };
                            let mut sample = Sample {
                                seed: settings.seed,
                                pixel,
                                sample: s,
                                counters: &mut counts.counters,
                                rays: 0,
                                hits: 0,
                            };
                            let base = mode.radiance(tracer, &sp, footprint.as_ref(), &mut sample);
                            counts.rays += sample.rays;
                            counts.hits += sample.hits;
                            if settings.overlay.enabled() {
                                let footprint = camera.pixel_footprint(hit.t, h);
                                settings.overlay.apply(
                                    base,
                                    &sp,
                                    footprint,
                                    tracer.face_edge_mask(hit.patch),
                                )
                            } else {
                                base
                            }
                        }
                    };
                    sums[i] += if colour.is_finite() {
                        colour
                    } else {
                        DVec3::ZERO
                    };
                }
            }
            for (&(dx, dy), sum) in block_pixels.iter().zip(&sums) {
                let c = *sum / f64::from(settings.spp);
                tile.rgb[dy as usize][dx as usize] = [c.x as f32, c.y as f32, c.z as f32];
            }
        }
    }
    counts
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::intersect::Tracer;
    use crate::testing::surfaces::octahedron_sphere;

    fn small_settings(mode: Mode) -> RenderSettings {
        RenderSettings {
            width: 48,
            height: 40,
            spp: 4,
            mode,
            progress: false,
            ..RenderSettings::default()
        }
    }

    /// The record is small: the frame holds one per pixel.
    #[test]
    fn pixel_record_is_at_most_80_bytes() {
        assert!(std::mem::size_of::<Option<PixelGeometry>>() <= 80);
    }

    #[test]
    fn image_is_identical_for_any_thread_count() {
        let surface = octahedron_sphere(3, 1.0, 0);
        let tracer = Tracer::with_default_settings(&surface).expect("tracer");
        let camera = Camera::frame(&surface.bounds(), Camera::DEFAULT_VIEW, 35.0, 48.0 / 40.0)
            .expect("camera");
        let settings = small_settings(Mode::by_name("zebra").expect("zebra"));
        let run = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("thread pool")
                .install(|| render(&tracer, &camera, &settings).expect("render"))
        };
        let (one, stats_one) = run(1);
        let (two, stats_two) = run(2);
        assert_eq!(one, two, "frames differ between 1 and 2 threads");
        assert_eq!(stats_one.rays, stats_two.rays);
        assert_eq!(stats_one.newton_runs, stats_two.newton_runs);
        assert!(stats_one.hits > 0 && stats_one.misses > 0, "{stats_one:?}");
    }

    /// At one sample per pixel the colour comes from the pixel-centre ray, traced once: one
    /// ray per pixel, and each hit pixel coloured from the normal of its geometry record.
    #[test]
    fn one_sample_per_pixel_traces_the_centre_ray_once() {
        let surface = octahedron_sphere(3, 1.0, 0);
        let tracer = Tracer::with_default_settings(&surface).expect("tracer");
        let (w, h) = (40u32, 30u32);
        let camera = Camera::frame(&surface.bounds(), Camera::DEFAULT_VIEW, 35.0, 4.0 / 3.0)
            .expect("camera");
        let mut settings = small_settings(Mode::by_name("normals").expect("normals"));
        (settings.width, settings.height, settings.spp) = (w, h, 1);
        let (frame, stats) = render(&tracer, &camera, &settings).expect("render");
        assert_eq!(stats.rays, u64::from(w * h));
        assert_eq!(stats.rays_per_pixel, 1.0);
        let hit_pixels = frame.geometry.iter().filter(|g| g.is_some()).count() as u64;
        assert_eq!(stats.hits, hit_pixels);
        for (k, g) in frame.geometry.iter().enumerate() {
            if let Some(g) = g {
                let normal = DVec3::from(g.normal.map(f64::from));
                let expected =
                    crate::render::modes::palette::srgb_to_linear(0.5 * (normal + DVec3::ONE));
                let rgb = DVec3::from(frame.rgb[k].map(f64::from));
                assert!(
                    (rgb - expected).abs().max_element() < 1e-6,
                    "pixel {k}: colour {rgb} from normal {normal}",
                );
            }
        }
        settings.spp = 4;
        let (_, stats) = render(&tracer, &camera, &settings).expect("render");
        assert_eq!(
            stats.rays,
            5 * u64::from(w * h),
            "centre ray plus four samples"
        );
    }

    /// The geometry record of a pixel is the exact hit on the pixel-centre ray, and its point
    /// and normal are the patch's there, rounded once to f32.
    #[test]
    fn pixel_geometry_lies_on_ray_and_patch() {
        let surface = octahedron_sphere(4, 2.0, 1);
        let tracer = Tracer::with_default_settings(&surface).expect("tracer");
        let (w, h) = (40u32, 30u32);
        let camera = Camera::frame(
            &surface.bounds(),
            Camera::DEFAULT_VIEW,
            40.0,
            f64::from(w) / f64::from(h),
        )
        .expect("camera");
        let mut settings = small_settings(Mode::by_name("normals").expect("normals"));
        (settings.width, settings.height, settings.spp) = (w, h, 1);
        let (frame, _) = render(&tracer, &camera, &settings).expect("render");
        let diag = surface.bounds().diagonal();
        assert!(
            tracer.root_tolerance() < crate::tolerance::G0_GAP_REL * diag,
            "root tolerance within the contract"
        );
        let mut checked = 0;
        for y in 0..h {
            for x in 0..w {
                let Some(g) = frame.geometry[(y * w + x) as usize] else {
                    continue;
                };
                let ray = camera.ray(
                    2.0 * (f64::from(x) + 0.5) / f64::from(w) - 1.0,
                    1.0 - 2.0 * (f64::from(y) + 0.5) / f64::from(h),
                    f64::from(w) / f64::from(h),
                );
                let patch = &surface.patches[g.hit.patch as usize];
                let jet = patch.jet(g.hit.u, g.hit.v);
                assert!(
                    (jet.p - ray.at(g.hit.t)).length() <= tracer.root_tolerance(),
                    "pixel ({x},{y}) off its ray"
                );
                assert!(
                    (jet.p - patch.eval(g.hit.u, g.hit.v)).length() <= 1e-15 * diag,
                    "pixel ({x},{y}) off its patch"
                );
                assert_eq!(
                    g.position,
                    jet.p.as_vec3().to_array(),
                    "pixel ({x},{y}) point"
                );
                let n = jet.normal();
                assert_eq!(g.normal, n.as_vec3().to_array(), "pixel ({x},{y}) normal");
                let c = jet.curvature().expect("curvature on a sphere");
                assert_eq!(g.gaussian, c.gaussian as f32, "pixel ({x},{y}) K");
                assert_eq!(g.mean, c.mean, "pixel ({x},{y}) H");
                assert_eq!(g.face, patch.face);
                checked += 1;
            }
        }
        assert!(checked > 100, "only {checked} pixels hit");
    }
}
