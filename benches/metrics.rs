//! The smoothness metrics of the hb surface of an icosphere of 5,120 faces (20,480 patches,
//! 30,720 joints): the whole `Metrics::measure`, and the measured continuity order of every
//! joint alone (on the surface scaled as `Metrics::measure` scales it), both on the global
//! rayon pool.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use rayon::prelude::*;
use smoothlab::Aabb;
use smoothlab::mesh::{Mesh, generate};
use smoothlab::metrics::{Metrics, joint_order, unit_scale};
use smoothlab::schemes;

fn metrics(c: &mut Criterion) {
    let sphere = generate::analytic::sphere(4);
    let (mesh, _) = Mesh::from_triangles(sphere.positions, sphere.faces).expect("valid icosphere");
    let surface = schemes::build("hb", &mesh, &[]).expect("builds");
    let factor = unit_scale(mesh.positions());
    let scaled = surface.scaled(factor);
    let positions: Vec<_> = mesh.positions().iter().map(|&p| p * factor).collect();
    let diag = Aabb::from_points(&positions).diagonal();
    let joints = scaled.joints(mesh.faces(), Some(&mesh.edge_ids()));

    let mut group = c.benchmark_group("metrics");
    group.sample_size(10);
    group.throughput(Throughput::Elements(joints.len() as u64));
    group.bench_function("continuity/hb/icosphere-5120", |b| {
        b.iter(|| {
            joints
                .par_iter()
                .map(|j| joint_order(&scaled, j, diag))
                .min()
        })
    });
    group.bench_function("measure/hb/icosphere-5120", |b| {
        b.iter(|| Metrics::measure(&surface, &mesh, 0.0))
    });
    group.finish();
}

criterion_group!(benches, metrics);
criterion_main!(benches);
