//! The arguments of the commands that build a surface on a mesh, or work on reports, and the
//! one function per command that runs them: `main.rs` parses a command line into these
//! structs and prints what the functions return. `render` and `view` keep theirs beside their
//! code ([`super::render::RenderArgs`], [`super::view::ViewArgs`]).

use std::path::PathBuf;

use clap::Args;

use super::Output;
use crate::error::{Error, Result};
use crate::export::Format;
use crate::mesh::LoadOptions;
use crate::render::theme::Theme;
use crate::report::compare::{Thresholds, TimingCheck};
use crate::report::shard::Shard;

/// The mesh a command builds a surface on, and the scheme with its parameters.
#[derive(Args, Clone, Debug)]
pub struct SchemeOnMesh {
    /// The mesh (.obj, .ply, .off or .stl, chosen by extension).
    pub mesh: PathBuf,
    /// Scheme name (`smoothlab schemes` lists them; `metrics` also takes `all`).
    #[arg(long)]
    pub scheme: String,
    /// Scheme parameter `name=value` (repeatable).
    #[arg(long = "param", value_name = "NAME=VALUE")]
    pub params: Vec<String>,
    /// Weld vertices closer than this fraction of the bounding-box diagonal (0: identical
    /// positions only).
    #[arg(
        long,
        value_name = "REL",
        default_value_t = crate::mesh::DEFAULT_WELD_TOLERANCE,
        value_parser = super::parse_weld_tolerance,
        allow_hyphen_values = true
    )]
    pub weld_tolerance: f64,
    /// Mark edges whose faces' normals are more than DEG degrees apart sharp, and the edges
    /// the file marks (OBJ `s` groups, per-corner `vn`): the surface is G0 there
    /// [default: no sharp edges].
    #[arg(long, value_name = "DEG", value_parser = super::parse_crease_angle, allow_hyphen_values = true)]
    pub crease_angle: Option<f64>,
    /// Refuse to repair the mesh (non-planar or concave polygons, degenerate, duplicate or
    /// inconsistently oriented faces, non-manifold edges and vertices, non-orientable
    /// surfaces): the first repair needed is an error naming the element.
    #[arg(long)]
    pub strict: bool,
}

impl SchemeOnMesh {
    /// How the mesh is loaded.
    pub fn load_options(&self) -> LoadOptions {
        LoadOptions {
            weld_tolerance: self.weld_tolerance,
            strict: self.strict,
            ..Default::default()
        }
        .with_crease_angle(self.crease_angle)
    }
}

/// `smoothlab metrics MESH --scheme S|all [--json FILE] [--explain]`.
#[derive(Args, Clone, Debug)]
pub struct MetricsArgs {
    #[command(flatten)]
    /// The mesh and the scheme.
    pub input: SchemeOnMesh,
    /// Also write the metrics JSON here.
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// After the table, explain every column: its JSON key, definition and good value
    /// (docs/metrics.md).
    #[arg(long)]
    pub explain: bool,
}

/// `smoothlab metrics`: hands the table to `line` line by line as the schemes are measured,
/// then (with `--explain`) the explanation of its columns.
pub fn metrics_command(args: &MetricsArgs, line: &mut dyn FnMut(&str)) -> Result<Output> {
    let output = super::run_metrics_streaming(
        &args.input.mesh,
        &args.input.load_options(),
        &args.input.scheme,
        &args.input.params,
        args.json.as_deref(),
        line,
    )?;
    if args.explain {
        line(&super::metrics_explanation());
    }
    Ok(output)
}

/// `smoothlab export MESH --scheme S -o FILE [--format F] [--tess N]`.
#[derive(Args, Clone, Debug)]
pub struct ExportArgs {
    #[command(flatten)]
    /// The mesh and the scheme.
    pub input: SchemeOnMesh,
    /// Output format (default: from the extension of -o: .json, .bv or .obj).
    #[arg(long, value_parser = super::render::choice_parser(&Format::CHOICES))]
    pub format: Option<String>,
    /// Output file.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: PathBuf,
    /// Subdivisions per patch edge (obj only).
    #[arg(
        long,
        default_value_t = 8,
        value_parser = clap::builder::RangedI64ValueParser::<usize>::new()
            .range(1..=crate::export::obj::MAX_TESS as i64),
        allow_negative_numbers = true
    )]
    pub tess: usize,
}

/// `smoothlab export`.
pub fn export_command(args: &ExportArgs) -> Result<Output> {
    let format = match &args.format {
        Some(name) => Format::parse(name)?,
        None => Format::from_path(&args.output)?,
    };
    super::run_export(
        &args.input.mesh,
        &args.input.load_options(),
        &args.input.scheme,
        format,
        &args.output,
        args.tess,
        &args.input.params,
    )
}

/// `smoothlab sample MESH --scheme S --json FILE`.
#[derive(Args, Clone, Debug)]
pub struct SampleArgs {
    #[command(flatten)]
    /// The mesh and the scheme.
    pub input: SchemeOnMesh,
    /// Output file.
    #[arg(long, value_name = "FILE")]
    pub json: PathBuf,
}

