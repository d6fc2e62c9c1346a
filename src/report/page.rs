//! The results page: `index.html` in the report folder, one self-contained HTML file (inline CSS
//! and JavaScript, no network) with the provenance of the run, the metrics tables (one per
//! benchmark mesh, sortable by any column), the SVG plots of [`super::plots`], a zebra and a
//! curvature thumbnail per benchmark mesh and scheme, and — when a baseline report is given —
//! the changes against it as [`super::compare`] judges them.
//!
//! Images are files beside the page, referenced relatively (`figures/*.svg`,
//! `thumbs/MESH-SCHEME-MODE.png`), so the folder can be opened from disk or served as it is.
//! Thumbnails are rendered by the exact renderer ([`RenderJob`]) from one camera per mesh,
//! framing points sampled on every scheme's surface, once per surface: the zebra image, and
//! from the same render's per-pixel geometry record (the ray through each pixel centre, as the
//! EXR's `H` channel) the mean-curvature image, in the curvature mode's diverging colours. The
//! curvature thumbnails of a mesh share one colour range (the median over its curved schemes of
//! the 95th percentile of |H| in view), so their colours compare across schemes.
//!
//! The page checks itself when it loads: its first script records every script error, failed
//! resource load, unhandled rejection and `console.error` call; after the `load` event it counts
//! the tables and the images that decoded and writes `data-ready`, `data-tables`, `data-images`
//! and `data-errors` onto `<body>` (the messages go into `<pre id="page-errors">`). The browser
//! test reads these from the DOM that headless Chromium dumps.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::compare::{Comparison, Verdict};
use super::image_changes::ImageChanges;
use super::trends::Trend;
use super::{COLUMNS, Report, TIMING_RUNS, plots, value_text};
use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::render::camera::Camera;
use crate::render::film::{Frame, RenderSettings};
use crate::render::job::{CameraSpec, Geometry, RenderJob, SurfaceSamples};
use crate::render::modes::Mode;
use crate::render::modes::curvature::abs_percentile;
use crate::render::modes::palette::rdbu;
use crate::render::output::write_png;
use crate::surface::Surface;

/// File name of the page in the report folder.
pub const PAGE: &str = "index.html";

/// Folder of the thumbnails, inside the report folder.
pub const THUMBS: &str = "thumbs";

/// The modes of the thumbnails, in the page's row order.
pub const THUMB_MODES: [&str; 2] = ["zebra", "curvature"];

/// Vertical field of view of the thumbnails' camera, degrees.
const THUMB_FOV: f64 = 30.0;

/// Bright stripes per turn of the thumbnails' zebra mode.
const THUMB_STRIPES: f64 = 8.0;

/// Percentile of |H| that sets a scheme's curvature range.
const CURVATURE_PERCENTILE: f64 = 95.0;

/// Size and sampling of the thumbnails.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThumbnailOptions {
    /// Side of each (square) thumbnail in pixels.
    pub size: u32,
    /// Samples per pixel.
    pub spp: u32,
    /// The tracer: BVH settings and leaf budget (or a tessellation).
    pub geometry: Geometry,
}

impl Default for ThumbnailOptions {
    fn default() -> Self {
        ThumbnailOptions {
            size: 128,
            spp: 1,
            geometry: Geometry::default(),
        }
    }
}

/// The thumbnails of one benchmark mesh.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MeshThumbnails {
    /// Benchmark mesh name.
    pub mesh: String,
    /// The schemes shown, in registry order.
    pub schemes: Vec<String>,
    /// Half-range of the mean curvature `[−r, r]` shared by the mesh's curvature thumbnails.
    pub curvature_half_range: f64,
    /// Side of the (square) thumbnails in pixels.
    pub size: u32,
    /// Milliseconds spent rendering (both modes, every scheme) and writing the PNGs.
    pub ms: f64,
}

/// The thumbnail's path relative to the report folder (as the page references it).
pub fn thumbnail_name(mesh: &str, scheme: &str, mode: &str) -> String {
    // A mesh named by a relative path (`report --meshes LIST`) stays inside `thumbs/`.
    let mesh = mesh.replace(['/', '\\'], "_");
    format!("{THUMBS}/{mesh}-{scheme}-{mode}.png")
}

/// The thumbnail's path inside `out_dir`.
pub fn thumbnail_path(out_dir: &Path, mesh: &str, scheme: &str, mode: &str) -> PathBuf {
    out_dir.join(thumbnail_name(mesh, scheme, mode))
}

