//! The built-in gallery (what `smoothlab` renders with no arguments): every registered scheme on
//! the deformed icosahedron, in zebra, isophote and curvature mode, from one shared camera, plus
//! one labelled sheet (rows = schemes, columns = modes) made by the figure grid
//! ([`crate::app::figure`]), with its common curvature range. Each cell's EXR (linear RGB,
//! curvature and the other geometry channels) is written beside its PNG.

use std::path::{Path, PathBuf};

use crate::app::figure::{
    CurvatureChoice, FigureJob, FigureMode, FigureSurface, View, framing_camera, render_figure,
};
use crate::error::Result;
use crate::files::{check_writable, create_folder};
use crate::mesh::Mesh;
use crate::mesh::generate::deformed_icosahedron;
use crate::render::curves::CurveOverlay;
use crate::render::job::Geometry;
use crate::render::modes::Mode;
use crate::render::output::{
    ExrCompression, OutputMeta, write_exr_with, write_png_with, write_rgb_png,
};
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

/// Compression of the gallery's EXRs: zlib, 60 % of RLE's size at this image size (2.75 MB
/// instead of 4.6 MB for a 320² curvature cell).
pub(crate) const GALLERY_EXR_COMPRESSION: ExrCompression = ExrCompression::Zip;

/// One rendered gallery image.
#[derive(Clone, Debug)]
pub struct GalleryImage {
    /// Scheme name.
    pub scheme: String,
    /// Mode name.
    pub mode: String,
    /// The PNG written.
    pub path: PathBuf,
    /// The EXR written beside it (linear RGB and the geometry channels: curvature values).
    pub exr: PathBuf,
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
pub(crate) fn render_gallery(out_dir: &Path) -> Result<Gallery> {
    render_gallery_with(out_dir, &GalleryOptions::default())
}

/// The gallery's modes, in column order.
pub(crate) const GALLERY_MODES: [&str; 3] = ["zebra", "isophote", "curvature"];

/// Renders the gallery into `out_dir` with `options`.
pub fn render_gallery_with(out_dir: &Path, options: &GalleryOptions) -> Result<Gallery> {
    create_folder(out_dir)?;
    let image_path = |scheme: &str, mode: &str| out_dir.join(format!("{scheme}-{mode}.png"));
    let sheet = out_dir.join("gallery.png");
    for spec in SCHEMES {
        for mode in GALLERY_MODES {
            let png = image_path(spec.name, mode);
            check_writable(&png)?;
            check_writable(&png.with_extension("exr"))?;
        }
    }
    check_writable(&sheet)?;
    let (positions, faces) = deformed_icosahedron();
    let (mesh, _) = Mesh::from_triangles(positions, faces)?;
    let surfaces = SCHEMES
        .iter()
        .map(|spec| {
            Ok(FigureSurface {
                label: spec.name.to_string(),
                surface: schemes::build(spec.name, &mesh, &[])?,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let all: Vec<_> = surfaces.iter().map(|s| &s.surface).collect();
    let camera = framing_camera(&all, 30.0, 1.0)?;
    let modes = GALLERY_MODES
        .iter()
        .map(|name| {
            let mode = Mode::by_name(name)?;
            Ok(FigureMode {
                label: name.to_string(),
                mode,
                curves: CurveOverlay::default(),
                surface: true,
                view: View::Common,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let job = FigureJob {
        title: "deformed icosahedron, every scheme".into(),
        mesh,
        surfaces,
        modes,
        camera,
        size: [options.size, options.size],
        spp: options.spp,
        curvature: CurvatureChoice::Common,
        transpose: false,
        geometry: Geometry::default(),
        theme: crate::render::theme::Theme::Dark,
        // The gallery's table lists each surface; its generated mesh loads as written.
        warnings: Vec::new(),
    };
    let figure = render_figure(&job)?;
    let mut images = Vec::with_capacity(figure.cells.len());
    for cell in figure.cells {
        let scheme = job.surfaces[cell.surface].surface.scheme.clone();
        let mode = GALLERY_MODES[cell.mode];
        let path = image_path(&scheme, mode);
        let exr = path.with_extension("exr");
        let meta = OutputMeta {
            command: Some(format!("smoothlab (default job): {scheme} {mode}")),
            camera: Some(camera),
        };
        write_png_with(&cell.frame, &path, &meta)?;
        write_exr_with(&cell.frame, &exr, GALLERY_EXR_COMPRESSION, &meta)?;
        images.push(GalleryImage {
            scheme,
            mode: mode.to_string(),
            path,
            exr,
            stats: cell.stats,
        });
    }
    write_rgb_png(&figure.sheet, &sheet)?;
    Ok(Gallery { images, sheet })
}

/// A plain-text table of the gallery's render statistics, one line per image.
pub(crate) fn gallery_table(gallery: &Gallery) -> String {
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
