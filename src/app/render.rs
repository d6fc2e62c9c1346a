//! The `render` subcommand: arguments (clap) and the command itself. The binary only parses
//! and calls [`render_command`]; everything else lives here in the library.

use std::path::{Path, PathBuf};

use crate::app::scene::SceneFile;
use crate::app::turntable;
use crate::app::{parse_crease_angle, parse_weld_tolerance};
use crate::error::{Error, Result};
use crate::files::{check_distinct, check_writable, utf8_path};
use crate::mesh::Mesh;
use crate::render::output::{OutputMeta, OutputOptions, prepare_outputs, write_outputs_with};
use crate::render::stats::RenderStats;
use crate::schemes;

/// Render modes (`--mode`).
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModeArg {
    /// Reflection lines of parallel light tubes.
    Zebra,
    /// View-independent highlight lines of parallel line lights.
    Highlight,
    /// Bands of constant n·L.
    Isophote,
    /// A curvature quantity through a colour map, with a legend.
    Curvature,
    /// The normal as a colour.
    Normals,
    /// One colour per face and piece.
    Patches,
    /// Plain grey lit from the eye.
    Diffuse,
    /// Path-traced clear coat in a studio.
    Shaded,
}

impl ModeArg {
    /// The mode's name in scenes.
    pub fn name(self) -> &'static str {
        match self {
            ModeArg::Zebra => "zebra",
            ModeArg::Highlight => "highlight",
            ModeArg::Isophote => "isophote",
            ModeArg::Curvature => "curvature",
            ModeArg::Normals => "normals",
            ModeArg::Patches => "patches",
            ModeArg::Diffuse => "diffuse",
            ModeArg::Shaded => "shaded",
        }
    }
}

/// Boundary overlays (`--overlay`).
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum OverlayArg {
    /// No lines.
    None,
    /// Lines along mesh-face boundaries.
    Faces,
    /// Lines along every patch boundary.
    Patches,
    /// Both.
    Both,
}

impl OverlayArg {
    /// The overlay's name in scenes.
    pub fn name(self) -> &'static str {
        match self {
            OverlayArg::None => "none",
            OverlayArg::Faces => "faces",
            OverlayArg::Patches => "patches",
            OverlayArg::Both => "both",
        }
    }
}

/// EXR compressions (`--exr-compression`), all lossless.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExrCompressionArg {
    /// Uncompressed.
    None,
    /// Run-length (fast).
    Rle,
    /// zlib per scan line.
    Zips,
    /// zlib per 16 scan lines.
    Zip,
    /// Wavelet + Huffman.
    Piz,
}

impl ExrCompressionArg {
    /// The compression's name in scenes.
    pub fn name(self) -> &'static str {
        match self {
            ExrCompressionArg::None => "none",
            ExrCompressionArg::Rle => "rle",
            ExrCompressionArg::Zips => "zips",
            ExrCompressionArg::Zip => "zip",
            ExrCompressionArg::Piz => "piz",
        }
    }
}

/// Curvature quantities (`--curvature-quantity`).
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum QuantityArg {
    /// K = κ1 κ2.
    Gaussian,
    /// H = (κ1 + κ2) / 2.
    Mean,
    /// max(|κ1|, |κ2|).
    Maxabs,
    /// The larger principal curvature.
    K1,
    /// The smaller principal curvature.
    K2,
}

/// Curvature colour maps (`--curvature-map`).
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum MapArg {
    /// ColorBrewer RdBu over [−r, r], zero white.
    Diverging,
    /// viridis over [−r, r] ([0, r] for maxabs).
    Sequential,
}

/// Curvature sign conventions (`--curvature-sign`).
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum SignArg {
    /// Positive where convex seen from the side the normal points to (outward normals).
    Convex,
    /// II/I with respect to the patch normal (convex is negative with outward normals).
    Normal,
}

/// The name of a clap value as written on the command line.
fn value_name(v: impl clap::ValueEnum) -> String {
    v.to_possible_value()
        .map_or_else(String::new, |p| p.get_name().to_string())
}

