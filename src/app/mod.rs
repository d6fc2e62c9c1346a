//! What the command line does, minus argument parsing and printing: loading a mesh with its
//! warnings, building schemes with timing, measuring, exporting, and formatting tables. Each
//! command returns an [`Output`] (text for stdout plus warnings) so that it can be tested
//! without running the binary.
//!
//! This is the command layer: it alone turns files and flags into values for the library
//! below (a mesh, a scheme run, a [`crate::render::RenderJob`]) and writes results. The
//! `render` and `figure` commands and the built-in gallery live in [`render`], [`scene`],
//! [`gallery`] and [`figure`].

pub(crate) mod batch;
pub(crate) mod commands;
pub(crate) mod figure;
pub(crate) mod gallery;
pub(crate) mod merge;
pub(crate) mod render;
pub(crate) mod scene;
pub(crate) mod selection;
pub(crate) mod toml_input;
pub(crate) mod turntable;
pub(crate) mod view;

use std::path::Path;

pub use crate::files::clean_up_on_signals;
pub(crate) use selection::{ALL_SCHEMES, SchemeRun, parse_params, select_schemes};

use crate::error::{Error, Problem, Result};
use crate::export::{self, Format};
use crate::files::{check_distinct, check_writable, write_atomic};
use crate::mesh::{LoadOptions, Mesh};
use crate::metrics::Metrics;
use crate::schemes::{self, SCHEMES, build_timed};
use crate::surface::Surface;

/// What a command produced: text for standard output and warnings (one line each, printed
/// by the binary as `warning: …` on standard error).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Output {
    /// Text for standard output.
    pub stdout: String,
    /// Warnings, one line each, without the `warning:` prefix.
    pub warnings: Vec<String>,
    /// True if the command ran but its verdict is a failure (exit code 1), e.g. `compare`
    /// found a regression.
    pub failed: bool,
}

/// Applies [`crate::budget::capped_threads`] to this process: when [`crate::budget::THREADS_VAR`] asks for too many
/// threads, the global thread pool is built with the cap before any parallel work, and the
/// warning is returned.
pub fn limit_threads() -> Option<String> {
    let requested = std::env::var(crate::budget::THREADS_VAR).ok()?;
    let cores = std::thread::available_parallelism().map_or(1, usize::from);
    let (threads, warning) = crate::budget::capped_threads(&requested, cores)?;
    // Building fails only if a global pool already exists, which then keeps its size.
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build_global()
        .ok()
        .map(|()| warning)
}

/// Loads a mesh (OBJ, PLY, OFF or STL by extension) with `options`; the loader's report
/// (welded vertices, re-oriented faces, …) becomes warnings.
pub(crate) fn load_mesh(path: &Path, options: &LoadOptions) -> Result<(Mesh, Vec<String>)> {
    let (mesh, report) = Mesh::load_with(path, options)?;
    Ok((mesh, report.warnings))
}

/// Parses a relative weld tolerance (`--weld-tolerance REL`), see [`crate::mesh::check_weld_tolerance`].
pub(crate) fn parse_weld_tolerance(text: &str) -> std::result::Result<f64, String> {
    let value: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("'{text}' is not a number"))?;
    crate::mesh::check_weld_tolerance(value)
}

/// Parses a crease angle in degrees (`--crease-angle DEG`), see
/// [`crate::mesh::check_crease_angle`].
pub(crate) fn parse_crease_angle(text: &str) -> std::result::Result<f64, String> {
    let value: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("'{text}' is not a number"))?;
    crate::mesh::check_crease_angle(value)
}

/// Builds and measures every selected scheme on `mesh`. With [`ALL_SCHEMES`], a scheme that
/// refuses an open mesh or sharp edges is skipped with a warning instead of failing the whole
/// run.
pub(crate) fn measure_schemes(
    mesh: &Mesh,
    selection: &str,
    params: &[(String, String)],
) -> Result<(Vec<Metrics>, Vec<String>)> {
    let runs = select_schemes(selection, params)?;
    measure_runs(mesh, &runs, selection == ALL_SCHEMES, &mut |_| {})
}

