//! `smoothlab view`: the exact renderer in the browser. The command builds the surface once,
//! serves one embedded page on the local machine and prints its URL; the page orbits, pans
//! and zooms the camera, sets the mode and its parameters, probes the exact hit under the
//! cursor and saves the view as a scene file with its PNG and EXR.
//!
//! One render path: the page sends its settings as the keys of a scene file
//! ([`scene`]); the server parses them with the scene-file parser into a
//! [`RenderJob`] and renders it with
//! [`RenderJob::render_with`](crate::render::RenderJob::render_with) on the tracer the job
//! built once ([`RenderJob::tracer`](crate::render::RenderJob::tracer)); "save" writes exactly
//! those keys,
//! so `smoothlab render` of the saved scene gives the converged frame's pixels.
//!
//! Why these parts:
//! - **Frames as PNG over plain HTTP requests** (a long poll: the page asks for the frame
//!   after the last one it has; the answer comes when the next pass is done). A frame is one
//!   image of a known size, so one response per frame is the whole protocol; the page needs
//!   no WebSocket framing or event-stream parsing, any HTTP tool can fetch frames in tests,
//!   and a page that asks for nothing costs nothing. Server-sent events would push the same
//!   images base64-encoded (a third larger) on a connection held per tab. PNG, not JPEG:
//!   the converged frame is shown exactly (the stripes' edges are what the user judges),
//!   and the coarse passes are small anyway (¼ × ¼ of the pixels).
//! - **Its own bounded transport** ([`http`], over `std::net` with `httparse` for the request
//!   head): the renderer is synchronous (rayon) and the server needs a handful of endpoints,
//!   so no async runtime is worth its build time; and the small synchronous servers give a
//!   thread to every connection without bound or read deadline, where the view caps open
//!   connections and closes idle ones.
//! - **Cancellation by generation**: every setting from the page is a new generation; the
//!   render asks between tiles (16 × 16 pixels) whether its generation is still the newest
//!   and stops if not ([`crate::render::film::render_cancellable`]), so a new camera waits at
//!   most one tile per thread for the old frame to stop. See [`session`].
//! - **Security** ([`server`]): bound to 127.0.0.1 unless `--bind` says otherwise; a random
//!   token (128 bits from the operating system, `getrandom`) in the printed URL on every
//!   request; the `Host` header checked against the bound address; fixed endpoints; bounded
//!   URLs, bodies, frame sizes, samples and waiting requests.

pub(crate) mod http;
pub(crate) mod scene;
pub(crate) mod server;
pub(crate) mod session;

use std::collections::HashMap;
use std::net::{IpAddr, SocketAddr};
use std::path::PathBuf;
use std::sync::Arc;

use crate::error::{Error, Result};
use crate::metrics::joints::{JumpAt, jump_at};
use crate::render::interaction::ShadingPoint;
use crate::render::{Frame, RenderJob};
use crate::surface::{Joint, Surface, edge_uv};

/// `smoothlab view MESH|SCENE.toml [options]`.
#[derive(clap::Args, Clone, Debug)]
pub struct ViewArgs {
    /// Scene file (.toml) or mesh (.obj, .ply, .off, .stl).
    pub input: PathBuf,
    /// Scheme name; required for a mesh input (default: the scene's `[scheme] name`).
    #[arg(long)]
    pub scheme: Option<String>,
    /// Scheme parameter `name=value` (repeatable).
    #[arg(long = "param", value_name = "NAME=VALUE")]
    pub params: Vec<String>,
    /// Shading mode to start with [default: the scene's, else zebra].
    #[arg(long, value_parser = crate::app::render::mode_value_parser())]
    pub mode: Option<String>,
    /// Port to listen on (0: any free port; the URL printed names it).
    #[arg(long, default_value_t = 0)]
    pub port: u16,
    /// Address to listen on. Anything but a loopback address exposes the view (behind its
    /// token) to the network.
    #[arg(long, value_name = "ADDR", default_value = "127.0.0.1")]
    pub bind: IpAddr,
    /// Do not open the page in a browser; only print its URL.
    #[arg(long)]
    pub no_browser: bool,
    /// Folder that "save" writes view-NNN.toml, .png and .exr into.
    #[arg(long, value_name = "DIR", default_value = ".")]
    pub out: PathBuf,
    /// Weld vertices closer than this fraction of the bounding-box diagonal (default: the
    /// scene's `weld_tolerance`, else 1e-10).
    #[arg(
        long,
        value_name = "REL",
        value_parser = crate::app::parse_weld_tolerance,
        allow_hyphen_values = true
    )]
    pub weld_tolerance: Option<f64>,
}

