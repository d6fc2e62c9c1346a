//! Measured properties of Piper's surface: G¹ between faces and C¹ (hence G¹) between the
//! three pieces of a face on closed meshes, open meshes and meshes with holes; vertex
//! positions and normals reproduced; planes reproduced; the size dependence of the thesis's
//! edge scaling; typed errors on degenerate data.

use glam::DVec3;

use super::*;
use crate::mesh::{NormalSource, generate};
use crate::metrics::{Metrics, normal_angle};
use crate::surface::UV_CORNERS;
use crate::testing::{self, JointFigures, Rng, assert_g1_joints, closed_test_meshes, mesh};

fn params(pairs: &[(&str, &str)]) -> Params {
    testing::params(&SPEC, pairs)
}

/// The mesh with some faces removed, each removed face sharing no vertex with another, so
/// every hole is a triangle and every vertex stays manifold (a fan with one gap).
fn with_holes(mesh: &Mesh, every: usize) -> Mesh {
    let mut used = vec![false; mesh.vertex_count()];
    let mut kept = Vec::new();
    for (f, face) in mesh.faces().iter().enumerate() {
        if f % every == 0 && face.iter().all(|&v| !used[v as usize]) {
            face.iter().for_each(|&v| used[v as usize] = true);
        } else {
            kept.push(*face);
        }
    }
    let (holed, _) = Mesh::from_triangles(mesh.positions().to_vec(), kept).expect("still valid");
    assert!(!holed.is_closed());
    holed
}

/// Closed scenes, closed meshes with a vertex of each valence 3..=16, and open meshes: lifted
/// hexagonal disks and scenes with triangular holes.
fn test_meshes() -> Vec<(String, Mesh)> {
    let mut out = closed_test_meshes();
    for rings in [1, 2, 4] {
        out.push((format!("disk-{rings} (open)"), mesh(generate::disk(rings))));
    }
    for name in ["torus", "genus2", "deformed-icosahedron", "mixed-valence"] {
        let closed = testing::scene(name);
        out.push((format!("{name} with holes (open)"), with_holes(&closed, 5)));
    }
    out
}

/// The hexagonal disk of `rings` rings pressed flat into the plane z = 0.
fn flat_disk(rings: u32) -> Mesh {
    let (positions, faces) = generate::disk(rings);
    let flat = positions
        .iter()
        .map(|p| DVec3::new(p.x, p.y, 0.0))
        .collect();
    mesh((flat, faces))
}

/// Largest angle between the patch normal at a vertex corner and the vertex normal.
fn vertex_normal_error(mesh: &Mesh, surface: &Surface, normals: &[DVec3]) -> f64 {
    surface
        .vertex_corners(mesh.faces())
        .iter()
        .map(|vc| {
            let uv = UV_CORNERS[vc.corner as usize];
            let jet = surface.patches[vc.patch as usize].jet(uv.x, uv.y);
            normal_angle(jet.normal(), normals[vc.vertex as usize])
        })
        .fold(0.0, f64::max)
}

/// Builds, measures, prints the figures and asserts the acceptance bounds.
fn check(name: &str, mesh: &Mesh, p: &Params) -> Metrics {
    let surface = build(mesh, p).expect("piper builds");
    assert_eq!(surface.patches.len(), 3 * mesh.face_count(), "{name}");
    let m = Metrics::measure(&surface, mesh, 0.0);
    let interior_edges = mesh.edges().iter().filter(|e| e.faces.1.is_some()).count();
    assert_eq!(
        m.joints_between_faces, interior_edges,
        "{name}: joints between faces"
    );
    assert_eq!(m.joints - m.joints_between_faces, 3 * mesh.face_count());
    assert_eq!(m.singular_samples, 0, "{name}: singular joint samples");
    let normals = mesh
        .vertex_normals(p.normal_source().expect("valid"))
        .expect("normals");
    let normal_error = vertex_normal_error(mesh, &surface, &normals);
    let label = format!("{name} {:?}", p.values());
    let JointFigures {
        gap,
        between,
        inside,
    } = assert_g1_joints(&m, &label);
    let interp = m.interp_max_rel.expect("corners");
    eprintln!(
        "{label}: normal jump between faces {between:.1e} rad, inside faces {inside:.1e} rad, \
         G0 gap {gap:.1e}, interpolation {interp:.1e}, vertex normals {normal_error:.1e} rad"
    );
    assert!(interp <= 1e-12, "interpolation error {interp} on {label}");
    assert!(
        normal_error <= crate::tolerance::NORMAL_RAD,
        "vertex normal off by {normal_error} rad on {label}"
    );
    m
}

