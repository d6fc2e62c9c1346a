//! Renderer throughput (a few minutes in total; the job group is the longest):
//! - BVH build over subdivided patch bounds, in patches per second, for an `hb` torus of
//!   15 360 quintic patches and for the scanned bunny's 4000 (`scenes/bunny.obj`: irregular
//!   rings, many more leaves per patch);
//! - primary-ray throughput (closest hit, one thread) on that surface, and on the scanned bunny
//!   seen close up (`primary_rays/exact_hb_bunny_view_256`, ray by ray, and
//!   `…_bundled`, in the renderer's 8×8 pixel bundles), and the same view rendered as a
//!   filtered zebra frame, shading included (`zebra_frame/exact_hb_bunny_view_256`);
//! - exact patches against the tessellated path at the level whose largest normal error is
//!   ≤ 0.01°, on a 1600-patch hb torus (the 15k-patch one would need ~16M triangles).
//!
//! - the BVH build of an `hb` icosphere of 81,920 faces (327,680 patches), for the cost per
//!   10^5 patches at scale;
//! - a whole `smoothlab render` job (OBJ read, weld and validation, hb, BVH, a 1024² zebra
//!   image, PNG) on that icosphere.
//!
//! Setup prints the figures criterion does not: leaves, memory, the tessellation level chosen
//! and its normal error, Newton statistics.

use std::hint::black_box;
use std::time::Duration;

use common::{camera_rays, ray_throughput_group, trace_all, trace_bundles};
use criterion::{Criterion, Throughput, criterion_group};
use smoothlab::mesh::Mesh;
use smoothlab::mesh::generate::analytic::torus;
use smoothlab::render::{Ray64, SurfaceTracer, Tracer};
use smoothlab::surface::Surface;
use smoothlab::testing::render::TessellatedTracer;
use smoothlab::testing::render::{PatchBvh, SubdivisionCriterion};

mod common;

/// 60 × 32 quads → 3840 faces → 15 360 hb patches.
fn hb_torus() -> Surface {
    hb_torus_of(60, 32)
}

/// An hb torus of `major × minor` quads (4 patches per triangle).
fn hb_torus_of(major: u32, minor: u32) -> Surface {
    let sampled = torus(major, minor, 1.0, 0.35);
    let (mesh, _) = Mesh::from_triangles(sampled.positions, sampled.faces).expect("torus mesh");
    smoothlab::schemes::build("hb", &mesh, &[]).expect("hb on the torus")
}

fn bvh_build(c: &mut Criterion) {
    let surface = hb_torus();
    let mut group = c.benchmark_group("bvh_build");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(6));
    group.throughput(Throughput::Elements(surface.patches.len() as u64));
    group.bench_function("hb_torus_15k_patches", |b| {
        b.iter(|| PatchBvh::build(black_box(&surface), &SubdivisionCriterion::default()))
    });
    let bunny = scanned_bunny_hb();
    group.throughput(Throughput::Elements(bunny.patches.len() as u64));
    group.bench_function("hb_scanned_bunny_4k_patches", |b| {
        b.iter(|| PatchBvh::build(black_box(&bunny), &SubdivisionCriterion::default()))
    });
    group.finish();
}

/// The hb surface of the scanned bunny (`scenes/bunny.obj`, 1000 faces, 4000 patches).
fn scanned_bunny_hb() -> Surface {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/bunny.obj");
    let (mesh, _) = Mesh::load(&path).expect("scenes/bunny.obj");
    smoothlab::schemes::build("hb", &mesh, &[]).expect("hb on the bunny")
}

/// The unit icosphere of 81,920 faces (`generate::analytic::sphere(6)`).
fn icosphere_81920() -> Mesh {
    let sampled = smoothlab::mesh::generate::analytic::sphere(6);
    let (mesh, _) = Mesh::from_triangles(sampled.positions, sampled.faces).expect("icosphere");
    mesh
}

fn bvh_build_at_scale(c: &mut Criterion) {
    let surface = smoothlab::schemes::build("hb", &icosphere_81920(), &[]).expect("hb");
    let mut group = c.benchmark_group("bvh_build");
    group.sample_size(10);
    group.throughput(Throughput::Elements(surface.patches.len() as u64));
    group.bench_function("hb_icosphere_327k_patches", |b| {
        b.iter(|| PatchBvh::build(black_box(&surface), &SubdivisionCriterion::default()))
    });
    group.finish();
}