/// Builds and measures every run of a selection ([`select_schemes`]) on `mesh`, calling `each`
/// with every scheme's metrics as soon as it is measured. With `skip_refusals` (the selection
/// was [`ALL_SCHEMES`]), a scheme that refuses an open mesh or sharp edges is skipped with a
/// warning instead of failing the whole run.
pub(crate) fn measure_runs(
    mesh: &Mesh,
    runs: &[SchemeRun],
    skip_refusals: bool,
    each: &mut dyn FnMut(&Metrics),
) -> Result<(Vec<Metrics>, Vec<String>)> {
    let mut results = Vec::new();
    let mut warnings = Vec::new();
    for run in runs {
        match schemes::build_timed_in_frame(run.scheme, mesh, &run.params) {
            Ok((surface, frame, ms)) => {
                warnings.extend(surface.warnings.iter().cloned());
                let measuring = crate::progress::spinner(format!("measuring {}", run.scheme));
                let metrics = Metrics::measure_in_frame(&surface, &frame, mesh, ms);
                measuring.finish_and_clear();
                metrics.check_finite()?;
                each(&metrics);
                results.push(metrics);
            }
            Err(e @ (Error::OpenMesh { .. } | Error::SharpEdgesUnsupported { .. }))
                if skip_refusals =>
            {
                warnings.push(format!("skipped: {e}"));
            }
            Err(e) => return Err(e),
        }
    }
    Ok((results, warnings))
}

/// `min/typical` measured continuity order, `-` without joints.
fn order_cell(min: Option<i32>, typical: Option<i32>) -> String {
    match (min, typical) {
        (Some(a), Some(b)) => format!("{a}/{b}"),
        _ => "-".to_string(),
    }
}

fn cell(x: Option<f64>) -> String {
    x.map_or_else(|| "-".to_string(), |x| format!("{x:.2e}"))
}

/// The metrics table's columns with the width of their values (the header may be wider;
/// the scheme column is as wide as the longest registered name). Fixed widths let the table
/// be printed row by row as schemes are measured.
const TABLE_COLUMNS: [(&str, usize); 20] = [
    ("scheme", 0),
    ("faces", 7),
    ("patches", 7),
    ("build_ms", 9),
    ("interp", 8),
    ("G0_gap", 8),
    ("G1_max", 8),
    ("G1_mean", 8),
    ("G1_between", 8),
    ("G1_inside", 8),
    ("G1>round", 8),
    ("curv_jump", 8),
    ("regularity", 8),
    ("undulation", 8),
    ("inflect", 7),
    ("G^k", 5),
    ("folds", 6),
    ("flat_vtx", 6),
    ("sharp", 5),
    ("G0_sharp", 8),
];

/// The metrics glossary the `--explain` footer is read from: docs/metrics.md, compiled in so
/// that the footer and the guide are one text.
const METRICS_GLOSSARY: &str = include_str!("../../docs/metrics.md");

/// What `metrics --explain` prints after the table: each column of [`TABLE_COLUMNS`] with its
/// JSON key, definition and good value, then the notes under the guide's table (why
/// `curv_jump` saturates, how `G^k` is measured), all taken from the "The text table" section
/// of docs/metrics.md with the Markdown marks removed.
pub(crate) fn metrics_explanation() -> String {
    let section = glossary_section("## The text table");
    let mut out = String::from("\ncolumns (docs/metrics.md):\n");
    for line in section.lines().filter(|l| l.starts_with("| `")) {
        let cells: Vec<&str> = line.trim_matches('|').split(" | ").map(str::trim).collect();
        if let [column, key, definition, good] = cells[..] {
            let good = if good == "—" {
                String::new()
            } else {
                format!(" Good: {}.", plain(good))
            };
            out += &wrap(
                &format!(
                    "{} ({}): {}.{good}",
                    plain(column),
                    plain(key),
                    plain(definition)
                ),
                "  ",
                "      ",
            );
        }
    }
    for paragraph in section
        .split("\n\n")
        .filter(|p| !p.starts_with('|') && !p.trim().is_empty())
    {
        out += "\n";
        out += &wrap(&plain(&paragraph.replace('\n', " ")), "", "");
    }
    out
}

