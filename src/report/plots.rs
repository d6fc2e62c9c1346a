//! SVG plots of a report (plotters): one chart per figure — normal jump between faces,
//! curvature jump, construction time, continuity order, undulation — with the schemes along x
//! and one marked line per benchmark mesh, on a log scale where the figure spans decades.

use std::path::{Path, PathBuf};

use plotters::prelude::*;

use super::Report;
use crate::error::{Error, Result};
use crate::files::{create_folder, write_atomic};

/// The plotted figures: key, title, log scale.
pub const PLOTS: &[(&str, &str, bool)] = &[
    (
        "g1_between_faces_max_rad",
        "largest normal jump between faces (rad)",
        true,
    ),
    (
        "curvature_jump_max_rel",
        "largest relative curvature jump",
        true,
    ),
    ("construct_ms", "construction time (ms)", true),
    (
        "continuity_order",
        "measured continuity order G^k (min over joints)",
        false,
    ),
    (
        "network_undulation_max_rad",
        "curve-network undulation (rad)",
        false,
    ),
];

/// Values below this are drawn at this floor on log charts (exact zeros have no logarithm).
const LOG_FLOOR: f64 = 1e-17;

/// The SVG files [`write_plots`] writes into `dir`, one per entry of [`PLOTS`].
pub fn plot_paths(dir: &Path) -> Vec<PathBuf> {
    PLOTS
        .iter()
        .map(|(key, _, _)| dir.join(format!("{key}.svg")))
        .collect()
}

/// Writes one SVG per entry of [`PLOTS`] into `dir` (created if missing; each file written
/// atomically); returns the paths.
pub fn write_plots(report: &Report, dir: &Path) -> Result<Vec<PathBuf>> {
    create_folder(dir)?;
    let mut schemes: Vec<&str> = Vec::new();
    let mut meshes: Vec<&str> = Vec::new();
    for r in &report.records {
        if !schemes.contains(&r.scheme.as_str()) {
            schemes.push(&r.scheme);
        }
        if !meshes.contains(&r.mesh.as_str()) {
            meshes.push(&r.mesh);
        }
    }
    let paths = plot_paths(dir);
    for (&(key, title, log), path) in PLOTS.iter().zip(&paths) {
        let mut svg = String::new();
        plot_one(report, key, title, log, &schemes, &meshes, &mut svg)
            .map_err(|e| Error::Invalid(format!("{}: {e}", path.display())))?;
        write_atomic(path, svg.as_bytes())?;
    }
    Ok(paths)
}

fn plot_one(
    report: &Report,
    key: &str,
    title: &str,
    log: bool,
    schemes: &[&str],
    meshes: &[&str],
    svg: &mut String,
) -> std::result::Result<(), Box<dyn std::error::Error>> {
    let value = |mesh: &str, scheme: &str| -> Option<f64> {
        report
            .records
            .iter()
            .find(|r| r.mesh == mesh && r.scheme == scheme)
            .and_then(|r| r.figures.get(key))
            .and_then(serde_json::Value::as_f64)
    };
    let transform = |v: f64| if log { v.max(LOG_FLOOR).log10() } else { v };
    let values: Vec<f64> = meshes
        .iter()
        .flat_map(|m| schemes.iter().filter_map(move |s| value(m, s)))
        .map(transform)
        .collect();
    let (lo, hi) = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(*v), b.max(*v))
        });
    let (lo, hi) = if lo.is_finite() {
        (lo.floor() - 0.5, hi.ceil() + 0.5)
    } else {
        (0.0, 1.0)
    };
    let root = SVGBackend::with_string(svg, (900, 520)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .right_y_label_area_size(0)
        .build_cartesian_2d(-0.5f64..schemes.len() as f64 - 0.5, lo..hi)?;
    chart
        .configure_mesh()
        .x_labels(schemes.len())
        .x_label_formatter(&|x| {
            let i = x.round();
            if (x - i).abs() < 1e-6 && i >= 0.0 {
                schemes
                    .get(i as usize)
                    .map_or(String::new(), |s| s.to_string())
            } else {
                String::new()
            }
        })
        .y_label_formatter(&|y| {
            if log {
                format!("1e{y:.0}")
            } else {
                format!("{y:.2}")
            }
        })
        .draw()?;
    for (m, mesh) in meshes.iter().enumerate() {
        let colour = Palette99::pick(m).to_rgba();
        let points: Vec<(f64, f64)> = schemes
            .iter()
            .enumerate()
            .filter_map(|(i, s)| value(mesh, s).map(|v| (i as f64, transform(v))))
            .collect();
        chart
            .draw_series(LineSeries::new(points.clone(), colour.stroke_width(1)))?
            .label(*mesh)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], colour));
        chart.draw_series(points.iter().map(|p| Circle::new(*p, 3, colour.filled())))?;
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()?;
    root.present()?;
    Ok(())
}
