//! Sharded figures: `smoothlab figure SPEC.toml --shard I/N` renders a deterministic,
//! cost-balanced share of the cells and writes them — each cell's EXR (as the whole run writes
//! it, unless `exr = false`) and its 8-bit PNG `STEM-<row>-<column>-<scheme>-<mode>.png` —
//! with the part file `STEM.shard-I-of-N.json` ([`FigurePart`]); `smoothlab merge` composes
//! the sheet PNG and SVG from the cells' PNGs ([`merge_figure`]), the bytes the whole run
//! writes.
//!
//! Every shard builds every surface of the spec: the common camera frames all of them, so a
//! shard cannot know it without them. What is split is the rendering, which dominates (a cell
//! of 256 × 256 pixels at 4 samples costs more than building its surface on a scenes/ mesh). A
//! shard builds the tracer (BVH) of a surface only when it renders one of its cells — or, for a
//! common automatic curvature range, when it renders a curvature cell (the range is the median
//! over all curved surfaces, computed as the whole run computes it).
//!
//! Cells are dealt one by one by [`crate::report::shard::assign`] over [`cell_costs`], not
//! grouped by surface: cells of one surface differ in cost by mode, and grouping would leave
//! at most one shard per surface.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::spec::FigureSpec;
use super::{FigureJob, render_cells, sheet_labels, svg_images};
use crate::error::{Error, Result};
use crate::files::{check_writable, create_folder, write_atomic};
use crate::render::output::{
    check_output_name, output_stem, with_suffix, write_exr, write_png, write_rgb_png,
};
use crate::render::theme::Theme;
use crate::report::shard::{Manifest, Shard, items_of, read_complete_parts};

/// The kind of work of partial figures, in their [`Manifest`].
pub(crate) const FIGURE_KIND: &str = "figure";

/// Relative cost per pixel sample of rendering each scheme's surface, `flat` = 1 — not
/// [`crate::report::shard::scheme_cost`], which is the cost of building and measuring (gk is
/// dear to build, not to trace). Measured once: `smoothlab figure --shard I/20` of every scheme
/// × zebra + curvature, one cell per shard, 128 × 128 pixels at 2 samples, the `render_ms` of
/// each part, on `deformed-icosahedron` (20 large patches) and `scenes/bunny.obj` (1000 small
/// ones); the table holds the geometric mean of the two ratios, which differ by up to 2× — pn
/// 1.9 / 2.7, hb 2.4 / 5.0, loop94 3.2 / 6.3, piper 3.4 / 3.1, nielson 22.9 / 13.2, fang-mann
/// 35.3 / 16.6, gk 4.5 / 5.2 — as do some parameters (fang-mann t = 2: 45.2 / 18.0; gk k = 1:
/// 0.9 / 2.8), which the table leaves out. On 2 cores shared with other work (±25 %). Only the
/// ratios matter, and only for balancing shards.
const RENDER_COST: &[(&str, f64)] = &[
    ("flat", 1.0),
    ("pn", 2.3),
    ("hb", 3.5),
    ("loop94", 4.5),
    ("piper", 3.2),
    ("nielson", 17.4),
    ("fang-mann", 24.2),
    ("gk", 4.8),
];

/// The relative rendering cost per pixel sample of `scheme` ([`RENDER_COST`]); a scheme
/// missing from the table costs as much as the dearest one (a wrong guess only unbalances the
/// shards).
pub(crate) fn render_cost(scheme: &str) -> f64 {
    RENDER_COST
        .iter()
        .find(|(name, _)| *name == scheme)
        .map_or_else(
            || RENDER_COST.iter().map(|(_, c)| *c).fold(0.0, f64::max),
            |(_, c)| *c,
        )
}

/// The estimated cost of every cell of `job` in sheet order: pixels × samples × the scheme's
/// [`render_cost`], × the mode's cost per sample ([`crate::render::modes::ModeKind::COST`]). The mesh's face count is left out:
/// it is the same for every cell of a figure.
pub(crate) fn cell_costs(job: &FigureJob) -> Vec<f64> {
    let samples = f64::from(job.size[0]) * f64::from(job.size[1]) * f64::from(job.spp);
    (0..job.cell_count())
        .map(|k| {
            let (s, m) = job.cell(k);
            let mode = job.modes[m].mode.cost();
            samples * render_cost(&job.surfaces[s].surface.scheme) * mode
        })
        .collect()
}

