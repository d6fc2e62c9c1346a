//! Sharp edges end to end: the CAD-like parts of scenes/ built with `--crease-angle 40` by
//! every scheme that keeps creases (G0 across them, the scheme's continuity elsewhere, flat
//! faces flat), the schemes that cannot refusing by name, darts, the sharp edges an OBJ file
//! marks (smoothing groups, per-corner normals), and the command line and its JSON.

mod common;

use std::path::{Path, PathBuf};

use glam::DVec3;
use smoothlab::mesh::{LoadOptions, Mesh};
use smoothlab::metrics::Metrics;
use smoothlab::schemes::{self, SCHEMES, SharpEdgeSupport};

/// Rounding-level bound on lengths, relative to the bounding-box diagonal.
const LENGTH_REL: f64 = 1e-9;
/// Rounding-level bound on angles (rad).
const ANGLE_RAD: f64 = 1e-9;

fn scene(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(format!("{name}.obj"))
}

fn crease(degrees: f64) -> LoadOptions {
    LoadOptions {
        crease_angle: Some(degrees),
        ..LoadOptions::default()
    }
}

fn load(name: &str, degrees: f64) -> Mesh {
    Mesh::load_with(&scene(name), &crease(degrees))
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .0
}

/// Schemes documented as G1 (flat and pn are C0 by design).
fn claims_g1(scheme: &str) -> bool {
    !matches!(scheme, "flat" | "pn")
}

fn builders() -> impl Iterator<Item = &'static str> {
    SCHEMES
        .iter()
        .filter(|s| s.sharp_edges == SharpEdgeSupport::Builds)
        .map(|s| s.name)
}

/// The largest distance of a patch of a flat face from the face's plane, the largest angle
/// between its normal and the face's, and the largest normal component of its second
/// derivatives (relative to the diagonal): 0 to rounding on a patch that stays flat (no
/// curvature, so zebra stripes cross it straight: its normal, hence its stripe, is constant).
fn flatness(
    surface: &smoothlab::surface::Surface,
    mesh: &Mesh,
    flat: &dyn Fn(u32) -> bool,
) -> [f64; 3] {
    let diag = mesh.bounds().diagonal();
    let mut worst = [0.0f64; 3];
    for patch in surface.patches.iter().filter(|p| flat(p.face)) {
        let n = mesh.face_normal(patch.face);
        let p0 = mesh.positions()[mesh.faces()[patch.face as usize][0] as usize];
        for i in 0..=8 {
            for j in 0..=8 - i {
                // Corners left out: a blend's weights have no derivatives there.
                if matches!((i, j), (0, 0) | (8, 0) | (0, 8)) {
                    continue;
                }
                let (u, v) = (f64::from(i) / 8.0, f64::from(j) / 8.0);
                let jet = patch.jet(u, v);
                let normal = jet.du.cross(jet.dv);
                let angle = normal.cross(n).length().atan2(normal.dot(n));
                let bend = [jet.duu, jet.duv, jet.dvv]
                    .iter()
                    .map(|d| d.dot(n).abs())
                    .fold(0.0, f64::max);
                worst[0] = worst[0].max((jet.p - p0).dot(n).abs() / diag);
                worst[1] = worst[1].max(angle);
                worst[2] = worst[2].max(bend / diag);
            }
        }
    }
    worst
}

/// Joints between faces per interior mesh edge: 1, or 2 for a scheme that splits faces at
/// their edges' midpoints (hb's 4-split).
fn joints_per_edge(m: &Metrics, mesh: &Mesh) -> usize {
    let interior = mesh.edges().iter().filter(|e| e.faces.1.is_some()).count();
    let per_edge = m.joints_between_faces / interior;
    assert!(
        per_edge * interior == m.joints_between_faces && (1..=2).contains(&per_edge),
        "{} joints between faces over {interior} edges",
        m.joints_between_faces
    );
    per_edge
}

