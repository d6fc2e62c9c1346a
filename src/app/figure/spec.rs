//! Figure spec files (TOML) for `smoothlab figure SPEC.toml`: a mesh, schemes with parameters,
//! modes with parameters and curve overlays, one camera, one cell size and sample count, one
//! curvature range, an output stem. Writes `STEM.png` (the labelled grid), `STEM.svg` (the
//! same grid with the cells embedded as PNG and the labels as vector text) and one
//! `STEM-<row>-<column>-<scheme>-<mode>.exr` per cell (the channels of the render command).
//!
//! ```toml
//! title = "G1 schemes"                  # optional title line
//! mesh = "deformed-icosahedron"         # a scenes/ mesh name, or an OBJ path (relative to this file)
//! crease_angle = 40                     # optional: edges turning by more than 40° are sharp
//! output = "../../results/figures/g1"   # stem, relative to this file (as every path here)
//! size = [256, 256]                     # per cell
//! spp = 4
//! exr = true                            # one EXR per cell
//! transpose = false                     # true: schemes as columns, modes as rows
//! curvature_range = "auto"              # or a number: fixed half-range of every curvature cell
//! theme = "dark"                        # or "paper": white ground, dark text, grey-zero curvature map
//! [camera]                              # as in scene files; omitted: frames all surfaces
//! fov = 30
//! [bvh]                                 # as in scene files: every cell's BVH and leaf budget
//! max_leaves = 16777216
//! [[schemes]]
//! name = "hb"
//! label = "HB00"                        # optional; default "name k=v ..."
//! params = { gamma0 = -3.7, gamma1 = 4.6, gamma2 = 0.1 }
//! [[modes]]
//! name = "zebra"
//! params = { stripes = 12 }             # keys of the mode's scene section ([zebra] etc.)
//! curves = true                         # boundary curves as blue tubes
//! control_polygons = true               # their control polygons as red tubes
//! surface = true                        # false: the tubes alone
//! curve_radius = 0.003                  # relative to the bounding-box diagonal
//! curve_edge = 0                        # only this mesh edge's curves
//! view = "common"                       # or "edge-side": across curve_edge's chord plane
//! ```

use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::app::figure::{
    CurvatureChoice, Figure, FigureJob, FigureMode, FigureSurface, View, framing_camera,
    render_figure,
};
use crate::app::scene::{BvhSection, CameraSection, file_beside};
use crate::app::toml_input::{self, exact};
use crate::error::{Error, Problem, Result};
use crate::files::{check_distinct, check_writable, create_folder, write_atomic};
use crate::mesh::generate::{SCENES, SHARP_SCENES};
use crate::mesh::{LoadOptions, Mesh, check_crease_angle};
use crate::render::camera::Projection;
use crate::render::curves::CurveOverlay;
use crate::render::job::DEFAULT_FOV;
use crate::render::job::{
    DEFAULT_CELL_SIZE, DEFAULT_SPP, MAX_CELL_SIDE, MAX_CELL_SPP, check_size, check_spp,
};
use crate::render::modes::keys::{one_of, positive};
use crate::render::modes::{Mode, keys_of};
use crate::render::output::{
    check_output_name, output_stem, with_suffix, write_exr, write_rgb_png,
};
use crate::render::theme::Theme;
use crate::schemes;

