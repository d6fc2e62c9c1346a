//! End-to-end tests of legends and themes: the curvature legend lies in a strip right of the
//! image in the PNG, never over it (the image part of the PNG is the render without legend,
//! the EXR is the image alone); the paper theme (`--theme paper`, `render.theme`, a figure
//! spec's `theme`) is white with dark text, its curvature map's zero grey; unknown theme
//! names are refused naming the key.

mod common;

use std::path::{Path, PathBuf};

use common::{assert_fails_naming, path_str, scratch, smoothlab, stderr};

const SIZE: (u32, u32) = (160, 120);

fn deformed() -> String {
    common::scene("deformed-icosahedron.obj")
}

/// Renders the deformed icosahedron with hb at [`SIZE`] in curvature mode with `extra`
/// options to `dir/name`; returns the stem.
fn render(dir: &Path, name: &str, input: &str, extra: &[&str]) -> PathBuf {
    let stem = dir.join(name);
    let size = format!("{}x{}", SIZE.0, SIZE.1);
    let mut args = vec!["render", input, "--size", &size, "--spp", "1"];
    args.extend_from_slice(extra);
    args.extend(["-o", path_str(&stem)]);
    let out = smoothlab(&args);
    assert!(out.status.success(), "{args:?}: {}", stderr(&out));
    stem
}

fn png(stem: &Path) -> image::RgbImage {
    image::open(stem.with_extension("png"))
        .expect("PNG")
        .to_rgb8()
}

/// The EXR's size and its R, G, B planes.
fn exr_rgb(stem: &Path) -> ((usize, usize), Vec<Vec<f32>>) {
    let image =
        exr::prelude::read_all_flat_layers_from_file(stem.with_extension("exr")).expect("EXR");
    let layer = &image.layer_data[0];
    let plane = |name: &str| {
        let c = layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name == *name)
            .unwrap_or_else(|| panic!("channel {name}"));
        (0..c.sample_data.len())
            .map(|i| c.sample_data.value_by_flat_index(i).to_f32())
            .collect::<Vec<f32>>()
    };
    let size = (layer.size.0, layer.size.1);
    (size, ["R", "G", "B"].map(plane).to_vec())
}

/// The PNG is the image and, right of it, the legend strip: its first `SIZE.0` columns are the
/// render without legend, pixel for pixel; the strip holds the bar and its text on the
/// background; the EXR is the image area alone, the same with and without legend.
#[test]
fn the_curvature_legend_lies_beside_the_image_never_over_it() {
    let dir = scratch("legend", "beside");
    let args = ["--scheme", "hb", "--mode", "curvature"];
    let with = render(&dir, "with", &deformed(), &args);
    let without = render(
        &dir,
        "without",
        &deformed(),
        &[&args[..], &["--no-legend"]].concat(),
    );
    let (with_png, without_png) = (png(&with), png(&without));
    assert_eq!(without_png.dimensions(), SIZE);
    assert_eq!(with_png.height(), SIZE.1);
    let strip = with_png.width() - SIZE.0;
    assert!((30..SIZE.0).contains(&strip), "a strip of {strip} pixels");
    let image_part = image::imageops::crop_imm(&with_png, 0, 0, SIZE.0, SIZE.1).to_image();
    assert_eq!(
        image_part, without_png,
        "a legend pixel lies over the image"
    );
    // The strip: on the background (the colour of the image's missed corner), coloured bar
    // pixels and light text pixels.
    let background = *without_png.get_pixel(0, 0);
    let strip_px: Vec<[u8; 3]> = (SIZE.0..with_png.width())
        .flat_map(|x| (0..SIZE.1).map(move |y| (x, y)))
        .map(|(x, y)| with_png.get_pixel(x, y).0)
        .collect();
    let ground = strip_px.iter().filter(|p| **p == background.0).count();
    assert!(
        2 * ground > strip_px.len(),
        "{ground} of {}",
        strip_px.len()
    );
    assert!(
        strip_px.iter().any(|p| p[0] > p[2] + 60),
        "red end of the bar"
    );
    assert!(
        strip_px.iter().any(|p| p[2] > p[0] + 60),
        "blue end of the bar"
    );
    // The title and units above the bar (its top is below row 30 at this height).
    let title = (SIZE.0..with_png.width())
        .flat_map(|x| (0..30).map(move |y| (x, y)))
        .filter(|&(x, y)| with_png.get_pixel(x, y).0.iter().all(|&c| c > 180))
        .count();
    assert!(title > 40, "{title} text pixels");
    // The EXR is the image area and the same image with or without legend.
    let (size, planes) = exr_rgb(&with);
    assert_eq!(size, (SIZE.0 as usize, SIZE.1 as usize));
    assert_eq!(planes, exr_rgb(&without).1);
}

