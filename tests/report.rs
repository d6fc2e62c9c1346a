//! `smoothlab report` writes the recorded results for every scheme, and `smoothlab compare`
//! passes on identical reports and flags an injected regression with exit code 1.

use std::path::PathBuf;

use common::smoothlab;
use smoothlab::testing::report::{self, Report};

mod common;

fn scratch(test: &str) -> PathBuf {
    common::scratch("report", test)
}

#[test]
fn report_then_compare() {
    let dir = scratch("compare");
    let out = smoothlab(&["report", "--out", dir.to_str().expect("utf-8")]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for name in ["metrics.json", "metrics.csv", "metrics.md"] {
        assert!(dir.join(name).exists(), "{name} written");
    }
    // One summary line on stdout; no progress bar when stderr is not a terminal.
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(stdout.lines().count(), 1, "{stdout}");
    assert!(stdout.starts_with("report: "), "{stdout}");
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let old_path = dir.join("metrics.json");
    let old: Report = report::read(&old_path).expect("readable");
    // Provenance: the machine, the commit with its dirty flag, the tool version.
    let machine = old.machine.as_ref().expect("machine fingerprint recorded");
    assert_eq!(*machine, report::provenance::Machine::current());
    let describe = old.describe.as_deref().expect("describe recorded");
    assert_eq!(
        old.dirty,
        (describe != "unknown").then(|| describe.ends_with("-dirty"))
    );
    assert_eq!(old.tool_version.as_deref(), Some(env!("CARGO_PKG_VERSION")));
    assert!(
        stdout.starts_with(&format!(
            "report: {} records ({} meshes, {} schemes) written to ",
            old.records.len(),
            report::benchmark_meshes().unwrap().len(),
            smoothlab::schemes::names().len()
        )),
        "{stdout}"
    );
    // Cheap constructions are timed several times, with their spread.
    let flat = &old.records[0].figures;
    assert_eq!(flat["construct_ms_runs"], report::TIMING_RUNS);
    assert!(flat["construct_ms_spread_rel"].as_f64().expect("spread") >= 0.0);
    assert_eq!(
        report::schemes_covered(&old),
        smoothlab::schemes::names(),
        "every scheme is in the report"
    );
    assert!(
        old.records
            .iter()
            .any(|r| r.figures.contains_key("distance_max_rel"))
    );

    let same = smoothlab(&[
        "compare",
        old_path.to_str().unwrap(),
        old_path.to_str().unwrap(),
    ]);
    assert!(same.status.success());
    assert!(String::from_utf8_lossy(&same.stdout).contains("no changes"));

    // Inject a G1 regression into hb on the icosahedron.
    let mut broken = old.clone();
    let hb = broken
        .records
        .iter_mut()
        .find(|r| r.scheme == "hb" && r.mesh == "icosahedron")
        .expect("hb on the icosahedron");
    hb.figures
        .insert("g1_between_faces_max_rad".into(), 0.01.into());
    let new_path = dir.join("broken.json");
    std::fs::write(&new_path, serde_json::to_string(&broken).unwrap()).unwrap();
    let out = smoothlab(&[
        "compare",
        old_path.to_str().unwrap(),
        new_path.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("WORSE") && text.contains("icosahedron / hb"),
        "{text}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn compare_rejects_a_file_that_is_not_a_report() {
    let dir = scratch("bad");
    let path = dir.join("x.json");
    std::fs::write(&path, "{\"format\": \"other\"}").unwrap();
    let out = smoothlab(&["compare", path.to_str().unwrap(), path.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).starts_with("error: "));
    std::fs::remove_dir_all(&dir).ok();
}

/// The committed report with a machine fingerprint of CPU `cpu`, as JSON.
fn committed_report_on(cpu: &str) -> serde_json::Value {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("results/metrics.json");
    let mut report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).expect("committed report")).unwrap();
    report["machine"] = serde_json::json!({
        "cpu": cpu, "logical_cores": 2, "os": "linux", "arch": "x86_64"
    });
    report
}

fn write_json(dir: &std::path::Path, name: &str, value: &serde_json::Value) -> String {
    let path = dir.join(name);
    std::fs::write(&path, serde_json::to_string_pretty(value).unwrap()).unwrap();
    path.to_str().expect("utf-8").to_string()
}

fn run(args: &[&str]) -> (Option<i32>, String, String) {
    let out = smoothlab(args);
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn compare_judges_timings_only_when_asked_and_on_one_machine() {
    let dir = scratch("timings");
    let old = committed_report_on("cpu A");
    let mut slower = old.clone();
    let mut timed = 0;
    for record in slower["records"].as_array_mut().unwrap() {
        let ms = record["figures"]["construct_ms"].as_f64().unwrap();
        let spread = record["figures"]["construct_ms_spread_rel"]
            .as_f64()
            .unwrap_or(0.0);
        record["figures"]["construct_ms"] = (3.0 * ms).into();
        // Judged: 1 ms or more, and 3× beyond the default ratio 1.5 widened by the spread.
        timed += usize::from(ms >= 1.0 && 3.0 > 1.5 * (1.0 + spread));
    }
    assert!(timed > 0, "some construction takes 1 ms or more");
    let old_path = write_json(&dir, "old.json", &old);
    let slower_path = write_json(&dir, "slower.json", &slower);

    // Quality only by default: timings 3x slower pass.
    let (code, stdout, stderr) = run(&["compare", &old_path, &slower_path]);
    assert_eq!(code, Some(0), "{stdout}{stderr}");
    assert!(
        stdout.starts_with("no changes\nnote: timings not judged"),
        "{stdout}"
    );
    // Same machine, --timings: the slowdown is a regression.
    let (code, stdout, _) = run(&["compare", "--timings", &old_path, &slower_path]);
    assert_eq!(code, Some(1), "{stdout}");
    assert!(
        stdout.contains("construct_ms") && stdout.contains("WORSE"),
        "{stdout}"
    );
    assert_eq!(
        stdout.lines().filter(|l| l.starts_with("WORSE")).count(),
        timed,
        "{stdout}"
    );

    // Another machine: not judged unless forced.
    slower["machine"]["cpu"] = "cpu B".into();
    let other_path = write_json(&dir, "other.json", &slower);
    let (code, stdout, _) = run(&["compare", "--timings", &old_path, &other_path]);
    assert_eq!(code, Some(0), "{stdout}");
    assert!(stdout.contains("note: timings not judged: measured on different machines (cpu A"));
    let (code, stdout, _) = run(&["compare", "--force-timings", &old_path, &other_path]);
    assert_eq!(code, Some(1), "{stdout}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn compare_flags_an_injected_quality_regression_whatever_the_timings() {
    let dir = scratch("quality");
    let old = committed_report_on("cpu A");
    let mut broken = old.clone();
    broken["machine"]["cpu"] = "cpu B".into();
    let record = broken["records"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .find(|r| r["scheme"] == "hb" && r["mesh"] == "icosahedron")
        .expect("hb on the icosahedron");
    record["figures"]["g1_between_faces_max_rad"] = 0.01.into();
    let old_path = write_json(&dir, "old.json", &old);
    let broken_path = write_json(&dir, "broken.json", &broken);
    for extra in [None, Some("--timings")] {
        let mut args = vec!["compare"];
        args.extend(extra);
        args.extend([old_path.as_str(), broken_path.as_str()]);
        let (code, stdout, _) = run(&args);
        assert_eq!(code, Some(1), "{stdout}");
        assert!(
            stdout.contains("WORSE icosahedron / hb")
                && stdout.contains("g1_between_faces_max_rad"),
            "{stdout}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn compare_accepts_metrics_json_output() {
    let dir = scratch("metrics-json");
    let mesh = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/octahedron.obj");
    let mesh = mesh.to_str().unwrap();
    let (a, b) = (dir.join("a.json"), dir.join("b.json"));
    for path in [&a, &b] {
        let (code, _, stderr) = run(&[
            "metrics",
            mesh,
            "--scheme",
            "all",
            "--json",
            path.to_str().unwrap(),
        ]);
        assert_eq!(code, Some(0), "{stderr}");
    }
    let (a, b) = (a.to_str().unwrap(), b.to_str().unwrap());
    let (code, stdout, stderr) = run(&["compare", a, b]);
    assert_eq!(code, Some(0), "{stdout}{stderr}");
    assert!(stdout.starts_with("no changes\n"), "{stdout}");

    // A quality regression in pn.
    let mut metrics: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(b).unwrap()).unwrap();
    let pn = metrics
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .find(|m| m["scheme"] == "pn")
        .expect("pn measured");
    let g1 = pn["g1_max_rad"].as_f64().unwrap();
    pn["g1_max_rad"] = (2.0 * g1 + 0.1).into();
    let broken = write_json(&dir, "broken.json", &metrics);
    let (code, stdout, _) = run(&["compare", a, &broken]);
    assert_eq!(code, Some(1), "{stdout}");
    assert!(
        stdout.contains("WORSE (metrics) / pn") && stdout.contains("g1_max_rad"),
        "{stdout}"
    );

    // A report against metrics output, and JSON of neither shape, are errors.
    let report = write_json(&dir, "report.json", &committed_report_on("cpu A"));
    let (code, _, stderr) = run(&["compare", &report, a]);
    assert_eq!(code, Some(1));
    assert!(
        stderr.starts_with("error: cannot compare a report with metrics --json output"),
        "{stderr}"
    );
    for (text, fragment) in [
        ("[1, 2]", "entry 0 of the list is not an object"),
        (
            "{\"scheme\": \"pn\"}",
            "neither a report nor a list of metrics",
        ),
        ("[]", "the list is empty"),
        (
            "[{\"scheme\": \"pn\"}, {\"scheme\": \"pn\"}]",
            "records 0 and 1 are both (metrics) / pn",
        ),
    ] {
        let path = dir.join("odd.json");
        std::fs::write(&path, text).unwrap();
        let (code, _, stderr) = run(&["compare", path.to_str().unwrap(), a]);
        assert_eq!(code, Some(1), "{text}");
        assert!(
            stderr.starts_with("error: ") && stderr.contains(fragment),
            "{text}: {stderr}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// A small closed mesh (the icosahedron) as OBJ text.
fn icosahedron_obj() -> String {
    let s = smoothlab::mesh::generate::analytic::sphere(0);
    smoothlab::mesh::generate::to_obj(&(s.positions, s.faces))
}

#[cfg(unix)]
#[test]
fn unreadable_entries_of_a_mesh_folder_are_error_records() {
    let dir = scratch("unreadable-entries");
    let meshes = dir.join("meshes");
    std::fs::create_dir_all(meshes.join("x.obj")).expect("a folder named like a mesh");
    std::fs::write(meshes.join("comma,name.obj"), icosahedron_obj()).expect("mesh");
    std::os::unix::fs::symlink("missing.obj", meshes.join("broken.obj")).expect("link");
    std::os::unix::fs::symlink("loop-b.obj", meshes.join("loop-a.obj")).expect("link");
    std::os::unix::fs::symlink("loop-a.obj", meshes.join("loop-b.obj")).expect("link");
    let out_dir = dir.join("out");
    let out = smoothlab(&[
        "report",
        "--meshes",
        common::path_str(&meshes),
        "--scheme",
        "flat",
        "--out",
        common::path_str(&out_dir),
    ]);
    assert!(out.status.success(), "{}", common::stderr(&out));
    let report = report::read(&out_dir.join("metrics.json")).expect("report");
    let error_of = |mesh: &str| {
        report
            .records
            .iter()
            .find(|r| r.mesh == mesh)
            .and_then(|r| r.error.clone())
            .unwrap_or_else(|| panic!("no error record for {mesh}"))
    };
    assert!(error_of("x.obj").contains("is a folder, not a mesh file"));
    assert!(error_of("broken.obj").contains("broken, or a loop of links"));
    assert!(error_of("loop-a.obj").contains("broken, or a loop of links"));
    assert!(error_of("loop-b.obj").contains("broken, or a loop of links"));
    let measured = report.records.iter().find(|r| r.mesh == "comma,name.obj");
    assert!(measured.is_some_and(|r| r.error.is_none()), "{measured:?}");
    assert_eq!(report.records.len(), 5);
    // The CSV quotes the name with a comma: every row as many fields as the header.
    let csv = std::fs::read_to_string(out_dir.join("metrics.csv")).expect("csv");
    let header = csv.lines().next().expect("header").split(',').count();
    let row = csv
        .lines()
        .find(|l| l.starts_with("\"comma,name.obj\",flat,"))
        .unwrap_or_else(|| panic!("quoted row missing: {csv}"));
    assert_eq!(row.split(',').count(), header + 1, "{row}");
    assert!(out_dir.join("index.html").is_file());
}

/// `compare` reads at a glance: before → after, the relative change, BETTER / WORSE / same,
/// last-digit changes counted but not listed; two single-scheme `metrics --json` outputs
/// compare with each other.
#[test]
fn compare_lists_verdicts_ratios_and_skips_unchanged_values() {
    let dir = scratch("at-a-glance");
    let old = committed_report_on("cpu A");
    let mut new = old.clone();
    let records = new["records"].as_array_mut().unwrap();
    let find = |mesh: &str, scheme: &str| -> usize {
        records
            .iter()
            .position(|r| r["scheme"] == scheme && r["mesh"] == mesh)
            .unwrap_or_else(|| panic!("{mesh} / {scheme} recorded"))
    };
    let (worse, better, drift) = (
        find("icosahedron", "hb"),
        find("torus", "pn"),
        find("cube", "hb"),
    );
    let figure = |r: &serde_json::Value, key: &str| r["figures"][key].as_f64().unwrap();
    let g1 = figure(&records[worse], "g1_between_faces_max_rad");
    records[worse]["figures"]["g1_between_faces_max_rad"] = (g1 + 0.01).into();
    let energy = figure(&records[better], "bending_energy");
    records[better]["figures"]["bending_energy"] = (0.5 * energy).into();
    let drifting = figure(&records[drift], "bending_energy");
    records[drift]["figures"]["bending_energy"] = (drifting * (1.0 + 1e-12)).into();
    let (old_path, new_path) = (
        write_json(&dir, "old.json", &old),
        write_json(&dir, "new.json", &new),
    );
    let (code, stdout, stderr) = run(&["compare", &old_path, &new_path]);
    assert_eq!(code, Some(1), "{stdout}{stderr}");
    let lines: Vec<String> = stdout
        .lines()
        .map(|l| l.split_whitespace().collect::<Vec<_>>().join(" "))
        .collect();
    assert_eq!(
        lines.len(),
        4,
        "two changes, the counts, the note: {stdout}"
    );
    assert!(
        lines[0].starts_with("WORSE icosahedron / hb g1_between_faces_max_rad ")
            && lines[0].contains(" → 1.000e-2 x"),
        "{stdout}"
    );
    assert!(
        lines[1].starts_with("BETTER torus / pn bending_energy ") && lines[1].ends_with("-50.0%"),
        "{stdout}"
    );
    assert_eq!(
        lines[2],
        "1 regression(s), 1 improvement(s), 0 within tolerance among 2 change(s); 1 \
         last-digit change(s) not listed"
    );
    assert!(!stdout.contains("cube / hb"), "{stdout}");

    // metrics --json of one scheme each: the two schemes are compared.
    let mesh = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/octahedron.obj");
    let mut paths = Vec::new();
    for scheme in ["flat", "pn"] {
        let path = dir.join(format!("{scheme}.json"));
        let (code, _, stderr) = run(&[
            "metrics",
            mesh.to_str().unwrap(),
            "--scheme",
            scheme,
            "--json",
            path.to_str().unwrap(),
        ]);
        assert_eq!(code, Some(0), "{stderr}");
        paths.push(path.to_str().unwrap().to_string());
    }
    let (code, stdout, _) = run(&["compare", &paths[0], &paths[1]]);
    assert!(!stdout.contains("(record)"), "{stdout}");
    assert!(stdout.contains("(metrics) / flat -> pn"), "{stdout}");
    // flat has G1 jumps at every edge that pn's normals smooth: better, not worse.
    assert!(stdout.contains("BETTER (metrics) / flat -> pn"), "{stdout}");
    assert!(matches!(code, Some(0 | 1)), "{stdout}");
    std::fs::remove_dir_all(&dir).ok();
}

/// `merge --baseline` prints the baseline's line as `report --baseline` does.
#[test]
fn merge_with_a_baseline_prints_the_regression_count() {
    let dir = scratch("merge-baseline");
    let meshes = dir.join("meshes");
    std::fs::create_dir_all(&meshes).unwrap();
    std::fs::write(meshes.join("ico.obj"), icosahedron_obj()).unwrap();
    let m = common::path_str(&meshes);
    let single = dir.join("single");
    let out = smoothlab(&[
        "report",
        "--meshes",
        m,
        "--scheme",
        "flat",
        "--out",
        common::path_str(&single),
    ]);
    assert!(out.status.success(), "{}", common::stderr(&out));
    let mut baseline: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(single.join("metrics.json")).unwrap())
            .unwrap();
    baseline["records"][0]["figures"]["g1_between_faces_max_rad"] = 0.0.into();
    let baseline = write_json(&dir, "baseline.json", &baseline);
    let part = dir.join("part");
    let out = smoothlab(&[
        "report",
        "--meshes",
        m,
        "--scheme",
        "flat",
        "--out",
        common::path_str(&part),
        "--shard",
        "0/1",
    ]);
    assert!(out.status.success(), "{}", common::stderr(&out));
    let merged = dir.join("merged");
    let (code, stdout, stderr) = run(&[
        "merge",
        common::path_str(&part),
        "-o",
        common::path_str(&merged),
        "--baseline",
        &baseline,
    ]);
    assert_eq!(code, Some(0), "{stdout}{stderr}");
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(lines.len(), 2, "{stdout}");
    assert!(
        lines[1].starts_with(&format!(
            "baseline {baseline}: 1 regression(s), 0 improvement(s)"
        )),
        "{stdout}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
