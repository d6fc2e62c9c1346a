//! Turntables and stripe sweeps of `smoothlab render`: a series of frames of one surface,
//! written as `NAME-000.png`, `NAME-001.png`, … and one looping animated `NAME.gif`.
//!
//! - A **turntable** (`--turntable N`, scene key `render.turntable`) turns the camera about the
//!   line through its target along an axis (`--turntable-axis X,Y,Z`, `render.turntable_axis`;
//!   default the camera's up, `--up` or +Y) in N equal steps of a full turn: reflection lines
//!   sliding across a seam show a break far better than one view.
//! - A **stripe sweep** (`--sweep N`, `render.sweep`, zebra mode only) keeps the camera and
//!   moves the zebra stripes over one period in N steps ([`crate::render::modes::ModeKind::swept`] with shift k / N).
//!
//! The surface does not change between frames, so the BVH (or tessellation) is built once and
//! every frame is traced through it. Frames are rendered one after the other, each split into
//! the renderer's fixed tiles, so they are bit-identical for any thread count. An automatic
//! framing is widened so that the surface stays in frame in every view of a turntable. A curvature
//! mode with an automatic range takes the range of the first frame for every frame, so the
//! colours of the frames compare. A progress bar over the frames shows on standard error when
//! it is a terminal.

use std::f64::consts::TAU;
use std::path::{Path, PathBuf};

use glam::DVec3;
use image::codecs::gif::{GifEncoder, Repeat};
use image::{Delay, RgbaImage};

use crate::error::{Error, Problem, Result};
use crate::files::{check_writable, create_folder, write_atomic};
use crate::mesh::Mesh;
use crate::render::camera::{Camera, Projection, unit};
use crate::render::film::{Frame, RenderSettings};
use crate::render::job::{JobTracer, RenderJob, SurfaceSamples};
use crate::render::output::{check_output_name, output_stem, srgb8, with_suffix, write_png};
use crate::render::stats::RenderStats;
use crate::report::shard::{Manifest, Shard, items_of, read_complete_parts};
use crate::surface::Surface;

/// The most frames of a turntable or sweep.
pub(crate) const MAX_FRAMES: u32 = 3600;

/// Time each frame of the animated GIF shows, milliseconds (12.5 frames per second).
pub(crate) const FRAME_DELAY_MS: u32 = 80;

/// Speed of the GIF colour quantiser (1 best … 30 fastest; 10 is the `gif` crate's
/// recommended balance).
const GIF_SPEED: i32 = 10;

/// A series of frames instead of one image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Animation {
    /// The camera turns about an axis through the target.
    Turntable {
        /// Number of frames (views), evenly spread over a full turn.
        frames: u32,
        /// The axis (unit); `None`: the camera's up.
        axis: Option<DVec3>,
    },
    /// The zebra stripes move over one period at a fixed camera.
    Sweep {
        /// Number of frames, evenly spread over one period.
        frames: u32,
    },
}

impl Animation {
    /// Number of frames.
    pub fn frames(&self) -> u32 {
        match *self {
            Animation::Turntable { frames, .. } | Animation::Sweep { frames } => frames,
        }
    }

    /// Checks a frame count given by `key` (the scene key and its flag).
    pub fn check_frames(key: &str, frames: u32) -> Result<u32> {
        crate::render::modes::keys::in_count_range(key, frames, 1, MAX_FRAMES)
    }
}

/// The files of an animation of `frames` frames named `name`: the frames `STEM-000.png` …
/// (at least three digits, more when needed, so they sort in order) and `STEM.gif`, where
/// `STEM` is [`output_stem`] of `name`.
pub(crate) fn animation_files(name: &Path, frames: u32) -> (Vec<PathBuf>, PathBuf) {
    let stem = output_stem(name);
    let digits = frames.saturating_sub(1).to_string().len().max(3);
    let base = stem
        .file_name()
        .map_or("render".into(), |s| s.to_string_lossy().into_owned());
    let pngs = (0..frames)
        .map(|k| stem.with_file_name(format!("{base}-{k:0digits$}.png")))
        .collect();
    (pngs, with_suffix(&stem, "gif"))
}

