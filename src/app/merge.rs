//! `smoothlab merge PARTS… -o OUT`: one command for every kind of partial result. The kind is
//! read from the parts' manifests ([`crate::report::shard::Manifest`]):
//!
//! - `report` parts (shard folders of `report --shard I/N --out DIR`, or their
//!   `partial.json`) become the report folder `OUT` ([`crate::report::partial::merge`]);
//! - `frames` parts (`NAME.shard-I-of-N.json` of `render --turntable|--sweep --shard I/N`)
//!   become the frames `OUT-000.png` … and `OUT.gif` ([`super::turntable::merge_frames`]);
//! - `figure` parts (`STEM.shard-I-of-N.json` of `figure SPEC --shard I/N`) become the sheet
//!   `OUT.png`, `OUT.svg` and the cells' EXRs ([`super::figure::shard::merge_figure`]).
//!
//! Parts of different kinds or runs are refused before anything is written.

use std::path::{Path, PathBuf};

use super::Output;
use crate::error::{Error, Result};
use crate::report::partial::{self, part_file};
use crate::report::shard::{self, Manifest};

/// The manifest of a part (a shard folder, `partial.json` or a frames part file).
fn manifest_of(path: &Path) -> Result<Manifest> {
    let file = part_file(path);
    let text = std::fs::read_to_string(&file).map_err(|e| Error::io(&file, e))?;
    let value: serde_json::Value = serde_json::from_str(&text)
        .map_err(|e| Error::Invalid(format!("{}: not JSON: {e}", file.display())))?;
    value
        .get("manifest")
        .cloned()
        .and_then(|m| serde_json::from_value(m).ok())
        .ok_or_else(|| {
            Error::Invalid(format!(
                "{}: not a smoothlab partial result (no manifest); merge reads the output of \
                 `report --shard`, `render --turntable|--sweep --shard` or `figure --shard`",
                file.display()
            ))
        })
}

/// `smoothlab merge PARTS… -o OUT [--baseline OLD.json]` (the baseline for reports only).
pub(crate) fn run_merge(parts: &[PathBuf], out: &Path, baseline: Option<&Path>) -> Result<Output> {
    let first = parts
        .first()
        .ok_or_else(|| Error::Invalid("merge: no partial results given".into()))?;
    let kind = manifest_of(first)?.kind;
    for path in &parts[1..] {
        let other = manifest_of(path)?.kind;
        if other != kind {
            return Err(Error::Invalid(format!(
                "{}: a {other} part cannot be merged with {} parts ({})",
                path.display(),
                kind,
                first.display()
            )));
        }
    }
    match kind.as_str() {
        partial::KIND => {
            let options = crate::report::WriteOptions {
                baseline: baseline.map(Path::to_path_buf),
                ..Default::default()
            };
            let merged = partial::merge(parts, out, &options)?;
            let errors = merged
                .report
                .records
                .iter()
                .filter(|r| r.error.is_some())
                .count();
            if !merged.missing.is_empty() {
                let indices: Vec<u32> = merged.missing.iter().map(|s| s.index).collect();
                return Err(Error::Invalid(format!(
                    "merge: {}; {} record(s) written as errors to {}",
                    shard::missing_text(&indices, merged.missing[0].count),
                    merged.missing_records,
                    out.join("metrics.json").display()
                )));
            }
            let mut stdout = format!(
                "merged {} parts: {} records ({errors} errors) written to {}/metrics.{{json,csv,md}}, \
                 figures/ and index.html\n",
                parts.len(),
                merged.report.records.len(),
                out.display()
            );
            if let (Some(path), Some(comparison)) = (baseline, &merged.comparison) {
                stdout += &super::baseline_line(path, comparison, out);
            }
            Ok(Output {
                stdout,
                warnings: merged.warnings,
                failed: false,
            })
        }
        super::turntable::FRAMES_KIND => {
            if baseline.is_some() {
                return Err(Error::Invalid(
                    "merge: --baseline is for report parts, not frames".into(),
                ));
            }
            Ok(Output {
                stdout: super::turntable::merge_frames(parts, out)?,
                ..Default::default()
            })
        }
        super::figure::shard::FIGURE_KIND => {
            if baseline.is_some() {
                return Err(Error::Invalid(
                    "merge: --baseline is for report parts, not figures".into(),
                ));
            }
            Ok(Output {
                stdout: super::figure::shard::merge_figure(parts, out)?,
                ..Default::default()
            })
        }
        other => Err(Error::Invalid(format!(
            "{}: unknown kind of partial result '{other}' (this build merges report, frames \
             and figure)",
            first.display()
        ))),
    }
}
