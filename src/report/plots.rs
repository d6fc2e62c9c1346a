//! SVG plots of a report (plotters): one chart per figure — normal jump between faces,
//! curvature jump, construction time, continuity order, undulation — with the schemes along x
//! (categories: one dot per benchmark mesh, side by side within its scheme's column, no lines
//! across schemes), on a log scale where the figure spans decades and with integer ticks for the
//! continuity order. The legend of the meshes is a column right of the chart, covering no point.

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

/// Plotted figures whose values are integers: integer ticks only.
const INTEGER_PLOTS: &[&str] = &["continuity_order"];

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
    let integer = INTEGER_PLOTS.contains(&key);
    let (lo, hi) = if integer {
        (lo - 0.5, hi + 0.5)
    } else {
        (lo, hi)
    };
    let root = SVGBackend::with_string(svg, (900, 520)).into_drawing_area();
    root.fill(&WHITE)?;
    let (plot_area, legend) = root.split_horizontally(740);
    let mut chart = ChartBuilder::on(&plot_area)
        .caption(title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(80)
        .build_cartesian_2d(-0.5f64..schemes.len() as f64 - 0.5, lo..hi)?;
    let y_labels = if integer {
        ((hi - lo).round() as usize + 1).clamp(2, 12)
    } else {
        10
    };
    chart
        .configure_mesh()
        .disable_x_mesh()
        .x_labels(schemes.len() * 2 + 1)
        .y_labels(y_labels)
        .label_style(("sans-serif", 15))
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
            let i = y.round();
            if log {
                if (y - i).abs() < 1e-6 {
                    format!("1e{i:.0}")
                } else {
                    String::new()
                }
            } else if integer {
                if (y - i).abs() < 1e-6 {
                    format!("{i:.0}")
                } else {
                    String::new()
                }
            } else {
                format!("{y:.2}")
            }
        })
        .draw()?;
    // Each mesh has its own slot within a scheme's column, so equal values do not hide
    // each other.
    let slot = |m: usize| {
        if meshes.len() <= 1 {
            0.0
        } else {
            -0.35 + 0.7 * m as f64 / (meshes.len() - 1) as f64
        }
    };
    for (m, mesh) in meshes.iter().enumerate() {
        let colour = Palette99::pick(m).to_rgba();
        let points: Vec<(f64, f64)> = schemes
            .iter()
            .enumerate()
            .filter_map(|(i, s)| value(mesh, s).map(|v| (i as f64 + slot(m), transform(v))))
            .collect();
        chart.draw_series(points.iter().map(|p| Circle::new(*p, 4, colour.filled())))?;
        let y = 40 + 24 * m as i32;
        legend.draw(&Circle::new((12, y + 8), 5, colour.filled()))?;
        legend.draw(&Text::new(
            mesh.to_string(),
            (24, y),
            ("sans-serif", 15).into_font().color(&BLACK),
        ))?;
    }
    root.present()?;
    Ok(())
}