/// A face of the capped cylinder lies on a cap when all its corners do (z = ±1).
fn on_a_cap(mesh: &Mesh) -> impl Fn(u32) -> bool + '_ {
    |f| {
        mesh.faces()[f as usize]
            .iter()
            .all(|&v| (mesh.positions()[v as usize].z.abs() - 1.0).abs() < 1e-15)
    }
}

#[test]
fn cad_parts_keep_their_creases_sharp_and_their_faces_flat() {
    for name in ["l-block", "capped-cylinder"] {
        let mesh = load(name, 40.0);
        let expected_sharp = if name == "l-block" { 44 } else { 32 };
        assert_eq!(mesh.sharp_edges().count(), expected_sharp, "{name}");
        let every_face = |_: u32| true;
        let cap = on_a_cap(&mesh);
        let flat: &dyn Fn(u32) -> bool = if name == "l-block" { &every_face } else { &cap };
        let mut built = Vec::new();
        for scheme in builders() {
            let (surface, frame, ms) = schemes::build_timed_in_frame(scheme, &mesh, &[])
                .unwrap_or_else(|e| panic!("{name}/{scheme}: {e}"));
            let m = Metrics::measure_in_frame(&surface, &frame, &mesh, ms);
            let user = surface.mapped(|q| frame.to_user(q));
            let [offset, tilt, bend] = flatness(&user, &mesh, flat);
            println!(
                "{name}/{scheme}: sharp joints {}, G0 sharp {:?}, G1 smooth {:?}, flat faces: \
                 offset {offset:.1e}, normal {tilt:.1e} rad, bend {bend:.1e}, folds {}",
                m.sharp_joints, m.sharp_g0_max_rel, m.g1_max_rad, m.folds
            );
            assert_eq!(
                m.sharp_joints,
                expected_sharp * joints_per_edge(&m, &mesh),
                "{name}/{scheme}"
            );
            assert!(
                m.sharp_g0_max_rel.expect("sharp joints") <= LENGTH_REL,
                "{name}/{scheme}: G0 across creases {:?}",
                m.sharp_g0_max_rel
            );
            // The creases stay creases: about 90° across every sharp joint.
            assert!(
                m.sharp_g1_max_rad.expect("sharp joints") > 1.5,
                "{name}/{scheme}"
            );
            if claims_g1(scheme) {
                assert!(
                    m.g1_max_rad.expect("smooth joints") <= ANGLE_RAD,
                    "{name}/{scheme}: G1 over smooth joints {:?}",
                    m.g1_max_rad
                );
            }
            assert_eq!(m.folds, 0, "{name}/{scheme}");
            assert!(
                offset <= LENGTH_REL && tilt <= ANGLE_RAD && bend <= LENGTH_REL,
                "{name}/{scheme}: a flat face is no longer flat: offset {offset:e}, normal \
                 {tilt:e} rad, bend {bend:e}"
            );
            built.push(scheme);
        }
        assert_eq!(
            built,
            [
                "flat",
                "pn",
                "hb",
                "loop94",
                "piper",
                "nielson",
                "fang-mann"
            ],
            "{name}"
        );
    }
}

#[test]
fn without_a_crease_angle_the_g1_schemes_round_the_creases() {
    // The papers' surfaces: no sharp edge, and flat faces bend near the creases.
    let mesh = Mesh::load(&scene("l-block")).expect("l-block").0;
    assert!(mesh.sharp_edges().is_empty());
    let surface = schemes::build("nielson", &mesh, &[]).expect("nielson");
    let [offset, _, _] = flatness(&surface, &mesh, &|_| true);
    assert!(offset > 1e-3, "offset {offset:e}");
}

#[test]
fn schemes_without_crease_rules_refuse_naming_why() {
    let mesh = load("l-block", 40.0);
    for spec in SCHEMES {
        if let SharpEdgeSupport::Refuses(reason) = spec.sharp_edges {
            let error = schemes::build(spec.name, &mesh, &[]).expect_err(spec.name);
            let text = error.to_string();
            assert!(
                text.contains(spec.name) && text.contains(reason) && text.contains("44"),
                "{text}"
            );
        }
    }
}

