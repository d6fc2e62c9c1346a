//! End-to-end tests of the analysis controls of `smoothlab render`: every zebra, highlight,
//! isophote and curvature flag against its scene key, the output options (`--no-exr`,
//! `--exr-compression`, PNG and EXR metadata, integer id channels) and the command-line
//! conventions (value lists, a mesh needs `--scheme`).

mod common;

use std::path::{Path, PathBuf};

use common::{assert_fails_naming, path_str, scratch, smoothlab, stderr};

fn ico() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/icosahedron.obj")
        .display()
        .to_string()
}

fn deformed() -> String {
    common::scene("deformed-icosahedron.obj")
}

/// Renders `input` with a small image and `extra` options to `dir/name`; returns the stem.
fn render(dir: &Path, name: &str, input: &str, extra: &[&str]) -> PathBuf {
    let stem = dir.join(name);
    let mut args = vec!["render", input, "--size", "48x40", "--spp", "1"];
    args.extend_from_slice(extra);
    args.extend(["-o", path_str(&stem)]);
    let out = smoothlab(&args);
    assert!(out.status.success(), "{args:?}: {}", stderr(&out));
    stem
}

/// A scene on `mesh` with scheme `scheme`, `mode` and extra TOML `sections`.
fn scene(dir: &Path, name: &str, mesh: &str, scheme: &str, mode: &str, sections: &str) -> String {
    let path = dir.join(format!("{name}.toml"));
    let text = format!(
        "mesh = {mesh:?}\n[scheme]\nname = \"{scheme}\"\n[render]\nmode = \"{mode}\"\n{sections}\n"
    );
    std::fs::write(&path, text).expect("write scene");
    path.display().to_string()
}

fn pixels(stem: &Path) -> Vec<[u8; 3]> {
    let img = image::open(stem.with_extension("png"))
        .expect("PNG")
        .to_rgb8();
    img.pixels().map(|p| p.0).collect()
}

/// Rendering with a flag and with its scene key gives the same pixels; without either the
/// pixels differ (the option has an effect).
fn flag_matches_key(test: &str, scheme: &str, mode: &str, flag: &[&str], key: &str) {
    let dir = scratch("analysis_controls", test);
    let mesh = deformed();
    let plain = scene(&dir, "plain", &mesh, scheme, mode, "");
    let keyed = scene(&dir, "keyed", &mesh, scheme, mode, key);
    let base = pixels(&render(&dir, "base", &plain, &[]));
    let by_flag = pixels(&render(&dir, "flag", &plain, flag));
    let by_key = pixels(&render(&dir, "key", &keyed, &[]));
    assert_eq!(by_flag, by_key, "{flag:?} and `{key}` differ");
    assert_ne!(base, by_flag, "{flag:?} changes nothing");
}

#[test]
fn a_mesh_without_scheme_is_an_error_listing_the_schemes() {
    let dir = scratch("analysis_controls", "no-scheme");
    let out = smoothlab(&["render", &ico(), "-o", path_str(&dir.join("x"))]);
    assert_fails_naming(
        &out,
        &["icosahedron.obj", "--scheme", "flat, pn, hb, loop94", "gk"],
    );
    assert!(!dir.join("x.png").exists());
}

#[test]
fn help_lists_values_and_defaults() {
    let out = smoothlab(&["render", "-h"]);
    assert!(out.status.success());
    let help = String::from_utf8_lossy(&out.stdout).replace("\n", " ");
    for fragment in [
        "possible values: zebra, highlight, isophote, curvature, normals, patches, diffuse, shaded",
        "[default: the scene's, else zebra]",
        "none, faces, patches, both",
        "none, rle, zips, zip, piz",
        "[default: rle]",
        "--no-exr",
        "--zebra-axis",
        "--zebra-stripes",
        "--zebra-width",
        "--zebra-duty",
        "--zebra-bright",
        "--zebra-dark",
        "--no-stripe-filter",
        "--highlight-lines",
        "--isophote-step",
        "gaussian, mean, maxabs, k1, k2",
        "diverging, coolwarm, sequential",
        "convex, normal",
        "--theme",
        "dark, paper",
        "--curvature-range",
        "--no-legend",
    ] {
        assert!(help.contains(fragment), "'{fragment}' missing from --help");
    }
    let out = smoothlab(&["render", &ico(), "--scheme", "pn", "--mode", "sparkle"]);
    assert_fails_naming(&out, &["sparkle", "zebra"]);
}

