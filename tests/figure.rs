//! End-to-end tests of `smoothlab figure SPEC.toml`: a small grid writes its labelled PNG and one
//! EXR per cell; bad specs fail with one line naming the key or name at fault.

use std::path::{Path, PathBuf};
use std::process::Command;

mod common;

/// A fresh directory for one test's files.
fn scratch(test: &str) -> PathBuf {
    common::scratch("figure", test)
}

fn figure(dir: &Path, spec: &str) -> std::process::Output {
    let path = dir.join("spec.toml");
    std::fs::write(&path, spec).expect("write spec");
    Command::new(env!("CARGO_BIN_EXE_smoothlab"))
        .arg("figure")
        .arg(&path)
        .current_dir(dir)
        .output()
        .expect("run smoothlab")
}

const SPEC: &str = r#"
title = "test"
mesh = "icosahedron"
output = "out/grid"
size = [24, 20]
spp = 1
[[schemes]]
name = "loop94"
params = { alpha = 1, beta = 0.1 }
[[schemes]]
name = "flat"
[[modes]]
name = "zebra"
curves = true
control_polygons = true
[[modes]]
name = "curvature"
[[modes]]
name = "diffuse"
curves = true
surface = false
curve_edge = 0
view = "edge-side"
"#;

#[test]
fn a_small_figure_writes_its_grid_and_cells() {
    let dir = scratch("grid");
    let out = figure(&dir, SPEC);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let png = image::open(dir.join("out/grid.png"))
        .expect("grid png")
        .to_rgb8();
    // Two rows and three columns of 24 x 20 cells plus labels and gutters.
    assert!(
        png.width() > 3 * 24 && png.height() > 2 * 20,
        "{:?}",
        png.dimensions()
    );
    let mut exrs: Vec<String> = std::fs::read_dir(dir.join("out"))
        .expect("out dir")
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".exr"))
        .collect();
    exrs.sort();
    assert_eq!(
        exrs,
        [
            "grid-0-0-loop94-zebra.exr",
            "grid-0-1-loop94-curvature.exr",
            "grid-0-2-loop94-diffuse.exr",
            "grid-1-0-flat-zebra.exr",
            "grid-1-1-flat-curvature.exr",
            "grid-1-2-flat-diffuse.exr",
        ]
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("grid.png") && stdout.contains("6 EXR"),
        "{stdout}"
    );
}

#[test]
fn bad_specs_fail_naming_the_fault() {
    let dir = scratch("bad");
    for (spec, fragment) in [
        (SPEC.replace("spp = 1", "spp = 1\nspeed = 2"), "speed"),
        (SPEC.replace("\"flat\"", "\"flatt\""), "flatt"),
        (SPEC.replace("\"diffuse\"", "\"glossy\""), "glossy"),
        (
            SPEC.replace("curve_edge = 0", "curve_edge = 999"),
            "edge 999",
        ),
        (SPEC.replace("beta = 0.1", "betta = 0.1"), "betta"),
    ] {
        let out = figure(&dir, &spec);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{fragment}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(
            stderr.starts_with("error: ") && stderr.contains(fragment),
            "{stderr}"
        );
        assert!(!stderr.contains("panicked"), "{stderr}");
    }
}

/// The scene keys of the overlay: tubes alone on the background, blue network and red polygons.
#[test]
fn render_scene_draws_the_network_alone() {
    let dir = scratch("scene");
    let obj = dir.join("ico.obj");
    let mesh = smoothlab::testing::mesh(smoothlab::mesh::generate::icosahedron());
    std::fs::write(&obj, mesh.to_obj("icosahedron")).expect("obj");
    let render = |surface: bool| {
        let text = format!(
            "mesh = \"ico.obj\"\n[scheme]\nname = \"loop94\"\n[render]\nmode = \"diffuse\"\n\
             size = [64, 64]\nspp = 1\noutput = \"net\"\ncurves = true\n\
             control_polygons = true\nsurface = {surface}\ncurve_radius = 0.004\n"
        );
        std::fs::write(dir.join("scene.toml"), text).expect("scene");
        let out = Command::new(env!("CARGO_BIN_EXE_smoothlab"))
            .args(["render", "scene.toml"])
            .current_dir(&dir)
            .output()
            .expect("run smoothlab");
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        image::open(dir.join("net.png")).expect("png").to_rgb8()
    };
    let alone = render(false);
    let count = |png: &image::RgbImage, f: &dyn Fn(&[u8; 3]) -> bool| {
        png.pixels().filter(|p| f(&p.0)).count()
    };
    let blue = count(&alone, &|p| {
        u32::from(p[2]) > 2 * u32::from(p[0].max(p[1])) && p[2] > 100
    });
    let red = count(&alone, &|p| {
        u32::from(p[0]) > 2 * u32::from(p[1].max(p[2])) && p[0] > 100
    });
    assert!(blue > 20 && red > 20, "blue {blue}, red {red}");
    // Without the surface, the tubes behind it show and the rest is background.
    let with_surface = render(true);
    let background = alone.get_pixel(0, 0).0;
    let empty_alone = count(&alone, &|p| *p == background);
    let empty_with = count(&with_surface, &|p| *p == background);
    assert!(
        empty_alone > empty_with + 300,
        "{empty_alone} vs {empty_with}"
    );
    let blue_with = count(&with_surface, &|p| {
        u32::from(p[2]) > 2 * u32::from(p[0].max(p[1])) && p[2] > 100
    });
    assert!(
        blue > blue_with,
        "hidden tubes appear: {blue} vs {blue_with}"
    );
}
