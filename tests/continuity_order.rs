//! The measured geometric continuity order of every scheme (DESIGN.md metrics key
//! `continuity_order`): `flat` and `pn` are G0, the G1 schemes measure exactly 1 between faces
//! on meshes without symmetries (a mirror-symmetric joint can agree to order 2 by symmetry).

use smoothlab::mesh::Mesh;
use smoothlab::metrics::Metrics;
use smoothlab::schemes;
use smoothlab::testing::scene;

fn order_between_faces(mesh: &Mesh, scheme: &str) -> i32 {
    let surface = schemes::build(scheme, mesh, &[]).expect("builds");
    let m = Metrics::measure(&surface, mesh, 0.0);
    eprintln!(
        "{scheme}: min {:?}, between faces {:?}, inside faces {:?}, typical {:?}",
        m.continuity_order,
        m.continuity_order_between_faces,
        m.continuity_order_inside_faces,
        m.continuity_order_typical
    );
    m.continuity_order_between_faces.expect("has joints")
}

#[test]
fn baselines_are_g0_and_g1_schemes_are_g1() {
    for mesh_name in ["deformed-icosahedron", "mixed-valence", "genus2"] {
        let mesh = scene(mesh_name);
        assert_eq!(order_between_faces(&mesh, "flat"), 0, "{mesh_name}");
        assert_eq!(order_between_faces(&mesh, "pn"), 0, "{mesh_name}");
        assert_eq!(order_between_faces(&mesh, "hb"), 1, "{mesh_name}");
        assert_eq!(order_between_faces(&mesh, "loop94"), 1, "{mesh_name}");
        assert_eq!(order_between_faces(&mesh, "piper"), 1, "{mesh_name}");
    }
}
