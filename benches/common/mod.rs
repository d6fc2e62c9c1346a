//! Inputs shared by the benchmark suites: parameter points spread over the domain triangle,
//! camera rays framing a surface, the one-thread closest-hit loop and the ray-throughput group.
//!
//! Each suite includes this module (`mod common;`) and uses the part it needs.

#![allow(dead_code, reason = "each suite uses only some of the helpers")]

use std::time::Duration;

use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, Criterion, Throughput};
use smoothlab::render::IntersectCounters;
use smoothlab::render::SurfaceSamples;
use smoothlab::render::{BundleScratch, Camera};
use smoothlab::render::{Ray64, SurfaceTracer};
use smoothlab::surface::Surface;

/// `count` parameter points `(u, v)` spread over the domain triangle `u, v ≥ 0, u + v ≤ 1` by
/// two irrational rotations (golden ratio and plastic number), so that consecutive points lie
/// far apart and branch prediction sees variety.
pub fn parameter_spread(count: usize) -> Vec<(f64, f64)> {
    (0..count)
        .map(|n| {
            let u = (n as f64 * 0.618_033_988_75).fract();
            let v = (n as f64 * 0.754_877_666_25).fract() * (1.0 - u);
            (u, v)
        })
        .collect()
}

/// Camera rays through the pixel centres of a `side × side` image framing `surface` from the
/// default view.
pub fn camera_rays(surface: &Surface, side: u32) -> Vec<Ray64> {
    let camera = Camera::frame_points(
        &SurfaceSamples::of(surface),
        Camera::DEFAULT_VIEW,
        35.0,
        1.0,
    )
    .expect("camera");
    let mut rays = Vec::with_capacity((side * side) as usize);
    for y in 0..side {
        for x in 0..side {
            let nx = 2.0 * (f64::from(x) + 0.5) / f64::from(side) - 1.0;
            let ny = 1.0 - 2.0 * (f64::from(y) + 0.5) / f64::from(side);
            rays.push(camera.ray(nx, ny, 1.0));
        }
    }
    rays
}

/// The closest hit of every ray on one thread: the number of hits and the counters.
///
/// Not inlined so that `valgrind --tool=callgrind --toggle-collect='*trace_all*'` counts the
/// tracing alone.
#[inline(never)]
pub fn trace_all<T: SurfaceTracer>(tracer: &T, rays: &[Ray64]) -> (u64, IntersectCounters) {
    let mut counters = IntersectCounters::default();
    let mut hits = 0;
    for ray in rays {
        if tracer
            .closest_hit(ray, 0.0, f64::INFINITY, &mut counters)
            .is_some()
        {
            hits += 1;
        }
    }
    (hits, counters)
}

/// The closest hit of every ray of a `side`-square image (row-major `rays`) on one thread,
/// traced as the renderer traces them: blocks of 8×8 pixels as bundles
/// ([`SurfaceTracer::closest_hits`]). The number of hits and the counters.
#[inline(never)]
pub fn trace_bundles<T: SurfaceTracer>(
    tracer: &T,
    rays: &[Ray64],
    side: usize,
) -> (u64, IntersectCounters) {
    let mut counters = IntersectCounters::default();
    let mut scratch = BundleScratch::default();
    let (mut bundle, mut hits) = (Vec::new(), Vec::new());
    let mut count = 0;
    for by in (0..side).step_by(8) {
        for bx in (0..side).step_by(8) {
            bundle.clear();
            for y in by..side.min(by + 8) {
                bundle.extend_from_slice(&rays[y * side + bx..y * side + side.min(bx + 8)]);
            }
            hits.clear();
            hits.resize(bundle.len(), None);
            tracer.closest_hits(
                &bundle,
                0.0,
                f64::INFINITY,
                &mut hits,
                &mut counters,
                &mut scratch,
            );
            count += hits.iter().filter(|h| h.is_some()).count() as u64;
        }
    }
    (count, counters)
}

/// A benchmark group counting `rays` rays per iteration: ten samples over `seconds` seconds
/// (tracing a whole image per iteration is slow, so criterion's defaults would take minutes).
pub fn ray_throughput_group<'c>(
    c: &'c mut Criterion,
    name: &str,
    rays: usize,
    seconds: u64,
) -> BenchmarkGroup<'c, WallTime> {
    let mut group = c.benchmark_group(name);
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(seconds));
    group.throughput(Throughput::Elements(rays as u64));
    group
}
