//! End-to-end tests of the exact renderer on scheme-built surfaces: watertightness from inside
//! closed `hb` surfaces, the `render` command's files (PNG, EXR channels and their meaning,
//! statistics keys) and its errors.

use std::path::PathBuf;

use glam::DVec3;
use smoothlab::mesh::Mesh;
use smoothlab::mesh::generate::{Triangles, icosahedron, mixed_valence};
use smoothlab::render::IntersectCounters;
use smoothlab::render::output::{EXR_CHANNELS, EXR_ID_CHANNELS};
use smoothlab::render::{Ray64, Tracer};
use smoothlab::surface::Surface;
use smoothlab::testing::app::{RenderArgs, render_command};
use smoothlab::testing::render::{sphere_direction, uniform};

mod common;

fn hb(mesh: Triangles) -> Surface {
    let mesh = smoothlab::testing::mesh(mesh);
    smoothlab::schemes::build("hb", &mesh, &[]).expect("hb builds on a closed mesh")
}

/// Shoots `rays` rays from points near the centre of a closed surface; returns the misses.
fn escapes(surface: &Surface, rays: u64) -> (u64, IntersectCounters) {
    let tracer = Tracer::with_default_settings(surface).expect("tracer");
    let centre = surface.bounds().center();
    let mut counters = IntersectCounters::default();
    let mut misses = 0;
    for i in 0..rays {
        let origin = centre + sphere_direction(77, i) * 0.05 * uniform(78, i, 0, 0);
        let ray = Ray64::new(origin, sphere_direction(79, i));
        if tracer
            .closest_hit(&ray, 0.0, f64::INFINITY, &mut counters)
            .is_none()
        {
            misses += 1;
        }
    }
    (misses, counters)
}

#[test]
fn hb_icosahedron_is_watertight_from_inside() {
    let (misses, counters) = escapes(&hb(icosahedron()), 100_000);
    assert_eq!(
        misses, 0,
        "rays escaped the closed hb icosahedron; {counters:?}"
    );
}

#[test]
fn hb_with_valence_16_vertices_is_watertight_from_inside() {
    let (misses, counters) = escapes(&hb(mixed_valence()), 100_000);
    assert_eq!(
        misses, 0,
        "rays escaped the closed hb surface; {counters:?}"
    );
}

fn write_obj(dir: &std::path::Path, triangles: Triangles) -> PathBuf {
    let path = dir.join("mesh.obj");
    std::fs::write(&path, smoothlab::mesh::generate::to_obj(&triangles)).expect("write obj");
    path
}