#[test]
fn g1_between_and_inside_faces_with_every_scaling() {
    for (name, mesh) in test_meshes() {
        for scaling in ["farin", "circle", "relative", "thesis"] {
            check(&name, &mesh, &params(&[("scaling", scaling)]));
        }
    }
}

/// The icosphere and a torus sampled from the analytic surfaces, with the exact normals read
/// from the OBJ's `vn` records (`normals=obj`): the normals are reproduced, joins are G¹.
#[test]
fn g1_with_the_obj_normals_of_analytic_surfaces() {
    let sphere = generate::analytic::sphere(2);
    let torus = generate::analytic::torus(12, 8, 1.0, 0.4);
    for (name, sampled) in [("sphere-2", sphere), ("torus-12x8", torus)] {
        let mut obj = String::new();
        for (p, n) in sampled.positions.iter().zip(&sampled.normals) {
            obj += &format!("v {} {} {}\nvn {} {} {}\n", p.x, p.y, p.z, n.x, n.y, n.z);
        }
        for f in &sampled.faces {
            let [a, b, c] = f.map(|v| v + 1);
            obj += &format!("f {a}//{a} {b}//{b} {c}//{c}\n");
        }
        let (mesh, _) = Mesh::parse_obj(&obj).expect("valid OBJ");
        let file_normals = mesh.vertex_normals(NormalSource::Obj).expect("has normals");
        for (n, exact) in file_normals.iter().zip(&sampled.normals) {
            assert!(normal_angle(*n, *exact) <= 1e-12);
        }
        check(name, &mesh, &params(&[("normals", "obj")]));
        check(name, &mesh, &params(&[("normals", "estimate")]));
    }
}

/// A flat mesh with the plane's normal everywhere gives the plane itself; with Farin's
/// scaling even the parametrisation is the linear one (linear precision).
#[test]
fn planes_are_reproduced() {
    let mesh = flat_disk(3);
    for scaling in ["farin", "circle", "relative", "thesis"] {
        let surface = build(&mesh, &params(&[("scaling", scaling)])).expect("builds");
        let mut worst_off_plane: f64 = 0.0;
        let mut worst_linear: f64 = 0.0;
        for patch in &surface.patches {
            let corners = mesh.faces()[patch.face as usize].map(|v| mesh.positions()[v as usize]);
            for (u, v) in [(0.2, 0.3), (0.6, 0.1), (0.1, 0.8), (1.0 / 3.0, 1.0 / 3.0)] {
                let point = patch.eval(u, v);
                worst_off_plane = worst_off_plane.max(point.z.abs());
                let [d0, d1, d2] = patch.domain;
                let w = (1.0 - u - v) * d0 + u * d1 + v * d2;
                let linear = w.x * corners[0] + w.y * corners[1] + w.z * corners[2];
                worst_linear = worst_linear.max((point - linear).length());
            }
        }
        eprintln!(
            "plane, scaling={scaling}: off plane {worst_off_plane:.1e}, off the linear map {worst_linear:.1e}"
        );
        assert!(worst_off_plane <= 1e-15, "{scaling}: {worst_off_plane}");
        if scaling == "farin" || scaling == "circle" {
            assert!(worst_linear <= 1e-14, "linear precision: {worst_linear}");
        }
    }
}

