//! Sharded runs merged: `report --meshes` over a folder of 50 generated meshes in 4 shards,
//! a parameter sweep in 2, a 36-frame turntable in 3 and the cells of a figure in 3, each
//! merged by `smoothlab merge` and compared with the single run — records equal figure for
//! figure (timings aside), thumbnails, frames, GIF, figure sheets and cell EXRs the same bytes. The shards run through GNU parallel when it is installed
//! (`.ci/run` installs it), else as plain processes. A missing shard is named by `merge` and its
//! items are written as errors; parts of different runs are refused.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use smoothlab::mesh::generate::{self, analytic};

mod common;
use common::{assert_fails_naming, path_str, scratch, smoothlab, stderr};

fn ok(out: &Output) -> String {
    assert!(out.status.success(), "failed: {}", stderr(out));
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// 50 small closed meshes — icospheres of 20 and 80 faces and tori of 24 to 70 faces, scaled
/// and moved so that no two are alike — plus one file that is no mesh.
fn mesh_folder(dir: &Path) -> PathBuf {
    let folder = dir.join("meshes");
    std::fs::create_dir_all(&folder).expect("folder");
    for k in 0..50_u32 {
        let s = if k % 3 == 0 {
            analytic::torus(4 + k % 4, 3 + k % 3, 1.0, 0.4)
        } else {
            analytic::sphere(k % 2)
        };
        let scale = 1.0 + 0.1 * f64::from(k);
        let positions = s
            .positions
            .iter()
            .map(|p| *p * scale + glam::DVec3::new(f64::from(k), 0.0, 0.0))
            .collect();
        let text = generate::to_obj(&(positions, s.faces));
        std::fs::write(folder.join(format!("mesh-{k:02}.obj")), text).expect("write");
    }
    std::fs::write(folder.join("zz-broken.obj"), "v 0 0 0\nf 1 2 3\n").expect("write");
    folder
}

/// Runs `smoothlab ARGS --shard {i}/N` for every i: through GNU parallel when it is on the
/// PATH, else as N concurrent processes. `args` may contain `{}`, replaced by the shard index.
fn run_shards(args: &[String], n: u32) -> Vec<Output> {
    let bin = env!("CARGO_BIN_EXE_smoothlab");
    let has_parallel = Command::new("parallel")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if has_parallel {
        // One job per shard, at most 2 at once; `{}` is the shard index from the list.
        let out = Command::new("parallel")
            .args(["--will-cite", "--halt", "never", "-j", "2", bin])
            .args(args)
            .arg("--shard")
            .arg(format!("{{}}/{n}"))
            .arg(":::")
            .args((0..n).map(|i| i.to_string()))
            .output()
            .expect("run GNU parallel");
        assert!(out.status.success(), "parallel: {}", stderr(&out));
        return vec![out];
    }
    let children: Vec<_> = (0..n)
        .map(|i| {
            Command::new(bin)
                .args(args.iter().map(|a| a.replace("{}", &i.to_string())))
                .arg("--shard")
                .arg(format!("{i}/{n}"))
                .stdout(std::process::Stdio::piped())
                .stderr(std::process::Stdio::piped())
                .spawn()
                .expect("start shard")
        })
        .collect();
    children
        .into_iter()
        .map(|c| {
            let out = c.wait_with_output().expect("run shard");
            ok(&out);
            out
        })
        .collect()
}

fn read_json(path: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).expect("JSON")
}

/// The records of a `metrics.json`, timings removed.
fn records_without_timings(dir: &Path) -> Vec<serde_json::Value> {
    let report = read_json(&dir.join("metrics.json"));
    let mut records = report["records"].as_array().expect("records").clone();
    for r in &mut records {
        if let Some(figures) = r["figures"].as_object_mut() {
            for key in smoothlab::testing::report::TIMING_KEYS {
                figures.remove(key);
            }
        }
    }
    records
}

/// Every file of `dir` (name, bytes), sorted.
fn files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| {
            let path = e.expect("entry").path();
            let name = path
                .file_name()
                .expect("name")
                .to_string_lossy()
                .into_owned();
            (name, std::fs::read(&path).expect("read"))
        })
        .collect();
    out.sort();
    out
}

