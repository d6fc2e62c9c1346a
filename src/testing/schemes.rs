//! The meshes every scheme is measured on, parameter helpers and the acceptance bounds of a
//! G¹ surface.

use crate::mesh::{Mesh, generate};
use crate::metrics::Metrics;
use crate::schemes::{Params, SchemeSpec};
use crate::tolerance::{NORMAL_RAD, POSITION_REL};

/// A validated mesh from generated triangles.
pub fn mesh((positions, faces): generate::Triangles) -> Mesh {
    Mesh::from_triangles(positions, faces)
        .expect("generated mesh is valid")
        .0
}

/// The closed scenes of scenes/ and a closed mesh with a vertex of each valence 3..=16.
pub fn closed_test_meshes() -> Vec<(String, Mesh)> {
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

/// `spec`'s parameters with the given overrides.
pub fn params(spec: &SchemeSpec, pairs: &[(&str, &str)]) -> Params {
    let user: Vec<(String, String)> = pairs
        .iter()
        .map(|(n, v)| (n.to_string(), v.to_string()))
        .collect();
    Params::resolve(spec, &user).expect("valid parameters")
}

/// The joint figures of a G¹ surface: G0 gap (relative to the diagonal) and the largest normal
/// jumps between faces and inside faces (rad).
#[derive(Clone, Copy, Debug)]
pub struct JointFigures {
    /// Largest G0 gap.
    pub gap: f64,
    /// Largest normal jump across mesh edges (0 with no interior edge).
    pub between: f64,
    /// Largest normal jump between the pieces of a face.
    pub inside: f64,
}

/// Asserts that the measured surface is G¹ up to round-off, between faces and between the
/// pieces of each face: G0 gap ≤ [`POSITION_REL`], normal jumps ≤ [`NORMAL_RAD`]. Returns the
/// figures.
pub fn assert_g1_joints(m: &Metrics, label: &str) -> JointFigures {
    let figures = JointFigures {
        gap: m.g0_max_rel.expect("joints measured"),
        between: m.g1_between_faces_max_rad.unwrap_or(0.0),
        inside: m.g1_inside_faces_max_rad.expect("several pieces per face"),
    };
    let JointFigures {
        gap,
        between,
        inside,
    } = figures;
    assert!(gap <= POSITION_REL, "G0 gap {gap} on {label}");
    assert!(
        between <= NORMAL_RAD,
        "normal jump between faces {between} rad on {label}"
    );
    assert!(
        inside <= NORMAL_RAD,
        "normal jump inside faces {inside} rad on {label}"
    );
    figures
}

/// Accuracy of a scheme on the unit icosphere of 80 faces (vertices on the unit sphere):
/// `[radial distance, normal error (rad), min |H|, max |H| at the mesh vertices]` of the
/// surface `build` makes.
pub fn unit_icosphere_accuracy(
    build: impl Fn(&Mesh) -> crate::Result<crate::surface::Surface>,
) -> [f64; 4] {
    use crate::report::analytic::{Analytic, surface_error, vertex_curvature_error};
    let sampled = generate::analytic::sphere(1);
    let mesh = mesh((sampled.positions, sampled.faces));
    let sphere = Analytic::Sphere { radius: 1.0 };
    let surface = build(&mesh).expect("builds on the icosphere");
    let (distance, _, normal) = surface_error(&surface, &sphere);
    let (_, h_min, h_max) = vertex_curvature_error(&surface, mesh.faces(), &sphere);
    [distance, normal, h_min, h_max]
}