#[test]
fn no_exr_writes_the_png_only() {
    let dir = scratch("analysis_controls", "no-exr");
    let stem = render(&dir, "flag", &ico(), &["--scheme", "pn", "--no-exr"]);
    assert!(stem.with_extension("png").is_file());
    assert!(!stem.with_extension("exr").exists());
    let keyed = scene(&dir, "s", &ico(), "pn", "zebra", "exr = false");
    let stem = render(&dir, "key", &keyed, &[]);
    assert!(stem.with_extension("png").is_file());
    assert!(!stem.with_extension("exr").exists());
    let stem = render(&dir, "both", &ico(), &["--scheme", "pn"]);
    assert!(stem.with_extension("exr").is_file());
}

fn exr_compression_of(path: &Path) -> exr::compression::Compression {
    let meta = exr::meta::MetaData::read_from_file(path, false).expect("EXR header");
    meta.headers[0].compression
}

#[test]
fn exr_compression_is_chosen_by_flag_or_key() {
    use exr::compression::Compression;
    let dir = scratch("analysis_controls", "exr-compression");
    let rle = render(&dir, "rle", &ico(), &["--scheme", "pn"]).with_extension("exr");
    assert_eq!(exr_compression_of(&rle), Compression::RLE, "default kept");
    let zip = render(
        &dir,
        "zip",
        &ico(),
        &["--scheme", "pn", "--exr-compression", "zip"],
    )
    .with_extension("exr");
    assert_eq!(exr_compression_of(&zip), Compression::ZIP16);
    let none = render(
        &dir,
        "none",
        &ico(),
        &["--scheme", "pn", "--exr-compression", "none"],
    )
    .with_extension("exr");
    assert_eq!(exr_compression_of(&none), Compression::Uncompressed);
    let size = |p: &Path| std::fs::metadata(p).expect("size").len();
    assert!(size(&zip) < size(&none), "zip is smaller than uncompressed");
    let keyed = scene(
        &dir,
        "s",
        &ico(),
        "pn",
        "zebra",
        "exr_compression = \"piz\"",
    );
    let piz = render(&dir, "piz", &keyed, &[]).with_extension("exr");
    assert_eq!(exr_compression_of(&piz), Compression::PIZ);
    let bad = scene(
        &dir,
        "bad",
        &ico(),
        "pn",
        "zebra",
        "exr_compression = \"jpeg\"",
    );
    let out = smoothlab(&["render", &bad, "-o", path_str(&dir.join("x"))]);
    assert_fails_naming(&out, &["render.exr_compression", "jpeg", "piz"]);
}

#[test]
fn png_has_an_srgb_chunk_the_command_and_the_camera() {
    let dir = scratch("analysis_controls", "png-meta");
    let stem = render(
        &dir,
        "r",
        &ico(),
        &["--scheme", "pn", "--eye", "3,2,4", "--target", "0,0,0"],
    );
    let decoder = png::Decoder::new(std::io::BufReader::new(
        std::fs::File::open(stem.with_extension("png")).expect("png"),
    ));
    let reader = decoder.read_info().expect("PNG header");
    let info = reader.info();
    assert!(info.srgb.is_some(), "sRGB chunk");
    let text = |key: &str| {
        info.uncompressed_latin1_text
            .iter()
            .find(|t| t.keyword == key)
            .map(|t| t.text.clone())
            .unwrap_or_default()
    };
    let command = text("Comment");
    assert!(
        command.contains("render") && command.contains("--scheme pn") && command.contains("48x40"),
        "{command}"
    );
    let camera = text("Camera");
    assert!(camera.starts_with("eye 3,2,4 target 0,0,0"), "{camera}");
    assert!(text("Software").starts_with("smoothlab"));
}

