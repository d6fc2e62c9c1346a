//! Recorded results: every registered scheme (default parameters) built on the benchmark
//! meshes — the closed scenes and meshes sampled from analytic surfaces with exact normals — and
//! measured: all metrics, the bending energy, and on analytic meshes the distance and normal
//! error to the true surface. Written as `metrics.json` (the machine-readable record that
//! [`compare`] reads), `metrics.csv` and `metrics.md`, stamped with the git commit (with a
//! dirty flag), the date, the tool version and the machine's fingerprint ([`provenance`]).
//!
//! Construction times are the median of [`TIMING_RUNS`] builds for schemes whose first build
//! takes under [`CHEAP_BUILD_MS`], with the spread recorded as `construct_ms_spread_rel`
//! ((slowest − fastest) / median); slower builds are timed once (`construct_ms_runs` = 1, no
//! spread).

pub mod analytic;
pub mod batch;
pub mod compare;
pub mod history;
pub mod image_changes;
pub mod page;
pub mod partial;
pub mod plots;
pub mod provenance;
pub mod shard;
pub mod trends;

use std::path::Path;
use std::time::{SystemTime, UNIX_EPOCH};

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Problem, Result};
use crate::files::{check_distinct, check_writable, create_folder, write_atomic};
use crate::mesh::{Mesh, generate};
use crate::metrics::Metrics;
use crate::metrics::energy::bending_energy;
use crate::schemes::{self, SCHEMES};
use crate::surface::Surface;
use analytic::{Analytic, curvature_error, surface_error, vertex_curvature_error};

/// The format version of `metrics.json` that this build writes and reads.
pub const REPORT_VERSION: u32 = 1;

/// How many times a cheap construction is timed; the report records the median.
pub const TIMING_RUNS: usize = 5;

/// A construction whose first build takes less than this (milliseconds) is timed
/// [`TIMING_RUNS`] times; a slower one once, which keeps the report's run time low.
pub const CHEAP_BUILD_MS: f64 = 50.0;

/// A mesh the report measures every scheme on.
pub struct BenchmarkMesh {
    /// Name in the report.
    pub name: String,
    /// The mesh.
    pub mesh: Mesh,
    /// The surface it was sampled from, if any.
    pub analytic: Option<Analytic>,
}

/// The benchmark meshes: the closed scenes, an icosphere (level 2), an ellipsoid (level 2) and
/// a 24 × 12 torus sampled from their analytic surfaces.
pub fn benchmark_meshes() -> Result<Vec<BenchmarkMesh>> {
    let mut out = Vec::new();
    for scene in generate::SCENES.iter() {
        out.push(BenchmarkMesh {
            name: scene.name.to_string(),
            mesh: scene.mesh()?,
            analytic: None,
        });
    }
    let radii = DVec3::new(1.0, 0.8, 1.3);
    let sampled = [
        (
            "sphere-320",
            generate::analytic::sphere(2),
            Analytic::Sphere { radius: 1.0 },
        ),
        (
            "ellipsoid-320",
            generate::analytic::ellipsoid(radii, 2),
            Analytic::Ellipsoid { radii },
        ),
        (
            "torus-576",
            generate::analytic::torus(24, 12, 1.0, 0.4),
            Analytic::Torus {
                major: 1.0,
                minor: 0.4,
            },
        ),
    ];
    for (name, s, analytic) in sampled {
        out.push(BenchmarkMesh {
            name: name.to_string(),
            mesh: Mesh::from_triangles(s.positions, s.faces)?.0,
            analytic: Some(analytic),
        });
    }
    Ok(out)
}

/// One scheme on one benchmark mesh.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Record {
    /// Benchmark mesh name.
    pub mesh: String,
    /// Scheme name.
    pub scheme: String,
    /// Every figure of the metrics JSON, by its key.
    pub figures: serde_json::Map<String, serde_json::Value>,
    /// Why the record has no figures: its mesh did not load or its scheme did not build on it
    /// (a batch records failures instead of stopping), or its shard is missing from a merge.
    /// Absent when it was measured.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
}

/// One shard of a merged report: where and when it ran.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShardRun {
    /// The shard (`I/N`).
    pub shard: shard::Shard,
    /// UTC date and time the shard finished.
    pub date: String,
    /// The machine it ran on (its timings were measured there).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub machine: Option<provenance::Machine>,
    /// Its wall time, seconds.
    pub seconds: f64,
}

