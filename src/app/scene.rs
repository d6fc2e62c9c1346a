//! Scene files (TOML): mesh, scheme and parameters, camera, mode and its parameters, size,
//! samples, output. Every key is optional; the command line overrides any of them. Example:
//!
//! ```toml
//! mesh = "ico.obj"            # relative to the scene file, as every path in it
//! weld_tolerance = 1e-10      # weld vertices closer than this fraction of the diagonal
//! crease_angle = 40           # edges whose faces turn by more than 40° are sharp (G0)
//! strict = false              # true: refuse to repair the mesh (every repair is an error)
//! [scheme]
//! name = "hb"
//! params = { normals = "estimate" }
//! [camera]
//! eye = [3.0, 2.0, 4.0]       # omitted: automatic framing
//! target = [0.0, 0.0, 0.0]
//! up = [0.0, 1.0, 0.0]
//! fov = 35.0
//! ortho = false
//! [render]
//! mode = "zebra"              # zebra highlight isophote curvature normals patches diffuse shaded
//! size = [640, 480]
//! spp = 4
//! theme = "dark"              # or "paper": white background, dark legend text
//! output = "out/ico-zebra"    # writes .png and .exr beside the scene file in out/
//! overlay = "faces"           # none, faces, patches, both
//! curves = true               # boundary curves as blue tubes
//! control_polygons = true     # their control polygons as red tubes
//! surface = true              # false: the tubes alone
//! curve_radius = 0.003        # relative to the bounding-box diagonal
//! curve_edge = 4              # only the curves of this mesh edge
//! exr = true                  # false: the PNG only
//! exr_compression = "rle"     # none rle zip zips piz pxr24 b44 b44a
//! turntable = 36              # 36 views around the axis: out/ico-zebra-000.png … and .gif
//! turntable_axis = [0.0, 1.0, 0.0]  # default: the camera's up
//! # sweep = 12                # or: zebra stripes moved over one period in 12 frames
//! [zebra]
//! axis = "view"               # view, view-horizontal or a world direction [0.0, 1.0, 0.0]
//! stripes = 16                # bright stripes per full turn, or:
//! width = "medium"            # thin medium thick, or the period in degrees
//! duty = 0.5
//! bright = [0.9, 0.9, 0.9]    # linear RGB
//! dark = [0.015, 0.015, 0.015]
//! filter = true               # box-filter the stripes over the pixel footprint
//! [highlight]
//! lines = 4                   # lights per scene diagonal (or spacing = world distance)
//! [isophote]
//! step_deg = 10               # an isophote every 10° (default: 16 bands of equal n·L)
//! [curvature]
//! quantity = "mean"           # gaussian mean maxabs k1 k2
//! range = "auto"              # or a number: fixed half-range
//! percentile = 95
//! legend = true
//! map = "diverging"           # diverging (RdBu), coolwarm (zero grey) or sequential (viridis)
//! sign = "convex"             # convex: > 0 where convex (outward normal); normal: II/I
//! ```

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::DVec3;
use serde::Deserialize;

use crate::app::toml_input::{self, exact};
use crate::app::turntable::Animation;
use crate::error::{Error, Problem, Result};
use crate::mesh::{LoadOptions, check_crease_angle, check_weld_tolerance};
use crate::render::bvh::SubdivisionCriterion;
use crate::render::curves::CurveOverlay;
use crate::render::film::RenderSettings;
use crate::render::job::{
    CameraSpec, DEFAULT_FOV, DEFAULT_MAX_LEAVES, Geometry, MAX_SIDE, RenderJob, check_size,
    check_spp,
};
use crate::render::modes::keys::{self, direction, in_count_range, in_range, positive};
use crate::render::modes::{DEFAULT_MODE, Key, MODE_KEYS, MODE_NAMES, Mode, Overlay};
use crate::render::output::ExrCompression;
use crate::render::theme::Theme;

pub(crate) use crate::render::job::{DEFAULT_SIZE, DEFAULT_SPP, MAX_SPP};

