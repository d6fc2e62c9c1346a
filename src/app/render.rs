//! The `render` subcommand: arguments (clap) and the command itself. The binary only parses
//! and calls [`render_command`]; everything else lives here in the library.

use std::path::{Path, PathBuf};

use crate::app::scene::SceneFile;
use crate::app::turntable;
use crate::app::{parse_crease_angle, parse_weld_tolerance};
use crate::error::{Error, Problem, Result};
use crate::files::{check_distinct, check_writable, utf8_path};
use crate::mesh::Mesh;
use crate::render::modes::{DEFAULT_MODE, Flag, MODE_FLAGS, MODE_HELP, Overlay};
use crate::render::output::{
    ExrCompression, OutputMeta, OutputOptions, prepare_outputs, write_outputs_with,
};
use crate::render::stats::RenderStats;
use crate::render::theme::Theme;
use crate::schemes;

/// The values of `--mode`: every registered mode, with its help.
pub(crate) fn mode_value_parser() -> clap::builder::PossibleValuesParser {
    clap::builder::PossibleValuesParser::new(
        MODE_HELP
            .iter()
            .map(|(name, help)| clap::builder::PossibleValue::new(*name).help(clap_help(help))),
    )
}

/// The values of an option taking one of `choices` (name, the help `--help` shows), as the
/// name: the domain type's list (`Theme::CHOICES`) is the only one.
pub(crate) fn choice_parser(
    choices: &'static [(&'static str, &'static str)],
) -> clap::builder::PossibleValuesParser {
    clap::builder::PossibleValuesParser::new(
        choices
            .iter()
            .map(|(name, help)| clap::builder::PossibleValue::new(*name).help(clap_help(help))),
    )
}

/// A sentence of help as clap shows it: without its final full stop (as clap's derive does
/// with doc comments).
fn clap_help(text: &str) -> &str {
    text.strip_suffix('.').unwrap_or(text)
}

/// Every registered mode's command-line flags, once each (a flag several modes declare, as
/// `--no-stripe-filter`, is one flag), in registry order.
fn mode_flags() -> Vec<&'static Flag> {
    let mut flags: Vec<&'static Flag> = Vec::new();
    for (_, declared) in MODE_FLAGS {
        for flag in declared.iter() {
            if !flags.iter().any(|f| f.long == flag.long) {
                flags.push(flag);
            }
        }
    }
    flags
}

/// The mode flags given on a command line (`--zebra-stripes 8`, `--no-legend`, …, from the
/// modes' [`Flag`]s): each sets one key of its mode's scene section, over the scene.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ModeFlags {
    /// Flag name and value (None: a switch) of every flag given, in registry order.
    pub given: Vec<(&'static str, Option<toml::Value>)>,
}

impl ModeFlags {
    /// `--long VALUE` (the value as its parser gives it) or the switch `--long`, as if given.
    pub fn with(mut self, long: &str, text: Option<&str>) -> Result<ModeFlags> {
        let flag = mode_flags()
            .into_iter()
            .find(|f| f.long == long)
            .ok_or_else(|| {
                Error::config(
                    format!("--{long}"),
                    Problem::Stated {
                        message: format!("no mode has the flag --{long}"),
                    },
                )
            })?;
        let value = match (flag.value, text) {
            (Some(parse), Some(text)) => Some(parse(text).map_err(|e| {
                Error::config(
                    format!("--{long}"),
                    Problem::Other {
                        text: format!("{text}: {e}"),
                    },
                )
            })?),
            (None, None) => None,
            _ => {
                return Err(Error::config(
                    format!("--{long}"),
                    Problem::Other {
                        text: format!(
                            "{} a value",
                            if flag.value.is_some() {
                                "takes"
                            } else {
                                "takes no"
                            }
                        ),
                    },
                ));
            }
        };
        self.given.push((flag.long, value));
        Ok(self)
    }