/// [`animation_files`], each checked writable (the folder must exist: see
/// [`crate::render::output::prepare_outputs`], which creates it).
pub(crate) fn prepare_animation(name: &Path, frames: u32) -> Result<(Vec<PathBuf>, PathBuf)> {
    let (pngs, gif) = animation_files(name, frames);
    for file in pngs.iter().chain([&gif]) {
        check_writable(file)?;
    }
    Ok((pngs, gif))
}

/// The camera and settings of frame `k` of `animation`, from the first frame's camera and
/// settings.
pub(crate) fn frame_view(
    animation: &Animation,
    k: u32,
    camera: &Camera,
    axis: DVec3,
    settings: &RenderSettings,
) -> Result<(Camera, RenderSettings)> {
    match *animation {
        Animation::Turntable { frames, .. } => {
            let angle = TAU * f64::from(k) / f64::from(frames);
            Ok((camera.orbit(axis, angle)?, settings.clone()))
        }
        Animation::Sweep { frames } => {
            let mode = settings
                .mode
                .swept(f64::from(k) / f64::from(frames))
                .ok_or_else(|| {
                    Error::config(
                        "render.sweep (--sweep)",
                        Problem::Stated {
                            message: format!(
                                "a stripe sweep needs a mode with stripes to move, not '{}'",
                                settings.mode.name()
                            ),
                        },
                    )
                })?;
            Ok((
                *camera,
                RenderSettings {
                    mode,
                    ..settings.clone()
                },
            ))
        }
    }
}

/// The turntable axis: the given one, else the camera spec's up (+Y when unset), else — when
/// that is parallel to the view — the camera's image up.
fn turntable_axis(animation: &Animation, job: &RenderJob, camera: &Camera) -> DVec3 {
    if let Animation::Turntable {
        axis: Some(axis), ..
    } = animation
    {
        return *axis;
    }
    let up = job.camera.up.and_then(unit).unwrap_or(DVec3::Y);
    if up.cross(camera.forward()).length() > 1e-9 {
        up
    } else {
        camera.up()
    }
}

/// The camera of frame 0: the job's; for a turntable framed automatically (no eye, no target),
/// moved back along its view until every view of the turn frames the whole surface, as
/// automatic framing frames the first.
pub(crate) fn first_camera(
    job: &RenderJob,
    animation: &Animation,
    surface: &Surface,
    aspect: f64,
) -> Result<Camera> {
    let camera = job.camera.camera(surface, aspect)?;
    let Animation::Turntable { frames, .. } = *animation else {
        return Ok(camera);
    };
    if job.camera.eye.is_some() || job.camera.target.is_some() {
        return Ok(camera);
    }
    // Every view of the turn looks at the centre of the surface's box, so the turn orbits it.
    let samples = SurfaceSamples::of(surface);
    let fov = job.camera.fov_deg;
    let fit = |view: &Camera| {
        Camera::frame_points_at_centre(&samples, view.eye - view.target, view.up(), fov, aspect)
    };
    let camera = fit(&camera)?;
    let axis = turntable_axis(animation, job, &camera);
    let back = camera.eye - camera.target;
    let mut distance = back.length();
    for k in 1..frames {
        let fitted = fit(&camera.orbit(axis, TAU * f64::from(k) / f64::from(frames))?)?;
        distance = distance.max(fitted.eye.distance(fitted.target));
    }
    let perspective = Camera::look_at(
        camera.target + back * (distance / back.length()),
        camera.target,
        camera.up(),
        Projection::Perspective { fov_deg: fov },
    )?;
    if job.camera.orthographic {
        perspective.orthographic_of(fov)
    } else {
        Ok(perspective)
    }
}

