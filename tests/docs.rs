//! The user guide in `docs/` is checked against the program: every figure `metrics` prints or
//! writes is explained in `docs/metrics.md`, and every paper the code cites is in
//! `docs/bibliography.md`.

mod common;

use std::path::Path;

use common::{path_str, scratch, smoothlab, stderr};

fn doc(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("docs")
        .join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Every column of the text table and every key of the JSON (of every scheme) is named, in
/// backquotes, in the metrics glossary.
#[test]
fn every_metrics_column_and_key_is_explained() {
    let glossary = doc("metrics.md");
    let dir = scratch("docs", "metrics");
    let json = dir.join("m.json");
    let mesh = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/octahedron.obj");
    let out = smoothlab(&[
        "metrics",
        path_str(&mesh),
        "--scheme",
        "all",
        "--json",
        path_str(&json),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let table = String::from_utf8(out.stdout).expect("utf-8");
    let header = table.lines().next().expect("a header line");
    let mut missing: Vec<String> = header
        .split_whitespace()
        .filter(|column| !glossary.contains(&format!("`{column}`")))
        .map(|column| format!("column {column}"))
        .collect();
    let value: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).expect("json")).expect("JSON");
    let schemes = value.as_array().expect("one object per scheme");
    assert!(schemes.len() >= 8, "{}", schemes.len());
    for scheme in schemes {
        for key in scheme.as_object().expect("an object").keys() {
            let entry = format!("key {key}");
            if !glossary.contains(&format!("`{key}`")) && !missing.contains(&entry) {
                missing.push(entry);
            }
        }
    }
    assert!(missing.is_empty(), "not in docs/metrics.md: {missing:?}");
}

/// Every short name the code cites a paper by (`[HB00 eq. 17]`, `[Piper87 §3.8]`, …) has a row
/// in the bibliography.
#[test]
fn every_cited_paper_is_in_the_bibliography() {
    let bibliography = doc("bibliography.md");
    let listed: Vec<&str> = bibliography
        .lines()
        .filter_map(|line| line.strip_prefix("| "))
        .filter_map(|row| row.split(" |").next())
        .collect();
    let mut cited = std::collections::BTreeSet::new();
    let mut stack = vec![Path::new(env!("CARGO_MANIFEST_DIR")).join("src")];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).expect("src folder") {
            let path = entry.expect("entry").path();
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            let text = std::fs::read_to_string(&path).expect("source file");
            // Citations are in comments: `[HB00 eq. 17]`, `[Piper87 §3.8 step 5]`, `[FM, t = 2]`.
            let comments = text
                .lines()
                .filter(|line| line.trim_start().starts_with("//"));
            for line in comments {
                // Code in backquotes (`[[Re Ĝ, −Im Ĝ], …]`) is not prose.
                let line: String = line.split('`').step_by(2).collect::<Vec<_>>().join(" ");
                for (start, _) in line.match_indices('[') {
                    let name: String = line[start + 1..]
                        .chars()
                        .take_while(|c| c.is_ascii_alphanumeric())
                        .collect();
                    let after = line[start + 1 + name.len()..].chars().next();
                    let starts_upper = name.chars().next().is_some_and(|c| c.is_ascii_uppercase());
                    if name.len() >= 2 && starts_upper && matches!(after, Some(' ' | ',')) {
                        cited.insert(name);
                    }
                }
            }
        }
    }
    for name in ["HB00", "Piper87", "UP", "FM"] {
        assert!(cited.contains(name), "{name} not found among the citations");
    }
    let missing: Vec<&String> = cited
        .iter()
        .filter(|name| !listed.contains(&name.as_str()))
        .collect();
    assert!(
        missing.is_empty(),
        "cited but not in docs/bibliography.md: {missing:?}"
    );
}