#[test]
fn crease_detection_and_g0_do_not_depend_on_scale_or_position() {
    let (positions, faces) = smoothlab::mesh::generate::l_block();
    for (scale, shift) in [(1e-30, 0.0), (1.0, 1e8), (1e30, -1e31)] {
        let moved: Vec<DVec3> = positions
            .iter()
            .map(|&p| p * scale + DVec3::splat(shift))
            .collect();
        let (mesh, _) =
            Mesh::from_triangles_with(moved, faces.clone(), &crease(40.0)).expect("valid");
        assert_eq!(
            mesh.sharp_edges().count(),
            44,
            "scale {scale} shift {shift}"
        );
        let (surface, frame, _) =
            schemes::build_timed_in_frame("fang-mann", &mesh, &[]).expect("fang-mann");
        let m = Metrics::measure_in_frame(&surface, &frame, &mesh, 0.0);
        assert!(m.sharp_g0_max_rel.unwrap() <= LENGTH_REL, "{scale} {shift}");
        assert!(m.g1_max_rad.unwrap() <= ANGLE_RAD, "{scale} {shift}");
    }
}

/// A 5×5-vertex grid over [−2, 2]² on the paraboloid z = (x² + y²)/10, as OBJ text whose
/// centre vertex (0, 0) has one normal in the faces left of x = 0 and another in those right
/// of it: the file marks the two edges from (0, −1) to (0, 0) to (0, 1) sharp, and (0, ±1)
/// are darts (one sharp edge each).
fn dart_grid_obj() -> String {
    let mut text = String::new();
    let id = |i: i32, j: i32| (i + 2) * 5 + (j + 2) + 1;
    for i in -2..=2 {
        for j in -2..=2 {
            let (x, y) = (f64::from(i), f64::from(j));
            text += &format!("v {x} {y} {}\n", (x * x + y * y) / 10.0);
        }
    }
    text += "vn 0 0 1\nvn -0.2 0 1\nvn 0.2 0 1\n";
    let corner = |i: i32, j: i32, left: bool| {
        let normal = if (i, j) == (0, 0) {
            if left { 2 } else { 3 }
        } else {
            1
        };
        format!("{}//{normal}", id(i, j))
    };
    for i in -2..2 {
        for j in -2..2 {
            let left = i < 0;
            let quad = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
            for tri in [[0, 1, 2], [0, 2, 3]] {
                let c: Vec<String> = tri
                    .iter()
                    .map(|&k| corner(quad[k].0, quad[k].1, left))
                    .collect();
                text += &format!("f {}\n", c.join(" "));
            }
        }
    }
    text
}

#[test]
fn per_corner_normals_mark_sharp_edges_and_darts_build() {
    let text = dart_grid_obj();
    let (plain, report) = Mesh::parse_obj(&text).expect("grid");
    assert!(plain.sharp_edges().is_empty());
    assert!(
        report
            .warnings
            .iter()
            .any(|w| w.contains("the file marks 2 edges sharp")),
        "{:?}",
        report.warnings
    );
    // 180°: only what the file marks.
    let (mesh, report) = Mesh::parse_obj_with(&text, &crease(180.0)).expect("grid");
    assert_eq!(mesh.sharp_edges().count(), 2);
    assert_eq!(report.sharp_edges, 2);
    let centre = 12;
    assert_eq!(mesh.sharp_valence(centre), 2);
    assert_eq!(mesh.sharp_valence(centre - 1), 1, "dart at (0, -1)");
    assert_eq!(mesh.sharp_valence(centre + 1), 1, "dart at (0, 1)");
    for scheme in builders() {
        let (surface, frame, _) = schemes::build_timed_in_frame(scheme, &mesh, &[])
            .unwrap_or_else(|e| panic!("{scheme}: {e}"));
        let m = Metrics::measure_in_frame(&surface, &frame, &mesh, 0.0);
        println!(
            "dart grid/{scheme}: sharp joints {}, G0 sharp {:?}, G1 smooth {:?}",
            m.sharp_joints, m.sharp_g0_max_rel, m.g1_max_rad
        );
        assert_eq!(m.sharp_joints, 2 * joints_per_edge(&m, &mesh), "{scheme}");
        assert!(m.sharp_g0_max_rel.unwrap() <= LENGTH_REL, "{scheme}");
        if claims_g1(scheme) {
            assert!(
                m.g1_max_rad.unwrap() <= ANGLE_RAD,
                "{scheme}: {:?}",
                m.g1_max_rad
            );
        }
    }
}