/// `--theme paper`: white background and legend ground, dark legend text, the curvature
/// map's zero a grey distinct from white; the scene key `render.theme` gives the same PNG;
/// the default is the dark theme.
#[test]
fn the_paper_theme_is_white_with_dark_text_by_flag_and_key() {
    let dir = scratch("legend", "paper");
    let scene = dir.join("paper.toml");
    std::fs::write(
        &scene,
        format!(
            "mesh = {:?}\n[scheme]\nname = \"hb\"\n[render]\nmode = \"curvature\"\ntheme = \"paper\"\n",
            deformed()
        ),
    )
    .expect("scene");
    let by_key = png(&render(&dir, "key", path_str(&scene), &[]));
    let args = ["--scheme", "hb", "--mode", "curvature"];
    let by_flag = png(&render(
        &dir,
        "flag",
        &deformed(),
        &[&args[..], &["--theme", "paper"]].concat(),
    ));
    assert_eq!(
        by_key, by_flag,
        "--theme paper and render.theme = \"paper\" differ"
    );
    let dark = png(&render(&dir, "dark", &deformed(), &args));
    let explicit = png(&render(
        &dir,
        "dark2",
        &deformed(),
        &[&args[..], &["--theme", "dark"]].concat(),
    ));
    assert_eq!(dark, explicit, "dark is the default");
    assert_ne!(dark, by_flag);
    let white = image::Rgb([255u8; 3]);
    assert_eq!(*by_flag.get_pixel(0, 0), white, "the background");
    assert_eq!(
        *by_flag.get_pixel(by_flag.width() - 1, SIZE.1 / 2),
        white,
        "the strip"
    );
    let title = (SIZE.0..by_flag.width())
        .flat_map(|x| (0..30).map(move |y| (x, y)))
        .filter(|&(x, y)| by_flag.get_pixel(x, y).0.iter().all(|&c| c < 75))
        .count();
    assert!(title > 40, "{title} dark text pixels");
    // The bar (5 pixels of pad, 10 wide at this height): its middle (zero) is a grey well below
    // white, cool–warm's 221, and no pixel inside it is white.
    let bar: Vec<[u8; 3]> = (48..82)
        .map(|y| by_flag.get_pixel(SIZE.0 + 10, y).0)
        .collect();
    // The bar's least saturated row (a row holds the value at its centre, so the zero row
    // is at most half a row off) is that grey.
    let spread = |p: &[u8; 3]| p.iter().max().unwrap_or(&0) - p.iter().min().unwrap_or(&0);
    let middle = bar.iter().min_by_key(|p| spread(p)).expect("bar");
    assert!(middle.iter().all(|&c| (210..=230).contains(&c)), "{bar:?}");
    assert!(bar.iter().all(|p| p != &[255; 3]), "{bar:?}");
    // No surface pixel is as white as the page (inside the silhouette, where every sample
    // hits): the lightest colour of the map is its grey zero.
    let (_, planes) = exr_rgb(&dir.join("flag"));
    let ids = exr_ids(&dir.join("flag"));
    let (w, h) = (SIZE.0 as usize, SIZE.1 as usize);
    let inside = |k: usize| {
        let (x, y) = (k % w, k / w);
        x > 0
            && y > 0
            && x + 1 < w
            && y + 1 < h
            && [k, k - 1, k + 1, k - w, k + w]
                .iter()
                .all(|&n| ids[n] != u32::MAX)
    };
    let surface = (0..w * h).filter(|&k| inside(k)).count();
    assert!(surface > 1000, "{surface} surface pixels");
    let on_white = (0..w * h)
        .filter(|&k| inside(k) && planes.iter().all(|p| p[k] > 0.9))
        .count();
    assert_eq!(on_white, 0, "surface pixels as white as the page");
}

/// The EXR's `id.patch` plane (`u32::MAX` where the centre ray missed).
fn exr_ids(stem: &Path) -> Vec<u32> {
    let image =
        exr::prelude::read_all_flat_layers_from_file(stem.with_extension("exr")).expect("EXR");
    let c = image.layer_data[0]
        .channel_data
        .list
        .iter()
        .find(|c| c.name == *"id.patch")
        .expect("id.patch");
    (0..c.sample_data.len())
        .map(|i| c.sample_data.value_by_flat_index(i).to_u32())
        .collect()
}

