//! Trends over the results history ([`super::history`]): per figure family one small SVG
//! plot over commits (plotters) — every tracked quality figure of [`super::compare`], one
//! panel per scheme and one series per mesh, and the construction time the same way, from the
//! runs of one machine only — with the step changes of each series ([`history::steps`])
//! marked at the commit that made them.
//!
//! The commit axis is ordinal (runs in order, integer ticks, labelled by commit); counts (the
//! continuity order, the folds) get integer ticks on the value axis too; figures spanning more
//! than a decade are drawn on a log scale. The legend of the meshes is a strip below the panels,
//! so it covers no point.

use std::path::{Path, PathBuf};

use plotters::prelude::*;

use super::compare::{self, Verdict};
use super::history::{self, Entry};
use crate::error::{Error, Result};
use crate::files::write_atomic;

/// The timing benchmark plotted.
pub const TIMING_KEY: &str = "construct_ms";

/// Values below this are drawn at this floor on log charts (exact zeros have no logarithm).
const LOG_FLOOR: f64 = 1e-17;

/// Quality figures that are counts (integer ticks).
const COUNTS: &[&str] = &["continuity_order", "folds", "folded_patches"];

/// Panels per row of a trend plot.
const PANEL_COLUMNS: usize = 4;

/// Size of one panel, pixels.
const PANEL: (u32, u32) = (330, 210);

/// Height of the legend strip, pixels per row of legend entries.
const LEGEND_ROW: u32 = 22;

/// One series of a trend: a mesh under one scheme, a value per history entry.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// Benchmark mesh.
    pub mesh: String,
    /// One value per history entry (None where the entry lacks it).
    pub values: Vec<Option<f64>>,
    /// Its step changes.
    pub steps: Vec<history::Step>,
}

/// One panel: the series of one scheme.
#[derive(Clone, Debug, PartialEq)]
pub struct Panel {
    /// Scheme (variant label).
    pub scheme: String,
    /// One series per mesh that has a value.
    pub series: Vec<Series>,
}

/// The trend of one figure family.
#[derive(Clone, Debug, PartialEq)]
pub struct Trend {
    /// The figure's key (`g1_between_faces_max_rad`, `construct_ms`).
    pub key: String,
    /// True for a timing (judged within one machine).
    pub timing: bool,
    /// The entries' commits, in run order (as shown on the axis).
    pub commits: Vec<String>,
    /// The panels, schemes in record order.
    pub panels: Vec<Panel>,
}

impl Trend {
    /// The plot's path relative to the report folder.
    pub fn file(&self) -> String {
        trend_file(&self.key)
    }

    /// Every step of the trend: (scheme, series, step).
    pub fn steps(&self) -> impl Iterator<Item = (&str, &Series, &history::Step)> {
        self.panels.iter().flat_map(|p| {
            p.series
                .iter()
                .flat_map(move |s| s.steps.iter().map(move |st| (p.scheme.as_str(), s, st)))
        })
    }
}

/// The path, relative to the report folder, of the trend plot of `key`.
pub fn trend_file(key: &str) -> String {
    format!("figures/trend-{key}.svg")
}

/// The keys that can have a trend plot: the tracked quality figures, then the timing.
pub fn trend_keys() -> Vec<&'static str> {
    compare::quality_keys()
        .chain(std::iter::once(TIMING_KEY))
        .collect()
}

/// The (mesh, scheme) pairs of the entries, in first-seen order, latest entry first.
fn records(entries: &[Entry]) -> (Vec<String>, Vec<String>) {
    let (mut meshes, mut schemes) = (Vec::<String>::new(), Vec::<String>::new());
    for e in entries.iter().rev() {
        for r in &e.quality {
            if !meshes.contains(&r.mesh) {
                meshes.push(r.mesh.clone());
            }
            if !schemes.contains(&r.scheme) {
                schemes.push(r.scheme.clone());
            }
        }
    }
    (meshes, schemes)
}

