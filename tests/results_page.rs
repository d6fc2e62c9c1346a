//! The results page (`index.html` of `smoothlab report`) in a real browser: headless Chromium
//! loads it from disk, and the DOM it dumps after the `load` event must carry the page's own
//! check — `data-ready`, no recorded error (script errors, failed loads, `console.error`), the
//! expected number of sortable tables and of images that decoded. A screenshot of each page
//! goes into the test's scratch folder (`target/tmp/results_page/…`).
//!
//! Chromium is found as `$SMOOTHLAB_CHROMIUM`, else `chromium` or `chromium-browser` on the
//! `PATH`. Without it the tests fail with the way to install it (`apt-get install -y
//! chromium` on Debian; `.ci/run` does so), unless `SMOOTHLAB_SKIP_BROWSER_TESTS=1` asks to
//! skip them.

use std::path::{Path, PathBuf};
use std::process::Command;

use smoothlab::testing::report::{self, history, page, plots, trends};

mod common;

fn scratch(test: &str) -> PathBuf {
    common::scratch("results_page", test)
}

/// The Chromium binary, or None when the tests are explicitly skipped; panics with the way to
/// install it otherwise.
fn chromium() -> Option<PathBuf> {
    if let Some(path) = std::env::var_os("SMOOTHLAB_CHROMIUM") {
        return Some(PathBuf::from(path));
    }
    let found = std::env::var_os("PATH").and_then(|paths| {
        std::env::split_paths(&paths)
            .flat_map(|dir| ["chromium", "chromium-browser"].map(|name| dir.join(name)))
            .find(|p| p.is_file())
    });
    if found.is_some() {
        return found;
    }
    if std::env::var("SMOOTHLAB_SKIP_BROWSER_TESTS").is_ok_and(|v| v == "1") {
        eprintln!("browser test skipped: SMOOTHLAB_SKIP_BROWSER_TESTS=1 and no Chromium found");
        return None;
    }
    panic!(
        "headless Chromium is needed to test the results page and was not found on the PATH: \
         install it (Debian: `apt-get install -y chromium`), point SMOOTHLAB_CHROMIUM at the \
         binary, or set SMOOTHLAB_SKIP_BROWSER_TESTS=1 to skip the browser tests"
    );
}

/// What the page reported about itself in the browser.
#[derive(Debug)]
struct PageCheck {
    ready: bool,
    tables: usize,
    images: usize,
    errors: usize,
    messages: String,
    /// The width of the page's viewport, CSS pixels.
    viewport: usize,
    /// Tables wider than the page or than their box (they would scroll sideways).
    wide_tables: usize,
    /// The step changes listed under the trend plots.
    steps: usize,
    /// The DOM after `load`.
    dom: String,
}

/// The value of attribute `name` in the `<body …>` tag of `dom`.
fn body_attribute<'a>(dom: &'a str, name: &str) -> Option<&'a str> {
    let start = dom.find("<body")?;
    let tag = &dom[start..start + dom[start..].find('>')?];
    let key = format!("{name}=\"");
    let from = tag.find(&key)? + key.len();
    Some(&tag[from..from + tag[from..].find('"')?])
}

/// Loads `page` in headless Chromium: the DOM after `load` (the page's self-check) and a
/// screenshot into `shot`.
fn open_in_browser(browser: &Path, page: &Path, shot: &Path) -> PageCheck {
    open_at_width(browser, page, shot, 1280)
}