/// Scaling the mesh by 10 scales Farin's and the relative surface by 10 (to rounding), but
/// changes the shape of the thesis's surface: its edge factor depends on absolute lengths.
#[test]
fn thesis_scaling_depends_on_the_mesh_size_the_default_does_not() {
    let original = generate::SCENES[3].mesh().expect("deformed icosahedron");
    assert_eq!(generate::SCENES[3].name, "deformed-icosahedron");
    let factor = 10.0;
    let (scaled, _) = Mesh::from_triangles(
        original.positions().iter().map(|p| factor * *p).collect(),
        original.faces().to_vec(),
    )
    .expect("valid");
    let diag = scaled.bounds().diagonal();
    for (scaling, invariant) in [
        ("farin", true),
        ("circle", true),
        ("relative", true),
        ("thesis", false),
    ] {
        let p = params(&[("scaling", scaling)]);
        let (small, big) = (build(&original, &p).unwrap(), build(&scaled, &p).unwrap());
        let defect = small
            .patches
            .iter()
            .zip(&big.patches)
            .flat_map(|(a, b)| {
                let (a, b) = (a.as_bezier().unwrap(), b.as_bezier().unwrap());
                a.control_points()
                    .zip(b.control_points())
                    .map(|(x, y)| (factor * x - y).length())
            })
            .fold(0.0, f64::max)
            / diag;
        eprintln!("scaling={scaling}: ‖10·S(mesh) − S(10·mesh)‖ / diag = {defect:.2e}");
        if invariant {
            assert!(
                defect <= 1e-12,
                "{scaling} is not scale invariant: {defect}"
            );
        } else {
            assert!(
                defect >= 1e-3,
                "thesis scaling unexpectedly invariant: {defect}"
            );
        }
    }
}

/// A vertex normal along an edge leaves that edge no tangent direction: a typed error naming
/// the edge, not a panic or NaN.
#[test]
fn normal_along_an_edge_is_a_typed_error() {
    let (positions, faces) = generate::octahedron();
    let mut obj = String::new();
    for p in &positions {
        obj += &format!("v {} {} {}\n", p.x, p.y, p.z);
    }
    // Vertex 0's normal points at vertex 2 (along the edge 0–2 of a face).
    let (a, b) = (positions[0], positions[2]);
    let along = (b - a).normalize();
    for (i, p) in positions.iter().enumerate() {
        let n = if i == 0 { along } else { *p };
        obj += &format!("vn {} {} {}\n", n.x, n.y, n.z);
    }
    for f in &faces {
        let [x, y, z] = f.map(|v| v + 1);
        obj += &format!("f {x}//{x} {y}//{y} {z}//{z}\n");
    }
    let (mesh, _) = Mesh::parse_obj(&obj).expect("valid OBJ");
    match build(&mesh, &params(&[("normals", "obj")])) {
        Err(Error::DegenerateEdge { a: 0, .. }) => {}
        other => panic!("expected a degenerate edge at vertex 0, got {other:?}"),
    }
}

/// The parallel construction gives the same surface every time.
#[test]
fn deterministic() {
    let mesh = generate::SCENES[5].mesh().expect("mixed valence");
    let a = build(&mesh, &params(&[])).unwrap();
    let b = build(&mesh, &params(&[])).unwrap();
    assert_eq!(a.patches, b.patches);
}

/// The mesh with the given per-vertex normals, as read from an OBJ's `vn` records.
fn with_obj_normals(mesh: &Mesh, normals: &[DVec3]) -> Mesh {
    let mut obj = String::new();
    for (p, n) in mesh.positions().iter().zip(normals) {
        obj += &format!("v {} {} {}\nvn {} {} {}\n", p.x, p.y, p.z, n.x, n.y, n.z);
    }
    for f in mesh.faces() {
        let [a, b, c] = f.map(|v| v + 1);
        obj += &format!("f {a}//{a} {b}//{b} {c}//{c}\n");
    }
    Mesh::parse_obj(&obj).expect("valid OBJ").0
}