/// The whole render command on the 81,920-face icosphere, as a user runs it.
fn render_job(c: &mut Criterion) {
    use smoothlab::testing::app::{RenderArgs, render_command};
    let dir = std::env::temp_dir().join(format!("smoothlab-bench-job-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch folder");
    let obj = dir.join("icosphere-81920.obj");
    std::fs::write(&obj, icosphere_81920().to_obj("icosphere")).expect("write the mesh");
    let args = RenderArgs {
        input: obj,
        scheme: Some("hb".into()),
        size: Some([1024, 1024]),
        no_exr: true,
        output: Some(dir.join("job")),
        ..RenderArgs::default()
    };
    let mut group = c.benchmark_group("render_job");
    group.sample_size(10);
    group.bench_function("hb_icosphere_81920_faces_1024", |b| {
        b.iter(|| render_command(black_box(&args)).expect("render"))
    });
    group.finish();
    let _ = std::fs::remove_dir_all(&dir);
}

fn primary_rays(c: &mut Criterion) {
    let surface = hb_torus();
    let rays = camera_rays(&surface, 256);
    let exact = Tracer::with_default_settings(&surface).expect("tracer");
    report_exact("hb torus 15k", &surface, &exact, &rays);
    let mut group = ray_throughput_group(c, "primary_rays", rays.len(), 5);
    group.bench_function("exact_hb_torus_15k", |b| {
        b.iter(|| trace_all(&exact, black_box(&rays)))
    });
    group.finish();
}

/// The scanned bunny (`scenes/bunny.obj`, 1000 faces, 4000 hb patches) seen close up, the
/// camera of `smoothlab render scenes/bunny.obj --scheme hb --eye 0,4,12 --target 0,3.5,0
/// --up 0,0,1 --fov 40`: 256² rays through the pixel centres, one thread.
fn bunny_view(c: &mut Criterion) {
    use smoothlab::render::{Camera, Projection};
    let surface = scanned_bunny_hb();
    let camera = Camera::look_at(
        glam::DVec3::new(0.0, 4.0, 12.0),
        glam::DVec3::new(0.0, 3.5, 0.0),
        glam::DVec3::Z,
        Projection::Perspective { fov_deg: 40.0 },
    )
    .expect("camera");
    let side = 256u32;
    let rays: Vec<Ray64> = (0..side * side)
        .map(|i| {
            let (x, y) = (f64::from(i % side), f64::from(i / side));
            let nx = 2.0 * (x + 0.5) / f64::from(side) - 1.0;
            let ny = 1.0 - 2.0 * (y + 0.5) / f64::from(side);
            camera.ray(nx, ny, 1.0)
        })
        .collect();
    let exact = Tracer::with_default_settings(&surface).expect("tracer");
    report_exact("hb bunny view", &surface, &exact, &rays);
    let mut group = ray_throughput_group(c, "primary_rays", rays.len(), 5);
    group.bench_function("exact_hb_bunny_view_256", |b| {
        b.iter(|| trace_all(&exact, black_box(&rays)))
    });
    // The same rays as the renderer traces them: 8×8 pixel blocks as bundles from the eye.
    group.bench_function("exact_hb_bunny_view_256_bundled", |b| {
        b.iter(|| trace_bundles(&exact, black_box(&rays), side as usize))
    });
    group.finish();
    // The same view as a filtered zebra frame (the default mode, one sample per pixel):
    // tracing plus the shading point, the stripe footprint and the stripe phase per pixel.
    let settings = smoothlab::render::RenderSettings {
        width: side,
        height: side,
        spp: 1,
        progress: false,
        ..smoothlab::render::RenderSettings::default()
    };
    let mut group = ray_throughput_group(c, "zebra_frame", rays.len(), 5);
    group.bench_function("exact_hb_bunny_view_256", |b| {
        b.iter(|| smoothlab::render::render(&exact, &camera, black_box(&settings)).expect("frame"))
    });
    group.finish();
}

fn report_exact(name: &str, surface: &Surface, exact: &Tracer, rays: &[Ray64]) {
    let (hits, counters) = trace_all(exact, rays);
    println!(
        "{name}: {} patches, {} leaves, {:.2} MB, build {:.0} ms; {hits}/{} rays hit; Newton runs per ray {:.2}, mean {:.3}, max {}, failures {}, unconverged {}",
        surface.patches.len(),
        exact.leaf_count(),
        exact.memory_bytes() as f64 / 1e6,
        exact.build_ms(),
        rays.len(),
        counters.newton_runs as f64 / rays.len() as f64,
        counters.accepted_iterations as f64 / counters.roots_accepted.max(1) as f64,
        counters.accepted_iterations_max,
        counters.newton_failures,
        counters.newton_unconverged
    );
}

/// Exact patches against the coarsest tessellation whose normals are within 0.01° of the
/// exact ones, on a torus small enough (1600 patches) that the tessellation fits a laptop.
fn exact_vs_tessellated(c: &mut Criterion) {
    let surface = hb_torus_of(20, 10);
    let rays = camera_rays(&surface, 256);
    let exact = Tracer::with_default_settings(&surface).expect("tracer");
    report_exact("hb torus 1600", &surface, &exact, &rays);
    let target = 0.01_f64.to_radians();
    let mut level = 8;
    let tessellated = loop {
        let t = TessellatedTracer::new(&surface, level).expect("tessellation");
        let error = t.max_normal_error(16);
        println!(
            "tessellation N = {level}: {} triangles, {:.1} MB, max normal error {:.4}°",
            t.leaf_count(),
            t.memory_bytes() as f64 / 1e6,
            error.to_degrees()
        );
        if error <= target || level >= 64 {
            break t;
        }
        // Interpolated normals converge quadratically in the edge length: aim just below.
        level = ((f64::from(level) * (error / target).sqrt() * 1.05).ceil() as u32).max(level + 1);
    };
    println!(
        "memory exact / tessellated = {:.4}",
        exact.memory_bytes() as f64 / tessellated.memory_bytes() as f64
    );
    let mut group = ray_throughput_group(c, "exact_vs_tessellated", rays.len(), 5);
    group.bench_function("exact_hb_torus_1600", |b| {
        b.iter(|| trace_all(&exact, black_box(&rays)))
    });
    group.bench_function(format!("tessellated_N{level}_hb_torus_1600"), |b| {
        b.iter(|| trace_all(&tessellated, black_box(&rays)))
    });
    group.finish();
}

/// `RENDER_RAY_STATS=SIDE cargo bench --bench render` traces SIDE² camera rays once on the 15k
/// torus and prints the Newton counters scaled per 10⁶ rays, instead of running criterion. Under
/// `valgrind --tool=callgrind --toggle-collect='*trace_all*'` the collected instructions divided
/// by SIDE² are the instructions per ray, a figure that does not depend on machine load.
fn ray_stats(side: u32) {
    let surface = hb_torus();
    let rays = camera_rays(&surface, side);
    let exact = Tracer::with_default_settings(&surface).expect("tracer");
    let (hits, counters) = trace_all(&exact, &rays);
    let per_million = 1e6 / rays.len() as f64;
    println!(
        "{} rays, {hits} hits, {} leaves; Newton runs {}, mean iterations {:.3}, max {}; per 10^6 rays: failures {:.1}, unconverged {:.1}",
        rays.len(),
        exact.leaf_count(),
        counters.newton_runs,
        counters.accepted_iterations as f64 / counters.roots_accepted.max(1) as f64,
        counters.accepted_iterations_max,
        counters.newton_failures as f64 * per_million,
        counters.newton_unconverged as f64 * per_million,
    );
}

criterion_group!(
    benches,
    bvh_build,
    bvh_build_at_scale,
    primary_rays,
    bunny_view,
    exact_vs_tessellated,
    render_job
);

fn main() {
    if let Some(side) = std::env::var("RENDER_RAY_STATS")
        .ok()
        .and_then(|s| s.parse::<u32>().ok())
    {
        ray_stats(side);
        return;
    }
    benches();
    Criterion::default().configure_from_args().final_summary();
}