    /// Writes the flags into the scene's mode sections, each replacing the keys its flag
    /// replaces. Two given flags that set the same thing are refused.
    fn apply(&self, scene: &mut SceneFile) -> Result<()> {
        let flags = mode_flags();
        let spec = |long: &str| flags.iter().copied().find(|f| f.long == long);
        for (long, _) in &self.given {
            let Some(flag) = spec(long) else { continue };
            if let Some(other) = flag
                .conflicts
                .iter()
                .find(|c| self.given.iter().any(|(l, _)| l == *c))
            {
                let (a, b) = if flags.iter().position(|f| f.long == *long)
                    < flags.iter().position(|f| f.long == *other)
                {
                    (*long, *other)
                } else {
                    (*other, *long)
                };
                return Err(Error::config(
                    format!("--{a}"),
                    Problem::Other {
                        text: format!(
                            "and --{b} both given: they set the same parameter, give one, not both"
                        ),
                    },
                ));
            }
        }
        for (long, value) in &self.given {
            for (mode, declared) in MODE_FLAGS {
                for flag in declared.iter().filter(|f| f.long == *long) {
                    let section = scene.mode_section_mut(mode);
                    for key in flag.replaces {
                        section.remove(*key);
                    }
                    let value = value.clone().unwrap_or(toml::Value::Boolean(false));
                    section.insert(flag.key.to_string(), value);
                }
            }
        }
        Ok(())
    }
}

impl clap::FromArgMatches for ModeFlags {
    fn from_arg_matches(matches: &clap::ArgMatches) -> std::result::Result<Self, clap::Error> {
        let mut given = Vec::new();
        for flag in mode_flags() {
            if flag.value.is_none() {
                if matches.get_flag(flag.long) {
                    given.push((flag.long, None));
                }
            } else if let Some(v) = matches.get_one::<toml::Value>(flag.long) {
                given.push((flag.long, Some(v.clone())));
            }
        }
        Ok(ModeFlags { given })
    }

    fn update_from_arg_matches(
        &mut self,
        matches: &clap::ArgMatches,
    ) -> std::result::Result<(), clap::Error> {
        *self = ModeFlags::from_arg_matches(matches)?;
        Ok(())
    }
}

impl clap::Args for ModeFlags {
    fn augment_args(cmd: clap::Command) -> clap::Command {
        let mut cmd = cmd;
        for flag in mode_flags() {
            let mut arg = clap::Arg::new(flag.long)
                .long(flag.long)
                .help(clap_help(flag.help));
            arg = match flag.value {
                None => arg.action(clap::ArgAction::SetTrue),
                Some(_) if !flag.choices.is_empty() => {
                    let choices =
                        clap::builder::PossibleValuesParser::new(flag.choices.iter().map(
                            |(name, help)| clap::builder::PossibleValue::new(*name).help(*help),
                        ));
                    arg.action(clap::ArgAction::Set).value_parser(
                        clap::builder::TypedValueParser::map(choices, toml::Value::String),
                    )
                }
                Some(parse) => arg
                    .action(clap::ArgAction::Set)
                    .value_parser(clap::builder::ValueParser::new(parse)),
            };
            if !flag.value_name.is_empty() {
                arg = arg.value_name(flag.value_name);
            }
            if flag.hyphen_values {
                arg = arg.allow_hyphen_values(true);
            }
            cmd = cmd.arg(arg);
        }
        cmd
    }

