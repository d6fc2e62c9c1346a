//! Figures: grids of renders, rows × columns (surfaces × modes, or transposed), from one camera
//! and one size, with labels, one common curvature colour range and the curve-network overlay
//! per column. Used by `smoothlab figure SPEC.toml` ([`spec`]) and by the built-in gallery.
//!
//! The common automatic curvature range is the median, over the rows whose surface is curved
//! (not every patch linear), of each surface's automatic range (the chosen percentile of |value|
//! in view): one fixed range for all cells so colours compare, and a scheme with sharp creases
//! saturates instead of washing out the others.

pub(crate) mod shard;
pub(crate) mod sheet;
pub(crate) mod spec;

use std::sync::Arc;

use crate::error::Result;
use crate::mesh::Mesh;
use crate::render::camera::{Camera, Projection};
use crate::render::curves::CurveOverlay;
use crate::render::film::{Frame, RenderSettings};
use crate::render::job::{Geometry, JobTracer, mode_for_mesh};
use crate::render::modes::{Mode, Overlay};
use crate::render::stats::RenderStats;
use crate::render::theme::Theme;
use crate::surface::Surface;

pub(crate) use sheet::{SheetLabels, compose, compose_images, svg, svg_images};

/// One surface of a figure (a row, or a column when transposed).
#[derive(Clone, Debug)]
pub struct FigureSurface {
    /// Label.
    pub label: String,
    /// The surface.
    pub surface: Surface,
}

/// Where a cell looks from.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum View {
    /// The figure's common camera.
    #[default]
    Common,
    /// Orthographic, perpendicular to the chord plane of mesh edge `edge` (the plane through
    /// the chord and the mean normal of the edge's faces), so the boundary curve's bending in
    /// that plane is seen undistorted [HB00 Fig. 14 bottom].
    EdgeSide {
        /// Mesh edge index.
        edge: usize,
    },
}

/// One way of looking at every surface (a column, or a row when transposed).
#[derive(Clone, Debug, PartialEq)]
pub struct FigureMode {
    /// Label.
    pub label: String,
    /// Shading mode; a curvature mode's range is replaced by the figure's.
    pub mode: Mode,
    /// Curve tubes to draw.
    pub curves: CurveOverlay,
    /// Trace the surface.
    pub surface: bool,
    /// Camera of these cells.
    pub view: View,
}

/// The curvature range of a figure's curvature cells.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CurvatureChoice {
    /// This half-range for every cell.
    Fixed(f64),
    /// The common automatic range (see the module docs).
    Common,
}

/// Everything a figure needs.
#[derive(Clone, Debug)]
pub struct FigureJob {
    /// Title line.
    pub title: String,
    /// The mesh all surfaces were built on.
    pub mesh: Mesh,
    /// Surfaces.
    pub surfaces: Vec<FigureSurface>,
    /// Modes.
    pub modes: Vec<FigureMode>,
    /// Common camera.
    pub camera: Camera,
    /// Cell size.
    pub size: [u32; 2],
    /// Samples per pixel.
    pub spp: u32,
    /// Curvature range.
    pub curvature: CurvatureChoice,
    /// Surfaces as columns and modes as rows.
    pub transpose: bool,
    /// The tracer of every surface: exact (BVH settings and leaf budget) or tessellated.
    pub geometry: Geometry,
    /// Colours of the cells' backgrounds and legends and of the sheet.
    pub theme: Theme,
    /// What loading repaired in the mesh and what each construction changed (e.g. sharp
    /// edges at spikes), one line each, for the command to print.
    pub warnings: Vec<String>,
}

/// One rendered cell.
#[derive(Clone, Debug)]
pub struct FigureCell {
    /// Index of its surface.
    pub surface: usize,
    /// Index of its mode.
    pub mode: usize,
    /// The image.
    pub frame: Frame,
    /// Its statistics.
    pub stats: RenderStats,
}

/// A rendered figure.
#[derive(Clone, Debug)]
pub struct Figure {
    /// Cells in sheet order (row-major).
    pub cells: Vec<FigureCell>,
    /// The labelled sheet.
    pub sheet: image::RgbImage,
    /// The same sheet as SVG (cells embedded as PNG, labels as text).
    pub svg: String,
    /// The curvature half-range used, if any cell shows curvature.
    pub curvature_half_range: Option<f64>,
}

/// The camera that frames all `surfaces` from the default direction.
pub(crate) fn framing_camera(surfaces: &[&Surface], fov: f64, aspect: f64) -> Result<Camera> {
    let samples = crate::render::job::SurfaceSamples::new(surfaces);
    Camera::frame_points(&samples, Camera::DEFAULT_VIEW, fov, aspect)
}