/// Normals far from the estimate (each tilted by up to about 40° in a pseudo-random
/// direction, halved until it is at most about 75° from every incident face's normal):
/// the construction still joins G¹ everywhere and reproduces the given normals.
///
/// A normal at more than 90° from an incident face's normal turns that face's corner inside
/// out (the projected edges swap order), and the surface folds there; the measure then sees
/// a normal jump of π (same tangent plane, opposite orientation). That is bad input, not a
/// G¹ defect, so the tilt keeps `n · face normal ≥ 0.25`.
#[test]
fn g1_with_tilted_normals() {
    let mut lcg = Rng::new(0x9e37_79b9);
    let mut random = move || lcg.next_f64() - 0.5;
    for (name, mesh) in test_meshes() {
        let estimate = mesh
            .vertex_normals(NormalSource::Estimate)
            .expect("normals");
        let mut worst_tilt: f64 = 0.0;
        let tilted: Vec<DVec3> = estimate
            .iter()
            .enumerate()
            .map(|(v, n)| {
                let mut push = 0.9 * DVec3::new(random(), random(), random());
                for _ in 0..20 {
                    let candidate = (*n + push).normalize();
                    let consistent = mesh
                        .ring_faces(v as u32)
                        .iter()
                        .all(|&f| candidate.dot(mesh.face_normal(f)) >= 0.25);
                    if consistent {
                        worst_tilt = worst_tilt.max(normal_angle(candidate, *n));
                        return candidate;
                    }
                    push *= 0.5;
                }
                // Even the estimate is that close to a face's plane here: keep it.
                *n
            })
            .collect();
        let tilted_mesh = with_obj_normals(&mesh, &tilted);
        check(
            &format!(
                "{name}, normals tilted up to {:.0}°",
                worst_tilt.to_degrees()
            ),
            &tilted_mesh,
            &params(&[("normals", "obj")]),
        );
    }
}

/// How many shared edges take the thesis's dependent-rows branch of the G¹ solve.
fn dependent_row_edges(mesh: &Mesh) -> (usize, usize) {
    let construction = candidates(mesh, &params(&[])).expect("valid");
    let (mut dependent, mut shared) = (0, 0);
    for f in 0..mesh.face_count() {
        for k in 0..3 {
            let Some((g, kg)) = mesh.neighbor(f as u32, k) else {
                continue;
            };
            if (g as usize) < f {
                continue;
            }
            let to_p = construction.origin(g as usize) - construction.origin(f);
            let (qp, qq) = construction.edge_quartics((f, k), (g as usize, kg), to_p);
            let net = edge_net(&qp, &qq, to_p);
            let (w1, w2) = g1_solve::end_weights(&net);
            let x = g1_solve::solve_edge(&net, w1.unwrap(), w2.unwrap());
            shared += 1;
            dependent += x.dependent_rows as usize;
        }
    }
    (dependent, shared)
}

/// The dependent-rows branch: taken where the weights at the two ends of an edge agree,
/// e.g. on a flat equilateral lattice (a mirror swaps the ends, and the point next to each
/// vertex projects onto the middle of the edge's first leg). The surface there is G¹ and
/// planar like everywhere else (checked in `planes_are_reproduced`); the counts on the scenes
/// are printed.
#[test]
fn dependent_rows_occur_on_a_flat_lattice() {
    let mesh = flat_disk(3);
    let (dependent, shared) = dependent_row_edges(&mesh);
    eprintln!("flat disk-3: {dependent} of {shared} edges with dependent rows");
    assert_eq!(dependent, shared);
    check("flat disk-3", &mesh, &params(&[]));
    for scene in &generate::SCENES {
        let (dependent, shared) = dependent_row_edges(&scene.mesh().expect("valid"));
        eprintln!(
            "{}: {dependent} of {shared} edges with dependent rows",
            scene.name
        );
    }
}