/// A whole report.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Report {
    /// Always `smoothlab-report`.
    pub format: String,
    /// Format version.
    pub version: u32,
    /// `git rev-parse HEAD` of the working tree, or `unknown`.
    pub commit: String,
    /// UTC date and time of the run (ISO 8601).
    pub date: String,
    /// The records, meshes in benchmark order, schemes in registry order.
    pub records: Vec<Record>,
    /// `git describe --always --dirty` of the working tree (`-dirty`: files differ from the
    /// commit), or `unknown`. Absent in reports of earlier versions.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub describe: Option<String>,
    /// True if the working tree differed from the commit. Absent when unknown.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dirty: Option<bool>,
    /// The smoothlab version that wrote the report. Absent in reports of earlier versions.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tool_version: Option<String>,
    /// The machine the timings were measured on. Absent in reports of earlier versions, whose
    /// timings [`compare`] therefore judges only when forced.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub machine: Option<provenance::Machine>,
    /// The shards a merged report was measured in (`smoothlab merge`), in shard order; absent
    /// in reports of one process.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shards: Option<Vec<ShardRun>>,
}

impl Report {
    /// An empty report stamped with this run's provenance: commit, describe string, date,
    /// tool version and machine.
    pub fn stamped(records: Vec<Record>) -> Report {
        let describe = provenance::git_describe();
        Report {
            format: "smoothlab-report".into(),
            version: REPORT_VERSION,
            commit: git_commit(),
            date: utc_now(),
            records,
            dirty: (describe != "unknown").then(|| describe.ends_with("-dirty")),
            describe: Some(describe),
            tool_version: Some(provenance::tool_version()),
            machine: Some(provenance::Machine::current()),
            shards: None,
        }
    }
}

/// Builds `scheme` with `params` on `mesh` and times it: once when the build takes
/// [`CHEAP_BUILD_MS`] or more, else [`TIMING_RUNS`] times after that first (warm-up) build.
/// Returns the surface, the median time (ms), the number of runs and the relative spread (None
/// for one run).
fn build_median_timed(
    scheme: &str,
    mesh: &Mesh,
    params: &[(String, String)],
) -> Result<(Surface, f64, usize, Option<f64>)> {
    let (surface, first) = schemes::build_timed(scheme, mesh, params)?;
    if first >= CHEAP_BUILD_MS {
        return Ok((surface, first, 1, None));
    }
    // The first build warms the caches and one-time tables (e.g. hb's energy map): it only
    // decides that the build is cheap; the timed runs follow it.
    let mut times = Vec::with_capacity(TIMING_RUNS);
    for _ in 0..TIMING_RUNS {
        times.push(schemes::build_timed(scheme, mesh, params)?.1);
    }
    times.sort_by(f64::total_cmp);
    let median = times[times.len() / 2];
    let spread = if median > 0.0 {
        (times[times.len() - 1] - times[0]) / median
    } else {
        0.0
    };
    Ok((surface, median, times.len(), Some(spread)))
}

/// The keys of a record's figures that are timings: they differ from run to run and are left
/// out when runs are checked for equality (e.g. a merged report against a single run).
pub const TIMING_KEYS: [&str; 3] = [
    "construct_ms",
    "construct_ms_runs",
    "construct_ms_spread_rel",
];

/// Every registered scheme with its default parameters, in registry order.
pub fn default_variants() -> Vec<batch::Variant> {
    SCHEMES
        .iter()
        .map(|s| batch::Variant::default_of(s.name))
        .collect()
}

/// The work list of the benchmark meshes with `variants` on each: every variant whose scheme
/// accepts the mesh (a scheme that needs a closed mesh is left out on an open one).
pub fn benchmark_work(variants: &[batch::Variant]) -> Result<batch::WorkList> {
    let mut items = Vec::new();
    for bench in benchmark_meshes()? {
        let closed = bench.mesh.is_closed();
        let variants = variants
            .iter()
            .filter(|v| closed || schemes::find(&v.scheme).is_ok_and(|s| !s.needs_closed_mesh))
            .cloned()
            .collect();
        items.push(batch::WorkItem {
            faces: bench.mesh.face_count(),
            source: batch::MeshSource::Benchmark(bench.name.clone()),
            mesh: bench.name,
            variants,
        });
    }
    Ok(batch::WorkList::new(
        items,
        &crate::mesh::LoadOptions::default(),
    ))
}

