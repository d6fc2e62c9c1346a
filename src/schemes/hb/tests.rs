//! Measured properties of the HB00 surface on many meshes: patch count, vertex interpolation,
//! G0 and tangent-plane continuity between faces (G¹) and inside faces (C¹), twist
//! compatibility, affine invariance and locality.

use glam::{DMat3, DVec3};

use super::*;
use crate::mesh::generate;
use crate::metrics::Metrics;
use crate::testing::{JointFigures, Rng, assert_g1_joints, closed_test_meshes, mesh, params};

fn check(mesh_name: &str, mesh: &Mesh, p: &Params, interpolates: bool) {
    let surface = build(mesh, p).expect("hb builds on a closed mesh");
    assert_eq!(surface.patches.len(), 4 * mesh.face_count(), "{mesh_name}");
    let m = Metrics::measure(&surface, mesh, 0.0);
    let label = format!("{mesh_name} {:?}", p.values());
    // Every mesh edge is covered by two half-edge joints, every face has three inner edges.
    assert_eq!(m.joints_between_faces, 2 * mesh.edges().len(), "{label}");
    assert_eq!(
        m.joints - m.joints_between_faces,
        3 * mesh.face_count(),
        "{label}"
    );
    assert_eq!(m.singular_samples, 0, "{label}");
    let JointFigures {
        gap,
        between,
        inside,
    } = assert_g1_joints(&m, &label);
    eprintln!(
        "{label}: gap {gap:.1e}, normal jump between faces {between:.1e} rad, inside {inside:.1e} rad"
    );
    if interpolates {
        let e = m.interp_max_rel.unwrap();
        assert!(e <= 1e-12, "interpolation error {e} on {label}");
    }
    let mismatch = max_corner_mismatch(mesh, p).expect("params ok") / mesh.bounds().diagonal();
    assert!(mismatch <= 1e-12, "twist mismatch {mismatch} on {label}");
}

#[test]
fn g1_between_faces_c1_inside_and_interpolation_with_default_parameters() {
    for (name, mesh) in closed_test_meshes() {
        check(&name, &mesh, &params(&SPEC, &[]), true);
        check(
            &name,
            &mesh,
            &params(&SPEC, &[("free", "zero-twist")]),
            true,
        );
    }
}

#[test]
fn g1_with_random_shape_parameters() {
    let mut rng = Rng::new(0x5eed);
    let mut rnd = move || rng.next_f64();
    for (name, mesh) in closed_test_meshes() {
        for _ in 0..3 {
            let beta = format!("{}", 0.05 + 0.6 * rnd());
            let g0 = format!("{}", -4.0 + 6.0 * rnd());
            let g1 = format!("{}", -1.0 + 5.0 * rnd());
            let alpha = format!("{}", 0.5 + 0.5 * rnd());
            let p = params(
                &SPEC,
                &[
                    ("beta", &beta),
                    ("gamma0", &g0),
                    ("gamma1", &g1),
                    ("alpha", &alpha),
                ],
            );
            check(&name, &mesh, &p, false);
        }
    }
}

/// HB00 Fig. 14's parameters on the icosahedron.
#[test]
fn g1_with_the_figure_14_parameters() {
    let mesh = mesh(generate::icosahedron());
    let p = params(
        &SPEC,
        &[
            ("beta", "0.1"),
            ("gamma0", "-3.7"),
            ("gamma1", "4.6"),
            ("gamma2", "0.1"),
        ],
    );
    check("icosahedron", &mesh, &p, true);
}

/// Building on an affinely mapped mesh equals mapping the surface.
#[test]
fn affine_invariance() {
    let a = DMat3::from_cols(
        DVec3::new(1.3, 0.2, -0.1),
        DVec3::new(0.4, 0.9, 0.3),
        DVec3::new(-0.2, 0.1, 1.7),
    );
    let t = DVec3::new(0.5, -2.0, 3.0);
    let map = |p: DVec3| a * p + t;
    for (name, mesh) in closed_test_meshes() {
        let (mapped, _) = Mesh::from_triangles(
            mesh.positions().iter().map(|&p| map(p)).collect(),
            mesh.faces().to_vec(),
        )
        .expect("mapped mesh is valid");
        for p in [params(&SPEC, &[]), params(&SPEC, &[("free", "zero-twist")])] {
            let s0 = build(&mesh, &p).expect("builds");
            let s1 = build(&mapped, &p).expect("builds");
            let scale = mapped.bounds().diagonal();
            for (p0, p1) in s0.patches.iter().zip(&s1.patches) {
                let (b0, b1) = (p0.as_bezier().unwrap(), p1.as_bezier().unwrap());
                for (x, y) in b0.points().iter().zip(b1.points()) {
                    let d = (map(*x) - *y).length() / scale;
                    assert!(d <= 1e-12, "{name}: affine defect {d}");
                }
            }
        }
    }
}

/// Moving one vertex changes only the patches of faces within its 2-ring.
#[test]
fn locality() {
    let mesh = mesh(generate::valence_fan(9).expect("valence in range"));
    let surface = build(&mesh, &params(&SPEC, &[])).expect("builds");
    for moved in [0u32, 3, 7] {
        let mut positions = mesh.positions().to_vec();
        positions[moved as usize] += DVec3::new(0.05, -0.02, 0.03);
        let (moved_mesh, _) = Mesh::from_triangles(positions, mesh.faces().to_vec()).unwrap();
        let changed = build(&moved_mesh, &params(&SPEC, &[])).expect("builds");
        // Vertices within distance 2 of the moved one; faces touching them form the 2-ring.
        let ring1 = mesh.one_ring(moved);
        let in_two_ring = |f: &[u32; 3]| f.iter().any(|v| *v == moved || ring1.contains(v));
        let mut changed_inside = 0;
        for (p0, p1) in surface.patches.iter().zip(&changed.patches) {
            let face = mesh.faces()[p0.face as usize];
            if !in_two_ring(&face) {
                assert_eq!(p0, p1, "face {} outside the 2-ring changed", p0.face);
            } else if p0 != p1 {
                changed_inside += 1;
            }
        }
        assert!(changed_inside > 0, "moving vertex {moved} changed nothing");
    }
}

#[test]
fn non_positive_beta_is_a_typed_error_naming_beta() {
    for beta in ["0", "-0.5"] {
        let err = shape_params(&params(&SPEC, &[("beta", beta)])).unwrap_err();
        assert!(
            matches!(&err, Error::BadParam { name, .. } if name == "beta"),
            "beta = {beta}: {err}"
        );
    }
}