/// What one shard of a figure wrote beside its cells (`STEM.shard-I-of-N.json`): which cells
/// it rendered, every cell's file names, and what `merge` needs to compose the sheet.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub(crate) struct FigurePart {
    /// Which shard of which run.
    pub manifest: Manifest,
    /// File name of the output stem (the cells' files are `STEM<suffix>.png` / `.exr`).
    pub stem: String,
    /// Every cell's file-name suffix `-<row>-<column>-<scheme>-<mode>`, in sheet order.
    pub cells: Vec<String>,
    /// The cells (positions in `cells`) this shard rendered.
    pub rendered: Vec<usize>,
    /// Whether the cells have EXRs (the spec's `exr`).
    pub exr: bool,
    /// Cell size, pixels.
    pub size: [u32; 2],
    /// Title line of the sheet.
    pub title: String,
    /// The surfaces' labels.
    pub surface_labels: Vec<String>,
    /// The modes' labels and whether each shows curvature (its label gets the range).
    pub modes: Vec<(String, bool)>,
    /// Surfaces as columns, modes as rows.
    pub transpose: bool,
    /// The theme of the sheet (its name).
    pub theme: String,
    /// The curvature half-range, when this shard knows it (a fixed range, or a curvature
    /// cell rendered).
    pub curvature_half_range: Option<f64>,
    /// Rays traced by this shard.
    pub rays: u64,
    /// Its render time, milliseconds.
    pub render_ms: f64,
}

/// The file of `shard`'s [`FigurePart`] for a figure whose output is `output`.
pub(crate) fn part_path(output: &Path, shard: Shard) -> PathBuf {
    crate::app::turntable::part_path(output, shard)
}

/// What `smoothlab figure SPEC --shard I/N` wrote.
#[derive(Clone, Debug)]
pub(crate) struct FigureShardFiles {
    /// The part file.
    pub part: PathBuf,
    /// What it says.
    pub record: FigurePart,
    /// The job's warnings ([`FigureJob::warnings`]).
    pub warnings: Vec<String>,
}

/// Renders `shard`'s share of the cells of the spec at `path` and writes them (PNG, and EXR
/// unless `exr = false`) with the part file, last; every output path is checked (its folder
/// created if missing) before rendering, and an earlier part of this shard is removed. The
/// sheet is left to `smoothlab merge`. `theme`, when given, replaces the spec's.
pub(crate) fn run_figure_spec_shard(
    path: &Path,
    shard: Shard,
    theme: Option<Theme>,
) -> Result<FigureShardFiles> {
    let spec = FigureSpec::load_themed(path, theme)?;
    let stem = output_stem(&spec.output);
    let base = spec.stem_name();
    let suffixes = spec.cell_suffixes();
    let exr = spec.exr.unwrap_or(true);
    let part = part_path(&spec.output, shard);
    if let Some(folder) = part.parent() {
        create_folder(folder)?;
    }
    check_writable(&part)?;
    // A part left by an earlier run of this shard goes first: if this run fails, `merge`
    // names the shard as missing instead of taking the old part.
    match std::fs::remove_file(&part) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(Error::io(&part, e)),
        _ => {}
    }
    let dir = path.parent().unwrap_or(Path::new(""));
    let job = spec
        .job(dir)
        .map_err(|e| e.within(path.display().to_string()))?;
    let rendered = items_of(&cell_costs(&job), shard);
    let cell_file =
        |k: usize, ext: &str| stem.with_file_name(format!("{base}{}.{ext}", suffixes[k]));
    let mut outputs = vec![part.clone()];
    for &k in &rendered {
        outputs.push(cell_file(k, "png"));
        if exr {
            outputs.push(cell_file(k, "exr"));
        }
    }
    for file in &outputs[1..] {
        check_writable(file)?;
    }
    spec.check_outputs(
        path,
        &outputs.iter().map(PathBuf::as_path).collect::<Vec<_>>(),
    )?;
    let (cells, half_range) = render_cells(&job, &rendered)?;
    for (cell, &k) in cells.iter().zip(&rendered) {
        write_png(&cell.frame, &cell_file(k, "png"))?;
        if exr {
            write_exr(&cell.frame, &cell_file(k, "exr"))?;
        }
    }
    // The work: everything that decides the cells' pixels, the labels and the names.
    let mut canonical = spec.clone();
    canonical.output = PathBuf::from(&base);
    let patches: Vec<usize> = job
        .surfaces
        .iter()
        .map(|s| s.surface.patches.len())
        .collect();
    let work = format!(
        "{canonical:?}|{}|{}|{:?}|{patches:?}|{suffixes:?}",
        job.mesh.vertex_count(),
        job.mesh.face_count(),
        job.camera
    );
    let labels = job.labels(None);
    let record = FigurePart {
        manifest: Manifest::new(FIGURE_KIND, shard, &work, suffixes.len()),
        stem: base,
        cells: suffixes,
        rendered,
        exr,
        size: job.size,
        title: labels.title,
        surface_labels: job.surfaces.iter().map(|s| s.label.clone()).collect(),
        modes: job
            .modes
            .iter()
            .map(|m| (m.label.clone(), m.mode.has_scale()))
            .collect(),
        transpose: job.transpose,
        theme: job.theme.name().to_string(),
        curvature_half_range: half_range,
        rays: cells.iter().map(|c| c.stats.rays).sum(),
        render_ms: cells.iter().map(|c| c.stats.render_ms).sum(),
    };
    let text = serde_json::to_string_pretty(&record)
        .map_err(|e| Error::Invalid(format!("figure part JSON: {e}")))?;
    write_atomic(&part, text.as_bytes())?;
    Ok(FigureShardFiles {
        part,
        record,
        warnings: job.warnings,
    })
}