/// Builds and measures `variant` on `mesh` (with its analytic surface, if any): one record and
/// the surface.
fn measure_variant(
    mesh_name: &str,
    mesh: &Mesh,
    analytic: Option<Analytic>,
    variant: &batch::Variant,
) -> Result<(Record, Surface)> {
    let (surface, ms, runs, spread) =
        build_median_timed(&variant.scheme, mesh, &variant.build_params())?;
    let metrics = Metrics::measure(&surface, mesh, ms);
    let mut figures = match serde_json::to_value(&metrics) {
        Ok(serde_json::Value::Object(map)) => map,
        _ => return Err(Error::Invalid("metrics did not serialise".into())),
    };
    figures.insert("construct_ms_runs".into(), runs.into());
    if let Some(spread) = spread {
        figures.insert("construct_ms_spread_rel".into(), spread.into());
    }
    figures.insert("bending_energy".into(), bending_energy(&surface).into());
    if let Some(a) = analytic {
        let diag = mesh.bounds().diagonal();
        let (max_d, mean_d, normal) = surface_error(&surface, &a);
        figures.insert("distance_max_rel".into(), (max_d / diag).into());
        figures.insert("distance_mean_rel".into(), (mean_d / diag).into());
        figures.insert("normal_error_max_rad".into(), normal.into());
        let k = curvature_error(&surface, &a);
        figures.insert("gaussian_error_max_rel".into(), k.gaussian_max_rel.into());
        figures.insert("gaussian_error_rms_rel".into(), k.gaussian_rms_rel.into());
        figures.insert("mean_error_max_rel".into(), k.mean_max_rel.into());
        figures.insert("mean_error_rms_rel".into(), k.mean_rms_rel.into());
        let (kv, h_lo, h_hi) = vertex_curvature_error(&surface, mesh.faces(), &a);
        figures.insert("vertex_mean_error_max_rel".into(), kv.mean_max_rel.into());
        figures.insert("vertex_mean_abs_min".into(), h_lo.into());
        figures.insert("vertex_mean_abs_max".into(), h_hi.into());
    }
    let record = Record {
        mesh: mesh_name.to_string(),
        scheme: variant.label(),
        figures,
        error: None,
    };
    Ok((record, surface))
}

/// A record that carries `error` instead of figures.
pub fn error_record(mesh: &str, variant: &batch::Variant, error: String) -> Record {
    Record {
        mesh: mesh.to_string(),
        scheme: variant.label(),
        figures: serde_json::Map::new(),
        error: Some(error),
    }
}

/// Checks that the mesh file `path` is a regular file that can be opened, with an error saying
/// what it is instead: a folder, a broken symbolic link or a link loop, a device or pipe.
fn check_mesh_file(path: &Path) -> Result<()> {
    let link = std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink());
    let problem = match std::fs::metadata(path) {
        Err(e) if link => {
            format!("a symbolic link that leads to no file (broken, or a loop of links): {e}")
        }
        Err(e) => return Err(Error::io(path, e)),
        Ok(meta) if meta.is_dir() => "is a folder, not a mesh file".to_string(),
        Ok(meta) if !meta.is_file() => {
            "is not a regular file (a device, pipe or socket), not a mesh file".to_string()
        }
        Ok(_) => return Ok(()),
    };
    Err(Error::Invalid(format!("{}: {problem}", path.display())))
}

/// What [`measure_items`] measured.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Measured {
    /// The records, items in the order given, variants in their order.
    pub records: Vec<Record>,
    /// The thumbnails of every item that has a built surface (when thumbnails were asked for).
    pub thumbnails: Vec<page::MeshThumbnails>,
    /// Warnings (one line each), e.g. a mesh loaded with repairs or thumbnails that failed.
    pub warnings: Vec<String>,
}

/// Measures the items `items` (positions in `work`) and, with `thumbs` (a report folder, whose
/// `thumbs/` must exist, and the thumbnail options), renders their thumbnails. A mesh that does
/// not load or a variant that does not build becomes records with the error; only a failure to
/// write a file stops the run. `progress(done, total, "mesh / variant")` is called before each
/// record and `progress(total, total, "")` at the end.
pub fn measure_items(
    work: &batch::WorkList,
    items: &[usize],
    thumbs: Option<(&Path, &page::ThumbnailOptions)>,
    progress: &dyn Fn(usize, usize, &str),
) -> Result<Measured> {
    let needs_benchmarks = items
        .iter()
        .any(|&k| matches!(work.items[k].source, batch::MeshSource::Benchmark(_)));
    let benchmarks = if needs_benchmarks {
        benchmark_meshes()?
    } else {
        Vec::new()
    };
    let total: usize = items.iter().map(|&k| work.items[k].variants.len()).sum();
    let mut out = Measured::default();
    for &k in items {
        let item = &work.items[k];
        let loaded = match &item.source {
            batch::MeshSource::Benchmark(name) => benchmarks
                .iter()
                .find(|b| &b.name == name)
                .map(|b| (std::borrow::Cow::Borrowed(&b.mesh), b.analytic))
                .ok_or_else(|| {
                    let message = format!("no benchmark mesh named '{name}'");
                    Error::config("mesh", Problem::Stated { message })
                }),
            batch::MeshSource::File(path) => check_mesh_file(path).and_then(|()| {
                Mesh::load_with(path, &work.load_options()).map(|(mesh, report)| {
                    out.warnings.extend(
                        report
                            .warnings
                            .into_iter()
                            .map(|w| format!("{}: {w}", item.mesh)),
                    );
                    (std::borrow::Cow::Owned(mesh), None)
                })
            }),
        };
        let (mesh, analytic) = match loaded {
            Ok(loaded) => loaded,
            Err(e) => {
                // The error names the file, whatever part of it is at fault.
                let mut error = e.to_string();
                if let batch::MeshSource::File(path) = &item.source
                    && !error.contains(&path.display().to_string())
                {
                    error = format!("{}: {error}", path.display());
                }
                for v in &item.variants {
                    progress(
                        out.records.len(),
                        total,
                        &format!("{} / {}", item.mesh, v.label()),
                    );
                    out.records.push(error_record(&item.mesh, v, error.clone()));
                }
                continue;
            }
        };
        let mut surfaces = Vec::new();
        for v in &item.variants {
            progress(
                out.records.len(),
                total,
                &format!("{} / {}", item.mesh, v.label()),
            );
            match measure_variant(&item.mesh, &mesh, analytic, v) {
                Ok((record, surface)) => {
                    out.records.push(record);
                    surfaces.push((v.label(), surface));
                }
                Err(e) => out.records.push(error_record(&item.mesh, v, e.to_string())),
            }
        }
        if let Some((dir, options)) = thumbs
            && !surfaces.is_empty()
        {
            match page::render_thumbnails(&item.mesh, &mesh, &surfaces, dir, options) {
                Ok(t) => out.thumbnails.push(t),
                Err(e @ Error::Io { .. }) => return Err(e),
                Err(e) => out
                    .warnings
                    .push(format!("{}: no thumbnails: {e}", item.mesh)),
            }
        }
    }
    progress(total, total, "");
    Ok(out)
}