/// A scene file as written (every key optional).
///
/// Beside the sections below, a scene has one section per render mode (`[zebra]`,
/// `[curvature]`, …, [`crate::render::modes::MODE_NAMES`]): its keys are the mode's own, read
/// and checked by the mode. Any other key is refused, naming the known ones.
#[derive(Clone, Debug, Default, Deserialize)]
pub struct SceneFile {
    /// Mesh file (OBJ, PLY, OFF or STL), relative to the scene file.
    pub mesh: Option<PathBuf>,
    /// Weld tolerance of the mesh, relative to its bounding-box diagonal (see
    /// [`LoadOptions::weld_tolerance`]).
    pub weld_tolerance: Option<f64>,
    /// Crease angle in degrees: edges whose faces' normals are further apart are sharp (see
    /// [`LoadOptions::crease_angle`]); unset, no edge is.
    pub crease_angle: Option<f64>,
    /// Refuse every repair of the mesh (see [`LoadOptions::strict`]; default false).
    pub strict: Option<bool>,
    /// Surface construction.
    #[serde(default)]
    pub scheme: SchemeSection,
    /// Camera.
    #[serde(default)]
    pub camera: CameraSection,
    /// Image settings.
    #[serde(default)]
    pub render: RenderSection,
    /// BVH subdivision criterion.
    #[serde(default)]
    pub bvh: BvhSection,
    /// The modes' sections by mode name, as written (checked by [`SceneFile::parse`] and
    /// [`SceneFile::load`]: only mode names, each a table).
    #[serde(flatten)]
    pub modes: BTreeMap<String, toml::Value>,
}

/// The top-level keys of a scene file other than the modes' sections.
const TOP_KEYS: &[&str] = &[
    "mesh",
    "weld_tolerance",
    "crease_angle",
    "strict",
    "scheme",
    "camera",
    "render",
    "bvh",
];

/// `[scheme]`
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SchemeSection {
    /// Registered scheme name.
    pub name: Option<String>,
    /// Scheme parameters, `name = value`.
    #[serde(default)]
    pub params: toml::Table,
}

/// `[camera]`
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraSection {
    /// Eye position (omitted: automatic framing).
    #[serde(default, deserialize_with = "exact")]
    pub eye: Option<[f64; 3]>,
    /// Point looked at (omitted: centre of the surface's bounds).
    #[serde(default, deserialize_with = "exact")]
    pub target: Option<[f64; 3]>,
    /// Up direction.
    #[serde(default, deserialize_with = "exact")]
    pub up: Option<[f64; 3]>,
    /// Vertical field of view in degrees.
    pub fov: Option<f64>,
    /// Orthographic projection (same framing at the target as the perspective view).
    pub ortho: Option<bool>,
}

/// `[render]`
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RenderSection {
    /// Mode name.
    pub mode: Option<String>,
    /// Width and height in pixels.
    #[serde(default, deserialize_with = "exact")]
    pub size: Option<[u32; 2]>,
    /// Samples per pixel.
    pub spp: Option<u32>,
    /// Output stem (".png" and ".exr" are appended), relative to the scene file (a `-o` on the
    /// command line is relative to the working directory).
    pub output: Option<PathBuf>,
    /// Boundary overlay: none, faces, patches, both.
    pub overlay: Option<String>,
    /// Overlay line width in pixels.
    pub line_width: Option<f64>,
    /// Sample seed.
    pub seed: Option<u64>,
    /// Background colour (linear RGB; default: the theme's).
    #[serde(default, deserialize_with = "exact")]
    pub background: Option<[f64; 3]>,
    /// Colours around the image: "dark" (default) or "paper" (white background, dark legend
    /// text, the curvature mode's grey-zero map; see [`crate::render::theme::Theme`]).
    pub theme: Option<String>,
    /// Render a tessellation with this many segments per patch edge instead of the patches.
    pub tessellate: Option<u32>,
    /// Draw the boundary curves (images of the mesh edges) as tubes.
    pub curves: Option<bool>,
    /// Draw the Bézier control polygons of the boundary curves as tubes.
    pub control_polygons: Option<bool>,
    /// Trace the surface (false: the curves alone).
    pub surface: Option<bool>,
    /// Tube radius relative to the bounding-box diagonal.
    pub curve_radius: Option<f64>,
    /// Draw the curves of this mesh edge only (index in the mesh's edge list).
    pub curve_edge: Option<usize>,
    /// Write the EXR beside the PNG (default true).
    pub exr: Option<bool>,
    /// EXR compression (see [`ExrCompression::NAMES`]).
    pub exr_compression: Option<String>,
    /// Render this many views around an axis (see [`crate::app::turntable`]).
    pub turntable: Option<u32>,
    /// Axis of the turntable (default: the camera's up).
    #[serde(default, deserialize_with = "exact")]
    pub turntable_axis: Option<[f64; 3]>,
    /// Move the zebra stripes over one period in this many frames.
    pub sweep: Option<u32>,
}

