//! Mesh loading (validation and topology of a 100,000-face torus) and the construction
//! throughput of every registered scheme (faces per second) on an icosphere of 81,920 faces
//! (`gk` once per smoothness order k = 1..4).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use smoothlab::mesh::{Mesh, generate};
use smoothlab::schemes;

fn construct(c: &mut Criterion) {
    let torus = generate::analytic::torus(250, 200, 1.0, 0.3);
    let mut load = c.benchmark_group("mesh");
    load.sample_size(10);
    load.throughput(Throughput::Elements(torus.faces.len() as u64));
    load.bench_function("validate-and-topology/torus-100000", |b| {
        b.iter(|| {
            Mesh::from_triangles(torus.positions.clone(), torus.faces.clone()).expect("valid")
        })
    });
    load.finish();

    let sphere = generate::analytic::sphere(6);
    let (mesh, _) = Mesh::from_triangles(sphere.positions, sphere.faces).expect("valid icosphere");
    let mut group = c.benchmark_group("construct");
    group.sample_size(10);
    group.measurement_time(std::time::Duration::from_secs(4));
    group.throughput(Throughput::Elements(mesh.face_count() as u64));
    for spec in schemes::SCHEMES {
        if spec.name == "gk" {
            // One figure per smoothness order: degree and subnet size grow with k.
            for k in 1..=4 {
                let params = [("k".to_string(), k.to_string())];
                group.bench_function(format!("gk-k{k}/icosphere-81920"), |b| {
                    b.iter(|| schemes::build("gk", &mesh, &params).expect("builds"))
                });
            }
            continue;
        }
        group.bench_function(format!("{}/icosphere-81920", spec.name), |b| {
            b.iter(|| schemes::build(spec.name, &mesh, &[]).expect("builds"))
        });
    }
    group.finish();
}

criterion_group!(benches, construct);
criterion_main!(benches);