/// Adds the statistics of one more frame: counts add up, the slowest Newton solve is the
/// largest, the mean iteration count is weighted by hits; the build figures are the tracer's.
fn accumulate(total: &mut RenderStats, frame: &RenderStats) {
    let hits = total.hits + frame.hits;
    if hits > 0 {
        total.newton_iter_mean = (total.newton_iter_mean * total.hits as f64
            + frame.newton_iter_mean * frame.hits as f64)
            / hits as f64;
    }
    total.rays += frame.rays;
    total.hits = hits;
    total.misses += frame.misses;
    total.newton_iter_max = total.newton_iter_max.max(frame.newton_iter_max);
    total.newton_failures += frame.newton_failures;
    total.render_ms += frame.render_ms;
    total.pixels += frame.pixels;
    total.newton_runs += frame.newton_runs;
    total.fallback_roots += frame.fallback_roots;
    total.newton_unconverged += frame.newton_unconverged;
    total.newton_undecided += frame.newton_undecided;
    total.newton_boundary_cleared += frame.newton_boundary_cleared;
    total.bvh_build_ms = frame.bvh_build_ms;
    total.leaves = frame.leaves;
    total.memory_bytes = frame.memory_bytes;
    total.memory_parts = frame.memory_parts.clone();
    total.patches = frame.patches;
    total.curvature_half_range = frame.curvature_half_range;
    total.zebra_stripes = total.zebra_stripes.or(frame.zebra_stripes);
    total.set_rates();
}

/// A progress bar over `frames` frames on standard error (see [`crate::progress`]).
fn progress_bar(animation: &Animation) -> indicatif::ProgressBar {
    let bar = crate::progress::bar(
        u64::from(animation.frames()),
        "{prefix} {bar:40} {pos}/{len} frames {elapsed} (eta {eta})",
    );
    bar.set_prefix(match animation {
        Animation::Turntable { .. } => "turntable",
        Animation::Sweep { .. } => "sweep",
    });
    bar
}

/// Renders every frame of `animation` of `surface` (built on `mesh`) with `job`, writes them to
/// `pngs` and the looping GIF to `gif`, and returns the statistics of all frames together.
pub fn render_animation(
    job: &RenderJob,
    animation: &Animation,
    surface: &Surface,
    mesh: &Mesh,
    pngs: &[PathBuf],
    gif: &Path,
) -> Result<RenderStats> {
    render_animation_frames(job, animation, surface, mesh, pngs, Some(gif), &|_| true)
}

/// The kind of work of partial frame sets, in their [`Manifest`].
pub(crate) const FRAMES_KIND: &str = "frames";

/// What one shard of a turntable or sweep wrote beside its frames
/// (`STEM.shard-I-of-N.json`): which frames it rendered, and every frame's file name.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub(crate) struct FramesPart {
    /// Which shard of which run.
    pub manifest: Manifest,
    /// File names (beside this file) of every frame of the animation, in order.
    pub frames: Vec<String>,
    /// The frames (positions in `frames`) this shard rendered.
    pub rendered: Vec<usize>,
    /// File name of the animation's GIF, which `merge` writes.
    pub gif: String,
    /// Rays traced by this shard.
    pub rays: u64,
    /// Its render time, milliseconds.
    pub render_ms: f64,
}

/// The file of `shard`'s [`FramesPart`] for an animation named `name`.
pub(crate) fn part_path(name: &Path, shard: Shard) -> PathBuf {
    let stem = output_stem(name);
    let base = stem
        .file_name()
        .map_or("render".into(), |s| s.to_string_lossy().into_owned());
    stem.with_file_name(format!(
        "{base}.shard-{}-of-{}.json",
        shard.index, shard.count
    ))
}

/// Renders `shard`'s share of the frames of `animation` (frames dealt round-robin: every frame
/// costs about the same) into their files `pngs` and writes its [`FramesPart`] to `part`; no
/// GIF (`merge` writes it). The frames are the bytes the whole run writes: the camera of every
/// view is computed as in the whole run, and an automatic curvature range still comes from
/// frame 0, rendered (not written) by every shard that does not own it.
#[allow(clippy::too_many_arguments)]
pub(crate) fn render_animation_shard(
    job: &RenderJob,
    animation: &Animation,
    surface: &Surface,
    mesh: &Mesh,
    pngs: &[PathBuf],
    gif: &Path,
    shard: Shard,
    part: &Path,
) -> Result<RenderStats> {
    check_writable(part)?;
    let costs = vec![1.0; pngs.len()];
    let rendered = items_of(&costs, shard);
    let wanted = |k: u32| rendered.binary_search(&(k as usize)).is_ok();
    let stats = render_animation_frames(job, animation, surface, mesh, pngs, None, &wanted)?;
    let file_name = |p: &Path| {
        p.file_name()
            .map_or(String::new(), |n| n.to_string_lossy().into_owned())
    };
    let frames: Vec<String> = pngs.iter().map(|p| file_name(p)).collect();
    // The work: everything that decides the frames' pixels and names.
    let work = format!(
        "{job:?}|{animation:?}|{}|{}|{}|{frames:?}",
        surface.scheme,
        surface.patches.len(),
        mesh.face_count()
    );
    let record = FramesPart {
        manifest: Manifest::new(FRAMES_KIND, shard, &work, pngs.len()),
        frames,
        rendered,
        gif: file_name(gif),
        rays: stats.rays,
        render_ms: stats.render_ms,
    };
    let text = serde_json::to_string_pretty(&record)
        .map_err(|e| Error::Invalid(format!("frames part JSON: {e}")))?;
    write_atomic(part, text.as_bytes())?;
    Ok(stats)
}