/// `smoothlab render SCENE.toml | MESH.obj [options]` — every option overrides the scene.
#[derive(clap::Args, Clone, Debug, Default)]
pub struct RenderArgs {
    /// Scene file (.toml) or mesh (.obj, .ply, .off, .stl).
    pub input: PathBuf,
    /// Scheme name; required for a mesh input (default: the scene's `[scheme] name`). One of
    /// flat, pn, hb, loop94, piper, nielson, fang-mann, gk (`smoothlab schemes`).
    #[arg(long)]
    pub scheme: Option<String>,
    /// Scheme parameter `name=value` (repeatable).
    #[arg(long = "param", value_name = "NAME=VALUE")]
    pub params: Vec<String>,
    /// Shading mode [default: the scene's, else zebra].
    #[arg(long, value_enum)]
    pub mode: Option<ModeArg>,
    /// Eye position `X,Y,Z`.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub eye: Option<[f64; 3]>,
    /// Point looked at `X,Y,Z`.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub target: Option<[f64; 3]>,
    /// Up direction `X,Y,Z`.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub up: Option<[f64; 3]>,
    /// Vertical field of view, degrees [default: 35].
    #[arg(long, value_parser = parse_fov, allow_negative_numbers = true)]
    pub fov: Option<f64>,
    /// Orthographic projection.
    #[arg(long)]
    pub ortho: bool,
    /// Image size `WxH` [default: 640x480].
    #[arg(long, value_parser = parse_size, allow_hyphen_values = true)]
    pub size: Option<[u32; 2]>,
    /// Samples per pixel [default: 4].
    #[arg(
        long,
        value_parser = clap::value_parser!(u32).range(1..=i64::from(crate::app::scene::MAX_SPP)),
        allow_negative_numbers = true
    )]
    pub spp: Option<u32>,
    /// Output name (writes NAME.png and NAME.exr) [default: MESH-SCHEME-MODE].
    #[arg(short = 'o', long = "output")]
    pub output: Option<PathBuf>,
    /// Write render statistics as JSON.
    #[arg(long, value_name = "F.json")]
    pub stats: Option<PathBuf>,
    /// Render an N-per-edge tessellation instead of the exact patches.
    #[arg(
        long,
        value_name = "N",
        value_parser = clap::value_parser!(u32).range(1..=crate::budget::MAX_TESS as i64),
        allow_negative_numbers = true
    )]
    pub tessellate: Option<u32>,
    /// Boundary overlay [default: none].
    #[arg(long, value_enum)]
    pub overlay: Option<OverlayArg>,
    /// Sample seed [default: 0].
    #[arg(long, allow_negative_numbers = true)]
    pub seed: Option<u64>,
    /// Weld vertices closer than this fraction of the bounding-box diagonal (0: identical
    /// positions only; default: the scene's `weld_tolerance`, else 1e-10).
    #[arg(
        long,
        value_name = "REL",
        value_parser = parse_weld_tolerance,
        allow_hyphen_values = true
    )]
    pub weld_tolerance: Option<f64>,
    /// Mark edges whose faces' normals are more than DEG degrees apart sharp, and the edges
    /// the file marks (OBJ `s` groups, per-corner `vn`): the surface is G0 there (default:
    /// the scene's `crease_angle`, else no sharp edges).
    #[arg(
        long,
        value_name = "DEG",
        value_parser = parse_crease_angle,
        allow_hyphen_values = true
    )]
    pub crease_angle: Option<f64>,
    /// Refuse to repair the mesh: the first repair loading would make is an error naming the
    /// element (scene: `strict = true`).
    #[arg(long)]
    pub strict: bool,
    /// Write the PNG only, no EXR (scene: `render.exr = false`).
    #[arg(long)]
    pub no_exr: bool,
    /// EXR compression [default: rle] (scene: `render.exr_compression`).
    #[arg(long, value_enum)]
    pub exr_compression: Option<ExrCompressionArg>,
    /// Zebra light-tube axis: `view` (stripes vertical on screen, poles only on the
    /// silhouette), `view-horizontal`, or a world direction `X,Y,Z` [default: view].
    #[arg(long, value_name = "AXIS", allow_hyphen_values = true)]
    pub zebra_axis: Option<String>,
    /// Zebra bright stripes per full turn of the reflected direction [default: 16].
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub zebra_stripes: Option<f64>,
    /// Zebra stripe period: thin (11.25°), medium (22.5°), thick (45°) or degrees.
    #[arg(long, value_name = "WIDTH")]
    pub zebra_width: Option<String>,
    /// Bright fraction of a zebra period, 0..1 [default: 0.5].
    #[arg(long, value_name = "F", allow_negative_numbers = true)]
    pub zebra_duty: Option<f64>,
    /// Linear RGB of the bright zebra stripes `R,G,B` [default: 0.9,0.9,0.9].
    #[arg(long, value_name = "R,G,B", value_parser = parse_vec3)]
    pub zebra_bright: Option<[f64; 3]>,
    /// Linear RGB of the dark zebra stripes `R,G,B` [default: 0.015,0.015,0.015].
    #[arg(long, value_name = "R,G,B", value_parser = parse_vec3)]
    pub zebra_dark: Option<[f64; 3]>,
    /// Point-sample the zebra, highlight and isophote stripes instead of box-filtering them
    /// over each pixel's footprint.
    #[arg(long)]
    pub no_stripe_filter: bool,
    /// Highlight lights per scene diagonal [default: 4].
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub highlight_lines: Option<f64>,
    /// An isophote every DEG degrees between normal and light [default: 16 bands of equal
    /// n·L].
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    pub isophote_step: Option<f64>,
    /// Curvature quantity [default: mean].
    #[arg(long, value_enum)]
    pub curvature_quantity: Option<QuantityArg>,
    /// Curvature colour map [default: diverging; sequential for maxabs].
    #[arg(long, value_enum)]
    pub curvature_map: Option<MapArg>,
    /// Sign convention of mean, κ1 and κ2 [default: convex].
    #[arg(long, value_enum)]
    pub curvature_sign: Option<SignArg>,
    /// Curvature half-range: `auto` (95th percentile of |value| in view) or a number
    /// [default: auto].
    #[arg(long, value_name = "auto|R", allow_hyphen_values = true)]
    pub curvature_range: Option<String>,
    /// No curvature legend (scene: `curvature.legend = false`).
    #[arg(long)]
    pub no_legend: bool,
    /// The command line as typed, recorded in the PNG and EXR (set by the binary).
    #[arg(skip)]
    pub command_line: Option<String>,
    /// Render N views around an axis through the target (a full turn): writes NAME-000.png …
    /// and the looping NAME.gif instead of NAME.png and NAME.exr.
    #[arg(
        long,
        value_name = "N",
        value_parser = clap::value_parser!(u32).range(1..=i64::from(turntable::MAX_FRAMES)),
        allow_negative_numbers = true
    )]
    pub turntable: Option<u32>,
    /// Axis of --turntable `X,Y,Z` (default: the camera's up, --up or +Y).
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true)]
    pub turntable_axis: Option<[f64; 3]>,
    /// Zebra mode: move the stripes over one period in N frames at a fixed camera; writes
    /// NAME-000.png … and the looping NAME.gif.
    #[arg(
        long,
        value_name = "N",
        value_parser = clap::value_parser!(u32).range(1..=i64::from(turntable::MAX_FRAMES)),
        allow_negative_numbers = true
    )]
    pub sweep: Option<u32>,
    /// With --turntable or --sweep: render only shard I of N of the frames (0 ≤ I < N) and
    /// write NAME.shard-I-of-N.json beside them; `smoothlab merge` writes the GIF.
    #[arg(long, value_name = "I/N", allow_hyphen_values = true)]
    pub shard: Option<crate::report::shard::Shard>,
}