/// The PNG bytes of a frame as the page gets it: the 8-bit sRGB pixels of the PNG `render`
/// writes ([`crate::render::output::srgb8`]: the image and, right of it, the mode's legend
/// strip, which the page draws beside its canvas), fast compression.
pub(crate) fn png_bytes(frame: &Frame) -> Result<Vec<u8>> {
    let pixels = crate::render::output::srgb8(frame);
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, frame.png_width(), frame.height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
    encoder.set_compression(png::Compression::Fast);
    let err = |e: png::EncodingError| Error::Invalid(format!("frame PNG: {e}"));
    let mut writer = encoder.write_header().map_err(err)?;
    writer.write_image_data(&pixels).map_err(err)?;
    writer.finish().map_err(err)?;
    Ok(bytes)
}

/// How near a joint the probe must hit to report it: within this many pixels' width of
/// the hit.
pub(crate) const JOINT_PIXELS: f64 = 2.0;

/// The joints of a surface by the patch edges on either side: `(patch, edge)` → the joint,
/// whether the patch is its side `a`, and whether it runs along a sharp edge of the mesh.
pub(crate) struct JointIndex {
    by_edge: HashMap<(u32, u8), (Joint, bool, bool)>,
}

/// A joint next to a probed hit and the jump measured across it there.
#[derive(Clone, Copy, Debug)]
pub(crate) struct JointUnder {
    /// The joint.
    pub joint: Joint,
    /// Fraction along side `a` of the point nearest the hit.
    pub s: f64,
    /// Distance from the hit to that point, in pixels' widths at the hit.
    pub pixels: f64,
    /// The jump there ([`crate::metrics::joints::jump_at`]).
    pub jump: JumpAt,
    /// `true` along a sharp edge of the mesh (a crease, G0 by design).
    pub sharp: bool,
}

impl JointIndex {
    /// The joints of `surface`, built on `mesh`.
    pub(crate) fn new(surface: &Surface, mesh: &crate::mesh::Mesh) -> JointIndex {
        let sharp = crate::metrics::sharp_face_pairs(surface, mesh);
        let mut by_edge = HashMap::new();
        for joint in surface.joints(mesh.faces(), Some(&mesh.edge_ids())) {
            let (f, g) = (
                surface.patches[joint.a.patch as usize].face,
                surface.patches[joint.b.patch as usize].face,
            );
            let is_sharp =
                joint.between_faces && sharp.binary_search(&(f.min(g), f.max(g))).is_ok();
            by_edge.insert((joint.a.patch, joint.a.edge), (joint, true, is_sharp));
            by_edge.insert((joint.b.patch, joint.b.edge), (joint, false, is_sharp));
        }
        JointIndex { by_edge }
    }

    /// The joint within [`JOINT_PIXELS`] of the hit `sp` through image point `(x, y)` of
    /// `job`, if any: the patch edge nearest the hit's `(u, v)`, the point on it at the same
    /// barycentric ratio, and the normal-angle jump measured there.
    pub(crate) fn near(
        &self,
        job: &RenderJob,
        surface: &Surface,
        x: f64,
        y: f64,
        sp: &ShadingPoint,
    ) -> Result<Option<JointUnder>> {
        let (u, v) = (sp.hit.u, sp.hit.v);
        let weights = [1.0 - u - v, u, v];
        // Edge e runs from corner e to corner e + 1, where the weight of corner e + 2 is 0.
        let edge = (0..3usize)
            .min_by(|&a, &b| weights[(a + 2) % 3].total_cmp(&weights[(b + 2) % 3]))
            .unwrap_or(0);
        let Some(&(joint, is_a, sharp)) = self.by_edge.get(&(sp.hit.patch, edge as u8)) else {
            return Ok(None);
        };
        let (w0, w1) = (weights[edge].max(0.0), weights[(edge + 1) % 3].max(0.0));
        let along = if w0 + w1 > 0.0 { w1 / (w0 + w1) } else { 0.5 };
        let uv = edge_uv(edge, along);
        let on_edge = surface.patches[sp.hit.patch as usize].jet(uv.x, uv.y).p;
        let (r0, r1) = (
            job.pixel_ray(surface, x, y)?,
            job.pixel_ray(surface, x + 1.0, y)?,
        );
        let pixel = ((r1.origin - r0.origin) + (r1.dir - r0.dir) * sp.hit.t).length();
        let pixels = (sp.jet.p - on_edge).length() / pixel;
        // A NaN distance (a degenerate pixel) is no joint either.
        if pixels.is_nan() || pixels > JOINT_PIXELS {
            return Ok(None);
        }
        // `along` is the fraction on the hit patch's side; the joint counts it on side a.
        let s = if is_a || !joint.reversed {
            along
        } else {
            1.0 - along
        };
        Ok(Some(JointUnder {
            joint,
            s,
            pixels,
            jump: jump_at(surface, &joint, s),
            sharp,
        }))
    }
}