fn git_commit() -> String {
    std::process::Command::new("git")
        .args(["rev-parse", "HEAD"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .map(|s| s.trim().to_string())
        .unwrap_or_else(|| "unknown".into())
}

/// The current UTC time as `YYYY-MM-DDTHH:MM:SSZ` (civil-from-days, proleptic Gregorian).
fn utc_now() -> String {
    let secs = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.as_secs()) as i64;
    let (days, rem) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}Z",
        rem / 3600,
        rem % 3600 / 60,
        rem % 60
    )
}

/// The columns of the CSV and Markdown tables (any figure a record lacks is left empty / `-`).
pub const COLUMNS: &[&str] = &[
    "patches",
    "construct_ms",
    "interp_max_rel",
    "g0_max_rel",
    "g1_between_faces_max_rad",
    "g1_inside_faces_max_rad",
    "curvature_jump_max_rel",
    "continuity_order",
    "continuity_order_typical",
    "min_regularity_rel",
    "network_undulation_max_rad",
    "bending_energy",
    "distance_max_rel",
    "normal_error_max_rad",
    "mean_error_max_rel",
    "mean_error_rms_rel",
    "gaussian_error_max_rel",
    "vertex_mean_abs_min",
    "vertex_flat_points",
];

fn value_text(v: Option<&serde_json::Value>) -> Option<String> {
    match v? {
        serde_json::Value::Number(n) if n.is_f64() => n.as_f64().map(|x| format!("{x:.3e}")),
        serde_json::Value::Number(n) => Some(n.to_string()),
        serde_json::Value::String(s) => Some(s.clone()),
        _ => None,
    }
}

/// One CSV field as RFC 4180 writes it: in double quotes, inner quotes doubled, when it holds
/// a comma, a quote or a line break; as it is otherwise.
fn csv_field(text: &str) -> std::borrow::Cow<'_, str> {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\"")).into()
    } else {
        text.into()
    }
}

/// `metrics.csv`: one row per record (RFC 4180: fields quoted where needed).
pub fn to_csv(report: &Report) -> String {
    let mut out = format!("mesh,scheme,{}\n", COLUMNS.join(","));
    for r in &report.records {
        let cells: Vec<String> = [r.mesh.clone(), r.scheme.clone()]
            .into_iter()
            .chain(
                COLUMNS
                    .iter()
                    .map(|c| value_text(r.figures.get(*c)).unwrap_or_default()),
            )
            .map(|cell| csv_field(&cell).into_owned())
            .collect();
        out += &cells.join(",");
        out += "\n";
    }
    out
}