#[test]
fn fifty_meshes_in_four_shards_merge_to_the_single_run() {
    let dir = scratch("shard", "report");
    let meshes = mesh_folder(&dir);
    let m = path_str(&meshes);
    let single = dir.join("single");
    let stdout = ok(&smoothlab(&[
        "report",
        "--meshes",
        m,
        "--scheme",
        "flat,pn",
        "--out",
        path_str(&single),
    ]));
    assert!(stdout.contains("2 record(s) not measured"), "{stdout}");

    let shard_dir = |i: u32| dir.join(format!("shard-{i}"));
    let args: Vec<String> = ["report", "--meshes", m, "--scheme", "flat,pn", "--out"]
        .iter()
        .map(|s| s.to_string())
        .chain([format!("{}/shard-{{}}", dir.display())])
        .collect();
    run_shards(&args, 4);
    // Balanced by cost: every shard got work, and the meshes differ in size, so the counts
    // of meshes per shard are not simply 51/4.
    let mut counts = Vec::new();
    for i in 0..4 {
        let part = read_json(&shard_dir(i).join("partial.json"));
        assert_eq!(part["manifest"]["shard"]["index"], i);
        counts.push(part["items"].as_array().expect("items").len());
    }
    assert_eq!(counts.iter().sum::<usize>(), 51, "{counts:?}");
    assert!(counts.iter().all(|c| *c > 0), "{counts:?}");

    let merged = dir.join("merged");
    let parts: Vec<String> = (0..4)
        .map(|i| path_str(&shard_dir(i)).to_string())
        .collect();
    let mut merge: Vec<&str> = vec!["merge"];
    merge.extend(parts.iter().map(String::as_str));
    merge.extend(["-o", path_str(&merged)]);
    let stdout = ok(&smoothlab(&merge));
    assert!(stdout.contains("102 records (2 errors)"), "{stdout}");

    let (a, b) = (
        records_without_timings(&single),
        records_without_timings(&merged),
    );
    assert_eq!(a.len(), 102);
    assert!(a == b, "merged records differ from the single run");
    // The failed mesh is recorded, not dropped.
    let broken: Vec<&serde_json::Value> =
        b.iter().filter(|r| r["mesh"] == "zz-broken.obj").collect();
    assert_eq!(broken.len(), 2);
    assert!(
        broken[0]["error"]
            .as_str()
            .is_some_and(|e| e.contains("zz-broken.obj")),
        "{broken:?}"
    );
    let thumbs = files(&single.join("thumbs"));
    assert_eq!(thumbs.len(), 50 * 2 * 2);
    assert!(thumbs == files(&merged.join("thumbs")), "thumbnails differ");
    let report = read_json(&merged.join("metrics.json"));
    assert_eq!(report["shards"].as_array().expect("shards").len(), 4);
    assert!(
        std::fs::read_to_string(merged.join("metrics.md"))
            .expect("md")
            .contains("## Errors")
    );

    // Shard 2 missing: named, its items written as errors, exit code 1.
    let incomplete = dir.join("incomplete");
    let out = smoothlab(&[
        "merge",
        &parts[0],
        &parts[1],
        &parts[3],
        "-o",
        path_str(&incomplete),
    ]);
    assert_fails_naming(&out, &["shard 2/4 missing"]);
    let records = records_without_timings(&incomplete);
    assert_eq!(records.len(), 102);
    let lost: Vec<_> = records
        .iter()
        .filter(|r| {
            r["error"]
                .as_str()
                .is_some_and(|e| e.contains("shard 2/4 is missing"))
        })
        .collect();
    let part2 = read_json(&shard_dir(2).join("partial.json"));
    assert_eq!(
        lost.len(),
        part2["report"]["records"]
            .as_array()
            .expect("records")
            .len()
    );

    // A part of another run (another scheme list) is refused before anything is written.
    let other = dir.join("other");
    ok(&smoothlab(&[
        "report",
        "--meshes",
        m,
        "--scheme",
        "flat",
        "--out",
        path_str(&other),
        "--shard",
        "1/4",
    ]));
    let refused = dir.join("refused");
    let out = smoothlab(&[
        "merge",
        &parts[0],
        path_str(&other),
        "-o",
        path_str(&refused),
    ]);
    assert_fails_naming(&out, &["work list", "not shards of one run"]);
    assert!(!refused.join("metrics.json").exists());
}

