//! Throughput of the triangular Bézier jet (position + first and second derivatives), the
//! evaluation the ray tracer's Newton iteration and shading call for every ray.

use std::hint::black_box;
use std::time::Duration;

use common::parameter_spread;
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::DVec3;
use smoothlab::TriangleBezier;

mod common;

/// Parameter points per iteration, spread over the domain so branch prediction sees variety.
const SAMPLES: usize = 1024;

fn quintic() -> TriangleBezier {
    // A smooth, non-degenerate net: a paraboloid-like bump over the unit triangle.
    TriangleBezier::from_fn(5, |i, j, k| {
        let (u, v) = (j as f64 / 5.0, k as f64 / 5.0);
        DVec3::new(u, v, (u * u + v * v) * 0.5 + (i * j * k) as f64 * 0.01)
    })
}

fn jet_throughput(c: &mut Criterion) {
    let patch = quintic();
    let params = parameter_spread(SAMPLES);
    let mut group = c.benchmark_group("triangle");
    group.throughput(Throughput::Elements(SAMPLES as u64));
    group.bench_function("jet_quintic", |b| {
        b.iter(|| {
            let mut acc = DVec3::ZERO;
            for &(u, v) in &params {
                let jet = patch.jet(black_box(u), black_box(v));
                acc += jet.p + jet.duu;
            }
            acc
        })
    });
    group.bench_function("eval_quintic", |b| {
        b.iter(|| {
            let mut acc = DVec3::ZERO;
            for &(u, v) in &params {
                acc += patch.eval(black_box(DVec3::new(1.0 - u - v, u, v)));
            }
            acc
        })
    });
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(Duration::from_secs(2));
    targets = jet_throughput
}
criterion_main!(benches);
