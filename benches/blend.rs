//! Throughput of the blend jet (three cubic or quartic sub-surface jets and the rational
//! weights with their derivatives) against the polynomial patches of `hb` and `loop94`, every
//! patch of the deformed icosahedron evaluated at the same parameter points.

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::DVec3;
use smoothlab::mesh::{Mesh, generate};
use smoothlab::surface::Surface;

/// Parameter points per patch, spread over the domain.
const SAMPLES: usize = 64;

fn surface(scheme: &str, params: &[(&str, &str)]) -> Surface {
    let (positions, faces) = generate::deformed_icosahedron();
    let mesh = Mesh::from_triangles(positions, faces)
        .expect("valid mesh")
        .0;
    let params: Vec<(String, String)> = params
        .iter()
        .map(|(n, v)| (n.to_string(), v.to_string()))
        .collect();
    smoothlab::schemes::build(scheme, &mesh, &params).expect("scheme builds")
}

fn jet_throughput(c: &mut Criterion) {
    let params: Vec<(f64, f64)> = (0..SAMPLES)
        .map(|n| {
            let u = (n as f64 * 0.618_033_988_75).fract();
            let v = (n as f64 * 0.754_877_666_25).fract() * (1.0 - u);
            (u, v)
        })
        .collect();
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

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(Duration::from_secs(2));
    targets = jet_throughput
}
criterion_main!(benches);
