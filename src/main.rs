//! The smoothlab command line: argument parsing and printing only.

use std::path::Path;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// Smooth surfaces from triangle meshes, ray-traced exactly and measured.
#[derive(Parser)]
#[command(version, about)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Ray-trace a surface exactly to PNG + EXR (zebra, isophote, curvature, …).
    Render(smoothlab::render::cli::RenderArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Some(Command::Render(args)) => smoothlab::render::cli::render_command(&args).map(|stats| {
            println!(
                "{} rays, {} hits, Newton mean {:.2} max {}, {} failures, BVH {:.1} ms, render {:.1} ms",
                stats.rays,
                stats.hits,
                stats.newton_iter_mean,
                stats.newton_iter_max,
                stats.newton_failures,
                stats.bvh_build_ms,
                stats.render_ms
            );
        }),
        None => smoothlab::render::gallery::render_gallery(Path::new("out/gallery")).map(|g| {
            print!("{}", smoothlab::render::gallery::gallery_table(&g));
            println!("wrote {}", g.sheet.display());
        }),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("smoothlab: {e}");
            ExitCode::FAILURE
        }
    }
}