/// The command writes PNG, EXR and statistics; every EXR hit pixel is the surface point of the
/// patch `patch_id` at `(u, v)` and lies on the pixel's ray (to f32 precision of the file).
#[test]
fn render_command_writes_png_exr_and_stats() {
    let dir = common::scratch("render", "cmd");
    let obj = write_obj(&dir, icosahedron());
    let stem = dir.join("ico");
    let stats_path = dir.join("stats.json");
    let args = RenderArgs {
        input: obj.clone(),
        scheme: Some("hb".into()),
        mode: Some("curvature".into()),
        size: Some([40, 30]),
        spp: Some(4),
        output: Some(stem.clone()),
        stats: Some(stats_path.clone()),
        ..RenderArgs::default()
    };
    let (stats, _) = render_command(&args).expect("render");
    assert!(stats.hits > 0 && stats.misses > 0, "{stats:?}");
    let png = image::open(stem.with_extension("png")).expect("PNG readable");
    // The image and, right of it, the curvature legend: at 30 pixels tall the bare bar, 10
    // pixels wide with 5 on either side (the EXR below is the 40 × 30 image alone).
    assert_eq!((png.width(), png.height()), (40 + 20, 30));

    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&stats_path).expect("stats file"))
            .expect("stats JSON");
    for key in [
        "rays",
        "hits",
        "misses",
        "newton_iter_mean",
        "newton_iter_max",
        "newton_failures",
        "bvh_build_ms",
        "render_ms",
        "leaves",
        "memory_bytes",
        "pixels",
        "rays_per_pixel",
        "rays_per_s",
        "pixels_per_s",
    ] {
        assert!(json.get(key).is_some(), "stats lack '{key}': {json}");
    }
    // Where the memory goes: the parts sum to `memory_bytes`; hb's quintic patches hold 21
    // control points and an origin each, and one quintic power form of 21 points each,
    // shared by the patch's leaves.
    let parts = json["memory_parts"].as_object().expect("memory_parts");
    let part = |name: &str| {
        parts[name]
            .as_u64()
            .unwrap_or_else(|| panic!("{name}: {json}"))
    };
    let total: u64 = parts.values().map(|v| v.as_u64().expect("bytes")).sum();
    assert_eq!(json["memory_bytes"].as_u64(), Some(total), "{json}");
    assert_eq!(part("control_points"), 22 * 24 * stats.patches, "{json}");
    assert_eq!(part("power_forms"), 21 * 24 * stats.patches, "{json}");
    assert!(part("leaves") > 0 && part("bvh_nodes") > 0, "{json}");
    assert!(stats.leaves > stats.patches, "{json}");
    // 40 × 30 pixels; the rates follow from the counts.
    assert_eq!(json["pixels"], 1200);
    let rays = json["rays"].as_f64().expect("rays");
    let per_pixel = json["rays_per_pixel"].as_f64().expect("rays_per_pixel");
    assert_eq!(per_pixel, rays / 1200.0, "{json}");
    let ms = json["render_ms"].as_f64().expect("render_ms");
    let per_s = json["pixels_per_s"].as_f64().expect("pixels_per_s");
    assert!((per_s * ms * 1e-3 / 1200.0 - 1.0).abs() < 1e-12, "{json}");

    let image = exr::prelude::read_all_flat_layers_from_file(stem.with_extension("exr"))
        .expect("EXR readable");
    let layer = &image.layer_data[0];
    let mut names: Vec<String> = layer
        .channel_data
        .list
        .iter()
        .map(|c| c.name.to_string())
        .collect();
    names.sort();
    let mut expected: Vec<String> = EXR_CHANNELS
        .iter()
        .chain(&EXR_ID_CHANNELS)
        .map(|s| s.to_string())
        .collect();
    expected.sort();
    assert_eq!(names, expected);
    let channel = |name: &str| -> Vec<f32> {
        layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.to_string() == name)
            .map(|c| c.sample_data.values_as_f32().collect())
            .unwrap_or_else(|| panic!("channel {name}"))
    };
    let (patch_id, u, v) = (channel("patch_id"), channel("u"), channel("v"));
    let (px, py, pz) = (channel("P.X"), channel("P.Y"), channel("P.Z"));
    let z = channel("Z");
    let all: Vec<Vec<f32>> = EXR_CHANNELS.iter().map(|n| channel(n)).collect();
    assert!(
        all.iter().flatten().all(|x| x.is_finite()),
        "no NaN or infinity in the EXR"
    );

    let surface = hb(icosahedron());
    let diag = surface.bounds().diagonal();
    let mut hits = 0;
    for i in 0..patch_id.len() {
        if patch_id[i] < 0.0 {
            assert_eq!((z[i], u[i], v[i]), (-1.0, -1.0, -1.0), "miss pixel {i}");
            continue;
        }
        hits += 1;
        let patch = &surface.patches[patch_id[i] as usize];
        let p = patch.eval(f64::from(u[i]), f64::from(v[i]));
        let stored = DVec3::new(f64::from(px[i]), f64::from(py[i]), f64::from(pz[i]));
        // The file holds f32: agreement to a few f32 ulps of the coordinates.
        assert!(
            (p - stored).length() <= 1e-6 * diag,
            "pixel {i}: {p} vs {stored}"
        );
    }
    assert!(hits > 100, "{hits} hit pixels");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn render_command_errors_name_the_problem() {
    let missing = RenderArgs {
        input: PathBuf::from("/nonexistent/mesh.obj"),
        scheme: Some("hb".into()),
        ..RenderArgs::default()
    };
    let err = render_command(&missing).expect_err("missing file");
    assert!(err.to_string().contains("/nonexistent/mesh.obj"), "{err}");

    let dir = common::scratch("render", "err");
    let obj = write_obj(&dir, icosahedron());
    let no_scheme = RenderArgs {
        input: obj,
        output: Some(dir.join("x")),
        ..RenderArgs::default()
    };
    let err = render_command(&no_scheme).expect_err("no scheme");
    assert!(err.to_string().contains("--scheme"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

/// The EXR is the same bytes for any number of render threads and from run to run: its chunks
/// are written in increasing-y order, not in the order the compressing threads finish.
#[test]
fn exr_bytes_do_not_depend_on_threads() {
    let dir = common::scratch("render", "exr-bytes");
    let obj = write_obj(&dir, icosahedron());
    let render_with = |threads: usize| {
        let stem = dir.join(format!("threads-{threads}"));
        let args = RenderArgs {
            input: obj.clone(),
            scheme: Some("pn".into()),
            mode: Some("shaded".into()),
            size: Some([384, 320]),
            spp: Some(1),
            output: Some(stem.clone()),
            ..RenderArgs::default()
        };
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("thread pool")
            .install(|| render_command(&args))
            .expect("render");
        std::fs::read(stem.with_extension("exr")).expect("EXR")
    };
    let one = render_with(1);
    let meta = exr::meta::MetaData::read_from_buffered(std::io::Cursor::new(&one), false)
        .expect("EXR header");
    assert_eq!(
        meta.headers[0].line_order,
        exr::meta::attribute::LineOrder::Increasing
    );
    assert!(meta.headers[0].chunk_count > 4, "several chunks to order");
    for threads in [2, 3, 1] {
        assert!(
            render_with(threads) == one,
            "EXR bytes differ with {threads} threads"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// The acceptance figure: 10^6 rays from inside each closed hb surface (run with `--ignored`;
/// prints the Newton statistics).
#[test]
#[ignore]
fn million_rays_stay_inside_closed_hb_surfaces() {
    for (name, mesh) in [
        ("icosahedron", icosahedron()),
        ("mixed_valence", mixed_valence()),
    ] {
        let (misses, c) = escapes(&hb(mesh), 1_000_000);
        println!(
            "{name}: misses {misses}, Newton mean {:.3} max {}, failures {}, unconverged {}, runs {}",
            c.accepted_iterations as f64 / c.roots_accepted as f64,
            c.accepted_iterations_max,
            c.newton_failures,
            c.newton_unconverged,
            c.newton_runs
        );
        assert_eq!(misses, 0, "{name}");
    }
}

/// Wall-clock throughput probe for tuning (run with `--ignored`): 65 536 camera rays on an hb
/// torus of 15 360 patches, one thread. The criterion bench benches/render.rs is the reference.
#[test]
#[ignore]
fn primary_ray_throughput_probe() {
    use smoothlab::render::Camera;
    use smoothlab::render::SurfaceSamples;
    let sampled = smoothlab::mesh::generate::analytic::torus(60, 32, 1.0, 0.35);
    let (mesh, _) = Mesh::from_triangles(sampled.positions, sampled.faces).expect("torus");
    let surface = smoothlab::schemes::build("hb", &mesh, &[]).expect("hb");
    let tracer = Tracer::with_default_settings(&surface).expect("tracer");
    let camera = Camera::frame_points(
        &SurfaceSamples::of(&surface),
        Camera::DEFAULT_VIEW,
        35.0,
        1.0,
    )
    .expect("camera");
    let side = 256u32;
    let rays: Vec<Ray64> = (0..side * side)
        .map(|k| {
            let (x, y) = (k % side, k / side);
            camera.ray(
                2.0 * (f64::from(x) + 0.5) / f64::from(side) - 1.0,
                1.0 - 2.0 * (f64::from(y) + 0.5) / f64::from(side),
                1.0,
            )
        })
        .collect();
    // On-CPU time of this thread (Linux schedstat, ns): the machine is shared, so wall time
    // understates what one core does.
    let cpu_ns = || -> Option<f64> {
        let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
        text.split_whitespace().next()?.parse().ok()
    };
    let cpu_start = cpu_ns();
    let start = std::time::Instant::now();
    let mut counters = IntersectCounters::default();
    let mut hits = 0;
    for _ in 0..5 {
        for ray in &rays {
            hits += u64::from(
                tracer
                    .closest_hit(ray, 0.0, f64::INFINITY, &mut counters)
                    .is_some(),
            );
        }
    }
    let seconds = start.elapsed().as_secs_f64();
    let cpu_seconds = cpu_ns()
        .zip(cpu_start)
        .map_or(seconds, |(end, begin)| (end - begin) * 1e-9);
    println!(
        "{:.0} rays/s wall, {:.0} rays/s per core (on-CPU time), {hits} hits, {:?}",
        5.0 * rays.len() as f64 / seconds,
        5.0 * rays.len() as f64 / cpu_seconds,
        counters
    );
}

/// Writes `source` with every vertex scaled by `factor` (other lines unchanged).
fn scaled_obj(source: &std::path::Path, factor: f64, target: &std::path::Path) {
    let text = std::fs::read_to_string(source).expect("read mesh");
    let scaled: String = text
        .lines()
        .map(|line| match line.strip_prefix("v ") {
            Some(rest) => {
                let c: Vec<f64> = rest
                    .split_whitespace()
                    .map(|x| x.parse::<f64>().expect("coordinate") * factor)
                    .collect();
                format!("v {:e} {:e} {:e}\n", c[0], c[1], c[2])
            }
            None => format!("{line}\n"),
        })
        .collect();
    std::fs::write(target, scaled).expect("write scaled mesh");
}

/// Rendering is scale-free: a mesh scaled by 1e±20 (and the huge ×1e21 and tiny ×1e-6 of
/// the bug reports, which panicked in the BVH or hit nothing) renders byte-identical pixels to
/// the unscaled mesh, the automatic camera scaling with it.
#[test]
fn scaled_meshes_render_the_same_image() {
    let dir = common::scratch("render", "scaled");
    let scenes = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    for (mesh, scheme, factors) in [
        ("octahedron", "flat", &[1e21, 1e-20][..]),
        ("octahedron", "hb", &[1e20, 1e-20][..]),
        ("bunny", "pn", &[1e-6][..]),
    ] {
        let render = |factor: f64| {
            let obj = dir.join(format!("{mesh}-{factor:e}.obj"));
            scaled_obj(&scenes.join(format!("{mesh}.obj")), factor, &obj);
            let out = dir.join(format!("{mesh}-{scheme}-{factor:e}"));
            let run = common::smoothlab(&[
                "render",
                obj.to_str().expect("path"),
                "--scheme",
                scheme,
                "--mode",
                "zebra",
                "--size",
                "48x48",
                "-o",
                out.to_str().expect("path"),
            ]);
            assert!(
                run.status.success(),
                "{mesh} ×{factor:e}: {}",
                String::from_utf8_lossy(&run.stderr)
            );
            // The pixels (the PNG's text chunks name the mesh file and the camera, which
            // scale with it).
            image::open(out.with_extension("png"))
                .expect("png written")
                .to_rgb8()
                .into_raw()
        };
        let reference = render(1.0);
        for &factor in factors {
            assert!(
                render(factor) == reference,
                "{mesh} {scheme} ×{factor:e} renders a different image"
            );
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// One vertex of the hostile corpus's pinched pair moved 1e8 away (a stray vertex, as a
/// corrupted file has): piper's surface spans eight orders of magnitude, and the model's
/// patches are below the f32 resolution of the tracer's bounds where they lie. The render
/// warns, naming the first such patch's face and the bounding box; each of those patches is
/// one leaf (it was 17.3 M leaves for 1,152 patches and 77 s of BVH for the whole view), and
/// a close view of the model still hits it. (hb and loop94 refuse this mesh: their surfaces
/// fold over its needle faces.)
#[test]
fn a_stray_far_vertex_is_named_and_does_not_multiply_leaves() {
    let dir = common::scratch("render", "stray");
    let text = std::fs::read_to_string(scene_mesh("hostile/pinched-pair.obj")).expect("read mesh");
    let stray = common::with_vertex_moved(&text, 1, "100000000 0 0");
    let obj = dir.join("stray.obj");
    std::fs::write(&obj, stray).expect("write mesh");
    let render = |name: &str, view: &[&str]| {
        let out = dir.join(name);
        let stats = dir.join(format!("{name}.json"));
        let mut args = vec![
            "render",
            common::path_str(&obj),
            "--scheme",
            "piper",
            "--size",
            "24x24",
            "--no-exr",
            "-o",
            common::path_str(&out),
            "--stats",
            common::path_str(&stats),
        ];
        args.extend_from_slice(view);
        let run = common::smoothlab(&args);
        assert!(run.status.success(), "{}", common::stderr(&run));
        let stats: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&stats).expect("stats")).expect("json");
        (common::stderr(&run), stats)
    };
    let (warnings, stats) = render("whole", &[]);
    assert!(
        warnings.contains("1140 of 1152 patches (first: patch 6, of face 1,")
            && warnings.contains("below the exact renderer's resolution")
            && warnings.contains("runs from (-1.002e0, -1.014e0, -9.870e-1) to (1.000e8"),
        "{warnings}"
    );
    assert!(
        stats["leaves"].as_u64().expect("leaves") <= 4 * 1152,
        "{stats}"
    );
    let (_, close) = render("close", &["--eye", "0,0,2.5", "--target", "0,0,0"]);
    let (hits, rays) = (close["hits"].as_u64(), close["rays"].as_u64());
    assert!(
        hits.zip(rays).is_some_and(|(h, r)| h > r / 2),
        "the model fills the close view: {close}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

fn scene_mesh(name: &str) -> String {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name)
        .display()
        .to_string()
}

/// A frame too large for the memory limit is refused before the mesh is even read (the
/// mesh path does not exist), naming the size, the estimate, the limit and both remedies.
#[test]
fn a_frame_beyond_the_memory_limit_is_refused_first() {
    let dir = common::scratch("render", "frame-memory");
    let out = common::smoothlab_with_env(
        &[
            "render",
            "/nonexistent/tetrahedron.obj",
            "--scheme",
            "flat",
            "--size",
            "16384x16384",
            "--spp",
            "1",
            "--no-exr",
            "-o",
            common::path_str(&dir.join("big")),
        ],
        &[("SMOOTHLAB_MEMORY_LIMIT", "1000000000")],
    );
    common::assert_fails_naming(
        &out,
        &[
            "16384x16384 frame",
            "GB",
            "1.000 GB (SMOOTHLAB_MEMORY_LIMIT)",
            "--size",
            "set SMOOTHLAB_MEMORY_LIMIT",
        ],
    );
    // The EXR's planes count too: a frame that fits alone does not fit with its EXR.
    let mid = dir.join("mid");
    let with = |exr: bool| {
        let mut args = vec![
            "render",
            "/nonexistent/tetrahedron.obj",
            "--scheme",
            "flat",
            "--size",
            "4096x4096",
            "-o",
            common::path_str(&mid),
        ];
        if !exr {
            args.push("--no-exr");
        }
        common::smoothlab_with_env(&args, &[("SMOOTHLAB_MEMORY_LIMIT", "2500000000")])
    };
    common::assert_fails_naming(&with(true), &["4096x4096 frame", "--size"]);
    let png_only = common::stderr(&with(false));
    assert!(
        png_only.contains("/nonexistent/tetrahedron.obj") && !png_only.contains("frame"),
        "the PNG-only frame fits, the missing mesh is the error: {png_only}"
    );
}

/// `--tessellate` levels whose triangles do not fit are refused by their estimate (the
/// 48 × 48 image is tiny; the tessellation is what is large), a fitting one renders.
#[test]
fn tessellations_beyond_the_memory_limit_are_refused() {
    let dir = common::scratch("render", "tessellate-memory");
    let run = |level: &str| {
        common::smoothlab_with_env(
            &[
                "render",
                &scene_mesh("icosahedron.obj"),
                "--scheme",
                "hb",
                "--size",
                "48x48",
                "--spp",
                "1",
                "--no-exr",
                "--tessellate",
                level,
                "-o",
                common::path_str(&dir.join(format!("t{level}"))),
            ],
            &[("SMOOTHLAB_MEMORY_LIMIT", "1000000000")],
        )
    };
    for level in ["4096", "1024", "256"] {
        common::assert_fails_naming(
            &run(level),
            &[
                &format!("tessellation of 80 patches at --tessellate {level}"),
                "lower --tessellate",
                "SMOOTHLAB_MEMORY_LIMIT",
            ],
        );
    }
    let fits = run("16");
    assert!(fits.status.success(), "{}", common::stderr(&fits));
}

/// An absurd thread count is capped with a warning, and the image is the same as with one
/// thread (the work is split into fixed tiles).
#[test]
fn absurd_thread_counts_are_capped_with_a_warning() {
    let dir = common::scratch("render", "threads");
    let run = |threads: &str| {
        let stem = dir.join(format!("threads-{threads}"));
        let start = std::time::Instant::now();
        let out = common::smoothlab_with_env(
            &[
                "render",
                &scene_mesh("icosahedron.obj"),
                "--scheme",
                "hb",
                "--size",
                "32x32",
                "--spp",
                "1",
                "--no-exr",
                "-o",
                common::path_str(&stem),
            ],
            &[("RAYON_NUM_THREADS", threads)],
        );
        assert!(out.status.success(), "{}", common::stderr(&out));
        let png = image::open(stem.with_extension("png"))
            .expect("png")
            .to_rgb8()
            .into_raw();
        (common::stderr(&out), png, start.elapsed())
    };
    let (quiet, one, _) = run("1");
    assert!(!quiet.contains("warning"), "{quiet}");
    let (warned, many, took) = run("100000");
    assert!(
        warned.contains("warning: RAYON_NUM_THREADS=100000") && warned.contains("threads per core"),
        "{warned}"
    );
    assert!(many == one, "the capped run renders another image");
    assert!(took.as_secs() < 30, "{took:?}");
}

/// `--zebra-stripes` and `--zebra-width` set the same period: both on one command line are
/// refused in either order (each alone still replaces the scene's choice of the other).
#[test]
fn zebra_stripes_and_width_flags_are_not_both_accepted() {
    let dir = common::scratch("render", "zebra-both");
    let target = dir.join("x");
    for flags in [
        ["--zebra-width", "10", "--zebra-stripes", "8"],
        ["--zebra-stripes", "8", "--zebra-width", "10"],
    ] {
        let mut args = vec!["render", "/nonexistent/mesh.obj", "--scheme", "hb"];
        args.extend(flags);
        args.extend(["-o", common::path_str(&target)]);
        let out = common::smoothlab(&args);
        common::assert_fails_naming(&out, &["--zebra-stripes", "--zebra-width", "not both"]);
    }
}

/// Stripe counts the footprint filter cannot resolve, up to the largest finite ones, render
/// the mean grey of the stripes everywhere on the surface (no aliasing, no bright surface).
#[test]
fn unresolvable_zebra_counts_render_the_mean_grey() {
    let dir = common::scratch("render", "zebra-dense");
    let surface_levels = |stripes: &str| {
        let stem = dir.join(format!("z{stripes}"));
        let out = common::smoothlab(&[
            "render",
            &scene_mesh("icosahedron.obj"),
            "--scheme",
            "hb",
            "--size",
            "64x64",
            "--spp",
            "1",
            "--no-exr",
            "--zebra-stripes",
            stripes,
            "-o",
            common::path_str(&stem),
        ]);
        assert!(out.status.success(), "{}", common::stderr(&out));
        let img = image::open(stem.with_extension("png"))
            .expect("png")
            .to_rgb8();
        let background = img.get_pixel(0, 0).0;
        let levels: Vec<u8> = img
            .pixels()
            .filter(|p| p.0 != background)
            .map(|p| p.0[0])
            .collect();
        assert!(
            levels.len() > 1000,
            "{stripes}: {} surface pixels",
            levels.len()
        );
        levels
    };
    // The mean of 0.9 and 0.015 (linear) is 0.4575, sRGB byte 179.
    for stripes in ["1e6", "1e15", "1e20", "1e300"] {
        let levels = surface_levels(stripes);
        let (lo, hi) = (levels.iter().min(), levels.iter().max());
        assert!(
            levels.iter().all(|&l| l.abs_diff(179) <= 2),
            "{stripes}: surface levels {lo:?}..{hi:?}"
        );
    }
    let crisp = surface_levels("16");
    assert!(crisp.iter().any(|&l| l < 100) && crisp.iter().any(|&l| l > 230));
}