/// The lines of docs/metrics.md from `heading` to the next `## ` heading.
fn glossary_section(heading: &str) -> &'static str {
    let start = METRICS_GLOSSARY
        .find(heading)
        .map_or(0, |i| i + heading.len());
    let rest = &METRICS_GLOSSARY[start..];
    &rest[..rest.find("\n## ").unwrap_or(rest.len())]
}

/// Markdown text without its marks: code spans and emphasis unmarked, links reduced to their
/// text.
fn plain(markdown: &str) -> String {
    let mut out = String::with_capacity(markdown.len());
    let mut rest = markdown;
    while let Some(open) = rest.find('[') {
        out += &rest[..open];
        let after = &rest[open + 1..];
        match after.find("](").zip(after.find(')')) {
            Some((close, end)) if close < end && !after[..close].contains('[') => {
                out += &after[..close];
                rest = &after[end + 1..];
            }
            _ => {
                out.push('[');
                rest = after;
            }
        }
    }
    out += rest;
    out.replace('`', "").replace("**", "")
}

/// `text` wrapped at 96 characters, its first line indented by `first`, the rest by `next`.
fn wrap(text: &str, first: &str, next: &str) -> String {
    let mut out = String::new();
    let (mut line, mut empty) = (first.to_string(), true);
    for word in text.split_whitespace() {
        if !empty && line.chars().count() + 1 + word.chars().count() > 96 {
            out += &line;
            out.push('\n');
            (line, empty) = (next.to_string(), true);
        }
        if !empty {
            line.push(' ');
        }
        line += word;
        empty = false;
    }
    out + &line + "\n"
}

/// One line of the metrics table: names left-aligned, numbers right-aligned.
fn table_line(cells: &[String]) -> String {
    let scheme_width = SCHEMES.iter().map(|s| s.name.len()).max().unwrap_or(0);
    let padded: Vec<String> = cells
        .iter()
        .zip(TABLE_COLUMNS)
        .enumerate()
        .map(|(c, (text, (header, width)))| {
            let w = width.max(header.len());
            if c == 0 {
                format!("{text:<w$}", w = w.max(scheme_width))
            } else {
                format!("{text:>w$}")
            }
        })
        .collect();
    padded.join("  ").trim_end().to_string() + "\n"
}

/// The header line of the metrics table.
pub(crate) fn metrics_table_header() -> String {
    table_line(&TABLE_COLUMNS.map(|(header, _)| header.to_string()))
}

/// The metrics table's line for one scheme.
pub(crate) fn metrics_table_row(m: &Metrics) -> String {
    table_line(&[
        m.scheme.clone(),
        m.faces.to_string(),
        m.patches.to_string(),
        format!("{:.2}", m.construct_ms),
        cell(m.interp_max_rel),
        cell(m.g0_max_rel),
        cell(m.g1_max_rad),
        cell(m.g1_mean_rad),
        cell(m.g1_between_faces_max_rad),
        cell(m.g1_inside_faces_max_rad),
        cell(m.g1_beyond_rounding_max_rad),
        cell(m.curvature_jump_max_rel),
        cell(m.min_regularity_rel),
        format!("{:.2e}", m.network_undulation_max_rad),
        m.network_inflections_max.to_string(),
        order_cell(m.continuity_order, m.continuity_order_typical),
        m.folds.to_string(),
        m.vertex_flat_points.to_string(),
        m.sharp_joints.to_string(),
        cell(m.sharp_g0_max_rel),
    ])
}

