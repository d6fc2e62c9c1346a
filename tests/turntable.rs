//! End-to-end tests of `smoothlab render --turntable N` and `--sweep N` (and their scene keys):
//! the numbered frames and the looping GIF are written, frame 0 is the single render, the
//! frames are bit-identical for one and two threads, and bad values fail with one line naming
//! the flag.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use image::AnimationDecoder;

mod common;

/// The deformed icosahedron of `scenes/` (no symmetry that would repeat a view).
fn icosahedron() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/deformed-icosahedron.obj")
}

/// Runs `smoothlab render` in `dir` with `args` and `RAYON_NUM_THREADS=threads`.
fn render(dir: &Path, args: &[&str], threads: &str) -> Output {
    Command::new(env!("CARGO_BIN_EXE_smoothlab"))
        .arg("render")
        .args(args)
        .current_dir(dir)
        .env("RAYON_NUM_THREADS", threads)
        .output()
        .expect("run smoothlab")
}

fn pixels(path: &Path) -> image::RgbImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8()
}

/// The frames of an animated GIF.
fn gif_frames(path: &Path) -> Vec<image::RgbaImage> {
    let file = std::io::BufReader::new(std::fs::File::open(path).expect("gif"));
    image::codecs::gif::GifDecoder::new(file)
        .expect("gif decoder")
        .into_frames()
        .collect_frames()
        .expect("gif frames")
        .into_iter()
        .map(image::Frame::into_buffer)
        .collect()
}

const COMMON: [&str; 6] = ["--scheme", "hb", "--size", "40x32", "--spp", "1"];

#[test]
fn a_turntable_writes_its_frames_and_gif_identically_for_any_thread_count() {
    let dir = common::scratch("turntable", "threads");
    let mesh = icosahedron();
    let mesh = mesh.to_str().expect("utf-8 path");
    let mut runs = Vec::new();
    for threads in ["1", "2"] {
        let name = format!("spin{threads}");
        let mut args = vec![mesh, "--turntable", "4", "-o", &name];
        args.extend(COMMON);
        let out = render(&dir, &args, threads);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(!dir.join(format!("{name}.png")).exists(), "no single image");
        let frames: Vec<Vec<u8>> = (0..4)
            .map(|k| std::fs::read(dir.join(format!("{name}-{k:03}.png"))).expect("frame"))
            .collect();
        assert!(!dir.join(format!("{name}-004.png")).exists());
        let gif = gif_frames(&dir.join(format!("{name}.gif")));
        assert_eq!(gif.len(), 4);
        assert_eq!(gif[0].dimensions(), (40, 32));
        runs.push(frames);
    }
    assert!(runs[0] == runs[1], "frames differ between 1 and 2 threads");
    // The automatic framing keeps the surface inside every view: the border is background.
    for k in 0..4 {
        let frame = pixels(&dir.join(format!("spin1-{k:03}.png")));
        let background = *frame.get_pixel(0, 0);
        let (w, h) = frame.dimensions();
        let border = frame
            .enumerate_pixels()
            .filter(|(x, y, _)| *x == 0 || *y == 0 || *x == w - 1 || *y == h - 1);
        assert!(
            border.clone().all(|(_, _, p)| *p == background),
            "frame {k} is cut"
        );
        assert!(
            frame.pixels().any(|p| *p != background),
            "frame {k} is empty"
        );
    }
    // With an eye given, frame 0 is the single render; the other views differ from it.
    let mut args = vec![mesh, "--eye", "0.5,0.8,3", "-o", "still"];
    args.extend(COMMON);
    let out = render(&dir, &args, "2");
    assert!(out.status.success());
    let still = pixels(&dir.join("still.png"));
    let mut args = vec![mesh, "--eye", "0.5,0.8,3", "--turntable", "4", "-o", "eye"];
    args.extend(COMMON);
    assert!(render(&dir, &args, "2").status.success());
    assert!(
        pixels(&dir.join("eye-000.png")) == still,
        "frame 0 is the still"
    );
    for k in 1..4 {
        assert!(
            pixels(&dir.join(format!("eye-{k:03}.png"))) != still,
            "frame {k} repeats the still"
        );
    }
}