/// Moving one vertex (keeping every normal) changes only the faces around it and the faces
/// across their edges [Piper87 §3.8, Fig. 22].
#[test]
fn locality() {
    let sampled = generate::analytic::sphere(1);
    let (base, _) =
        Mesh::from_triangles(sampled.positions.clone(), sampled.faces.clone()).expect("valid");
    let mesh = with_obj_normals(&base, &sampled.normals);
    let p = params(&[("normals", "obj")]);
    let surface = build(&mesh, &p).expect("builds");
    for moved in [0u32, 17, 30] {
        let mut positions = mesh.positions().to_vec();
        positions[moved as usize] += DVec3::new(0.03, -0.02, 0.01);
        let (moved_base, _) = Mesh::from_triangles(positions, mesh.faces().to_vec()).unwrap();
        let moved_mesh = with_obj_normals(&moved_base, &sampled.normals);
        let changed = build(&moved_mesh, &p).expect("builds");
        let touches = |f: usize| mesh.faces()[f].contains(&moved);
        let affected = |f: usize| {
            touches(f)
                || (0..3).any(|k| {
                    mesh.neighbor(f as u32, k)
                        .is_some_and(|(g, _)| touches(g as usize))
                })
        };
        let mut changed_faces = std::collections::BTreeSet::new();
        for (a, b) in surface.patches.iter().zip(&changed.patches) {
            if a != b {
                changed_faces.insert(a.face as usize);
                assert!(affected(a.face as usize), "face {} changed", a.face);
            }
        }
        let expected = (0..mesh.face_count()).filter(|&f| affected(f)).count();
        assert_eq!(changed_faces.len(), expected, "vertex {moved}");
    }
}

/// The smallest open meshes: one triangle (no shared edge, only the C¹ restoration inside)
/// and two triangles (one shared edge).
#[test]
fn one_and_two_triangles() {
    let p = vec![
        DVec3::ZERO,
        DVec3::X,
        DVec3::new(0.3, 0.9, 0.2),
        DVec3::new(1.1, 0.8, -0.3),
    ];
    let one = Mesh::from_triangles(p[..3].to_vec(), vec![[0, 1, 2]])
        .expect("valid")
        .0;
    let two = Mesh::from_triangles(p, vec![[0, 1, 2], [1, 3, 2]])
        .expect("valid")
        .0;
    let m = check("one triangle", &one, &params(&[]));
    assert_eq!(m.joints_between_faces, 0);
    let m = check("two triangles", &two, &params(&[]));
    assert_eq!(m.joints_between_faces, 1);
}

/// Shape, not only smoothness: on icospheres with the sphere's own normals the surface stays
/// close to the unit sphere, and closer with finer meshes. Printed for every edge rule;
/// asserted for the rules with a third of the chord on flat data (fourth order).
#[test]
fn approximates_the_sphere() {
    for scaling in ["farin", "circle", "relative", "thesis"] {
        let mut errors = Vec::new();
        for level in 1..=3 {
            let sampled = generate::analytic::sphere(level);
            let (base, _) = Mesh::from_triangles(sampled.positions.clone(), sampled.faces.clone())
                .expect("valid");
            let mesh = with_obj_normals(&base, &sampled.normals);
            let p = params(&[("normals", "obj"), ("scaling", scaling)]);
            let surface = build(&mesh, &p).expect("builds");
            let mut worst: f64 = 0.0;
            for patch in &surface.patches {
                for i in 0..=6 {
                    for j in 0..=6 - i {
                        let p = patch.eval(i as f64 / 6.0, j as f64 / 6.0);
                        worst = worst.max((p.length() - 1.0).abs());
                    }
                }
            }
            errors.push(worst);
        }
        let shown: Vec<String> = errors.iter().map(|e| format!("{e:.2e}")).collect();
        eprintln!("scaling={scaling}: largest |‖S‖ − 1| on icospheres 1..3: {shown:?}");
        if scaling == "farin" || scaling == "circle" {
            assert!(errors[1] < errors[0] / 8.0 && errors[2] < errors[1] / 8.0);
            assert!(errors[2] <= 1e-5, "{scaling}: {errors:?}");
        }
    }
}