/// A GIF encoder of the animations' settings (quantiser speed, endless loop) writing to `bytes`.
fn gif_encoder<'a>(bytes: &'a mut Vec<u8>, gif: &Path) -> Result<GifEncoder<&'a mut Vec<u8>>> {
    let mut encoder = GifEncoder::new_with_speed(bytes, GIF_SPEED);
    encoder
        .set_repeat(Repeat::Infinite)
        .map_err(|e| Error::Invalid(format!("{}: {e}", gif.display())))?;
    Ok(encoder)
}

/// Adds one frame to an animation's GIF.
fn gif_frame(encoder: &mut GifEncoder<&mut Vec<u8>>, image: RgbaImage, gif: &Path) -> Result<()> {
    let delay = Delay::from_numer_denom_ms(FRAME_DELAY_MS, 1);
    encoder
        .encode_frame(image::Frame::from_parts(image, 0, 0, delay))
        .map_err(|e| Error::Invalid(format!("{}: {e}", gif.display())))
}

/// Merges the frame parts `parts` (`STEM.shard-I-of-N.json` files) of one animation: checks
/// that they are the shards of one run and that every frame file is there, copies the frames to
/// `name`'s frame files when `name` names other files, and writes `name`'s GIF from them, the
/// bytes the whole run writes. Returns a line for the terminal. A missing shard is an error
/// naming it.
pub(crate) fn merge_frames(parts: &[PathBuf], name: &Path) -> Result<String> {
    check_output_name(name)?;
    let read = read_complete_parts(
        parts,
        "frames",
        |part: &FramesPart| &part.manifest,
        "frames are not merged",
    )?;
    let count = read[0].1.manifest.shard.count;
    let n = read[0].1.frames.len();
    let frames_u32 =
        u32::try_from(n).map_err(|_| Error::Invalid(format!("merge: {n} frames are too many")))?;
    let mut sources: Vec<Option<PathBuf>> = vec![None; n];
    for (path, part) in &read {
        let dir = path.parent().unwrap_or(Path::new("."));
        for &k in &part.rendered {
            let slot = sources.get_mut(k).ok_or_else(|| {
                Error::Invalid(format!("{}: frame {k} out of range", path.display()))
            })?;
            let frame = part.frames.get(k).ok_or_else(|| {
                Error::Invalid(format!(
                    "{}: frames lists {} names, rendered names frame {k}",
                    path.display(),
                    part.frames.len()
                ))
            })?;
            *slot = Some(dir.join(frame));
        }
    }
    let (pngs, gif) = animation_files(name, frames_u32);
    // The folder of NAME is created if missing, as `render -o NAME` does.
    if let Some(folder) = gif.parent().filter(|f| !f.as_os_str().is_empty()) {
        create_folder(folder)?;
    }
    for file in pngs.iter().chain([&gif]) {
        check_writable(file)?;
    }
    let mut bytes = Vec::new();
    {
        let mut encoder = gif_encoder(&mut bytes, &gif)?;
        for (k, (source, png)) in sources.iter().zip(&pngs).enumerate() {
            let source = source
                .as_ref()
                .ok_or_else(|| Error::Invalid(format!("merge: no shard rendered frame {k}")))?;
            let data = std::fs::read(source).map_err(|e| {
                Error::Invalid(format!(
                    "{}: frame {k} is missing ({e}): its shard did not finish",
                    source.display()
                ))
            })?;
            let image = image::load_from_memory_with_format(&data, image::ImageFormat::Png)
                .map_err(|e| Error::Invalid(format!("{}: {e}", source.display())))?
                .to_rgba8();
            let same = std::fs::canonicalize(source).ok() == std::fs::canonicalize(png).ok();
            if !same {
                write_atomic(png, &data)?;
            }
            gif_frame(&mut encoder, image, &gif)?;
        }
    }
    write_atomic(&gif, &bytes)?;
    Ok(format!(
        "merged {n} frames of {count} shards: {} … and {}\n",
        pngs.first()
            .map_or(String::new(), |p| p.display().to_string()),
        gif.display()
    ))
}

