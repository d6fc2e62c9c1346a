//! End-to-end tests of the `smoothlab` binary: every bad input gives exit code 1 and exactly
//! one `error: …` line naming the element at fault; good input writes the contracted files.

use std::path::{Path, PathBuf};
use std::process::Output;

use common::{assert_fails_naming, path_str, smoothlab, stderr};

mod common;

/// A fresh directory for one test's files.
fn scratch(test: &str) -> PathBuf {
    common::scratch("cli", test)
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write test file");
    path
}

/// A regular tetrahedron, consistently oriented (outward).
const TETRAHEDRON: &str = "\
v 1 1 1
v 1 -1 -1
v -1 1 -1
v -1 -1 1
f 1 2 3
f 1 4 2
f 1 3 4
f 2 4 3
";

fn metrics_of(dir: &Path, name: &str, obj: &str, extra: &[&str]) -> Output {
    let mesh = write(dir, name, obj);
    let mut args = vec!["metrics", mesh.to_str().expect("utf-8 path")];
    args.extend_from_slice(extra);
    smoothlab(&args)
}

#[test]
fn missing_file_names_the_path() {
    let dir = scratch("missing");
    let path = dir.join("no-such-mesh.obj");
    let out = smoothlab(&["metrics", path.to_str().expect("utf-8"), "--scheme", "flat"]);
    assert_fails_naming(&out, &["no-such-mesh.obj"]);
}

#[test]
fn malformed_obj_names_the_file() {
    let dir = scratch("malformed");
    let out = metrics_of(
        &dir,
        "bad.obj",
        "v 0 0 zero\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        &["--scheme", "flat"],
    );
    assert_fails_naming(&out, &["bad.obj"]);
}

#[test]
fn out_of_range_index_names_the_face() {
    let dir = scratch("range");
    let out = metrics_of(
        &dir,
        "range.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n",
        &["--scheme", "flat"],
    );
    assert_fails_naming(&out, &["face 0"]);
}

#[test]
fn nan_names_the_vertex() {
    let dir = scratch("nan");
    let out = metrics_of(
        &dir,
        "nan.obj",
        "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n",
        &["--scheme", "flat"],
    );
    assert_fails_naming(&out, &["vertex 1", "non-finite"]);
}

/// Fails unless `metrics --scheme flat` on `obj` succeeds with a `warning:` line containing
/// every fragment of `repaired`, and with `--strict` fails naming every fragment of `refused`.
fn assert_repaired_unless_strict(test: &str, obj: &str, repaired: &[&str], refused: &[&str]) {
    let dir = scratch(test);
    let out = metrics_of(&dir, "mesh.obj", obj, &["--scheme", "flat"]);
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert!(
        err.lines()
            .any(|l| l.starts_with("warning: ") && repaired.iter().all(|f| l.contains(f))),
        "{repaired:?} missing from: {err}"
    );
    let out = metrics_of(&dir, "mesh.obj", obj, &["--scheme", "flat", "--strict"]);
    let mut fragments = refused.to_vec();
    fragments.push("--strict");
    assert_fails_naming(&out, &fragments);
}

#[test]
fn degenerate_face_is_collapsed_unless_strict() {
    // Face 1 is a cap: vertex 3 lies on the edge (1, 2), nearer to vertex 2.
    let obj = "v 0 0 0\nv 2 0 0\nv 1.4 0 0\nv 1 1 0\nv 0.5 -1 0\nv 1.5 -1 0\n\
               f 1 2 4\nf 2 1 3\nf 3 1 5\nf 3 5 6\nf 2 3 6\n";
    assert_repaired_unless_strict(
        "degenerate",
        obj,
        &[
            "collapsed 1 degenerate faces",
            "first: face 1",
            "vertex 2 is merged into vertex 1",
        ],
        &["face 1: zero area"],
    );
}

#[test]
fn duplicate_face_is_removed_unless_strict() {
    // The same triangle twice, with opposite orientation: every edge still has two faces.
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 3 2\n";
    assert_repaired_unless_strict(
        "duplicate",
        obj,
        &["removed 1 duplicate faces", "first: face 1: repeats face 0"],
        &["face 1: repeats face 0"],
    );
}

#[test]
fn non_manifold_edge_is_split_unless_strict() {
    // Three triangles on edge (0, 1), pointing in different directions.
    let obj = "v 0 0 0\nv 1 0 0\nv 0.5 1 0\nv 0.5 -1 0\nv 0.5 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n";
    assert_repaired_unless_strict(
        "nonmanifold-edge",
        obj,
        &[
            "split 1 non-manifold edges",
            "first: edge (0, 1): shared by 3 faces",
        ],
        &["edge (0, 1): shared by 3 faces"],
    );
}

#[test]
fn bow_tie_vertex_is_split_unless_strict() {
    // Two triangles touching only at vertex 0.
    let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv -1 0 0\nv -1 -1 0\nf 1 2 3\nf 1 4 5\n";
    assert_repaired_unless_strict(
        "bowtie",
        obj,
        &[
            "split 1 non-manifold vertices",
            "first: vertex 0: its faces form 2 separate fans",
        ],
        &["vertex 0: its faces form 2 separate fans"],
    );
}

#[test]
fn bent_and_concave_polygons_are_triangulated_unless_strict() {
    let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0.3\nv 0 1 0\nv 2 0 0\nv 2 1 0\nv 1.5 0.5 0\n\
               f 1 2 3 4\nf 2 5 7 6 3\n";
    assert_repaired_unless_strict(
        "polygons",
        obj,
        &[
            "triangulated 2 non-planar or non-convex faces",
            "first: face 0",
            "not planar",
        ],
        &["face 0: it has 4 corners and is not planar"],
    );
}

#[test]
fn flipped_octahedron_face_is_reoriented_outward_unless_strict() {
    let obj = "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n\
               f 1 3 5\nf 3 2 5\nf 2 4 5\nf 1 4 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n";
    assert_repaired_unless_strict(
        "flipped",
        obj,
        &["re-oriented 1 faces", "first: face 3"],
        &["face 3: it is oriented against its neighbours"],
    );
}

#[test]
fn faces_merged_by_welding_name_the_weld_and_the_flag() {
    // Issue row: the octahedron flattened to z × 1e-13; welding merges its two poles, which
    // makes each lower face repeat an upper one.
    let obj = "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1e-13\nv 0 0 -1e-13\n\
               f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n";
    assert_repaired_unless_strict(
        "weld-duplicates",
        obj,
        &[
            "removed 4 duplicate faces",
            "first: face 4: repeats face 0 after welding merged vertex 5 into vertex 4",
            "--weld-tolerance",
        ],
        &[
            "face 4: repeats face 0 after welding merged vertex 5 into vertex 4",
            "--weld-tolerance",
        ],
    );
}