/// Unknown theme names are refused: the scene key by name, the flag by clap with the values.
#[test]
fn unknown_themes_are_refused_naming_the_key() {
    let dir = scratch("legend", "unknown");
    let scene = dir.join("sepia.toml");
    std::fs::write(
        &scene,
        format!(
            "mesh = {:?}\n[scheme]\nname = \"flat\"\n[render]\ntheme = \"sepia\"\n",
            deformed()
        ),
    )
    .expect("scene");
    let out = smoothlab(&["render", path_str(&scene), "-o", path_str(&dir.join("x"))]);
    assert_fails_naming(&out, &["render.theme", "sepia", "dark, paper"]);
    let out = smoothlab(&[
        "render",
        &deformed(),
        "--scheme",
        "flat",
        "--theme",
        "sepia",
        "-o",
        path_str(&dir.join("y")),
    ]);
    assert!(!out.status.success());
    let err = stderr(&out);
    assert!(err.contains("--theme") && err.contains("paper"), "{err}");
    assert!(!dir.join("x.png").exists() && !dir.join("y.png").exists());
}

/// A paper-theme figure: a white sheet with dark labels, one legend for the curvature column
/// (its cells share the range), right of the column, beside the cells, never over them.
#[test]
fn a_paper_figure_has_a_white_sheet_and_one_legend_per_column() {
    let dir = scratch("legend", "figure");
    let spec = dir.join("spec.toml");
    std::fs::write(
        &spec,
        "mesh = \"deformed-icosahedron\"\noutput = \"fig\"\nsize = [120, 120]\nspp = 1\n\
         exr = false\ntheme = \"paper\"\n[[schemes]]\nname = \"flat\"\n[[schemes]]\nname = \"hb\"\n\
         [[modes]]\nname = \"zebra\"\n[[modes]]\nname = \"curvature\"\n",
    )
    .expect("spec");
    let out = smoothlab(&["figure", path_str(&spec)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let sheet = image::open(dir.join("fig.png")).expect("sheet").to_rgb8();
    assert_eq!(*sheet.get_pixel(0, 0), image::Rgb([255; 3]));
    let svg = std::fs::read_to_string(dir.join("fig.svg")).expect("svg");
    assert!(svg.contains("fill=\"#ffffff\"") && svg.contains("fill=\"#141414\""));
    // Four cells and one legend strip.
    let images: Vec<[u32; 4]> = svg
        .lines()
        .filter(|l| l.starts_with("<image "))
        .map(|l| {
            ["x", "y", "width", "height"].map(|k| {
                let at = l.find(&format!(" {k}=\"")).expect(k) + k.len() + 3;
                l[at..].split('"').next().expect(k).parse().expect(k)
            })
        })
        .collect();
    assert_eq!(images.len(), 5, "{images:?}");
    let (cells, legend) = (&images[..4], images[4]);
    assert!(
        cells.iter().all(|c| c[2] == 120 && c[3] == 120),
        "{cells:?}"
    );
    // Right of the first curvature cell, and no cell overlaps it.
    assert_eq!([legend[0], legend[1]], [cells[1][0] + 120, cells[1][1]]);
    let overlaps = |a: [u32; 4], b: [u32; 4]| {
        a[0] < b[0] + b[2] && b[0] < a[0] + a[2] && a[1] < b[1] + b[3] && b[1] < a[1] + a[3]
    };
    assert!(cells.iter().all(|c| !overlaps(*c, legend)));
    assert!(legend[0] + legend[2] <= sheet.width());
}

/// `figure --theme paper` renders a spec without a `theme` key as the key would: the same
/// sheet, byte for byte; an unknown theme is refused naming the flag and the known names.
#[test]
fn figure_theme_flag_replaces_the_spec_key() {
    let dir = scratch("legend", "figure-flag");
    let body = "mesh = \"tetrahedron\"\nsize = [64, 64]\nspp = 1\nexr = false\n\
                [[schemes]]\nname = \"hb\"\n[[modes]]\nname = \"curvature\"\n";
    let keyed = dir.join("keyed.toml");
    let plain = dir.join("plain.toml");
    std::fs::write(
        &keyed,
        format!("output = \"keyed\"\ntheme = \"paper\"\n{body}"),
    )
    .expect("spec");
    std::fs::write(&plain, format!("output = \"plain\"\n{body}")).expect("spec");
    let out = smoothlab(&["figure", path_str(&keyed)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let out = smoothlab(&["figure", "--theme", "paper", path_str(&plain)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let sheet = |name: &str| image::open(dir.join(name)).expect(name).to_rgb8();
    let flagged = sheet("plain.png");
    assert_eq!(*flagged.get_pixel(0, 0), image::Rgb([255; 3]));
    assert!(
        flagged == sheet("keyed.png"),
        "--theme paper and theme = \"paper\" differ"
    );
    // The flag also wins over the key.
    let out = smoothlab(&["figure", "--theme", "dark", path_str(&keyed)]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_ne!(*sheet("keyed.png").get_pixel(0, 0), image::Rgb([255; 3]));
    let out = smoothlab(&["figure", "--theme", "sepia", path_str(&plain)]);
    assert_fails_naming(&out, &["--theme", "sepia", "paper"]);
}