/// The trends of `entries` (in run order): one per tracked quality figure with any value, and
/// the construction time over the entries measured on the machine of the last entry (others'
/// timings are left out, with a note in the second value).
pub fn trends(entries: &[Entry]) -> (Vec<Trend>, Option<String>) {
    let (meshes, schemes) = records(entries);
    let commits: Vec<String> = entries.iter().map(Entry::short_commit).collect();
    let machine = entries.last().and_then(|e| e.timings.machine.clone());
    let same_machine: Vec<bool> = entries
        .iter()
        .map(|e| machine.is_some() && e.timings.machine == machine)
        .collect();
    let others = same_machine.iter().filter(|s| !**s).count();
    let note = (others > 0).then(|| {
        format!(
            "construction times of {others} run(s) measured on another machine (or on an \
             unknown one) are left out of the timing trend"
        )
    });
    let mut out = Vec::new();
    for key in trend_keys() {
        let timing = key == TIMING_KEY;
        let mut panels = Vec::new();
        for scheme in &schemes {
            let mut series = Vec::new();
            for mesh in &meshes {
                let (values, spreads): (Vec<Option<f64>>, Vec<f64>) = entries
                    .iter()
                    .zip(&same_machine)
                    .map(|(e, same)| {
                        if timing {
                            match e.timing(mesh, scheme, key).filter(|_| *same) {
                                Some(t) => (Some(t.median_ms), t.spread_rel.unwrap_or(0.0)),
                                None => (None, 0.0),
                            }
                        } else {
                            (e.quality(mesh, scheme, key), 0.0)
                        }
                    })
                    .unzip();
                if values.iter().all(Option::is_none) {
                    continue;
                }
                let spread = spreads.iter().copied().fold(0.0, f64::max);
                let judge = |a: f64, b: f64| {
                    if timing {
                        history::judge_timing(a, b, spread)
                    } else {
                        history::judge_quality(key, a, b).unwrap_or(Verdict::Same)
                    }
                };
                let steps = history::steps(&values, &judge);
                series.push(Series {
                    mesh: mesh.clone(),
                    values,
                    steps,
                });
            }
            if !series.is_empty() {
                panels.push(Panel {
                    scheme: scheme.clone(),
                    series,
                });
            }
        }
        if !panels.is_empty() {
            out.push(Trend {
                key: key.to_string(),
                timing,
                commits: commits.clone(),
                panels,
            });
        }
    }
    (out, note)
}

/// The files [`write_trends`] may write into the report folder `out_dir`.
pub fn trend_paths(out_dir: &Path) -> Vec<PathBuf> {
    trend_keys()
        .iter()
        .map(|k| out_dir.join(trend_file(k)))
        .collect()
}

/// Writes the SVG of every trend into the report folder `out_dir` (whose `figures/` exists).
pub fn write_trends(trends: &[Trend], out_dir: &Path) -> Result<()> {
    for trend in trends {
        let path = out_dir.join(trend.file());
        let mut svg = String::new();
        plot_trend(trend, &mut svg)
            .map_err(|e| Error::Invalid(format!("{}: {e}", path.display())))?;
        write_atomic(&path, svg.as_bytes())?;
    }
    Ok(())
}

/// The colour of mesh number `m`.
fn colour(m: usize) -> RGBColor {
    let c = Palette99::pick(m).to_rgba();
    RGBColor(c.0, c.1, c.2)
}

/// The colour of a step's marker: red for worse, green for better.
fn step_colour(verdict: Verdict) -> RGBColor {
    match verdict {
        Verdict::Worse => RGBColor(200, 30, 30),
        _ => RGBColor(20, 140, 40),
    }
}

/// The label of the commit at `k` on the axis: at most 8 characters.
fn commit_label(trend: &Trend, k: usize) -> String {
    trend
        .commits
        .get(k)
        .map(|c| c.chars().take(8).collect())
        .unwrap_or_default()
}

type DrawResult = std::result::Result<(), Box<dyn std::error::Error>>;

