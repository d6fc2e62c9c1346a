//! The smoothlab command line: argument parsing and printing only; the work is done by
//! [`smoothlab::app`].

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand, ValueEnum};
use smoothlab::app::{self, Output};
use smoothlab::export::Format;

/// Smooth surfaces from triangle meshes with classical schemes, ray-traced exactly and
/// measured. Without a command: the default job on the embedded deformed icosahedron.
#[derive(Parser)]
#[command(name = "smoothlab", version)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// Draw no progress bars or spinners on standard error (they are drawn only on a
    /// terminal anyway); warnings and errors are still printed.
    #[arg(long, global = true)]
    quiet: bool,
}

#[derive(Subcommand)]
enum Command {
    /// Build one scheme (or all) on a mesh and print the smoothness metrics.
    Metrics {
        #[command(flatten)]
        input: SchemeOnMesh,
        /// Also write the metrics JSON here.
        #[arg(long, value_name = "FILE")]
        json: Option<PathBuf>,
        /// After the table, explain every column: its JSON key, definition and good value
        /// (docs/metrics.md).
        #[arg(long)]
        explain: bool,
    },
    /// Build a scheme on a mesh and write its patches.
    Export {
        #[command(flatten)]
        input: SchemeOnMesh,
        /// Output format (default: from the extension of -o: .json, .bv or .obj).
        #[arg(long, value_enum)]
        format: Option<FormatArg>,
        /// Output file.
        #[arg(short = 'o', long = "output", value_name = "FILE")]
        output: PathBuf,
        /// Subdivisions per patch edge (obj only).
        #[arg(
            long,
            default_value_t = 8,
            value_parser = clap::builder::RangedI64ValueParser::<usize>::new()
                .range(1..=smoothlab::export::obj::MAX_TESS as i64),
            allow_negative_numbers = true
        )]
        tess: usize,
    },
    /// Build a scheme on a mesh and write, for every shared edge, points and normals sampled
    /// from both of its faces (edge-samples JSON).
    Sample {
        #[command(flatten)]
        input: SchemeOnMesh,
        /// Output file.
        #[arg(long, value_name = "FILE")]
        json: PathBuf,
    },
    /// List the schemes and their parameters.
    Schemes,
    /// Measure every scheme on the benchmark meshes; write metrics.{json,csv,md}, SVG plots
    /// and the results page index.html (tables, plots, zebra and curvature thumbnails).
    Report {
        /// Output folder.
        #[arg(long, default_value = "results")]
        out: PathBuf,
        /// A previous report (metrics.json): the page lists the changes against it.
        #[arg(long, value_name = "OLD.json")]
        baseline: Option<PathBuf>,
        /// Measure these meshes instead of the benchmark meshes: a folder (its .obj, .ply, .off
        /// and .stl files) or a list file (one path per line, relative to the list). A mesh
        /// that fails is recorded as an error; the batch goes on.
        #[arg(long, value_name = "DIR|LIST")]
        meshes: Option<PathBuf>,
        /// The schemes: `all` or names separated by commas (e.g. flat,pn).
        #[arg(long, default_value = "all")]
        scheme: String,
        /// A parameter sweep `SCHEME:NAME=V1,V2,…[:NAME2=…]` (every combination), measured
        /// instead of --scheme; repeatable. Not render's --sweep (a stripe sweep).
        #[arg(long = "sweep", value_name = "SCHEME:NAME=V1,V2")]
        sweeps: Vec<String>,
        /// A file of sweeps, one per line (`#` comments); repeatable.
        #[arg(long = "sweep-file", value_name = "FILE")]
        sweep_files: Vec<PathBuf>,
        /// Measure only shard I of N (0 ≤ I < N, balanced by estimated cost) and write the
        /// partial report OUT/partial.json; `smoothlab merge` combines the shards.
        #[arg(long, value_name = "I/N", allow_hyphen_values = true)]
        shard: Option<smoothlab::report::shard::Shard>,
        /// Weld vertices of --meshes files closer than this fraction of the bounding-box
        /// diagonal (0: identical positions only).
        #[arg(
            long,
            value_name = "REL",
            default_value_t = smoothlab::mesh::DEFAULT_WELD_TOLERANCE,
            value_parser = app::parse_weld_tolerance,
            allow_hyphen_values = true
        )]
        weld_tolerance: f64,
        /// Mark edges of --meshes files whose faces' normals are more than DEG degrees
        /// apart sharp, and the edges the file marks (OBJ `s` groups, per-corner `vn`): the
        /// surface is G0 there [default: no sharp edges].
        #[arg(long, value_name = "DEG", value_parser = app::parse_crease_angle, allow_hyphen_values = true)]
        crease_angle: Option<f64>,
        /// A parameter `name=value` that replaces its default for the run, for every scheme
        /// of --scheme that has it (repeatable); the records keep the scheme's name.
        #[arg(long = "param", value_name = "NAME=VALUE")]
        params: Vec<String>,
        /// The history folder whose runs the page's trends show (e.g. the main branch's
        /// results/history); default OUT/history. The run is recorded in OUT/history either
        /// way.
        #[arg(long, value_name = "DIR")]
        history: Option<PathBuf>,
        /// Refuse to repair --meshes files (non-planar or concave polygons, degenerate,
        /// duplicate or inconsistently oriented faces, non-manifold edges and vertices,
        /// non-orientable surfaces): the first repair needed is an error naming the element.
        #[arg(long)]
        strict: bool,
    },
    /// Merge the partial results of sharded runs (`report --shard`, `render --turntable|
    /// --sweep --shard`, `figure --shard`) into what one process would have written; names
    /// missing shards.
    Merge {
        /// The parts: shard folders of `report --shard` (or their partial.json), or the
        /// NAME.shard-I-of-N.json files of a sharded turntable, sweep or figure.
        #[arg(required = true)]
        parts: Vec<PathBuf>,
        /// Output: the report folder, the NAME of the merged frames (NAME-000.png …,
        /// NAME.gif), or the STEM of the merged figure (STEM.png, STEM.svg, its cells' EXRs).
        #[arg(short = 'o', long = "output", value_name = "OUT")]
        output: PathBuf,
        /// Report parts: a previous report (metrics.json) to list the changes against.
        #[arg(long, value_name = "OLD.json")]
        baseline: Option<PathBuf>,
    },
    /// Compare two reports (metrics.json) or two `metrics --json` outputs; exit code 1 if a
    /// quality figure (or, with --timings, a timing) got worse.
    Compare {
        /// The earlier report.
        old: PathBuf,
        /// The later report.
        new: PathBuf,
        /// Relative tolerance of quality figures (finite, ≥ 0).
        #[arg(long, default_value_t = 0.05, allow_negative_numbers = true)]
        quality_rel: f64,
        /// Largest accepted new/old timing ratio (finite, ≥ 1).
        #[arg(long, default_value_t = 1.5, allow_negative_numbers = true)]
        time_ratio: f64,
        /// Judge timings too, when both reports were measured on the same machine.
        #[arg(long)]
        timings: bool,
        /// Judge timings whatever machines the reports were measured on.
        #[arg(long)]
        force_timings: bool,
    },
    /// Ray-trace a surface exactly to NAME.png + NAME.exr (zebra, isophote, curvature, …).
    Render(Box<smoothlab::app::render::RenderArgs>),
    /// Serve an interactive view in the browser: orbit under exact zebra stripes (or any
    /// mode), probe the exact hit under the cursor, save the view as a scene with its PNG and
    /// EXR. Prints the URL (with its access token); Ctrl-C stops it.
    View(Box<smoothlab::app::view::ViewArgs>),
    /// Render a labelled grid (schemes x modes) from a figure spec to PNG + one EXR per cell.
    Figure {
        /// Figure spec files (.toml), rendered in turn.
        #[arg(required = true)]
        specs: Vec<PathBuf>,
        /// Render only shard I of N of the cells (0 ≤ I < N, balanced by estimated cost):
        /// writes those cells (STEM-<row>-<column>-<scheme>-<mode>.png and .exr) and
        /// STEM.shard-I-of-N.json; `smoothlab merge` composes the sheet.
        #[arg(long, value_name = "I/N", allow_hyphen_values = true)]
        shard: Option<smoothlab::report::shard::Shard>,
        /// Colours of the sheet, its legends and the cells' background, instead of the spec's
        /// `theme` [default: the spec's, else dark].
        #[arg(long, value_parser = clap::builder::PossibleValuesParser::new(smoothlab::render::theme::Theme::NAMES))]
        theme: Option<String>,
    },
}