/// [`render_animation`] of the frames `wanted` says, the GIF only when `gif` is given.
fn render_animation_frames(
    job: &RenderJob,
    animation: &Animation,
    surface: &Surface,
    mesh: &Mesh,
    pngs: &[PathBuf],
    gif: Option<&Path>,
    wanted: &dyn Fn(u32) -> bool,
) -> Result<RenderStats> {
    let mut settings = job.settings_for(surface, mesh)?;
    settings.progress = false;
    let aspect = f64::from(settings.width) / f64::from(settings.height);
    let camera = first_camera(job, animation, surface, aspect)?;
    let tracer = job.tracer(surface)?;
    let frames = Frames { pngs, gif, wanted };
    render_frames(&tracer, job, animation, &camera, settings, &frames)
}

/// The frame as an RGBA image (opaque), its legend beside it as in the PNG.
fn rgba(frame: &Frame) -> RgbaImage {
    let rgb = srgb8(frame);
    let bytes = rgb
        .chunks_exact(3)
        .flat_map(|p| [p[0], p[1], p[2], 255])
        .collect();
    RgbaImage::from_raw(frame.png_width(), frame.height, bytes)
        .unwrap_or_else(|| RgbaImage::new(frame.png_width(), frame.height))
}

/// Where the frames go: every frame's file, the GIF (if written) and which frames to render.
struct Frames<'a> {
    pngs: &'a [PathBuf],
    gif: Option<&'a Path>,
    wanted: &'a dyn Fn(u32) -> bool,
}

/// Refuses an image size an animated GIF cannot hold (at most 65535 pixels a side).
fn check_gif_size(width: u32, height: u32) -> Result<()> {
    if u16::try_from(width).is_err() || u16::try_from(height).is_err() {
        return Err(Error::config(
            "render.size (--size)",
            Problem::Stated {
                message: format!(
                    "an animated GIF is at most 65535 pixels per side, not {width}x{height}"
                ),
            },
        ));
    }
    Ok(())
}