#[test]
fn scene_keys_set_the_turntable_and_its_axis() {
    let dir = common::scratch("turntable", "scene");
    let scene = format!(
        "mesh = {:?}\n[scheme]\nname = \"loop94\"\n[render]\nmode = \"isophote\"\n\
         size = [24, 24]\nspp = 1\noutput = \"out/axis\"\nturntable = 2\n\
         turntable_axis = [0.0, 0.0, 1.0]\n",
        icosahedron()
    );
    std::fs::write(dir.join("scene.toml"), scene).expect("scene");
    let out = render(&dir, &["scene.toml"], "2");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let first = pixels(&dir.join("out/axis-000.png"));
    let second = pixels(&dir.join("out/axis-001.png"));
    assert!(first != second, "the second view repeats the first");
    assert_eq!(gif_frames(&dir.join("out/axis.gif")).len(), 2);
    // The flag overrides the key.
    let out = render(&dir, &["scene.toml", "--turntable", "3"], "2");
    assert!(out.status.success());
    assert!(dir.join("out/axis-002.png").exists());
}

#[test]
fn a_sweep_moves_the_stripes_at_a_fixed_camera() {
    let dir = common::scratch("turntable", "sweep");
    let mesh = icosahedron();
    let mesh = mesh.to_str().expect("utf-8 path");
    // Point-sampled stripes: only the two stripe colours cover the surface, so a pixel of the
    // background colour is a miss (a filtered stripe's grey could equal the background's).
    let mut args = vec![
        mesh,
        "--mode",
        "zebra",
        "--no-stripe-filter",
        "--sweep",
        "3",
        "-o",
        "sweep",
    ];
    args.extend(COMMON);
    let out = render(&dir, &args, "2");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut args = vec![mesh, "--mode", "zebra", "--no-stripe-filter", "-o", "still"];
    args.extend(COMMON);
    assert!(render(&dir, &args, "2").status.success());
    let still = pixels(&dir.join("still.png"));
    let frames: Vec<image::RgbImage> = (0..3)
        .map(|k| pixels(&dir.join(format!("sweep-{k:03}.png"))))
        .collect();
    assert!(frames[0] == still, "frame 0 is the still");
    // The stripes move; the silhouette (background pixels) does not.
    let background = still.get_pixel(0, 0);
    for frame in &frames[1..] {
        assert!(*frame != still, "the stripes did not move");
        for (a, b) in frame.pixels().zip(still.pixels()) {
            assert_eq!(a == background, b == background);
        }
    }
    assert_eq!(gif_frames(&dir.join("sweep.gif")).len(), 3);
}

#[test]
fn bad_turntables_and_sweeps_fail_in_one_line() {
    let dir = common::scratch("turntable", "bad");
    let mesh = icosahedron();
    let mesh = mesh.to_str().expect("utf-8 path");
    for (extra, fragment) in [
        (vec!["--turntable", "0"], "--turntable"),
        (vec!["--turntable", "2", "--sweep", "2"], "exclude"),
        (
            vec!["--turntable", "2", "--turntable-axis", "0,0,0"],
            "--turntable-axis",
        ),
        (vec!["--turntable-axis", "0,1,0"], "needs render.turntable"),
        (vec!["--sweep", "2", "--mode", "curvature"], "curvature"),
        (vec!["--sweep", "5000"], "--sweep"),
    ] {
        let mut args = vec![mesh, "-o", "bad"];
        args.extend(COMMON);
        args.extend(&extra);
        let out = render(&dir, &args, "2");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{extra:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(
            stderr.starts_with("error: ") && stderr.contains(fragment),
            "{stderr}"
        );
        assert!(!dir.join("bad-000.png").exists());
    }
}

#[test]
fn help_names_the_flags() {
    let out = common::smoothlab(&["render", "--help"]);
    let help = String::from_utf8_lossy(&out.stdout);
    for flag in ["--turntable <N>", "--turntable-axis <X,Y,Z>", "--sweep <N>"] {
        assert!(help.contains(flag), "{flag} missing:\n{help}");
    }
}