#[test]
fn a_parameter_sweep_in_two_shards_merges_to_the_single_run() {
    let dir = scratch("shard", "sweep");
    let folder = dir.join("meshes");
    std::fs::create_dir_all(&folder).expect("folder");
    for (name, mesh) in [
        ("ico.obj", generate::icosahedron()),
        ("oct.obj", generate::octahedron()),
    ] {
        std::fs::write(folder.join(name), generate::to_obj(&mesh)).expect("write");
    }
    let list = dir.join("list.txt");
    std::fs::write(&list, "# the data set\nmeshes/ico.obj\nmeshes/oct.obj\n").expect("list");
    let sweep = dir.join("sweep.txt");
    std::fs::write(&sweep, "loop94:beta=0.5,0.8\n").expect("sweep file");
    let common_args = [
        "report",
        "--meshes",
        path_str(&list),
        "--sweep",
        "hb:beta=0.2,0.33",
        "--sweep-file",
        path_str(&sweep),
    ];
    let single = dir.join("single");
    let mut args = common_args.to_vec();
    args.extend(["--out", path_str(&single)]);
    ok(&smoothlab(&args));
    let records = records_without_timings(&single);
    let names: Vec<String> = records
        .iter()
        .map(|r| {
            format!(
                "{} {}",
                r["mesh"].as_str().unwrap(),
                r["scheme"].as_str().unwrap()
            )
        })
        .collect();
    assert_eq!(
        names,
        [
            "meshes/ico.obj hb:beta=0.2",
            "meshes/ico.obj hb:beta=0.33",
            "meshes/ico.obj loop94:beta=0.5",
            "meshes/ico.obj loop94:beta=0.8",
            "meshes/oct.obj hb:beta=0.2",
            "meshes/oct.obj hb:beta=0.33",
            "meshes/oct.obj loop94:beta=0.5",
            "meshes/oct.obj loop94:beta=0.8",
        ]
    );
    assert_eq!(records[0]["figures"]["params"]["beta"], "0.2");
    assert!(
        records[0]["figures"] != records[1]["figures"],
        "beta changes the surface"
    );

    let mut parts = Vec::new();
    for i in 0..2 {
        let part = dir.join(format!("part-{i}"));
        let mut args = common_args.to_vec();
        let shard = format!("{i}/2");
        args.extend(["--out", path_str(&part), "--shard", &shard]);
        ok(&smoothlab(&args));
        parts.push(path_str(&part.join("partial.json")).to_string());
    }
    let merged = dir.join("merged");
    ok(&smoothlab(&[
        "merge",
        &parts[0],
        &parts[1],
        "-o",
        path_str(&merged),
    ]));
    assert!(
        records == records_without_timings(&merged),
        "merged sweep differs"
    );
    assert!(files(&single.join("thumbs")) == files(&merged.join("thumbs")));
}

#[test]
fn a_turntable_in_three_shards_merges_bit_identically() {
    let dir = scratch("shard", "turntable");
    let mesh = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/deformed-icosahedron.obj");
    // Curvature with an automatic range: every shard takes the range of frame 0.
    let base = [
        "render",
        path_str(&mesh),
        "--scheme",
        "pn",
        "--mode",
        "curvature",
        "--size",
        "32x24",
        "--turntable",
        "36",
    ];
    let mut single = base.to_vec();
    let single_name = dir.join("single/spin");
    single.extend(["-o", path_str(&single_name)]);
    ok(&smoothlab(&single));

    let part_name = format!("{}/parts/spin", dir.display());
    let args: Vec<String> = base
        .iter()
        .map(|s| s.to_string())
        .chain(["-o".into(), part_name.clone()])
        .collect();
    run_shards(&args, 3);
    let parts: Vec<String> = (0..3)
        .map(|i| format!("{part_name}.shard-{i}-of-3.json"))
        .collect();
    let merged_name = dir.join("merged/spin");
    let stdout = ok(&smoothlab(&[
        "merge",
        &parts[2],
        &parts[0],
        &parts[1],
        "-o",
        path_str(&merged_name),
    ]));
    assert!(stdout.contains("merged 36 frames of 3 shards"), "{stdout}");
    let (a, b) = (files(&dir.join("single")), files(&dir.join("merged")));
    assert_eq!(a.len(), 37, "36 frames and the GIF");
    assert!(a == b, "merged frames or GIF differ from the single run");
    // In place: merging into the parts' own name writes the GIF beside the frames.
    ok(&smoothlab(&[
        "merge", &parts[0], &parts[1], &parts[2], "-o", &part_name,
    ]));
    assert_eq!(
        std::fs::read(format!("{part_name}.gif")).expect("gif"),
        std::fs::read(dir.join("single/spin.gif")).expect("gif")
    );

    // A missing shard is named; no GIF is made from an incomplete set.
    let out = smoothlab(&[
        "merge",
        &parts[0],
        &parts[2],
        "-o",
        path_str(&dir.join("x/spin")),
    ]);
    assert_fails_naming(&out, &["shard 1/3 missing"]);
    // A deleted frame is named too.
    std::fs::remove_file(format!("{part_name}-004.png")).expect("remove");
    let out = smoothlab(&[
        "merge",
        &parts[0],
        &parts[1],
        &parts[2],
        "-o",
        path_str(&merged_name),
    ]);
    assert_fails_naming(&out, &["spin-004.png", "frame 4 is missing"]);
}