/// An aligned text table of metrics, one row per scheme. Lengths are relative to the
/// bounding-box diagonal, angles in radians; `-` marks a figure over an empty set.
pub(crate) fn metrics_table(metrics: &[Metrics]) -> String {
    let rows: Vec<String> = metrics.iter().map(metrics_table_row).collect();
    metrics_table_header() + &rows.concat()
}

/// The metrics JSON of docs/guide/contracts.md: a list with one object per scheme.
pub(crate) fn metrics_json(metrics: &[Metrics]) -> Result<String> {
    serde_json::to_string_pretty(metrics).map_err(|e| Error::Invalid(format!("metrics JSON: {e}")))
}

/// Every registered scheme with its summary and parameters (default and help).
pub(crate) fn schemes_listing() -> String {
    let mut out = String::new();
    for spec in SCHEMES {
        let closed = if spec.needs_closed_mesh {
            " [closed meshes only]"
        } else {
            ""
        };
        out += &format!("{}: {}{closed}\n", spec.name, spec.summary);
        for p in spec.params {
            out += &format!("    {}={}  {}\n", p.name, p.default, p.help);
        }
    }
    out
}

/// `smoothlab metrics MESH --scheme S|all [--param k=v]… [--json F]`.
pub fn run_metrics(
    mesh_path: &Path,
    load: &LoadOptions,
    selection: &str,
    raw_params: &[String],
    json: Option<&Path>,
) -> Result<Output> {
    let mut table = String::new();
    let mut output =
        run_metrics_streaming(mesh_path, load, selection, raw_params, json, &mut |line| {
            table += line
        })?;
    output.stdout = table;
    Ok(output)
}

/// [`run_metrics`], handing the table to `line` line by line as the schemes are measured (the
/// header once the mesh is loaded) instead of in [`Output::stdout`], which stays empty.
pub fn run_metrics_streaming(
    mesh_path: &Path,
    load: &LoadOptions,
    selection: &str,
    raw_params: &[String],
    json: Option<&Path>,
    line: &mut dyn FnMut(&str),
) -> Result<Output> {
    let params = parse_params(raw_params)?;
    // Check the scheme, the parameters and the output path before the (possibly slow) work.
    let runs = select_schemes(selection, &params)?;
    if let Some(path) = json {
        check_writable(path)?;
        check_distinct(&[("the mesh", mesh_path)], &[("--json", path)])?;
    }
    let (mesh, mut warnings) = load_mesh(mesh_path, load)?;
    line(&metrics_table_header());
    let (metrics, skipped) = measure_runs(&mesh, &runs, selection == ALL_SCHEMES, &mut |m| {
        line(&metrics_table_row(m))
    })?;
    warnings.extend(skipped);
    if let Some(path) = json {
        write_atomic(path, metrics_json(&metrics)?.as_bytes())?;
    }
    Ok(Output {
        warnings,
        ..Default::default()
    })
}

/// Builds `scheme` with the raw `--param` values on the mesh file at `mesh_path` (loaded with
/// `load`); the scheme name, the parameter syntax and the output path `out_path` (given by
/// `flag`: writable, not the mesh) are checked before the (possibly slow) mesh load. Returns the mesh, the surface and the loading warnings.
fn build_on_file(
    mesh_path: &Path,
    load: &LoadOptions,
    scheme: &str,
    raw_params: &[String],
    (flag, out_path): (&str, &Path),
) -> Result<(Mesh, Surface, Vec<String>)> {
    let params = parse_params(raw_params)?;
    schemes::find(scheme)?;
    check_writable(out_path)?;
    check_distinct(&[("the mesh", mesh_path)], &[(flag, out_path)])?;
    let (mesh, mut warnings) = load_mesh(mesh_path, load)?;
    let (surface, _) = build_timed(scheme, &mesh, &params)?;
    warnings.extend(surface.warnings.iter().cloned());
    Ok((mesh, surface, warnings))
}