#[test]
fn exr_has_camera_command_and_integer_ids() {
    use exr::prelude::{AttributeValue, FlatSamples, ReadChannels, ReadLayers, Text};
    let dir = scratch("analysis_controls", "exr-meta");
    let stem = render(
        &dir,
        "r",
        &ico(),
        &[
            "--scheme", "hb", "--eye", "3,2,4", "--up", "0,1,0", "--fov", "30",
        ],
    );
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .all_layers()
        .all_attributes()
        .from_file(stem.with_extension("exr"))
        .expect("EXR");
    let layer = &image.layer_data[0];
    let attribute = |name: &str| layer.attributes.other.get(&Text::from(name)).cloned();
    match attribute("smoothlab.camera") {
        Some(AttributeValue::Text(t)) => {
            let t = t.to_string();
            assert!(t.starts_with("eye 3,2,4 target "), "{t}");
            assert!(t.contains(" up ") && t.ends_with("fov_deg 30"), "{t}");
        }
        other => panic!("no camera attribute: {other:?}"),
    }
    let command = layer
        .attributes
        .comments
        .as_ref()
        .map(ToString::to_string)
        .unwrap_or_default();
    assert!(
        command.contains("render") && command.contains("--eye 3,2,4"),
        "{command}"
    );
    let channel = |name: &str| {
        layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name == *name)
            .map(|c| c.sample_data.clone())
            .unwrap_or_else(|| panic!("channel {name}"))
    };
    let (FlatSamples::U32(patch_u32), FlatSamples::F32(patch_f32)) =
        (channel("id.patch"), channel("patch_id"))
    else {
        panic!("id.patch must be u32 and patch_id f32");
    };
    let (FlatSamples::U32(face_u32), FlatSamples::F32(face_f32)) =
        (channel("id.face"), channel("face_id"))
    else {
        panic!("id.face must be u32 and face_id f32");
    };
    let mut hits = 0;
    for i in 0..patch_u32.len() {
        if patch_f32[i] < 0.0 {
            assert_eq!(
                (patch_u32[i], face_u32[i]),
                (u32::MAX, u32::MAX),
                "miss {i}"
            );
        } else {
            assert_eq!(patch_u32[i] as f32, patch_f32[i]);
            assert_eq!(face_u32[i] as f32, face_f32[i]);
            hits += 1;
        }
    }
    assert!(hits > 100 && hits < patch_u32.len(), "{hits} hits");
    assert!(face_u32.iter().filter(|&&f| f != u32::MAX).any(|&f| f > 0));
}

#[test]
fn zebra_axis_flag_and_key() {
    flag_matches_key(
        "zebra-axis",
        "hb",
        "zebra",
        &["--zebra-axis", "0,1,0"],
        "[zebra]\naxis = [0.0, 1.0, 0.0]",
    );
    flag_matches_key(
        "zebra-axis-h",
        "hb",
        "zebra",
        &["--zebra-axis", "view-horizontal"],
        "[zebra]\naxis = \"view-horizontal\"",
    );
    let dir = scratch("analysis_controls", "zebra-axis-bad");
    for bad in ["0,0,0", "sideways"] {
        let out = smoothlab(&[
            "render",
            &ico(),
            "--scheme",
            "pn",
            "--zebra-axis",
            bad,
            "-o",
            path_str(&dir.join("x")),
        ]);
        assert_fails_naming(&out, &["zebra.axis"]);
    }
}