/// The cube of scenes/ as OBJ text with a smoothing-group record before each side's two
/// triangles (`groups[side]`), and optionally one normal per side on every corner.
fn cube_obj(groups: &[&str; 6], face_normals: bool) -> String {
    let (positions, faces) = smoothlab::mesh::generate::cube();
    let mut text = String::new();
    for p in &positions {
        text += &format!("v {} {} {}\n", p.x, p.y, p.z);
    }
    for (k, face) in faces.iter().enumerate() {
        if k % 2 == 0 {
            text += &format!("s {}\n", groups[k / 2]);
        }
        let [a, b, c] = face.map(|v| positions[v as usize]);
        let n = (b - a).cross(c - a).normalize();
        if face_normals {
            text += &format!("vn {} {} {}\n", n.x, n.y, n.z);
            let vn = k + 1;
            text += &format!(
                "f {}//{vn} {}//{vn} {}//{vn}\n",
                face[0] + 1,
                face[1] + 1,
                face[2] + 1
            );
        } else {
            text += &format!("f {} {} {}\n", face[0] + 1, face[1] + 1, face[2] + 1);
        }
    }
    text
}

#[test]
fn smoothing_groups_mark_the_edges_between_groups() {
    // One group per side: the 12 cube edges, not the 6 diagonals inside the sides.
    let sides = cube_obj(&["1", "2", "3", "4", "5", "6"], false);
    let (mesh, _) = Mesh::parse_obj_with(&sides, &crease(180.0)).expect("cube");
    assert_eq!(mesh.sharp_edges().count(), 12);
    assert_eq!(mesh.sharp_edges().from_file(), 12);
    // `s off` is a group of its own: three sides off, three in group 1 → the 6 edges
    // between an `off` side and a group-1 side.
    let halves = cube_obj(&["off", "off", "1", "1", "0", "1"], false);
    let (mesh, _) = Mesh::parse_obj_with(&halves, &crease(180.0)).expect("cube");
    let sides_of = [0, 0, 1, 1, 0, 1];
    let faces = mesh.faces();
    let expected = mesh
        .edges()
        .iter()
        .filter(|e| sides_of[e.faces.0 as usize / 2] != sides_of[e.faces.1.unwrap() as usize / 2])
        .count();
    assert_eq!(mesh.sharp_edges().count(), expected);
    assert!(expected > 0 && faces.len() == 12);
    // One group everywhere marks nothing.
    let one = cube_obj(&["1"; 6], false);
    let (mesh, report) = Mesh::parse_obj_with(&one, &crease(180.0)).expect("cube");
    assert!(mesh.sharp_edges().is_empty());
    assert_eq!(report.sharp_edges, 0);
    // A bad group is an error naming the line.
    let bad = one.replacen("s 1", "s smooth", 1);
    let error = Mesh::parse_obj(&bad).expect_err("bad group").to_string();
    assert!(
        error.contains("line") && error.contains("smoothing group 'smooth'"),
        "{error}"
    );
}