/// A figure of flat, pn and hb on the deformed icosahedron, zebra and curvature (with the
/// common automatic range), 64 x 48 pixels per cell, written to `output`.
fn figure_spec(dir: &Path, name: &str, output: &str) -> PathBuf {
    let spec = dir.join(name);
    let text = format!(
        r#"title = "sharded"
mesh = "deformed-icosahedron"
output = "{output}"
size = [64, 48]
spp = 2
[[schemes]]
name = "flat"
[[schemes]]
name = "pn"
[[schemes]]
name = "hb"
[[modes]]
name = "zebra"
curves = true
[[modes]]
name = "curvature"
"#
    );
    std::fs::write(&spec, text).expect("write spec");
    spec
}

#[test]
fn a_figure_in_three_shards_merges_bit_identically() {
    let dir = scratch("shard", "figure");
    let single = figure_spec(&dir, "single.toml", "single/fig");
    let stdout = ok(&smoothlab(&["figure", path_str(&single)]));
    assert!(stdout.contains("6 EXR cells"), "{stdout}");

    let sharded = figure_spec(&dir, "sharded.toml", "parts/fig");
    run_shards(&["figure".into(), path_str(&sharded).into()], 3);
    let parts: Vec<String> = (0..3)
        .map(|i| format!("{}/parts/fig.shard-{i}-of-3.json", dir.display()))
        .collect();
    // Cells in sheet order: flat, pn, hb × zebra, curvature. Balanced by cost (hb renders
    // about 3.5 times as dear as flat, pn 2.3 times), not dealt round robin ([0, 3], [1, 4],
    // [2, 5]): each hb cell shares a shard with a flat one, the pn cells go together.
    let rendered: Vec<serde_json::Value> = parts
        .iter()
        .map(|p| read_json(Path::new(p))["rendered"].clone())
        .collect();
    assert_eq!(
        rendered,
        [
            serde_json::json!([0, 4]),
            serde_json::json!([1, 5]),
            serde_json::json!([2, 3])
        ]
    );
    let merged = dir.join("merged/fig");
    let stdout = ok(&smoothlab(&[
        "merge",
        &parts[1],
        &parts[2],
        &parts[0],
        "-o",
        path_str(&merged),
    ]));
    assert!(stdout.contains("merged 6 cells of 3 shards"), "{stdout}");
    let (a, b) = (files(&dir.join("single")), files(&dir.join("merged")));
    let names: Vec<&str> = a.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        [
            "fig-0-0-flat-zebra.exr",
            "fig-0-1-flat-curvature.exr",
            "fig-1-0-pn-zebra.exr",
            "fig-1-1-pn-curvature.exr",
            "fig-2-0-hb-zebra.exr",
            "fig-2-1-hb-curvature.exr",
            "fig.png",
            "fig.svg"
        ]
    );
    for ((name, x), (other, y)) in a.iter().zip(&b) {
        assert_eq!(name, other);
        assert!(x == y, "{name} of the merge differs from the single run");
    }
    assert_eq!(a.len(), b.len());

    // A missing shard is named; nothing is written.
    let nowhere = dir.join("incomplete/fig");
    let out = smoothlab(&["merge", &parts[0], &parts[2], "-o", path_str(&nowhere)]);
    assert_fails_naming(&out, &["shard 1/3 missing", "not merged"]);
    assert!(!dir.join("incomplete").exists());
    // So is a cell whose file is gone (its shard did not finish).
    std::fs::remove_file(dir.join("parts/fig-2-1-hb-curvature.png")).expect("remove");
    let out = smoothlab(&[
        "merge",
        &parts[0],
        &parts[1],
        &parts[2],
        "-o",
        path_str(&nowhere),
    ]);
    assert_fails_naming(&out, &["fig-2-1-hb-curvature.png", "cell 5 is missing"]);
    assert!(!dir.join("incomplete/fig.png").exists());
}