#[test]
fn zebra_stripes_and_width_flags_and_keys() {
    flag_matches_key(
        "zebra-stripes",
        "hb",
        "zebra",
        &["--zebra-stripes", "8"],
        "[zebra]\nstripes = 8",
    );
    // thick = 45° per period = 8 stripes per turn.
    flag_matches_key(
        "zebra-width",
        "hb",
        "zebra",
        &["--zebra-width", "45"],
        "[zebra]\nwidth = \"thick\"",
    );
    let dir = scratch("analysis_controls", "zebra-width-bad");
    let both = scene(
        &dir,
        "both",
        &ico(),
        "pn",
        "zebra",
        "[zebra]\nstripes = 8\nwidth = 10",
    );
    let out = smoothlab(&["render", &both, "-o", path_str(&dir.join("x"))]);
    assert_fails_naming(&out, &["zebra.stripes", "zebra.width"]);
    let out = smoothlab(&[
        "render",
        &ico(),
        "--scheme",
        "pn",
        "--zebra-width",
        "huge",
        "-o",
        path_str(&dir.join("x")),
    ]);
    assert_fails_naming(&out, &["zebra.width", "huge", "thin"]);
}

#[test]
fn zebra_duty_and_colours_flags_and_keys() {
    flag_matches_key(
        "zebra-duty",
        "hb",
        "zebra",
        &["--zebra-duty", "0.2"],
        "[zebra]\nduty = 0.2",
    );
    flag_matches_key(
        "zebra-colours",
        "hb",
        "zebra",
        &["--zebra-bright", "1,0,0", "--zebra-dark", "0,0,0.5"],
        "[zebra]\nbright = [1.0, 0.0, 0.0]\ndark = [0.0, 0.0, 0.5]",
    );
    let dir = scratch("analysis_controls", "zebra-colour-check");
    let px = pixels(&render(
        &dir,
        "c",
        &deformed(),
        &[
            "--scheme",
            "hb",
            "--zebra-bright",
            "1,0,0",
            "--zebra-dark",
            "0,0,0.5",
            "--no-stripe-filter",
        ],
    ));
    // Every surface pixel is red or blue, none green (the background is grey).
    assert!(px.iter().any(|p| p[0] > 200 && p[2] == 0), "red stripes");
    assert!(px.iter().any(|p| p[2] > 150 && p[0] == 0), "blue stripes");
    assert!(
        px.iter()
            .all(|p| p[1] == 0 || (p[0] == p[1] && p[1] == p[2]))
    );
    let out = smoothlab(&[
        "render",
        &ico(),
        "--scheme",
        "pn",
        "--zebra-duty",
        "1.5",
        "-o",
        path_str(&dir.join("x")),
    ]);
    assert_fails_naming(&out, &["zebra.duty", "1.5"]);
}

/// With one sample per pixel, point-sampled stripes have exactly two colours; the filtered
/// ones have intermediate values where a pixel covers a stripe edge.
#[test]
fn stripe_filter_flag_and_key() {
    for (mode, section) in [
        ("zebra", "zebra"),
        ("highlight", "highlight"),
        ("isophote", "isophote"),
    ] {
        let test = format!("filter-{mode}");
        flag_matches_key(
            &test,
            "loop94",
            mode,
            &["--no-stripe-filter"],
            &format!("[{section}]\nfilter = false"),
        );
    }
    let dir = scratch("analysis_controls", "filter-grey");
    let grey_levels = |extra: &[&str]| {
        let mut args = vec!["--scheme", "loop94", "--zebra-axis", "0,1,0"];
        args.extend_from_slice(extra);
        let px = pixels(&render(&dir, "z", &deformed(), &args));
        let mut levels: Vec<u8> = px.iter().map(|p| p[0]).collect();
        levels.sort_unstable();
        levels.dedup();
        levels.len()
    };
    let point = grey_levels(&["--no-stripe-filter"]);
    let filtered = grey_levels(&[]);
    assert!(
        point <= 3,
        "bright, dark and background only: {point} levels"
    );
    assert!(filtered > 20, "filtered edges: {filtered} levels");
}

#[test]
fn highlight_lines_flag_and_key() {
    flag_matches_key(
        "highlight-lines",
        "hb",
        "highlight",
        &["--highlight-lines", "9"],
        "[highlight]\nlines = 9",
    );
    let dir = scratch("analysis_controls", "highlight-bad");
    let both = scene(
        &dir,
        "both",
        &ico(),
        "pn",
        "highlight",
        "[highlight]\nlines = 3\nspacing = 0.5",
    );
    let out = smoothlab(&["render", &both, "-o", path_str(&dir.join("x"))]);
    assert_fails_naming(&out, &["highlight.spacing", "highlight.lines"]);
}

