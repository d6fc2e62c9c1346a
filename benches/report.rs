//! Not a timing: runs `smoothlab report` (tables, plots, results page) so that the smoothness
//! and accuracy figures of every scheme can be recorded beside the criterion timings.
//!
//! The target is left out of a plain `cargo bench` (`bench = false` in Cargo.toml) and runs
//! only when selected: `cargo bench --bench report`. It writes into a scratch folder under
//! Cargo's target directory (`target/tmp/report-bench/`) unless `SMOOTHLAB_UPDATE_RESULTS=1`
//! asks it to update the committed `results/`. Like criterion's targets it takes a filter
//! (`cargo bench --bench report -- NAME` runs only when `report` contains NAME) and `--list`.

use std::path::PathBuf;

/// The benchmark's name, matched against a filter as criterion matches its benchmark ids.
const NAME: &str = "report";

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.iter().any(|a| a == "--list") {
        println!("{NAME}: benchmark");
        return;
    }
    // Criterion's convention: positional arguments are filters; flags (`--bench`,
    // `--save-baseline NAME`, …) are for the criterion targets and ignored here.
    let mut filters = Vec::new();
    let mut skip_value = false;
    for a in &args {
        if skip_value {
            skip_value = false;
        } else if a.starts_with("--") {
            skip_value = matches!(
                a.as_str(),
                "--save-baseline" | "--baseline" | "--baseline-lenient" | "--load-baseline"
            );
        } else {
            filters.push(a.as_str());
        }
    }
    if !filters.is_empty() && !filters.iter().any(|f| NAME.contains(f)) {
        return;
    }
    let update = std::env::var("SMOOTHLAB_UPDATE_RESULTS").is_ok_and(|v| v == "1");
    // `cargo bench` runs bench targets from the package root.
    let out = if update {
        PathBuf::from("results")
    } else {
        PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("report-bench")
    };
    let start = std::time::Instant::now();
    match smoothlab::testing::report::write(&out) {
        Ok(report) => {
            print!(
                "{}",
                smoothlab::testing::report::summary_line(
                    &report,
                    &out,
                    start.elapsed().as_secs_f64()
                )
            );
            if !update {
                println!(
                    "(scratch folder; SMOOTHLAB_UPDATE_RESULTS=1 cargo bench --bench report \
                     updates results/)"
                );
            }
        }
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
    }
}