/// A figure spec as written.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FigureSpec {
    /// Title line.
    pub title: Option<String>,
    /// A scenes/ mesh name or an OBJ path relative to the spec file.
    pub mesh: String,
    /// Crease angle in degrees (edges whose faces turn by more are sharp, see
    /// [`crate::mesh::LoadOptions::crease_angle`]); unset, no edge is.
    pub crease_angle: Option<f64>,
    /// Refuse every repair of a mesh file (see [`crate::mesh::LoadOptions::strict`]; default
    /// false).
    pub strict: Option<bool>,
    /// Output stem (`.png` appended; a `.png` or `.exr` ending is dropped first), relative to
    /// the spec file once loaded by [`FigureSpec::load`].
    pub output: PathBuf,
    /// Cell size in pixels.
    #[serde(default, deserialize_with = "exact")]
    pub size: Option<[u32; 2]>,
    /// Samples per pixel.
    pub spp: Option<u32>,
    /// Write one EXR per cell (default true).
    pub exr: Option<bool>,
    /// Schemes as columns, modes as rows.
    pub transpose: Option<bool>,
    /// "auto" (common automatic range) or a fixed half-range.
    pub curvature_range: Option<toml::Value>,
    /// Colours of the cells and the sheet: "dark" (default) or "paper" (see
    /// [`crate::render::theme::Theme`]).
    pub theme: Option<String>,
    /// The common camera.
    #[serde(default)]
    pub camera: CameraSection,
    /// BVH subdivision and leaf budget of every cell's tracer (the scene file's `[bvh]`).
    #[serde(default)]
    pub bvh: BvhSection,
    /// The schemes.
    pub schemes: Vec<SchemeEntry>,
    /// The modes.
    pub modes: Vec<ModeEntry>,
}

/// `[[schemes]]`
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SchemeEntry {
    /// Registered scheme name.
    pub name: String,
    /// Label (default: name and parameters).
    pub label: Option<String>,
    /// Scheme parameters.
    #[serde(default)]
    pub params: toml::Table,
}

/// `[[modes]]`
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModeEntry {
    /// Mode name.
    pub name: String,
    /// Label (default: the mode name).
    pub label: Option<String>,
    /// Keys of the mode's scene section.
    #[serde(default)]
    pub params: toml::Table,
    /// Boundary curves as tubes.
    pub curves: Option<bool>,
    /// Control polygons as tubes.
    pub control_polygons: Option<bool>,
    /// Trace the surface.
    pub surface: Option<bool>,
    /// Tube radius relative to the bounding-box diagonal.
    pub curve_radius: Option<f64>,
    /// Only this mesh edge's curves.
    pub curve_edge: Option<usize>,
    /// "common" or "edge-side".
    pub view: Option<String>,
}

