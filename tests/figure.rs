//! End-to-end tests of `smoothlab figure SPEC.toml`: a small grid writes its labelled PNG, its
//! SVG and one EXR per cell; the labels read right in both; bad specs fail with one line naming
//! the key or name at fault.

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
        stdout.contains("grid.png") && stdout.contains("grid.svg") && stdout.contains("6 EXR"),
        "{stdout}"
    );
}

/// One `<text>` of a figure's SVG.
struct SvgText {
    text: String,
    x: f32,
    baseline: f32,
    size: f32,
    middle: bool,
    fill: [u8; 3],
}

/// `#rrggbb` as bytes.
fn parse_hex(text: &str) -> [u8; 3] {
    let h = text.trim_start_matches('#');
    let byte = |k: usize| u8::from_str_radix(&h[2 * k..2 * k + 2], 16).expect("hex colour");
    [byte(0), byte(1), byte(2)]
}

/// The labels and cell rectangles of a figure's SVG (which must parse as XML).
fn read_svg(text: &str) -> (Vec<SvgText>, Vec<[u32; 4]>, [u32; 2]) {
    let doc = roxmltree::Document::parse(text).expect("the SVG parses as XML");
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "svg");
    let number = |n: &roxmltree::Node, key: &str| -> f32 {
        n.attribute(key)
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("{key} of {n:?}"))
    };
    let size = [
        number(&root, "width") as u32,
        number(&root, "height") as u32,
    ];
    let mut texts = Vec::new();
    let mut cells = Vec::new();
    for node in root.descendants().filter(|n| n.is_element()) {
        match node.tag_name().name() {
            "text" => {
                let fill = node
                    .ancestors()
                    .find_map(|a| a.attribute("fill"))
                    .expect("fill");
                texts.push(SvgText {
                    text: node.text().unwrap_or("").to_string(),
                    x: number(&node, "x"),
                    baseline: number(&node, "y"),
                    size: number(&node, "font-size"),
                    middle: node.attribute("text-anchor") == Some("middle"),
                    fill: parse_hex(fill),
                });
                let family = node
                    .ancestors()
                    .find_map(|a| a.attribute("font-family"))
                    .expect("font-family");
                assert!(
                    family.starts_with(smoothlab::testing::text::FONT_FAMILY),
                    "{family}"
                );
            }
            "image" => {
                let href = node.attribute("href").expect("href");
                assert!(href.starts_with("data:image/png;base64,"));
                cells.push(["x", "y", "width", "height"].map(|k| number(&node, k) as u32));
            }
            _ => {}
        }
    }
    (texts, cells, size)
}

/// Draws `texts` as the SVG places them with the crate's rasteriser onto `background`.
fn draw_svg_texts(texts: &[SvgText], size: [u32; 2], background: [u8; 3]) -> image::RgbImage {
    use smoothlab::testing::text::{ascent, draw_text, text_width};
    let mut img = image::RgbImage::from_pixel(size[0], size[1], image::Rgb(background));
    for t in texts {
        let left = if t.middle {
            t.x - 0.5 * text_width(t.size, &t.text)
        } else {
            t.x
        };
        draw_text(
            &mut img,
            left,
            t.baseline - ascent(t.size),
            t.size,
            t.fill,
            &t.text,
        );
    }
    img
}