/// `smoothlab export MESH --scheme S --format json|bv|obj -o F [--tess N] [--param k=v]…`.
pub(crate) fn run_export(
    mesh_path: &Path,
    load: &LoadOptions,
    scheme: &str,
    format: Format,
    out_path: &Path,
    tess: usize,
    raw_params: &[String],
) -> Result<Output> {
    let (mesh, surface, warnings) =
        build_on_file(mesh_path, load, scheme, raw_params, ("-o", out_path))?;
    let writing = crate::progress::spinner(format!(
        "writing {} patches to {}",
        surface.patches.len(),
        out_path.display()
    ));
    write_atomic(
        out_path,
        export::export(&surface, format, tess, &|t| mesh.input_face(t))?.as_bytes(),
    )?;
    writing.finish_and_clear();
    Ok(Output {
        stdout: format!(
            "wrote {} patches of '{scheme}' to {}\n",
            surface.patches.len(),
            out_path.display()
        ),
        warnings,

        ..Default::default()
    })
}

/// `smoothlab sample MESH --scheme S [--param k=v]… --json F`.
pub(crate) fn run_sample(
    mesh_path: &Path,
    load: &LoadOptions,
    scheme: &str,
    raw_params: &[String],
    json: &Path,
) -> Result<Output> {
    let (mesh, surface, warnings) =
        build_on_file(mesh_path, load, scheme, raw_params, ("--json", json))?;
    let samples = export::samples::edge_samples(&surface, &mesh)?;
    let text = serde_json::to_string(&samples)
        .map_err(|e| Error::Invalid(format!("edge samples JSON: {e}")))?;
    write_atomic(json, text.as_bytes())?;
    Ok(Output {
        stdout: format!(
            "wrote samples of {} edges of '{scheme}' to {}\n",
            samples.edges.len(),
            json.display()
        ),
        warnings,
        ..Output::default()
    })
}

/// `smoothlab schemes`.
pub(crate) fn run_schemes() -> Output {
    Output {
        stdout: schemes_listing(),
        warnings: Vec::new(),

        ..Default::default()
    }
}

/// The mesh of the default job: the embedded deformed icosahedron.
pub(crate) fn default_mesh() -> Result<Mesh> {
    let (positions, faces) = crate::mesh::generate::deformed_icosahedron();
    Ok(Mesh::from_triangles(positions, faces)?.0)
}

/// `smoothlab` without arguments: the metrics table of every scheme on the embedded
/// deformed icosahedron (the gallery renders are added to this job by the renderer).
pub(crate) fn run_default() -> Result<Output> {
    let mesh = default_mesh()?;
    let (metrics, warnings) = measure_schemes(&mesh, ALL_SCHEMES, &[])?;
    Ok(Output {
        stdout: format!(
            "every scheme on the embedded deformed icosahedron ({} faces):\n{}",
            mesh.face_count(),
            metrics_table(&metrics)
        ),
        warnings,

        ..Default::default()
    })
}

/// What `smoothlab report` is asked to do.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ReportArgs {
    /// The report folder (with a shard: the shard's folder).
    pub out: std::path::PathBuf,
    /// A previous report to list the changes against.
    pub baseline: Option<std::path::PathBuf>,
    /// A folder of meshes or a list of mesh files (`--meshes`); `None`: the benchmark meshes.
    pub meshes: Option<std::path::PathBuf>,
    /// `--scheme`: `all` or a comma-separated list.
    pub scheme: String,
    /// `--sweep` values.
    pub sweeps: Vec<String>,
    /// `--sweep-file` files.
    pub sweep_files: Vec<std::path::PathBuf>,
    /// `--shard I/N`: measure one shard and write a partial report.
    pub shard: Option<crate::report::shard::Shard>,
    /// How mesh files are loaded.
    pub load: LoadOptions,
    /// `--param name=value`: replaces the default of that parameter for the run.
    pub params: Vec<String>,
    /// `--history DIR`: the history the page's trends show (default: `OUT/history/`).
    pub history: Option<std::path::PathBuf>,
}