/// `[bvh]`
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BvhSection {
    /// See [`SubdivisionCriterion::flatness`].
    pub flatness: Option<f64>,
    /// See [`SubdivisionCriterion::max_cone_deg`].
    pub cone_deg: Option<f64>,
    /// See [`SubdivisionCriterion::max_depth`].
    pub max_depth: Option<u32>,
    /// Largest number of BVH leaves (estimated before the build); default
    /// [`DEFAULT_MAX_LEAVES`].
    pub max_leaves: Option<u64>,
}

impl BvhSection {
    /// The subdivision criterion (defaults where unset).
    pub fn criterion(&self) -> Result<SubdivisionCriterion> {
        let mut c = SubdivisionCriterion::default();
        if let Some(f) = self.flatness {
            c.flatness = in_range("bvh.flatness", f, FLATNESS_RANGE)?;
        }
        if let Some(a) = self.cone_deg {
            c.max_cone_deg = in_range("bvh.cone_deg", a, CONE_DEG_RANGE)?;
        }
        if let Some(d) = self.max_depth {
            c.max_depth = in_count_range("bvh.max_depth", d, 0, MAX_DEPTH_LIMIT)?;
        }
        Ok(c)
    }

    /// The largest number of BVH leaves `max_leaves` allows (at least 1).
    pub fn max_leaves(&self) -> Result<u64> {
        match self.max_leaves {
            Some(0) => Err(Error::config(
                "bvh.max_leaves",
                Problem::BelowMinimum {
                    value: "0".into(),
                    min: "1".into(),
                },
            )),
            Some(n) => Ok(n),
            None => Ok(DEFAULT_MAX_LEAVES),
        }
    }

    /// The exact geometry these settings describe.
    pub fn geometry(&self) -> Result<Geometry> {
        Ok(Geometry::Exact {
            criterion: self.criterion()?,
            max_leaves: self.max_leaves()?,
        })
    }
}

/// Allowed range of `bvh.flatness`.
pub(crate) const FLATNESS_RANGE: (f64, f64) = (1e-4, 1.0);
/// Allowed range of `bvh.cone_deg`.
pub(crate) const CONE_DEG_RANGE: (f64, f64) = (1.0, 90.0);
/// Largest `bvh.max_depth` (a piece then covers 4^-16 of its patch).
pub(crate) const MAX_DEPTH_LIMIT: u32 = 16;

/// The error of a scene or mesh argument `input` that gives no mesh: a configuration error of
/// `mesh`, in `input`.
pub(crate) fn no_mesh_given(input: &Path) -> Error {
    let message = "no mesh given".to_string();
    Error::config("mesh", Problem::Stated { message }).within(input.display().to_string())
}

/// The value `value` of mode key `key` written in a file in folder `dir`: a relative file
/// name made relative to `dir` (as every path of scene files and figure specs is); built-in
/// names, absolute paths and keys naming no file as they are.
pub(crate) fn file_beside(key: &Key, value: &str, dir: &Path) -> String {
    if !key.names_file(value) || Path::new(value).is_absolute() {
        return value.to_string();
    }
    dir.join(value).to_string_lossy().into_owned()
}