#[test]
fn bad_shards_are_one_line_errors() {
    let dir = scratch("shard", "bad");
    let mesh = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/deformed-icosahedron.obj");
    let m = path_str(&mesh);
    let out_dir = path_str(&dir);
    assert_fails_naming(
        &smoothlab(&["report", "--out", out_dir, "--shard", "4/4"]),
        &["shard '4/4'", "below the count"],
    );
    assert_fails_naming(
        &smoothlab(&[
            "render", m, "--scheme", "flat", "--shard", "0/2", "-o", out_dir,
        ]),
        &["--shard", "--turntable or --sweep"],
    );
    assert_fails_naming(
        &smoothlab(&["report", "--out", out_dir, "--sweep", "hb:beta"]),
        &["--sweep", "'beta' is not NAME=V1"],
    );
    assert_fails_naming(
        &smoothlab(&[
            "report",
            "--out",
            out_dir,
            "--meshes",
            path_str(&dir.join("none")),
        ]),
        &["none"],
    );
    let not_part = dir.join("x.json");
    std::fs::write(&not_part, "{}").expect("write");
    assert_fails_naming(
        &smoothlab(&["merge", path_str(&not_part), "-o", out_dir]),
        &["x.json", "not a smoothlab partial result"],
    );
}

/// `path` (JSON) with `edit` applied.
fn edit_json(path: &Path, to: &Path, edit: impl Fn(&mut serde_json::Value)) {
    let mut value = read_json(path);
    edit(&mut value);
    std::fs::write(to, serde_json::to_string(&value).expect("JSON")).expect("write");
}

#[test]
fn damaged_report_parts_are_named_with_the_field_at_fault() {
    let dir = scratch("shard", "damaged");
    let meshes = dir.join("meshes");
    std::fs::create_dir_all(&meshes).expect("folder");
    for k in 0..3 {
        let s = analytic::sphere(0);
        let positions = s.positions.iter().map(|p| *p * f64::from(k + 1)).collect();
        std::fs::write(
            meshes.join(format!("s{k}.obj")),
            generate::to_obj(&(positions, s.faces)),
        )
        .expect("write");
    }
    let shard_dir = dir.join("s0");
    ok(&smoothlab(&[
        "report",
        "--meshes",
        path_str(&meshes),
        "--scheme",
        "flat",
        "--out",
        path_str(&shard_dir),
        "--shard",
        "0/2",
    ]));
    let part = shard_dir.join("partial.json");
    let damaged = shard_dir.join("damaged.json");
    let merged = dir.join("merged");
    type Edit = fn(&mut serde_json::Value);
    let cases: [(&str, Edit, &[&str]); 4] = [
        (
            "an item out of range",
            |v| v["items"] = serde_json::json!([99]),
            &["damaged.json: items:", "damaged part"],
        ),
        (
            "a huge shard count",
            |v| v["manifest"]["shard"]["count"] = serde_json::json!(4_000_000_000_u32),
            &["damaged.json: manifest.shard.count 4000000000"],
        ),
        (
            "an index past the count",
            |v| v["manifest"]["shard"]["index"] = serde_json::json!(5),
            &["damaged.json: manifest.shard.index 5"],
        ),
        (
            "records dropped",
            |v| v["report"]["records"] = serde_json::json!([]),
            &["damaged.json: report.records: 0 records"],
        ),
    ];
    for (what, edit, fragments) in cases {
        edit_json(&part, &damaged, edit);
        let out = smoothlab(&["merge", path_str(&damaged), "-o", path_str(&merged)]);
        assert!(!stderr(&out).contains("memory allocation"), "{what}");
        assert_fails_naming(&out, fragments);
        assert!(!merged.exists(), "{what}: nothing written");
    }
}

#[test]
fn merged_frames_named_as_a_folder_are_refused() {
    let dir = scratch("shard", "merge-folder");
    let mesh = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/deformed-icosahedron.obj");
    let name = dir.join("spin");
    for shard in ["0/2", "1/2"] {
        ok(&smoothlab(&[
            "render",
            path_str(&mesh),
            "--scheme",
            "flat",
            "--size",
            "8x8",
            "--spp",
            "1",
            "--turntable",
            "2",
            "--shard",
            shard,
            "-o",
            path_str(&name),
        ]));
    }
    let part = |i: u32| format!("{}.shard-{i}-of-2.json", name.display());
    let slash = format!("{}/slash/", dir.display());
    let out = smoothlab(&["merge", &part(0), &part(1), "-o", &slash]);
    assert_fails_naming(&out, &["slash/", "is a folder"]);
    assert!(!dir.join("slash").exists(), "nothing written");
    // A part whose frame list is shorter than the frames it rendered is named, not indexed
    // past its end.
    let damaged = dir.join("damaged.json");
    edit_json(Path::new(&part(1)), &damaged, |v| {
        v["frames"] = serde_json::json!(["spin-000.png"]);
    });
    let out = smoothlab(&[
        "merge",
        &part(0),
        path_str(&damaged),
        "-o",
        path_str(&dir.join("m")),
    ]);
    assert_fails_naming(
        &out,
        &["damaged.json: frames lists 1 names, rendered names frame 1"],
    );
}
