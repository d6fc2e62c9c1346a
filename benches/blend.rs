//! Blend evaluation and rendering against `hb`:
//! - throughput of the patch jet (a blend: three cubic or quartic sub-surface jets and the
//!   rational weights with their derivatives), every patch of the deformed icosahedron at the
//!   same parameter points;
//! - primary-ray throughput of the exact renderer (closest hit, one thread) on the same torus
//!   mesh built with `hb`, `fang-mann t=2` and `nielson`, with the same camera rays;
//! - the same on the deformed icosahedron (20 blend patches, 128² rays), where most rays pass
//!   close to few, large leaves and the in-leaf search of an undecided Newton run dominates.

use std::hint::black_box;
use std::time::Duration;

use common::{camera_rays, parameter_spread, ray_throughput_group, trace_all};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::DVec3;
use smoothlab::mesh::generate;
use smoothlab::mesh::generate::analytic::torus;
use smoothlab::render::{SurfaceTracer, Tracer};
use smoothlab::surface::Surface;

mod common;

/// Parameter points per patch, spread over the domain.
const SAMPLES: usize = 64;

fn surface(scheme: &str, params: &[(&str, &str)]) -> Surface {
    let (positions, faces) = generate::deformed_icosahedron();
    build(scheme, params, positions, faces)
}

fn build(
    scheme: &str,
    params: &[(&str, &str)],
    positions: Vec<DVec3>,
    faces: Vec<[u32; 3]>,
) -> Surface {
    let mesh = smoothlab::testing::mesh((positions, faces));
    let params: Vec<(String, String)> = params
        .iter()
        .map(|(n, v)| (n.to_string(), v.to_string()))
        .collect();
    smoothlab::schemes::build(scheme, &mesh, &params).expect("scheme builds")
}

fn jet_throughput(c: &mut Criterion) {
    let params = parameter_spread(SAMPLES);
    let mut group = c.benchmark_group("patch_jet");
    for (label, scheme, p) in [
        ("hb", "hb", vec![]),
        ("fang-mann-t2", "fang-mann", vec![("t", "2")]),
        ("nielson", "nielson", vec![]),
    ] {
        let surface = surface(scheme, &p);
        group.throughput(Throughput::Elements(
            (SAMPLES * surface.patches.len()) as u64,
        ));
        group.bench_function(label, |b| {
            b.iter(|| {
                let mut acc = DVec3::ZERO;
                for patch in &surface.patches {
                    for &(u, v) in &params {
                        let jet = patch.jet(black_box(u), black_box(v));
                        acc += jet.p + jet.duu;
                    }
                }
                acc
            })
        });
    }
    group.finish();
}

fn primary_rays(c: &mut Criterion) {
    // 40 × 20 quads → 1600 faces: 6400 hb patches, 1600 blend patches.
    let sampled = torus(40, 20, 1.0, 0.35);
    let surfaces: Vec<(&str, Surface)> = [
        ("hb", "hb", vec![]),
        ("fang-mann-t2", "fang-mann", vec![("t", "2")]),
        ("nielson", "nielson", vec![]),
    ]
    .into_iter()
    .map(|(label, scheme, p)| {
        let s = build(scheme, &p, sampled.positions.clone(), sampled.faces.clone());
        (label, s)
    })
    .collect();
    let rays = camera_rays(&surfaces[0].1, 128);
    let mut group = ray_throughput_group(c, "primary_rays_torus_1600_faces", rays.len(), 4);
    for (label, surface) in &surfaces {
        let tracer = Tracer::with_default_settings(surface).expect("tracer");
        let (hits, counters) = trace_all(&tracer, &rays);
        println!(
            "{label}: {} patches, {} leaves, build {:.0} ms; {hits}/{} rays hit; Newton runs \
             per ray {:.2}, mean iterations {:.2}, failures {}",
            surface.patches.len(),
            tracer.leaf_count(),
            tracer.build_ms(),
            rays.len(),
            counters.newton_runs as f64 / rays.len() as f64,
            counters.accepted_iterations as f64 / counters.roots_accepted.max(1) as f64,
            counters.newton_failures,
        );
        group.bench_function(*label, |b| b.iter(|| trace_all(&tracer, black_box(&rays))));
    }
    group.finish();
}

fn primary_rays_deformed(c: &mut Criterion) {
    let surfaces: Vec<(&str, Surface)> = [
        ("nielson", "nielson", vec![]),
        ("fang-mann-t2", "fang-mann", vec![("t", "2")]),
    ]
    .into_iter()
    .map(|(label, scheme, p)| (label, surface(scheme, &p)))
    .collect();
    let rays = camera_rays(&surfaces[0].1, 128);
    let mut group = ray_throughput_group(c, "primary_rays_deformed_icosahedron", rays.len(), 4);
    for (label, surface) in &surfaces {
        let tracer = Tracer::with_default_settings(surface).expect("tracer");
        let (hits, counters) = trace_all(&tracer, &rays);
        println!(
            "{label}: {} leaves; {hits}/{} rays hit; Newton runs {}, unconverged {}, failures {}, \
             undecided pieces {}",
            tracer.leaf_count(),
            rays.len(),
            counters.newton_runs,
            counters.newton_unconverged,
            counters.newton_failures,
            counters.undecided,
        );
        group.bench_function(*label, |b| b.iter(|| trace_all(&tracer, black_box(&rays))));
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(Duration::from_secs(2));
    targets = jet_throughput, primary_rays, primary_rays_deformed
}
criterion_main!(benches);