/// `metrics.md`: a table per mesh.
pub fn to_markdown(report: &Report) -> String {
    let mut out = format!(
        "# smoothlab results\n\ncommit `{}`, {}. Lengths relative to the bounding-box diagonal, \
         angles in radians; written by `smoothlab report`.\n",
        report.describe.as_deref().unwrap_or(&report.commit),
        report.date
    );
    if let Some(machine) = &report.machine {
        out += &format!(
            "\nTimings (ms, median of up to {TIMING_RUNS} runs) measured on {}.\n",
            machine.describe()
        );
    }
    let mut meshes: Vec<&str> = report.records.iter().map(|r| r.mesh.as_str()).collect();
    meshes.dedup();
    for mesh in meshes {
        out += &format!("\n## {mesh}\n\n| scheme | {} |\n", COLUMNS.join(" | "));
        out += &format!("|---|{}\n", "---:|".repeat(COLUMNS.len()));
        for r in report.records.iter().filter(|r| r.mesh == mesh) {
            let cells: Vec<String> = COLUMNS
                .iter()
                .map(|c| value_text(r.figures.get(*c)).unwrap_or_else(|| "-".into()))
                .collect();
            out += &format!("| {} | {} |\n", r.scheme, cells.join(" | "));
        }
    }
    let errors: Vec<&Record> = report
        .records
        .iter()
        .filter(|r| r.error.is_some())
        .collect();
    if !errors.is_empty() {
        out += &format!(
            "\n## Errors\n\n{} record(s) not measured:\n\n",
            errors.len()
        );
        for r in errors {
            out += &format!(
                "- {} / {}: {}\n",
                r.mesh,
                r.scheme,
                r.error.as_deref().unwrap_or_default()
            );
        }
    }
    out
}

/// The tables [`write()`] writes into its folder.
const TABLES: [&str; 3] = ["metrics.json", "metrics.csv", "metrics.md"];

/// What [`write_with`] writes besides the tables and plots.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WriteOptions {
    /// A previous report (`metrics.json`) to compare the new one with on the page
    /// (`report --baseline`).
    pub baseline: Option<std::path::PathBuf>,
    /// Size and sampling of the page's thumbnails.
    pub thumbnails: page::ThumbnailOptions,
    /// The history folder whose runs the page's trends show (`report --history DIR`); None:
    /// the report folder's own `history/`. The run is recorded in the report folder's
    /// `history/` either way.
    pub history: Option<std::path::PathBuf>,
}

/// What [`write_with`] measured and wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct Written {
    /// The new report.
    pub report: Report,
    /// The comparison with the baseline, when one was given.
    pub comparison: Option<compare::Comparison>,
    /// The thumbnails of each benchmark mesh.
    pub thumbnails: Vec<page::MeshThumbnails>,
    /// Warnings of the run (one line each).
    pub warnings: Vec<String>,
}

/// Runs the report and writes `metrics.{json,csv,md}` into `out_dir`, the SVG plots of
/// [`plots`] into `out_dir/figures/` and the results page ([`page`]: `index.html`, thumbnails
/// in `out_dir/thumbs/`), folders created if missing. Every output path is checked before the
/// measurements start, and every file is written atomically.
pub fn write(out_dir: &Path) -> Result<Report> {
    write_with_progress(out_dir, &|_, _, _| {})
}

/// [`write()`], calling `progress(done, total, "mesh / scheme")` before each record is
/// measured and `progress(total, total, "")` at the end.
pub fn write_with_progress(
    out_dir: &Path,
    progress: &dyn Fn(usize, usize, &str),
) -> Result<Report> {
    Ok(write_with(out_dir, &WriteOptions::default(), progress)?.report)
}

/// [`write_with_progress`] with `options`: with a baseline, the baseline is read (it must be a
/// report, see [`read`]) before anything is measured, and the page lists the changes against it as
/// `compare --timings` judges them with the default thresholds.
pub fn write_with(
    out_dir: &Path,
    options: &WriteOptions,
    progress: &dyn Fn(usize, usize, &str),
) -> Result<Written> {
    write_work(
        out_dir,
        &benchmark_work(&default_variants())?,
        options,
        progress,
    )
}

/// The runs of the history the page's trends show: `options.history`, or the report folder's
/// own `history/` (a missing folder is an empty history). Read before anything is measured, so
/// that a damaged entry stops the run early.
fn read_history(out_dir: &Path, options: &WriteOptions) -> Result<Vec<history::Entry>> {
    match &options.history {
        Some(dir) if !dir.is_dir() => Err(Error::Invalid(format!(
            "--history {}: not a folder of history entries",
            dir.display()
        ))),
        Some(dir) => history::read_dir(dir),
        None => history::read_dir(&out_dir.join(history::HISTORY)),
    }
}

/// The baseline of `options`, read (it must be a report, see [`read`]).
fn read_baseline(options: &WriteOptions) -> Result<Option<(&Path, Report)>> {
    options
        .baseline
        .as_deref()
        .map(|path| read(path).map(|report| (path, report)))
        .transpose()
}