/// Parses `X,Y,Z`.
pub fn parse_vec3(text: &str) -> std::result::Result<[f64; 3], String> {
    let parts: Vec<&str> = text.split(',').collect();
    if parts.len() != 3 {
        return Err(format!("'{text}' is not X,Y,Z"));
    }
    let mut out = [0.0; 3];
    for (slot, part) in out.iter_mut().zip(parts) {
        *slot = part
            .trim()
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("'{part}' in '{text}' is not a finite number"))?;
    }
    Ok(out)
}

/// Parses a vertical field of view in degrees (`--fov`): finite, at least
/// [`MIN_FOV_DEG`](crate::render::camera::MIN_FOV_DEG) and below 180.
pub fn parse_fov(text: &str) -> std::result::Result<f64, String> {
    let min = crate::render::camera::MIN_FOV_DEG;
    let fov: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("'{text}' is not a number of degrees"))?;
    if !(min..180.0).contains(&fov) {
        return Err(format!(
            "field of view {}° is outside the valid range: at least {min}° and below 180°",
            text.trim()
        ));
    }
    Ok(fov)
}

/// Parses `WxH`.
pub fn parse_size(text: &str) -> std::result::Result<[u32; 2], String> {
    let (w, h) = text
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("'{text}' is not WxH"))?;
    let parse = |s: &str| {
        s.trim()
            .parse::<u32>()
            .ok()
            .filter(|&v| v > 0)
            .ok_or_else(|| format!("'{s}' in '{text}' is not a positive integer"))
    };
    Ok([parse(w)?, parse(h)?])
}