#[test]
fn isophote_step_flag_and_key() {
    flag_matches_key(
        "isophote-step",
        "hb",
        "isophote",
        &["--isophote-step", "10"],
        "[isophote]\nstep_deg = 10.0",
    );
    let dir = scratch("analysis_controls", "isophote-bad");
    let out = smoothlab(&[
        "render",
        &ico(),
        "--scheme",
        "pn",
        "--mode",
        "isophote",
        "--isophote-step",
        "0",
        "-o",
        path_str(&dir.join("x")),
    ]);
    assert_fails_naming(&out, &["isophote.step_deg", "0"]);
}

#[test]
fn curvature_flags_and_keys() {
    flag_matches_key(
        "curvature-quantity",
        "hb",
        "curvature",
        &["--curvature-quantity", "gaussian"],
        "[curvature]\nquantity = \"gaussian\"",
    );
    flag_matches_key(
        "curvature-map",
        "hb",
        "curvature",
        &["--curvature-map", "sequential"],
        "[curvature]\nmap = \"sequential\"",
    );
    flag_matches_key(
        "curvature-sign",
        "hb",
        "curvature",
        &["--curvature-sign", "normal"],
        "[curvature]\nsign = \"normal\"",
    );
    flag_matches_key(
        "curvature-range",
        "hb",
        "curvature",
        &["--curvature-range", "7.5"],
        "[curvature]\nrange = 7.5",
    );
    flag_matches_key(
        "curvature-legend",
        "hb",
        "curvature",
        &["--no-legend"],
        "[curvature]\nlegend = false",
    );
}

/// The default sign convention makes a convex surface positive (red in the diverging map);
/// `normal` (II/I with the outward patch normal) makes it negative (blue).
#[test]
fn convex_surfaces_are_positive_by_default() {
    let dir = scratch("analysis_controls", "convex-sign");
    let count = |extra: &[&str]| {
        let mut args = vec!["--scheme", "hb", "--mode", "curvature", "--no-legend"];
        args.extend_from_slice(extra);
        let px = pixels(&render(&dir, "c", &ico(), &args));
        let red = px.iter().filter(|p| p[0] > p[2] + 30).count();
        let blue = px.iter().filter(|p| p[2] > p[0] + 30).count();
        (red, blue)
    };
    let (red, blue) = count(&[]);
    assert!(
        red > 200 && 20 * blue < red,
        "convex: {red} red, {blue} blue"
    );
    let (red, blue) = count(&["--curvature-sign", "normal"]);
    assert!(
        blue > 200 && 20 * red < blue,
        "normal: {red} red, {blue} blue"
    );
}

#[test]
fn gallery_writes_an_exr_beside_each_png() {
    use smoothlab::testing::app::{GalleryOptions, render_gallery_with};
    let dir = scratch("analysis_controls", "gallery");
    let gallery = render_gallery_with(&dir, &GalleryOptions { size: 24, spp: 1 }).expect("gallery");
    assert!(!gallery.images.is_empty());
    for image in &gallery.images {
        assert!(image.path.is_file() && image.exr.is_file(), "{image:?}");
        assert_eq!(image.exr, image.path.with_extension("exr"));
    }
    // The curvature cells carry curvature values.
    let curved = gallery
        .images
        .iter()
        .find(|i| i.scheme == "hb" && i.mode == "curvature")
        .expect("hb curvature cell");
    let image = exr::prelude::read_all_flat_layers_from_file(&curved.exr).expect("EXR");
    let h = image.layer_data[0]
        .channel_data
        .list
        .iter()
        .find(|c| c.name == *"H")
        .expect("H channel");
    let values: Vec<f32> = (0..h.sample_data.len())
        .map(|i| h.sample_data.value_by_flat_index(i).to_f32())
        .collect();
    assert!(
        values.iter().any(|v| v.abs() > 0.1),
        "curvature values present"
    );
}