/// `smoothlab sample`.
pub fn sample_command(args: &SampleArgs) -> Result<Output> {
    super::run_sample(
        &args.input.mesh,
        &args.input.load_options(),
        &args.input.scheme,
        &args.input.params,
        &args.json,
    )
}

/// `smoothlab schemes`.
pub fn schemes_command() -> Output {
    super::run_schemes()
}

/// `smoothlab` without a command: the metrics of every scheme on the embedded deformed
/// icosahedron, then the gallery renders into `out/gallery`.
pub fn default_command() -> Result<Output> {
    let mut output = super::run_default()?;
    output.stdout += &super::render::run_gallery(std::path::Path::new("out/gallery"))?;
    Ok(output)
}

/// `smoothlab render`: the render the arguments describe, and its one-line summary.
pub fn render_command(args: &super::render::RenderArgs) -> Result<Output> {
    let (stats, warnings) = super::render::render_command(args)?;
    Ok(Output {
        stdout: super::render::render_summary(&stats),
        warnings,
        failed: false,
    })
}

/// `smoothlab view`: serves the view until interrupted, reporting to `report` as it starts.
pub fn view_command(
    args: &super::view::ViewArgs,
    report: &mut dyn super::view::ViewReport,
) -> Result<Output> {
    super::view::view_command(args, report)?;
    Ok(Output::default())
}

/// `smoothlab report [options]`.
#[derive(Args, Clone, Debug)]
pub struct ReportCommandArgs {
    /// Output folder.
    #[arg(long, default_value = "results")]
    pub out: PathBuf,
    /// A previous report (metrics.json): the page lists the changes against it.
    #[arg(long, value_name = "OLD.json")]
    pub baseline: Option<PathBuf>,
    /// Measure these meshes instead of the benchmark meshes: a folder (its .obj, .ply, .off
    /// and .stl files) or a list file (one path per line, relative to the list). A mesh
    /// that fails is recorded as an error; the batch goes on.
    #[arg(long, value_name = "DIR|LIST")]
    pub meshes: Option<PathBuf>,
    /// The schemes: `all` or names separated by commas (e.g. flat,pn).
    #[arg(long, default_value = "all")]
    pub scheme: String,
    /// A parameter sweep `SCHEME:NAME=V1,V2,…[:NAME2=…]` (every combination), measured
    /// instead of --scheme; repeatable. Not render's --sweep (a stripe sweep).
    #[arg(long = "sweep", value_name = "SCHEME:NAME=V1,V2")]
    pub sweeps: Vec<String>,
    /// A file of sweeps, one per line (`#` comments); repeatable.
    #[arg(long = "sweep-file", value_name = "FILE")]
    pub sweep_files: Vec<PathBuf>,
    /// Measure only shard I of N (0 ≤ I < N, balanced by estimated cost) and write the
    /// partial report OUT/partial.json; `smoothlab merge` combines the shards.
    #[arg(long, value_name = "I/N", allow_hyphen_values = true)]
    pub shard: Option<Shard>,
    /// Weld vertices of --meshes files closer than this fraction of the bounding-box
    /// diagonal (0: identical positions only).
    #[arg(
        long,
        value_name = "REL",
        default_value_t = crate::mesh::DEFAULT_WELD_TOLERANCE,
        value_parser = super::parse_weld_tolerance,
        allow_hyphen_values = true
    )]
    pub weld_tolerance: f64,
    /// Mark edges of --meshes files whose faces' normals are more than DEG degrees
    /// apart sharp, and the edges the file marks (OBJ `s` groups, per-corner `vn`): the
    /// surface is G0 there [default: no sharp edges].
    #[arg(long, value_name = "DEG", value_parser = super::parse_crease_angle, allow_hyphen_values = true)]
    pub crease_angle: Option<f64>,
    /// A parameter `name=value` that replaces its default for the run, for every scheme
    /// of --scheme that has it (repeatable); the records keep the scheme's name.
    #[arg(long = "param", value_name = "NAME=VALUE")]
    pub params: Vec<String>,
    /// The history folder whose runs the page's trends show (e.g. the main branch's
    /// results/history); default OUT/history. The run is recorded in OUT/history either
    /// way.
    #[arg(long, value_name = "DIR")]
    pub history: Option<PathBuf>,
    /// Refuse to repair --meshes files (non-planar or concave polygons, degenerate,
    /// duplicate or inconsistently oriented faces, non-manifold edges and vertices,
    /// non-orientable surfaces): the first repair needed is an error naming the element.
    #[arg(long)]
    pub strict: bool,
}

