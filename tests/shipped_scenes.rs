//! Every shipped render scene (`scenes/*.toml`) and figure spec (`scenes/figures/*.toml`) runs:
//! each is rendered at a tiny size (scenes through the command line's `--size`, `--spp` and `-o`
//! overrides, figure specs through a copy with `size`, `spp` and `output` replaced), so that a
//! key renamed in the parser, a mesh moved or a path gone stale fails here.

mod common;

use std::path::{Path, PathBuf};

use common::{path_str, scratch, smoothlab, stderr};

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes")
}

/// The `.toml` files of `dir` (not of its subfolders), sorted.
fn toml_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("scenes folder")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.is_file() && p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    files
}

fn stem(path: &Path) -> &str {
    path.file_stem().and_then(|s| s.to_str()).expect("name")
}

/// The lat-long map the peer scene reads (`environment = "../out/studio.exr"`), resolved as
/// the scene resolves it.
fn peer_map() -> PathBuf {
    scenes().join("../out/studio.exr")
}

#[test]
fn every_render_scene_renders() {
    let dir = scratch("shipped_scenes", "render");
    let files = toml_files(&scenes());
    assert!(files.len() >= 8, "{files:?}");
    for scene in &files {
        let name = stem(scene);
        let output = dir.join(name);
        let mut args = vec![
            "render",
            path_str(scene),
            "--size",
            "24x18",
            "--spp",
            "1",
            "--no-exr",
            "-o",
            path_str(&output),
        ];
        let turntable = std::fs::read_to_string(scene)
            .expect("scene")
            .contains("turntable =");
        if turntable {
            args.extend(["--turntable", "2"]);
        }
        let out = smoothlab(&args);
        if name == "shaded-hb-torus-peer" && !peer_map().exists() {
            // Without its map the peer scene says how to write it.
            common::assert_fails_naming(&out, &["environment map", "--example studio_map"]);
            continue;
        }
        assert!(out.status.success(), "{name}: {}", stderr(&out));
        let png = if turntable {
            dir.join(format!("{name}-001.png"))
        } else {
            dir.join(format!("{name}.png"))
        };
        assert!(png.is_file(), "{name}: no {}", png.display());
    }
}

/// The peer scene with its map in place renders: a tiny lat-long map written beside a copy of
/// the scene stands in for the studio map.
#[test]
fn the_peer_scene_renders_with_its_map() {
    let dir = scratch("shipped_scenes", "peer");
    let text = std::fs::read_to_string(scenes().join("shaded-hb-torus-peer.toml")).expect("scene");
    assert!(
        text.contains("environment = \"../out/studio.exr\""),
        "{text}"
    );
    let mesh = scenes().join("torus.obj");
    let copy = text.replace(
        "mesh = \"torus.obj\"",
        &format!("mesh = {:?}", path_str(&mesh)),
    );
    assert_ne!(copy, text, "the mesh line");
    std::fs::create_dir_all(dir.join("scene")).expect("folder");
    std::fs::create_dir_all(dir.join("out")).expect("folder");
    std::fs::write(dir.join("scene/peer.toml"), &copy).expect("scene copy");
    let out = smoothlab(&["render", path_str(&dir.join("scene/peer.toml"))]);
    common::assert_fails_naming(
        &out,
        &[
            "studio.exr",
            "cannot read environment map",
            "--example studio_map",
        ],
    );
    exr::prelude::write_rgb_file(dir.join("out/studio.exr"), 16, 8, |x, y| {
        let v = 0.2 + 0.05 * (x + y) as f32;
        (v, v, v)
    })
    .expect("map");
    let out = smoothlab(&[
        "render",
        path_str(&dir.join("scene/peer.toml")),
        "--size",
        "24x18",
        "--spp",
        "1",
        "-o",
        path_str(&dir.join("peer")),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(dir.join("peer.png").is_file());
}

/// A copy of figure spec `spec` for a tiny run: cells of 24×24 pixels at 1 sample, no EXR,
/// output `output`, and every relative path (the mesh file, environment maps) made absolute.
fn tiny_spec(spec: &Path, output: &Path) -> String {
    let text = std::fs::read_to_string(spec).expect("spec");
    let mut table: toml::Table = text.parse().expect("spec is TOML");
    let folder = spec.parent().expect("folder");
    table.insert(
        "size".into(),
        toml::Value::Array(vec![toml::Value::Integer(24), toml::Value::Integer(24)]),
    );
    table.insert("spp".into(), toml::Value::Integer(1));
    table.insert("exr".into(), false.into());
    table.insert("output".into(), path_str(output).into());
    let absolute = |value: &mut toml::Value| {
        if let toml::Value::String(path) = value {
            let is_file = [".obj", ".ply", ".off", ".stl", ".exr"]
                .iter()
                .any(|e| path.ends_with(e));
            if is_file && Path::new(path.as_str()).is_relative() {
                *path = path_str(&folder.join(path.as_str())).to_owned();
            }
        }
    };
    if let Some(mesh) = table.get_mut("mesh") {
        absolute(mesh);
    }
    if let Some(toml::Value::Array(modes)) = table.get_mut("modes") {
        for mode in modes {
            if let Some(env) = mode
                .get_mut("params")
                .and_then(|p| p.get_mut("environment"))
            {
                absolute(env);
            }
        }
    }
    toml::to_string(&table).expect("TOML")
}

#[test]
fn every_figure_spec_renders() {
    let dir = scratch("shipped_scenes", "figure");
    let specs = toml_files(&scenes().join("figures"));
    assert!(specs.len() >= 9, "{specs:?}");
    for spec in &specs {
        let name = stem(spec);
        let copy = dir.join(format!("{name}.toml"));
        std::fs::write(&copy, tiny_spec(spec, &dir.join(name))).expect("spec copy");
        let out = smoothlab(&["figure", path_str(&copy)]);
        assert!(out.status.success(), "{name}: {}", stderr(&out));
        assert!(
            dir.join(format!("{name}.png")).is_file(),
            "{name}: no sheet"
        );
        assert!(dir.join(format!("{name}.svg")).is_file(), "{name}: no SVG");
    }
}

/// Figure specs are kept apart from render scenes: none of `scenes/*.toml` is a figure spec,
/// and `render` given a figure spec says which command it belongs to.
#[test]
fn figure_specs_and_render_scenes_are_told_apart() {
    for scene in toml_files(&scenes()) {
        let text = std::fs::read_to_string(&scene).expect("scene");
        let table: toml::Table = text.parse().expect("TOML");
        assert!(
            !table.contains_key("schemes") && !table.contains_key("modes"),
            "{} is a figure spec: it belongs in scenes/figures/",
            scene.display()
        );
    }
    let spec = scenes().join("figures/fig14.toml");
    let out = smoothlab(&["render", path_str(&spec)]);
    common::assert_fails_naming(&out, &["figure spec", "smoothlab figure"]);
}