/// One line for the terminal about a shard of a figure.
pub(crate) fn shard_summary(files: &FigureShardFiles) -> String {
    let r = &files.record;
    format!(
        "wrote shard {} of the figure: {} of {} cells ({}) and {}; {:.0} ms rendering\n",
        r.manifest.shard,
        r.rendered.len(),
        r.cells.len(),
        if r.exr { "PNG + EXR" } else { "PNG" },
        files.part.display(),
        r.render_ms
    )
}

/// Merges the figure parts `parts` (`STEM.shard-I-of-N.json` files) of one figure: checks
/// that they are the shards of one run and that every cell file is there, writes the sheet
/// `OUT.png` and `OUT.svg` (`OUT` = [`output_stem`] of `out`) composed from the cells' PNGs,
/// and copies the cells' EXRs to `OUT-<row>-<column>-<scheme>-<mode>.exr` when those are other
/// files: the bytes `smoothlab figure SPEC` writes. Returns a line for the terminal. A missing
/// shard is an error naming it.
pub(crate) fn merge_figure(parts: &[PathBuf], out: &Path) -> Result<String> {
    check_output_name(out)?;
    let read = read_complete_parts(
        parts,
        "figure",
        |part: &FigurePart| &part.manifest,
        "the figure is not merged",
    )?;
    let count = read[0].1.manifest.shard.count;
    let first = &read[0].1;
    let n = first.cells.len();
    // Every cell's source files (the PNG and, when there are EXRs, the EXR), by its shard.
    let mut sources: Vec<Option<PathBuf>> = vec![None; n];
    let mut half_range: Option<(f64, &Path)> = None;
    for (path, part) in &read {
        let dir = path.parent().unwrap_or(Path::new("."));
        for &k in &part.rendered {
            let out_of_range = || {
                Error::Invalid(format!(
                    "{}: rendered: cell {k} out of range",
                    path.display()
                ))
            };
            let suffix = part.cells.get(k).ok_or_else(out_of_range)?;
            *sources.get_mut(k).ok_or_else(out_of_range)? =
                Some(dir.join(format!("{}{suffix}", part.stem)));
        }
        if let Some(r) = part.curvature_half_range {
            match half_range {
                Some((other, from)) if other.to_bits() != r.to_bits() => {
                    return Err(Error::Invalid(format!(
                        "{}: curvature half-range {r} differs from {other} of {}",
                        path.display(),
                        from.display()
                    )));
                }
                _ => half_range = Some((r, path)),
            }
        }
    }
    if half_range.is_none() && first.modes.iter().any(|(_, curvature)| *curvature) {
        return Err(Error::Invalid(
            "merge: no part knows the curvature range (no shard rendered a curvature cell)".into(),
        ));
    }
    let stem = output_stem(out);
    let base = stem
        .file_name()
        .map_or("figure".into(), |s| s.to_string_lossy().into_owned());
    let (png, svg) = (with_suffix(&stem, "png"), with_suffix(&stem, "svg"));
    let exrs: Vec<PathBuf> = if first.exr {
        first
            .cells
            .iter()
            .map(|suffix| stem.with_file_name(format!("{base}{suffix}.exr")))
            .collect()
    } else {
        Vec::new()
    };
    let sources = sources
        .into_iter()
        .enumerate()
        .map(|(k, s)| s.ok_or_else(|| Error::Invalid(format!("merge: no shard rendered cell {k}"))))
        .collect::<Result<Vec<PathBuf>>>()?;
    let lost = |file: &Path, k: usize, e: &dyn std::fmt::Display| {
        Error::Invalid(format!(
            "{}: cell {k} is missing ({e}): its shard did not finish",
            file.display()
        ))
    };
    let mut images = Vec::with_capacity(n);
    for (k, source) in sources.iter().enumerate() {
        let file = with_suffix(source, "png");
        let data = std::fs::read(&file).map_err(|e| lost(&file, k, &e))?;
        let image = image::load_from_memory_with_format(&data, image::ImageFormat::Png)
            .map_err(|e| Error::Invalid(format!("{}: {e}", file.display())))?
            .to_rgb8();
        // A cell's PNG is the cell, and its legend strip right of it if the mode has one.
        if image.width() < first.size[0] || image.height() != first.size[1] {
            return Err(Error::Invalid(format!(
                "{}: cell {k} is {}x{}, not the figure's {}x{} (and a legend strip)",
                file.display(),
                image.width(),
                image.height(),
                first.size[0],
                first.size[1]
            )));
        }
        images.push(image);
    }
    // Every EXR is read before anything is written, so that a missing one leaves no half
    // merge; an EXR that already is the output file stays as it is.
    let mut exr_data = Vec::with_capacity(exrs.len());
    for (k, (source, exr)) in sources.iter().zip(&exrs).enumerate() {
        let file = with_suffix(source, "exr");
        let data = std::fs::read(&file).map_err(|e| lost(&file, k, &e))?;
        let same = std::fs::canonicalize(&file).ok() == std::fs::canonicalize(exr).ok();
        exr_data.push((!same).then_some(data));
    }
    // Every cell is there. The folder of OUT is created if missing, as `figure` does for
    // its output.
    if let Some(folder) = png.parent().filter(|f| !f.as_os_str().is_empty()) {
        create_folder(folder)?;
    }
    for file in [&png, &svg].into_iter().chain(&exrs) {
        check_writable(file)?;
    }
    let labels = sheet_labels(
        &first.title,
        first.surface_labels.clone(),
        &first.modes,
        first.transpose,
        half_range.map(|(r, _)| r),
    );
    let refs: Vec<&image::RgbImage> = images.iter().collect();
    let theme = Theme::by_name("theme", &first.theme)?;
    let sheet = super::compose_images(&refs, &labels, first.size, theme);
    let text = svg_images(&refs, &labels, first.size, theme)?;
    write_rgb_png(&sheet, &png)?;
    write_atomic(&svg, text.as_bytes())?;
    for (data, exr) in exr_data.iter().zip(&exrs) {
        if let Some(data) = data {
            write_atomic(exr, data)?;
        }
    }
    let mut line = format!(
        "merged {n} cells of {count} shards: {}, {}",
        png.display(),
        svg.display()
    );
    if !exrs.is_empty() {
        line += &format!(" and {} EXR cells", exrs.len());
    }
    Ok(line + "\n")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::Problem;
    use std::path::Path;

    fn job(spec: &str) -> FigureJob {
        FigureSpec::parse(spec)
            .expect("spec")
            .job(Path::new(""))
            .expect("job")
    }

    const SPEC: &str = r#"
        mesh = "icosahedron"
        output = "x"
        size = [16, 8]
        spp = 2
        [[schemes]]
        name = "flat"
        [[schemes]]
        name = "nielson"
        [[modes]]
        name = "zebra"
        [[modes]]
        name = "shaded"
    "#;

    #[test]
    fn cells_cost_by_pixels_scheme_and_mode() {
        let costs = cell_costs(&job(SPEC));
        let samples = 16.0 * 8.0 * 2.0;
        // The path tracer's cost per sample, as the mode states it (3, not 1).
        let shaded = crate::render::modes::Mode::by_name("shaded")
            .expect("shaded")
            .cost();
        assert_eq!(shaded, 3.0);
        // Row-major: flat zebra, flat shaded, nielson zebra, nielson shaded.
        assert_eq!(
            costs,
            [
                samples,
                samples * shaded,
                samples * 17.4,
                samples * 17.4 * shaded
            ]
        );
        // Transposed: modes are rows, the same cells in another order.
        let costs = cell_costs(&job(&SPEC.replace("spp = 2", "spp = 2\ntranspose = true")));
        assert_eq!(costs[1], samples * 17.4);
        assert_eq!(costs[2], samples * shaded);
        assert_eq!(render_cost("future"), render_cost("fang-mann"));
    }

    #[test]
    fn shards_get_balanced_cells_not_equal_counts() {
        // One dear cell (nielson shaded) and three cheap ones in two shards: the dear one
        // alone.
        let costs = cell_costs(&job(SPEC));
        let shard = |index| items_of(&costs, Shard { index, count: 2 });
        assert_eq!(shard(0), [3]);
        assert_eq!(shard(1), [0, 1, 2]);
    }

    #[test]
    fn any_subset_of_cells_renders_as_the_whole_figure() {
        let job = job(&format!("{SPEC}\n[[modes]]\nname = \"curvature\"\n"));
        let all: Vec<usize> = (0..job.cell_count()).collect();
        let (whole, range) = render_cells(&job, &all).expect("whole");
        // A subset without a curvature cell does not know the automatic range.
        let (some, none) = render_cells(&job, &[1, 3]).expect("subset");
        assert_eq!(none, None);
        assert_eq!(some[0].frame.rgb, whole[1].frame.rgb);
        assert_eq!(some[1].frame.rgb, whole[3].frame.rgb);
        // With a curvature cell (of the flat surface only) the range is the whole figure's.
        let (curv, known) = render_cells(&job, &[2]).expect("curvature");
        assert_eq!(known, range);
        assert_eq!(curv[0].frame.rgb, whole[2].frame.rgb);
        assert!(render_cells(&job, &[6]).is_err());
    }

    /// A spec's configuration error keeps its type under the spec's path, worded as before.
    #[test]
    fn spec_errors_keep_their_type() {
        let dir = std::env::temp_dir().join(format!("smoothlab-shard-spec-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let path = dir.join("fig.toml");
        let spec = format!(
            "mesh = \"icosahedron\"\noutput = {:?}\ncurvature_range = -1\n[[schemes]]\n\
             name = \"flat\"\n[[modes]]\nname = \"zebra\"\n",
            dir.join("x")
        );
        std::fs::write(&path, spec).expect("spec");
        let err = run_figure_spec_shard(&path, Shard { index: 0, count: 2 }, None)
            .expect_err("bad curvature_range");
        std::fs::remove_dir_all(&dir).ok();
        let Error::In {
            ref place,
            ref error,
        } = err
        else {
            panic!("{err:?}")
        };
        assert_eq!(place, &path.display().to_string());
        assert!(
            matches!(**error, Error::In { ref error, .. } if matches!(**error, Error::Config { ref key, problem: Problem::Neither { .. } } if key == "curvature_range")),
            "{err:?}"
        );
        assert_eq!(
            err.to_string(),
            format!(
                "{}: figure spec: curvature_range -1 is neither \"auto\" nor a positive number",
                path.display()
            )
        );
    }
}
