//! The `render` subcommand: arguments (clap) and the command itself. The binary only parses
//! and calls [`render_command`]; everything else lives here in the library.

use std::path::PathBuf;

use crate::app::parse_weld_tolerance;
use crate::app::scene::SceneFile;
use crate::app::turntable;
use crate::error::{Error, Result};
use crate::files::check_writable;
use crate::mesh::Mesh;
use crate::render::output::{prepare_outputs, write_outputs};
use crate::render::stats::RenderStats;
use crate::schemes;

/// `smoothlab render SCENE.toml | MESH.obj [options]` — every option overrides the scene.
#[derive(clap::Args, Clone, Debug, Default)]
pub struct RenderArgs {
    /// Scene file (.toml) or mesh (.obj).
    pub input: PathBuf,
    /// Scheme name (default: the scene's, else the first registered scheme).
    #[arg(long)]
    pub scheme: Option<String>,
    /// Scheme parameter `name=value` (repeatable).
    #[arg(long = "param", value_name = "NAME=VALUE")]
    pub params: Vec<String>,
    /// Mode: zebra, highlight, isophote, curvature, normals, patches, diffuse, shaded.
    #[arg(long)]
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
    /// Vertical field of view, degrees.
    #[arg(long)]
    pub fov: Option<f64>,
    /// Orthographic projection.
    #[arg(long)]
    pub ortho: bool,
    /// Image size `WxH`.
    #[arg(long, value_parser = parse_size)]
    pub size: Option<[u32; 2]>,
    /// Samples per pixel.
    #[arg(long)]
    pub spp: Option<u32>,
    /// Output name (writes NAME.png and NAME.exr).
    #[arg(short = 'o', long = "output")]
    pub output: Option<PathBuf>,
    /// Write render statistics as JSON.
    #[arg(long, value_name = "F.json")]
    pub stats: Option<PathBuf>,
    /// Render an N-per-edge tessellation instead of the exact patches.
    #[arg(long, value_name = "N")]
    pub tessellate: Option<u32>,
    /// Boundary overlay: none, faces, patches, both.
    #[arg(long)]
    pub overlay: Option<String>,
    /// Sample seed.
    #[arg(long)]
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
    /// Render N views around an axis through the target (a full turn): writes NAME-000.png …
    /// and the looping NAME.gif instead of NAME.png and NAME.exr.
    #[arg(long, value_name = "N")]
    pub turntable: Option<u32>,
    /// Axis of --turntable `X,Y,Z` (default: the camera's up, --up or +Y).
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true)]
    pub turntable_axis: Option<[f64; 3]>,
    /// Zebra mode: move the stripes over one period in N frames at a fixed camera; writes
    /// NAME-000.png … and the looping NAME.gif.
    #[arg(long, value_name = "N")]
    pub sweep: Option<u32>,
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

/// The scene of `args`: the scene file (or a bare mesh) with every given option applied.
pub fn scene_of(args: &RenderArgs) -> Result<SceneFile> {
    let is_scene = args
        .input
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("toml"));
    let mut scene = if is_scene {
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
    if let Some(s) = &args.scheme {
        scene.scheme.name = Some(s.clone());
    }
    for text in &args.params {
        let (name, value) = schemes::parse_param(text)?;
        scene.scheme.params.insert(name, toml::Value::String(value));
    }
    let r = &mut scene.render;
    if args.mode.is_some() {
        r.mode = args.mode.clone();
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
    if args.overlay.is_some() {
        r.overlay = args.overlay.clone();
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
        .ok_or_else(|| Error::Invalid(format!("{}: no mesh given", args.input.display())))?;
    let scheme = scene
        .scheme
        .name
        .clone()
        .unwrap_or_else(|| schemes::names().first().map_or("hb", |s| s).to_string());
    let name = scene.render.output.clone().unwrap_or_else(|| {
        let mode = scene.render.mode.as_deref().unwrap_or("zebra");
        let mesh = mesh_path
            .file_stem()
            .map_or("render".into(), |s| s.to_string_lossy().into_owned());
        PathBuf::from(format!("{mesh}-{scheme}-{mode}"))
    });
    // Every output path is checked before the (possibly long) work.
    let outputs = prepare_outputs(&name)?;
    let frames = animation
        .map(|a| turntable::prepare_animation(&name, a.frames()))
        .transpose()?;
    if let Some(path) = &args.stats {
        check_writable(path)?;
    }
    let (mesh, report) = Mesh::load_with(&mesh_path, &scene.load_options()?)?;
    let surface = schemes::build(&scheme, &mesh, &scene.scheme_params())?;
    let stats = match (animation, frames) {
        (Some(animation), Some((pngs, gif))) => {
            turntable::render_animation(&job, &animation, &surface, &mesh, &pngs, &gif)?
        }
        _ => {
            let (frame, stats) = job.render(&surface, &mesh)?;
            write_outputs(&frame, &outputs)?;
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