impl SceneFile {
    /// Reads and parses a scene file; every relative path in it — mesh, output, environment —
    /// is made relative to the file's directory.
    pub fn load(path: &Path) -> Result<SceneFile> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
        // A figure spec given to `render` is named as one, whichever check refuses it.
        let figure_spec_or = |e: Error| {
            if toml_input::has_top_level_key(&text, &["schemes", "modes"]) {
                Error::Invalid(format!(
                    "this is a figure spec ([[schemes]], [[modes]]), not a scene file: run \
                     `smoothlab figure {}`",
                    path.display()
                ))
                .within(path.display().to_string())
            } else {
                e
            }
        };
        let mut scene: SceneFile =
            toml_input::parse(&text, &path.display().to_string()).map_err(figure_spec_or)?;
        let dir = path.parent().unwrap_or(Path::new(""));
        if let Some(mesh) = &scene.mesh
            && mesh.is_relative()
        {
            scene.mesh = Some(dir.join(mesh));
        }
        if let Some(output) = &scene.render.output
            && output.is_relative()
        {
            scene.render.output = Some(dir.join(output));
        }
        scene
            .check_sections()
            .map_err(|e| figure_spec_or(e.within(path.display().to_string())))?;
        scene.files_beside(dir);
        Ok(scene)
    }

    /// Parses scene text (errors are one line, see [`toml_input::one_line`]).
    pub fn parse(text: &str) -> Result<SceneFile> {
        let scene: SceneFile = toml_input::parse(text, "scene file")?;
        scene.check_sections()?;
        Ok(scene)
    }

    /// Refuses a top-level key that is neither a section of its own nor a mode's section
    /// (a table named after a registered mode).
    fn check_sections(&self) -> Result<()> {
        for (name, value) in &self.modes {
            if !MODE_NAMES.contains(&name.as_str()) {
                let known: Vec<String> = TOP_KEYS
                    .iter()
                    .chain(MODE_NAMES)
                    .map(|k| format!("`{k}`"))
                    .collect();
                return Err(keys::unknown_key(None, name, known));
            }
            let Some(section) = value.as_table() else {
                return Err(Error::config(
                    name,
                    keys::wrong_type(value, &format!("a section [{name}]")),
                ));
            };
            // Every mode's section is checked for unknown keys, whether or not its mode is
            // the one rendered: a misspelt key is an error, not silently ignored.
            if let Some((_, keys)) = MODE_KEYS.iter().find(|(mode, _)| *mode == name.as_str()) {
                crate::render::modes::Keys::new(name, section, keys)?;
            }
        }
        Ok(())
    }

    /// Every mode key that names a file made relative to `dir` ([`file_beside`]).
    fn files_beside(&mut self, dir: &Path) {
        for (name, keys) in MODE_KEYS {
            let Some(toml::Value::Table(section)) = self.modes.get_mut(*name) else {
                continue;
            };
            for key in keys.iter() {
                if let Some(toml::Value::String(file)) = section.get_mut(key.name) {
                    *file = file_beside(key, file, dir);
                }
            }
        }
    }

    /// The section of mode `name` as written (empty when the scene has none).
    pub fn mode_section(&self, name: &str) -> toml::Table {
        match self.modes.get(name) {
            Some(toml::Value::Table(t)) => t.clone(),
            _ => toml::Table::new(),
        }
    }

    /// The section of mode `name`, made when missing, to write keys into.
    pub fn mode_section_mut(&mut self, name: &str) -> &mut toml::Table {
        let value = self
            .modes
            .entry(name.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        if !value.is_table() {
            *value = toml::Value::Table(toml::Table::new());
        }
        match value {
            toml::Value::Table(t) => t,
            _ => unreachable!("made a table above"),
        }
    }

    /// The files the scene's mode keys name (lat-long maps), each with what it is.
    pub fn mode_files(&self) -> Vec<(&'static str, PathBuf)> {
        let mut files = Vec::new();
        for (name, keys) in MODE_KEYS {
            let section = self.mode_section(name);
            for key in keys.iter() {
                if let Some(toml::Value::String(file)) = section.get(key.name)
                    && key.names_file(file)
                {
                    files.push((key.what, PathBuf::from(file)));
                }
            }
        }
        files
    }

    /// How the mesh is loaded (defaults where unset).
    pub fn load_options(&self) -> Result<LoadOptions> {
        let mut options = LoadOptions::default();
        if let Some(tolerance) = self.weld_tolerance {
            options.weld_tolerance = check_weld_tolerance(tolerance)
                .map_err(|reason| Error::config("weld_tolerance", Problem::Refused { reason }))?;
        }
        if let Some(degrees) = self.crease_angle {
            options.crease_angle =
                Some(check_crease_angle(degrees).map_err(|reason| {
                    Error::config("crease_angle", Problem::Refused { reason })
                })?);
        }
        if let Some(strict) = self.strict {
            options.strict = strict;
        }
        Ok(options)
    }

    /// Scheme parameters as `name = value` text pairs.
    pub fn scheme_params(&self) -> Vec<(String, String)> {
        self.scheme
            .params
            .iter()
            .map(|(k, v)| {
                let text = match v {
                    toml::Value::String(s) => s.clone(),
                    other => other.to_string(),
                };
                (k.clone(), text)
            })
            .collect()
    }

    /// The validated render job of this scene: every key checked once, defaults filled in.
    pub fn job(&self) -> Result<RenderJob> {
        let r = &self.render;
        let [width, height] = r.size.unwrap_or(DEFAULT_SIZE);
        check_size("render.size", width, height, MAX_SIDE)?;
        let spp = r.spp.unwrap_or(DEFAULT_SPP);
        check_spp("render.spp", spp, MAX_SPP)?;
        let theme = match &r.theme {
            Some(name) => Theme::by_name("render.theme", name)?,
            None => Theme::default(),
        };
        let mut settings = RenderSettings {
            width,
            height,
            spp,
            mode: self.mode()?,
            overlay: self.overlay()?,
            seed: r.seed.unwrap_or(0),
            surface: r.surface.unwrap_or(true),
            background: theme.background(),
            theme,
            ..RenderSettings::default()
        };
        if let Some(bg) = r.background {
            if bg.iter().any(|x| !(x.is_finite() && *x >= 0.0)) {
                return Err(Error::config(
                    "render.background",
                    Problem::Must {
                        value: format!("{bg:?}"),
                        requirement: "be non-negative".into(),
                    },
                ));
            }
            settings.background = DVec3::from_array(bg);
        }
        let c = &self.camera;
        let camera = CameraSpec {
            eye: c.eye.map(DVec3::from_array),
            target: c.target.map(DVec3::from_array),
            up: c.up.map(DVec3::from_array),
            fov_deg: c.fov.unwrap_or(DEFAULT_FOV),
            orthographic: c.ortho.unwrap_or(false),
        };
        let geometry = match r.tessellate {
            Some(n) => Geometry::Tessellated(n),
            None => Geometry::Exact {
                criterion: self.criterion()?,
                max_leaves: self.max_leaves()?,
            },
        };
        Ok(RenderJob {
            settings,
            camera,
            curves: self.curve_overlay()?,
            geometry,
        })
    }

    /// The EXR compression of `[render]` (None: no EXR is written).
    pub fn exr_compression(&self) -> Result<Option<ExrCompression>> {
        if self.render.exr == Some(false) {
            return Ok(None);
        }
        match &self.render.exr_compression {
            None => Ok(Some(ExrCompression::default())),
            Some(name) => ExrCompression::by_name(name).map(Some).map_err(|e| {
                Error::config(
                    "render.exr_compression",
                    Problem::Refused {
                        reason: e.to_string(),
                    },
                )
            }),
        }
    }

    /// The turntable or stripe sweep of `render.turntable` / `render.sweep`, if any, checked:
    /// not both, a frame count in range, a non-zero axis only with a turntable, a sweep only
    /// in zebra mode.
    pub fn animation(&self) -> Result<Option<Animation>> {
        let r = &self.render;
        let axis = r
            .turntable_axis
            .map(|a| direction("render.turntable_axis (--turntable-axis)", a))
            .transpose()?;
        match (r.turntable, r.sweep) {
            (Some(_), Some(_)) => Err(Error::config(
                "render.turntable (--turntable)",
                Problem::Excludes {
                    other: "render.sweep (--sweep)".into(),
                },
            )),
            (Some(n), None) => Ok(Some(Animation::Turntable {
                frames: Animation::check_frames("render.turntable (--turntable)", n)?,
                axis,
            })),
            (None, sweep) if axis.is_some() => Err(Error::config(
                "render.turntable_axis (--turntable-axis)",
                Problem::Needs {
                    value: None,
                    needed: format!(
                        "render.turntable (--turntable){}",
                        if sweep.is_some() { ", not a sweep" } else { "" }
                    ),
                },
            )),
            (None, Some(n)) => {
                let frames = Animation::check_frames("render.sweep (--sweep)", n)?;
                let mode = r.mode.as_deref().unwrap_or(DEFAULT_MODE);
                if !Mode::by_name(mode)?.sweeps() {
                    return Err(Error::config(
                        "render.sweep (--sweep)",
                        Problem::Other {
                            text: format!("moves a mode's stripes; mode '{mode}' has none"),
                        },
                    ));
                }
                Ok(Some(Animation::Sweep { frames }))
            }
            (None, None) => Ok(None),
        }
    }

    /// The subdivision criterion (defaults where unset).
    pub fn criterion(&self) -> Result<SubdivisionCriterion> {
        self.bvh.criterion()
    }

    /// The largest number of BVH leaves `bvh.max_leaves` allows (at least 1).
    pub fn max_leaves(&self) -> Result<u64> {
        self.bvh.max_leaves()
    }

    /// The boundary overlay.
    pub fn overlay(&self) -> Result<Overlay> {
        let name = self.render.overlay.as_deref().unwrap_or("none");
        keys::one_of("render.overlay", name, &Overlay::NAMES)?;
        let mut o = Overlay::by_name(name).unwrap_or_default();
        if let Some(w) = self.render.line_width {
            o.width_px = positive("render.line_width", w)?;
        }
        Ok(o)
    }

    /// The curve-network overlay of `[render]`.
    pub fn curve_overlay(&self) -> Result<CurveOverlay> {
        let r = &self.render;
        let mut c = CurveOverlay {
            curves: r.curves.unwrap_or(false),
            control_polygons: r.control_polygons.unwrap_or(false),
            edge: r.curve_edge,
            ..CurveOverlay::default()
        };
        if let Some(radius) = r.curve_radius {
            c.radius_rel = positive("render.curve_radius", radius)?;
        }
        if !r.surface.unwrap_or(true) && !c.enabled() {
            return Err(Error::config(
                "render.surface",
                Problem::Needs {
                    value: Some("false".into()),
                    needed: "render.curves or render.control_polygons".into(),
                },
            ));
        }
        Ok(c)
    }

    /// The mode with its section's parameters, read and checked by the mode.
    pub fn mode(&self) -> Result<Mode> {
        let name = self.render.mode.as_deref().unwrap_or(DEFAULT_MODE);
        Mode::configured(name, &self.mode_section(name))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn full_scene_parses() {
        let scene = SceneFile::parse(
            r#"
            mesh = "ico.obj"
            [scheme]
            name = "hb"
            params = { normals = "estimate", t = 0.5 }
            [camera]
            eye = [3.0, 2.0, 4.0]
            fov = 30
            [render]
            mode = "curvature"
            size = [320, 200]
            spp = 9
            overlay = "both"
            [curvature]
            quantity = "gaussian"
            range = 2.5
            legend = true
            "#,
        )
        .expect("valid scene");
        assert_eq!(scene.scheme.name.as_deref(), Some("hb"));
        let params = scene.scheme_params();
        assert!(params.contains(&("t".into(), "0.5".into())), "{params:?}");
        // The mode reads its own section (its keys are checked in render/modes/).
        let mode = scene.mode().expect("mode");
        assert_eq!(mode.name(), "curvature");
        assert_ne!(mode, Mode::by_name("curvature").expect("curvature"));
        assert!(!mode.scale_is_automatic());
        let o = scene.overlay().expect("overlay");
        assert!(o.face_edges && o.patch_edges);
    }

    #[test]
    fn strict_key_sets_the_load_options() {
        assert!(
            !SceneFile::parse("")
                .expect("parses")
                .load_options()
                .expect("valid")
                .strict
        );
        let scene = SceneFile::parse("mesh = \"a.obj\"\nstrict = true").expect("parses");
        assert!(scene.load_options().expect("valid").strict);
        assert!(SceneFile::parse("strict = 1").is_err());
    }

    #[test]
    fn weld_tolerance_key_sets_the_load_options() {
        let default = SceneFile::parse("mesh = \"a.obj\"").expect("parses");
        assert_eq!(
            default.load_options().expect("valid"),
            LoadOptions::default()
        );
        let scene = SceneFile::parse("mesh = \"a.obj\"\nweld_tolerance = 1e-6").expect("parses");
        assert_eq!(scene.load_options().expect("valid").weld_tolerance, 1e-6);
        for bad in ["-1e-9", "1.5", "nan"] {
            let scene = SceneFile::parse(&format!("weld_tolerance = {bad}")).expect("parses");
            let err = scene.load_options().expect_err("out of range");
            assert!(err.to_string().starts_with("weld_tolerance: "), "{err}");
        }
    }

    #[test]
    fn bad_scenes_name_the_key() {
        let err = SceneFile::parse("[render]\nsize = [1, 2]\nfoo = 3").expect_err("unknown key");
        assert!(err.to_string().contains("foo"), "{err}");
        let scene = SceneFile::parse("[zebra]\nduty = 1.5").expect("parses");
        let err = scene.mode().expect_err("duty out of range");
        assert!(err.to_string().contains("zebra.duty"), "{err}");
        // A mode's section is checked as the scene is parsed, whatever mode is rendered.
        let err = SceneFile::parse("[zebra]\nfoo = 1")
            .expect_err("unknown mode key")
            .to_string();
        assert!(err.contains("`foo`") && err.contains("`stripes`"), "{err}");
        for bad in ["[sparkle]\nx = 1", "zebra = 3", "colour = 3"] {
            let err = SceneFile::parse(bad).expect_err(bad).to_string();
            assert!(
                err.contains(
                    bad.trim_start_matches('[')
                        .split([']', ' '])
                        .next()
                        .unwrap_or(bad)
                ),
                "{bad}: {err}"
            );
        }
        let scene = SceneFile::parse("[render]\nmode = \"sparkle\"").expect("parses");
        assert!(
            scene
                .mode()
                .expect_err("unknown mode")
                .to_string()
                .contains("sparkle")
        );
    }

    #[test]
    fn turntable_and_sweep_keys_are_checked() {
        let animation = |text: &str| SceneFile::parse(text).expect("parses").animation();
        assert_eq!(animation("").expect("none"), None);
        assert_eq!(
            animation("[render]\nturntable = 36\nturntable_axis = [0, 2, 0]").expect("ok"),
            Some(Animation::Turntable {
                frames: 36,
                axis: Some(DVec3::Y)
            })
        );
        assert_eq!(
            animation("[render]\nsweep = 8").expect("ok"),
            Some(Animation::Sweep { frames: 8 })
        );
        for (text, fragment) in [
            ("[render]\nturntable = 0", "render.turntable"),
            ("[render]\nturntable = 4\nsweep = 4", "exclude"),
            (
                "[render]\nturntable = 4\nturntable_axis = [0, 0, 0]",
                "turntable_axis",
            ),
            (
                "[render]\nturntable_axis = [0, 1, 0]",
                "needs render.turntable",
            ),
            ("[render]\nmode = \"isophote\"\nsweep = 4", "isophote"),
            ("[render]\nsweep = 100000", "render.sweep"),
        ] {
            let err = animation(text).expect_err(text).to_string();
            assert!(
                err.contains(fragment) && !err.contains('\n'),
                "{text}: {err}"
            );
        }
    }
}
