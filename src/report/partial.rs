//! Partial reports: `smoothlab report --shard I/N --out DIR` measures its share of the work
//! list ([`super::shard::items_of`] over the items' estimated costs) and writes
//! `DIR/partial.json` ([`ReportPart`]) with the thumbnails of its meshes in `DIR/thumbs/`;
//! [`merge`] combines the parts of one run into the report a single process would have written.
//!
//! The merged records are in work-list order and equal, figure for figure, to a single run's
//! (timings aside, [`super::TIMING_KEYS`]); the thumbnails are the same bytes. The merged
//! report keeps each shard's machine, date and run time in `shards`. A shard without a part (it
//! failed, or was not run) is named in the error `merge` returns, and its items are written as
//! records carrying that error, so nothing is dropped silently.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::batch::WorkList;
use super::page::{self, MeshThumbnails};
use super::shard::{self, Manifest, Shard};
use super::{Record, Report, ShardRun, WriteOptions, compare, error_record};
use crate::error::{Error, Result};
use crate::files::{check_writable, create_folder, write_atomic};

/// The file name of a partial report in its shard's folder.
pub const PARTIAL_FILE: &str = "partial.json";

/// The kind of work of partial reports, in their [`Manifest`].
pub const KIND: &str = "report";

/// What one shard of a report wrote.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReportPart {
    /// Which shard of which run.
    pub manifest: Manifest,
    /// The whole work list (every shard carries it, so `merge` can place every record and name
    /// the items of a missing shard).
    pub work: WorkList,
    /// The items this shard measured (positions in `work`).
    pub items: Vec<usize>,
    /// Its records (items in order, variants in order) with this shard's provenance.
    pub report: Report,
    /// The thumbnails of its meshes, in `thumbs/` beside this file.
    pub thumbnails: Vec<MeshThumbnails>,
    /// Its warnings.
    pub warnings: Vec<String>,
    /// Its wall time, seconds.
    pub seconds: f64,
}

/// Measures the share of `shard` of `work` and writes it into `out_dir` (`partial.json` and
/// `thumbs/`; the folder is created if missing, every path checked before the work starts).
pub fn write_part(
    out_dir: &Path,
    work: &WorkList,
    shard: Shard,
    options: &WriteOptions,
    progress: &dyn Fn(usize, usize, &str),
) -> Result<ReportPart> {
    let start = std::time::Instant::now();
    let items = shard::items_of(&work.costs(), shard);
    create_folder(&out_dir.join(page::THUMBS))?;
    let file = out_dir.join(PARTIAL_FILE);
    check_writable(&file)?;
    for &k in &items {
        let item = &work.items[k];
        for v in &item.variants {
            for mode in page::THUMB_MODES {
                check_writable(&page::thumbnail_path(out_dir, &item.mesh, &v.label(), mode))?;
            }
        }
    }
    let measured =
        super::measure_items(work, &items, Some((out_dir, &options.thumbnails)), progress)?;
    let part = ReportPart {
        manifest: Manifest::new(KIND, shard, &work.canonical(), work.items.len()),
        work: work.clone(),
        items,
        report: Report::stamped(measured.records),
        thumbnails: measured.thumbnails,
        warnings: measured.warnings,
        seconds: start.elapsed().as_secs_f64(),
    };
    let text = serde_json::to_string_pretty(&part)
        .map_err(|e| Error::Invalid(format!("partial report JSON: {e}")))?;
    write_atomic(&file, text.as_bytes())?;
    Ok(part)
}

/// The `partial.json` a merge argument names: the file itself, or the shard's folder.
pub fn part_file(path: &Path) -> PathBuf {
    if path.is_dir() {
        path.join(PARTIAL_FILE)
    } else {
        path.to_path_buf()
    }
}

/// Reads a partial report (`partial.json`, or a folder holding one).
pub fn read_part(path: &Path) -> Result<ReportPart> {
    let file = part_file(path);
    let text = std::fs::read_to_string(&file).map_err(|e| Error::io(&file, e))?;
    serde_json::from_str(&text).map_err(|e| {
        Error::Invalid(format!(
            "{}: not a smoothlab partial report: {e}",
            file.display()
        ))
    })
}

/// What [`merge`] wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct Merged {
    /// The merged report.
    pub report: Report,
    /// The shards that had no part.
    pub missing: Vec<Shard>,
    /// Records written as errors because their shard was missing.
    pub missing_records: usize,
    /// The comparison with the baseline, when one was given.
    pub comparison: Option<compare::Comparison>,
    /// The warnings of every part.
    pub warnings: Vec<String>,
}