/// `smoothlab report`.
pub fn report_command(args: &ReportCommandArgs) -> Result<Output> {
    super::run_report_with(&super::ReportArgs {
        out: args.out.clone(),
        baseline: args.baseline.clone(),
        meshes: args.meshes.clone(),
        scheme: args.scheme.clone(),
        sweeps: args.sweeps.clone(),
        sweep_files: args.sweep_files.clone(),
        shard: args.shard,
        load: LoadOptions {
            weld_tolerance: args.weld_tolerance,
            strict: args.strict,
            ..Default::default()
        }
        .with_crease_angle(args.crease_angle),
        params: args.params.clone(),
        history: args.history.clone(),
    })
}

/// `smoothlab merge PARTS… -o OUT [--baseline OLD.json]`.
#[derive(Args, Clone, Debug)]
pub struct MergeArgs {
    /// The parts: shard folders of `report --shard` (or their partial.json), or the
    /// NAME.shard-I-of-N.json files of a sharded turntable, sweep or figure.
    #[arg(required = true)]
    pub parts: Vec<PathBuf>,
    /// Output: the report folder, the NAME of the merged frames (NAME-000.png …,
    /// NAME.gif), or the STEM of the merged figure (STEM.png, STEM.svg, its cells' EXRs).
    #[arg(short = 'o', long = "output", value_name = "OUT")]
    pub output: PathBuf,
    /// Report parts: a previous report (metrics.json) to list the changes against.
    #[arg(long, value_name = "OLD.json")]
    pub baseline: Option<PathBuf>,
}

/// `smoothlab merge`.
pub fn merge_command(args: &MergeArgs) -> Result<Output> {
    super::merge::run_merge(&args.parts, &args.output, args.baseline.as_deref())
}

/// `smoothlab compare OLD NEW [--quality-rel R] [--time-ratio R] [--timings|--force-timings]`.
#[derive(Args, Clone, Debug)]
pub struct CompareArgs {
    /// The earlier report.
    pub old: PathBuf,
    /// The later report.
    pub new: PathBuf,
    /// Relative tolerance of quality figures (finite, ≥ 0).
    #[arg(long, default_value_t = 0.05, allow_negative_numbers = true)]
    pub quality_rel: f64,
    /// Largest accepted new/old timing ratio (finite, ≥ 1).
    #[arg(long, default_value_t = 1.5, allow_negative_numbers = true)]
    pub time_ratio: f64,
    /// Judge timings too, when both reports were measured on the same machine.
    #[arg(long)]
    pub timings: bool,
    /// Judge timings whatever machines the reports were measured on.
    #[arg(long)]
    pub force_timings: bool,
}

/// `smoothlab compare`.
pub fn compare_command(args: &CompareArgs) -> Result<Output> {
    super::run_compare(
        &args.old,
        &args.new,
        Thresholds {
            quality_rel: args.quality_rel,
            time_ratio: args.time_ratio,
        },
        match (args.timings, args.force_timings) {
            (_, true) => TimingCheck::Force,
            (true, false) => TimingCheck::SameMachine,
            (false, false) => TimingCheck::Skip,
        },
    )
}

/// `smoothlab figure SPEC… [--shard I/N]`.
#[derive(Args, Clone, Debug)]
pub struct FigureArgs {
    /// Figure spec files (.toml), rendered in turn.
    #[arg(required = true)]
    pub specs: Vec<PathBuf>,
    /// Render only shard I of N of the cells (0 ≤ I < N, balanced by estimated cost):
    /// writes those cells (`STEM-<row>-<column>-<scheme>-<mode>.png` and `.exr`) and
    /// `STEM.shard-I-of-N.json`; `smoothlab merge` composes the sheet.
    #[arg(long, value_name = "I/N", allow_hyphen_values = true)]
    pub shard: Option<Shard>,
    /// Colours of the sheet, its legends and the cells' background, instead of the spec's
    /// `theme` [default: the spec's, else dark].
    #[arg(long, value_parser = clap::builder::PossibleValuesParser::new(Theme::NAMES))]
    pub theme: Option<String>,
}

/// `smoothlab figure`: every spec in turn, whole or the shard's cells.
pub fn figure_command(args: &FigureArgs) -> Result<Output> {
    let theme = args
        .theme
        .as_deref()
        .map(|name| Theme::by_name("--theme", name))
        .transpose()?;
    let mut stdout = String::new();
    let mut warnings = Vec::new();
    for spec in &args.specs {
        if let Some(shard) = args.shard {
            let files = super::figure::shard::run_figure_spec_shard(spec, shard, theme)?;
            stdout += &super::figure::shard::shard_summary(&files);
            warnings.extend(files.warnings);
        } else {
            let files = super::figure::spec::run_figure_spec(spec, theme)?;
            stdout += &super::figure::spec::figure_summary(&files);
            warnings.extend(files.warnings);
        }
    }
    Ok(Output {
        stdout,
        warnings,
        failed: false,
    })
}

/// The error of a failed write to standard output while a command streams its table (a
/// closed pipe is not one: the reader wanted no more).
pub fn stdout_error(e: &std::io::Error) -> Option<Error> {
    (e.kind() != std::io::ErrorKind::BrokenPipe)
        .then(|| Error::Invalid(format!("standard output: {e}")))
}
