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

/// `mesh` with every edge sharp whose faces turn by more than `degrees` (`--crease-angle`).
pub fn creased(mesh: &Mesh, degrees: f64) -> Mesh {
    let options = crate::mesh::LoadOptions {
        crease_angle: Some(degrees),
        ..crate::mesh::LoadOptions::default()
    };
    Mesh::from_triangles_with(mesh.positions().to_vec(), mesh.faces().to_vec(), &options)
        .expect("valid mesh")
        .0
}

/// The vertices of `mesh` by kind of sharp edges met: `[corners (3 or more sharp edges,
/// interior), darts (1, interior), boundary vertices with a sharp edge]`.
pub fn sharp_vertex_kinds(mesh: &Mesh) -> [usize; 3] {
    let mut kinds = [0; 3];
    for v in 0..mesh.vertex_count() as u32 {
        match (mesh.is_boundary_vertex(v), mesh.sharp_valence(v)) {
            (false, 3..) => kinds[0] += 1,
            (false, 1) => kinds[1] += 1,
            (true, 1..) => kinds[2] += 1,
            _ => {}
        }
    }
    kinds
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

/// Open meshes (with boundaries) for the schemes that take them: the lifted hexagonal disk, the
/// unit hemisphere, a cylinder open at both ends, the scanned bunny with its base cut open
/// (`scenes/bunny-open.obj`, boundary valences 2 to 8), half fans whose centre is a boundary
/// vertex of valence 2..=8 (their ends are corners of valence 2) and wheels whose centre is an
/// interior vertex of valence 3..=12 with every neighbour on the boundary.
pub fn open_test_meshes() -> Vec<(String, Mesh)> {
    let mut out = vec![
        ("disk-3".to_string(), mesh(generate::disk(3))),
        ("hemisphere".to_string(), mesh(generate::hemisphere(9, 4))),
        (
            "open-cylinder".to_string(),
            mesh(generate::open_cylinder(10, 3)),
        ),
        ("bunny-open".to_string(), open_bunny()),
    ];
    for n in 2..=8 {
        out.push((format!("half-fan-{n}"), mesh(generate::half_fan(n))));
    }
    for m in 3..=12 {
        out.push((format!("wheel-{m}"), mesh(generate::wheel(m))));
    }
    out
}

/// The one warning of `surface` that contains `fragment` (panics unless there is exactly
/// one).
pub fn the_warning<'a>(surface: &'a crate::surface::Surface, fragment: &str) -> &'a str {
    let warned: Vec<&String> = surface
        .warnings
        .iter()
        .filter(|w| w.contains(fragment))
        .collect();
    assert_eq!(warned.len(), 1, "'{fragment}' in {:?}", surface.warnings);
    warned[0]
}

/// The scene `name` as a mesh: a generated one of [`crate::mesh::generate::SCENES`] or a
/// scanned one of [`crate::mesh::generate::SCANNED_SCENES`] (`scenes/<name>.obj`).
pub fn scene(name: &str) -> Mesh {
    use crate::mesh::generate::{SCANNED_SCENES, SCENES};
    match SCENES.iter().find(|s| s.name == name) {
        Some(generated) => generated.mesh(),
        None => SCANNED_SCENES
            .iter()
            .find(|s| s.name == name)
            .expect("scene exists")
            .mesh(),
    }
    .expect("valid")
}

