//! The view's HTTP server: a fixed set of endpoints over the bounded transport of
//! [`super::http`], each request checked before anything is done for it.
//!
//! Checks, in order: the `Host` header must name the bound address (`ADDR:PORT`, and
//! `localhost:PORT` when bound to a loopback address), so a page of another site that a DNS
//! name rebinds to this address is refused; the URL is at most [`MAX_URL`] bytes and carries
//! `token=` with the random token of the printed URL (compared in constant time); the path
//! is one of the endpoints below with its method; a body is at most [`MAX_BODY`] bytes.
//! Everything else is refused (403, 404, 405, 413, 414) before it costs work.
//!
//! Endpoints (all need the token): `GET /` the embedded page; `GET /info` the mesh, scheme
//! registry, modes and a framed camera (JSON); `POST /view` new settings as scene keys
//! (JSON), answered with their generation; `GET /frame?after=SEQ` the next frame as PNG
//! (long poll, 204 after [`FRAME_WAIT`]); `GET /probe?x=X&y=Y` the exact hit under a pixel
//! (JSON); `POST /save` writes the current view as scene TOML, PNG and EXR into the output
//! folder given on the command line and names the files (JSON). The page names no path: the
//! server reads and writes nothing else.
//!
//! Load: at most [`MAX_CONNECTIONS`] connections are open at once, each must send its request
//! within [`REQUEST_DEADLINE`] (idle or slow clients are closed then), and at most
//! [`MAX_WAITING`] frame requests wait at once (more are told 503 at once), so a page left
//! open in many tabs or a client that stops reading ties up no renderer: the render worker
//! does not depend on any client, and a client that disconnects mid-frame only loses its
//! response. Every response closes its connection, so no idle connection is kept.

use std::net::{IpAddr, SocketAddr};
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use serde_json::json;

use crate::app::view::http::{HttpServer, Limits, Method, Request, Response};
use crate::app::view::session::{Session, Wanted};
use crate::error::{Error, Problem, Result};
use crate::render::output::{OutputMeta, OutputOptions, write_outputs_with};

/// The embedded page.
const PAGE: &str = include_str!("../../../assets/view/index.html");

/// The most connections open at once (a page holds two or three: a frame poll, a probe,
/// a settings change).
pub(crate) const MAX_CONNECTIONS: usize = 16;

/// Time from a connection's opening by which its request must have arrived.
pub(crate) const REQUEST_DEADLINE: Duration = Duration::from_secs(10);

/// The most frame requests waiting at once.
pub(crate) const MAX_WAITING: usize = 2;

/// The longest URL accepted, bytes.
pub(crate) const MAX_URL: usize = 4096;

/// The largest request body accepted, bytes.
pub(crate) const MAX_BODY: usize = 64 * 1024;

/// How long a frame request waits for a new frame before it is answered 204.
pub(crate) const FRAME_WAIT: Duration = Duration::from_secs(10);

/// A running view server.
pub(crate) struct ViewServer {
    http: HttpServer,
    /// The token every request must carry.
    pub token: String,
    session: Arc<Session>,
    allowed_hosts: Vec<String>,
    out_dir: PathBuf,
    waiting: AtomicUsize,
    saving: Mutex<()>,
}

/// 128 random bits from the operating system, as 32 hex digits.
pub(crate) fn random_token() -> Result<String> {
    let mut bytes = [0u8; 16];
    getrandom::fill(&mut bytes)
        .map_err(|e| Error::Invalid(format!("no random numbers from the system: {e}")))?;
    Ok(bytes.iter().map(|b| format!("{b:02x}")).collect())
}

/// The `Host` values that name `addr`.
fn hosts_of(addr: SocketAddr) -> Vec<String> {
    let port = addr.port();
    let mut hosts = vec![match addr.ip() {
        IpAddr::V4(ip) => format!("{ip}:{port}"),
        IpAddr::V6(ip) => format!("[{ip}]:{port}"),
    }];
    if addr.ip().is_loopback() {
        hosts.push(format!("localhost:{port}"));
    }
    hosts
}

/// Equal strings, compared in time independent of where they differ.
fn same_secret(a: &str, b: &str) -> bool {
    a.len() == b.len()
        && a.bytes()
            .zip(b.bytes())
            .fold(0u8, |acc, (x, y)| acc | (x ^ y))
            == 0
}

/// The value of query key `key` in `query` (`a=1&b=2`), if present.
fn query_value<'q>(query: &'q str, key: &str) -> Option<&'q str> {
    query
        .split('&')
        .filter_map(|pair| pair.split_once('='))
        .find(|(k, _)| *k == key)
        .map(|(_, v)| v)
}