/// Renders the zebra and curvature thumbnails of every surface built on `mesh` into
/// `out_dir/thumbs/` (the folder must exist), from one camera framing all of them.
pub fn render_thumbnails(
    mesh_name: &str,
    mesh: &Mesh,
    surfaces: &[(String, Surface)],
    out_dir: &Path,
    options: &ThumbnailOptions,
) -> Result<MeshThumbnails> {
    let start = std::time::Instant::now();
    let surfaces_only: Vec<&Surface> = surfaces.iter().map(|(_, s)| s).collect();
    let samples = SurfaceSamples::new(&surfaces_only);
    let camera = Camera::frame_points(&samples, Camera::DEFAULT_VIEW, THUMB_FOV, 1.0)?;
    let job = |mode: Mode| RenderJob {
        settings: RenderSettings {
            width: options.size,
            height: options.size,
            spp: options.spp,
            mode,
            progress: false,
            ..RenderSettings::default()
        },
        camera: CameraSpec {
            eye: Some(camera.eye),
            target: Some(camera.target),
            up: Some(camera.up()),
            fov_deg: THUMB_FOV,
            orthographic: false,
        },
        geometry: options.geometry,
        ..RenderJob::default()
    };
    // Half the default stripe count: the default's stripes alias at thumbnail size.
    let mut stripes = toml::Table::new();
    stripes.insert("stripes".into(), toml::Value::Float(THUMB_STRIPES));
    let zebra = job(Mode::configured(THUMB_MODES[0], &stripes)?);
    // One render per surface: the zebra image, and the mean curvature seen through each pixel
    // centre (the frame's geometry record, the EXR's `H`), which the curvature thumbnail shows.
    let mut means = Vec::with_capacity(surfaces.len());
    let mut ranges = Vec::new();
    for (scheme, surface) in surfaces {
        let (frame, _) = zebra.render(surface, mesh)?;
        write_png(
            &frame,
            &thumbnail_path(out_dir, mesh_name, scheme, THUMB_MODES[0]),
        )?;
        let pixels: Vec<Option<f64>> = frame
            .geometry
            .iter()
            .map(|g| g.map(|g| g.mean).filter(|h| h.is_finite()))
            .collect();
        let mut curved: Vec<f64> = pixels
            .iter()
            .flatten()
            .copied()
            .filter(|h| *h != 0.0)
            .collect();
        let r = abs_percentile(&mut curved, CURVATURE_PERCENTILE);
        if r > 0.0 && r.is_finite() {
            ranges.push(r);
        }
        means.push(pixels);
    }
    // Flat surfaces (no curvature in view) do not vote; nothing curved at all gives [−1, 1].
    ranges.sort_by(f64::total_cmp);
    let half_range = ranges.get(ranges.len() / 2).copied().unwrap_or(1.0);
    let background = RenderSettings::default().background.as_vec3().to_array();
    for ((scheme, _), pixels) in surfaces.iter().zip(&means) {
        let frame = Frame {
            width: options.size,
            height: options.size,
            rgb: pixels
                .iter()
                .map(|h| match h {
                    // Convex positive (red), as the curvature mode's default: H of the
                    // outward patch normal is negative on convex regions.
                    Some(h) => rdbu((0.5 - 0.5 * h / half_range).clamp(0.0, 1.0))
                        .as_vec3()
                        .to_array(),
                    None => background,
                })
                .collect(),
            geometry: Vec::new(),
            legend: None,
        };
        write_png(
            &frame,
            &thumbnail_path(out_dir, mesh_name, scheme, THUMB_MODES[1]),
        )?;
    }
    Ok(MeshThumbnails {
        mesh: mesh_name.to_string(),
        schemes: surfaces.iter().map(|(s, _)| s.clone()).collect(),
        curvature_half_range: half_range,
        size: options.size,
        ms: start.elapsed().as_secs_f64() * 1e3,
    })
}

/// The baseline a page is compared against: where it was read from, the report, and the
/// comparison of the new report with it.
pub struct Baseline<'a> {
    /// The path given to `--baseline`, as shown on the page.
    pub path: &'a Path,
    /// The baseline report.
    pub report: &'a Report,
    /// The new report compared with the baseline ([`super::compare::compare`]).
    pub comparison: &'a Comparison,
    /// The thumbnails compared with the baseline's ([`super::image_changes`]).
    pub images: Option<&'a ImageChanges>,
}

/// A relative file path as a URL path: every byte but the unreserved characters of RFC 3986
/// (`A-Z a-z 0-9 - . _ ~`) and the separator `/` percent-encoded, so that a file named
/// `hash#1.obj` or `pct%41.obj` is referenced as itself, not as a fragment or another name.
pub fn url_path(path: &str) -> String {
    let mut out = String::with_capacity(path.len());
    for byte in path.bytes() {
        if byte.is_ascii_alphanumeric() || b"-._~/".contains(&byte) {
            out.push(char::from(byte));
        } else {
            out.push_str(&format!("%{byte:02X}"));
        }
    }
    out
}