/// [`render_animation_frames`] through one built tracer.
fn render_frames(
    tracer: &JobTracer<'_>,
    job: &RenderJob,
    animation: &Animation,
    camera: &Camera,
    mut settings: RenderSettings,
    out: &Frames,
) -> Result<RenderStats> {
    check_gif_size(settings.width, settings.height)?;
    let axis = turntable_axis(animation, job, camera);
    let bar = progress_bar(animation);
    let mut total = RenderStats::default();
    let mut bytes = Vec::new();
    {
        let mut encoder = out
            .gif
            .map(|gif| gif_encoder(&mut bytes, gif))
            .transpose()?;
        let from_view = settings.mode.chosen_from_view();
        for (k, png) in (0..animation.frames()).zip(out.pngs) {
            let wanted = (out.wanted)(k);
            // Frame 0 fixes what the mode chooses from the view (an automatic curvature
            // range, a zebra stripe count) for every frame: rendered even when another shard
            // writes it.
            if !(wanted || k == 0 && from_view) {
                continue;
            }
            let (view, frame_settings) = frame_view(animation, k, camera, axis, &settings)?;
            let (frame, stats) = tracer.render_frame(&view, &frame_settings)?;
            if k == 0 {
                // Every frame in the colours of the first.
                settings.mode = settings.mode.pinned(&stats);
            }
            accumulate(&mut total, &stats);
            if !wanted {
                continue;
            }
            write_png(&frame, png)?;
            if let (Some(encoder), Some(gif)) = (encoder.as_mut(), out.gif) {
                gif_frame(encoder, rgba(&frame), gif)?;
            }
            bar.inc(1);
        }
    }
    bar.finish_and_clear();
    if let Some(gif) = out.gif {
        write_atomic(gif, &bytes)?;
    }
    Ok(total)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::test_support::assert_config_error;
    use crate::render::modes::Mode;

    #[test]
    fn frame_files_are_numbered_in_order() {
        let (pngs, gif) = animation_files(Path::new("out/spin.png"), 3);
        assert_eq!(
            pngs,
            ["out/spin-000.png", "out/spin-001.png", "out/spin-002.png"].map(PathBuf::from)
        );
        assert_eq!(gif, PathBuf::from("out/spin.gif"));
        let (pngs, _) = animation_files(Path::new("spin"), 1001);
        assert_eq!(pngs[1000], PathBuf::from("spin-1000.png"));
        assert_eq!(pngs[7], PathBuf::from("spin-0007.png"));
        assert!(Animation::check_frames("render.turntable", 0).is_err());
        assert!(Animation::check_frames("render.turntable", MAX_FRAMES + 1).is_err());
        assert_eq!(Animation::check_frames("render.sweep", 36).ok(), Some(36));
    }

    #[test]
    fn views_turn_the_camera_or_move_the_stripes() {
        let camera = Camera::look_at(
            DVec3::new(0.0, 1.0, 4.0),
            DVec3::ZERO,
            DVec3::Y,
            Projection::Perspective { fov_deg: 30.0 },
        )
        .expect("camera");
        let settings = RenderSettings::default();
        let turntable = Animation::Turntable {
            frames: 4,
            axis: None,
        };
        let (first, s0) = frame_view(&turntable, 0, &camera, DVec3::Y, &settings).expect("view");
        assert_eq!(first, camera);
        assert_eq!(s0.mode, settings.mode);
        let (half, _) = frame_view(&turntable, 2, &camera, DVec3::Y, &settings).expect("view");
        assert!(half.eye.distance(DVec3::new(0.0, 1.0, -4.0)) < 1e-12);
        let sweep = Animation::Sweep { frames: 4 };
        let (same, s3) = frame_view(&sweep, 3, &camera, DVec3::Y, &settings).expect("view");
        assert_eq!(same, camera);
        assert_eq!(Some(s3.mode), settings.mode.swept(0.75));
        assert_ne!(settings.mode.swept(0.75), settings.mode.swept(0.5));
        let diffuse = RenderSettings {
            mode: Mode::by_name("diffuse").expect("mode"),
            ..settings
        };
        let err = frame_view(&sweep, 1, &camera, DVec3::Y, &diffuse).expect_err("no stripes");
        assert!(err.to_string().contains("diffuse"), "{err}");
        assert_config_error(
            &err,
            "render.sweep (--sweep)",
            |p| matches!(p, Problem::Stated { .. }),
            "a stripe sweep needs a mode with stripes to move, not 'diffuse'",
        );
    }

    /// An animation's size must fit a GIF: a configuration error of `render.size`.
    #[test]
    fn gif_sides_are_limited() {
        assert!(check_gif_size(65535, 1).is_ok());
        let err = check_gif_size(65536, 10).expect_err("too wide");
        assert_config_error(
            &err,
            "render.size (--size)",
            |p| matches!(p, Problem::Stated { .. }),
            "an animated GIF is at most 65535 pixels per side, not 65536x10",
        );
    }

    #[test]
    fn the_default_axis_is_the_up_unless_it_is_the_view() {
        let job = RenderJob::default();
        let side = Camera::look_at(
            DVec3::new(0.0, 1.0, 4.0),
            DVec3::ZERO,
            DVec3::Y,
            Projection::Perspective { fov_deg: 30.0 },
        )
        .expect("camera");
        let turntable = Animation::Turntable {
            frames: 4,
            axis: None,
        };
        assert_eq!(turntable_axis(&turntable, &job, &side), DVec3::Y);
        let above = Camera::look_at(
            DVec3::new(0.0, 4.0, 0.0),
            DVec3::ZERO,
            DVec3::Z,
            Projection::Perspective { fov_deg: 30.0 },
        )
        .expect("camera");
        assert_eq!(turntable_axis(&turntable, &job, &above), above.up());
        let given = Animation::Turntable {
            frames: 4,
            axis: Some(DVec3::X),
        };
        assert_eq!(turntable_axis(&given, &job, &side), DVec3::X);
    }
}
