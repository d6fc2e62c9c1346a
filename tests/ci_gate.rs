//! The CI regression gate of `deploy/github/` run locally, as the workflow runs it: the gate
//! script measures a base checkout and a head with the two builds, passes when nothing got
//! worse, fails (exit 1) on a quality regression — here a head whose hb is built with a worse
//! parameter (`alpha=0.5`: the vertices are no longer interpolated) — reports the timings of
//! the two runs of this machine, and leaves the page (with the trends of the base's history) where
//! the workflow uploads it from.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

mod common;

fn scratch(test: &str) -> PathBuf {
    common::scratch("ci_gate", test)
}

fn repo_file(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

/// Runs git with `args` in `repo` (an identity given, no global configuration needed).
fn git(repo: &Path, args: &[&str]) -> String {
    let out = Command::new("git")
        .args([
            "-c",
            "user.name=smoothlab test",
            "-c",
            "user.email=test@smoothlab.invalid",
        ])
        .args(["-c", "commit.gpgsign=false"])
        .args(args)
        .current_dir(repo)
        .output()
        .expect("run git");
    assert!(
        out.status.success(),
        "git {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).trim().to_string()
}

/// A git repository in `dir` with one empty commit; returns the commit.
fn repository(dir: &Path) -> String {
    std::fs::create_dir_all(dir).expect("repository folder");
    git(dir, &["init", "-q"]);
    // Messages differ: two empty commits of one second and author are the same commit.
    let message = format!("start {}", dir.display());
    git(dir, &["commit", "-q", "--allow-empty", "-m", &message]);
    git(dir, &["rev-parse", "HEAD"])
}

/// Runs the gate script in `head` (the current folder of the workflow).
fn gate(base: &Path, head: &Path, head_bin: &Path, out: &Path, flags: &[&str]) -> Output {
    Command::new("bash")
        .arg(repo_file("deploy/github/regression-gate.sh"))
        .arg(base)
        .arg(env!("CARGO_BIN_EXE_smoothlab"))
        .arg(head_bin)
        .arg(out)
        .args(flags)
        .current_dir(head)
        .env_remove("GITHUB_STEP_SUMMARY")
        .output()
        .expect("run the gate script")
}

fn text(out: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    )
}

#[test]
fn the_gate_passes_a_clean_head_and_fails_a_quality_regression() {
    let dir = scratch("gate");
    let meshes = dir.join("meshes");
    std::fs::create_dir_all(&meshes).expect("meshes");
    let s = smoothlab::mesh::generate::analytic::sphere(0);
    let obj = smoothlab::mesh::generate::to_obj(&(s.positions, s.faces));
    std::fs::write(meshes.join("ico.obj"), obj).expect("mesh");
    let flags = [
        "--meshes",
        meshes.to_str().expect("utf-8"),
        "--scheme",
        "hb,pn",
    ];
    // The base branch with a committed history of one earlier run.
    let base = dir.join("base");
    let first = repository(&base);
    let mut args = vec!["report", "--out", "results"];
    args.extend(flags);
    let out = Command::new(env!("CARGO_BIN_EXE_smoothlab"))
        .args(&args)
        .current_dir(&base)
        .output()
        .expect("run smoothlab");
    assert!(out.status.success(), "{}", text(&out));
    git(&base, &["add", "results"]);
    git(&base, &["commit", "-q", "-m", "results"]);
    let base_commit = git(&base, &["rev-parse", "HEAD"]);
    assert_ne!(first, base_commit);
    let head = dir.join("head");
    let head_commit = repository(&head);
    std::thread::sleep(std::time::Duration::from_millis(1100));

    let clean = dir.join("clean");
    let real = PathBuf::from(env!("CARGO_BIN_EXE_smoothlab"));
    let out = gate(&base, &head, &real, &clean, &flags);
    let log = text(&out);
    assert_eq!(out.status.code(), Some(0), "{log}");
    assert!(log.contains("gate: no quality regression"), "{log}");
    assert!(
        log.contains("== timings (same machine, reported only)"),
        "{log}"
    );
    let base_report =
        smoothlab::testing::report::read(&clean.join("base/metrics.json")).expect("base");
    let head_report =
        smoothlab::testing::report::read(&clean.join("head/metrics.json")).expect("head");
    assert_eq!(
        base_report.commit, base_commit,
        "the base measured in its checkout"
    );
    assert_eq!(head_report.commit, head_commit);
    assert_eq!(
        base_report.machine, head_report.machine,
        "timings of one machine"
    );
    // The page: the base's history (its committed run) followed by this run.
    let html = std::fs::read_to_string(clean.join("head/index.html")).expect("page");
    assert!(
        html.contains("2 run(s) in the history"),
        "trends of the base's history"
    );
    assert!(html.contains("id=\"baseline\""), "changes against the base");
    let timings = std::fs::read_to_string(clean.join("timings.txt")).expect("timings.txt");
    // Judged (one machine): no note that they were not.
    assert!(
        timings.starts_with("no changes") || timings.contains(" regression(s), "),
        "{timings}"
    );
    assert!(!timings.contains("timings not judged"), "{timings}");

    // A head whose hb default got worse: the gate fails and names it.
    let worse_bin = dir.join("worse-smoothlab");
    std::fs::write(
        &worse_bin,
        format!(
            "#!/bin/bash\nif [ \"$1\" = report ]; then exec '{0}' \"$@\" --param alpha=0.5; fi\n\
             exec '{0}' \"$@\"\n",
            real.display()
        ),
    )
    .expect("wrapper");
    let status = Command::new("chmod")
        .arg("+x")
        .arg(&worse_bin)
        .status()
        .expect("chmod");
    assert!(status.success());
    let worse = dir.join("worse");
    let out = gate(&base, &head, &worse_bin, &worse, &flags);
    let log = text(&out);
    assert_eq!(out.status.code(), Some(1), "{log}");
    assert!(log.contains("gate: quality regression (exit 1)"), "{log}");
    let quality = std::fs::read_to_string(worse.join("quality.txt")).expect("quality.txt");
    let line = quality
        .lines()
        .find(|l| l.contains("interp_max_rel"))
        .unwrap_or_else(|| panic!("{quality}"));
    assert!(line.starts_with("WORSE ico.obj / hb "), "{quality}");
    let html = std::fs::read_to_string(worse.join("head/index.html")).expect("page");
    assert!(
        html.contains(&format!(
            "<li class=\"step worse\" data-figure=\"interp_max_rel\" data-record=\"ico.obj / hb\" \
             data-commit=\"{head_commit}\""
        )),
        "the step marked at the head's commit"
    );
}

/// The workflow runs the script the test runs, and uploads the folder the script writes the
/// page into.
#[test]
fn the_workflow_runs_the_gate_script_and_uploads_its_page() {
    let workflow =
        std::fs::read_to_string(repo_file("deploy/github/regression.yml")).expect("workflow");
    assert!(workflow.contains("on:\n  pull_request:"), "{workflow}");
    let gate = workflow
        .rsplit("run: >")
        .next()
        .and_then(|step| step.split("deploy/github/regression-gate.sh").nth(1))
        .expect("the workflow runs the gate script");
    let args: Vec<&str> = gate
        .split("- name:")
        .next()
        .expect("step")
        .split_whitespace()
        .collect();
    assert_eq!(
        args.len(),
        4,
        "BASE_CHECKOUT BASE_BIN HEAD_BIN OUT: {args:?}"
    );
    assert_eq!(args[2], "target/release/smoothlab");
    let out = args[3];
    assert!(
        workflow.contains(&format!("path: {out}/head")),
        "the artefact is the head's report folder: {workflow}"
    );
    assert!(workflow.contains("uses: actions/upload-artifact@"));
    assert!(
        workflow.contains("if: always()"),
        "the page is uploaded when the gate fails"
    );
}