/// The creased test meshes on which Piper's surface folds (G¹ = π between faces): the crease
/// line n₀ × n₁ of two nearly coplanar sectors can swing far from the mesh edge it stands for.
/// The edge points projected onto it then turn a face's corner over, Piper's end weights go
/// negative and the tangent planes agree with opposite orientations. Corner sectors take the
/// plane of their sharp edges ([`Mesh::corner_normals`]), and so do the two sectors of a
/// crease that turns back at a vertex (a hairpin), which keeps the crease lines on the edges
/// there; what is left is the scan creased at 35°, whose crease lines zig-zag through crease
/// vertices (74 fold samples with the circle scaling, 101 before hairpins were taken in their
/// edges' plane; at 20° 32 then, and none now). Measured, not claimed away:
/// the metrics count the folds, and creases are meant for CAD parts, not scans.
const FOLDS_WHEN_CREASED: [(&str, f64); 1] = [("bunny-open", 35.0)];

/// On every closed and open test mesh with the edges above 20° and 35° sharp (corners,
/// darts, creases ending at boundaries): G0 across the sharp joints (one boundary curve, bit
/// for bit), G¹ across every other joint between faces, C¹ inside faces, the vertices
/// interpolated and each patch corner tangent to its sector's normal. Every kind of vertex is
/// met. The meshes of [`FOLDS_WHEN_CREASED`] fold instead, and say so.
#[test]
fn creased_meshes_are_g0_across_sharp_edges_and_g1_elsewhere() {
    let (mut corners, mut darts, mut on_boundary) = (0, 0, 0);
    let meshes = closed_test_meshes()
        .into_iter()
        .chain(testing::open_test_meshes());
    for (name, mesh) in meshes {
        for degrees in [20.0, 35.0] {
            let mesh = testing::creased(&mesh, degrees);
            if mesh.sharp_edges().is_empty() {
                continue;
            }
            let [c, d, b] = testing::sharp_vertex_kinds(&mesh);
            (corners, darts, on_boundary) = (corners + c, darts + d, on_boundary + b);
            for scaling in ["circle", "farin"] {
                let p = params(&[("scaling", scaling)]);
                let label = format!("{name} at {degrees}° {scaling}");
                let surface = build(&mesh, &p).unwrap_or_else(|e| panic!("{label}: {e}"));
                let m = Metrics::measure(&surface, &mesh, 0.0);
                assert_eq!(m.singular_samples, 0, "{label}");
                // Both faces build the crease's curve from the same data, each in its own
                // frame (offsets from its first corner): the copies agree to an ulp.
                let sharp_gap = m.sharp_g0_max_rel.expect("sharp joints measured");
                assert!(sharp_gap <= f64::EPSILON, "{label}: sharp G0 {sharp_gap:e}");
                let gap = m.g0_max_rel.expect("joints measured");
                let between = m.g1_between_faces_max_rad.unwrap_or(0.0);
                let inside = m.g1_inside_faces_max_rad.expect("pieces measured");
                assert!(gap <= crate::tolerance::POSITION_REL, "{label}: G0 {gap}");
                let known_fold = FOLDS_WHEN_CREASED.contains(&(name.as_str(), degrees));
                assert_eq!(
                    between > crate::tolerance::NORMAL_RAD,
                    known_fold,
                    "{label}: G1 {between} (FOLDS_WHEN_CREASED lists the meshes that fold)"
                );
                assert!(
                    inside <= crate::tolerance::NORMAL_RAD,
                    "{label}: C1 {inside}"
                );
                let interpolation = m.interp_max_rel.expect("vertices measured");
                assert!(interpolation <= 1e-12, "{label}: {interpolation}");
                let (front, _) =
                    crate::schemes::scheme_normals(&mesh, &p, SPEC.name, AtFoldedVertex::Refuse)
                        .expect("normals");
                let corner_normals = mesh.corner_normals(&front);
                // A face that is a sector of its own between the two sharp edges of a crease
                // through the vertex has both its edges there along the one crease line: its
                // corner opens by 180° and the patch's normal there is left to rounding.
                let (mut straight_corners, mut turned_corners) = (0, 0);
                let mut worst_corner = 0.0f64;
                for vc in surface.vertex_corners(mesh.faces()) {
                    let patch = &surface.patches[vc.patch as usize];
                    let uv = UV_CORNERS[vc.corner as usize];
                    let jet = patch.jet(uv.x, uv.y);
                    let face = mesh.faces()[patch.face as usize];
                    let c = face.iter().position(|&x| x == vc.vertex).expect("corner");
                    let own_sector = mesh.is_sharp(patch.face, c)
                        && mesh.is_sharp(patch.face, (c + 2) % 3)
                        && mesh.sharp_valence(vc.vertex) == 2;
                    if own_sector {
                        straight_corners += 1;
                        continue;
                    }
                    let sector_normal = corner_normals[patch.face as usize][c];
                    let angle = normal_angle(jet.normal(), sector_normal);
                    if angle > std::f64::consts::FRAC_PI_2 {
                        // Tangent to the sector's plane, but turned over (a fold).
                        turned_corners += 1;
                    } else {
                        worst_corner = worst_corner.max(angle);
                    }
                }
                assert!(
                    worst_corner <= crate::tolerance::NORMAL_RAD,
                    "{label}: corner normal off its sector's by {worst_corner} rad"
                );
                // The fold is the turned-over corner, and it is reported to the user.
                assert_eq!(turned_corners > 0, known_fold, "{label}: {turned_corners}");
                // Straight corners (a sector of one face between two sharp edges in line, on
                // the hemisphere and the scan) are singular points: their normal is rounding
                // and no fold.
                assert_eq!(m.folds > 0, known_fold, "{label}: folds {}", m.folds);
                if scaling == "circle" {
                    eprintln!(
                        "{label}: {} sharp joints, G1 {between:.1e} rad, C1 {inside:.1e} rad, \
                         corners {worst_corner:.1e} rad ({straight_corners} straight, \
                         {turned_corners} turned over), folds {}",
                        m.sharp_joints, m.folds
                    );
                }
            }
        }
    }
    assert!(
        corners > 0 && darts > 0 && on_boundary > 0,
        "corners {corners}, darts {darts}, on the boundary {on_boundary}"
    );
}