/// True if `input` names a scene file (`.toml`), not a mesh.
fn is_scene_file(input: &Path) -> bool {
    input
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("toml"))
}

/// The scene of `args`: the scene file (or a bare mesh) with every given option applied.
pub fn scene_of(args: &RenderArgs) -> Result<SceneFile> {
    let mut scene = if is_scene_file(&args.input) {
        SceneFile::load(&args.input)?
    } else {
        SceneFile {
            mesh: Some(args.input.clone()),
            ..SceneFile::default()
        }
    };
    if args.weld_tolerance.is_some() {
        scene.weld_tolerance = args.weld_tolerance;
    }
    if args.crease_angle.is_some() {
        scene.crease_angle = args.crease_angle;
    }
    if args.strict {
        scene.strict = Some(true);
    }
    if let Some(s) = &args.scheme {
        scene.scheme.name = Some(s.clone());
    }
    for text in &args.params {
        let (name, value) = schemes::parse_param(text)?;
        scene.scheme.params.insert(name, toml::Value::String(value));
    }
    let r = &mut scene.render;
    if let Some(m) = args.mode {
        r.mode = Some(m.name().to_string());
    }
    if args.size.is_some() {
        r.size = args.size;
    }
    if args.spp.is_some() {
        r.spp = args.spp;
    }
    if args.output.is_some() {
        r.output = args.output.clone();
    }
    if args.tessellate.is_some() {
        r.tessellate = args.tessellate;
    }
    if let Some(o) = args.overlay {
        r.overlay = Some(o.name().to_string());
    }
    if args.no_exr {
        r.exr = Some(false);
    }
    if let Some(c) = args.exr_compression {
        r.exr_compression = Some(c.name().to_string());
    }
    if args.seed.is_some() {
        r.seed = args.seed;
    }
    if args.turntable.is_some() {
        r.turntable = args.turntable;
    }
    if args.turntable_axis.is_some() {
        r.turntable_axis = args.turntable_axis;
    }
    if args.sweep.is_some() {
        r.sweep = args.sweep;
    }
    apply_mode_options(args, &mut scene)?;
    let c = &mut scene.camera;
    if args.eye.is_some() {
        c.eye = args.eye;
    }
    if args.target.is_some() {
        c.target = args.target;
    }
    if args.up.is_some() {
        c.up = args.up;
    }
    if args.fov.is_some() {
        c.fov = args.fov;
    }
    if args.ortho {
        c.ortho = Some(true);
    }
    Ok(scene)
}

/// The zebra, highlight, isophote and curvature options of `args` written into the scene's
/// sections (validated with the scene). Either of `--zebra-stripes` and `--zebra-width`
/// replaces the scene's choice of the other; both on one command line are refused.
fn apply_mode_options(args: &RenderArgs, scene: &mut SceneFile) -> Result<()> {
    if args.zebra_stripes.is_some() && args.zebra_width.is_some() {
        return Err(Error::Invalid(
            "--zebra-stripes and --zebra-width both given: they set the same period, give one, \
             not both"
                .into(),
        ));
    }
    let z = &mut scene.zebra;
    if let Some(axis) = &args.zebra_axis {
        z.axis = Some(match parse_vec3(axis) {
            Ok(v) => toml::Value::Array(v.iter().map(|x| toml::Value::Float(*x)).collect()),
            // A view axis by name, or anything else for the scene's check to name.
            Err(_) => toml::Value::String(axis.trim().to_string()),
        });
    }
    if args.zebra_stripes.is_some() {
        z.stripes = args.zebra_stripes;
        z.width = None;
    }
    if let Some(w) = &args.zebra_width {
        z.width = Some(toml::Value::String(w.clone()));
        z.stripes = None;
    }
    if args.zebra_duty.is_some() {
        z.duty = args.zebra_duty;
    }
    if args.zebra_bright.is_some() {
        z.bright = args.zebra_bright;
    }
    if args.zebra_dark.is_some() {
        z.dark = args.zebra_dark;
    }
    if args.no_stripe_filter {
        z.filter = Some(false);
        scene.highlight.filter = Some(false);
        scene.isophote.filter = Some(false);
    }
    if args.highlight_lines.is_some() {
        scene.highlight.lines = args.highlight_lines;
        scene.highlight.spacing = None;
    }
    if args.isophote_step.is_some() {
        scene.isophote.step_deg = args.isophote_step;
    }
    let c = &mut scene.curvature;
    if let Some(q) = args.curvature_quantity {
        c.quantity = Some(value_name(q));
    }
    if let Some(m) = args.curvature_map {
        c.map = Some(value_name(m));
    }
    if let Some(s) = args.curvature_sign {
        c.sign = Some(value_name(s));
    }
    if let Some(r) = &args.curvature_range {
        c.range = Some(match r.trim().parse::<f64>() {
            Ok(x) => toml::Value::Float(x),
            Err(_) => toml::Value::String(r.trim().to_string()),
        });
    }
    if args.no_legend {
        c.legend = Some(false);
    }
    Ok(())
}