/// Text of a TOML parameter value as the scheme registry reads it.
fn param_text(value: &toml::Value) -> String {
    match value {
        toml::Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

impl FigureSpec {
    /// Parses spec text; errors are one line naming the line, column and key (see
    /// [`toml_input::one_line`]).
    pub fn parse(text: &str) -> Result<FigureSpec> {
        toml_input::parse(text, "figure spec")
    }

    /// Reads a spec file; errors name the file, line, column and key. A relative `output` is
    /// made relative to the spec file's folder, like its mesh path and the modes'
    /// `environment` maps; an output that names a folder (`out/`) is an error.
    pub fn load(path: &Path) -> Result<FigureSpec> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
        let mut spec: FigureSpec =
            toml_input::parse(&text, &path.display().to_string()).map_err(|e| {
                if toml_input::has_top_level_key(&text, &["scheme", "render"]) {
                    Error::Invalid(format!(
                        "this is a scene file ([scheme], [render]), not a figure spec: run \
                         `smoothlab render {}`",
                        path.display()
                    ))
                    .within(path.display().to_string())
                } else {
                    e
                }
            })?;
        let dir = path.parent().unwrap_or(Path::new(""));
        if spec.output.is_relative() {
            spec.output = dir.join(&spec.output);
        }
        check_output_name(&spec.output)
            .map_err(|e| e.within(format!("{}: output", path.display())))?;
        for mode in &mut spec.modes {
            for key in keys_of(&mode.name) {
                if let Some(toml::Value::String(file)) = mode.params.get_mut(key.name) {
                    *file = file_beside(key, file, dir);
                }
            }
        }
        Ok(spec)
    }

    /// The spec at `path` ([`FigureSpec::load`]) in `theme` instead of its own `theme` key
    /// when given (`figure --theme`).
    pub fn load_themed(path: &Path, theme: Option<Theme>) -> Result<FigureSpec> {
        let mut spec = FigureSpec::load(path)?;
        if let Some(theme) = theme {
            spec.theme = Some(theme.name().to_string());
        }
        Ok(spec)
    }

    /// The mesh: a scenes/ name, else a mesh file (OBJ, PLY, OFF, STL) relative to `dir`,
    /// with what loading repaired (warnings, one line each).
    pub fn load_mesh(&self, dir: &Path) -> Result<(Mesh, Vec<String>)> {
        let mut options = LoadOptions {
            strict: self.strict.unwrap_or(false),
            ..Default::default()
        };
        if let Some(degrees) = self.crease_angle {
            options.crease_angle =
                Some(check_crease_angle(degrees).map_err(|reason| {
                    Error::config("crease_angle", Problem::Refused { reason })
                })?);
        }
        match (
            SCENES
                .iter()
                .chain(&SHARP_SCENES)
                .find(|s| s.name == self.mesh),
            self.mesh_file(dir),
        ) {
            (Some(scene), _) => {
                let (positions, faces) = (scene.build)();
                let (mesh, report) = Mesh::from_triangles_with(positions, faces, &options)?;
                Ok((mesh, report.warnings))
            }
            (None, path) => {
                let (mesh, report) = Mesh::load_with(&path, &options)?;
                Ok((mesh, report.warnings))
            }
        }
    }

    /// The mesh file `mesh` names, relative to `dir` (unless it names a scenes/ mesh).
    fn mesh_file(&self, dir: &Path) -> PathBuf {
        let path = Path::new(&self.mesh);
        if path.is_relative() {
            dir.join(path)
        } else {
            path.to_path_buf()
        }
    }

    /// The files a run of the spec at `path` reads, each with its part for messages: the
    /// spec, its mesh file and the modes' environment maps. The outputs must be none of them
    /// ([`check_distinct`]).
    pub fn input_files(&self, path: &Path) -> Vec<(&'static str, PathBuf)> {
        let dir = path.parent().unwrap_or(Path::new(""));
        let mut files = vec![("the figure spec", path.to_path_buf())];
        if !SCENES
            .iter()
            .chain(&SHARP_SCENES)
            .any(|s| s.name == self.mesh)
        {
            files.push(("the mesh", self.mesh_file(dir)));
        }
        for mode in &self.modes {
            for key in keys_of(&mode.name) {
                if let Some(toml::Value::String(file)) = mode.params.get(key.name)
                    && key.names_file(file)
                {
                    files.push((key.what_an, PathBuf::from(file)));
                }
            }
        }
        files
    }

    /// Checks, before any work, that none of `outputs` is an input of the spec at `path`
    /// ([`FigureSpec::input_files`]) or another of the outputs.
    pub fn check_outputs(&self, path: &Path, outputs: &[&Path]) -> Result<()> {
        let inputs = self.input_files(path);
        let read: Vec<(&str, &Path)> = inputs.iter().map(|(r, p)| (*r, p.as_path())).collect();
        let written: Vec<(&str, &Path)> = outputs.iter().map(|p| ("an output", *p)).collect();
        check_distinct(&read, &written)
    }

    /// The mode of entry `k` with its parameters, checked through the scene-file sections.
    fn figure_mode(&self, k: usize) -> Result<FigureMode> {
        let entry = &self.modes[k];
        let context = |e: Error| e.within(format!("modes[{k}] ({})", entry.name));
        let mut mode = Mode::by_name(&entry.name).map_err(context)?;
        if keys_of(&entry.name).is_empty() && !entry.params.is_empty() {
            return Err(context(Error::config(
                format!("mode '{}'", entry.name),
                Problem::Other {
                    text: "takes no params".into(),
                },
            )));
        }
        mode.configure(&entry.params).map_err(context)?;
        let mut curves = CurveOverlay {
            curves: entry.curves.unwrap_or(false),
            control_polygons: entry.control_polygons.unwrap_or(false),
            edge: entry.curve_edge,
            ..CurveOverlay::default()
        };
        if let Some(r) = entry.curve_radius {
            curves.radius_rel = positive("curve_radius", r).map_err(context)?;
        }
        let surface = entry.surface.unwrap_or(true);
        if !surface && !curves.enabled() {
            return Err(context(Error::config(
                "surface",
                Problem::Needs {
                    value: Some("false".into()),
                    needed: "curves or control_polygons".into(),
                },
            )));
        }
        let view = match one_of(
            "view",
            entry.view.as_deref().unwrap_or("common"),
            &["common", "edge-side"],
        )
        .map_err(context)?
        {
            "common" => View::Common,
            _ => View::EdgeSide {
                edge: entry.curve_edge.unwrap_or(0),
            },
        };
        Ok(FigureMode {
            label: entry.label.clone().unwrap_or_else(|| entry.name.clone()),
            mode,
            curves,
            surface,
            view,
        })
    }

    /// The figure job: builds the mesh and every scheme, resolves modes and the camera.
    pub fn job(&self, dir: &Path) -> Result<FigureJob> {
        if self.schemes.is_empty() || self.modes.is_empty() {
            return Err(Error::Invalid(
                "figure spec: needs at least one [[schemes]] and one [[modes]]".into(),
            ));
        }
        let (mesh, mut warnings) = self.load_mesh(dir)?;
        let mut surfaces = Vec::with_capacity(self.schemes.len());
        for (k, entry) in self.schemes.iter().enumerate() {
            let params: Vec<(String, String)> = entry
                .params
                .iter()
                .map(|(n, v)| (n.clone(), param_text(v)))
                .collect();
            let surface = schemes::build(&entry.name, &mesh, &params)
                .map_err(|e| e.within(format!("schemes[{k}] ({})", entry.name)))?;
            warnings.extend(surface.warnings.iter().cloned());
            warnings.extend(crate::app::render::resolution_warning(&surface, &mesh));
            let label = entry.label.clone().unwrap_or_else(|| {
                let mut l = entry.name.clone();
                for (n, v) in &params {
                    l += &format!(" {n}={v}");
                }
                l
            });
            surfaces.push(FigureSurface { label, surface });
        }
        let modes = (0..self.modes.len())
            .map(|k| self.figure_mode(k))
            .collect::<Result<Vec<_>>>()?;
        let size = self.size.unwrap_or(DEFAULT_CELL_SIZE);
        check_size("figure spec: size", size[0], size[1], MAX_CELL_SIDE)?;
        let spp = self.spp.unwrap_or(DEFAULT_SPP);
        check_spp("figure spec: spp", spp, MAX_CELL_SPP)?;
        let geometry = self.bvh.geometry().map_err(|e| e.within("figure spec"))?;
        let curvature = match &self.curvature_range {
            None => CurvatureChoice::Common,
            Some(toml::Value::String(s)) if s == "auto" => CurvatureChoice::Common,
            Some(toml::Value::Float(x)) if *x > 0.0 && x.is_finite() => CurvatureChoice::Fixed(*x),
            Some(toml::Value::Integer(x)) if *x > 0 => CurvatureChoice::Fixed(*x as f64),
            Some(other) => {
                return Err(Error::config(
                    "curvature_range",
                    Problem::Neither {
                        value: other.to_string(),
                        forms: "\"auto\" nor a positive number".into(),
                    },
                )
                .within("figure spec"));
            }
        };
        let theme = match &self.theme {
            Some(name) => Theme::by_name("figure spec: theme", name)?,
            None => Theme::default(),
        };
        let aspect = f64::from(size[0]) / f64::from(size[1]);
        let camera = self.camera(&surfaces, aspect)?;
        Ok(FigureJob {
            title: self.title.clone().unwrap_or_default(),
            mesh,
            surfaces,
            modes,
            camera,
            size,
            spp,
            curvature,
            transpose: self.transpose.unwrap_or(false),
            geometry,
            theme,
            warnings,
        })
    }

    /// The common camera: the spec's eye, else automatic framing of all surfaces.
    fn camera(
        &self,
        surfaces: &[FigureSurface],
        aspect: f64,
    ) -> Result<crate::render::camera::Camera> {
        let c = &self.camera;
        let fov = c.fov.unwrap_or(DEFAULT_FOV);
        let all: Vec<&crate::surface::Surface> = surfaces.iter().map(|s| &s.surface).collect();
        let framed = framing_camera(&all, fov, aspect)?;
        let camera = match c.eye {
            Some(eye) => crate::render::camera::Camera::look_at(
                glam::DVec3::from_array(eye),
                c.target.map_or(framed.target, glam::DVec3::from_array),
                c.up.map_or(glam::DVec3::Y, glam::DVec3::from_array),
                Projection::Perspective { fov_deg: fov },
            )?,
            None => framed,
        };
        if c.ortho.unwrap_or(false) {
            camera.orthographic_of(fov)
        } else {
            Ok(camera)
        }
    }
}

/// What `smoothlab figure` wrote.
#[derive(Clone, Debug)]
pub(crate) struct FigureFiles {
    /// The labelled grid.
    pub png: PathBuf,
    /// The labelled grid as SVG.
    pub svg: PathBuf,
    /// One EXR per cell (empty when `exr = false`).
    pub exrs: Vec<PathBuf>,
    /// The rendered figure.
    pub figure: Figure,
    /// The job's warnings ([`FigureJob::warnings`]).
    pub warnings: Vec<String>,
}

/// File-name-safe form of a label.
fn slug(text: &str) -> String {
    text.chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
        .collect()
}

impl FigureSpec {
    /// The SVG of the spec: `STEM.svg` beside `STEM.png`.
    pub fn svg_file(&self) -> PathBuf {
        with_suffix(&output_stem(&self.output), "svg")
    }

    /// The files of the spec: the sheet `STEM.png` and, unless `exr = false`, one
    /// `STEM-<row>-<column>-<scheme>-<mode>.exr` per cell in sheet order (row-major). The stem
    /// is [`output_stem`] of `output`.
    pub fn output_files(&self) -> (PathBuf, Vec<PathBuf>) {
        let stem = output_stem(&self.output);
        let png = with_suffix(&stem, "png");
        if !self.exr.unwrap_or(true) {
            return (png, Vec::new());
        }
        let base = self.stem_name();
        let exrs = self
            .cell_suffixes()
            .iter()
            .map(|suffix| stem.with_file_name(format!("{base}{suffix}.exr")))
            .collect();
        (png, exrs)
    }

    /// The file name of the output stem (`figure` when it has none).
    pub fn stem_name(&self) -> String {
        output_stem(&self.output)
            .file_name()
            .map_or("figure".into(), |s| s.to_string_lossy().into_owned())
    }

    /// What follows the stem in the name of each cell's file, in sheet order (row-major):
    /// `-<row>-<column>-<scheme>-<mode>`.
    pub fn cell_suffixes(&self) -> Vec<String> {
        let transpose = self.transpose.unwrap_or(false);
        let (rows, columns) = if transpose {
            (self.modes.len(), self.schemes.len())
        } else {
            (self.schemes.len(), self.modes.len())
        };
        (0..rows)
            .flat_map(|row| (0..columns).map(move |column| (row, column)))
            .map(|(row, column)| {
                let (scheme, mode) = if transpose {
                    (column, row)
                } else {
                    (row, column)
                };
                format!(
                    "-{row}-{column}-{}-{}",
                    slug(&self.schemes[scheme].name),
                    slug(&self.modes[mode].name)
                )
            })
            .collect()
    }
}

/// Renders the spec at `path` (in `theme` instead of the spec's when given) and writes its
/// files; every output path is checked (its folder created if missing) before rendering.
pub(crate) fn run_figure_spec(path: &Path, theme: Option<Theme>) -> Result<FigureFiles> {
    let spec = FigureSpec::load_themed(path, theme)?;
    let (png, exrs) = spec.output_files();
    let svg = spec.svg_file();
    if let Some(folder) = png.parent() {
        create_folder(folder)?;
    }
    for file in [&png, &svg].into_iter().chain(&exrs) {
        check_writable(file)?;
    }
    let outputs: Vec<&Path> = [&png, &svg]
        .into_iter()
        .chain(&exrs)
        .map(PathBuf::as_path)
        .collect();
    spec.check_outputs(path, &outputs)?;
    let dir = path.parent().unwrap_or(Path::new(""));
    let job = spec
        .job(dir)
        .map_err(|e| e.within(path.display().to_string()))?;
    let figure = render_figure(&job)?;
    write_rgb_png(&figure.sheet, &png)?;
    write_atomic(&svg, figure.svg.as_bytes())?;
    // Cells come in sheet order, as the names do.
    for (cell, exr) in figure.cells.iter().zip(&exrs) {
        write_exr(&cell.frame, exr)?;
    }
    Ok(FigureFiles {
        png,
        svg,
        exrs,
        figure,
        warnings: job.warnings,
    })
}

/// One summary per figure for the terminal.
pub(crate) fn figure_summary(files: &FigureFiles) -> String {
    let mut out = format!("wrote {}, {}", files.png.display(), files.svg.display());
    if !files.exrs.is_empty() {
        out += &format!(" and {} EXR cells", files.exrs.len());
    }
    if let Some(r) = files.figure.curvature_half_range {
        out += &format!("; curvature half-range {r:.4}");
    }
    let ms: f64 = files.figure.cells.iter().map(|c| c.stats.render_ms).sum();
    out += &format!("; {:.0} ms rendering\n", ms);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const SPEC: &str = r#"
        mesh = "icosahedron"
        output = "x"
        size = [16, 16]
        [[schemes]]
        name = "loop94"
        params = { alpha = 1, beta = 0.1 }
        [[modes]]
        name = "zebra"
        params = { stripes = 8 }
        curves = true
    "#;

    #[test]
    fn a_spec_becomes_a_job() {
        let job = FigureSpec::parse(SPEC)
            .expect("spec")
            .job(Path::new(""))
            .expect("job");
        assert_eq!(job.surfaces[0].label, "loop94 alpha=1 beta=0.1");
        assert_eq!(
            job.surfaces[0]
                .surface
                .params
                .iter()
                .find(|p| p.0 == "beta")
                .map(|p| p.1.as_str()),
            Some("0.1")
        );
        assert!(job.modes[0].curves.curves && !job.modes[0].curves.control_polygons);
        let mut eight = toml::Table::new();
        eight.insert("stripes".into(), toml::Value::Integer(8));
        assert_eq!(
            job.modes[0].mode,
            Mode::configured("zebra", &eight).expect("zebra")
        );
        assert_ne!(job.modes[0].mode, Mode::by_name("zebra").expect("zebra"));
    }

    #[test]
    fn bad_specs_name_the_key_or_name() {
        let err = |text: &str| {
            FigureSpec::parse(text)
                .and_then(|s| s.job(Path::new("")).map(|_| ()))
                .expect_err("bad spec")
                .to_string()
        };
        let top = err(&format!("colour = 3\n{SPEC}"));
        assert!(
            top.starts_with("figure spec:1:1: ") && top.contains("colour") && !top.contains('\n'),
            "{top}"
        );
        assert!(err(&SPEC.replace("curves = true", "curvez = true")).contains("curvez"));
        assert!(err(&SPEC.replace("stripes = 8", "stripez = 8")).contains("stripez"));
        assert!(err(&SPEC.replace("\"loop94\"", "\"loop95\"")).contains("loop95"));
        assert!(err(&SPEC.replace("\"zebra\"", "\"sparkle\"")).contains("sparkle"));
        assert!(err(&SPEC.replace("beta = 0.1", "gamma = 0.1")).contains("gamma"));
        assert!(err(&SPEC.replace("\"icosahedron\"", "\"nowhere.obj\"")).contains("nowhere.obj"));
        assert!(err(&SPEC.replace("curves = true", "surface = false")).contains("surface"));
    }
}