/// [`open_in_browser`] with a window `width` pixels wide.
fn open_at_width(browser: &Path, page: &Path, shot: &Path, width: u32) -> PageCheck {
    let url = format!(
        "file://{}",
        page.canonicalize().expect("page path").display()
    );
    let profile = shot.with_extension("profile");
    let run = |extra: &[&str]| {
        let out = Command::new(browser)
            .args([
                "--headless",
                "--disable-gpu",
                "--no-sandbox",
                "--no-first-run",
                "--hide-scrollbars",
                "--virtual-time-budget=20000",
            ])
            .arg(format!("--window-size={width},1600"))
            .arg(format!("--user-data-dir={}", profile.display()))
            .args(extra)
            .arg(&url)
            .output()
            .expect("run chromium");
        assert!(
            out.status.success(),
            "chromium failed: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        out
    };
    let dom = String::from_utf8(run(&["--dump-dom"]).stdout).expect("utf-8 DOM");
    run(&[&format!("--screenshot={}", shot.display())]);
    let png = std::fs::read(shot).expect("screenshot written");
    assert!(png.starts_with(b"\x89PNG"), "screenshot is a PNG");
    eprintln!("screenshot: {}", shot.display());
    let number = |name: &str| {
        body_attribute(&dom, name)
            .and_then(|v| v.parse().ok())
            .unwrap_or(usize::MAX)
    };
    let messages = dom
        .split("<pre id=\"page-errors\">")
        .nth(1)
        .and_then(|rest| rest.split("</pre>").next())
        .unwrap_or("(no page-errors element)")
        .to_string();
    PageCheck {
        ready: body_attribute(&dom, "data-ready") == Some("true"),
        tables: number("data-tables"),
        images: number("data-images"),
        errors: number("data-errors"),
        messages,
        viewport: number("data-viewport"),
        wide_tables: number("data-wide-tables"),
        steps: number("data-steps"),
        dom,
    }
}

/// The page must have run its check with no error and shown every table and image.
fn assert_page_ok(check: &PageCheck, tables: usize, images: usize) {
    assert!(check.ready, "the page's script did not finish: {check:?}");
    assert_eq!(check.errors, 0, "errors in the page: {}", check.messages);
    assert_eq!(check.tables, tables, "sortable tables: {check:?}");
    assert_eq!(check.images, images, "images shown: {check:?}");
}

/// The figure tables of a report's page.
fn table_count(report: &report::Report) -> usize {
    page::table_figures(report).len()
}

/// The trend plots of the history in the report folder `dir`.
fn trend_count(dir: &Path) -> usize {
    let runs = history::read_dir(&dir.join(history::HISTORY)).expect("history");
    trends::trends(&runs).0.len()
}

/// The committed `results/index.html` (the acceptance check of `.ci/run`).
#[test]
fn committed_results_page_renders_in_a_browser() {
    let Some(browser) = chromium() else { return };
    let results = Path::new(env!("CARGO_MANIFEST_DIR")).join("results");
    let recorded = report::read(&results.join("metrics.json")).expect("results/metrics.json");
    let html = std::fs::read_to_string(results.join(page::PAGE)).expect("results/index.html");
    page::check_references(&html, &results).expect("every referenced file is committed");
    let dir = scratch("committed");
    let check = open_in_browser(
        &browser,
        &results.join(page::PAGE),
        &dir.join("results.png"),
    );
    assert_page_ok(
        &check,
        table_count(&recorded),
        plots::PLOTS.len()
            + trend_count(&results)
            + page::THUMB_MODES.len() * recorded.records.len(),
    );
    assert!(trend_count(&results) > 0, "results/ carries its history");
}

/// `report --baseline`: a bad baseline is refused before any work; a good one adds the table of
/// changes to a page that renders cleanly, and a second summary line.
#[test]
fn a_report_with_a_baseline_renders_in_a_browser() {
    let dir = scratch("baseline");
    let out_dir = dir.join("out");
    let out_str = out_dir.to_str().expect("utf-8");
    // A metrics --json style list is no report: one error line naming the file.
    let bad = dir.join("list.json");
    std::fs::write(&bad, "[{\"scheme\":\"hb\"}]").expect("write");
    let out = common::smoothlab(&[
        "report",
        "--out",
        out_str,
        "--baseline",
        bad.to_str().expect("utf-8"),
    ]);
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.starts_with("error: ") && stderr.contains("list.json: not a smoothlab report"),
        "{stderr}"
    );
    assert!(!out_dir.join(page::PAGE).exists(), "nothing written");

    // The committed report, with one quality figure made better than it is now: the new run
    // must flag it as a regression on the page.
    let committed = Path::new(env!("CARGO_MANIFEST_DIR")).join("results/metrics.json");
    let mut old = report::read(&committed).expect("results/metrics.json");
    let target = old
        .records
        .iter_mut()
        .find(|r| r.mesh == "torus" && r.scheme == "hb")
        .expect("torus / hb recorded");
    target
        .figures
        .insert("bending_energy".into(), serde_json::json!(1e-3));
    let baseline = dir.join("old.json");
    std::fs::write(&baseline, serde_json::to_string(&old).expect("json")).expect("write");
    let out = common::smoothlab(&[
        "report",
        "--out",
        out_str,
        "--baseline",
        baseline.to_str().expect("utf-8"),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(lines.len(), 2, "{stdout}");
    assert!(lines[0].starts_with("report: "), "{stdout}");
    assert!(
        lines[1].starts_with(&format!("baseline {}: ", baseline.display())),
        "{stdout}"
    );
    let new = report::read(&out_dir.join("metrics.json")).expect("new report");
    let html = std::fs::read_to_string(out_dir.join(page::PAGE)).expect("page");
    assert!(
        html.contains(
            "<tr class=\"worse\"><td>torus / hb</td><td>bending_energy</td><td data-v=\"1e-3\">"
        ),
        "the injected regression is on the page"
    );
    // The changed cell is marked worse (and may also be marked as the mesh's best or worst
    // scheme).
    let at = html
        .find("title=\"WORSE: before 1.000e-3, x")
        .expect("the changed cell of the bending-energy table is marked");
    let cell = &html[html[..at].rfind("<td").expect("its cell")..at];
    assert!(
        cell.starts_with("<td class=\"worse"),
        "the changed cell is marked worse: {cell}"
    );
    let thumbs = std::fs::read_dir(out_dir.join(page::THUMBS))
        .expect("thumbs")
        .count();
    assert_eq!(thumbs, page::THUMB_MODES.len() * new.records.len());
    let Some(browser) = chromium() else { return };
    let check = open_in_browser(&browser, &out_dir.join(page::PAGE), &dir.join("page.png"));
    assert_page_ok(
        &check,
        table_count(&new) + 1,
        plots::PLOTS.len() + trend_count(&out_dir) + page::THUMB_MODES.len() * new.records.len(),
    );
}

/// The check can fail: the committed page copied without its images and with a script error
/// reports both.
#[test]
fn the_browser_check_catches_a_broken_page() {
    let Some(browser) = chromium() else { return };
    let dir = scratch("broken");
    let results = Path::new(env!("CARGO_MANIFEST_DIR")).join("results");
    let html = std::fs::read_to_string(results.join(page::PAGE)).expect("results/index.html");
    let broken = html.replacen(
        "</body>",
        "<script>undefinedFunctionOfTheTest();</script></body>",
        1,
    );
    assert_ne!(broken, html, "script injected");
    let path = dir.join(page::PAGE);
    std::fs::write(&path, broken).expect("write");
    let check = open_in_browser(&browser, &path, &dir.join("broken.png"));
    assert!(check.ready, "{check:?}");
    assert_eq!(check.images, 0, "{check:?}");
    assert!(check.errors > 1, "{check:?}");
    assert!(
        check.messages.contains("undefinedFunctionOfTheTest"),
        "{}",
        check.messages
    );
    assert!(
        check.messages.contains("failed to load img thumbs/"),
        "{}",
        check.messages
    );
}

/// Meshes named with HTML and URL characters (`'`, `&`, `"`, `<`, `>`, `#`, `%`, spaces): the
/// report writes its page, and the browser loads every thumbnail under its own name.
#[test]
fn meshes_with_markup_and_url_characters_in_their_names_show_on_the_page() {
    let dir = scratch("odd-names");
    let meshes = dir.join("meshes");
    std::fs::create_dir_all(&meshes).expect("folder");
    let s = smoothlab::mesh::generate::analytic::sphere(0);
    let obj = smoothlab::mesh::generate::to_obj(&(s.positions, s.faces));
    let names = [
        "Bob's chair.obj",
        "a & \"b\" <c>.obj",
        "hash#1.obj",
        "pct%41.obj",
        "comma,name.obj",
    ];
    for name in names {
        std::fs::write(meshes.join(name), &obj).expect("mesh");
    }
    // A raw `pct%41` would be loaded as `pctA`, which is not there: the browser reports it.
    let out_dir = dir.join("out");
    let out = common::smoothlab(&[
        "report",
        "--meshes",
        meshes.to_str().expect("utf-8"),
        "--scheme",
        "flat",
        "--out",
        out_dir.to_str().expect("utf-8"),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let new = report::read(&out_dir.join("metrics.json")).expect("report");
    assert_eq!(new.records.len(), names.len());
    assert!(new.records.iter().all(|r| r.error.is_none()), "{new:?}");
    let html = std::fs::read_to_string(out_dir.join(page::PAGE)).expect("page");
    assert!(
        html.contains("src=\"thumbs/pct%2541.obj-flat-zebra.png\""),
        "percent-encoded"
    );
    assert!(
        html.contains("src=\"thumbs/hash%231.obj-flat-zebra.png\""),
        "percent-encoded"
    );
    let Some(browser) = chromium() else { return };
    let check = open_in_browser(&browser, &out_dir.join(page::PAGE), &dir.join("page.png"));
    assert_page_ok(
        &check,
        table_count(&new),
        plots::PLOTS.len() + trend_count(&out_dir) + page::THUMB_MODES.len() * new.records.len(),
    );
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

/// The acceptance test of the history: three reports on three commits of a scratch repository,
/// the third with a worse hb parameter (`alpha=0.5` no longer interpolates the vertices), make
/// a page whose `interp_max_rel` trend marks one step, worse, at the third commit — and none
/// elsewhere — and whose tables fit a 1400 px window without scrolling sideways.
#[test]
fn three_commits_with_a_regression_show_the_step_at_its_commit() {
    let dir = scratch("history");
    let repo = dir.join("repo");
    std::fs::create_dir_all(&repo).expect("repo");
    git(&repo, &["init", "-q"]);
    let meshes = dir.join("meshes");
    std::fs::create_dir_all(&meshes).expect("meshes");
    for (name, level) in [("ico.obj", 0), ("sphere-80.obj", 1)] {
        let s = smoothlab::mesh::generate::analytic::sphere(level);
        let obj = smoothlab::mesh::generate::to_obj(&(s.positions, s.faces));
        std::fs::write(meshes.join(name), obj).expect("mesh");
    }
    let out_dir = dir.join("results");
    let mut commits = Vec::new();
    for (k, extra) in [&[][..], &[][..], &["--param", "alpha=0.5"][..]]
        .iter()
        .enumerate()
    {
        git(
            &repo,
            &[
                "commit",
                "-q",
                "--allow-empty",
                "-m",
                &format!("change {k}"),
            ],
        );
        commits.push(git(&repo, &["rev-parse", "HEAD"]));
        let mut args = vec![
            "report",
            "--meshes",
            meshes.to_str().expect("utf-8"),
            "--scheme",
            "hb,pn",
            "--out",
            out_dir.to_str().expect("utf-8"),
        ];
        args.extend_from_slice(extra);
        let out = Command::new(env!("CARGO_BIN_EXE_smoothlab"))
            .args(&args)
            .current_dir(&repo)
            .output()
            .expect("run smoothlab");
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        // Runs are ordered by their date (seconds): one second between them.
        std::thread::sleep(std::time::Duration::from_millis(1100));
    }
    // One entry per commit, in run order.
    let runs = history::read_dir(&out_dir.join(history::HISTORY)).expect("history");
    let order: Vec<&str> = runs.iter().map(|e| e.commit.as_str()).collect();
    assert_eq!(
        order,
        commits.iter().map(String::as_str).collect::<Vec<_>>()
    );
    let files = std::fs::read_dir(out_dir.join(history::HISTORY))
        .expect("history folder")
        .count();
    assert_eq!(files, 3);
    let recorded = report::read(&out_dir.join("metrics.json")).expect("report");
    assert_eq!(recorded.commit, commits[2]);
    let hb = recorded
        .records
        .iter()
        .find(|r| r.scheme == "hb" && r.mesh == "ico.obj")
        .expect("hb keeps its name under --param");
    assert_eq!(hb.figures["params"]["alpha"], "0.5");

    let html = std::fs::read_to_string(out_dir.join(page::PAGE)).expect("page");
    let Some(browser) = chromium() else { return };
    let check = open_at_width(
        &browser,
        &out_dir.join(page::PAGE),
        &dir.join("page.png"),
        1400,
    );
    assert_page_ok(
        &check,
        table_count(&recorded),
        plots::PLOTS.len()
            + trend_count(&out_dir)
            + page::THUMB_MODES.len() * recorded.records.len(),
    );
    assert_eq!(check.viewport, 1400, "{check:?}");
    assert_eq!(check.wide_tables, 0, "tables scroll sideways at 1400 px");
    // The step of hb's interpolation error on both meshes, at the third commit, worse; pn did
    // not change, and nothing changed at the second commit.
    let steps: Vec<&str> = check
        .dom
        .split("<li class=\"step ")
        .skip(1)
        .map(|li| &li[..li.find("</li>").expect("closed")])
        .collect();
    assert_eq!(check.steps, steps.len());
    let marker = |mesh: &str| {
        format!(
            "worse\" data-figure=\"interp_max_rel\" data-record=\"{mesh} / hb\" data-commit=\"{}\"",
            commits[2]
        )
    };
    for mesh in ["ico.obj", "sphere-80.obj"] {
        assert!(
            steps.iter().any(|s| s.starts_with(&marker(mesh))),
            "no step marked for {mesh}: {steps:#?}"
        );
    }
    // (Timings on a shared machine may step anywhere; quality may not.)
    assert!(
        steps
            .iter()
            .filter(|s| !s.contains("data-figure=\"construct_ms\""))
            .all(|s| s.contains(&commits[2]) && s.contains("/ hb\"")),
        "quality steps only at the third commit, only for hb: {steps:#?}"
    );
    // The plot marks it at that commit (the axis shows the short commit).
    let svg = std::fs::read_to_string(out_dir.join(trends::trend_file("interp_max_rel")))
        .expect("trend plot");
    let short: String = runs
        .last()
        .expect("run")
        .short_commit()
        .chars()
        .take(8)
        .collect();
    assert!(
        svg.contains(&format!("step worse at {short}")),
        "marker in the plot"
    );
    assert!(html.contains("src=\"figures/trend-interp_max_rel.svg\""));
}

/// `report --baseline` compares the thumbnails too: one pixel changed in one of the
/// baseline's thumbnails is shown before / after / difference with its count, the others
/// (same pixels) are not listed, and the page renders with the three extra images.
#[test]
fn a_changed_thumbnail_is_shown_before_and_after_with_its_pixel_count() {
    let dir = scratch("image-changes");
    let meshes = dir.join("meshes");
    std::fs::create_dir_all(&meshes).expect("folder");
    std::fs::copy(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/icosahedron.obj"),
        meshes.join("icosahedron.obj"),
    )
    .expect("mesh");
    let run = |out: &Path, baseline: Option<&Path>| {
        let mut args = vec![
            "report",
            "--meshes",
            common::path_str(&meshes),
            "--out",
            common::path_str(out),
        ];
        if let Some(b) = baseline {
            args.extend(["--baseline", common::path_str(b)]);
        }
        let out = common::smoothlab(&args);
        assert!(out.status.success(), "{}", common::stderr(&out));
    };
    let (old, new) = (dir.join("old"), dir.join("new"));
    run(&old, None);
    let name = page::thumbnail_name("icosahedron.obj", "hb", "zebra");
    let mut image = image::open(old.join(&name)).expect("thumbnail").to_rgb8();
    let pixel = image.get_pixel(10, 20).0;
    image.put_pixel(10, 20, image::Rgb([pixel[0] ^ 0x40, pixel[1], pixel[2]]));
    image.save(old.join(&name)).expect("save");
    run(&new, Some(&old.join("metrics.json")));
    let html = std::fs::read_to_string(new.join(page::PAGE)).expect("page");
    let thumbnails = page::THUMB_MODES.len() * 8;
    assert!(
        html.contains(&format!(
            "1 of {thumbnails} thumbnail(s) differ from the baseline's."
        )),
        "{html}"
    );
    assert!(
        html.contains("<td>1 of 16384 (0.01 %), largest channel difference 64</td>"),
        "{html}"
    );
    let before = new.join("thumbs-baseline/icosahedron.obj-hb-zebra.png");
    assert_eq!(
        std::fs::read(&before).expect("copied baseline"),
        std::fs::read(old.join(&name)).expect("baseline"),
        "the baseline's own bytes"
    );
    let diff = image::open(new.join("thumbs-diff/icosahedron.obj-hb-zebra.png"))
        .expect("difference image")
        .to_rgb8();
    let marked: Vec<(u32, u32)> = diff
        .enumerate_pixels()
        .filter(|(_, _, p)| p.0 == [255, 0, 255])
        .map(|(x, y, _)| (x, y))
        .collect();
    assert_eq!(marked, [(10, 20)]);
    let Some(browser) = chromium() else { return };
    let report = report::read(&new.join("metrics.json")).expect("report");
    let check = open_in_browser(&browser, &new.join(page::PAGE), &dir.join("page.png"));
    assert_page_ok(
        &check,
        table_count(&report) + 1,
        plots::PLOTS.len() + trend_count(&new) + thumbnails + 3,
    );
}