/// Creates the folders of a report in `out_dir` and checks that every file of it can be
/// written: the tables, the plots, the page and the thumbnails of `work`, none of them onto
/// one of the run's inputs (the mesh files of `work`, the `baseline`) or onto another of them
/// ([`check_distinct`]).
fn prepare_report_folder(
    out_dir: &Path,
    work: &batch::WorkList,
    baseline: Option<&Path>,
) -> Result<()> {
    let figures = out_dir.join("figures");
    create_folder(&figures)?;
    create_folder(&out_dir.join(page::THUMBS))?;
    create_folder(&out_dir.join(history::HISTORY))?;
    let mut outputs: Vec<std::path::PathBuf> = TABLES.map(|name| out_dir.join(name)).to_vec();
    outputs.extend(plots::plot_paths(&figures));
    outputs.extend(trends::trend_paths(out_dir));
    outputs.push(out_dir.join(page::PAGE));
    for item in &work.items {
        for v in &item.variants {
            for mode in page::THUMB_MODES {
                outputs.push(page::thumbnail_path(out_dir, &item.mesh, &v.label(), mode));
            }
        }
    }
    let mut inputs: Vec<(&str, &Path)> = work
        .items
        .iter()
        .filter_map(|item| match &item.source {
            batch::MeshSource::File(path) => Some(("a mesh of --meshes", path.as_path())),
            batch::MeshSource::Benchmark(_) => None,
        })
        .collect();
    inputs.extend(baseline.map(|path| ("--baseline", path)));
    let roles: Vec<(&str, &Path)> = outputs
        .iter()
        .map(|path| ("a file of the report", path.as_path()))
        .collect();
    check_distinct(&inputs, &roles)?;
    for path in &outputs {
        check_writable(path)?;
    }
    Ok(())
}

/// [`write_with`] over the work list `work` (e.g. a user's meshes, `report --meshes`).
pub fn write_work(
    out_dir: &Path,
    work: &batch::WorkList,
    options: &WriteOptions,
    progress: &dyn Fn(usize, usize, &str),
) -> Result<Written> {
    let baseline = read_baseline(options)?;
    let earlier = read_history(out_dir, options)?;
    prepare_report_folder(out_dir, work, options.baseline.as_deref())?;
    let all: Vec<usize> = (0..work.items.len()).collect();
    let measured = measure_items(work, &all, Some((out_dir, &options.thumbnails)), progress)?;
    let report = Report::stamped(measured.records);
    let comparison = write_outputs(
        out_dir,
        &report,
        &measured.thumbnails,
        baseline.as_ref().map(|(p, r)| (*p, r)),
        earlier,
    )?;
    Ok(Written {
        report,
        comparison,
        thumbnails: measured.thumbnails,
        warnings: measured.warnings,
    })
}

/// Writes the tables, the plots and the page of `report` into `out_dir` (whose folders exist;
/// the thumbnails `thumbnails` are already in `out_dir/thumbs/`), with the changes against
/// `baseline` (its path and report) when given; records the run in `out_dir/history/` and
/// draws the trends of the runs `earlier` with this one (in place of an earlier run of its
/// commit); returns the comparison with the baseline.
pub fn write_outputs(
    out_dir: &Path,
    report: &Report,
    thumbnails: &[page::MeshThumbnails],
    baseline: Option<(&Path, &Report)>,
    earlier: Vec<history::Entry>,
) -> Result<Option<compare::Comparison>> {
    let comparison = baseline.map(|(_, old)| {
        compare::compare(
            old,
            report,
            compare::Thresholds::default(),
            compare::TimingCheck::SameMachine,
        )
    });
    let entry = history::Entry::of(report);
    history::record(&out_dir.join(history::HISTORY), &entry)?;
    let runs = history::with_current(earlier, entry);
    let (trends, trend_note) = trends::trends(&runs);
    trends::write_trends(&trends, out_dir)?;
    plots::write_plots(report, &out_dir.join("figures"))?;
    let json = serde_json::to_string_pretty(report)
        .map_err(|e| Error::Invalid(format!("report JSON: {e}")))?;
    for (name, text) in TABLES
        .iter()
        .zip([json, to_csv(report), to_markdown(report)])
    {
        write_atomic(&out_dir.join(name), text.as_bytes())?;
    }
    // The baseline's thumbnails sit beside its metrics.json.
    let images = match baseline {
        Some((path, _)) => {
            let listed: Vec<image_changes::Thumbnail> = thumbnails
                .iter()
                .flat_map(|t| {
                    t.schemes.iter().flat_map(move |scheme| {
                        page::THUMB_MODES.map(|mode| image_changes::Thumbnail {
                            mesh: t.mesh.clone(),
                            scheme: scheme.clone(),
                            mode: mode.to_string(),
                            name: page::thumbnail_name(&t.mesh, scheme, mode),
                        })
                    })
                })
                .collect();
            Some(image_changes::compare_thumbnails(
                path.parent().unwrap_or(Path::new(".")),
                out_dir,
                &listed,
            )?)
        }
        None => None,
    };
    let html = page::to_html(
        report,
        thumbnails,
        baseline
            .zip(comparison.as_ref())
            .map(|((path, old), comparison)| page::Baseline {
                path,
                report: old,
                comparison,
                images: images.as_ref(),
            })
            .as_ref(),
        &page::History {
            runs: &runs,
            trends: &trends,
            note: trend_note.as_deref(),
        },
    );
    page::check_references(&html, out_dir)?;
    write_atomic(&out_dir.join(page::PAGE), html.as_bytes())?;
    Ok(comparison)
}