/// The labels read "isophote", "piper", "fang-mann", "gk" in the SVG (vector text) and in the
/// PNG: every pixel outside the cells is what the rasteriser paints for the SVG's strings at
/// the SVG's positions, and a misspelt label would paint different pixels.
#[test]
fn labels_read_right_in_png_and_svg() {
    let dir = scratch("labels");
    let spec = r#"
mesh = "icosahedron"
output = "labels"
size = [160, 60]
spp = 1
exr = false
[[schemes]]
name = "piper"
[[schemes]]
name = "fang-mann"
[[schemes]]
name = "gk"
[[modes]]
name = "isophote"
[[modes]]
name = "curvature"
label = "mean curvature"
"#;
    let out = figure(&dir, spec);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let svg = std::fs::read_to_string(dir.join("labels.svg")).expect("svg");
    let png = image::open(dir.join("labels.png")).expect("png").to_rgb8();
    let (texts, cells, size) = read_svg(&svg);
    assert_eq!(size, [png.width(), png.height()]);
    // Six cells and one legend strip: the curvature column's cells share the figure's range,
    // so their legend is drawn once, right of the column's first cell, beside it, not over it.
    assert_eq!(cells.len(), 7);
    let legend = cells[6];
    assert_eq!([legend[0], legend[1]], [cells[1][0] + 160, cells[1][1]]);
    assert_eq!(legend[3], 60);
    let strings: Vec<&str> = texts.iter().map(|t| t.text.as_str()).collect();
    for label in ["isophote", "piper", "fang-mann", "gk"] {
        assert!(strings.contains(&label), "{label} missing from {strings:?}");
    }
    let curvature = strings
        .iter()
        .find(|s| s.starts_with("mean curvature ±"))
        .expect("curvature label with its range");
    assert!(
        curvature
            .trim_start_matches("mean curvature ±")
            .parse::<f64>()
            .is_ok(),
        "{curvature}"
    );
    let outside = |x: u32, y: u32| {
        !cells
            .iter()
            .any(|[cx, cy, w, h]| x >= *cx && x < cx + w && y >= *cy && y < cy + h)
    };
    let background = *png.get_pixel(0, 0);
    let drawn = draw_svg_texts(&texts, size, background.0);
    let mismatched = png
        .enumerate_pixels()
        .filter(|(x, y, p)| outside(*x, *y) && drawn.get_pixel(*x, *y) != *p)
        .count();
    assert_eq!(mismatched, 0, "label pixels differ from the SVG's text");
    let ink = png
        .enumerate_pixels()
        .filter(|(x, y, p)| outside(*x, *y) && **p != background)
        .count();
    assert!(ink > 200, "labels leave ink: {ink}");
    // The old bitmap spellings paint other pixels.
    for (right, wrong) in [("isophote", "isoPhote"), ("piper", "Piper"), ("gk", "9k")] {
        let mut misspelt: Vec<SvgText> = Vec::new();
        for t in &texts {
            misspelt.push(SvgText {
                text: if t.text == right {
                    wrong.into()
                } else {
                    t.text.clone()
                },
                ..*t
            });
        }
        let other = draw_svg_texts(&misspelt, size, background.0);
        assert!(
            png.enumerate_pixels()
                .any(|(x, y, p)| outside(x, y) && other.get_pixel(x, y) != p),
            "{wrong} would look like {right}"
        );
    }
    // The cells of the SVG are the cells of the PNG.
    let doc = roxmltree::Document::parse(&svg).expect("xml");
    use base64::Engine as _;
    for (node, [cx, cy, w, h]) in doc
        .descendants()
        .filter(|n| n.has_tag_name("image"))
        .zip(&cells)
    {
        let data = node.attribute("href").expect("href");
        let bytes = base64::engine::general_purpose::STANDARD
            .decode(data.trim_start_matches("data:image/png;base64,"))
            .expect("base64");
        let cell = image::load_from_memory(&bytes).expect("cell png").to_rgb8();
        assert_eq!(cell.dimensions(), (*w, *h));
        let crop = image::imageops::crop_imm(&png, *cx, *cy, *w, *h).to_image();
        assert_eq!(cell, crop);
    }
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
        (
            SPEC.replace("spp = 1", "spp = 1\ntheme = \"sepia\""),
            "theme: unknown theme 'sepia'",
        ),
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

/// Every file under `dir` (paths relative to it), sorted.
fn files_under(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).expect("list") {
            let path = e.expect("entry").path();
            if path.is_dir() {
                stack.push(path);
            } else {
                let rel = path.strip_prefix(dir).expect("inside");
                out.push(rel.to_string_lossy().into_owned());
            }
        }
    }
    out.sort();
    out
}

#[test]
fn an_output_that_names_a_folder_is_refused() {
    let dir = scratch("output-folder");
    std::fs::create_dir_all(dir.join("made")).expect("folder");
    for output in ["out/", "made", "."] {
        let spec = SPEC.replace("output = \"out/grid\"", &format!("output = \"{output}\""));
        let out = figure(&dir, &spec);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{output}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(
            stderr.contains("spec.toml: output: output name") && stderr.contains("is a folder"),
            "{stderr}"
        );
        let shard = Command::new(env!("CARGO_BIN_EXE_smoothlab"))
            .args(["figure", "spec.toml", "--shard", "0/2"])
            .current_dir(&dir)
            .output()
            .expect("run smoothlab");
        assert_eq!(shard.status.code(), Some(1), "{output}: --shard");
    }
    assert_eq!(files_under(&dir), ["spec.toml"], "nothing written");
}