/// A response with the headers every response carries.
fn respond(status: u16, content_type: &str, body: Vec<u8>) -> Response {
    Response::new(status, content_type, body)
        .with_header("Cache-Control", "no-store")
        .with_header("X-Content-Type-Options", "nosniff")
        .with_header("X-Frame-Options", "DENY")
        .with_header("Referrer-Policy", "no-referrer")
        .with_header(
            "Content-Security-Policy",
            "default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; \
             img-src 'self' blob:; connect-src 'self'; frame-ancestors 'none'",
        )
}

fn respond_json(status: u16, value: &serde_json::Value) -> Response {
    respond(status, "application/json", value.to_string().into_bytes())
}

fn refuse(status: u16, why: &str) -> Response {
    respond_json(status, &json!({ "error": why }))
}

/// Refuses the unspecified address for `--bind`: no request's Host header could name it.
fn check_bind(addr: SocketAddr) -> Result<()> {
    if addr.ip().is_unspecified() {
        return Err(Error::config(
            "--bind",
            Problem::Other {
                text: format!(
                    "{}: give the address of one interface (every request's Host header must \
                     name it), not the unspecified address",
                    addr.ip()
                ),
            },
        ));
    }
    Ok(())
}

impl ViewServer {
    /// Binds `addr` (port 0: any free port) for `session`; "save" writes into `out_dir`.
    pub(crate) fn bind(
        addr: SocketAddr,
        session: Arc<Session>,
        out_dir: PathBuf,
    ) -> Result<ViewServer> {
        check_bind(addr)?;
        let http = HttpServer::bind(
            addr,
            Limits {
                connections: MAX_CONNECTIONS,
                request_deadline: REQUEST_DEADLINE,
                // Room for a URL beyond MAX_URL, so that it is refused by name (414).
                head_bytes: 4 * MAX_URL,
                body_bytes: MAX_BODY,
                write_timeout: Duration::from_secs(30),
            },
        )?;
        let addr = http.local_addr()?;
        Ok(ViewServer {
            http,
            token: random_token()?,
            session,
            allowed_hosts: hosts_of(addr),
            out_dir,
            waiting: AtomicUsize::new(0),
            saving: Mutex::new(()),
        })
    }

    /// The URL of the page, with the token.
    pub(crate) fn url(&self) -> String {
        format!("http://{}/?token={}", self.allowed_hosts[0], self.token)
    }

    /// Serves requests until the process ends.
    pub(crate) fn serve(self: Arc<Self>) {
        let me = self.clone();
        self.http.serve(Arc::new(move |request| me.handle(request)));
    }

    /// Checks and answers one request.
    fn handle(&self, request: Request) -> Response {
        if !request
            .host
            .as_ref()
            .is_some_and(|h| self.allowed_hosts.contains(h))
        {
            return refuse(403, "the Host header does not name this server");
        }
        let url = request.target.as_str();
        if url.len() > MAX_URL {
            return refuse(414, "URL too long");
        }
        let (path, query) = url.split_once('?').unwrap_or((url, ""));
        if !query_value(query, "token").is_some_and(|t| same_secret(t, &self.token)) {
            return refuse(
                403,
                "missing or wrong token: open the URL the server printed",
            );
        }
        let endpoint = match path {
            "/" | "/info" | "/frame" | "/probe" => Method::Get,
            "/view" | "/save" => Method::Post,
            _ => return refuse(404, "no such page"),
        };
        if request.method != endpoint {
            return refuse(405, "method not allowed");
        }
        match path {
            "/" => respond(200, "text/html; charset=utf-8", PAGE.as_bytes().to_vec()),
            "/info" => self.info(query),
            "/view" => self.view(&request.body),
            "/frame" => self.frame(query),
            "/probe" => self.probe(query),
            _ => self.save(),
        }
    }