    fn augment_args_for_update(cmd: clap::Command) -> clap::Command {
        ModeFlags::augment_args(cmd)
    }
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
    #[arg(long, value_parser = mode_value_parser())]
    pub mode: Option<String>,
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
    #[arg(long, value_parser = choice_parser(&Overlay::CHOICES))]
    pub overlay: Option<String>,
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
    #[arg(long, value_parser = choice_parser(&ExrCompression::CHOICES))]
    pub exr_compression: Option<String>,
    /// Colours around the image [default: dark] (scene: `render.theme`).
    #[arg(long, value_parser = choice_parser(&Theme::CHOICES))]
    pub theme: Option<String>,
    /// The modes' own flags (`--zebra-stripes`, `--curvature-range`, …; see each mode's
    /// [`crate::render::modes::ModeKind::FLAGS`]).
    #[command(flatten)]
    pub mode_flags: ModeFlags,
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

/// Parses `X,Y,Z` ([`crate::render::modes::keys::parse_triple`]).
pub(crate) fn parse_vec3(text: &str) -> std::result::Result<[f64; 3], String> {
    crate::render::modes::keys::parse_triple(text)
}

/// Parses a vertical field of view in degrees (`--fov`): finite, at least
/// [`MIN_FOV_DEG`](crate::render::camera::MIN_FOV_DEG) and below 180.
pub(crate) fn parse_fov(text: &str) -> std::result::Result<f64, String> {
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
pub(crate) fn parse_size(text: &str) -> std::result::Result<[u32; 2], String> {
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
pub(crate) fn scene_of(args: &RenderArgs) -> Result<SceneFile> {
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
    if let Some(m) = &args.mode {
        r.mode = Some(m.clone());
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
    if let Some(o) = &args.overlay {
        r.overlay = Some(o.clone());
    }
    if args.no_exr {
        r.exr = Some(false);
    }
    if let Some(c) = &args.exr_compression {
        r.exr_compression = Some(c.clone());
    }
    if let Some(t) = &args.theme {
        r.theme = Some(t.clone());
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
    args.mode_flags.apply(&mut scene)?;
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
        .ok_or_else(|| crate::app::scene::no_mesh_given(&args.input))?;
    let load_options = scene.load_options()?;
    let exr = scene.exr_compression()?;
    // The frame and its files are the largest allocation a small mesh makes: refused first.
    crate::render::film::check_frame_memory(
        job.settings.width,
        job.settings.height,
        crate::render::output::output_bytes_per_pixel(exr.is_some()),
    )?;
    let scheme = scene.scheme.name.clone().ok_or_else(|| {
        Error::config(
            "scheme.name (--scheme)",
            Problem::Stated {
                message: format!(
                    "no scheme given: pass --scheme NAME (one of {}) or set [scheme] name in a \
                     scene",
                    schemes::names().join(", ")
                ),
            },
        )
        .within(args.input.display().to_string())
    })?;
    schemes::find(&scheme)?;
    let name = match scene.render.output.clone() {
        Some(name) => name,
        None => {
            let mode = scene.render.mode.as_deref().unwrap_or(DEFAULT_MODE);
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
        return Err(Error::config(
            "--shard",
            Problem::Other {
                text: "splits the frames of --turntable or --sweep; a single image is one piece"
                    .into(),
            },
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
    let mode_files = scene.mode_files();
    let mut read: Vec<(&str, &Path)> = vec![("the mesh", &mesh_path)];
    if is_scene_file(&args.input) {
        read.push(("the scene file", &args.input));
    }
    read.extend(
        mode_files
            .iter()
            .map(|(what, file)| (*what, file.as_path())),
    );
    check_distinct(&read, &written)?;
    let (mesh, mut report) = Mesh::load_with(&mesh_path, &load_options)?;
    let surface = schemes::build(&scheme, &mesh, &scene.scheme_params())?;
    report.warnings.extend(surface.warnings.iter().cloned());
    report.warnings.extend(resolution_warning(&surface, &mesh));
    let job = job.for_mesh(&mesh);
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

/// The warning for patches the exact tracer cannot resolve where they lie
/// ([`crate::render::intersect::unresolved_patches`]: the surface spans about seven orders of
/// magnitude or more), naming the first one's input face and the surface's bounding box, where
/// a stray far vertex shows; None when there are none.
pub(crate) fn resolution_warning(surface: &crate::surface::Surface, mesh: &Mesh) -> Option<String> {
    let unresolved = crate::render::intersect::unresolved_patches(surface);
    let &first = unresolved.first()?;
    let patch = &surface.patches[first as usize];
    let bounds = surface.bounds();
    let size = patch.full_bounds().diagonal();
    Some(format!(
        "{}: {} of {} patches (first: patch {first}, of face {}, {size:.3e} across) are below \
         the exact renderer's resolution where they lie: the surface's bounding box runs from \
         {} to {} (diagonal {:.3e}), beyond the f32 precision of the tracer's bounds; their \
         hits are accurate to 1e-9 of that diagonal only, and slow to find when seen close \
         up. Look for stray vertices far from the model",
        surface.scheme,
        unresolved.len(),
        surface.patches.len(),
        mesh.input_face(patch.face),
        fmt_point(bounds.min),
        fmt_point(bounds.max),
        bounds.diagonal(),
    ))
}

/// A point as `(x, y, z)` with four significant digits.
fn fmt_point(p: glam::DVec3) -> String {
    format!("({:.3e}, {:.3e}, {:.3e})", p.x, p.y, p.z)
}

/// One line about a finished render, for the terminal: what a user needs first (hits, rays
/// that missed the surface, time), then the tracer's work. Roots the leaf's fallback
/// subdivision found after Newton did not settle (`newton_failures` in the stats JSON) are
/// said as such: they are hits, not missed rays (docs/metrics.md, "Words the renderer prints").
pub(crate) fn render_summary(stats: &RenderStats) -> String {
    let stripes = match stats.zebra_stripes {
        Some(n) => format!(
            "zebra: {n} stripes per turn, chosen from the view (`--zebra-stripes N` fixes the count)\n"
        ),
        None => String::new(),
    };
    let work = format!(
        "{} rays: {} hit the surface, {} missed it; render {:.1} ms, BVH {:.1} ms ({} leaves); \
         Newton {:.2} iterations mean, {} max, {} roots found by the fallback subdivision\n",
        stats.rays,
        stats.hits,
        stats.misses,
        stats.render_ms,
        stats.bvh_build_ms,
        stats.leaves,
        stats.newton_iter_mean,
        stats.newton_iter_max,
        stats.newton_failures,
    );
    work + &stripes
}

/// Renders the gallery into `out_dir` and returns its table and where the sheet went.
pub(crate) fn run_gallery(out_dir: &std::path::Path) -> Result<String> {
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
            mode: Some("isophote".into()),
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
        // Mode flags land in their modes' sections; a switch several modes declare sets
        // each; a flag replaces the key it stands for.
        let flags = ModeFlags::default()
            .with("zebra-stripes", Some("8"))
            .and_then(|f| f.with("no-stripe-filter", None))
            .expect("flags");
        let mut flagged = SceneFile::parse("[zebra]\nwidth = \"thin\"").expect("scene");
        flags.apply(&mut flagged).expect("applied");
        let zebra = flagged.mode_section("zebra");
        assert_eq!(zebra.get("stripes"), Some(&toml::Value::Float(8.0)));
        assert!(!zebra.contains_key("width"));
        for mode in ["zebra", "highlight", "isophote"] {
            let section = flagged.mode_section(mode);
            assert_eq!(
                section.get("filter"),
                Some(&toml::Value::Boolean(false)),
                "{mode}"
            );
        }
        assert!(flagged.mode_section("curvature").is_empty());
        let both = flags.with("zebra-width", Some("thin")).expect("flags");
        let err = both
            .apply(&mut SceneFile::default())
            .expect_err("one period")
            .to_string();
        assert!(err.contains("--zebra-stripes and --zebra-width"), "{err}");
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

    /// The config error of `key` that `err` is, inside its place if it has one.
    fn config_of(err: &Error) -> (&str, &Problem) {
        match err {
            Error::Config { key, problem } => (key, problem),
            Error::In { error, .. } => config_of(error),
            other => panic!("not a configuration error: {other:?}"),
        }
    }

    /// Bad flag values, conflicting flags and flags without their animation are typed
    /// configuration errors naming the flag, worded as before.
    #[test]
    fn flag_errors_are_config_errors() {
        let err = ModeFlags::default()
            .with("zebra-stripes", Some("many"))
            .expect_err("not a number");
        assert!(
            matches!(err, Error::Config { ref key, problem: Problem::Other { .. } } if key == "--zebra-stripes"),
            "{err:?}"
        );
        assert!(
            err.to_string().starts_with("--zebra-stripes many: "),
            "{err}"
        );
        let err = ModeFlags::default()
            .with("zebra-stripes", None)
            .expect_err("takes a value");
        assert!(matches!(
            config_of(&err),
            ("--zebra-stripes", Problem::Other { .. })
        ));
        assert_eq!(err.to_string(), "--zebra-stripes takes a value");
        let err = ModeFlags::default()
            .with("no-such-flag", None)
            .expect_err("unknown");
        assert!(matches!(
            config_of(&err),
            ("--no-such-flag", Problem::Stated { .. })
        ));
        assert_eq!(err.to_string(), "no mode has the flag --no-such-flag");
        let err = ModeFlags::default()
            .with("zebra-width", Some("thin"))
            .and_then(|f| f.with("zebra-stripes", Some("8")))
            .expect("flags")
            .apply(&mut SceneFile::default())
            .expect_err("one period");
        assert!(matches!(
            config_of(&err),
            ("--zebra-stripes", Problem::Other { .. })
        ));
        assert_eq!(
            err.to_string(),
            "--zebra-stripes and --zebra-width both given: they set the same parameter, give \
             one, not both"
        );
        let args = RenderArgs {
            input: PathBuf::from("bunny.obj"),
            ..RenderArgs::default()
        };
        let err = render_command(&args).expect_err("no scheme");
        assert!(matches!(
            config_of(&err),
            ("scheme.name (--scheme)", Problem::Stated { .. })
        ));
        assert!(
            err.to_string()
                .starts_with("bunny.obj: no scheme given: pass --scheme NAME (one of "),
            "{err}"
        );
        let err = render_command(&RenderArgs {
            scheme: Some("flat".into()),
            shard: Some(crate::report::shard::Shard { index: 0, count: 2 }),
            ..args
        })
        .expect_err("one image");
        assert!(matches!(
            config_of(&err),
            ("--shard", Problem::Other { .. })
        ));
        assert_eq!(
            err.to_string(),
            "--shard splits the frames of --turntable or --sweep; a single image is one piece"
        );
    }
}
