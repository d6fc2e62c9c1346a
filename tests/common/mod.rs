//! Helpers shared by the end-to-end test suites (each includes this module with `mod common;`).

#![allow(dead_code, reason = "each suite uses only some of the helpers")]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A fresh, empty directory for the files of test `test` of suite `suite`, under Cargo's
/// scratch directory for integration tests.
pub fn scratch(suite: &str, test: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(suite)
        .join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch directory");
    dir
}

/// Runs the `smoothlab` binary with `args` and waits for it.
pub fn smoothlab(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_smoothlab"))
        .args(args)
        .output()
        .expect("run smoothlab")
}

/// Runs the `smoothlab` binary with `args` and the environment variables `env` set.
pub fn smoothlab_with_env(args: &[&str], env: &[(&str, &str)]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_smoothlab"))
        .args(args)
        .envs(env.iter().copied())
        .output()
        .expect("run smoothlab")
}

/// Runs the `smoothlab` binary with `args` and its standard output going to `stdout` (a
/// closed pipe, `/dev/full`, …); standard error is captured.
pub fn smoothlab_with_stdout(args: &[&str], stdout: std::process::Stdio) -> Output {
    Command::new(env!("CARGO_BIN_EXE_smoothlab"))
        .args(args)
        .stdout(stdout)
        .stderr(std::process::Stdio::piped())
        .output()
        .expect("run smoothlab")
}

pub mod mesh_files;

/// The standard error of a finished run, as text.
/// The path of a shipped scene file (`scenes/NAME`) as a string, for command lines.
pub fn scene(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name)
        .display()
        .to_string()
}

pub fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// The OBJ `text` with its vertex number `vertex` (1-based, as OBJ counts) written as
/// `v {position}` instead: a stray vertex, as a corrupted file has.
pub fn with_vertex_moved(text: &str, vertex: usize, position: &str) -> String {
    let mut seen = 0;
    text.lines()
        .map(|line| {
            if line.starts_with("v ") {
                seen += 1;
                if seen == vertex {
                    return format!("v {position}\n");
                }
            }
            format!("{line}\n")
        })
        .collect()
}

/// `p` as UTF-8 (every test path is).
pub fn path_str(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

/// Fails unless `out` failed (exit code 1) with one `error:` line containing every fragment,
/// and no panic.
pub fn assert_fails_naming(out: &Output, fragments: &[&str]) {
    let err = stderr(out);
    assert_eq!(out.status.code(), Some(1), "exit code; stderr: {err}");
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "one line expected: {err}");
    assert!(lines[0].starts_with("error: "), "{err}");
    for f in fragments {
        assert!(lines[0].contains(f), "'{f}' missing from: {err}");
    }
    assert!(!err.contains("panicked"), "{err}");
}