/// `scenes/bunny-open.obj`: the scanned bunny with its base cut open.
pub fn open_bunny() -> Mesh {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/bunny-open.obj");
    Mesh::load_obj(&path)
        .expect("scenes/bunny-open.obj loads")
        .0
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

/// The largest defect of Farin's `C^order` conditions between the Bézier pieces of one face
/// that share a domain edge (Farin, CAGD §17.5): every control point of one piece within
/// `order` rows of the shared edge must equal the other piece's blossom at that point's
/// multi-index, the pieces' corners written in the other piece's barycentric coordinates.
/// Absolute (in the surface's units); 0 when no face has two Bézier pieces with a common edge.
///
/// This reads the control nets only, through the patches' face-barycentric domains, so it
/// checks a scheme's fill rules independently of how the scheme indexes its nets.
pub fn max_smoothness_defect_inside_faces(surface: &crate::surface::Surface, order: usize) -> f64 {
    use glam::{DMat3, DVec3};
    let mut by_face: std::collections::BTreeMap<u32, Vec<&crate::surface::Patch>> =
        Default::default();
    for patch in &surface.patches {
        by_face.entry(patch.face).or_default().push(patch);
    }
    let mut worst: f64 = 0.0;
    for pieces in by_face.values() {
        for a in pieces {
            for b in pieces {
                let (Some(net_a), Some(net_b)) = (a.as_bezier(), b.as_bezier()) else {
                    continue;
                };
                if std::ptr::eq(*a, *b) || net_a.degree() != net_b.degree() {
                    continue;
                }
                // b's corners shared with a, and the one that is not.
                let shared: Vec<usize> = (0..3)
                    .filter(|&c| a.domain.contains(&b.domain[c]))
                    .collect();
                if shared.len() != 2 {
                    continue;
                }
                let free = 3 - shared[0] - shared[1];
                let to_a = DMat3::from_cols(a.domain[0], a.domain[1], a.domain[2]).inverse();
                let corners: [DVec3; 3] = b.domain.map(|x| to_a * x);
                let d = net_b.degree();
                for i in 0..=d {
                    for j in 0..=d - i {
                        let weights = [i, j, d - i - j];
                        if weights[free] > order {
                            continue;
                        }
                        let args: Vec<DVec3> = (0..3)
                            .flat_map(|c| std::iter::repeat_n(corners[c], weights[c]))
                            .collect();
                        let defect = (net_b.point(i, j) - net_a.blossom(&args)).length();
                        worst = worst.max(defect);
                    }
                }
            }
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::max_smoothness_defect_inside_faces;
    use crate::bezier::TriangleBezier;
    use crate::surface::{Patch, PatchGeometry, Surface};
    use crate::testing::Rng;

    /// One random quintic over a face, cut into the pieces of a 4-split: the pieces of one
    /// polynomial are C^∞, so every order has no defect; moving one control point of the
    /// middle piece `r` rows from an edge breaks exactly the orders ≥ `r`.
    #[test]
    fn the_defect_is_zero_for_one_polynomial_and_sees_a_moved_point() {
        let mut rng = Rng::new(17);
        let whole = TriangleBezier::from_fn(5, |_, _, _| {
            DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64())
        });
        // The 4-split of the face: three corner triangles and the middle one.
        let a = crate::surface::WHOLE_FACE;
        let m = |k: usize, l: usize| 0.5 * (a[k] + a[l]);
        let domains = [
            [a[0], m(0, 1), m(2, 0)],
            [a[1], m(1, 2), m(0, 1)],
            [a[2], m(2, 0), m(1, 2)],
            [m(1, 2), m(2, 0), m(0, 1)],
        ];
        let piece = |domain: [DVec3; 3]| {
            TriangleBezier::from_fn(5, |i, j, k| {
                let args: Vec<DVec3> = [(domain[0], i), (domain[1], j), (domain[2], k)]
                    .iter()
                    .flat_map(|&(x, n)| std::iter::repeat_n(x, n))
                    .collect();
                whole.blossom(&args)
            })
        };
        let surface_of = |nets: Vec<TriangleBezier>| Surface {
            scheme: "test".into(),
            warnings: Vec::new(),
            spike_face_pairs: Vec::new(),
            params: vec![],
            patches: nets
                .into_iter()
                .zip(domains)
                .enumerate()
                .map(|(p, (net, domain))| Patch {
                    face: 0,
                    piece: p as u8,
                    domain,
                    geometry: PatchGeometry::Bezier(net),
                })
                .collect(),
        };
        let nets: Vec<TriangleBezier> = domains.iter().map(|&d| piece(d)).collect();
        let exact = surface_of(nets.clone());
        for order in 0..=5 {
            let defect = max_smoothness_defect_inside_faces(&exact, order);
            assert!(defect <= 1e-14, "order {order}: {defect}");
        }
        // The middle piece's b(2,2,1) is 1 row from its edge opposite corner 2 and 2 rows
        // from the other two edges.
        let mut moved = nets;
        let p = moved[3].point(2, 2);
        moved[3].set_point(2, 2, p + DVec3::new(1e-6, 0.0, 0.0));
        let moved = surface_of(moved);
        assert!(max_smoothness_defect_inside_faces(&moved, 0) <= 1e-14);
        let c1 = max_smoothness_defect_inside_faces(&moved, 1);
        assert!((c1 - 1e-6).abs() <= 1e-12, "C1 defect {c1}");
    }
}
