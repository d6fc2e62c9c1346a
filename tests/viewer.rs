//! End-to-end tests of `smoothlab view`: the server's refusals over plain HTTP, and the page in
//! a real browser — headless Chromium driven over the DevTools protocol (a minimal client over
//! a WebSocket: `Runtime.evaluate` and `Input.dispatchMouseEvent`): first frame, orbit by
//! dragging, stripe count and mode, the probe on a sphere, and save reproduced by
//! `smoothlab render`.
//!
//! Chromium is found as `$SMOOTHLAB_CHROMIUM`, else `chromium` or `chromium-browser` on the
//! `PATH`; without it the browser test fails with how to install it (Debian: `apt-get install
//! -y chromium`; `.ci/run` does so), unless `SMOOTHLAB_SKIP_BROWSER_TESTS=1` asks to skip.

mod common;

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::{Value, json};

/// A running `smoothlab view`, stopped when dropped.
struct View {
    child: Child,
    /// `127.0.0.1:PORT`
    host: String,
    token: String,
    url: String,
}

impl Drop for View {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Starts `smoothlab view ARGS --no-browser --port 0` and waits for its URL.
fn start_view(args: &[&str]) -> View {
    let mut child = Command::new(env!("CARGO_BIN_EXE_smoothlab"))
        .arg("view")
        .args(args)
        .args(["--no-browser", "--port", "0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .expect("run smoothlab view");
    let stdout = child.stdout.take().expect("stdout");
    let mut lines = BufReader::new(stdout).lines();
    let url = loop {
        let line = lines
            .next()
            .expect("the view ended before printing its URL")
            .expect("stdout");
        if let Some(url) = line.strip_prefix("open ") {
            break url.trim().to_string();
        }
    };
    // Keep reading (and dropping) its output so that it never blocks on a full pipe.
    std::thread::spawn(move || for _ in lines {});
    let rest = url.strip_prefix("http://").expect("http URL");
    let (host, query) = rest.split_once("/?token=").expect("token in the URL");
    View {
        child,
        host: host.to_string(),
        token: query.to_string(),
        url,
    }
}

/// One HTTP/1.1 request with the given `Host` (None: no Host header); returns the status,
/// the headers (lower-case names) and the body.
fn http(
    addr: &str,
    method: &str,
    target: &str,
    host: Option<&str>,
    body: &[u8],
) -> (u16, Vec<(String, String)>, Vec<u8>) {
    let mut stream = TcpStream::connect(addr).expect("connect");
    stream
        .set_read_timeout(Some(Duration::from_secs(60)))
        .expect("timeout");
    let mut request = format!("{method} {target} HTTP/1.1\r\n");
    if let Some(h) = host {
        request += &format!("Host: {h}\r\n");
    }
    request += &format!(
        "Content-Length: {}\r\nConnection: close\r\n\r\n",
        body.len()
    );
    stream.write_all(request.as_bytes()).expect("send");
    // A refused body may close the connection before it is all sent.
    let _ = stream.write_all(body);
    // Read up to the body's length: the DevTools server keeps its connections open.
    let mut response = Vec::new();
    let mut buf = [0u8; 65536];
    loop {
        let n = stream.read(&mut buf).unwrap_or(0);
        response.extend_from_slice(&buf[..n]);
        let length = response
            .windows(4)
            .position(|w| w == b"\r\n\r\n")
            .and_then(|at| {
                let head = String::from_utf8_lossy(&response[..at]).to_ascii_lowercase();
                head.lines()
                    .find_map(|l| l.strip_prefix("content-length:"))
                    .and_then(|v| v.trim().parse::<usize>().ok())
                    .map(|len| at + 4 + len)
            });
        if n == 0 || length.is_some_and(|end| response.len() >= end) {
            break;
        }
    }
    let split = response
        .windows(4)
        .position(|w| w == b"\r\n\r\n")
        .expect("header end");
    let head = String::from_utf8_lossy(&response[..split]).into_owned();
    let mut lines = head.lines();
    let status = lines
        .next()
        .and_then(|l| l.split_whitespace().nth(1))
        .and_then(|s| s.parse().ok())
        .expect("status line");
    let headers: Vec<(String, String)> = lines
        .filter_map(|l| l.split_once(':'))
        .map(|(k, v)| (k.trim().to_ascii_lowercase(), v.trim().to_string()))
        .collect();
    let mut body = response[split + 4..].to_vec();
    // The view sends every body with its length; the DevTools server may send it chunked.
    if headers_have(&headers, "transfer-encoding", "chunked") {
        body = dechunk(&body);
    }
    (status, headers, body)
}

fn headers_have(headers: &[(String, String)], name: &str, value: &str) -> bool {
    headers
        .iter()
        .any(|(k, v)| k == name && v.eq_ignore_ascii_case(value))
}

fn dechunk(mut data: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    loop {
        let end = data
            .windows(2)
            .position(|w| w == b"\r\n")
            .expect("chunk size");
        let size = usize::from_str_radix(
            String::from_utf8_lossy(&data[..end])
                .split(';')
                .next()
                .unwrap_or("")
                .trim(),
            16,
        )
        .expect("hex chunk size");
        if size == 0 {
            return out;
        }
        out.extend_from_slice(&data[end + 2..end + 2 + size]);
        data = &data[end + 2 + size + 2..];
    }
}

/// A mesh small enough for fast frames.
fn icosahedron() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/icosahedron.obj")
}

/// Every request must carry the token, name the bound address in `Host`, ask for an
/// endpoint with its method and stay within the size bounds; settings that name a file are
/// refused. Each refusal comes before any work and leaves the server serving.
#[test]
fn requests_without_token_with_a_foreign_host_or_for_other_paths_are_refused() {
    let dir = common::scratch("viewer", "refusals");
    let ico = icosahedron();
    let out = dir.join("out");
    let view = start_view(&[
        common::path_str(&ico),
        "--scheme",
        "flat",
        "--out",
        common::path_str(&out),
    ]);
    let (addr, host, token) = (view.host.as_str(), Some(view.host.as_str()), &view.token);
    let get = |target: &str, host: Option<&str>| http(addr, "GET", target, host, b"").0;
    assert_eq!(get(&format!("/?token={token}"), host), 200, "the page");
    let (status, headers, page) = http(addr, "GET", &format!("/?token={token}"), host, b"");
    assert_eq!(status, 200);
    assert!(String::from_utf8_lossy(&page).contains("smoothlab view"));
    assert!(
        headers_have(&headers, "x-frame-options", "DENY"),
        "{headers:?}"
    );
    for (target, host, status, why) in [
        ("/".to_string(), host, 403, "no token"),
        ("/info".to_string(), host, 403, "no token"),
        (
            format!("/?token={}", "0".repeat(32)),
            host,
            403,
            "wrong token",
        ),
        (format!("/?token={token}x"), host, 403, "longer token"),
        (
            format!("/?xtoken={token}"),
            host,
            403,
            "token under another key",
        ),
        (
            format!("/?token={token}"),
            Some("evil.example:80"),
            403,
            "foreign Host",
        ),
        (
            format!("/?token={token}"),
            Some(&format!(
                "evil.example:{}",
                addr.rsplit(':').next().unwrap_or("")
            )),
            403,
            "foreign Host, same port",
        ),
        (format!("/?token={token}"), None, 403, "no Host"),
        (
            format!("/etc/passwd?token={token}"),
            host,
            404,
            "a file path",
        ),
        (
            format!("/../Cargo.toml?token={token}"),
            host,
            404,
            "a relative path",
        ),
        (
            format!("/index.html?token={token}"),
            host,
            404,
            "another name",
        ),
        (
            format!("/view?token={token}"),
            host,
            405,
            "GET of a POST endpoint",
        ),
        (
            format!("/?token={token}&pad={}", "a".repeat(5000)),
            host,
            414,
            "long URL",
        ),
    ] {
        assert_eq!(get(&target, host), status, "{why}: {target}");
    }
    let post = |target: &str, body: &[u8]| http(addr, "POST", target, host, body);
    assert_eq!(
        post(&format!("/?token={token}"), b"").0,
        405,
        "POST of the page"
    );
    let big = vec![b' '; 70 * 1024];
    assert_eq!(
        post(&format!("/view?token={token}"), &big).0,
        413,
        "big body"
    );
    for (settings, fragment) in [
        (json!({ "mesh": "/etc/passwd" }), "'mesh'"),
        (json!({ "render": { "output": "/tmp/x" } }), "render.output"),
        (
            json!({ "shaded": { "environment": "/etc/passwd" } }),
            "shaded.environment",
        ),
        (json!({ "render": { "size": [100000, 2] } }), "render.size"),
    ] {
        let (status, _, body) = post(
            &format!("/view?token={token}"),
            settings.to_string().as_bytes(),
        );
        let text = String::from_utf8_lossy(&body);
        assert_eq!(status, 400, "{settings}: {text}");
        assert!(text.contains(fragment), "{settings}: {text}");
    }
    // Still serving, and a frame arrives for valid settings.
    let (status, _, body) = post(
        &format!("/view?token={token}"),
        json!({ "render": { "size": [64, 48], "spp": 1 } })
            .to_string()
            .as_bytes(),
    );
    assert_eq!(status, 200, "{}", String::from_utf8_lossy(&body));
    let (status, headers, png) = http(
        addr,
        "GET",
        &format!("/frame?token={token}&after=0"),
        host,
        b"",
    );
    assert_eq!(status, 200);
    assert!(headers_have(&headers, "content-type", "image/png"));
    assert!(png.starts_with(b"\x89PNG"), "a PNG");
    assert!(
        !out.join("view-001.toml").exists(),
        "nothing written without save"
    );
}

/// The probe next to a joint reports the normal-angle jump measured there: on the flat
/// icosahedron the angle between the two faces' normals, on its hb surface 0 to rounding.
#[test]
fn the_probe_reports_the_jump_across_a_joint() {
    let ico = icosahedron();
    let view = start_view(&[common::path_str(&ico), "--scheme", "flat"]);
    let (addr, host, token) = (view.host.as_str(), Some(view.host.as_str()), &view.token);
    let mesh = smoothlab::mesh::Mesh::load_with(&ico, &Default::default())
        .expect("mesh")
        .0;
    let face_normal = |f: usize| {
        let [a, b, c] = mesh.faces()[f].map(|i| mesh.positions()[i as usize]);
        (b - a).cross(c - a)
    };
    for (scheme, flat) in [("flat", true), ("hb", false)] {
        let settings = json!({
            "render": { "size": [96, 72], "spp": 1 },
            "scheme": { "name": scheme, "params": {} },
        });
        let (status, _, body) = http(
            addr,
            "POST",
            &format!("/view?token={token}"),
            host,
            settings.to_string().as_bytes(),
        );
        assert_eq!(status, 200, "{}", String::from_utf8_lossy(&body));
        let surface = smoothlab::schemes::build(scheme, &mesh, &[]).expect(scheme);
        let (mut hits, mut joints) = (0, 0);
        // Every pixel of the middle row, at a quarter-pixel pitch.
        for i in 0..4 * 96 {
            let x = 0.125 + 0.25 * f64::from(i);
            let (status, _, body) = http(
                addr,
                "GET",
                &format!("/probe?token={token}&x={x}&y=36.5"),
                host,
                b"",
            );
            assert_eq!(status, 200);
            let probe: Value = serde_json::from_slice(&body).expect("probe JSON");
            if probe["hit"] != json!(true) {
                continue;
            }
            hits += 1;
            let joint = &probe["joint"];
            if joint.is_null() {
                continue;
            }
            joints += 1;
            assert!(joint["pixels"].as_f64().expect("pixels") <= 2.0, "{probe}");
            assert!(joint["gap"].as_f64().expect("gap") < 1e-12, "{probe}");
            let angle = joint["normal_angle"].as_f64().expect("angle");
            let [a, b] = [0, 1].map(|k| {
                surface.patches[joint["patches"][k].as_u64().expect("patch") as usize].face as usize
            });
            let [na, nb] = [face_normal(a), face_normal(b)];
            let expected = if flat {
                na.cross(nb).length().atan2(na.dot(nb))
            } else {
                0.0
            };
            assert!(
                (angle - expected).abs() < 1e-12,
                "{scheme}: jump {angle} rad, expected {expected}: {probe}"
            );
        }
        eprintln!("{scheme}: {hits} hits, {joints} next to a joint");
        assert!(
            hits > 100 && joints >= 4,
            "{scheme}: {hits} hits, {joints} joints"
        );
        assert!(joints < hits / 2, "{scheme}: {hits} hits, {joints} joints");
    }
}

/// `--bind` with the unspecified address is refused (no Host could be checked), naming the
/// flag.
#[test]
fn the_unspecified_address_is_refused() {
    let ico = icosahedron();
    let out = common::smoothlab(&[
        "view",
        common::path_str(&ico),
        "--scheme",
        "flat",
        "--no-browser",
        "--bind",
        "0.0.0.0",
    ]);
    common::assert_fails_naming(&out, &["--bind 0.0.0.0", "Host"]);
}

/// Chromium, or None when the browser tests are to be skipped.
fn chromium() -> Option<PathBuf> {
    if std::env::var("SMOOTHLAB_SKIP_BROWSER_TESTS").is_ok_and(|v| v == "1") {
        return None;
    }
    if let Ok(path) = std::env::var("SMOOTHLAB_CHROMIUM") {
        return Some(PathBuf::from(path));
    }
    let path = std::env::var_os("PATH").unwrap_or_default();
    let found = std::env::split_paths(&path)
        .flat_map(|dir| ["chromium", "chromium-browser"].map(|name| dir.join(name)))
        .find(|p| p.is_file());
    assert!(
        found.is_some(),
        "no chromium on the PATH: install it (Debian: `apt-get install -y chromium`), point \
         SMOOTHLAB_CHROMIUM at it, or set SMOOTHLAB_SKIP_BROWSER_TESTS=1"
    );
    found
}

/// A headless Chromium showing one page, driven over the DevTools protocol.
struct Browser {
    child: Child,
    ws: tungstenite::WebSocket<tungstenite::stream::MaybeTlsStream<TcpStream>>,
    id: u64,
}

impl Drop for Browser {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Browser {
    /// Opens `url` in a `width` × `height` window.
    fn open(binary: &Path, profile: &Path, url: &str, width: u32, height: u32) -> Browser {
        let mut child = Command::new(binary)
            .args([
                "--headless",
                "--no-sandbox",
                "--disable-gpu",
                "--no-first-run",
                "--force-color-profile=srgb",
                "--remote-debugging-port=0",
                "--remote-allow-origins=*",
                &format!("--window-size={width},{height}"),
                &format!("--user-data-dir={}", profile.display()),
                url,
            ])
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("run chromium");
        let stderr = child.stderr.take().expect("stderr");
        let mut lines = BufReader::new(stderr).lines();
        let endpoint = loop {
            let line = lines
                .next()
                .expect("chromium ended before its DevTools endpoint")
                .expect("stderr");
            if let Some(at) = line.find("ws://") {
                break line[at..].trim().to_string();
            }
        };
        std::thread::spawn(move || for _ in lines {});
        let port = endpoint
            .trim_start_matches("ws://127.0.0.1:")
            .split('/')
            .next()
            .expect("port")
            .to_string();
        let addr = format!("127.0.0.1:{port}");
        let deadline = Instant::now() + Duration::from_secs(20);
        let page = loop {
            let (_, _, body) = http(&addr, "GET", "/json/list", Some(&addr), b"");
            let targets: Value = serde_json::from_slice(&body).expect("target list");
            let page = targets.as_array().and_then(|t| {
                t.iter()
                    .find(|t| {
                        t["type"] == "page"
                            && t["url"].as_str().is_some_and(|u| u.starts_with("http"))
                    })
                    .and_then(|t| t["webSocketDebuggerUrl"].as_str())
                    .map(str::to_string)
            });
            if let Some(page) = page {
                break page;
            }
            assert!(Instant::now() < deadline, "no page target: {targets}");
            std::thread::sleep(Duration::from_millis(100));
        };
        let (ws, _) = tungstenite::connect(page.as_str()).expect("DevTools WebSocket");
        Browser { child, ws, id: 0 }
    }

    /// Calls a DevTools method and returns its result.
    fn call(&mut self, method: &str, params: Value) -> Value {
        self.id += 1;
        let message = json!({ "id": self.id, "method": method, "params": params });
        self.ws
            .send(tungstenite::Message::text(message.to_string()))
            .expect("send");
        loop {
            let reply = self.ws.read().expect("read");
            let Ok(text) = reply.to_text() else { continue };
            let value: Value = serde_json::from_str(text).expect("JSON");
            if value["id"] == json!(self.id) {
                assert!(value.get("error").is_none(), "{method}: {value}");
                return value["result"].clone();
            }
        }
    }

    /// The value of a JavaScript expression (promises awaited).
    fn eval(&mut self, expression: &str) -> Value {
        let result = self.call(
            "Runtime.evaluate",
            json!({ "expression": expression, "returnByValue": true, "awaitPromise": true }),
        );
        assert!(
            result.get("exceptionDetails").is_none(),
            "{expression}: {result}"
        );
        result["result"]["value"].clone()
    }

    /// Waits until `expression` is truthy and returns its value.
    fn wait_for(&mut self, expression: &str, timeout: Duration) -> Value {
        let deadline = Instant::now() + timeout;
        // The page may still be loading: an expression that throws is not yet true.
        let guarded =
            format!("(() => {{ try {{ return {expression}; }} catch (e) {{ return null; }} }})()");
        loop {
            let value = self.eval(&guarded);
            if !(value.is_null() || value == json!(false) || value == json!("")) {
                return value;
            }
            assert!(
                Instant::now() < deadline,
                "timed out waiting for {expression}; error shown: {}",
                self.eval("document.getElementById('error').textContent")
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    /// A mouse event at `(x, y)` (CSS pixels of the page).
    fn mouse(&mut self, kind: &str, x: f64, y: f64, buttons: u32) {
        let button = if buttons == 0 && kind == "mouseMoved" {
            "none"
        } else {
            "left"
        };
        self.call(
            "Input.dispatchMouseEvent",
            json!({ "type": kind, "x": x, "y": y, "button": button, "buttons": buttons, "clickCount": 1 }),
        );
    }

    /// Waits for the converged frame of the last settings sent; returns its generation.
    fn converged(&mut self) -> u64 {
        self.wait_for(
            "(s => s.dataset.converged === '1' && +s.dataset.generation)(document.getElementById('status'))",
            Duration::from_secs(40),
        )
        .as_u64()
        .expect("generation")
    }

    /// The canvas's pixels, as 8-bit RGB (read back through a PNG data URL).
    fn canvas_rgb(&mut self) -> (u32, u32, Vec<u8>) {
        self.canvas_rgb_of("view")
    }

    /// Width, height and RGB pixels of the page's canvas `id`.
    fn canvas_rgb_of(&mut self, id: &str) -> (u32, u32, Vec<u8>) {
        let url = self.eval(&format!(
            "document.getElementById({id:?}).toDataURL('image/png')"
        ));
        let data = url
            .as_str()
            .and_then(|u| u.strip_prefix("data:image/png;base64,"))
            .expect("PNG data URL");
        use base64::Engine;
        let bytes = base64::engine::general_purpose::STANDARD
            .decode(data)
            .expect("base64");
        decode_rgb(&bytes)
    }

    /// Sets a control's value as a user would, and lets the page send it.
    fn set_control(&mut self, id: &str, value: &str) {
        self.eval(&format!(
            "(el => {{ el.value = {value:?}; el.dispatchEvent(new Event('change')); return true; }})(document.getElementById({id:?}))"
        ));
    }
}

/// Width, height and 8-bit RGB pixels of a PNG (alpha dropped).
fn decode_rgb(bytes: &[u8]) -> (u32, u32, Vec<u8>) {
    let image = image::load_from_memory_with_format(bytes, image::ImageFormat::Png)
        .expect("PNG")
        .to_rgb8();
    (image.width(), image.height(), image.into_raw())
}

/// The page in a real browser: the first frame arrives; dragging orbits the view; the stripe
/// count and the mode change the image; the probe on a sphere of radius r reads the exact
/// hit — the patch's own point and curvatures at the reported (u, v), and κ1 ≈ κ2 ≈ 1/r to
/// the scheme's approximation of the sphere; save writes a scene whose `smoothlab render`
/// has the converged canvas's pixels (beside them, the PNG's legend strip).
#[test]
fn the_page_orbits_probes_and_saves_in_a_browser() {
    let Some(binary) = chromium() else { return };
    let start = Instant::now();
    let dir = common::scratch("viewer", "browser");
    let radius = 2.5;
    let sphere = smoothlab::mesh::generate::analytic::sphere(2);
    let positions: Vec<glam::DVec3> = sphere.positions.iter().map(|p| *p * radius).collect();
    let mesh_path = dir.join("sphere.obj");
    std::fs::write(
        &mesh_path,
        smoothlab::mesh::generate::to_obj(&(positions, sphere.faces.clone())),
    )
    .expect("mesh");
    let scene = dir.join("sphere.toml");
    std::fs::write(
        &scene,
        "mesh = \"sphere.obj\"\n[scheme]\nname = \"hb\"\n[render]\nspp = 2\n",
    )
    .expect("scene");
    let out = dir.join("saved");
    let view = start_view(&[common::path_str(&scene), "--out", common::path_str(&out)]);
    let mut browser = Browser::open(&binary, &dir.join("profile"), &view.url, 640, 360);
    // First frame, converged.
    let first = browser.converged();
    let (w, h, before) = browser.canvas_rgb();
    assert!(w > 100 && h > 100, "{w}x{h}");
    assert!(before.chunks(3).any(|p| p[0] > 200), "bright stripes");
    assert!(before.chunks(3).any(|p| p[0] < 40), "dark stripes");
    // Drag to orbit.
    let (cx, cy) = (f64::from(w) / 2.0, f64::from(h) / 2.0);
    browser.mouse("mouseMoved", cx, cy, 0);
    browser.mouse("mousePressed", cx, cy, 1);
    for k in 1..=5 {
        browser.mouse(
            "mouseMoved",
            cx + 12.0 * f64::from(k),
            cy + 3.0 * f64::from(k),
            1,
        );
    }
    browser.mouse("mouseReleased", cx + 60.0, cy + 15.0, 0);
    let orbited = browser.converged();
    assert!(orbited > first, "the drag sent a new camera");
    let (_, _, after) = browser.canvas_rgb();
    assert_ne!(before, after, "the orbit changed the view");
    // The same drag in arcball mode turns about the screen's axes: the camera rolls off the
    // up axis (a turntable keeps the image's right horizontal), and stays orthonormal.
    browser.set_control("orbit", "arcball");
    browser.mouse("mousePressed", cx, cy, 1);
    for k in 1..=5 {
        browser.mouse(
            "mouseMoved",
            cx + 12.0 * f64::from(k),
            cy + 9.0 * f64::from(k),
            1,
        );
    }
    browser.mouse("mouseReleased", cx + 60.0, cy + 45.0, 0);
    let turned = browser.converged();
    assert!(turned > orbited, "the arcball drag sent a new camera");
    let camera: Value = serde_json::from_str(
        browser
            .eval("JSON.stringify(sceneKeys().camera)")
            .as_str()
            .expect("camera JSON"),
    )
    .expect("camera");
    let vector = |key: &str| -> glam::DVec3 {
        let v: [f64; 3] = serde_json::from_value(camera[key].clone()).expect(key);
        glam::DVec3::from_array(v)
    };
    let (back, up) = ((vector("eye") - vector("target")).normalize(), vector("up"));
    let right = up.cross(back);
    let axis = if browser.eval("document.getElementById('upaxis').value") == json!("z") {
        glam::DVec3::Z
    } else {
        glam::DVec3::Y
    };
    assert!(
        (up.length() - 1.0).abs() < 1e-9 && up.dot(back).abs() < 1e-9,
        "{camera}"
    );
    assert!(right.dot(axis).abs() > 1e-3, "the arcball rolled: {camera}");
    let (_, _, after) = browser.canvas_rgb();
    let orbited = turned;
    // Stripe count, then mode.
    browser.set_control("stripes", "5");
    let striped = browser.converged();
    assert!(striped > orbited);
    let (_, _, five) = browser.canvas_rgb();
    assert_ne!(after, five, "5 stripes look different from 16");
    browser.set_control("mode", "curvature");
    browser.converged();
    let (_, _, curvature) = browser.canvas_rgb();
    assert_ne!(five, curvature, "curvature mode looks different");
    // The probe under the centre of the canvas.
    browser.eval("document.getElementById('probe').dataset.json = ''");
    browser.mouse("mouseMoved", cx, cy, 0);
    let probe = browser.wait_for(
        "document.getElementById('probe').dataset.json",
        Duration::from_secs(20),
    );
    let probe: Value = serde_json::from_str(probe.as_str().expect("text")).expect("probe JSON");
    assert_eq!(probe["hit"], json!(true), "{probe}");
    let mesh = smoothlab::mesh::Mesh::load_with(&mesh_path, &Default::default())
        .expect("mesh")
        .0;
    let surface = smoothlab::schemes::build("hb", &mesh, &[]).expect("hb");
    let patch = &surface.patches[probe["patch"].as_u64().expect("patch") as usize];
    let (u, v) = (
        probe["u"].as_f64().expect("u"),
        probe["v"].as_f64().expect("v"),
    );
    let jet = patch.jet(u, v);
    let c = jet.curvature().expect("curvature");
    let number = |key: &str| probe["curvature"][key].as_f64().expect("curvature value");
    let position: Vec<f64> = serde_json::from_value(probe["position"].clone()).expect("position");
    assert_eq!(
        position,
        jet.p.to_array().to_vec(),
        "the patch's point at (u, v)"
    );
    assert_eq!(probe["face"], json!(patch.face));
    // The convex sign: κ of an outward-oriented sphere is +1/r.
    assert_eq!(
        (
            number("k1"),
            number("k2"),
            number("gaussian"),
            number("mean")
        ),
        (-c.k2, -c.k1, c.gaussian, -c.mean),
        "the patch's curvatures at (u, v)"
    );
    let radial = (jet.p.length() - radius).abs() / radius;
    let (k1r, k2r) = (number("k1") * radius, number("k2") * radius);
    eprintln!(
        "probe on the hb sphere (r = {radius}, 320 faces): |p|/r - 1 = {radial:.2e}, \
         κ1 r = {k1r:.6}, κ2 r = {k2r:.6}"
    );
    // The hb surface interpolates the sphere's vertices but is no sphere: its deviation
    // bounds how close the curvatures can come to 1/r.
    assert!(radial < 1e-3, "the hit lies on the sphere: {radial:e}");
    assert!(
        (k1r - 1.0).abs() < 0.1 && (k2r - 1.0).abs() < 0.1,
        "κ1 r = {k1r}, κ2 r = {k2r}"
    );
    // Save, then render the saved scene.
    let shown = browser.converged();
    let (_, _, canvas) = browser.canvas_rgb();
    browser.eval("document.getElementById('save').click(), true");
    let saved = browser.wait_for(
        "document.getElementById('saved').dataset.json",
        Duration::from_secs(40),
    );
    let saved: Value = serde_json::from_str(saved.as_str().expect("text")).expect("save JSON");
    assert_eq!(saved["generation"], json!(shown), "{saved}");
    let saved_toml = PathBuf::from(saved["scene"].as_str().expect("scene path"));
    assert!(saved_toml.starts_with(&out), "{}", saved_toml.display());
    let again = dir.join("again");
    let run = common::smoothlab(&[
        "render",
        common::path_str(&saved_toml),
        "-o",
        common::path_str(&again),
    ]);
    assert!(run.status.success(), "{}", common::stderr(&run));
    // The page shows the image; the PNGs carry the curvature legend right of it, so their
    // first canvas-width columns are compared.
    let (cw, ch, _) = browser.canvas_rgb();
    let image_part = |png: &str| {
        let img = image::open(png).expect("PNG").to_rgb8();
        assert_eq!(img.height(), ch);
        assert!(img.width() > cw, "the legend strip beside the image");
        image::imageops::crop_imm(&img, 0, 0, cw, ch)
            .to_image()
            .into_raw()
    };
    let rendered = image_part(common::path_str(&again.with_extension("png")));
    let written = image_part(saved["png"].as_str().expect("png"));
    assert_eq!(rendered.len(), canvas.len(), "same size");
    assert!(
        rendered == canvas,
        "render of the saved scene = the converged canvas"
    );
    assert!(written == canvas, "the saved PNG = the converged canvas");
    // Beside the canvas, never over it, the page shows the legend strip of the PNG.
    let beside = browser.eval(
        "(() => { const v = document.getElementById('view').getBoundingClientRect(), \
         l = document.getElementById('legend'); const r = l.getBoundingClientRect(); \
         return !l.classList.contains('hidden') && r.width > 0 && r.left >= v.right; })()",
    );
    assert_eq!(
        beside,
        json!(true),
        "the legend canvas lies right of the image"
    );
    let (lw, lh, strip) = browser.canvas_rgb_of("legend");
    let png = image::open(again.with_extension("png"))
        .expect("PNG")
        .to_rgb8();
    assert_eq!(
        (lw + cw, lh),
        png.dimensions(),
        "the legend canvas is the PNG's strip"
    );
    let png_strip = image::imageops::crop_imm(&png, cw, 0, lw, lh)
        .to_image()
        .into_raw();
    assert!(
        strip == png_strip,
        "the legend canvas = the PNG's legend strip"
    );
    assert!(PathBuf::from(saved["exr"].as_str().expect("exr")).is_file());
    eprintln!("browser test took {:.1} s", start.elapsed().as_secs_f64());
}