/// The mesh a command builds a surface on, and the scheme with its parameters.
#[derive(Args)]
struct SchemeOnMesh {
    /// The mesh (.obj, .ply, .off or .stl, chosen by extension).
    mesh: PathBuf,
    /// Scheme name (`smoothlab schemes` lists them; `metrics` also takes `all`).
    #[arg(long)]
    scheme: String,
    /// Scheme parameter `name=value` (repeatable).
    #[arg(long = "param", value_name = "NAME=VALUE")]
    params: Vec<String>,
    /// Weld vertices closer than this fraction of the bounding-box diagonal (0: identical
    /// positions only).
    #[arg(
        long,
        value_name = "REL",
        default_value_t = smoothlab::mesh::DEFAULT_WELD_TOLERANCE,
        value_parser = app::parse_weld_tolerance,
        allow_hyphen_values = true
    )]
    weld_tolerance: f64,
    /// Mark edges whose faces' normals are more than DEG degrees apart sharp, and the edges
    /// the file marks (OBJ `s` groups, per-corner `vn`): the surface is G0 there
    /// [default: no sharp edges].
    #[arg(long, value_name = "DEG", value_parser = app::parse_crease_angle, allow_hyphen_values = true)]
    crease_angle: Option<f64>,
    /// Refuse to repair the mesh (non-planar or concave polygons, degenerate, duplicate or
    /// inconsistently oriented faces, non-manifold edges and vertices, non-orientable
    /// surfaces): the first repair needed is an error naming the element.
    #[arg(long)]
    strict: bool,
}

