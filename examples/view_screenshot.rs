//! A screenshot of a running `smoothlab view` once its frame has converged, taken with
//! headless Chromium over the DevTools protocol (`results/figures/viewer.png`, shown in docs/guide/viewer.md):
//!
//! ```text
//! smoothlab view scenes/bunny.obj --scheme hb --no-browser   # prints open URL
//! cargo run --release --example view_screenshot -- URL OUT.png [WIDTH HEIGHT]
//! ```

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use base64::Engine;
use serde_json::{Value, json};

fn get(addr: &str, path: &str) -> Vec<u8> {
    let mut s = TcpStream::connect(addr).expect("connect");
    write!(
        s,
        "GET {path} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n"
    )
    .expect("send");
    read_response(&mut s)
}

/// The body of an HTTP response, read up to its `Content-Length` (the DevTools server keeps
/// the connection open) or to the end.
fn read_response(s: &mut TcpStream) -> Vec<u8> {
    let mut r = Vec::new();
    let mut buf = [0u8; 65536];
    loop {
        let n = s.read(&mut buf).unwrap_or(0);
        r.extend_from_slice(&buf[..n]);
        if let Some(at) = r.windows(4).position(|w| w == b"\r\n\r\n") {
            let head = String::from_utf8_lossy(&r[..at]).to_ascii_lowercase();
            let length = head
                .lines()
                .find_map(|l| l.strip_prefix("content-length:"))
                .and_then(|v| v.trim().parse::<usize>().ok());
            if length.is_some_and(|len| r.len() >= at + 4 + len) || n == 0 {
                let end = length.map_or(r.len(), |len| at + 4 + len);
                return r[at + 4..end].to_vec();
            }
        } else if n == 0 {
            return Vec::new();
        }
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (url, out) = (&args[0], &args[1]);
    let (w, h) = (
        args.get(2).map_or(1100, |s| s.parse().expect("width")),
        args.get(3).map_or(620, |s| s.parse().expect("height")),
    );
    let profile = std::env::temp_dir().join(format!("view-screenshot-{}", std::process::id()));
    let mut child = Command::new("chromium")
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--hide-scrollbars",
            "--force-color-profile=srgb",
            "--remote-debugging-port=0",
            "--remote-allow-origins=*",
            &format!("--window-size={w},{h}"),
            &format!("--user-data-dir={}", profile.display()),
            url,
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run chromium");
    let mut lines = BufReader::new(child.stderr.take().expect("stderr")).lines();
    let endpoint = loop {
        let line = lines.next().expect("DevTools endpoint").expect("stderr");
        if let Some(at) = line.find("ws://") {
            break line[at..].trim().to_string();
        }
    };
    std::thread::spawn(move || for _ in lines {});
    let addr = endpoint
        .trim_start_matches("ws://")
        .split('/')
        .next()
        .expect("address")
        .to_string();
    let page = loop {
        let targets: Value = serde_json::from_slice(&get(&addr, "/json/list")).expect("targets");
        if let Some(p) = targets.as_array().and_then(|t| {
            t.iter()
                .find(|t| t["type"] == "page")
                .and_then(|t| t["webSocketDebuggerUrl"].as_str())
                .map(str::to_string)
        }) {
            break p;
        }
        std::thread::sleep(Duration::from_millis(100));
    };
    let (mut ws, _) = tungstenite::connect(page.as_str()).expect("WebSocket");
    let mut id = 0;
    let mut call = |method: &str, params: Value| -> Value {
        id += 1;
        let m = json!({ "id": id, "method": method, "params": params });
        ws.send(tungstenite::Message::text(m.to_string()))
            .expect("send");
        loop {
            let reply = ws.read().expect("read");
            let Ok(text) = reply.to_text() else { continue };
            let v: Value = serde_json::from_str(text).expect("JSON");
            if v["id"] == json!(id) {
                return v["result"].clone();
            }
        }
    };
    let deadline = Instant::now() + Duration::from_secs(120);
    loop {
        let r = call(
            "Runtime.evaluate",
            json!({ "expression": "document.getElementById('status').dataset.converged === '1'", "returnByValue": true }),
        );
        if r["result"]["value"] == json!(true) {
            break;
        }
        assert!(Instant::now() < deadline, "no converged frame");
        std::thread::sleep(Duration::from_millis(100));
    }
    let shot = call("Page.captureScreenshot", json!({ "format": "png" }));
    let png = base64::engine::general_purpose::STANDARD
        .decode(shot["data"].as_str().expect("data"))
        .expect("base64");
    std::fs::write(out, png).expect("write");
    let _ = child.kill();
    let _ = child.wait();
    let _ = std::fs::remove_dir_all(profile);
}