#[test]
fn a_mode_environment_map_is_relative_to_the_spec() {
    let dir = scratch("environment");
    let specs = dir.join("specs");
    std::fs::create_dir_all(&specs).expect("folder");
    exr::prelude::write_rgb_file(specs.join("env.exr"), 16, 8, |x, _| {
        let v = 0.2 + 0.05 * x as f32;
        (v, v, v)
    })
    .expect("write map");
    let spec = r#"
mesh = "icosahedron"
output = "out/shaded"
size = [16, 12]
spp = 1
exr = false
[[schemes]]
name = "flat"
[[modes]]
name = "shaded"
params = { environment = "env.exr", bounces = 1 }
"#;
    std::fs::write(specs.join("fig.toml"), spec).expect("spec");
    // Run from the parent folder: the map is found beside the spec, not in the working folder.
    let out = Command::new(env!("CARGO_BIN_EXE_smoothlab"))
        .args(["figure", "specs/fig.toml"])
        .current_dir(&dir)
        .output()
        .expect("run smoothlab");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(specs.join("out/shaded.png").is_file());
    // A cell's EXR written over the map it is lit by is refused before any work.
    let cell = specs.join("out/shaded-0-0-flat-shaded.exr");
    std::fs::copy(specs.join("env.exr"), &cell).expect("copy");
    let over = spec
        .replace("exr = false", "exr = true")
        .replace("env.exr", "out/shaded-0-0-flat-shaded.exr");
    std::fs::write(specs.join("fig.toml"), over).expect("spec");
    for extra in [&[][..], &["--shard", "0/1"][..]] {
        let out = Command::new(env!("CARGO_BIN_EXE_smoothlab"))
            .args(["figure", "specs/fig.toml"])
            .args(extra)
            .current_dir(&dir)
            .output()
            .expect("run smoothlab");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{stderr}");
        assert!(
            stderr.contains(
                "shaded-0-0-flat-shaded.exr: an output would overwrite an \
                             environment map"
            ),
            "{stderr}"
        );
    }
    assert_eq!(
        std::fs::read(&cell).ok(),
        std::fs::read(specs.join("env.exr")).ok()
    );
    // A map that is not there is named by the path it was looked for at.
    std::fs::write(specs.join("fig.toml"), spec.replace("env.exr", "gone.exr")).expect("spec");
    let out = Command::new(env!("CARGO_BIN_EXE_smoothlab"))
        .args(["figure", "specs/fig.toml"])
        .current_dir(&dir)
        .output()
        .expect("run smoothlab");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("specs/gone.exr"), "{stderr}");
}

#[test]
fn a_figure_spec_and_a_scene_file_given_to_the_wrong_command_say_which_to_run() {
    let dir = scratch("wrong-command");
    let spec = dir.join("fig.toml");
    std::fs::write(&spec, SPEC.replace("spp = 1", "spp = 1\nexr = false")).expect("spec");
    let out = common::smoothlab(&["render", common::path_str(&spec)]);
    common::assert_fails_naming(
        &out,
        &["fig.toml: this is a figure spec", "run `smoothlab figure"],
    );
    let scene = dir.join("scene.toml");
    std::fs::write(
        &scene,
        "mesh = \"m.obj\"\n[scheme]\nname = \"hb\"\n[render]\nmode = \"zebra\"\n",
    )
    .expect("scene");
    let out = common::smoothlab(&["figure", common::path_str(&scene)]);
    common::assert_fails_naming(
        &out,
        &["scene.toml: this is a scene file", "run `smoothlab render"],
    );
    assert_eq!(files_under(&dir), ["fig.toml", "scene.toml"]);
}

/// A figure prints what loading repaired and what each construction changed, as the other
/// commands do: the flipped octahedron of the hostile corpus is re-oriented on loading, and
/// hb makes the spike edges of the scanned bunny's ear tip sharp.
#[test]
fn a_figure_prints_the_repairs_and_the_constructions_warnings() {
    let dir = scratch("warnings");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for (mesh, scheme, expected) in [
        (
            "scenes/hostile/octahedron-flipped.obj",
            "flat",
            "warning: re-oriented 1 faces",
        ),
        (
            "scenes/bunny.obj",
            "hb",
            "warning: hb: made 3 edges sharp at spikes of the mesh",
        ),
    ] {
        let spec = format!(
            "mesh = {:?}\noutput = \"out/w\"\nsize = [16, 16]\nspp = 1\nexr = false\n\
             [[schemes]]\nname = \"{scheme}\"\n[[modes]]\nname = \"zebra\"\n",
            root.join(mesh).display().to_string()
        );
        let out = figure(&dir, &spec);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{mesh}: {stderr}");
        assert!(stderr.contains(expected), "{mesh}: {stderr}");
    }
}