/// The relative path a `src` attribute value (HTML-escaped, percent-encoded) refers to, or
/// `None` when its escapes are malformed: the inverse of `escape(&url_path(path))`.
fn referenced_path(src: &str) -> Option<String> {
    let unescaped = src
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&quot;", "\"")
        .replace("&#39;", "'")
        .replace("&amp;", "&");
    let bytes = unescaped.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut k = 0;
    while k < bytes.len() {
        if bytes[k] == b'%' {
            let hex = std::str::from_utf8(bytes.get(k + 1..k + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            k += 3;
        } else {
            out.push(bytes[k]);
            k += 1;
        }
    }
    String::from_utf8(out).ok()
}

/// Text with `&`, `<`, `>`, `"` and `'` escaped for HTML text and attribute values.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// The inline style sheet.
const STYLE: &str = "
body { font: 14px/1.4 system-ui, sans-serif; margin: 1.5em; color: #222; }
h1 { font-size: 1.5em; } h2 { margin-top: 1.6em; } h3 { margin-bottom: 0.3em; }
table { border-collapse: collapse; margin: 0.4em 0 1em; font-variant-numeric: tabular-nums; }
th, td { border: 1px solid #ccc; padding: 2px 6px; text-align: right; white-space: nowrap; }
td.error { color: #a00; }
th:first-child, td:first-child { text-align: left; }
thead th { background: #f0f0f0; cursor: pointer; user-select: none; position: sticky; top: 0; }
th[data-dir=asc]::after { content: ' \\25B2'; } th[data-dir=desc]::after { content: ' \\25BC'; }
tr.worse td, td.worse { background: #fde2e2; }
tr.better td, td.better { background: #dff3df; }
td.same { background: #f4f4f4; }
td.best { font-weight: bold; box-shadow: inset 4px 0 #2a8a3a; }
td.worst { box-shadow: inset 4px 0 #c8463c; }
.scroll { overflow-x: auto; }
table.figure { min-width: 24em; }
figure.trend { margin: 0.5em 0 1.5em; }
figure.trend img { max-width: 100%; border: 1px solid #ddd; }
ul.steps { margin: 0.3em 0; padding-left: 1.2em; }
li.step.worse { color: #a00; } li.step.better { color: #186a1e; }
.plots img { width: 480px; max-width: 100%; margin: 0 0.5em 0.5em 0; border: 1px solid #ddd; }
.thumbs td, .thumbs th { border: none; text-align: center; padding: 2px; font-weight: normal; }
.thumbs thead th { background: none; cursor: default; position: static; }
.thumbs img { display: block; image-rendering: auto; }
#page-errors:empty { display: none; }
#page-errors { color: #a00; }
.note { color: #555; }
.error { color: #a00; text-align: left; }
";

/// The first script: records errors of every kind before anything else runs.
const ERROR_CAPTURE: &str = "
window.pageErrors = [];
function pageError(message) { window.pageErrors.push(String(message)); }
window.addEventListener('error', function (ev) {
  var t = ev.target;
  if (t && t !== window && t.tagName) {
    pageError('failed to load ' + t.tagName.toLowerCase() + ' ' + (t.getAttribute('src') || ''));
  } else {
    pageError(ev.message + ' (' + ev.filename + ':' + ev.lineno + ')');
  }
}, true);
window.addEventListener('unhandledrejection', function (ev) {
  pageError('unhandled rejection: ' + ev.reason);
});
(function () {
  var original = console.error;
  console.error = function () {
    pageError(Array.prototype.join.call(arguments, ' '));
    original.apply(console, arguments);
  };
})();
";

/// The last script: sortable tables and the self-check after `load`.
const PAGE_SCRIPT: &str = "
function cellKey(row, column) {
  var cell = row.cells[column];
  if (!cell.hasAttribute('data-v')) { return cell.textContent; }
  var v = cell.getAttribute('data-v');
  return v === '' ? null : Number(v);
}
function sortBy(th) {
  var column = th.cellIndex;
  var table = th.closest('table');
  var body = table.tBodies[0];
  var ascending = th.getAttribute('data-dir') !== 'asc';
  Array.prototype.forEach.call(th.parentNode.cells, function (h) { h.removeAttribute('data-dir'); });
  th.setAttribute('data-dir', ascending ? 'asc' : 'desc');
  var rows = Array.prototype.slice.call(body.rows);
  rows.sort(function (a, b) {
    var x = cellKey(a, column), y = cellKey(b, column);
    if (x === null) { return y === null ? 0 : 1; }
    if (y === null) { return -1; }
    var d = (typeof x === 'number' && typeof y === 'number') ? x - y : String(x).localeCompare(String(y));
    return ascending ? d : -d;
  });
  rows.forEach(function (r) { body.appendChild(r); });
}
document.querySelectorAll('table.sortable thead th').forEach(function (th) {
  th.title = 'sort by this column';
  th.addEventListener('click', function () { sortBy(th); });
});
window.addEventListener('load', function () {
  var images = Array.prototype.slice.call(document.images);
  var loaded = images.filter(function (i) { return i.complete && i.naturalWidth > 0; });
  images.forEach(function (i) {
    if (!(i.complete && i.naturalWidth > 0)) { pageError('image not shown: ' + i.getAttribute('src')); }
  });
  document.getElementById('page-errors').textContent = window.pageErrors.join('\\n');
  var b = document.body;
  b.setAttribute('data-tables', String(document.querySelectorAll('table.sortable').length));
  var width = document.documentElement.clientWidth;
  var wide = Array.prototype.filter.call(document.querySelectorAll('table'), function (t) {
    var box = t.parentElement;
    return t.getBoundingClientRect().right > width + 0.5 || box.scrollWidth > box.clientWidth + 0.5;
  });
  b.setAttribute('data-viewport', String(width));
  b.setAttribute('data-wide-tables', String(wide.length));
  b.setAttribute('data-steps', String(document.querySelectorAll('li.step').length));
  b.setAttribute('data-images', String(loaded.length));
  b.setAttribute('data-errors', String(window.pageErrors.length));
  b.setAttribute('data-ready', 'true');
});
";

/// One numeric or text cell of a metrics table: the shown text and, for numbers, the exact
/// value to sort by in `data-v` (empty for a missing figure, which sorts last).
fn figure_cell(value: Option<&serde_json::Value>) -> String {
    match value {
        Some(serde_json::Value::Number(n)) => format!(
            "<td data-v=\"{}\">{}</td>",
            n,
            escape(&value_text(value).unwrap_or_default())
        ),
        Some(serde_json::Value::String(s)) => format!("<td>{}</td>", escape(s)),
        _ => "<td data-v=\"\">-</td>".to_string(),
    }
}

/// Whether `value` of quality figure `key` is the best or the worst among the schemes
/// measured on `mesh`: `"best"` when no other scheme's value is better beyond the comparison's
/// tolerance ([`super::compare::judge_quality`] at the default relative tolerance),
/// `"worst"` when none is worse; `None` for the others, for figures without a better
/// direction, and where every scheme is the same within tolerance (nothing stands out).
fn rank_among(report: &Report, key: &str, mesh: &str, value: f64) -> Option<&'static str> {
    let rel = super::compare::Thresholds::default().quality_rel;
    let others: Vec<f64> = report
        .records
        .iter()
        .filter(|r| r.mesh == mesh && r.error.is_none())
        .filter_map(|r| r.figures.get(key).and_then(serde_json::Value::as_f64))
        .collect();
    // `judge_quality(key, a, b)` says what moving from a to b would be.
    let verdicts: Vec<Verdict> = others
        .iter()
        .map(|&other| super::compare::judge_quality(key, value, other, rel))
        .collect::<Option<_>>()?;
    let stands_out = others.iter().any(|&a| {
        others
            .iter()
            .any(|&b| super::compare::judge_quality(key, a, b, rel) == Some(Verdict::Better))
    });
    if !stands_out {
        return None;
    }
    if !verdicts.contains(&Verdict::Better) {
        Some("best")
    } else if !verdicts.contains(&Verdict::Worse) {
        Some("worst")
    } else {
        None
    }
}

/// A number of a comparison as a cell (`-` when missing).
fn change_cell(x: Option<f64>) -> String {
    match x {
        Some(x) => format!("<td data-v=\"{x:e}\">{x:.3e}</td>"),
        None => "<td data-v=\"\">-</td>".to_string(),
    }
}

/// The meshes of a report, in record order.
fn meshes(report: &Report) -> Vec<&str> {
    let mut meshes: Vec<&str> = Vec::new();
    for r in &report.records {
        if !meshes.contains(&r.mesh.as_str()) {
            meshes.push(&r.mesh);
        }
    }
    meshes
}

/// The history a page shows: the runs in order (the last one is the page's) and their trends.
pub struct History<'a> {
    /// The runs, in run order.
    pub runs: &'a [super::history::Entry],
    /// The trends of the runs, each plotted as `figures/trend-KEY.svg` beforehand.
    pub trends: &'a [Trend],
    /// What the trends leave out, if anything (timings of other machines).
    pub note: Option<&'a str>,
}

impl History<'_> {
    /// No history (a page of one run without trends).
    pub const NONE: History<'static> = History {
        runs: &[],
        trends: &[],
        note: None,
    };
}

/// The figures of `report` that get a table on the page: the [`COLUMNS`] some record has.
pub fn table_figures(report: &Report) -> Vec<&'static str> {
    COLUMNS
        .iter()
        .copied()
        .filter(|c| report.records.iter().any(|r| r.figures.contains_key(*c)))
        .collect()
}

/// The page for `report`, with the thumbnails `thumbnails` (written beforehand), the changes
/// against `baseline` when given, and the trends of `history`.
pub fn to_html(
    report: &Report,
    thumbnails: &[MeshThumbnails],
    baseline: Option<&Baseline>,
    history: &History,
) -> String {
    let commit = report.describe.as_deref().unwrap_or(&report.commit);
    let mut out = String::new();
    let _ = write!(
        out,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <title>smoothlab results {}</title>\n<script>{ERROR_CAPTURE}</script>\n\
         <style>{STYLE}</style>\n</head>\n<body>\n<h1>smoothlab results</h1>\n\
         <pre id=\"page-errors\"></pre>\n",
        escape(commit)
    );
    let _ = write!(
        out,
        "<p>commit <code>{}</code>, {}",
        escape(commit),
        escape(&report.date)
    );
    if let Some(version) = &report.tool_version {
        let _ = write!(out, ", smoothlab {}", escape(version));
    }
    out += ".";
    if let Some(machine) = &report.machine {
        let _ = write!(
            out,
            " Timings (ms, median of up to {TIMING_RUNS} runs) measured on {}.",
            escape(&machine.describe())
        );
    }
    out += " Lengths relative to the bounding-box diagonal, angles in radians. \
            Files: <a href=\"metrics.json\">metrics.json</a>, \
            <a href=\"metrics.csv\">metrics.csv</a>, <a href=\"metrics.md\">metrics.md</a>. \
            Click a column header to sort.</p>\n<nav><a href=\"#tables\">tables</a> · \
            <a href=\"#trends\">trends</a> · <a href=\"#plots\">plots</a> · \
            <a href=\"#thumbnails\">zebra and curvature</a>";
    if baseline.is_some() {
        out += " · <a href=\"#baseline\">changes against the baseline</a>";
    }
    out += "</nav>\n";
    if let Some(b) = baseline {
        baseline_section(&mut out, b);
    }
    figure_tables(&mut out, report, baseline.map(|b| b.comparison));
    trends_section(&mut out, history);
    out += "<h2 id=\"plots\">Plots</h2>\n<div class=\"plots\">\n";
    for (key, title, _) in plots::PLOTS {
        let _ = writeln!(
            out,
            "<img src=\"figures/{}.svg\" alt=\"{}\" title=\"{}\">",
            escape(&url_path(key)),
            escape(title),
            escape(title)
        );
    }
    out += "</div>\n<h2 id=\"thumbnails\">Zebra stripes and mean curvature</h2>\n\
            <p class=\"note\">Exact ray tracing of each scheme's surface from one camera per mesh. \
            Curvature: mean curvature H on a diverging scale over [−r, r], convex positive (red) and \
            concave negative (blue) for the outward normal, r shared by the schemes of a mesh.</p>\n";
    for t in thumbnails {
        let _ = write!(
            out,
            "<h3 id=\"thumbs-{0}\">{0}</h3>\n<p class=\"note\">curvature range r = {1:.3e}</p>\n\
             <div class=\"scroll\"><table class=\"thumbs\"><thead><tr><th></th>",
            escape(&t.mesh),
            t.curvature_half_range
        );
        for s in &t.schemes {
            let _ = write!(out, "<th>{}</th>", escape(s));
        }
        out += "</tr></thead>\n<tbody>\n";
        for mode in THUMB_MODES {
            let _ = write!(out, "<tr><th>{mode}</th>");
            for s in &t.schemes {
                let _ = write!(
                    out,
                    "<td><img src=\"{}\" width=\"{size}\" height=\"{size}\" alt=\"{} {} {}\" \
                     loading=\"eager\"></td>",
                    escape(&url_path(&thumbnail_name(&t.mesh, s, mode))),
                    escape(&t.mesh),
                    escape(s),
                    mode,
                    size = t.size
                );
            }
            out += "</tr>\n";
        }
        out += "</tbody></table></div>\n";
    }
    let _ = write!(out, "<script>{PAGE_SCRIPT}</script>\n</body>\n</html>\n");
    out
}

/// The metrics, one table per figure: the schemes along one side and the meshes along the
/// other (the fewer of the two as columns, so that a table grows downwards and fits the
/// page); with a comparison, changed cells are marked worse / better / same and carry the
/// value before in their title.
fn figure_tables(out: &mut String, report: &Report, comparison: Option<&Comparison>) {
    let meshes = meshes(report);
    let mut schemes: Vec<&str> = Vec::new();
    for r in &report.records {
        if !schemes.contains(&r.scheme.as_str()) {
            schemes.push(&r.scheme);
        }
    }
    let schemes_as_columns = schemes.len() <= meshes.len();
    let (rows, columns, corner) = if schemes_as_columns {
        (&meshes, &schemes, "mesh \\ scheme")
    } else {
        (&schemes, &meshes, "scheme \\ mesh")
    };
    let _ = writeln!(
        out,
        "<h2 id=\"tables\">Metrics</h2>\n<p class=\"note\">One table per figure. On each \
         mesh, the best scheme's value (beyond the comparison's tolerance) is bold with a green \
         bar, the worst's has a red bar.{}</p>",
        if comparison.is_some() {
            " Cells that changed against the baseline are marked: red worse, green better, \
             grey the same within tolerance (hover for the value before)."
        } else {
            ""
        }
    );
    for key in table_figures(report) {
        let _ = write!(
            out,
            "<h3 id=\"table-{0}\">{0}</h3>\n<table class=\"sortable figure\">\
             <thead><tr><th>{1}</th>",
            escape(key),
            escape(corner)
        );
        for c in columns.iter() {
            let _ = write!(out, "<th>{}</th>", escape(c));
        }
        *out += "</tr></thead>\n<tbody>\n";
        for row in rows.iter() {
            let _ = write!(out, "<tr><td>{}</td>", escape(row));
            for column in columns.iter() {
                let (mesh, scheme) = if schemes_as_columns {
                    (*row, *column)
                } else {
                    (*column, *row)
                };
                let Some(r) = report
                    .records
                    .iter()
                    .find(|r| r.mesh == mesh && r.scheme == scheme)
                else {
                    *out += "<td data-v=\"\"></td>";
                    continue;
                };
                if let Some(error) = &r.error {
                    let _ = write!(
                        out,
                        "<td data-v=\"\" class=\"error\" title=\"{}\">error</td>",
                        escape(error)
                    );
                    continue;
                }
                let record = format!("{mesh} / {scheme}");
                let change = comparison.and_then(|c| {
                    c.changes
                        .iter()
                        .find(|c| c.key == key && c.record == record)
                });
                let cell = figure_cell(r.figures.get(key));
                let mut classes = Vec::new();
                let mut titles = Vec::new();
                if let Some(c) = change {
                    classes.push(verdict_class(c.verdict));
                    titles.push(format!(
                        "{}: before {}, {}",
                        c.verdict.word(),
                        super::compare::number_text(c.old),
                        c.ratio_text()
                    ));
                }
                let rank = r
                    .figures
                    .get(key)
                    .and_then(serde_json::Value::as_f64)
                    .and_then(|v| rank_among(report, key, mesh, v));
                if let Some(rank) = rank {
                    classes.push(rank);
                    titles.push(format!("the {rank} scheme on {mesh}"));
                }
                if classes.is_empty() {
                    *out += &cell;
                } else {
                    *out += &cell.replacen(
                        "<td",
                        &format!(
                            "<td class=\"{}\" title=\"{}\"",
                            classes.join(" "),
                            escape(&titles.join("; "))
                        ),
                        1,
                    );
                }
            }
            *out += "</tr>\n";
        }
        *out += "</tbody></table>\n";
    }
    let errors: Vec<&super::Record> = report
        .records
        .iter()
        .filter(|r| r.error.is_some())
        .collect();
    if !errors.is_empty() {
        let _ = writeln!(out, "<h3 id=\"errors\">Not measured</h3>\n<ul>");
        for r in errors {
            let _ = writeln!(
                out,
                "<li class=\"error\">{} / {}: error: {}</li>",
                escape(&r.mesh),
                escape(&r.scheme),
                escape(r.error.as_deref().unwrap_or_default())
            );
        }
        *out += "</ul>\n";
    }
}

/// The trends over the history: one plot per figure family, and under it the step changes
/// found in it, each with the commit that made it.
fn trends_section(out: &mut String, history: &History) {
    let _ = writeln!(
        out,
        "<h2 id=\"trends\">Trends over commits</h2>\n<p class=\"note\">{} run(s) in the \
         history, oldest first. A step is a change beyond the tolerance of \
         <code>smoothlab compare</code> (timings: beyond the ratio widened by the runs' \
         spread) that the later runs sustain; it is marked at the commit that made it.</p>",
        history.runs.len()
    );
    if let Some(note) = history.note {
        let _ = writeln!(out, "<p class=\"note\">note: {}</p>", escape(note));
    }
    let steps: usize = history.trends.iter().map(|t| t.steps().count()).sum();
    let _ = writeln!(
        out,
        "<p id=\"step-count\" data-steps=\"{steps}\">{steps} step change(s) found.</p>"
    );
    for trend in history.trends {
        let _ = writeln!(
            out,
            "<figure class=\"trend\" id=\"trend-{0}\"><img src=\"{1}\" alt=\"{0} over \
             commits\" title=\"{0} over commits\">",
            escape(&trend.key),
            escape(&url_path(&trend.file()))
        );
        let marked: Vec<_> = trend.steps().collect();
        if !marked.is_empty() {
            *out += "<figcaption><ul class=\"steps\">";
            for (scheme, series, step) in marked {
                let commit = history
                    .runs
                    .get(step.at)
                    .map(|e| e.short_commit())
                    .unwrap_or_default();
                let full = history
                    .runs
                    .get(step.at)
                    .map(|e| e.commit.clone())
                    .unwrap_or_default();
                let change = super::compare::Change {
                    record: String::new(),
                    key: String::new(),
                    old: Some(step.before),
                    new: Some(step.after),
                    verdict: step.verdict,
                };
                let _ = write!(
                    out,
                    "<li class=\"step {}\" data-figure=\"{}\" data-record=\"{} / {}\" \
                     data-commit=\"{}\">{} {} / {}: {} at commit <code>{}</code> ({} → {}, \
                     {})</li>",
                    verdict_class(step.verdict),
                    escape(&trend.key),
                    escape(&series.mesh),
                    escape(scheme),
                    escape(&full),
                    escape(&trend.key),
                    escape(&series.mesh),
                    escape(scheme),
                    step.verdict.word(),
                    escape(&commit),
                    super::compare::number_text(Some(step.before)),
                    super::compare::number_text(Some(step.after)),
                    escape(&change.ratio_text())
                );
            }
            *out += "</ul></figcaption>";
        }
        *out += "</figure>\n";
    }
}

/// The section with the changes against the baseline: one row per listed change, before →
/// after, the relative change and the verdict, regressions red and improvements green.
fn baseline_section(out: &mut String, b: &Baseline) {
    let c = b.comparison;
    let _ = write!(
        out,
        "<h2 id=\"baseline\">Changes against the baseline</h2>\n<p>baseline <code>{}</code>: \
         commit <code>{}</code>, {}. {}, judged as \
         <code>smoothlab compare --timings</code> judges them (default tolerances).</p>\n",
        escape(&b.path.display().to_string()),
        escape(b.report.describe.as_deref().unwrap_or(&b.report.commit)),
        escape(&b.report.date),
        escape(&c.summary())
    );
    for note in &c.notes {
        let _ = writeln!(out, "<p class=\"note\">note: {}</p>", escape(note));
    }
    *out += "<table class=\"sortable\" id=\"baseline-changes\"><thead><tr>\
            <th>record</th><th>figure</th><th>before</th><th>after</th><th>change</th>\
            <th>verdict</th></tr></thead>\n<tbody>\n";
    for change in &c.changes {
        let _ = writeln!(
            out,
            "<tr class=\"{}\"><td>{}</td><td>{}</td>{}{}<td data-v=\"{}\">{}</td><td>{}</td></tr>",
            verdict_class(change.verdict),
            escape(&change.record),
            escape(&change.key),
            change_cell(change.old),
            change_cell(change.new),
            change.ratio().map_or(String::new(), |r| format!("{r:e}")),
            escape(&change.ratio_text()),
            change.verdict.word()
        );
    }
    *out += "</tbody></table>\n";
    if let Some(images) = b.images {
        image_section(out, images);
    }
}

/// The thumbnails that changed against the baseline: before, after and the changed pixels
/// (magenta on grey) side by side, with their count.
fn image_section(out: &mut String, images: &ImageChanges) {
    let _ = write!(
        out,
        "<h3 id=\"image-changes\">Thumbnails that changed</h3>\n<p>{} of {} thumbnail(s) \
         differ from the baseline's{}.</p>\n",
        images.changes.len(),
        images.compared,
        if images.missing > 0 {
            format!(
                "; {} have no baseline thumbnail to compare with",
                images.missing
            )
        } else {
            String::new()
        }
    );
    if images.changes.is_empty() {
        return;
    }
    *out += "<table class=\"thumbs\" id=\"image-changes-table\"><thead><tr><th>mesh</th>\
             <th>scheme</th><th>mode</th><th>before</th><th>after</th><th>changed pixels</th>\
             <th></th></tr></thead>\n<tbody>\n";
    let img = |src: &str| {
        format!(
            "<img src=\"{}\" alt=\"{}\">",
            escape(&url_path(src)),
            escape(src)
        )
    };
    for c in &images.changes {
        let _ = writeln!(
            out,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>\
             <td>{} of {} ({:.2} %), largest channel difference {}</td></tr>",
            escape(&c.mesh),
            escape(&c.scheme),
            escape(&c.mode),
            img(&c.before),
            img(&c.after),
            c.diff
                .as_deref()
                .map_or_else(|| "size changed".to_string(), img),
            c.changed,
            c.pixels,
            100.0 * c.changed as f64 / c.pixels.max(1) as f64,
            c.max_delta
        );
    }
    *out += "</tbody></table>\n";
}

/// The CSS class of a change's row or cell: `worse`, `better` or `same`.
fn verdict_class(verdict: Verdict) -> &'static str {
    match verdict {
        Verdict::Worse => "worse",
        Verdict::Better => "better",
        Verdict::Same => "same",
    }
}

/// Checks that an HTML page names every file it references and that each exists under
/// `dir`: the relative `src` attributes of `page` (HTML-escaped, percent-encoded URL paths). Returns the first missing one as an error.
pub fn check_references(page: &str, dir: &Path) -> Result<usize> {
    let mut count = 0;
    for piece in page.split("src=\"").skip(1) {
        let Some(end) = piece.find('"') else {
            return Err(Error::Invalid("unterminated src attribute".into()));
        };
        let src = &piece[..end];
        if src.contains("://") || src.starts_with('/') {
            return Err(Error::Invalid(format!(
                "{src}: the page must reference files beside it only"
            )));
        }
        let path = referenced_path(src).ok_or_else(|| {
            Error::Invalid(format!(
                "{src}: a reference of the page with a broken escape"
            ))
        })?;
        if !dir.join(&path).is_file() {
            return Err(Error::Invalid(format!(
                "{}: referenced by the page but missing",
                dir.join(&path).display()
            )));
        }
        count += 1;
    }
    Ok(count)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::compare::Change;
    use crate::report::{REPORT_VERSION, Record};

    fn report() -> Report {
        let mut figures = serde_json::Map::new();
        figures.insert("patches".into(), 4.into());
        figures.insert("g1_between_faces_max_rad".into(), 1.5e-3.into());
        figures.insert("continuity_order".into(), "n/a".into());
        Report {
            format: "smoothlab-report".into(),
            version: REPORT_VERSION,
            commit: "abc".into(),
            date: "2026-01-01T00:00:00Z".into(),
            records: vec![Record {
                mesh: "cube".into(),
                scheme: "hb<&>".into(),
                figures,
                error: None,
            }],
            describe: None,
            dirty: None,
            tool_version: None,
            machine: None,
            shards: None,
        }
    }

    /// Best and worst per mesh, beyond the comparison's tolerance, in the figure's direction.
    #[test]
    fn the_best_and_worst_scheme_of_each_mesh_are_marked() {
        let mut r = report();
        let base = r.records[0].clone();
        r.records.clear();
        for (mesh, scheme, g1, order) in [
            ("cube", "a", 1e-3, 2),
            ("cube", "b", 1.02e-3, 1),
            ("cube", "c", 5e-3, 1),
            ("ball", "a", 1e-3, 1),
            ("ball", "b", 1.01e-3, 1),
        ] {
            let mut rec = base.clone();
            rec.mesh = mesh.into();
            rec.scheme = scheme.into();
            rec.figures.insert("g1_max_rad".into(), g1.into());
            rec.figures.insert("continuity_order".into(), order.into());
            r.records.push(rec);
        }
        let rank = |mesh, key, v| rank_among(&r, key, mesh, v);
        // a and b are the same within 5 %: both best; c is worst.
        assert_eq!(rank("cube", "g1_max_rad", 1e-3), Some("best"));
        assert_eq!(rank("cube", "g1_max_rad", 1.02e-3), Some("best"));
        assert_eq!(rank("cube", "g1_max_rad", 5e-3), Some("worst"));
        // Higher is better for the order, judged exactly.
        assert_eq!(rank("cube", "continuity_order", 2.0), Some("best"));
        assert_eq!(rank("cube", "continuity_order", 1.0), Some("worst"));
        // On the ball nothing stands out; a figure without a direction is never ranked.
        assert_eq!(rank("ball", "g1_max_rad", 1e-3), None);
        assert_eq!(rank("ball", "continuity_order", 1.0), None);
        assert_eq!(rank("cube", "patches", 4.0), None);
        let page = to_html(&r, &[], None, &History::NONE);
        assert!(
            page.contains("<td class=\"best\" title=\"the best scheme on cube\" data-v=\"2\">"),
            "{page}"
        );
    }

    #[test]
    fn escape_covers_markup_characters() {
        assert_eq!(escape("a<b>&\"c'"), "a&lt;b&gt;&amp;&quot;c&#39;");
    }

    #[test]
    fn tables_carry_sort_values_and_escape_names() {
        let mut two = report();
        let mut torus = two.records[0].clone();
        torus.mesh = "torus".into();
        torus.figures.remove("g1_between_faces_max_rad");
        two.records.push(torus);
        let page = to_html(&two, &[], None, &History::NONE);
        assert!(page.contains("<th>hb&lt;&amp;&gt;</th>"), "scheme escaped");
        assert!(
            page.contains("<tr><td>cube</td><td data-v=\"4\">4</td></tr>"),
            "integer cell"
        );
        assert!(
            page.contains("<td data-v=\"0.0015\">1.500e-3</td>"),
            "float cell"
        );
        assert!(page.contains("<td>n/a</td>"), "text cell");
        // A figure the record lacks sorts last (empty data-v) and shows as '-'.
        assert!(page.contains("<tr><td>torus</td><td data-v=\"\">-</td></tr>"));
        // One table per figure some record has.
        assert_eq!(
            table_figures(&two),
            ["patches", "g1_between_faces_max_rad", "continuity_order"]
        );
        assert_eq!(page.matches("<table class=\"sortable figure\"").count(), 3);
        assert!(!page.contains("id=\"baseline\""));
        // Every plot, no thumbnails, no trends without a history.
        assert_eq!(page.matches("<img ").count(), plots::PLOTS.len());
        assert!(page.contains("data-steps=\"0\""));
        assert!(!page.contains("http://") && !page.contains("https://"));
    }

    #[test]
    fn baseline_changes_are_listed_with_their_verdicts() {
        let new = report();
        let comparison = Comparison {
            changes: vec![
                Change {
                    record: "cube / hb".into(),
                    key: "g1_max_rad".into(),
                    old: Some(0.1),
                    new: Some(0.2),
                    verdict: Verdict::Worse,
                },
                Change {
                    record: "cube / hb<&>".into(),
                    key: "g1_between_faces_max_rad".into(),
                    old: Some(1e-3),
                    new: Some(1.5e-3),
                    verdict: Verdict::Worse,
                },
                Change {
                    record: "cube / pn".into(),
                    key: "construct_ms".into(),
                    old: Some(20.0),
                    new: Some(10.0),
                    verdict: Verdict::Better,
                },
            ],
            unlisted: 3,
            new_figures: 0,
            notes: vec!["timings <not> judged".into()],
        };
        let page = to_html(
            &new,
            &[],
            Some(&Baseline {
                path: Path::new("old.json"),
                report: &new,
                comparison: &comparison,
                images: None,
            }),
            &History::NONE,
        );
        assert!(
            page.contains(
                "2 regression(s), 1 improvement(s), 0 within tolerance among 3 change(s); 3 \
                 last-digit change(s) not listed"
            ),
            "{page}"
        );
        assert!(page.contains(
            "<tr class=\"worse\"><td>cube / hb</td><td>g1_max_rad</td><td data-v=\"1e-1\">\
             1.000e-1</td><td data-v=\"2e-1\">2.000e-1</td><td data-v=\"2e0\">+100.0%</td>\
             <td>WORSE</td></tr>"
        ));
        assert!(page.contains("<td data-v=\"5e-1\">-50.0%</td><td>BETTER</td></tr>"));
        // The changed cell of the figure table is marked, with the value before.
        assert!(
            page.contains(
                "<td class=\"worse\" title=\"WORSE: before 1.000e-3, +50.0%\" \
                 data-v=\"0.0015\">1.500e-3</td>"
            ),
            "{page}"
        );
        assert!(page.contains("note: timings &lt;not&gt; judged"));
        assert_eq!(page.matches("<table class=\"sortable").count(), 4);
    }

    #[test]
    fn missing_references_are_named() {
        let dir = std::env::temp_dir().join(format!("smoothlab-page-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("figures")).expect("scratch");
        std::fs::write(dir.join("figures/a.svg"), "<svg/>").expect("write");
        let ok = "<img src=\"figures/a.svg\">";
        assert_eq!(check_references(ok, &dir).expect("present"), 1);
        let missing = "<img src=\"figures/a.svg\"><img src=\"thumbs/b.png\">";
        let err = check_references(missing, &dir).expect_err("missing");
        assert!(err.to_string().contains("thumbs/b.png"), "{err}");
        let remote = "<img src=\"https://example.org/x.png\">";
        assert!(check_references(remote, &dir).is_err());
        // Names with markup and URL characters are found under their own names.
        for name in [
            "Bob's chair & \"co\" <1>.png",
            "hash#1.png",
            "pct%41.png",
            "é ü.png",
        ] {
            std::fs::write(dir.join("figures").join(name), "png").expect("write");
            let src = escape(&url_path(&format!("figures/{name}")));
            let page = format!("<img src=\"{src}\">");
            assert_eq!(check_references(&page, &dir).expect(name), 1, "{page}");
            assert!(!src.contains(['#', '\'', ' ', '&']), "{src}");
        }
        assert_eq!(url_path("thumbs/pct%41.obj"), "thumbs/pct%2541.obj");
        assert_eq!(url_path("a b/é"), "a%20b/%C3%A9");
        assert!(check_references("<img src=\"figures/a%4\">", &dir).is_err());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