/// Runs `smoothlab render`: checks the output paths, loads the mesh, builds the scheme,
/// renders, writes `NAME.png`, `NAME.exr` (or, for a turntable or sweep, the frames and the
/// GIF of [`crate::app::turntable`]) and the statistics. Returns the statistics (of all frames
/// together) and the loading warnings (one line each, without the `warning:` prefix).
pub fn render_command(args: &RenderArgs) -> Result<(RenderStats, Vec<String>)> {
    let scene = scene_of(args)?;
    let job = scene.job()?;
    let animation = scene.animation()?;
    let mesh_path = scene
        .mesh
        .clone()
        .ok_or_else(|| Error::Invalid(format!("{}: no mesh given", args.input.display())))?;
    let load_options = scene.load_options()?;
    let exr = scene.exr_compression()?;
    // The frame and its files are the largest allocation a small mesh makes: refused first.
    crate::render::film::check_frame_memory(
        job.settings.width,
        job.settings.height,
        crate::render::output::output_bytes_per_pixel(exr.is_some()),
    )?;
    let scheme = scene.scheme.name.clone().ok_or_else(|| {
        Error::Invalid(format!(
            "{}: no scheme given: pass --scheme NAME (one of {}) or set [scheme] name in a scene",
            args.input.display(),
            schemes::names().join(", ")
        ))
    })?;
    schemes::find(&scheme)?;
    let name = match scene.render.output.clone() {
        Some(name) => name,
        None => {
            let mode = scene.render.mode.as_deref().unwrap_or("zebra");
            let stem = mesh_path.file_stem().map_or(Path::new("render"), Path::new);
            let mesh = utf8_path(stem).map_err(|e| {
                Error::Invalid(format!(
                    "{e} (the output is named after the mesh: give -o NAME)"
                ))
            })?;
            PathBuf::from(format!("{mesh}-{scheme}-{mode}"))
        }
    };
    if args.shard.is_some() && animation.is_none() {
        return Err(Error::Invalid(
            "--shard splits the frames of --turntable or --sweep; a single image is one piece"
                .into(),
        ));
    }
    // Every output path is checked before the (possibly long) work.
    let outputs = prepare_outputs(&name)?;
    let frames = animation
        .map(|a| turntable::prepare_animation(&name, a.frames()))
        .transpose()?;
    if let Some(path) = &args.stats {
        check_writable(path)?;
    }
    let part = args.shard.map(|shard| turntable::part_path(&name, shard));
    let mut written: Vec<(&str, &Path)> = Vec::new();
    match &frames {
        Some((pngs, gif)) => {
            written.extend(pngs.iter().map(|p| ("a frame", p.as_path())));
            written.push(("the GIF", gif));
        }
        None => {
            written.push(("the PNG image", &outputs[0]));
            if exr.is_some() {
                written.push(("the EXR image", &outputs[1]));
            }
        }
    }
    written.extend(part.as_deref().map(|p| ("the shard's part file", p)));
    written.extend(args.stats.as_deref().map(|p| ("--stats", p)));
    let environment = scene
        .shaded
        .environment
        .as_deref()
        .filter(|e| *e != "studio")
        .map(Path::new);
    let mut read: Vec<(&str, &Path)> = vec![("the mesh", &mesh_path)];
    if is_scene_file(&args.input) {
        read.push(("the scene file", &args.input));
    }
    read.extend(environment.map(|e| ("the environment map", e)));
    check_distinct(&read, &written)?;
    let (mesh, mut report) = Mesh::load_with(&mesh_path, &load_options)?;
    let surface = schemes::build(&scheme, &mesh, &scene.scheme_params())?;
    report.warnings.extend(surface.warnings.iter().cloned());
    // The back of an open surface shows: tint it in the quality modes.
    let mut job = job;
    if !mesh.is_closed() {
        job.settings.mode = job.settings.mode.with_back_faces_tinted();
    }
    let stats = match (animation, frames) {
        (Some(animation), Some((pngs, gif))) => match (args.shard, &part) {
            (Some(shard), Some(part)) => turntable::render_animation_shard(
                &job, &animation, &surface, &mesh, &pngs, &gif, shard, part,
            )?,
            _ => turntable::render_animation(&job, &animation, &surface, &mesh, &pngs, &gif)?,
        },
        _ => {
            let (frame, stats) = job.render(&surface, &mesh)?;
            let options = OutputOptions {
                exr,
                meta: OutputMeta {
                    command: args.command_line.clone(),
                    camera: Some(job.camera_of(&surface)?),
                },
            };
            write_outputs_with(&frame, &outputs, &options)?;
            stats
        }
    };
    if let Some(path) = &args.stats {
        stats.write_json(path)?;
    }
    Ok((stats, report.warnings))
}