impl SchemeOnMesh {
    /// How the mesh is loaded.
    fn load_options(&self) -> smoothlab::mesh::LoadOptions {
        smoothlab::mesh::LoadOptions {
            weld_tolerance: self.weld_tolerance,
            strict: self.strict,
            ..Default::default()
        }
        .with_crease_angle(self.crease_angle)
    }
}

#[derive(Clone, Copy, ValueEnum)]
enum FormatArg {
    /// smoothlab-patches JSON.
    Json,
    /// BezierView type-3 records.
    Bv,
    /// Tessellated OBJ with exact normals, welded along patch edges.
    Obj,
}

impl From<FormatArg> for Format {
    fn from(f: FormatArg) -> Format {
        match f {
            FormatArg::Json => Format::Json,
            FormatArg::Bv => Format::BezierView,
            FormatArg::Obj => Format::Obj,
        }
    }
}

fn run(cli: Cli) -> smoothlab::Result<Output> {
    match cli.command {
        None => {
            let mut output = app::run_default()?;
            output.stdout += &smoothlab::app::render::run_gallery(Path::new("out/gallery"))?;
            Ok(output)
        }
        Some(Command::Render(mut args)) => {
            args.command_line = Some(command_line());
            let (stats, warnings) = smoothlab::app::render::render_command(&args)?;
            Ok(Output {
                stdout: smoothlab::app::render::render_summary(&stats),
                warnings,
                failed: false,
            })
        }
        Some(Command::View(args)) => {
            smoothlab::app::view::view_command(&args, &mut Printer)?;
            Ok(Output::default())
        }
        Some(Command::Figure {
            specs,
            shard,
            theme,
        }) => {
            let theme = theme
                .map(|name| smoothlab::render::theme::Theme::by_name("--theme", &name))
                .transpose()?;
            let mut stdout = String::new();
            for spec in &specs {
                if let Some(shard) = shard {
                    let files =
                        smoothlab::app::figure::shard::run_figure_spec_shard(spec, shard, theme)?;
                    stdout += &smoothlab::app::figure::shard::shard_summary(&files);
                    continue;
                }
                let files = smoothlab::app::figure::spec::run_figure_spec(spec, theme)?;
                stdout += &smoothlab::app::figure::spec::figure_summary(&files);
            }
            Ok(Output {
                stdout,
                warnings: Vec::new(),
                failed: false,
            })
        }
        Some(Command::Metrics {
            input,
            json,
            explain,
        }) => {
            // Rows are printed as the schemes are measured; a closed pipe ends the printing
            // quietly, any other failure to print is the command's error.
            let (mut stdout, mut failure) = (std::io::stdout(), None);
            let output = app::run_metrics_streaming(
                &input.mesh,
                &input.load_options(),
                &input.scheme,
                &input.params,
                json.as_deref(),
                &mut |line| {
                    if failure.is_none()
                        && let Err(e) = stdout
                            .write_all(line.as_bytes())
                            .and_then(|()| stdout.flush())
                    {
                        failure = Some(e);
                    }
                },
            )?;
            if explain && failure.is_none() {
                failure = stdout
                    .write_all(app::metrics_explanation().as_bytes())
                    .err();
            }
            match failure {
                Some(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(
                    smoothlab::error::Error::Invalid(format!("standard output: {e}")),
                ),
                _ => Ok(output),
            }
        }
        Some(Command::Export {
            input,
            format,
            output,
            tess,
        }) => app::run_export(
            &input.mesh,
            &input.load_options(),
            &input.scheme,
            match format {
                Some(format) => format.into(),
                None => smoothlab::export::Format::from_path(&output)?,
            },
            &output,
            tess,
            &input.params,
        ),
        Some(Command::Sample { input, json }) => app::run_sample(
            &input.mesh,
            &input.load_options(),
            &input.scheme,
            &input.params,
            &json,
        ),
        Some(Command::Schemes) => Ok(app::run_schemes()),
        Some(Command::Report {
            out,
            baseline,
            meshes,
            scheme,
            sweeps,
            sweep_files,
            shard,
            weld_tolerance,
            crease_angle,
            params,
            history,
            strict,
        }) => app::run_report_with(&app::ReportArgs {
            out,
            baseline,
            meshes,
            scheme,
            sweeps,
            sweep_files,
            shard,
            load: smoothlab::mesh::LoadOptions {
                weld_tolerance,
                strict,
                ..Default::default()
            }
            .with_crease_angle(crease_angle),
            params,
            history,
        }),
        Some(Command::Merge {
            parts,
            output,
            baseline,
        }) => app::merge::run_merge(&parts, &output, baseline.as_deref()),
        Some(Command::Compare {
            old,
            new,
            quality_rel,
            time_ratio,
            timings,
            force_timings,
        }) => app::run_compare(
            &old,
            &new,
            smoothlab::report::compare::Thresholds {
                quality_rel,
                time_ratio,
            },
            match (timings, force_timings) {
                (_, true) => smoothlab::report::compare::TimingCheck::Force,
                (true, false) => smoothlab::report::compare::TimingCheck::SameMachine,
                (false, false) => smoothlab::report::compare::TimingCheck::Skip,
            },
        ),
    }
}

/// Prints what `view` reports while it starts, as it happens.
struct Printer;

impl smoothlab::app::view::ViewReport for Printer {
    fn line(&mut self, text: &str) {
        let mut out = std::io::stdout().lock();
        let _ = writeln!(out, "{text}").and_then(|()| out.flush());
    }

    fn warning(&mut self, text: &str) {
        to_stderr(&format!("warning: {text}\n"));
    }
}

/// The command line as typed, arguments with spaces or quotes in single quotes.
fn command_line() -> String {
    std::env::args_os()
        .map(|a| a.to_string_lossy().into_owned())
        .map(|a| {
            if a.is_empty() || a.contains(|c: char| c.is_whitespace() || "'\"$\\".contains(c)) {
                format!("'{}'", a.replace('\'', "'\\''"))
            } else {
                a
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// Writes `text` to standard error. Nothing useful can be done when that fails (e.g. standard
/// error is closed), so a failure is ignored rather than turned into a panic.
fn to_stderr(text: &str) {
    let _ = std::io::stderr().lock().write_all(text.as_bytes());
}

/// Writes `text` to standard output and returns the exit code: `status` when it was written or
/// when the reader closed the pipe (`smoothlab schemes | head -1`: the rest of the output is
/// not wanted, which is no error); 1 with an `error:` line for any other failure (e.g. a full
/// device).
fn to_stdout(text: &str, status: ExitCode) -> ExitCode {
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => status,
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => status,
        Err(e) => {
            to_stderr(&format!("error: standard output: {e}\n"));
            ExitCode::FAILURE
        }
    }
}

fn main() -> ExitCode {
    // An interrupt removes the temporary files being written instead of leaving them behind.
    if let Err(e) = app::clean_up_on_signals() {
        to_stderr(&format!("warning: {e}\n"));
    }
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if !e.use_stderr() => {
            // --help and --version.
            return to_stdout(&e.to_string(), ExitCode::SUCCESS);
        }
        Err(e) => {
            // clap's message is a paragraph (e.g. "required arguments were not provided:"
            // followed by their names), then usage: keep the paragraph, on one line.
            let text = e.to_string();
            let paragraph: Vec<&str> = text
                .lines()
                .take_while(|l| !l.trim().is_empty())
                .map(str::trim)
                .collect();
            to_stderr(&format!(
                "error: {}\n",
                paragraph.join(" ").trim_start_matches("error: ")
            ));
            return ExitCode::FAILURE;
        }
    };
    if let Some(w) = smoothlab::app::limit_threads() {
        to_stderr(&format!("warning: {w}\n"));
    }
    smoothlab::progress::set_quiet(cli.quiet);
    match run(cli) {
        Ok(output) => {
            for w in &output.warnings {
                to_stderr(&format!("warning: {w}\n"));
            }
            let status = if output.failed {
                ExitCode::FAILURE
            } else {
                ExitCode::SUCCESS
            };
            to_stdout(&output.stdout, status)
        }
        Err(e) => {
            to_stderr(&format!("error: {e}\n"));
            ExitCode::FAILURE
        }
    }
}