    /// The mesh, the schemes, the modes, the base scene's keys and the camera the base scene
    /// gives for an image of `w` × `h`.
    fn info(&self, query: &str) -> Response {
        let size = |key: &str| {
            query_value(query, key)
                .and_then(|v| v.parse::<u32>().ok())
                .filter(|v| (1..=crate::app::view::scene::MAX_VIEW_SIDE).contains(v))
        };
        let result = (|| -> Result<serde_json::Value> {
            let scene = self.session.base.scene()?;
            let mut job = scene.job()?;
            if let (Some(w), Some(h)) = (size("w"), size("h")) {
                (job.settings.width, job.settings.height) = (w, h);
            }
            let scheme = crate::app::view::session::scheme_of(&scene)?;
            let built = self.session.built(&scheme, &job)?;
            let camera = job.camera_of(built.surface)?;
            let bounds = built.surface.bounds();
            let v = |p: glam::DVec3| [p.x, p.y, p.z];
            let schemes: Vec<_> = crate::schemes::SCHEMES
                .iter()
                .map(|s| {
                    json!({
                        "name": s.name,
                        "summary": s.summary,
                        "params": s.params.iter().map(|p| json!({
                            "name": p.name, "default": p.default, "help": p.help
                        })).collect::<Vec<_>>(),
                    })
                })
                .collect();
            Ok(json!({
                "mesh": scene.mesh.as_ref().and_then(|m| m.file_name()).map(|m| m.to_string_lossy().into_owned()),
                "faces": self.session.mesh.faces().len(),
                "patches": built.surface.patches.len(),
                "scheme": scheme.0,
                "build_ms": built.build_ms,
                "tracer_ms": built.tracer_ms,
                "schemes": schemes,
                "modes": crate::render::modes::MODE_NAMES,
                "base": serde_json::to_value(&self.session.base.table).unwrap_or_default(),
                "camera": {
                    "eye": v(camera.eye), "target": v(camera.target), "up": v(camera.up()),
                    "fov": job.camera.fov_deg,
                },
                "bounds": { "center": v(bounds.center()), "diagonal": bounds.diagonal() },
            }))
        })();
        match result {
            Ok(value) => respond_json(200, &value),
            Err(e) => refuse(500, &e.to_string()),
        }
    }

    /// New settings: checked, made the newest generation.
    fn view(&self, body: &[u8]) -> Response {
        let settings: serde_json::Value = match serde_json::from_slice(body) {
            Ok(v) => v,
            Err(e) => return refuse(400, &format!("view settings: {e}")),
        };
        match self.session.request(&settings) {
            Ok(w) => respond_json(200, &json!({ "generation": w.generation })),
            Err(e) => refuse(400, &e.to_string()),
        }
    }

    /// The next frame after `after` (long poll).
    fn frame(&self, query: &str) -> Response {
        let after = query_value(query, "after")
            .and_then(|v| v.parse::<u64>().ok())
            .unwrap_or(0);
        if self.waiting.fetch_add(1, Ordering::SeqCst) >= MAX_WAITING {
            self.waiting.fetch_sub(1, Ordering::SeqCst);
            return refuse(503, "too many frame requests at once");
        }
        let (frame, error) = self.session.frame_after(after, FRAME_WAIT);
        self.waiting.fetch_sub(1, Ordering::SeqCst);
        match (frame, error) {
            (_, Some(e)) => refuse(422, &e),
            (None, None) => respond(204, "text/plain", Vec::new()),
            (Some(p), None) => respond(200, "image/png", p.png.as_ref().clone())
                .with_header("X-Seq", p.seq.to_string())
                .with_header("X-Generation", p.generation.to_string())
                .with_header("X-Level", p.level.to_string())
                .with_header("X-Width", p.width.to_string())
                .with_header("X-Height", p.height.to_string())
                .with_header("X-Since-Request-Ms", format!("{:.1}", p.since_request_ms))
                .with_header("X-Render-Ms", format!("{:.1}", p.render_ms)),
        }
    }

    /// The exact hit under pixel coordinates `x`, `y` of the current view.
    fn probe(&self, query: &str) -> Response {
        let coordinate = |key: &str| {
            query_value(query, key)
                .and_then(|v| v.parse::<f64>().ok())
                .filter(|v| v.is_finite())
        };
        let (Some(x), Some(y)) = (coordinate("x"), coordinate("y")) else {
            return refuse(400, "probe needs finite x and y");
        };
        match self.session.probe(x, y) {
            Ok((wanted, sp, joint)) => {
                let json = super::probe_json(&wanted, x, y, sp.as_ref(), joint, self.session.mesh);
                respond_json(200, &json)
            }
            Err(e) => refuse(400, &e.to_string()),
        }
    }

    /// Writes the current view as `view-NNN.toml`, `.png` and `.exr` in the output folder.
    fn save(&self) -> Response {
        let _one_at_a_time = self.saving.lock();
        let result = (|| -> Result<serde_json::Value> {
            let wanted = self
                .session
                .wanted()
                .ok_or_else(|| Error::Invalid("nothing is shown yet".into()))?;
            let files = save_view(&self.session, &wanted, &self.out_dir)?;
            Ok(json!({
                "generation": wanted.generation,
                "scene": files[0], "png": files[1], "exr": files[2],
            }))
        })();
        match result {
            Ok(value) => respond_json(200, &value),
            Err(e) => refuse(500, &e.to_string()),
        }
    }
}

