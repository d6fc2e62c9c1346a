//! `smoothlab metrics` prints the table row by row, each scheme's row as soon as it is
//! measured: when a later scheme fails, the rows of the earlier ones are already out.

mod common;

use std::path::Path;

use common::{scratch, smoothlab};
use smoothlab::mesh::LoadOptions;
use smoothlab::testing::app;

/// A closed bipyramid over a 70-gon: its apexes have valence 70, above what `gk` takes with
/// `max_valence=64`, while every other scheme builds on it.
fn bipyramid() -> String {
    let n = 70;
    let mut text = String::from("v 0 0 1\nv 0 0 -1\n");
    for i in 0..n {
        let a = std::f64::consts::TAU * i as f64 / n as f64;
        text += &format!("v {} {} 0\n", a.cos(), a.sin());
    }
    for i in 0..n {
        let j = (i + 1) % n;
        text += &format!("f 1 {} {}\nf 2 {} {}\n", i + 3, j + 3, j + 3, i + 3);
    }
    text
}

#[test]
fn rows_of_the_schemes_measured_before_a_failure_are_printed() {
    let dir = scratch("metrics_output", "failure");
    let mesh = dir.join("bipyramid.obj");
    std::fs::write(&mesh, bipyramid()).unwrap();
    let out = smoothlab(&[
        "metrics",
        mesh.to_str().unwrap(),
        "--scheme",
        "all",
        "--param",
        "max_valence=64",
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.starts_with("error: scheme 'gk'") && stderr.contains("valence 70"),
        "{stderr}"
    );
    let schemes: Vec<&str> = stdout
        .lines()
        .skip(1)
        .map(|l| l.split_whitespace().next().unwrap())
        .collect();
    let before_gk: Vec<&str> = smoothlab::schemes::names()
        .into_iter()
        .take_while(|&s| s != "gk")
        .collect();
    assert!(!before_gk.is_empty());
    assert_eq!(schemes, before_gk, "{stdout}");
    assert!(stdout.starts_with("scheme "), "{stdout}");
}

#[test]
fn the_streamed_table_is_the_collected_table() {
    let mesh = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/octahedron.obj");
    let options = LoadOptions::default();
    let mut lines = Vec::new();
    let streamed = app::run_metrics_streaming(&mesh, &options, "all", &[], None, &mut |l| {
        lines.push(l.to_string())
    })
    .unwrap();
    assert!(streamed.stdout.is_empty());
    let collected = app::run_metrics(&mesh, &options, "all", &[], None).unwrap();
    // The same lines but for the build times.
    let strip_time = |line: &str| {
        let mut cells: Vec<&str> = line.split_whitespace().collect();
        cells.remove(3);
        cells.join(" ")
    };
    let streamed: Vec<String> = lines.iter().map(|l| strip_time(l)).collect();
    let collected: Vec<String> = collected.stdout.lines().map(strip_time).collect();
    assert_eq!(streamed, collected);
    assert_eq!(lines.len(), 1 + smoothlab::schemes::names().len());
    assert!(
        lines
            .iter()
            .all(|l| l.ends_with('\n') && l.lines().count() == 1)
    );
    assert!(
        lines.iter().all(|l| l.len() == lines[0].len()),
        "fixed widths: {lines:?}"
    );
}