/// The side camera of [`View::EdgeSide`] for an image of aspect `aspect`.
pub(crate) fn edge_side_camera(mesh: &Mesh, edge: usize, aspect: f64) -> Result<Camera> {
    let edges = mesh.edges();
    let e = edges.get(edge).ok_or_else(|| {
        crate::Error::Invalid(format!(
            "edge {edge} does not exist (the mesh has {} edges)",
            edges.len()
        ))
    })?;
    let p = mesh.positions();
    let (a, b) = (p[e.a as usize], p[e.b as usize]);
    let mut normal = mesh.face_normal(e.faces.0);
    if let Some(f) = e.faces.1 {
        normal += mesh.face_normal(f);
    }
    let chord = b - a;
    let side = chord.cross(normal).normalize_or_zero();
    let up = side.cross(chord).normalize_or_zero();
    let length = chord.length();
    let centre = 0.5 * (a + b);
    // The chord spans 85 % of the width.
    let height = length / 0.85 / aspect;
    Camera::look_at(
        centre + side * (4.0 * length),
        centre,
        up,
        Projection::Orthographic { height },
    )
}

/// The median of the automatic curvature ranges of the curved surfaces' tracers `curved` (1
/// if none is curved).
fn common_curvature_range(
    curved: &[&JobTracer<'_>],
    camera: &Camera,
    settings: &RenderSettings,
    mode: &Mode,
) -> f64 {
    let mut ranges: Vec<f64> = curved
        .iter()
        .filter_map(|t| t.measure_scale(mode, camera, settings.width, settings.height))
        .collect();
    ranges.sort_by(f64::total_cmp);
    ranges.get(ranges.len() / 2).copied().unwrap_or(1.0)
}

/// Whether `surface` is curved (not every patch linear): only curved surfaces take part in the
/// common curvature range.
fn is_curved(surface: &Surface) -> bool {
    surface.patches.iter().any(|p| p.degree() != Some(1))
}

impl FigureJob {
    /// Number of cells: surfaces × modes.
    pub fn cell_count(&self) -> usize {
        self.surfaces.len() * self.modes.len()
    }

    /// The surface and mode of the cell at sheet position `k` (row-major).
    pub fn cell(&self, k: usize) -> (usize, usize) {
        if self.transpose {
            let n = self.surfaces.len().max(1);
            (k % n, k / n)
        } else {
            let n = self.modes.len().max(1);
            (k / n, k % n)
        }
    }

    /// The labels of the sheet, the curvature modes' with `±half_range`.
    pub fn labels(&self, half_range: Option<f64>) -> SheetLabels {
        let surfaces: Vec<String> = self.surfaces.iter().map(|s| s.label.clone()).collect();
        let modes: Vec<(String, bool)> = self
            .modes
            .iter()
            .map(|m| (m.label.clone(), m.mode.has_scale()))
            .collect();
        sheet_labels(&self.title, surfaces, &modes, self.transpose, half_range)
    }
}

/// The labels of a sheet of `surfaces` × `modes` (label, whether it shows curvature): the
/// curvature modes' labels end in `±half_range` when it is known.
pub(crate) fn sheet_labels(
    title: &str,
    surfaces: Vec<String>,
    modes: &[(String, bool)],
    transpose: bool,
    half_range: Option<f64>,
) -> SheetLabels {
    let modes: Vec<String> = modes
        .iter()
        .map(|(label, curvature)| match (curvature, half_range) {
            (true, Some(r)) => format!("{label} ±{}", short_number(r)),
            _ => label.clone(),
        })
        .collect();
    let (rows, columns) = if transpose {
        (modes, surfaces)
    } else {
        (surfaces, modes)
    };
    SheetLabels {
        title: title.to_string(),
        rows,
        columns,
    }
}

/// Renders every cell of `job` and composes the labelled sheet.
pub fn render_figure(job: &FigureJob) -> Result<Figure> {
    let all: Vec<usize> = (0..job.cell_count()).collect();
    let (cells, half_range) = render_cells(job, &all)?;
    let labels = job.labels(half_range);
    let frames: Vec<&Frame> = cells.iter().map(|c| &c.frame).collect();
    let sheet = compose(&frames, &labels, job.size, job.theme);
    let svg = svg(&frames, &labels, job.size, job.theme)?;
    Ok(Figure {
        cells,
        sheet,
        svg,
        curvature_half_range: half_range,
    })
}

/// Renders the cells of `job` at the sheet positions `wanted` (ascending), each exactly as
/// [`render_figure`] renders it. A surface's tracer is built only when one of its cells is
/// wanted or when the common automatic curvature range needs it (a wanted cell shows
/// curvature). Returns the cells in sheet order and the curvature half-range: known when the
/// figure has a curvature mode and the range is fixed or a wanted cell shows curvature.
pub(crate) fn render_cells(
    job: &FigureJob,
    wanted: &[usize],
) -> Result<(Vec<FigureCell>, Option<f64>)> {
    let [w, h] = job.size;
    let aspect = f64::from(w) / f64::from(h);
    let count = job.cell_count();
    if let Some(&k) = wanted.iter().find(|&&k| k >= count) {
        return Err(crate::Error::Invalid(format!(
            "figure cell {k} does not exist (the figure has {count} cells)"
        )));
    }
    let first_curvature = job.modes.iter().find(|m| m.mode.has_scale());
    let needs_range = matches!(job.curvature, CurvatureChoice::Common)
        && wanted
            .iter()
            .any(|&k| job.modes[job.cell(k).1].mode.has_scale());
    // The tracers, in surface order, of the surfaces this call needs.
    let mut needed = vec![false; job.surfaces.len()];
    for &k in wanted {
        needed[job.cell(k).0] = true;
    }
    if needs_range {
        for (n, s) in needed.iter_mut().zip(&job.surfaces) {
            *n |= is_curved(&s.surface);
        }
    }
    // What a mode other than curvature chooses from the view (the zebra stripe count) is
    // chosen once, for the first curved surface, so that every cell of the mode shows the
    // same stripes.
    let reference = job.surfaces.iter().position(|s| is_curved(&s.surface));
    let chooses = |m: &Mode| m.chosen_from_view() && !m.has_scale();
    if let Some(r) = reference
        && wanted
            .iter()
            .any(|&k| chooses(&job.modes[job.cell(k).1].mode))
    {
        needed[r] = true;
    }
    let tracers = job
        .surfaces
        .iter()
        .zip(&needed)
        .map(|(s, n)| {
            n.then(|| JobTracer::new(&s.surface, &job.geometry))
                .transpose()
        })
        .collect::<Result<Vec<_>>>()?;
    let base = RenderSettings {
        width: w,
        height: h,
        spp: job.spp,
        overlay: Overlay::default(),
        progress: false,
        background: job.theme.background(),
        theme: job.theme,
        ..RenderSettings::default()
    };
    let half_range = match (first_curvature, job.curvature) {
        (None, _) => None,
        (Some(_), CurvatureChoice::Fixed(r)) => Some(r),
        (Some(m), CurvatureChoice::Common) if needs_range => {
            let curved: Vec<&JobTracer<'_>> = tracers
                .iter()
                .zip(&job.surfaces)
                .filter(|(_, s)| is_curved(&s.surface))
                .filter_map(|(t, _)| t.as_ref())
                .collect();
            Some(common_curvature_range(&curved, &job.camera, &base, &m.mode))
        }
        (Some(_), CurvatureChoice::Common) => None,
    };
    let mut cameras = Vec::with_capacity(job.modes.len());
    for m in &job.modes {
        cameras.push(match m.view {
            View::Common => job.camera,
            View::EdgeSide { edge } => edge_side_camera(&job.mesh, edge, aspect)?,
        });
    }
    let mut modes = Vec::with_capacity(job.modes.len());
    for (m, camera) in job.modes.iter().zip(&cameras) {
        modes.push(match reference.and_then(|r| tracers[r].as_ref()) {
            Some(tracer) if chooses(&m.mode) => tracer.pin_view(&m.mode, camera, w, h),
            _ => m.mode.clone(),
        });
    }
    let mut cells = Vec::with_capacity(wanted.len());
    let bar = crate::progress::bar(
        wanted.len() as u64,
        "figure {bar:40} {pos}/{len} cells {elapsed} {msg}",
    );
    for &k in wanted {
        let (s, m) = job.cell(k);
        let spec = &job.modes[m];
        bar.set_message(format!("{} / {}", job.surfaces[s].label, spec.label));
        let mode = match half_range {
            Some(r) if spec.mode.has_scale() => spec.mode.with_scale(r),
            _ => modes[m].clone(),
        };
        let mode = mode_for_mesh(&mode, &job.mesh);
        let surface = &job.surfaces[s].surface;
        let tracer = tracers[s].as_ref().ok_or_else(|| {
            crate::Error::Invalid(format!("figure cell {k}: surface {s} has no tracer"))
        })?;
        let curves: Option<Arc<_>> = spec.curves.tubes(surface, &job.mesh)?;
        let settings = RenderSettings {
            mode,
            surface: spec.surface,
            curves,
            ..base.clone()
        };
        let (frame, stats) = tracer.render_frame(&cameras[m], &settings)?;
        cells.push(FigureCell {
            surface: s,
            mode: m,
            frame,
            stats,
        });
        bar.inc(1);
    }
    bar.finish_and_clear();
    Ok((cells, half_range))
}

/// A number with three significant digits for labels.
pub(crate) fn short_number(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let digits = (2 - x.abs().log10().floor() as i32).clamp(0, 6) as usize;
    format!("{x:.digits$}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_numbers_keep_three_digits() {
        assert_eq!(short_number(0.012345), "0.0123");
        assert_eq!(short_number(1.5), "1.50");
        assert_eq!(short_number(123.4), "123");
    }

    #[test]
    fn the_side_camera_looks_across_the_chord() {
        let mesh = crate::testing::mesh(crate::mesh::generate::icosahedron());
        let camera = edge_side_camera(&mesh, 0, 1.0).expect("camera");
        let e = mesh.edges()[0];
        let chord = mesh.positions()[e.b as usize] - mesh.positions()[e.a as usize];
        assert!(camera.forward().dot(chord).abs() < 1e-12 * chord.length());
        assert!(edge_side_camera(&mesh, 10_000, 1.0).is_err());
    }
}