/// Reads a `metrics.json` written by [`write()`]: the format must be `smoothlab-report` of
/// version [`REPORT_VERSION`], and no mesh × scheme may have two records (a comparison would
/// silently judge only the first).
pub fn read(path: &Path) -> Result<Report> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let report: Report = serde_json::from_str(&text)
        .map_err(|e| Error::Invalid(format!("{}: not a smoothlab report: {e}", path.display())))?;
    check(&report).map_err(|e| Error::Invalid(format!("{}: {e}", path.display())))?;
    Ok(report)
}

/// The mesh name given to the records of `metrics --json` output read by [`read_comparable`]
/// (that output does not name its mesh).
pub const METRICS_MESH: &str = "(metrics)";

/// Reads what `compare` compares: a report written by [`write()`] (see [`read`]), or the output
/// of `smoothlab metrics --json` (a list of per-scheme objects), turned into a report with one
/// record per scheme on the mesh [`METRICS_MESH`] and no provenance. The shape is detected
/// from the JSON; anything else is an error naming the file and the two accepted shapes.
pub fn read_comparable(path: &Path) -> Result<Report> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let value: serde_json::Value = serde_json::from_str(&text)
        .map_err(|e| Error::Invalid(format!("{}: not JSON: {e}", path.display())))?;
    let shape_error = |what: &str| {
        Error::Invalid(format!(
            "{}: {what}; compare reads a smoothlab report (an object with \"format\": \
             \"smoothlab-report\", from `smoothlab report`) or `smoothlab metrics --json` \
             output (a list of objects with a \"scheme\")",
            path.display()
        ))
    };
    let report = match value {
        serde_json::Value::Object(ref map) if map.contains_key("format") => {
            serde_json::from_value::<Report>(value).map_err(|e| {
                Error::Invalid(format!("{}: not a smoothlab report: {e}", path.display()))
            })?
        }
        serde_json::Value::Array(entries) => {
            let mut records = Vec::with_capacity(entries.len());
            for (k, entry) in entries.into_iter().enumerate() {
                let serde_json::Value::Object(figures) = entry else {
                    return Err(shape_error(&format!(
                        "entry {k} of the list is not an object"
                    )));
                };
                let Some(scheme) = figures.get("scheme").and_then(|s| s.as_str()) else {
                    return Err(shape_error(&format!(
                        "entry {k} of the list has no \"scheme\""
                    )));
                };
                records.push(Record {
                    mesh: METRICS_MESH.to_string(),
                    scheme: scheme.to_string(),
                    figures,
                    error: None,
                });
            }
            if records.is_empty() {
                return Err(shape_error("the list is empty"));
            }
            Report {
                format: "smoothlab-report".into(),
                version: REPORT_VERSION,
                commit: "unknown".into(),
                date: String::new(),
                records,
                describe: None,
                dirty: None,
                tool_version: None,
                machine: None,
                shards: None,
            }
        }
        _ => return Err(shape_error("neither a report nor a list of metrics")),
    };
    check(&report).map_err(|e| Error::Invalid(format!("{}: {e}", path.display())))?;
    Ok(report)
}

/// Checks the format, the version and the uniqueness of the records of a parsed report.
fn check(report: &Report) -> Result<()> {
    if report.format != "smoothlab-report" {
        return Err(Error::Invalid(format!(
            "format '{}' is not smoothlab-report",
            report.format
        )));
    }
    if report.version != REPORT_VERSION {
        return Err(Error::Invalid(format!(
            "report version {} is not supported (this build reads version {REPORT_VERSION})",
            report.version
        )));
    }
    let mut seen = std::collections::HashMap::new();
    for (k, r) in report.records.iter().enumerate() {
        if let Some(first) = seen.insert((&r.mesh, &r.scheme), k) {
            return Err(Error::Invalid(format!(
                "records {first} and {k} are both {} / {}",
                r.mesh, r.scheme
            )));
        }
    }
    Ok(())
}

/// A progress bar for [`write_with_progress`] on standard error (see [`crate::progress`]:
/// hidden when standard error is redirected or with `--quiet`). Returns the callback; the bar
/// clears itself when the run is done.
pub fn terminal_progress() -> impl Fn(usize, usize, &str) {
    let bar = crate::progress::bar(0, "report {bar:40} {pos}/{len} {elapsed} {msg}");
    move |done: usize, total: usize, record: &str| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
        bar.set_message(record.to_string());
        if done == total {
            bar.finish_and_clear();
        }
    }
}