fn plot_trend(trend: &Trend, svg: &mut String) -> DrawResult {
    let meshes: Vec<&str> = {
        let mut m: Vec<&str> = Vec::new();
        for p in &trend.panels {
            for s in &p.series {
                if !m.contains(&s.mesh.as_str()) {
                    m.push(&s.mesh);
                }
            }
        }
        m
    };
    let columns = PANEL_COLUMNS.min(trend.panels.len()).max(1);
    let rows = trend.panels.len().div_ceil(columns);
    let legend_per_row = 6;
    let legend_rows = meshes.len().div_ceil(legend_per_row) as u32;
    let width = PANEL.0 * columns as u32;
    let height = 36 + PANEL.1 * rows as u32 + legend_rows * LEGEND_ROW + 8;
    let root = SVGBackend::with_string(svg, (width, height)).into_drawing_area();
    root.fill(&WHITE)?;
    let title = if trend.timing {
        format!("{} over commits (ms, one machine)", trend.key)
    } else {
        format!("{} over commits", trend.key)
    };
    let (head, rest) = root.split_vertically(36);
    head.draw(&Text::new(
        title,
        (8, 8),
        ("sans-serif", 20).into_font().color(&BLACK),
    ))?;
    let (grid, legend) = rest.split_vertically(PANEL.1 * rows as u32);
    let count = COUNTS.contains(&trend.key.as_str());
    let cells = grid.split_evenly((rows, columns));
    for (panel, area) in trend.panels.iter().zip(cells) {
        plot_panel(trend, panel, &meshes, count, &area)?;
    }
    for (m, mesh) in meshes.iter().enumerate() {
        let x = (m % legend_per_row) as i32 * (width as i32 / legend_per_row as i32) + 10;
        let y = (m / legend_per_row) as i32 * LEGEND_ROW as i32 + 6;
        legend.draw(&Circle::new((x + 5, y + 7), 5, colour(m).filled()))?;
        legend.draw(&Text::new(
            mesh.to_string(),
            (x + 16, y),
            ("sans-serif", 14).into_font().color(&BLACK),
        ))?;
    }
    root.present()?;
    Ok(())
}

