//! Measured properties of the HB00 surface on many meshes: patch count, vertex interpolation,
//! G0 and tangent-plane continuity between faces (G¹) and inside faces (C¹), twist
//! compatibility, affine invariance and locality.

use glam::{DMat3, DVec3};

use super::*;
use crate::mesh::generate;
use crate::surface::{Joint, edge_uv};

/// Worst G0 gap (relative to the bbox diagonal) and normal jumps (rad) between faces and inside
/// faces, sampled at 33 points along every joint.
struct Continuity {
    gap: f64,
    between_faces: f64,
    inside_faces: f64,
}

fn continuity(mesh: &Mesh, surface: &Surface) -> Continuity {
    let diag = mesh.bounds().diagonal();
    let mut c = Continuity {
        gap: 0.0,
        between_faces: 0.0,
        inside_faces: 0.0,
    };
    let joints: Vec<Joint> = surface.joints(mesh.faces());
    // Every mesh edge is covered by two half-edge joints, every face has three inner edges.
    let between = joints.iter().filter(|j| j.between_faces).count();
    assert_eq!(between, 2 * mesh.edges().len(), "joints between faces");
    assert_eq!(
        joints.len() - between,
        3 * mesh.face_count(),
        "joints inside faces"
    );
    for j in &joints {
        let (pa, pb) = (
            &surface.patches[j.a.patch as usize],
            &surface.patches[j.b.patch as usize],
        );
        for step in 0..=32 {
            let s = step as f64 / 32.0;
            let sb = if j.reversed { 1.0 - s } else { s };
            let (ua, ub) = (
                edge_uv(j.a.edge as usize, s),
                edge_uv(j.b.edge as usize, sb),
            );
            let (ja, jb) = (pa.jet(ua.x, ua.y), pb.jet(ub.x, ub.y));
            c.gap = c.gap.max((ja.p - jb.p).length() / diag);
            let (na, nb) = (ja.normal(), jb.normal());
            let angle = na.cross(nb).length().atan2(na.dot(nb));
            if j.between_faces {
                c.between_faces = c.between_faces.max(angle);
            } else {
                c.inside_faces = c.inside_faces.max(angle);
            }
        }
    }
    c
}

fn interpolation_error(mesh: &Mesh, surface: &Surface) -> f64 {
    let diag = mesh.bounds().diagonal();
    surface
        .vertex_corners(mesh.faces())
        .iter()
        .map(|vc| {
            let uv = crate::surface::UV_CORNERS[vc.corner as usize];
            let p = surface.patches[vc.patch as usize].eval(uv.x, uv.y);
            (p - mesh.positions()[vc.vertex as usize]).length() / diag
        })
        .fold(0.0, f64::max)
}

fn params(pairs: &[(&str, &str)]) -> Params {
    let user: Vec<(String, String)> = pairs
        .iter()
        .map(|(n, v)| (n.to_string(), v.to_string()))
        .collect();
    Params::resolve(&SPEC, &user).expect("valid parameters")
}

fn mesh((positions, faces): generate::Triangles) -> Mesh {
    Mesh::from_triangles(positions, faces)
        .expect("generated mesh is valid")
        .0
}

/// The closed scenes and a closed mesh with a vertex of each valence 3..=16.
fn test_meshes() -> Vec<(String, Mesh)> {
    let mut out: Vec<(String, Mesh)> = generate::SCENES
        .iter()
        .map(|s| (s.name.to_string(), s.mesh().expect("scene mesh is valid")))
        .collect();
    for n in 3..=16 {
        let fan = generate::valence_fan(n).expect("valence in range");
        out.push((format!("valence-fan-{n}"), mesh(fan)));
    }
    out
}

fn check(mesh_name: &str, mesh: &Mesh, p: &Params, interpolates: bool) {
    let surface = build(mesh, p).expect("hb builds on a closed mesh");
    assert_eq!(surface.patches.len(), 4 * mesh.face_count(), "{mesh_name}");
    let c = continuity(mesh, &surface);
    let label = format!("{mesh_name} {:?}", p.values());
    assert!(c.gap <= 1e-12, "G0 gap {} on {label}", c.gap);
    assert!(
        c.between_faces <= 1e-9,
        "normal jump between faces {} rad on {label}",
        c.between_faces
    );
    assert!(
        c.inside_faces <= 1e-9,
        "normal jump inside faces {} rad on {label}",
        c.inside_faces
    );
    eprintln!(
        "{label}: gap {:.1e}, normal jump between faces {:.1e} rad, inside {:.1e} rad",
        c.gap, c.between_faces, c.inside_faces
    );
    if interpolates {
        let e = interpolation_error(mesh, &surface);
        assert!(e <= 1e-12, "interpolation error {e} on {label}");
    }
    let mismatch = max_corner_mismatch(mesh, p).expect("params ok") / mesh.bounds().diagonal();
    assert!(mismatch <= 1e-12, "twist mismatch {mismatch} on {label}");
}

#[test]
fn g1_between_faces_c1_inside_and_interpolation_with_default_parameters() {
    for (name, mesh) in test_meshes() {
        check(&name, &mesh, &params(&[]), true);
        check(&name, &mesh, &params(&[("free", "zero-twist")]), true);
    }
}

#[test]
fn g1_with_random_shape_parameters() {
    let mut state = 0x5eed_u64;
    let mut rnd = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    for (name, mesh) in test_meshes() {
        for _ in 0..3 {
            let beta = format!("{}", 0.05 + 0.6 * rnd());
            let g0 = format!("{}", -4.0 + 6.0 * rnd());
            let g1 = format!("{}", -1.0 + 5.0 * rnd());
            let alpha = format!("{}", 0.5 + 0.5 * rnd());
            let p = params(&[
                ("beta", &beta),
                ("gamma0", &g0),
                ("gamma1", &g1),
                ("alpha", &alpha),
            ]);
            check(&name, &mesh, &p, false);
        }
    }
}

/// HB00 Fig. 14's parameters on the icosahedron.
#[test]
fn g1_with_the_figure_14_parameters() {
    let mesh = mesh(generate::icosahedron());
    let p = params(&[
        ("beta", "0.1"),
        ("gamma0", "-3.7"),
        ("gamma1", "4.6"),
        ("gamma2", "0.1"),
    ]);
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
    for (name, mesh) in test_meshes() {
        let (mapped, _) = Mesh::from_triangles(
            mesh.positions().iter().map(|&p| map(p)).collect(),
            mesh.faces().to_vec(),
        )
        .expect("mapped mesh is valid");
        for p in [params(&[]), params(&[("free", "zero-twist")])] {
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
    let surface = build(&mesh, &params(&[])).expect("builds");
    for moved in [0u32, 3, 7] {
        let mut positions = mesh.positions().to_vec();
        positions[moved as usize] += DVec3::new(0.05, -0.02, 0.03);
        let (moved_mesh, _) = Mesh::from_triangles(positions, mesh.faces().to_vec()).unwrap();
        let changed = build(&moved_mesh, &params(&[])).expect("builds");
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