/// Legs that swerve across their face's far edge are shortened ([`swerving_legs`]): the
/// mixed-valence scene's 14.65° fans around its valence-15 and -16 vertices, whose vertex
/// normals lean 54° off the thin faces, folded on 49 samples of the metrics grid with the
/// circle scaling and fold on none now, G¹ as before. The rule fires there and nowhere on the
/// regular meshes (the icosahedron and the octahedron keep the thesis's legs).
#[test]
fn swerving_legs_are_shortened_so_thin_fans_do_not_fold() {
    let swerving = |mesh: &Mesh| {
        let normals = mesh.corner_normals(
            &mesh
                .vertex_normals(NormalSource::Estimate)
                .expect("normals"),
        );
        (0..mesh.face_count())
            .map(|f| {
                swerving_legs(mesh, &normals, f)
                    .iter()
                    .flatten()
                    .filter(|&&s| s)
                    .count()
            })
            .sum::<usize>()
    };
    let mixed = testing::scene("mixed-valence");
    assert!(swerving(&mixed) > 0, "the rule fires on the thin fans");
    for scaling in ["circle", "farin", "relative", "thesis"] {
        let m = check("mixed-valence", &mixed, &params(&[("scaling", scaling)]));
        assert_eq!(m.folds, 0, "mixed-valence, scaling {scaling}");
    }
    for regular in [mesh(generate::icosahedron()), mesh(generate::octahedron())] {
        assert_eq!(swerving(&regular), 0);
    }
}
