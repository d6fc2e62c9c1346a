//! The smoothlab command line: argument parsing and printing only; the work is done by
//! `smoothlab::cli`.

use std::io::Write;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use smoothlab::cli::{self as commands, Output};

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
    Metrics(commands::MetricsArgs),
    /// Build a scheme on a mesh and write its patches.
    Export(commands::ExportArgs),
    /// Build a scheme on a mesh and write, for every shared edge, points and normals sampled
    /// from both of its faces (edge-samples JSON).
    Sample(commands::SampleArgs),
    /// List the schemes and their parameters.
    Schemes,
    /// Measure every scheme on the benchmark meshes; write metrics.{json,csv,md}, SVG plots
    /// and the results page index.html (tables, plots, zebra and curvature thumbnails).
    Report(commands::ReportCommandArgs),
    /// Merge the partial results of sharded runs (`report --shard`, `render --turntable|
    /// --sweep --shard`, `figure --shard`) into what one process would have written; names
    /// missing shards.
    Merge(commands::MergeArgs),
    /// Compare two reports (metrics.json) or two `metrics --json` outputs; exit code 1 if a
    /// quality figure (or, with --timings, a timing) got worse.
    Compare(commands::CompareArgs),
    /// Ray-trace a surface exactly to NAME.png + NAME.exr (zebra, isophote, curvature, …).
    Render(Box<commands::RenderArgs>),
    /// Serve an interactive view in the browser: orbit under exact zebra stripes (or any
    /// mode), probe the exact hit under the cursor, save the view as a scene with its PNG and
    /// EXR. Prints the URL (with its access token); Ctrl-C stops it.
    View(Box<commands::ViewArgs>),
    /// Render a labelled grid (schemes x modes) from a figure spec to PNG + one EXR per cell.
    Figure(commands::FigureArgs),
}

/// Runs the command: one function of the command layer each.
fn run(cli: Cli) -> smoothlab::Result<Output> {
    match cli.command {
        None => commands::default_command(),
        Some(Command::Render(mut args)) => {
            args.command_line = Some(command_line());
            commands::render_command(&args)
        }
        Some(Command::View(args)) => commands::view_command(&args, &mut Printer),
        Some(Command::Figure(args)) => commands::figure_command(&args),
        Some(Command::Metrics(args)) => {
            // Rows are printed as the schemes are measured; a closed pipe ends the printing
            // quietly, any other failure to print is the command's error.
            let (mut stdout, mut failure) = (std::io::stdout(), None);
            let output = commands::metrics_command(&args, &mut |line| {
                if failure.is_none()
                    && let Err(e) = stdout
                        .write_all(line.as_bytes())
                        .and_then(|()| stdout.flush())
                {
                    failure = Some(e);
                }
            })?;
            match failure.as_ref().and_then(commands::stdout_error) {
                Some(e) => Err(e),
                None => Ok(output),
            }
        }
        Some(Command::Export(args)) => commands::export_command(&args),
        Some(Command::Sample(args)) => commands::sample_command(&args),
        Some(Command::Schemes) => Ok(commands::schemes_command()),
        Some(Command::Report(args)) => commands::report_command(&args),
        Some(Command::Merge(args)) => commands::merge_command(&args),
        Some(Command::Compare(args)) => commands::compare_command(&args),
    }
}

/// Prints what `view` reports while it starts, as it happens.
struct Printer;

impl commands::ViewReport for Printer {
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
    if let Err(e) = commands::clean_up_on_signals() {
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
    if let Some(w) = commands::limit_threads() {
        to_stderr(&format!("warning: {w}\n"));
    }
    commands::set_quiet(cli.quiet);
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