/// One line about a finished render, for the terminal.
pub fn render_summary(stats: &RenderStats) -> String {
    format!(
        "{} rays, {} hits; Newton {:.2} mean, {} max, {} failures; BVH {:.1} ms ({} leaves), render {:.1} ms\n",
        stats.rays,
        stats.hits,
        stats.newton_iter_mean,
        stats.newton_iter_max,
        stats.newton_failures,
        stats.bvh_build_ms,
        stats.leaves,
        stats.render_ms
    )
}

/// Renders the gallery into `out_dir` and returns its table and where the sheet went.
pub fn run_gallery(out_dir: &std::path::Path) -> Result<String> {
    let gallery = crate::app::gallery::render_gallery(out_dir)?;
    Ok(format!(
        "\ngallery renders:\n{}wrote {}\n",
        crate::app::gallery::gallery_table(&gallery),
        gallery.sheet.display()
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vectors_and_sizes_parse() {
        assert_eq!(parse_vec3("1,-2.5, 3"), Ok([1.0, -2.5, 3.0]));
        assert!(parse_vec3("1,2").is_err());
        assert!(parse_vec3("1,nan,2").is_err());
        assert_eq!(parse_size("640x480"), Ok([640, 480]));
        assert!(parse_size("640x0").is_err());
        assert!(parse_size("640").is_err());
        assert_eq!(parse_weld_tolerance("1e-8"), Ok(1e-8));
        assert_eq!(parse_weld_tolerance("0"), Ok(0.0));
        for bad in ["-1e-9", "1", "inf", "nan", "x"] {
            assert!(parse_weld_tolerance(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn options_override_the_scene() {
        let args = RenderArgs {
            input: PathBuf::from("bunny.obj"),
            mode: Some(ModeArg::Isophote),
            size: Some([32, 16]),
            params: vec!["normals=obj".into()],
            ortho: true,
            ..RenderArgs::default()
        };
        let scene = scene_of(&args).expect("scene");
        assert_eq!(scene.mesh, Some(PathBuf::from("bunny.obj")));
        assert_eq!(scene.render.mode.as_deref(), Some("isophote"));
        assert_eq!(scene.render.size, Some([32, 16]));
        assert_eq!(scene.camera.ortho, Some(true));
        assert_eq!(scene.weld_tolerance, None);
        let spin = scene_of(&RenderArgs {
            turntable: Some(12),
            turntable_axis: Some([0.0, 0.0, 1.0]),
            ..args.clone()
        })
        .expect("scene");
        assert_eq!(
            spin.animation().expect("valid"),
            Some(turntable::Animation::Turntable {
                frames: 12,
                axis: Some(glam::DVec3::Z)
            })
        );
        let sweep = RenderArgs {
            sweep: Some(6),
            ..args.clone()
        };
        let err = scene_of(&sweep)
            .and_then(|s| s.animation())
            .expect_err("isophote");
        assert!(err.to_string().contains("isophote"), "{err}");
        let welded = scene_of(&RenderArgs {
            weld_tolerance: Some(0.0),
            ..args.clone()
        })
        .expect("scene");
        assert_eq!(welded.load_options().expect("valid").weld_tolerance, 0.0);
        assert_eq!(
            scene.scheme_params(),
            vec![("normals".to_string(), "obj".to_string())]
        );
    }
}