#[test]
fn moebius_strip_is_cut_open_unless_strict() {
    // One-sided: the orientation fill meets one edge from both sides wanting opposite
    // orientations; that edge is cut open.
    let obj = smoothlab::mesh::generate::to_obj(&smoothlab::mesh::generate::bad::mobius_strip(8));
    assert_repaired_unless_strict(
        "moebius",
        &obj,
        &[
            "cut open 1 edges where the surface is not orientable",
            "first: edge (",
            "2 vertices of the cuts duplicated",
        ],
        &["edge (", "the mesh is not orientable"],
    );
    // The cut strip is an open disk: the repair is recorded in the JSON, and the G1 schemes
    // that take open meshes join their patches with G1 continuity across every interior edge.
    let dir = scratch("moebius-json");
    let mesh = write(&dir, "moebius.obj", &obj);
    let json = dir.join("m.json");
    let out = smoothlab(&[
        "metrics",
        path_str(&mesh),
        "--scheme",
        "all",
        "--json",
        path_str(&json),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = std::fs::read_to_string(&json).expect("metrics JSON");
    let value: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    for run in value.as_array().expect("one object per scheme") {
        assert_eq!(
            run["repairs"][0]["kind"], "non_orientable_edge_cut",
            "{text}"
        );
        assert_eq!(run["repairs"][0]["count"], 1, "{text}");
        if ["hb", "loop94", "piper"].contains(&run["scheme"].as_str().expect("scheme")) {
            let (g0, g1) = (&run["g0_max_rel"], &run["g1_max_rad"]);
            assert!(
                g0.as_f64().expect("g0") <= smoothlab::tolerance::POSITION_REL
                    && g1.as_f64().expect("g1") <= smoothlab::tolerance::NORMAL_RAD,
                "{}: G0 {g0}, G1 {g1}",
                run["scheme"]
            );
        }
    }
}

/// `metrics --explain` prints the table, then every column's meaning from docs/metrics.md.
#[test]
fn metrics_explain_follows_the_table_with_the_columns() {
    let dir = scratch("metrics-explain");
    let out = metrics_of(
        &dir,
        "tet.obj",
        TETRAHEDRON,
        &["--scheme", "pn", "--explain"],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8_lossy(&out.stdout);
    let (table, footer) = text
        .split_once("\ncolumns (docs/metrics.md):\n")
        .expect("footer");
    assert!(
        table.starts_with("scheme") && table.contains("\npn "),
        "{table}"
    );
    for column in [
        "interp (interp_max_rel)",
        "G^k (continuity_order",
        "flat_vtx (vertex_flat",
    ] {
        assert!(
            footer.contains(&format!("  {column}")),
            "{column}: {footer}"
        );
    }
    assert!(
        footer.contains("Why curv_jump saturates at 2.00."),
        "{footer}"
    );
}

/// On a terminal, a long step draws a spinner on standard error and clears it; `--quiet`
/// (before or after the command) draws none. The terminal is `script`'s pseudo-terminal
/// (util-linux); without `script` the test says so and checks nothing.
#[test]
fn progress_is_drawn_on_a_terminal_unless_quiet() {
    if std::process::Command::new("script")
        .arg("--version")
        .output()
        .is_err()
    {
        eprintln!("skipped: no `script` to give the command a terminal");
        return;
    }
    let dir = scratch("progress-terminal");
    let mesh = write(&dir, "tet.obj", TETRAHEDRON);
    let on_terminal = |args: &str| {
        let command = format!(
            "{} {args}",
            env!("CARGO_BIN_EXE_smoothlab").replace(' ', "\\ ")
        )
        .replace("MESH", path_str(&mesh));
        let out = std::process::Command::new("script")
            .args(["-qec", &command, "/dev/null"])
            .output()
            .expect("script runs");
        assert!(out.status.success(), "{command}: {}", stderr(&out));
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    let shown = on_terminal("metrics MESH --scheme hb");
    assert!(shown.contains("building hb on 4 faces"), "{shown}");
    assert!(shown.contains("measuring hb"), "{shown}");
    assert!(shown.contains(" 1/1 "), "the table row: {shown}");
    for quiet in [
        "--quiet metrics MESH --scheme hb",
        "metrics MESH --scheme hb --quiet",
    ] {
        let text = on_terminal(quiet);
        assert!(
            !text.contains("building") && !text.contains("measuring"),
            "{text}"
        );
        assert!(text.contains(" 1/1 "), "the table row: {text}");
    }
}

#[test]
fn open_mesh_is_refused_by_gk_by_name() {
    let dir = scratch("open-gk");
    let open: String = TETRAHEDRON
        .lines()
        .take(7)
        .map(|l| format!("{l}\n"))
        .collect();
    let out = metrics_of(&dir, "open.obj", &open, &["--scheme", "gk"]);
    assert_fails_naming(&out, &["'gk'", "boundary edge"]);
}

#[test]
fn unknown_scheme_lists_the_known_ones() {
    let dir = scratch("unknown-scheme");
    let out = metrics_of(&dir, "tet.obj", TETRAHEDRON, &["--scheme", "nurbs"]);
    assert_fails_naming(&out, &["'nurbs'", "flat", "pn", "hb"]);
}

#[test]
fn unknown_param_is_named() {
    let dir = scratch("unknown-param");
    let out = metrics_of(
        &dir,
        "tet.obj",
        TETRAHEDRON,
        &["--scheme", "pn", "--param", "tension=2"],
    );
    assert_fails_naming(&out, &["'tension'", "'pn'", "normals"]);
    let out = metrics_of(
        &dir,
        "tet.obj",
        TETRAHEDRON,
        &["--scheme", "all", "--param", "tension=2"],
    );
    assert_fails_naming(&out, &["'tension'"]);
}

#[test]
fn bad_param_value_is_named() {
    let dir = scratch("bad-param");
    let out = metrics_of(
        &dir,
        "tet.obj",
        TETRAHEDRON,
        &["--scheme", "pn", "--param", "normals=sideways"],
    );
    assert_fails_naming(&out, &["'normals'", "sideways"]);
    let out = metrics_of(
        &dir,
        "tet.obj",
        TETRAHEDRON,
        &["--scheme", "pn", "--param", "normals"],
    );
    assert_fails_naming(&out, &["name=value"]);
}

#[test]
fn bad_arguments_give_one_line() {
    let out = smoothlab(&[
        "export", "x.obj", "--scheme", "pn", "--format", "stl", "-o", "y",
    ]);
    assert_fails_naming(&out, &["stl"]);
}

#[test]
fn inconsistent_orientation_is_repaired_with_a_warning() {
    let dir = scratch("reorient");
    // The last face of the tetrahedron written the wrong way round.
    let flipped = TETRAHEDRON.replace("f 2 4 3", "f 2 3 4");
    let out = metrics_of(&dir, "flipped.obj", &flipped, &["--scheme", "flat"]);
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert!(err.lines().any(|l| l.starts_with("warning: ")), "{err}");
    // Re-oriented, the flat surface has the tetrahedron's dihedral kink (π − acos(1/3)) at
    // every edge, not an orientation flip of π.
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("1.91e0"), "{stdout}");
}

#[test]
fn metrics_json_has_the_contract_keys() {
    let dir = scratch("metrics-json");
    let json = dir.join("metrics.json");
    let out = metrics_of(
        &dir,
        "tet.obj",
        TETRAHEDRON,
        &["--scheme", "pn", "--json", json.to_str().expect("utf-8")],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let text = std::fs::read_to_string(&json).expect("metrics JSON written");
    let value: serde_json::Value = serde_json::from_str(&text).expect("valid JSON");
    let list = value.as_array().expect("a list, one object per scheme");
    assert_eq!(list.len(), 1);
    let m = &list[0];
    for key in smoothlab::metrics::CONTRACT_KEYS {
        assert!(m.get(key).is_some(), "missing key {key} in {m}");
    }
    assert_eq!(m["scheme"], "pn");
    assert_eq!(m["params"]["normals"], "estimate");
    assert_eq!(
        (m["faces"].as_u64(), m["patches"].as_u64()),
        (Some(4), Some(4))
    );
    // PN triangles are not G1: the metric sees it.
    assert!(m["g1_max_rad"].as_f64().expect("number") > 0.1, "{m}");
}

#[test]
fn all_on_an_open_mesh_skips_gk_with_a_warning() {
    let dir = scratch("all-open");
    let open: String = TETRAHEDRON
        .lines()
        .take(7)
        .map(|l| format!("{l}\n"))
        .collect();
    let json = dir.join("m.json");
    let out = metrics_of(
        &dir,
        "open.obj",
        &open,
        &["--scheme", "all", "--json", json.to_str().expect("utf-8")],
    );
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("warning: skipped") && err.contains("'gk'"),
        "{err}"
    );
    let value: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).expect("written")).expect("JSON");
    let names: Vec<&str> = value
        .as_array()
        .expect("list")
        .iter()
        .filter_map(|m| m["scheme"].as_str())
        .collect();
    // Every scheme that takes open meshes (all but gk), in registry order.
    let open_capable: Vec<&str> = smoothlab::schemes::SCHEMES
        .iter()
        .filter(|s| !s.needs_closed_mesh)
        .map(|s| s.name)
        .collect();
    assert_eq!(names, open_capable);
    assert_eq!(&names[..2], ["flat", "pn"]);
}

fn export(dir: &Path, format: &str, extra: &[&str]) -> (Output, PathBuf) {
    let mesh = write(dir, "tet.obj", TETRAHEDRON);
    let target = dir.join(format!("out.{format}"));
    let mut args = vec![
        "export",
        mesh.to_str().expect("utf-8"),
        "--scheme",
        "pn",
        "--format",
        format,
        "-o",
        target.to_str().expect("utf-8"),
    ];
    args.extend_from_slice(extra);
    (smoothlab(&args), target)
}

#[test]
fn export_writes_json_bv_and_obj() {
    let dir = scratch("export");
    let (out, path) = export(&dir, "json", &[]);
    assert!(out.status.success(), "{}", stderr(&out));
    let value: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).expect("json written")).expect("JSON");
    assert_eq!(value["format"], "smoothlab-patches");
    assert_eq!(value["scheme"], "pn");
    assert_eq!(value["patches"].as_array().map(Vec::len), Some(4));
    assert_eq!(value["patches"][0]["degree"], 3);

    let (out, path) = export(&dir, "bv", &[]);
    assert!(out.status.success(), "{}", stderr(&out));
    let bv = std::fs::read_to_string(path).expect("bv written");
    assert_eq!(bv.lines().count(), 4 * (1 + 10));
    assert_eq!(bv.lines().filter(|l| *l == "3 3").count(), 4);

    let (out, path) = export(&dir, "obj", &["--tess", "3"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let obj = std::fs::read_to_string(path).expect("obj written");
    // Welded: 4 corners, 2 more vertices on each of the 6 edges, 1 inside each face.
    assert_eq!(
        obj.lines().filter(|l| l.starts_with("v ")).count(),
        4 + 6 * 2 + 4
    );
    // pn takes each vertex's normal at the patch corners (one vn there) and is C0 across
    // edges (a vn per side at the 2 inner points of each edge), plus 1 per face inside.
    assert_eq!(
        obj.lines().filter(|l| l.starts_with("vn ")).count(),
        4 + 6 * 2 * 2 + 4
    );
    assert_eq!(obj.lines().filter(|l| l.starts_with("f ")).count(), 4 * 9);

    let (out, _) = export(&dir, "obj", &["--tess", "0"]);
    assert_fails_naming(&out, &["--tess"]);
}

#[test]
fn export_to_an_unwritable_path_names_it() {
    let dir = scratch("export-unwritable");
    let mesh = write(&dir, "tet.obj", TETRAHEDRON);
    let target = mesh.join("out.json");
    let out = smoothlab(&[
        "export",
        mesh.to_str().expect("utf-8"),
        "--scheme",
        "flat",
        "--format",
        "json",
        "-o",
        target.to_str().expect("utf-8"),
    ]);
    assert_fails_naming(&out, &["tet.obj: is not a folder"]);
}

/// Export errors name a patch's face as the file numbers its faces: here the file's face 0
/// repeats a corner and is removed on loading, so the surface's first patch lies on the
/// file's face 1.
#[test]
fn export_errors_name_the_face_the_file_wrote() {
    let dir = scratch("export-face-numbers");
    let mesh = write(
        &dir,
        "tet.obj",
        &TETRAHEDRON.replace("f 1 2 3", "f 1 1 2\nf 1 2 3"),
    );
    let target = dir.join("out.bv");
    let out = smoothlab(&[
        "export",
        mesh.to_str().expect("utf-8"),
        "--scheme",
        "nielson",
        "-o",
        target.to_str().expect("utf-8"),
    ]);
    assert_fails_naming(&out, &["patch 0 (face 1, piece 0) is not polynomial"]);
    assert!(!target.exists(), "nothing is written on an error");
}

/// `export` takes its format from `-o`'s extension when `--format` is not given, and every
/// command creates a missing output folder as `render -o` does.
#[test]
fn export_and_sample_infer_the_format_and_create_the_folder() {
    let dir = scratch("export-infer");
    let mesh = write(&dir, "tet.obj", TETRAHEDRON);
    let mesh = path_str(&mesh);
    for (name, first_line) in [("a/p.json", "{"), ("b/p.bv", "3 1"), ("c/p.obj", "#")] {
        let target = dir.join("new").join(name);
        let out = smoothlab(&["export", mesh, "--scheme", "flat", "-o", path_str(&target)]);
        assert!(out.status.success(), "{name}: {}", stderr(&out));
        let text = std::fs::read_to_string(&target).expect("written");
        assert!(
            text.starts_with(first_line),
            "{name}: {}",
            &text[..40.min(text.len())]
        );
    }
    let out = smoothlab(&[
        "export",
        mesh,
        "--scheme",
        "flat",
        "-o",
        path_str(&dir.join("p.stl")),
    ]);
    assert_fails_naming(
        &out,
        &["p.stl: the export format cannot be told", "--format"],
    );
    let samples = dir.join("new").join("d").join("s.json");
    let out = smoothlab(&[
        "sample",
        mesh,
        "--scheme",
        "flat",
        "--json",
        path_str(&samples),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(samples.is_file());
}

#[test]
fn schemes_lists_names_and_params() {
    let out = smoothlab(&["schemes"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    for name in [
        "flat:",
        "pn:",
        "hb:",
        "piper:",
        "normals=estimate",
        "scaling=circle",
    ] {
        assert!(text.contains(name), "{name} missing: {text}");
    }
}

#[test]
fn default_job_prints_every_scheme() {
    let out = smoothlab(&[]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("deformed icosahedron (20 faces)"), "{text}");
    for name in ["flat", "pn", "hb", "piper"] {
        assert!(
            text.lines().any(|l| l.starts_with(name)),
            "{name} row missing: {text}"
        );
    }
    // Each gallery cell's EXR (curvature values and the other channels) is beside its PNG.
    for name in ["hb-zebra", "hb-curvature", "gk-isophote"] {
        let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("out/gallery");
        for ext in ["png", "exr"] {
            let file = folder.join(format!("{name}.{ext}"));
            assert!(file.is_file(), "{} missing", file.display());
        }
    }
}

#[test]
fn all_on_a_closed_mesh_measures_every_scheme() {
    let dir = scratch("all-closed");
    let json = dir.join("m.json");
    let out = metrics_of(
        &dir,
        "tet.obj",
        TETRAHEDRON,
        &["--scheme", "all", "--json", json.to_str().expect("utf-8")],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let value: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).expect("written")).expect("JSON");
    let list = value.as_array().expect("list");
    let names: Vec<&str> = list.iter().filter_map(|m| m["scheme"].as_str()).collect();
    assert_eq!(names, smoothlab::schemes::names());
    assert_eq!(&names[..3], ["flat", "pn", "hb"]);
    // piper is G1 with 3 patches per face.
    let piper = &list[names
        .iter()
        .position(|n| *n == "piper")
        .expect("piper measured")];
    assert_eq!(piper["patches"], 12);
    assert!(
        piper["g1_max_rad"].as_f64().expect("number") <= 1e-9,
        "{piper}"
    );
    // hb is G1 (4 patches per face); pn is not.
    assert_eq!(list[2]["patches"], 16);
    assert!(
        list[2]["g1_max_rad"].as_f64().expect("number") <= 1e-9,
        "{}",
        list[2]
    );
    assert!(
        list[1]["g1_max_rad"].as_f64().expect("number") > 0.1,
        "{}",
        list[1]
    );
}

#[test]
fn pn_takes_the_file_normals_when_asked() {
    let dir = scratch("pn-obj-normals");
    // The tetrahedron's vertices are on a sphere about the origin: the sphere's normals.
    let with_normals = TETRAHEDRON
        .replace(
            "f 1 2 3",
            "vn 1 1 1\nvn 1 -1 -1\nvn -1 1 -1\nvn -1 -1 1\nf 1//1 2//2 3//3",
        )
        .replace("f 1 4 2", "f 1//1 4//4 2//2")
        .replace("f 1 3 4", "f 1//1 3//3 4//4")
        .replace("f 2 4 3", "f 2//2 4//4 3//3");
    let out = metrics_of(
        &dir,
        "tet-vn.obj",
        &with_normals,
        &["--scheme", "pn", "--param", "normals=obj"],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let out = metrics_of(
        &dir,
        "tet.obj",
        TETRAHEDRON,
        &["--scheme", "pn", "--param", "normals=obj"],
    );
    assert_fails_naming(&out, &["normals=obj"]);
}

/// Largest normal angle and point gap between the two sides over an edge-samples file, read
/// with nothing but serde_json and arithmetic.
fn sample_jumps(value: &serde_json::Value) -> (usize, f64, f64) {
    let xyz = |v: &serde_json::Value| -> [f64; 3] {
        let a = v.as_array().expect("xyz");
        [0, 1, 2].map(|i| a[i].as_f64().expect("number"))
    };
    let edges = value["edges"].as_array().expect("edges");
    let (mut angle, mut gap) = (0.0_f64, 0.0_f64);
    for edge in edges {
        let (s0, s1) = (
            edge["side0"].as_array().expect("side0"),
            edge["side1"].as_array().expect("side1"),
        );
        assert_eq!(s0.len(), s1.len(), "same points on both sides");
        assert_eq!(edge["faces"].as_array().map(Vec::len), Some(2));
        for (p, q) in s0.iter().zip(s1) {
            let (n0, n1) = (xyz(&p["normal"]), xyz(&q["normal"]));
            let cross = [
                n0[1] * n1[2] - n0[2] * n1[1],
                n0[2] * n1[0] - n0[0] * n1[2],
                n0[0] * n1[1] - n0[1] * n1[0],
            ];
            let sin = cross.iter().map(|c| c * c).sum::<f64>().sqrt();
            let cos: f64 = (0..3).map(|i| n0[i] * n1[i]).sum();
            angle = angle.max(sin.atan2(cos));
            let (a, b) = (xyz(&p["point"]), xyz(&q["point"]));
            gap = gap.max((0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt());
        }
    }
    (edges.len(), angle, gap)
}

#[test]
fn sample_writes_both_sides_of_every_edge() {
    let dir = scratch("sample");
    let cube = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cube.obj");
    let cube = cube.to_str().expect("utf-8");
    for (scheme, param, smooth) in [
        ("fang-mann", "t=2", true),
        ("nielson", "t=1", true),
        ("hb", "alpha=0.5", true),
        ("pn", "normals=estimate", false),
    ] {
        let json = dir.join(format!("{scheme}.json"));
        let json_arg = json.to_str().expect("utf-8");
        let out = smoothlab(&[
            "sample", cube, "--scheme", scheme, "--param", param, "--json", json_arg,
        ]);
        assert!(out.status.success(), "{scheme}: {}", stderr(&out));
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(stdout.contains("18 edges"), "{stdout}");
        let text = std::fs::read_to_string(&json).expect("samples written");
        let value: serde_json::Value = serde_json::from_str(&text).expect("JSON");
        let (edges, angle, gap) = sample_jumps(&value);
        println!("{scheme} {param}: {edges} edges, normal jump {angle:.2e} rad, gap {gap:.1e}");
        assert_eq!(edges, 18, "the cube's 12 triangles have 18 edges");
        assert!(gap <= 1e-12, "{scheme}: sides apart by {gap}");
        if smooth {
            assert!(angle <= 1e-9, "{scheme}: normal jump {angle} rad");
        } else {
            assert!(
                angle > 0.05,
                "{scheme}: pn must show its normal jump, got {angle}"
            );
        }
    }
    let out = smoothlab(&["sample", cube, "--scheme", "coons", "--json", "x.json"]);
    assert_fails_naming(&out, &["'coons'"]);
    let out = smoothlab(&[
        "sample",
        cube,
        "--scheme",
        "fang-mann",
        "--param",
        "t=9",
        "--json",
        "x.json",
    ]);
    assert_fails_naming(&out, &["'t'"]);
    let out = smoothlab(&["sample", cube, "--scheme", "pn"]);
    assert_fails_naming(&out, &["--json"]);
}

#[test]
fn piper_works_on_an_open_mesh_with_file_normals_and_thesis_scaling() {
    let dir = scratch("piper-open");
    // The tetrahedron less its last face, with the sphere's normals.
    let open = TETRAHEDRON
        .replace(
            "f 1 2 3",
            "vn 1 1 1\nvn 1 -1 -1\nvn -1 1 -1\nvn -1 -1 1\nf 1//1 2//2 3//3",
        )
        .replace("f 1 4 2", "f 1//1 4//4 2//2")
        .replace("f 1 3 4", "f 1//1 3//3 4//4")
        .replace("f 2 4 3", "");
    let json = dir.join("m.json");
    let out = metrics_of(
        &dir,
        "open-vn.obj",
        &open,
        &[
            "--scheme",
            "piper",
            "--param",
            "normals=obj",
            "--param",
            "scaling=thesis",
            "--json",
            json.to_str().expect("utf-8"),
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let value: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).expect("written")).expect("JSON");
    let m = &value[0];
    assert_eq!(m["patches"], 9, "{m}");
    assert_eq!(m["joints_between_faces"], 3, "three interior edges: {m}");
    assert_eq!(m["params"]["scaling"], "thesis");
    assert!(m["g1_max_rad"].as_f64().expect("number") <= 1e-9, "{m}");
    let out = metrics_of(
        &dir,
        "open-vn.obj",
        &open,
        &["--scheme", "piper", "--param", "scaling=cubic"],
    );
    assert_fails_naming(&out, &["scaling", "cubic"]);
}

/// `scenes/octahedron.obj` with every coordinate multiplied by `scale`, written into `dir`.
fn scaled_octahedron(dir: &Path, scale: f64) -> PathBuf {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/octahedron.obj"),
    )
    .expect("octahedron");
    let scaled: String = text
        .lines()
        .map(|line| match line.strip_prefix("v ") {
            Some(rest) => {
                let xyz: Vec<String> = rest
                    .split_whitespace()
                    .map(|x| (x.parse::<f64>().expect("number") * scale).to_string())
                    .collect();
                format!("v {}\n", xyz.join(" "))
            }
            None => format!("{line}\n"),
        })
        .collect();
    write(dir, &format!("octahedron-{scale:e}.obj"), &scaled)
}

/// Absurd scheme parameters make huge or non-finite surfaces: refused right after the
/// construction, naming the scheme and the parameters, by every command.
#[test]
fn absurd_parameters_are_refused_naming_them() {
    let dir = scratch("absurd_parameters");
    let mesh = scaled_octahedron(&dir, 1.0);
    let cases: [(&str, &[&str], &str); 3] = [
        ("hb", &["alpha=1e300"], "alpha=1e300"),
        (
            "hb",
            &["gamma0=1e150", "gamma1=-1e150"],
            "gamma0=1e150, gamma1=-1e150",
        ),
        (
            "hb",
            &["gamma0=1e300", "gamma1=-1e300"],
            "gamma0=1e300, gamma1=-1e300",
        ),
    ];
    // loop94's β is an upper limit, capped per vertex so that no boundary curve swerves off
    // its edge: even 1e300 builds the capped surface, G1 to rounding.
    let json = dir.join("loop94.json");
    let out = smoothlab(&[
        "metrics",
        path_str(&mesh),
        "--scheme",
        "loop94",
        "--param",
        "beta=1e300",
        "--json",
        path_str(&json),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = std::fs::read_to_string(&json).expect("metrics JSON");
    let value: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    let g1 = value[0]["g1_max_rad"].as_f64().expect("g1_max_rad");
    assert!(g1 <= 1e-9, "loop94 beta=1e300: G1 {g1} rad");
    let obj = dir.join("out.obj");
    let image = dir.join("img");
    for (scheme, params, named) in cases {
        let mut tail = vec!["--scheme", scheme];
        for p in params {
            tail.extend(["--param", p]);
        }
        let commands: [Vec<&str>; 3] = [
            vec!["metrics", path_str(&mesh)],
            vec![
                "export",
                path_str(&mesh),
                "--format",
                "obj",
                "-o",
                path_str(&obj),
            ],
            vec![
                "render",
                path_str(&mesh),
                "--mode",
                "curvature",
                "--size",
                "8x8",
                "-o",
                path_str(&image),
            ],
        ];
        for mut args in commands {
            args.extend(&tail);
            let out = smoothlab(&args);
            assert_fails_naming(
                &out,
                &[
                    &format!("scheme '{scheme}' with {named}"),
                    "unusable surface",
                    "mesh diagonals",
                ],
            );
        }
        assert!(!obj.exists(), "no OBJ written for {named}");
    }
    // A large but sane value still builds.
    let out = smoothlab(&[
        "metrics",
        path_str(&mesh),
        "--scheme",
        "hb",
        "--param",
        "alpha=2",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
}

/// The metrics JSON of `mesh` for every scheme, parsed.
fn metrics_json(dir: &Path, mesh: &Path) -> Vec<serde_json::Value> {
    let json = dir.join(format!(
        "{}.json",
        mesh.file_stem().unwrap().to_string_lossy()
    ));
    let out = smoothlab(&[
        "metrics",
        path_str(mesh),
        "--scheme",
        "all",
        "--json",
        path_str(&json),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = std::fs::read_to_string(&json).expect("metrics JSON");
    serde_json::from_str(&text).expect("JSON")
}

/// Metrics are scale-free: the octahedron scaled by 1e±20 and 1e±50 measures like the
/// unscaled one in every scheme (angles and relative lengths equal up to the rounding of the
/// scaled coordinates, continuity orders equal).
#[test]
fn metrics_do_not_depend_on_scale() {
    let dir = scratch("metrics_scale");
    let reference = metrics_json(&dir, &scaled_octahedron(&dir, 1.0));
    for scale in [1e20, 1e-20, 1e50, 1e-50] {
        let scaled = metrics_json(&dir, &scaled_octahedron(&dir, scale));
        assert_eq!(scaled.len(), reference.len());
        for (a, b) in reference.iter().zip(&scaled) {
            let scheme = &a["scheme"];
            for key in [
                "g1_max_rad",
                "g1_mean_rad",
                "g1_between_faces_max_rad",
                "interp_max_rel",
                "g0_max_rel",
                "min_regularity_rel",
                "network_undulation_max_rad",
            ] {
                let (x, y) = (a[key].as_f64().expect(key), b[key].as_f64().expect(key));
                assert!(
                    (x - y).abs() <= 1e-13 + 1e-9 * x.abs(),
                    "{scheme} ×{scale:e} {key}: {y} vs {x}"
                );
            }
            assert_eq!(
                a["continuity_order_between_faces"], b["continuity_order_between_faces"],
                "{scheme} ×{scale:e}"
            );
        }
    }
}

/// `export --tess` is capped, and the size of the OBJ is estimated against the memory
/// limit before anything is evaluated.
#[test]
fn export_tessellation_is_bounded() {
    let dir = scratch("export_tess");
    let mesh = scaled_octahedron(&dir, 1.0);
    let obj = dir.join("t.obj");
    let args = |tess: &'static str| {
        vec![
            "export",
            path_str(&mesh),
            "--scheme",
            "hb",
            "--format",
            "obj",
            "-o",
            path_str(&obj),
            "--tess",
            tess,
        ]
        .into_iter()
        .map(String::from)
        .collect::<Vec<_>>()
    };
    let run = |tess, env: &[(&str, &str)]| {
        let a = args(tess);
        common::smoothlab_with_env(&a.iter().map(String::as_str).collect::<Vec<_>>(), env)
    };
    assert_fails_naming(&run("100000", &[]), &["'--tess", "'100000'", "1..=4096"]);
    let out = run("1000", &[("SMOOTHLAB_MEMORY_LIMIT", "1e8")]);
    assert_fails_naming(
        &out,
        &[
            "32 patches at --tess 1000",
            "GB",
            "SMOOTHLAB_MEMORY_LIMIT",
            "lower --tess",
        ],
    );
    assert!(!obj.exists());
    let out = run("4", &[]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = std::fs::read_to_string(&obj).expect("obj");
    assert!(!text.contains("vn 0 0 0"));
}

/// A bipyramid with two apexes of valence `n`.
fn bipyramid(n: usize) -> String {
    let mut text = String::from("v 0 0 1\nv 0 0 -1\n");
    for i in 0..n {
        let a = std::f64::consts::TAU * i as f64 / n as f64;
        text += &format!("v {} {} 0\n", a.cos(), a.sin());
    }
    for i in 0..n {
        let (a, b) = (3 + i, 3 + (i + 1) % n);
        text += &format!("f 1 {a} {b}\nf 2 {b} {a}\n");
    }
    text
}

/// gk refuses a vertex above its valence limit (`--param max_valence`, default 1000) at once,
/// naming the vertex, its valence, the limit, the estimated cost and how to raise it; the
/// parameter lowers and raises the limit, and valence 200 builds.
#[test]
fn gk_refuses_valences_above_its_limit_by_vertex() {
    let dir = scratch("gk_valence");
    let huge = write(&dir, "bipyramid-1200.obj", &bipyramid(1200));
    let start = std::time::Instant::now();
    for k in ["1", "4"] {
        let out = smoothlab(&[
            "metrics",
            path_str(&huge),
            "--scheme",
            "gk",
            "--param",
            &format!("k={k}"),
        ]);
        assert_fails_naming(
            &out,
            &[
                &format!("k={k}"),
                "vertex 0 has valence 1200",
                "above max_valence=1000",
                "MB",
                "--param max_valence=1200",
            ],
        );
    }
    assert!(start.elapsed().as_secs() < 10, "{:?}", start.elapsed());
    let mesh = write(&dir, "bipyramid-17.obj", &bipyramid(17));
    let metrics = |params: &[&str]| {
        let mut args = vec!["metrics", path_str(&mesh), "--scheme", "gk"];
        for p in params {
            args.extend(["--param", p]);
        }
        smoothlab(&args)
    };
    let out = metrics(&["k=1", "max_valence=16"]);
    assert_fails_naming(&out, &["vertex 0 has valence 17", "above max_valence=16"]);
    let out = metrics(&["k=1", "max_valence=2.5"]);
    assert_fails_naming(&out, &["max_valence", "whole number"]);
    let out = metrics(&["k=1", "max_valence=17"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let mesh = write(&dir, "bipyramid-200.obj", &bipyramid(200));
    let out = smoothlab(&[
        "metrics",
        path_str(&mesh),
        "--scheme",
        "gk",
        "--param",
        "k=1",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
}

/// Scene `[bvh]` keys outside their ranges are refused by name; settings within the ranges
/// that would still make an absurd number of leaves are refused by the leaf estimate before
/// the subdivision, and a BVH beyond the memory limit by the memory estimate.
#[test]
fn bvh_settings_and_size_are_bounded() {
    let dir = scratch("bvh_bounds");
    let mesh = scaled_octahedron(&dir, 1.0);
    let scene = |name: &str, bvh: &str| {
        let text = format!(
            "mesh = {:?}\n[scheme]\nname = \"hb\"\n[render]\nmode = \"normals\"\nsize = [8, 8]\nspp = 1\n[bvh]\n{bvh}\n",
            path_str(&mesh)
        );
        write(&dir, &format!("{name}.toml"), &text)
    };
    let render = |scene: &Path, env: &[(&str, &str)]| {
        let image = dir.join("img");
        common::smoothlab_with_env(&["render", path_str(scene), "-o", path_str(&image)], env)
    };
    let bad = scene("flat", "max_depth = 16\nflatness = 1e-300");
    assert_fails_naming(
        &render(&bad, &[]),
        &["bvh.flatness = 1e-300", "[1e-4, 1e0]"],
    );
    let bad = scene("cone", "cone_deg = 0.001");
    assert_fails_naming(&render(&bad, &[]), &["bvh.cone_deg = 1e-3"]);
    let start = std::time::Instant::now();
    let deep = scene("deep", "max_depth = 16\nflatness = 1e-4");
    assert_fails_naming(
        &render(&deep, &[]),
        &[
            "BVH of scheme 'hb'",
            "leaves",
            "bvh.max_leaves",
            "raise bvh.flatness",
        ],
    );
    assert!(start.elapsed().as_secs() < 10, "{:?}", start.elapsed());
    let fine = scene(
        "fine",
        "max_depth = 8\nflatness = 1e-4\nmax_leaves = 100000000",
    );
    // Above the construction's estimate (8 faces × 3.8 kB) and what the process holds, below
    // the BVH's (about 3.5 GB).
    let out = render(&fine, &[("SMOOTHLAB_MEMORY_LIMIT", "5e8")]);
    assert_fails_naming(
        &out,
        &["BVH of scheme 'hb'", "GB", "SMOOTHLAB_MEMORY_LIMIT"],
    );
    let out = render(&scene("default", ""), &[]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
}

/// A mesh whose construction would need more memory than the limit is refused before the
/// scheme allocates, naming the scheme, the face count, the estimate and how to raise the
/// limit; just above the estimate it builds.
#[test]
fn construction_beyond_the_memory_limit_is_refused_before_it_starts() {
    let mesh = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/bunny.obj");
    let metrics = |limit: &str| {
        common::smoothlab_with_env(
            &["metrics", path_str(&mesh), "--scheme", "hb"],
            &[("SMOOTHLAB_MEMORY_LIMIT", limit)],
        )
    };
    // 1,000 faces × 3.8 kB ≈ 3.8 MB.
    let out = metrics("1e6");
    assert_fails_naming(
        &out,
        &[
            "building scheme 'hb' on",
            "faces",
            "MB",
            "fewer faces",
            "SMOOTHLAB_MEMORY_LIMIT",
        ],
    );
    let out = metrics("1e8");
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    // The limit is for the whole process: 1 MB above the construction's estimate is less
    // than the construction plus what the process already holds (the binary, the mesh).
    let out = metrics("4.8e6");
    assert_fails_naming(&out, &["building scheme 'hb' on", "already holds"]);
}

/// The 12 × 8 torus with both seams written twice, the copies differing by rounding.
fn seamed_torus_obj() -> String {
    smoothlab::mesh::generate::to_obj(&smoothlab::mesh::generate::bad::seamed_torus(12, 8))
}

/// Asserts success with exactly one stderr line, the welding warning.
fn assert_welds_with_one_warning(out: &Output, what: &str) {
    let err = stderr(out);
    assert!(out.status.success(), "{what}: {err}");
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "{what}: {err}");
    assert!(
        lines[0].starts_with("warning: welded 21 vertices")
            && lines[0].contains("largest distance merged 3.566e-16"),
        "{what}: {err}"
    );
}

#[test]
fn rounding_seams_are_welded_with_a_warning_by_every_command() {
    let dir = scratch("weld-seams");
    let mesh = write(&dir, "torus.obj", &seamed_torus_obj());
    let mesh = mesh.to_str().expect("utf-8");
    let out = smoothlab(&["metrics", mesh, "--scheme", "hb"]);
    assert_welds_with_one_warning(&out, "metrics");
    let json = dir.join("p.json");
    let json = json.to_str().expect("utf-8");
    let out = smoothlab(&[
        "export", mesh, "--scheme", "hb", "--format", "json", "-o", json,
    ]);
    assert_welds_with_one_warning(&out, "export");
    let out = smoothlab(&["sample", mesh, "--scheme", "hb", "--json", json]);
    assert_welds_with_one_warning(&out, "sample");
    let image = dir.join("torus");
    let render = |extra: &[&str]| {
        let mut args = vec![
            "render",
            mesh,
            "--scheme",
            "hb",
            "--mode",
            "normals",
            "--size",
            "8x8",
            "--spp",
            "1",
            "-o",
            image.to_str().expect("utf-8"),
        ];
        args.extend_from_slice(extra);
        smoothlab(&args)
    };
    assert_welds_with_one_warning(&render(&[]), "render");
    assert!(dir.join("torus.png").is_file());

    // Tolerance 0 welds identical positions only: every command then sees the open seams.
    let boundary = ["needs a closed mesh", "boundary edge"];
    let zero = ["--weld-tolerance", "0"];
    assert_fails_naming(
        &smoothlab(&[&["metrics", mesh, "--scheme", "gk"][..], &zero].concat()),
        &boundary,
    );
    assert_fails_naming(
        &smoothlab(
            &[
                &[
                    "export", mesh, "--scheme", "gk", "--format", "bv", "-o", json,
                ][..],
                &zero,
            ]
            .concat(),
        ),
        &boundary,
    );
    assert_fails_naming(
        &smoothlab(
            &[
                &["sample", mesh, "--scheme", "gk", "--json", json][..],
                &zero,
            ]
            .concat(),
        ),
        &boundary,
    );
    let closed_only = [
        "render", mesh, "--scheme", "gk", "--mode", "normals", "--size", "8x8",
    ];
    assert_fails_naming(&smoothlab(&[&closed_only[..], &zero].concat()), &boundary);
}

#[test]
fn scene_key_weld_tolerance_and_the_flag_that_overrides_it() {
    let dir = scratch("weld-scene");
    write(&dir, "torus.obj", &seamed_torus_obj());
    let scene = write(
        &dir,
        "torus.toml",
        "mesh = \"torus.obj\"\nweld_tolerance = 0.0\n[scheme]\nname = \"gk\"\n\
         [render]\nmode = \"normals\"\nsize = [8, 8]\nspp = 1\n",
    );
    let image = dir.join("torus");
    let render = |extra: &[&str]| {
        let mut args = vec![
            "render",
            scene.to_str().expect("utf-8"),
            "-o",
            image.to_str().expect("utf-8"),
        ];
        args.extend_from_slice(extra);
        smoothlab(&args)
    };
    assert_fails_naming(&render(&[]), &["boundary edge"]);
    assert_welds_with_one_warning(&render(&["--weld-tolerance", "1e-10"]), "flag over key");
    let bad = write(
        &dir,
        "bad.toml",
        "mesh = \"torus.obj\"\nweld_tolerance = -1\n",
    );
    assert_fails_naming(
        &smoothlab(&["render", bad.to_str().expect("utf-8")]),
        &["weld_tolerance", "-1"],
    );
}

/// A scene that names no mesh is refused by `render` and by `view` with the scene's path.
#[test]
fn a_scene_without_a_mesh_is_refused() {
    let dir = scratch("scene-without-mesh");
    let scene = write(&dir, "empty.toml", "[scheme]\nname = \"hb\"\n");
    let path = scene.to_str().expect("utf-8");
    for command in ["render", "view"] {
        let out = smoothlab(&[command, path]);
        assert_fails_naming(&out, &[&format!("{path}: no mesh given")]);
    }
}

#[test]
fn weld_tolerance_that_collapses_an_edge_names_the_face() {
    let dir = scratch("weld-collapse");
    let out = metrics_of(
        &dir,
        "torus.obj",
        &seamed_torus_obj(),
        &["--scheme", "hb", "--weld-tolerance", "0.2"],
    );
    // Welding that far collapses faces: a repair naming the weld and the flag, refused by
    // --strict.
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("first: face 0: welding merged its corners 0 and 9"),
        "{}",
        stderr(&out)
    );
    let out = metrics_of(
        &dir,
        "torus.obj",
        &seamed_torus_obj(),
        &["--scheme", "hb", "--weld-tolerance", "0.2", "--strict"],
    );
    assert_fails_naming(
        &out,
        &[
            "face 0: welding merged its corners 0 and 9",
            "--weld-tolerance",
            "--strict",
        ],
    );
    for bad in ["-1e-9", "1", "nan", "tiny"] {
        let out = metrics_of(
            &dir,
            "torus.obj",
            &seamed_torus_obj(),
            &["--scheme", "hb", "--weld-tolerance", bad],
        );
        assert_fails_naming(&out, &["--weld-tolerance", bad]);
    }
}

/// The octahedron of scenes/ (comments, 6 `v`, 8 `f` records).
fn octahedron_obj() -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/octahedron.obj"))
        .expect("scenes/octahedron.obj")
}

/// Runs `sample --scheme hb` on `obj` (written as `name`) and returns the samples JSON.
fn hb_samples(dir: &Path, name: &str, obj: &str) -> String {
    let mesh = write(dir, name, obj);
    let json = dir.join(format!("{name}.json"));
    let out = smoothlab(&[
        "sample",
        mesh.to_str().expect("utf-8"),
        "--scheme",
        "hb",
        "--json",
        json.to_str().expect("utf-8"),
    ]);
    assert!(out.status.success(), "{name}: {}", stderr(&out));
    assert!(out.stderr.is_empty(), "{name}: {}", stderr(&out));
    std::fs::read_to_string(json).expect("samples written")
}

#[test]
fn byte_order_mark_and_old_line_ends_are_read() {
    let dir = scratch("bom-line-ends");
    let octahedron = octahedron_obj();
    let expected = hb_samples(&dir, "lf.obj", &octahedron);
    // The mark directly before the first `v` record, and before the comments.
    let records: String = octahedron
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| format!("{l}\n"))
        .collect();
    for (name, text) in [
        ("bom.obj", format!("\u{feff}{records}")),
        ("bom-comments.obj", format!("\u{feff}{octahedron}")),
        ("cr.obj", octahedron.replace('\n', "\r")),
        ("crlf.obj", octahedron.replace('\n', "\r\n")),
    ] {
        assert_eq!(hb_samples(&dir, name, &text), expected, "{name}");
    }
}

#[test]
fn signed_zero_copies_are_welded_silently() {
    let dir = scratch("signed-zero");
    // Face `f 2 3 6` written with its own copies of vertices 3 and 6 (1-based), their zeros
    // written as -0: welded by bit pattern, the copies would leave the face hanging by one
    // vertex.
    let octahedron = octahedron_obj();
    assert!(octahedron.contains("v 0 1 0\n") && octahedron.contains("v 0 0 -1\n"));
    let text = octahedron.replace("f 2 3 6\n", "f 2 7 8\n") + "v -0 1 -0\nv -0 -0 -1\n";
    let out = metrics_of(&dir, "signed-zero.obj", &text, &["--scheme", "hb"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(stderr(&out).is_empty(), "{}", stderr(&out));
}

#[test]
fn coordinates_out_of_range_name_the_range() {
    let dir = scratch("coordinate-range");
    let octahedron = octahedron_obj();
    for scale in ["1e-100", "1e100", "1e154"] {
        let text: String = octahedron
            .lines()
            .map(|l| match l.strip_prefix("v ") {
                Some(rest) => {
                    let scaled: Vec<String> = rest
                        .split_whitespace()
                        .map(|c| format!("{c}{}", &scale[1..]))
                        .collect();
                    format!("v {}\n", scaled.join(" "))
                }
                None => format!("{l}\n"),
            })
            .collect();
        let out = metrics_of(&dir, "scaled.obj", &text, &["--scheme", "hb"]);
        assert_fails_naming(
            &out,
            &["coordinates span", "smoothlab supports", "1e-60", "1e60"],
        );
    }
}

// Hostile but plausible input (issue 12): closed standard output, output names and paths,
// scene-file errors, cameras, compare gates, concurrent writers.

/// Arguments of a small, fast render of the tetrahedron written to `dir`.
fn small_render(dir: &Path, extra: &[&str]) -> Output {
    let mesh = write(dir, "tet.obj", TETRAHEDRON);
    let mut args = vec![
        "render",
        mesh.to_str().expect("utf-8"),
        "--scheme",
        "pn",
        "--mode",
        "normals",
        "--size",
        "24x16",
        "--spp",
        "1",
    ];
    args.extend_from_slice(extra);
    smoothlab(&args)
}

/// The names in `dir`, sorted.
fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("list folder")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// A reader that closes its end at once: writing to standard output fails with a broken
/// pipe. That is no error (`smoothlab schemes | head -1`): nothing on stderr, the command's
/// own exit code.
#[test]
fn closed_stdout_pipe_exits_quietly() {
    let dir = scratch("closed-pipe");
    let mesh = write(&dir, "tet.obj", TETRAHEDRON);
    let stem = dir.join("r");
    let runs: [&[&str]; 3] = [
        &["schemes"],
        &["metrics", path_str(&mesh), "--scheme", "flat"],
        &[
            "render",
            path_str(&mesh),
            "--scheme",
            "flat",
            "--size",
            "8x8",
            "--spp",
            "1",
            "-o",
            path_str(&stem),
        ],
    ];
    for args in runs {
        let (reader, writer) = std::io::pipe().expect("pipe");
        drop(reader);
        let out = common::smoothlab_with_stdout(args, writer.into());
        assert_eq!(out.status.code(), Some(0), "{args:?}: {}", stderr(&out));
        assert_eq!(stderr(&out), "", "{args:?}");
    }
}

/// A full device is an error: one line, exit code 1.
#[test]
fn full_stdout_is_one_error_line() {
    let dir = scratch("full-stdout");
    let mesh = write(&dir, "tet.obj", TETRAHEDRON);
    let runs: [&[&str]; 2] = [
        &["schemes"],
        &["metrics", path_str(&mesh), "--scheme", "flat"],
    ];
    for args in runs {
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .expect("/dev/full");
        let out = common::smoothlab_with_stdout(args, full.into());
        assert_fails_naming(&out, &["standard output", "No space left"]);
    }
}

/// `-o NAME` drops only a `.png` or `.exr` ending; a folder or a device is no output name.
#[test]
fn output_names_keep_their_dots_and_refuse_folders_and_devices() {
    let dir = scratch("output-names");
    let out = small_render(&dir, &["-o", path_str(&dir.join("o/run.v2"))]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(listing(&dir.join("o")), ["run.v2.exr", "run.v2.png"]);

    let out = small_render(&dir, &["-o", path_str(&dir.join("o/plain.png"))]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(dir.join("o/plain.png").is_file() && dir.join("o/plain.exr").is_file());

    let folder = format!("{}/", dir.join("new").display());
    let out = small_render(&dir, &["-o", &folder]);
    assert_fails_naming(&out, &[&folder, "is a folder"]);
    let out = small_render(&dir, &["-o", path_str(&dir.join("o"))]);
    assert_fails_naming(&out, &["is a folder"]);
    assert!(!dir.join("o.png").exists() && !dir.join("new").exists());

    let out = small_render(&dir, &["-o", "/dev/null"]);
    assert_fails_naming(&out, &["/dev/null", "not a regular file"]);
    assert!(!Path::new("/dev/null.png").exists());
}

/// Every output path is checked before the work: nothing is written when one of them is bad.
#[test]
fn bad_output_paths_fail_before_any_file_is_written() {
    let dir = scratch("output-paths");
    let stem = dir.join("x");
    let stats = dir.join("tet.obj").join("s.json");
    let out = small_render(&dir, &["-o", path_str(&stem), "--stats", path_str(&stats)]);
    assert_fails_naming(&out, &["tet.obj: is not a folder"]);
    assert_eq!(listing(&dir), ["tet.obj"], "no PNG or EXR written");

    std::fs::create_dir(dir.join("y.exr")).expect("folder named like the EXR");
    let out = small_render(&dir, &["-o", path_str(&dir.join("y"))]);
    assert_fails_naming(&out, &["y.exr", "is a folder"]);
    assert!(
        !dir.join("y.png").exists(),
        "PNG written before the EXR failed"
    );

    let mesh = dir.join("tet.obj");
    let json = dir.join("tet.obj").join("m.json");
    let out = smoothlab(&[
        "metrics",
        path_str(&mesh),
        "--scheme",
        "flat",
        "--json",
        path_str(&json),
    ]);
    assert_fails_naming(&out, &["tet.obj: is not a folder"]);
    assert_eq!(out.stdout, b"", "no table printed after a failure");

    let start = std::time::Instant::now();
    let out = smoothlab(&["report", "--out", "/proc/smoothlab-report"]);
    assert_fails_naming(&out, &["/proc/smoothlab-report"]);
    assert!(
        start.elapsed().as_secs_f64() < 5.0,
        "report measured before failing: {:?}",
        start.elapsed()
    );
}

/// Two renders to the same `-o` at once: each file is written to a temporary name and renamed,
/// so the files are always complete and no temporary file is left behind.
#[test]
fn concurrent_renders_to_one_name_leave_readable_files() {
    let dir = scratch("concurrent");
    let mesh = write(&dir, "tet.obj", TETRAHEDRON);
    let stem = dir.join("out").join("same");
    let args = [
        "render",
        path_str(&mesh),
        "--scheme",
        "pn",
        "--mode",
        "normals",
        "--size",
        "320x320",
        "--spp",
        "1",
        "-o",
        path_str(&stem),
    ];
    for round in 0..3 {
        let writers: Vec<std::process::Child> = (0..3)
            .map(|_| {
                std::process::Command::new(env!("CARGO_BIN_EXE_smoothlab"))
                    .args(args)
                    .stdout(std::process::Stdio::null())
                    .spawn()
                    .expect("spawn smoothlab")
            })
            .collect();
        for mut w in writers {
            assert!(w.wait().expect("wait").success(), "round {round}");
        }
        exr::prelude::read_all_flat_layers_from_file(stem.with_extension("exr"))
            .unwrap_or_else(|e| panic!("round {round}: EXR unreadable: {e}"));
        image::open(stem.with_extension("png"))
            .unwrap_or_else(|e| panic!("round {round}: PNG unreadable: {e}"));
        assert_eq!(listing(&dir.join("out")), ["same.exr", "same.png"]);
    }
}

/// A scene file error is one line `FILE:LINE:COLUMN: KEY: message`.
#[test]
fn scene_file_errors_are_one_line_with_file_line_and_key() {
    let dir = scratch("scene-errors");
    let mesh = write(&dir, "tet.obj", TETRAHEDRON);
    // Line 1 of every file is the mesh.
    let cases = [
        (
            "unknown.toml",
            "[render]\nspp = 1\nsparkle = 3\n",
            "4:1: render: unknown field `sparkle`",
        ),
        ("syntax.toml", "[render]\nmode = \"zebra\n", "3:14: "),
        (
            "type.toml",
            "[render]\nspp = \"many\"\n",
            "3:7: render.spp: invalid type",
        ),
        (
            "size.toml",
            "[render]\nsize = [48, 32, 999]\n",
            "3:8: render.size: invalid length 3, expected 2 elements",
        ),
        (
            "up.toml",
            "[camera]\nup = [0, 1, 0, 7]\n",
            "3:6: camera.up: invalid length 4, expected 3 elements",
        ),
    ];
    for (name, body, expected) in cases {
        let scene = write(
            &dir,
            name,
            &format!("mesh = \"{}\"\n{body}", path_str(&mesh)),
        );
        let out = smoothlab(&["render", path_str(&scene), "-o", path_str(&dir.join("x"))]);
        assert_fails_naming(&out, &[&format!("error: {}:{expected}", scene.display())]);
    }
}

/// A camera far away or with a tiny field of view: no false "eye and target coincide".
#[test]
fn far_cameras_render_or_name_the_value() {
    let dir = scratch("far-camera");
    for eye in ["1e300,0,0", "-1e300,1e300,3"] {
        let out = small_render(&dir, &["--eye", eye, "-o", path_str(&dir.join("far"))]);
        assert!(out.status.success(), "eye {eye}: {}", stderr(&out));
    }
    let out = small_render(&dir, &["--fov", "1e-300", "-o", path_str(&dir.join("f"))]);
    assert_fails_naming(&out, &["field of view 1e-300°", "at least"]);
    let out = small_render(&dir, &["--eye", "1,2,3", "--target", "1,2,3"]);
    assert_fails_naming(&out, &["coincide"]);
}

/// `--up` without `--eye` turns the automatically framed view.
#[test]
fn up_applies_to_automatic_framing() {
    let dir = scratch("up");
    let png = |name: &str, extra: &[&str]| {
        let stem = dir.join(name);
        let mut args = vec!["-o", path_str(&stem)];
        args.extend_from_slice(extra);
        let out = small_render(&dir, &args);
        assert!(out.status.success(), "{name}: {}", stderr(&out));
        // The pixels (the PNG's text chunks record the command line and camera).
        image::open(stem.with_extension("png"))
            .expect("PNG")
            .to_rgb8()
            .into_raw()
    };
    let default = png("default", &[]);
    assert_eq!(
        default,
        png("y-up", &["--up", "0,1,0"]),
        "+y is the default up"
    );
    assert_ne!(
        default,
        png("x-up", &["--up", "1,0,0"]),
        "--up 1,0,0 ignored"
    );
    assert_ne!(
        png("target", &["--target", "0.1,0,0"]),
        png("target-x-up", &["--target", "0.1,0,0", "--up", "1,0,0"]),
        "--up ignored with --target"
    );
    let out = small_render(&dir, &["--up", "0.55,0.45,1"]);
    assert_fails_naming(&out, &["camera up", "parallel"]);
}

/// `compare` refuses thresholds and reports with which no comparison can fail.
#[test]
fn compare_gates_that_cannot_fail_are_errors() {
    let dir = scratch("compare-gates");
    let report = |name: &str, version: u32, records: &[(&str, f64)]| {
        let records: Vec<serde_json::Value> = records
            .iter()
            .map(|(scheme, g1)| {
                serde_json::json!({
                    "mesh": "cube",
                    "scheme": scheme,
                    "figures": { "g1_max_rad": g1, "construct_ms": 10.0 * g1 + 10.0 },
                })
            })
            .collect();
        let json = serde_json::json!({
            "format": "smoothlab-report",
            "version": version,
            "commit": "x",
            "date": "d",
            "records": records,
        });
        write(&dir, name, &json.to_string())
    };
    let old = report("old.json", 1, &[("hb", 0.0), ("pn", 0.1)]);
    let worse = report("worse.json", 1, &[("hb", 1.0), ("pn", 0.1)]);
    let out = smoothlab(&["compare", path_str(&old), path_str(&worse)]);
    assert_eq!(
        out.status.code(),
        Some(1),
        "a regression fails: {}",
        stderr(&out)
    );

    for (flag, value) in [
        ("--quality-rel", "NaN"),
        ("--quality-rel", "-0.5"),
        ("--time-ratio", "NaN"),
        ("--time-ratio", "inf"),
        ("--time-ratio", "0"),
        ("--time-ratio", "-1"),
    ] {
        let out = smoothlab(&["compare", path_str(&old), path_str(&worse), flag, value]);
        assert_fails_naming(&out, &[&format!("{flag} {value}")]);
    }

    let duplicate = report("dup.json", 1, &[("hb", 0.0), ("pn", 0.1), ("hb", 0.0)]);
    let out = smoothlab(&["compare", path_str(&old), path_str(&duplicate)]);
    assert_fails_naming(&out, &["dup.json", "records 0 and 2 are both cube / hb"]);
    let v2 = report("v2.json", 2, &[("hb", 0.0), ("pn", 0.1)]);
    let out = smoothlab(&["compare", path_str(&v2), path_str(&old)]);
    assert_fails_naming(&out, &["v2.json", "version 2"]);
}

#[test]
fn an_output_onto_an_input_is_refused_before_any_work() {
    let dir = scratch("output-is-input");
    let mesh = write(&dir, "m.obj", TETRAHEDRON);
    let m = path_str(&mesh);
    let out = smoothlab(&["metrics", m, "--scheme", "flat", "--json", m]);
    assert_fails_naming(&out, &["m.obj", "--json would overwrite the mesh"]);
    // The same file under another spelling.
    let roundabout = format!("{}/./m.obj", path_str(&dir));
    for args in [
        vec![
            "export",
            m,
            "--scheme",
            "pn",
            "--format",
            "obj",
            "-o",
            &roundabout,
        ],
        vec!["sample", m, "--scheme", "pn", "--json", &roundabout],
    ] {
        let flag = if args[0] == "export" { "-o" } else { "--json" };
        let out = smoothlab(&args);
        assert_fails_naming(
            &out,
            &["m.obj", &format!("{flag} would overwrite the mesh")],
        );
    }
    assert_eq!(std::fs::read_to_string(&mesh).expect("mesh"), TETRAHEDRON);
    assert_eq!(listing(&dir), ["m.obj"], "nothing written");
}

#[test]
fn two_outputs_of_one_render_on_one_file_are_refused_before_any_work() {
    let dir = scratch("outputs-collide");
    let mesh = write(&dir, "m.obj", TETRAHEDRON);
    let name = dir.join("out");
    let base = [
        "render",
        path_str(&mesh),
        "--scheme",
        "flat",
        "--size",
        "8x8",
        "--spp",
        "1",
        "-o",
        path_str(&name),
    ];
    let stats_on = |target: &str| {
        let mut args = base.to_vec();
        args.extend(["--stats", target]);
        smoothlab(&args)
    };
    let png = dir.join("out.png");
    let out = stats_on(path_str(&png));
    assert_fails_naming(
        &out,
        &["out.png", "written both as the PNG image and as --stats"],
    );
    let out = stats_on(path_str(&dir.join("out.exr")));
    assert_fails_naming(&out, &["out.exr", "the EXR image and as --stats"]);
    let out = stats_on(path_str(&mesh));
    assert_fails_naming(&out, &["m.obj", "--stats would overwrite the mesh"]);
    // A turntable's frames and GIF, and its shard part.
    let mut spin = base.to_vec();
    spin.extend(["--turntable", "2", "--stats"]);
    let frame = dir.join("out-001.png");
    let out = smoothlab(&[spin.as_slice(), &[path_str(&frame)]].concat());
    assert_fails_naming(&out, &["out-001.png", "a frame and as --stats"]);
    let out = smoothlab(&[spin.as_slice(), &[path_str(&dir.join("out.gif"))]].concat());
    assert_fails_naming(&out, &["out.gif", "the GIF and as --stats"]);
    let part = dir.join("out.shard-0-of-2.json");
    let out = smoothlab(&[spin.as_slice(), &[path_str(&part), "--shard", "0/2"]].concat());
    assert_fails_naming(&out, &["out.shard-0-of-2.json", "part file and as --stats"]);
    assert_eq!(listing(&dir), ["m.obj"], "nothing written");
    // Distinct names work.
    let out = stats_on(path_str(&dir.join("stats.json")));
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(listing(&dir), ["m.obj", "out.exr", "out.png", "stats.json"]);
}

#[test]
fn a_file_name_of_245_bytes_is_written() {
    let dir = scratch("long-name");
    let mesh = write(&dir, "m.obj", TETRAHEDRON);
    let name = format!("{}.json", "g".repeat(240));
    assert_eq!(name.len(), 245);
    let target = dir.join(&name);
    let out = smoothlab(&[
        "export",
        path_str(&mesh),
        "--scheme",
        "flat",
        "--format",
        "json",
        "-o",
        path_str(&target),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        std::fs::read_to_string(&target)
            .expect("written")
            .contains("smoothlab-patches")
    );
    assert_eq!(listing(&dir), [name, "m.obj".to_string()]);
}

#[cfg(unix)]
#[test]
fn output_names_that_are_not_utf8_are_refused_everywhere() {
    use std::os::unix::ffi::OsStrExt;
    let dir = scratch("not-utf8");
    let mesh = write(&dir, "m.obj", TETRAHEDRON);
    std::fs::create_dir_all(dir.join("l")).expect("folder");
    let bad = dir
        .join("l")
        .join(std::ffi::OsStr::from_bytes(b"L17\xffname"));
    let run = |args: &[&std::ffi::OsStr]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_smoothlab"))
            .args(args)
            .output()
            .expect("run smoothlab")
    };
    let os = |s: &'static str| std::ffi::OsStr::new(s);
    let m = mesh.as_os_str();
    let render = [
        os("render"),
        m,
        os("--scheme"),
        os("flat"),
        os("--size"),
        os("8x8"),
        os("--spp"),
        os("1"),
        os("-o"),
        bad.as_os_str(),
    ];
    for extra in [&[][..], &[os("--turntable"), os("4")][..]] {
        let out = run(&[&render[..], extra].concat());
        assert_fails_naming(&out, &["L17\u{fffd}name", "not valid UTF-8"]);
    }
    let export = [
        os("export"),
        m,
        os("--scheme"),
        os("flat"),
        os("--format"),
        os("json"),
        os("-o"),
        bad.as_os_str(),
    ];
    assert_fails_naming(&run(&export), &["L17\u{fffd}name", "not valid UTF-8"]);
    let metrics = [
        os("metrics"),
        m,
        os("--scheme"),
        os("flat"),
        os("--json"),
        bad.as_os_str(),
    ];
    assert_fails_naming(&run(&metrics), &["L17\u{fffd}name", "not valid UTF-8"]);
    assert!(listing(&dir.join("l")).is_empty(), "nothing written");
    // A mesh whose name is not UTF-8 renders under a name given with -o, and asks for one
    // when the output would be named after it.
    let odd = dir.join(std::ffi::OsStr::from_bytes(b"m\xff.obj"));
    std::fs::copy(&mesh, &odd).expect("copy");
    let named_after = [
        os("render"),
        odd.as_os_str(),
        os("--scheme"),
        os("flat"),
        os("--size"),
        os("8x8"),
    ];
    assert_fails_naming(&run(&named_after), &["not valid UTF-8", "give -o NAME"]);
}

#[test]
fn an_interrupt_removes_the_temporary_being_written() {
    let dir = scratch("interrupt");
    let mesh = write(&dir, "m.obj", TETRAHEDRON);
    let name = dir.join("big");
    // A 2048² uncompressed EXR is tens of megabytes: the signal is sent once the temporary is
    // there, which takes a few tries at most when the writing is quick.
    let mut caught = 0;
    for _ in 0..20 {
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_smoothlab"))
            .args([
                "render",
                path_str(&mesh),
                "--scheme",
                "flat",
                "--size",
                "2048x2048",
                "--spp",
                "1",
                "--exr-compression",
                "none",
                "-o",
                path_str(&name),
            ])
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("start");
        let temporary = || listing(&dir).iter().any(|n| n.ends_with(".tmp"));
        // A temporary with bytes in it is an image being written (the checks before the work
        // leave empty ones for an instant).
        let writing = || {
            std::fs::read_dir(&dir).expect("list").any(|e| {
                let e = e.expect("entry");
                e.file_name().to_string_lossy().ends_with(".tmp")
                    && e.metadata().is_ok_and(|m| m.len() > 0)
            })
        };
        let mut seen = false;
        while child.try_wait().expect("wait").is_none() {
            if writing() {
                seen = true;
                let kill = std::process::Command::new("kill")
                    .args(["-TERM", &child.id().to_string()])
                    .status()
                    .expect("kill");
                assert!(kill.success());
                break;
            }
            std::thread::sleep(std::time::Duration::from_micros(200));
        }
        let out = child.wait_with_output().expect("finished");
        if seen && out.status.code() == Some(130) {
            caught += 1;
            assert!(!temporary(), "temporaries left: {:?}", listing(&dir));
            assert!(stderr(&out).contains("interrupted"), "{}", stderr(&out));
            break;
        }
        assert!(!temporary(), "temporaries left: {:?}", listing(&dir));
    }
    assert_eq!(caught, 1, "no run was interrupted while writing");
}

/// The OFF triangle whose one face announces 2⁶⁴ − 1 corners.
const OFF_CORNER_COUNT_AT_THE_LIMIT: &str =
    "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n18446744073709551615 0 1 2\n";

#[test]
fn a_corner_count_at_the_integer_limit_names_the_face() {
    let dir = scratch("off-corner-count");
    let off = write(&dir, "a.off", OFF_CORNER_COUNT_AT_THE_LIMIT);
    let out = smoothlab(&["metrics", path_str(&off), "--scheme", "flat"]);
    assert_fails_naming(
        &out,
        &["a.off: malformed OFF: line 6: face 0 announces 18446744073709551615 corners"],
    );
}

#[test]
fn a_report_batch_records_an_unreadable_mesh_and_goes_on() {
    let dir = scratch("report-bad-mesh");
    write(&dir, "a.off", OFF_CORNER_COUNT_AT_THE_LIMIT);
    write(&dir, "tetrahedron.obj", TETRAHEDRON);
    let list = write(&dir, "meshes.txt", "\u{feff}a.off\r\ntetrahedron.obj\r\n");
    let out_dir = dir.join("report");
    let out = smoothlab(&[
        "report",
        "--meshes",
        path_str(&list),
        "--scheme",
        "flat",
        "--out",
        path_str(&out_dir),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = std::fs::read_to_string(out_dir.join("metrics.json")).expect("metrics.json");
    let json: serde_json::Value = serde_json::from_str(&text).expect("json");
    let records = json["records"].as_array().expect("records");
    assert_eq!(records.len(), 2, "{records:?}");
    assert_eq!(records[0]["mesh"], "a.off");
    let error = records[0]["error"].as_str().expect("an error record");
    assert!(error.contains("line 6: face 0 announces"), "{error}");
    assert_eq!(records[1]["mesh"], "tetrahedron.obj");
    assert!(records[1]["error"].is_null(), "{:?}", records[1]);
}

/// A report that would overwrite its own baseline is refused before any work, naming the flag
/// (the baseline is copied first, as the documented workflow does).
#[test]
fn a_report_onto_its_own_baseline_is_refused() {
    let dir = scratch("report-onto-baseline");
    write(&dir, "tetrahedron.obj", TETRAHEDRON);
    let out_dir = dir.join("report");
    let report = |extra: &[&str]| {
        let mut args = vec![
            "report",
            "--meshes",
            path_str(&dir),
            "--scheme",
            "flat",
            "--out",
            path_str(&out_dir),
        ];
        args.extend_from_slice(extra);
        smoothlab(&args)
    };
    let first = report(&[]);
    assert!(first.status.success(), "{}", stderr(&first));
    let baseline = out_dir.join("metrics.json");
    let before = std::fs::read(&baseline).expect("metrics.json");
    let again = report(&["--baseline", path_str(&baseline)]);
    assert_fails_naming(
        &again,
        &["metrics.json: a file of the report would overwrite --baseline"],
    );
    assert_eq!(std::fs::read(&baseline).expect("metrics.json"), before);
    let copy = dir.join("before.json");
    std::fs::copy(&baseline, &copy).expect("copy");
    let compared = report(&["--baseline", path_str(&copy)]);
    assert!(compared.status.success(), "{}", stderr(&compared));
}

#[test]
fn a_mesh_given_to_meshes_is_an_error() {
    let dir = scratch("meshes-is-a-mesh");
    let mesh = write(&dir, "tetrahedron.obj", TETRAHEDRON);
    let out = smoothlab(&[
        "report",
        "--meshes",
        path_str(&mesh),
        "--out",
        path_str(&dir.join("report")),
    ]);
    assert_fails_naming(
        &out,
        &["tetrahedron.obj: this is a mesh (OBJ file); --meshes takes a folder"],
    );
}

#[test]
fn negative_numeric_flags_name_the_flag_value_and_range() {
    let dir = scratch("negative-flags");
    let mesh = write(&dir, "tetrahedron.obj", TETRAHEDRON);
    let mesh = path_str(&mesh);
    let render = |flag: &str, value: &str| {
        let output = path_str(&dir.join("r")).to_string();
        smoothlab(&[
            "render", mesh, "--scheme", "flat", "-o", &output, flag, value,
        ])
    };
    for (out, fragments) in [
        (render("--fov", "-10"), ["--fov", "'-10'", "below 180°"]),
        (render("--spp", "-1"), ["--spp", "'-1'", "1..=65536"]),
        (
            render("--tessellate", "-1"),
            ["--tessellate", "'-1'", "1..=4096"],
        ),
        (
            render("--turntable", "-3"),
            ["--turntable", "'-3'", "1..=3600"],
        ),
        (render("--shard", "-1/4"), ["--shard", "'-1/4'", "≥ 0"]),
        (
            smoothlab(&[
                "export", mesh, "--scheme", "flat", "--format", "obj", "-o", "x.obj", "--tess",
                "-1",
            ]),
            ["--tess", "'-1'", "1..=4096"],
        ),
        (
            smoothlab(&["report", "--shard", "-1/4", "--out", path_str(&dir)]),
            ["--shard", "'-1/4'", "≥ 0"],
        ),
    ] {
        assert_fails_naming(&out, &fragments);
    }
}

#[test]
fn repairs_are_recorded_in_the_metrics_json_and_strict_refuses_them_on_every_command() {
    let dir = scratch("repairs-json");
    let obj = "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n\
               f 1 3 5\nf 3 2 5\nf 2 4 5\nf 1 4 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n";
    let mesh = write(&dir, "flipped.obj", obj);
    let json = dir.join("m.json");
    let out = smoothlab(&[
        "metrics",
        path_str(&mesh),
        "--scheme",
        "flat",
        "--json",
        path_str(&json),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = std::fs::read_to_string(&json).expect("metrics JSON");
    let value: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    let repairs = &value[0]["repairs"];
    assert_eq!(repairs[0]["kind"], "faces_reoriented", "{text}");
    assert_eq!(repairs[0]["count"], 1, "{text}");
    assert_eq!(repairs[0]["first"]["face"], 3, "{text}");
    let out_png = dir.join("r");
    for args in [
        vec!["metrics", path_str(&mesh), "--scheme", "flat", "--strict"],
        vec![
            "export",
            path_str(&mesh),
            "--scheme",
            "flat",
            "--format",
            "json",
            "-o",
            path_str(&dir.join("e.json")),
            "--strict",
        ],
        vec![
            "sample",
            path_str(&mesh),
            "--scheme",
            "flat",
            "--json",
            path_str(&dir.join("s.json")),
            "--strict",
        ],
        vec![
            "render",
            path_str(&mesh),
            "--scheme",
            "flat",
            "--size",
            "8x8",
            "--spp",
            "1",
            "-o",
            path_str(&out_png),
            "--strict",
        ],
    ] {
        assert_fails_naming(&smoothlab(&args), &["face 3", "--strict"]);
    }
}