/// Merges the partial reports `parts` (each a shard folder or its `partial.json`) into the
/// report folder `out_dir`: `metrics.{json,csv,md}`, plots, the page and the thumbnails, as a
/// single run writes them. Parts of different runs (kind, shard count, work list or tool
/// version) or a shard given twice are refused before anything is written. Missing shards do not
/// stop the merge: their items become error records, and [`Merged::missing`] names them (the
/// command then fails).
pub fn merge(parts: &[PathBuf], out_dir: &Path, options: &WriteOptions) -> Result<Merged> {
    let mut read = Vec::with_capacity(parts.len());
    for path in parts {
        read.push((part_file(path), read_part(path)?));
    }
    let named: Vec<(String, &Manifest)> = read
        .iter()
        .map(|(file, part)| (file.display().to_string(), &part.manifest))
        .collect();
    let (count, missing) = shard::check_parts(&named)?;
    let work = &read[0].1.work;
    let costs = work.costs();
    for (file, part) in &read {
        if shard::fingerprint(&part.work.canonical()) != part.manifest.fingerprint {
            return Err(Error::Invalid(format!(
                "{}: its work list does not match its fingerprint (edited or damaged)",
                file.display()
            )));
        }
        // `items` is compared with the share before it indexes anything.
        let expected = shard::items_of(&costs, part.manifest.shard);
        if part.items != expected {
            return Err(Error::Invalid(format!(
                "{}: items: shard {} holds other items than its share of the work list \
                 (damaged part)",
                file.display(),
                part.manifest.shard
            )));
        }
        let records: usize = expected.iter().map(|&k| work.items[k].variants.len()).sum();
        if part.report.records.len() != records {
            return Err(Error::Invalid(format!(
                "{}: report.records: {} records where the items of shard {} make {records} \
                 (damaged part)",
                file.display(),
                part.report.records.len(),
                part.manifest.shard
            )));
        }
    }
    let baseline = super::read_baseline(options)?;
    let earlier = super::read_history(out_dir, options)?;
    create_folder(&out_dir.join("figures"))?;
    create_folder(&out_dir.join(page::THUMBS))?;
    // Every item's records and thumbnails from the part that owns it, in work-list order.
    let owner = shard::assign(&costs, count);
    let mut cursors: Vec<Option<(usize, usize)>> = vec![None; count as usize];
    for (p, (_, part)) in read.iter().enumerate() {
        cursors[part.manifest.shard.index as usize] = Some((p, 0));
    }
    let mut records: Vec<Record> = Vec::with_capacity(work.record_count());
    let mut thumbnails = Vec::new();
    let mut missing_records = 0;
    for (k, item) in work.items.iter().enumerate() {
        let s = owner[k] as usize;
        let Some((p, next)) = cursors[s].as_mut() else {
            for v in &item.variants {
                records.push(error_record(
                    &item.mesh,
                    v,
                    format!("not measured: shard {s}/{count} is missing from the merge"),
                ));
                missing_records += 1;
            }
            continue;
        };
        let (file, part) = &read[*p];
        let n = item.variants.len();
        records.extend(part.report.records[*next..*next + n].iter().cloned());
        *next += n;
        if let Some(t) = part.thumbnails.iter().find(|t| t.mesh == item.mesh) {
            let dir = file.parent().unwrap_or(Path::new("."));
            for scheme in &t.schemes {
                for mode in page::THUMB_MODES {
                    let from = page::thumbnail_path(dir, &t.mesh, scheme, mode);
                    let bytes = std::fs::read(&from).map_err(|e| Error::io(&from, e))?;
                    write_atomic(
                        &page::thumbnail_path(out_dir, &t.mesh, scheme, mode),
                        &bytes,
                    )?;
                }
            }
            thumbnails.push(t.clone());
        }
    }
    let mut runs: Vec<ShardRun> = read
        .iter()
        .map(|(_, part)| ShardRun {
            shard: part.manifest.shard,
            date: part.report.date.clone(),
            machine: part.report.machine.clone(),
            seconds: part.seconds,
        })
        .collect();
    runs.sort_by_key(|r| r.shard.index);
    let first = &read[0].1.report;
    let same_machine = read.iter().all(|(_, p)| p.report.machine == first.machine);
    let report = Report {
        records,
        date: runs
            .iter()
            .map(|r| r.date.clone())
            .max()
            .unwrap_or_default(),
        machine: if same_machine {
            first.machine.clone()
        } else {
            None
        },
        shards: Some(runs),
        ..first.clone()
    };
    let comparison = super::write_outputs(
        out_dir,
        &report,
        &thumbnails,
        baseline.as_ref().map(|(p, r)| (*p, r)),
        earlier,
    )?;
    Ok(Merged {
        report,
        missing: missing
            .into_iter()
            .map(|index| Shard { index, count })
            .collect(),
        missing_records,
        comparison,
        warnings: read
            .iter()
            .flat_map(|(_, part)| part.warnings.iter().cloned())
            .collect(),
    })
}