impl Default for ReportArgs {
    fn default() -> Self {
        ReportArgs {
            out: "results".into(),
            baseline: None,
            meshes: None,
            scheme: ALL_SCHEMES.into(),
            sweeps: Vec::new(),
            sweep_files: Vec::new(),
            shard: None,
            load: LoadOptions::default(),
            params: Vec::new(),
            history: None,
        }
    }
}

/// `smoothlab report [--meshes DIR|LIST] [--scheme …] [--sweep …] [--shard I/N]`: the report
/// over the work list the flags describe ([`batch`]); with a shard, that shard's partial
/// report (`OUT/partial.json`, see [`crate::report::partial`]).
pub(crate) fn run_report_with(args: &ReportArgs) -> Result<Output> {
    let start = std::time::Instant::now();
    let out_dir = args.out.as_path();
    let variants = batch::with_defaults(
        batch::variants(&args.scheme, &args.sweeps, &args.sweep_files)?,
        &args.params,
    )?;
    let work = match &args.meshes {
        Some(source) => batch::mesh_work(source, &variants, &args.load)?,
        None => crate::report::benchmark_work(&variants)?,
    };
    let options = crate::report::WriteOptions {
        baseline: args.baseline.clone(),
        history: args.history.clone(),
        ..Default::default()
    };
    if let Some(shard) = args.shard {
        if args.baseline.is_some() {
            return Err(Error::config(
                "--shard",
                Problem::Stated {
                    message: "report --shard writes a partial report: give --baseline to merge \
                              instead"
                        .into(),
                },
            ));
        }
        let part = crate::report::partial::write_part(
            out_dir,
            &work,
            shard,
            &options,
            &crate::report::terminal_progress(),
        )?;
        let errors = part
            .report
            .records
            .iter()
            .filter(|r| r.error.is_some())
            .count();
        return Ok(Output {
            stdout: format!(
                "report shard {shard}: {} of {} meshes, {} records ({errors} errors) written to {} in {:.1} s\n",
                part.items.len(),
                work.items.len(),
                part.report.records.len(),
                crate::report::partial::part_file(out_dir).display(),
                start.elapsed().as_secs_f64()
            ),
            warnings: part.warnings,
            failed: false,
        });
    }
    let written = crate::report::write_work(
        out_dir,
        &work,
        &options,
        &crate::report::terminal_progress(),
    )?;
    let baseline = args.baseline.as_deref();
    let mut stdout =
        crate::report::summary_line(&written.report, out_dir, start.elapsed().as_secs_f64());
    let errors = written
        .report
        .records
        .iter()
        .filter(|r| r.error.is_some())
        .count();
    if errors > 0 {
        stdout += &format!(
            "{errors} record(s) not measured: their errors are in {}\n",
            out_dir.join("metrics.md").display()
        );
    }
    if let (Some(path), Some(comparison)) = (baseline, &written.comparison) {
        stdout += &baseline_line(path, comparison, out_dir);
    }
    Ok(Output {
        stdout,
        warnings: written.warnings,
        ..Default::default()
    })
}

/// The line `report --baseline` and `merge --baseline` print: the counts of the comparison
/// and where its changes are listed.
pub(crate) fn baseline_line(
    baseline: &Path,
    comparison: &crate::report::compare::Comparison,
    out_dir: &Path,
) -> String {
    format!(
        "baseline {}: {}, listed in {}\n",
        baseline.display(),
        comparison.summary(),
        out_dir.join(crate::report::page::PAGE).display()
    )
}

/// `smoothlab compare OLD NEW`: the changes between two reports (or two `metrics --json`
/// outputs); quality always judged, timings as `timings` says; fails on a regression.
pub(crate) fn run_compare(
    old: &Path,
    new: &Path,
    thresholds: crate::report::compare::Thresholds,
    timings: crate::report::compare::TimingCheck,
) -> Result<Output> {
    use crate::report::{compare, read_comparable};
    thresholds.check()?;
    let (old, new) = (read_comparable(old)?, read_comparable(new)?);
    compare::check_comparable(&old, &new)?;
    let comparison = compare::compare(&old, &new, thresholds, timings);
    Ok(Output {
        stdout: compare::to_text(&comparison),
        failed: comparison.failed(),
        ..Default::default()
    })
}