/// Writes `wanted` into `dir` as the first free `view-NNN`: the scene TOML (its
/// `render.output` naming the PNG and EXR beside it), then the converged frame as PNG and EXR
/// through the normal output path. Returns the three paths.
pub(crate) fn save_view(
    session: &Session,
    wanted: &Wanted,
    dir: &std::path::Path,
) -> Result<[String; 3]> {
    crate::files::create_folder(dir)?;
    let (stem, toml_path) = (1..10000)
        .map(|n| {
            let stem = format!("view-{n:03}");
            (stem.clone(), dir.join(format!("{stem}.toml")))
        })
        .find(|(stem, toml)| {
            !toml.exists()
                && crate::render::output::output_files(&dir.join(stem))
                    .iter()
                    .all(|f| !f.exists())
        })
        .ok_or_else(|| Error::Invalid(format!("{}: no free view-NNN name", dir.display())))?;
    let outputs = crate::render::output::prepare_outputs(&dir.join(&stem))?;
    crate::files::check_writable(&toml_path)?;
    let mut table = wanted.table.clone();
    let mut render = match table.remove("render") {
        Some(toml::Value::Table(t)) => t,
        _ => toml::Table::new(),
    };
    render.insert("output".into(), toml::Value::String(stem.clone()));
    table.insert("render".into(), toml::Value::Table(render));
    let text = format!(
        "# The view saved by `smoothlab view`; `smoothlab render {stem}.toml` renders {stem}.png\n\
         # again, byte for byte in its pixels.\n{}",
        toml::to_string(&table)
            .map_err(|e| Error::Invalid(format!("the view cannot be written as TOML: {e}")))?
    );
    let frame = session.converged(wanted)?;
    let built = session.built(&wanted.scheme, &wanted.job)?;
    let options = OutputOptions {
        exr: Some(crate::render::output::ExrCompression::default()),
        meta: OutputMeta {
            command: Some(format!("smoothlab render {stem}.toml")),
            camera: Some(wanted.job.camera_of(built.surface)?),
        },
    };
    crate::files::write_atomic(&toml_path, text.as_bytes())?;
    write_outputs_with(&frame, &outputs, &options)?;
    let name = |p: &std::path::Path| p.to_string_lossy().into_owned();
    Ok([name(&toml_path), name(&outputs[0]), name(&outputs[1])])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::test_support::assert_config_error;

    #[test]
    fn tokens_are_random_and_hex() {
        let (a, b) = (
            random_token().expect("token"),
            random_token().expect("token"),
        );
        assert_eq!(a.len(), 32);
        assert!(a.bytes().all(|c| c.is_ascii_hexdigit()), "{a}");
        assert_ne!(a, b);
    }

    #[test]
    fn secrets_and_queries() {
        assert!(same_secret("abc", "abc"));
        assert!(!same_secret("abc", "abd"));
        assert!(!same_secret("abc", "ab"));
        assert_eq!(query_value("token=1&after=7", "after"), Some("7"));
        assert_eq!(query_value("token=1&after", "after"), None);
        assert_eq!(query_value("xtoken=1", "token"), None);
    }

    #[test]
    fn hosts_name_the_bound_address() {
        let v4: SocketAddr = "127.0.0.1:8080".parse().expect("address");
        assert_eq!(hosts_of(v4), ["127.0.0.1:8080", "localhost:8080"]);
        let v6: SocketAddr = "[::1]:80".parse().expect("address");
        assert_eq!(hosts_of(v6), ["[::1]:80", "localhost:80"]);
        let lan: SocketAddr = "192.168.1.5:9000".parse().expect("address");
        assert_eq!(hosts_of(lan), ["192.168.1.5:9000"]);
    }

    /// `--bind` with the unspecified address is a configuration error of `--bind`.
    #[test]
    fn the_unspecified_address_is_a_config_error() {
        let any: SocketAddr = "0.0.0.0:8080".parse().expect("address");
        let err = check_bind(any).expect_err("refused");
        assert_config_error(
            &err,
            "--bind",
            |p| matches!(p, Problem::Other { .. }),
            "--bind 0.0.0.0: give the address of one interface (every request's Host header must \
             name it), not the unspecified address",
        );
        let local: SocketAddr = "127.0.0.1:8080".parse().expect("address");
        assert!(check_bind(local).is_ok());
    }
}
