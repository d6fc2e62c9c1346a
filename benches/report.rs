//! Not a timing: runs `smoothlab report` into results/ so that `cargo bench` records the
//! smoothness and accuracy figures of every scheme beside the criterion timings (compare two
//! runs with `smoothlab compare OLD/metrics.json results/metrics.json`).

use std::path::Path;

fn main() {
    // `cargo bench` runs bench targets from the package root.
    let out = Path::new("results");
    match smoothlab::report::write(out) {
        Ok(report) => println!(
            "report: {} records written to {}/metrics.{{json,csv,md}}",
            report.records.len(),
            out.display()
        ),
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
    }
}