/// One line summing up a written report: records, meshes, schemes, where the files are,
/// the commit and the run time.
pub fn summary_line(report: &Report, out_dir: &Path, seconds: f64) -> String {
    let mut meshes: Vec<&str> = report.records.iter().map(|r| r.mesh.as_str()).collect();
    meshes.dedup();
    let mut schemes: Vec<&str> = report.records.iter().map(|r| r.scheme.as_str()).collect();
    schemes.sort_unstable();
    schemes.dedup();
    format!(
        "report: {} records ({} meshes, {} schemes) written to {}/metrics.{{json,csv,md}}, \
         figures/ and index.html in {seconds:.1} s; commit {}\n",
        report.records.len(),
        meshes.len(),
        schemes.len(),
        out_dir.display(),
        report.describe.as_deref().unwrap_or(&report.commit),
    )
}

/// Names of the schemes a report covers, for checks that every registered scheme is in it.
pub fn schemes_covered(report: &Report) -> Vec<String> {
    let mut names: Vec<String> = schemes::names().iter().map(|s| s.to_string()).collect();
    names.retain(|n| report.records.iter().any(|r| &r.scheme == n));
    names
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(mesh: &str, scheme: &str) -> Record {
        Record {
            mesh: mesh.into(),
            scheme: scheme.into(),
            figures: serde_json::Map::new(),
            error: None,
        }
    }

    #[test]
    fn unknown_versions_and_duplicate_records_are_refused() {
        let mut report = Report {
            format: "smoothlab-report".into(),
            version: REPORT_VERSION,
            commit: "x".into(),
            date: "d".into(),
            records: vec![
                record("torus", "hb"),
                record("torus", "pn"),
                record("cube", "hb"),
            ],
            describe: None,
            dirty: None,
            tool_version: None,
            machine: None,
            shards: None,
        };
        check(&report).expect("valid report");
        report.version = 2;
        let err = check(&report).expect_err("version 2");
        assert!(err.to_string().contains("version 2"), "{err}");
        report.version = REPORT_VERSION;
        report.records.push(record("torus", "pn"));
        let err = check(&report).expect_err("duplicate");
        assert!(
            err.to_string()
                .contains("records 1 and 3 are both torus / pn"),
            "{err}"
        );
    }

    #[test]
    fn utc_date_is_well_formed() {
        let d = utc_now();
        assert_eq!(d.len(), 20, "{d}");
        assert!(d.ends_with('Z') && d.as_bytes()[10] == b'T', "{d}");
        assert!(d.starts_with("20"), "{d}");
    }

    /// The records of RFC 4180 text, each a list of fields (quotes removed, doubled quotes
    /// undone).
    fn parse_csv(text: &str) -> Vec<Vec<String>> {
        let (mut rows, mut row, mut field) = (Vec::new(), Vec::new(), String::new());
        let (mut quoted, mut chars) = (false, text.chars().peekable());
        while let Some(c) = chars.next() {
            match (quoted, c) {
                (true, '"') if chars.peek() == Some(&'"') => {
                    chars.next();
                    field.push('"');
                }
                (true, '"') => quoted = false,
                (false, '"') if field.is_empty() => quoted = true,
                (false, ',') => row.push(std::mem::take(&mut field)),
                (false, '\n') => {
                    row.push(std::mem::take(&mut field));
                    rows.push(std::mem::take(&mut row));
                }
                (_, c) => field.push(c),
            }
        }
        rows
    }

    #[test]
    fn csv_fields_with_commas_quotes_and_line_breaks_are_quoted() {
        let names = [
            "comma,name.obj",
            "say \"hi\".obj",
            "two\nlines.obj",
            "plain.obj",
        ];
        let report = Report {
            records: names.iter().map(|n| record(n, "hb:beta=0.1")).collect(),
            ..Report::stamped(Vec::new())
        };
        let csv = to_csv(&report);
        assert!(csv.contains("\n\"comma,name.obj\",hb:beta=0.1,"), "{csv}");
        assert!(csv.contains("\n\"say \"\"hi\"\".obj\","), "{csv}");
        assert!(csv.contains("\nplain.obj,"), "{csv}");
        let rows = parse_csv(&csv);
        assert_eq!(rows.len(), 1 + names.len(), "{csv}");
        for (row, name) in rows[1..].iter().zip(names) {
            assert_eq!(row.len(), rows[0].len(), "{row:?}");
            assert_eq!((row[0].as_str(), row[1].as_str()), (name, "hb:beta=0.1"));
        }
    }
}