fn plot_panel(
    trend: &Trend,
    panel: &Panel,
    meshes: &[&str],
    count: bool,
    area: &DrawingArea<SVGBackend, plotters::coord::Shift>,
) -> DrawResult {
    let values: Vec<f64> = panel
        .series
        .iter()
        .flat_map(|s| s.values.iter().flatten().copied())
        .collect();
    let (min, max) = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(*v), b.max(*v))
        });
    let log = !count && min >= 0.0 && max > 0.0 && max / min.max(LOG_FLOOR) > 10.0;
    let transform = move |v: f64| if log { v.max(LOG_FLOOR).log10() } else { v };
    let (lo, hi) = (transform(min), transform(max));
    let (lo, hi) = if count || log {
        (lo.floor() - 1.0, hi.ceil() + 1.0)
    } else if hi > lo {
        let pad = 0.15 * (hi - lo);
        (lo - pad, hi + pad)
    } else {
        let pad = 0.1 * lo.abs().max(1e-12);
        (lo - pad, hi + pad)
    };
    let n = trend.commits.len();
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.scheme, ("sans-serif", 16))
        .margin(6)
        .x_label_area_size(30)
        .y_label_area_size(62)
        .build_cartesian_2d(-0.5f64..n as f64 - 0.5, lo..hi)?;
    let x_labels = n.min(5);
    let y_labels = if count {
        ((hi - lo) as usize + 1).min(8)
    } else {
        5
    };
    chart
        .configure_mesh()
        .light_line_style(WHITE)
        .x_labels(x_labels.max(1))
        .y_labels(y_labels)
        .label_style(("sans-serif", 12))
        .x_label_formatter(&|x| {
            let i = x.round();
            if (x - i).abs() < 1e-6 && i >= 0.0 {
                commit_label(trend, i as usize)
            } else {
                String::new()
            }
        })
        .y_label_formatter(&|y| {
            if log || count {
                let i = y.round();
                if (y - i).abs() > 1e-6 {
                    String::new()
                } else if log {
                    format!("1e{i:.0}")
                } else {
                    format!("{i:.0}")
                }
            } else {
                format!("{y:.3e}")
            }
        })
        .draw()?;
    for series in &panel.series {
        let m = meshes.iter().position(|x| *x == series.mesh).unwrap_or(0);
        let points: Vec<(f64, f64)> = series
            .values
            .iter()
            .enumerate()
            .filter_map(|(k, v)| v.map(|v| (k as f64, transform(v))))
            .collect();
        let c = colour(m);
        chart.draw_series(LineSeries::new(points.clone(), c.mix(0.5).stroke_width(1)))?;
        chart.draw_series(points.iter().map(|p| Circle::new(*p, 3, c.filled())))?;
    }
    // The steps: a dashed line before the commit that made each, labelled with that commit.
    let mut marked: Vec<(usize, Verdict)> = Vec::new();
    for series in &panel.series {
        for step in &series.steps {
            chart.draw_series(std::iter::once(Circle::new(
                (step.at as f64, transform(step.after)),
                6,
                step_colour(step.verdict).stroke_width(2),
            )))?;
            if !marked.contains(&(step.at, step.verdict)) {
                marked.push((step.at, step.verdict));
            }
        }
    }
    for (k, (at, verdict)) in marked.iter().enumerate() {
        let x = *at as f64 - 0.5;
        let c = step_colour(*verdict);
        chart.draw_series(DashedLineSeries::new(
            vec![(x, lo), (x, hi)],
            4,
            3,
            c.stroke_width(2),
        ))?;
        let arrow = if *verdict == Verdict::Worse {
            "worse"
        } else {
            "better"
        };
        let y = hi - (hi - lo) * (0.08 + 0.1 * k as f64);
        let label = format!("step {arrow} at {}", commit_label(trend, *at));
        // Beside the line, on the side with room: about 6.5 px a character over the plot's
        // width of the panel.
        let units_per_px = n as f64 / f64::from(PANEL.0 - 80);
        let width = label.chars().count() as f64 * 6.5 * units_per_px;
        let left = x - 0.05 - width;
        let text_x = if x + 0.05 + width > n as f64 - 0.5 && left > -0.5 {
            left
        } else {
            x + 0.05
        };
        chart.draw_series(std::iter::once(Text::new(
            label,
            (text_x, y),
            ("sans-serif", 12).into_font().color(&c),
        )))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::history::{QualityRecord, Timings};

    fn entry(commit: &str, g1: f64) -> Entry {
        let mut figures = serde_json::Map::new();
        figures.insert("g1_max_rad".into(), g1.into());
        figures.insert("continuity_order".into(), 1.into());
        Entry {
            format: history::FORMAT.into(),
            version: history::VERSION,
            commit: commit.into(),
            describe: None,
            date: format!("2026-01-0{}T00:00:00Z", commit.len()),
            tool_version: None,
            quality: vec![QualityRecord {
                mesh: "cube".into(),
                scheme: "hb".into(),
                figures,
            }],
            timings: Timings {
                machine: None,
                records: Vec::new(),
            },
        }
    }

    #[test]
    fn the_step_is_found_and_marked_at_its_commit() {
        let entries = [entry("c1", 1e-15), entry("c22", 2e-15), entry("c333", 0.05)];
        let (trends, note) = trends(&entries);
        assert!(note.is_some(), "no machine: timings left out");
        let keys: Vec<&str> = trends.iter().map(|t| t.key.as_str()).collect();
        assert_eq!(keys, ["g1_max_rad", "continuity_order"]);
        let steps: Vec<(&str, &str, usize)> = trends
            .iter()
            .flat_map(|t| {
                t.steps()
                    .map(|(scheme, s, st)| (scheme, s.mesh.as_str(), st.at))
            })
            .collect();
        assert_eq!(steps, [("hb", "cube", 2)]);
        let mut svg = String::new();
        plot_trend(&trends[0], &mut svg).expect("plot");
        assert!(svg.contains("step worse at c333"), "marker labelled");
        assert_eq!(svg.matches("step ").count(), 1);
        // Integer ticks only on the count's axis.
        let mut svg = String::new();
        plot_trend(&trends[1], &mut svg).expect("plot");
        assert!(!svg.contains(".5<") && !svg.contains("0.50"), "{svg}");
    }
}