#[cfg(test)]
mod tests {
    /// Every column of the table is explained by docs/metrics.md exactly once, with its
    /// JSON key, and the curv_jump note is in the footer without Markdown marks.
    #[test]
    fn every_metrics_column_is_explained() {
        let text = super::metrics_explanation();
        for (column, _) in super::TABLE_COLUMNS {
            let lines = text
                .lines()
                .filter(|l| l.starts_with(&format!("  {column} (")))
                .count();
            assert_eq!(lines, 1, "column {column} explained {lines} times:\n{text}");
        }
        assert!(text.contains("  curv_jump (curvature_jump_max_rel): largest relative jump"));
        assert!(text.contains("Why curv_jump saturates at 2.00."), "{text}");
        assert!(
            !text.contains('`') && !text.contains("**") && !text.contains("]("),
            "{text}"
        );
        assert!(
            text.lines()
                .all(|l| l.chars().count() <= 96 || !l.contains(' '))
        );
    }

    #[test]
    fn markdown_marks_are_removed() {
        assert_eq!(
            super::plain("a [glossary](glossary.md) and `x` **bold** [HB00 §9]"),
            "a glossary and x bold [HB00 §9]"
        );
    }

    use super::*;

    #[test]
    fn registry_order_is_flat_pn_hb() {
        assert_eq!(&schemes::names()[..3], ["flat", "pn", "hb"]);
        let listing = schemes_listing();
        assert!(listing.contains("normals=estimate"), "{listing}");
    }

    #[test]
    fn table_is_aligned() {
        let m = Metrics {
            scheme: "pn".into(),
            params: Default::default(),
            faces: 20,
            patches: 20,
            construct_ms: 0.5,
            interp_max_rel: Some(0.0),
            g0_max_rel: Some(1e-17),
            g1_max_rad: Some(0.25),
            g1_mean_rad: Some(0.1),
            g1_between_faces_max_rad: Some(0.25),
            g1_beyond_rounding_max_rad: Some(0.25),
            g1_inside_faces_max_rad: None,
            curvature_jump_max_rel: Some(1.0),
            gaussian_jump_max_rel: Some(1.0),
            mean_jump_max_rel: Some(0.5),
            min_regularity_rel: Some(0.9),
            network_undulation_max_rad: 0.0,
            network_undulation_total_rad: 0.0,
            network_inflections_max: 0,
            network_curves_with_inflections: 0,
            network_chord_deviation_max_rel: 0.1,
            continuity_order: Some(0),
            continuity_order_between_faces: Some(0),
            continuity_order_inside_faces: None,
            continuity_order_typical: Some(0),
            joints: 30,
            joints_between_faces: 30,
            samples_per_joint: 17,
            singular_samples: 0,
            folds: 0,
            folded_patches: 0,
            vertex_flat_points: 0,
            vertex_curved: 12,
            vertex_mean_curvature_ratio_min: Some(0.5),
            vertex_mean_curvature_ratio_max: Some(1.5),
            sharp_joints: 0,
            spike_edges: 0,
            sharp_g0_max_rel: None,
            sharp_g1_max_rad: None,
            repairs: Vec::new(),
        };
        let table = metrics_table(&[
            m.clone(),
            Metrics {
                scheme: "flat".into(),
                ..m
            },
        ]);
        let lines: Vec<&str> = table.lines().collect();
        assert_eq!(lines.len(), 3);
        assert!(lines.iter().all(|l| l.len() == lines[0].len()), "{table}");
        assert!(
            lines[1].contains("2.50e-1") && lines[1].contains(" 9.00e-1 "),
            "{table}"
        );
        assert!(lines[1].contains(" - "), "empty set shown as '-': {table}");
    }
}
