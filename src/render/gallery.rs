//! The built-in gallery (what `smoothlab` renders with no arguments): every registered scheme on
//! the deformed icosahedron, in zebra, isophote and curvature mode, from one shared camera, plus
//! one side-by-side sheet (rows = schemes, columns = modes).
//!
//! The curvature colour range is chosen once — the median over the curved schemes of the
//! automatic range (95th percentile of |H| in view) — and then fixed for all schemes, so their
//! colours compare; a scheme with sharp creases saturates instead of washing out the others.

use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::mesh::generate::deformed_icosahedron;
use crate::render::bvh::SubdivisionCriterion;
use crate::render::camera::Camera;
use crate::render::film::{Frame, RenderSettings, auto_curvature_range, render};
use crate::render::intersect::{NewtonSettings, Tracer};
use crate::render::job::surface_samples;
use crate::render::modes::{CurvatureParams, CurvatureRange, Mode, Overlay};
use crate::render::output::{srgb8, write_png};
use crate::render::stats::RenderStats;
use crate::schemes::{self, SCHEMES};

/// Image size and sampling of the gallery.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GalleryOptions {
    /// Side of each (square) image in pixels.
    pub size: u32,
    /// Samples per pixel.
    pub spp: u32,
}

impl Default for GalleryOptions {
    fn default() -> Self {
        GalleryOptions { size: 320, spp: 4 }
    }
}

/// One rendered gallery image.
#[derive(Clone, Debug)]
pub struct GalleryImage {
    /// Scheme name.
    pub scheme: String,
    /// Mode name.
    pub mode: String,
    /// The PNG written.
    pub path: PathBuf,
    /// Its render statistics.
    pub stats: RenderStats,
}

/// What the gallery wrote.
#[derive(Clone, Debug)]
pub struct Gallery {
    /// Every single image, scheme-major.
    pub images: Vec<GalleryImage>,
    /// The side-by-side sheet.
    pub sheet: PathBuf,
}

/// Renders the gallery into `out_dir` with default options.
pub fn render_gallery(out_dir: &Path) -> Result<Gallery> {
    render_gallery_with(out_dir, &GalleryOptions::default())
}

/// The gallery's modes, in column order.
pub const GALLERY_MODES: [&str; 3] = ["zebra", "isophote", "curvature"];

/// Renders the gallery into `out_dir` with `options`.
pub fn render_gallery_with(out_dir: &Path, options: &GalleryOptions) -> Result<Gallery> {
    std::fs::create_dir_all(out_dir).map_err(|e| Error::io(out_dir, e))?;
    let (positions, faces) = deformed_icosahedron();
    let (mesh, _) = Mesh::from_triangles(positions, faces)?;
    let surfaces = SCHEMES
        .iter()
        .map(|spec| schemes::build(spec.name, &mesh, &[]))
        .collect::<Result<Vec<_>>>()?;
    let samples: Vec<_> = surfaces.iter().flat_map(surface_samples).collect();
    let camera = Camera::frame_points(&samples, Camera::DEFAULT_VIEW, 30.0, 1.0)?;
    let tracers = surfaces
        .iter()
        .map(|s| {
            Tracer::new(
                s,
                &SubdivisionCriterion::default(),
                NewtonSettings::default(),
            )
        })
        .collect::<Result<Vec<_>>>()?;
    let curvature = CurvatureParams::default();
    let percentile = match curvature.range {
        CurvatureRange::Auto { percentile } => percentile,
        CurvatureRange::Fixed(_) => 95.0,
    };
    let probe_settings = RenderSettings {
        width: options.size,
        height: options.size,
        ..RenderSettings::default()
    };
    // Schemes with nothing curved in view (flat) report the fallback range 1 and do not vote.
    let mut ranges: Vec<f64> = tracers
        .iter()
        .filter(|t| t.surface.patches.iter().any(|p| p.degree() != Some(1)))
        .map(|t| auto_curvature_range(t, &camera, &probe_settings, curvature.quantity, percentile))
        .collect();
    ranges.sort_by(f64::total_cmp);
    let half_range = ranges.get(ranges.len() / 2).copied().unwrap_or(1.0);
    let mut images = Vec::new();
    let mut frames: Vec<Frame> = Vec::new();
    for (surface, tracer) in surfaces.iter().zip(&tracers) {
        for mode_name in GALLERY_MODES {
            let mode = match Mode::by_name(mode_name)? {
                Mode::Curvature(p) => Mode::Curvature(CurvatureParams {
                    range: CurvatureRange::Fixed(half_range),
                    legend: true,
                    ..p
                }),
                other => other,
            };
            let settings = RenderSettings {
                width: options.size,
                height: options.size,
                spp: options.spp,
                mode,
                overlay: Overlay::default(),
                progress: false,
                ..RenderSettings::default()
            };
            let (frame, stats) = render(tracer, &camera, &settings)?;
            let path = out_dir.join(format!("{}-{mode_name}.png", surface.scheme));
            write_png(&frame, &path)?;
            images.push(GalleryImage {
                scheme: surface.scheme.clone(),
                mode: mode_name.to_string(),
                path,
                stats,
            });
            frames.push(frame);
        }
    }
    let sheet = out_dir.join("gallery.png");
    write_sheet(&frames, GALLERY_MODES.len(), options.size, &sheet)?;
    Ok(Gallery { images, sheet })
}

/// Tiles equally sized frames into rows of `columns`, with a 4-pixel dark gutter.
fn write_sheet(frames: &[Frame], columns: usize, size: u32, path: &Path) -> Result<()> {
    let rows = frames.len().div_ceil(columns).max(1) as u32;
    let gutter = 4u32;
    let cols = columns as u32;
    let (w, h) = (
        cols * size + (cols + 1) * gutter,
        rows * size + (rows + 1) * gutter,
    );
    let mut sheet = image::RgbImage::from_pixel(w, h, image::Rgb([24, 24, 24]));
    for (k, frame) in frames.iter().enumerate() {
        let (col, row) = ((k % columns) as u32, (k / columns) as u32);
        let (x0, y0) = (
            gutter + col * (size + gutter),
            gutter + row * (size + gutter),
        );
        let bytes = srgb8(frame);
        for y in 0..frame.height.min(size) {
            for x in 0..frame.width.min(size) {
                let i = ((y * frame.width + x) * 3) as usize;
                sheet.put_pixel(
                    x0 + x,
                    y0 + y,
                    image::Rgb([bytes[i], bytes[i + 1], bytes[i + 2]]),
                );
            }
        }
    }
    sheet
        .save_with_format(path, image::ImageFormat::Png)
        .map_err(|e| Error::Invalid(format!("{}: {e}", path.display())))
}

/// A plain-text table of the gallery's render statistics, one line per image.
pub fn gallery_table(gallery: &Gallery) -> String {
    let mut out = format!(
        "{:<10} {:<10} {:>8} {:>9} {:>8} {:>7} {:>6} {:>9}\n",
        "scheme", "mode", "patches", "leaves", "rays", "newton", "fails", "ms"
    );
    for image in &gallery.images {
        let s = &image.stats;
        out += &format!(
            "{:<10} {:<10} {:>8} {:>9} {:>8} {:>7.2} {:>6} {:>9.1}\n",
            image.scheme,
            image.mode,
            s.patches,
            s.leaves,
            s.rays,
            s.newton_iter_mean,
            s.newton_failures,
            s.render_ms
        );
    }
    out
}