#[test]
fn per_face_normals_mark_every_cube_edge_and_repeated_normals_none() {
    let flat_shaded = cube_obj(&["1"; 6], true);
    let (mesh, _) = Mesh::parse_obj_with(&flat_shaded, &crease(180.0)).expect("cube");
    // Every edge's faces differ in normal except the diagonals (coplanar: same normal).
    assert_eq!(mesh.sharp_edges().count(), 12);
    // Normals that repeat one direction under different indices mark nothing.
    let (positions, faces) = smoothlab::mesh::generate::cube();
    let mut text = String::new();
    for p in &positions {
        text += &format!("v {} {} {}\n", p.x, p.y, p.z);
    }
    for (k, face) in faces.iter().enumerate() {
        for &v in face {
            let n = positions[v as usize].normalize();
            text += &format!("vn {} {} {}\n", n.x, n.y, n.z);
        }
        let base = 3 * k;
        text += &format!(
            "f {}//{} {}//{} {}//{}\n",
            face[0] + 1,
            base + 1,
            face[1] + 1,
            base + 2,
            face[2] + 1,
            base + 3
        );
    }
    let (mesh, _) = Mesh::parse_obj_with(&text, &crease(180.0)).expect("cube");
    assert!(mesh.sharp_edges().is_empty());
}

#[test]
fn the_command_line_takes_crease_angles_and_reports_sharp_joints() {
    let dir = common::scratch("sharp_edges", "cli");
    let json = dir.join("m.json");
    let out = common::smoothlab(&[
        "metrics",
        common::path_str(&scene("l-block")),
        "--scheme",
        "all",
        "--crease-angle",
        "40",
        "--json",
        common::path_str(&json),
    ]);
    assert!(out.status.success(), "{}", common::stderr(&out));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.lines().next().unwrap().contains("sharp"), "{stdout}");
    // Schemes without crease rules are skipped, named, in `all`.
    let stderr = common::stderr(&out);
    assert!(
        stderr.contains("skipped: scheme 'gk' cannot build sharp edges"),
        "{stderr}"
    );
    let value: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let rows = value.as_array().unwrap();
    assert_eq!(rows.len(), 7);
    for row in rows {
        // hb splits every face into four: two joints along each edge.
        let per_edge = if row["scheme"] == "hb" { 2 } else { 1 };
        assert_eq!(row["sharp_joints"], 44 * per_edge, "{row}");
        assert!(
            row["sharp_g0_max_rel"].as_f64().unwrap() <= LENGTH_REL,
            "{row}"
        );
        assert!(row["sharp_g1_max_rad"].as_f64().unwrap() > 1.5, "{row}");
    }
    for bad in ["-1", "181", "nan", "x"] {
        let out = common::smoothlab(&[
            "metrics",
            common::path_str(&scene("l-block")),
            "--scheme",
            "pn",
            "--crease-angle",
            bad,
        ]);
        assert!(!out.status.success(), "{bad}");
        assert!(
            common::stderr(&out).contains("crease"),
            "{bad}: {}",
            common::stderr(&out)
        );
    }
    let out = common::smoothlab(&[
        "metrics",
        common::path_str(&scene("l-block")),
        "--scheme",
        "gk",
        "--crease-angle",
        "40",
    ]);
    common::assert_fails_naming(&out, &["scheme 'gk' cannot build sharp edges", "44"]);
}

#[test]
fn scene_files_take_the_crease_angle_key() {
    let scene_text = format!(
        "mesh = {:?}\ncrease_angle = 40\n",
        scene("l-block").display().to_string()
    );
    let parsed = smoothlab::testing::app::SceneFile::parse(&scene_text).expect("scene");
    let options = parsed.load_options().expect("valid");
    assert_eq!(options.crease_angle, Some(40.0));
    let bad = smoothlab::testing::app::SceneFile::parse("crease_angle = 200").expect("parses");
    let error = bad.load_options().expect_err("out of range").to_string();
    assert!(error.starts_with("crease_angle: "), "{error}");
}
