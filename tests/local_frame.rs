//! Metrics do not depend on where the mesh is: every scheme builds and measures in the mesh's
//! local frame, so a mesh moved by 1e8 or 1e15 or scaled by 2^±40 measures exactly like the
//! original (the meshes are put on an integer grid first, so that every move is exact).

use glam::DVec3;
use smoothlab::mesh::Mesh;
use smoothlab::metrics::Metrics;
use smoothlab::schemes;

/// A named move of the mesh's points.
type Move = (&'static str, Box<dyn Fn(DVec3) -> DVec3>);

fn on_grid(mesh: &Mesh) -> Vec<DVec3> {
    let scale = (1u64 << 20) as f64 / mesh.bounds().diagonal();
    mesh.positions()
        .iter()
        .map(|&p| (p * scale).round())
        .collect()
}

fn measured(scheme: &str, positions: Vec<DVec3>, faces: &[[u32; 3]]) -> Metrics {
    let (mesh, _) = Mesh::from_triangles(positions, faces.to_vec()).expect("valid mesh");
    let (surface, frame, _) = schemes::build_timed_in_frame(scheme, &mesh, &[]).expect("surface");
    Metrics {
        construct_ms: 0.0,
        ..Metrics::measure_in_frame(&surface, &frame, &mesh, 0.0)
    }
}

#[test]
fn metrics_are_the_same_for_any_translation_and_power_of_two_scale() {
    let octahedron = Mesh::load(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/octahedron.obj"
    )))
    .expect("octahedron")
    .0;
    let mut meshes = vec![("octahedron".to_string(), octahedron)];
    meshes.extend(smoothlab::testing::closed_test_meshes().into_iter().take(3));
    for (name, mesh) in &meshes {
        let base = on_grid(mesh);
        for spec in schemes::SCHEMES {
            let reference = measured(spec.name, base.clone(), mesh.faces());
            let moves: [Move; 4] = [
                ("+1e8", Box::new(|p| p + DVec3::splat(1e8))),
                ("+1e15", Box::new(|p| p + DVec3::new(1e15, -1e15, 3e15))),
                ("x2^40", Box::new(|p| p * 2f64.powi(40))),
                ("x2^-40", Box::new(|p| p * 2f64.powi(-40))),
            ];
            for (label, f) in &moves {
                let moved = base.iter().map(|&p| f(p)).collect();
                let got = measured(spec.name, moved, mesh.faces());
                assert_eq!(got, reference, "{name} {} {label}", spec.name);
            }
        }
    }
}
