//! `smoothlab report` writes the recorded results for every scheme, and `smoothlab compare`
//! passes on identical reports and flags an injected regression with exit code 1.

use std::path::PathBuf;

use common::smoothlab;
use smoothlab::report::{self, Report};

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
    let old_path = dir.join("metrics.json");
    let old: Report = report::read(&old_path).expect("readable");
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