/// The probe's answer: the exact hit through image point `(x, y)` of `wanted`'s job — point,
/// unit normal (patch orientation), principal, Gaussian and mean curvature, patch, piece,
/// input face of `mesh` and `(u, v)`; curvatures with the convex sign (positive where the surface is
/// convex seen from the side its normal points to, as the curvature mode's default); and, next
/// to a joint, the jump measured across it (`joint`: its two patches, the fraction along it,
/// the distance in pixels, gap, normal angle in radians, and whether it is a sharp edge).
pub(crate) fn probe_json(
    wanted: &session::Wanted,
    x: f64,
    y: f64,
    sp: Option<&ShadingPoint>,
    joint: Option<JointUnder>,
    mesh: &crate::mesh::Mesh,
) -> serde_json::Value {
    let v = |p: glam::DVec3| [p.x, p.y, p.z];
    let Some(sp) = sp else {
        return serde_json::json!({ "generation": wanted.generation, "x": x, "y": y, "hit": false });
    };
    // II/I with respect to the normal; the convex sign negates it (κ1 ≥ κ2 kept).
    let curvature = sp.curvature.map(|c| {
        serde_json::json!({
            "k1": -c.k2, "k2": -c.k1, "gaussian": c.gaussian, "mean": -c.mean,
            "sign": "convex",
        })
    });
    serde_json::json!({
        "generation": wanted.generation,
        "x": x, "y": y, "hit": true,
        "position": v(sp.jet.p),
        "normal": v(sp.normal),
        "curvature": curvature,
        "patch": sp.hit.patch, "piece": sp.piece,
        // The face the user wrote (a polygon's triangles share it), as in the EXR's face_id.
        "face": mesh.face_origins().get(sp.face as usize).copied().unwrap_or(sp.face),
        "u": sp.hit.u, "v": sp.hit.v, "t": sp.hit.t,
        "back_face": sp.is_back_face(),
        "joint": joint.map(|j| serde_json::json!({
            "patches": [j.joint.a.patch, j.joint.b.patch],
            "s": j.s,
            "pixels": j.pixels,
            "gap": j.jump.gap,
            "normal_angle": j.jump.normal_angle,
            "sharp": j.sharp,
            "between_faces": j.joint.between_faces,
        })),
    })
}

/// What the view prints while it starts.
pub trait ViewReport {
    /// A line for standard output.
    fn line(&mut self, text: &str);
    /// A warning (without the `warning:` prefix).
    fn warning(&mut self, text: &str);
}

/// Runs `smoothlab view`: loads the mesh, builds the surface and its tracer, starts the
/// render worker and the server, reports the URL and (unless `--no-browser`) opens it; then
/// serves until the process is interrupted.
pub(crate) fn view_command(args: &ViewArgs, report: &mut dyn ViewReport) -> Result<()> {
    if args.bind.is_unspecified() {
        return Err(Error::Invalid(format!(
            "--bind {}: give the address of one interface (every request's Host header must \
             name it), not the unspecified address",
            args.bind
        )));
    }
    let params = crate::app::parse_params(&args.params)?;
    let mut base = scene::BaseScene::new(
        &args.input,
        args.scheme.as_deref(),
        &params,
        args.mode.as_deref(),
    )?;
    if let Some(w) = args.weld_tolerance {
        base.table
            .insert("weld_tolerance".into(), toml::Value::Float(w));
    }
    let scene = base.scene()?;
    let scheme = session::scheme_of(&scene)?;
    let mesh_path = scene
        .mesh
        .clone()
        .ok_or_else(|| crate::app::scene::no_mesh_given(&args.input))?;
    if !args.bind.is_loopback() {
        report.warning(&format!(
            "--bind {}: the view is reachable from the network by anyone who has its URL \
             (plain HTTP, the token is not encrypted); prefer SSH port forwarding",
            args.bind
        ));
    }
    crate::files::create_folder(&args.out)?;
    let (mesh, load) = crate::mesh::Mesh::load_with(&mesh_path, &scene.load_options()?)?;
    for w in &load.warnings {
        report.warning(w);
    }
    let job = scene.job()?;
    let session = Arc::new(session::Session::new(base, mesh));
    let built = session.built(&scheme, &job)?;
    report.line(&format!(
        "{}: {} patches of {} built in {:.0} ms, BVH in {:.0} ms",
        mesh_path.display(),
        built.surface.patches.len(),
        scheme.0,
        built.build_ms,
        built.tracer_ms
    ));
    let server = Arc::new(server::ViewServer::bind(
        SocketAddr::new(args.bind, args.port),
        session.clone(),
        args.out.clone(),
    )?);
    let worker = session.clone();
    std::thread::spawn(move || worker.run_worker());
    crate::files::interrupt_is_the_normal_end("smoothlab view stopped\n");
    let url = server.url();
    report.line(&format!("open {url}\n(Ctrl-C stops the view)"));
    if !args.no_browser {
        let opened = std::process::Command::new("xdg-open")
            .arg(&url)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn();
        if let Err(e) = opened {
            report.warning(&format!(
                "cannot open a browser (xdg-open: {e}): open the URL above"
            ));
        }
    }
    server.serve();
    Ok(())
}
