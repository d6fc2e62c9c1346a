//! Patch evaluation with derivatives (evals/s) of every registered scheme: the position, first
//! and second derivatives that Newton iteration, shading and the metrics ask for, spread over
//! all patches of the scheme's surface on the deformed icosahedron.

use std::hint::black_box;
use std::time::Duration;

use common::parameter_spread;
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use smoothlab::mesh::generate;
use smoothlab::schemes;

mod common;

const SAMPLES: usize = 4096;

fn evaluate(c: &mut Criterion) {
    let mesh = smoothlab::testing::mesh(generate::deformed_icosahedron());
    let params = parameter_spread(SAMPLES);
    let mut group = c.benchmark_group("evaluate");
    group.sample_size(20);
    group.measurement_time(Duration::from_secs(2));
    group.throughput(Throughput::Elements(SAMPLES as u64));
    for spec in schemes::SCHEMES {
        let surface = schemes::build(spec.name, &mesh, &[]).expect("builds");
        let patches = &surface.patches;
        group.bench_function(format!("{}/deformed-icosahedron", spec.name), |b| {
            b.iter(|| {
                for (n, (u, v)) in params.iter().enumerate() {
                    black_box(patches[n % patches.len()].jet(*u, *v));
                }
            })
        });
    }
    group.finish();
}

criterion_group!(benches, evaluate);
criterion_main!(benches);
