//! The results history: one small JSON file per commit in `OUT/history/`
//! (`<date>-<commit>.json`), written by every `report` (and `merge`) run, so that results can
//! be followed across commits (as asv keeps one result file per commit). An entry holds the
//! commit, the date, the tool version, every quality figure of every record, and — apart, with
//! the machine they were measured on — the timing medians with their spread: quality compares
//! across machines, timings only within one.
//!
//! Re-running on a commit replaces that commit's file. [`read_dir`] reads a history folder
//! (this run's, or another one given to `report --history DIR`) in run order: by date, then by
//! commit. [`steps`] finds the step changes of one figure over the history.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::compare::{self, Thresholds, Verdict};
use super::{Report, TIMING_KEYS, provenance::Machine};
use crate::error::{Error, Result};
use crate::files::{create_folder, write_atomic};

/// The folder of the history inside a report folder.
pub const HISTORY: &str = "history";

/// The `format` of a history entry.
pub const FORMAT: &str = "smoothlab-history";

/// The format version of history entries that this build writes and reads.
pub const VERSION: u32 = 1;

/// The quality figures of one record (scheme × mesh) at one commit.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct QualityRecord {
    /// Benchmark mesh name.
    pub mesh: String,
    /// Scheme (variant label, as in the report).
    pub scheme: String,
    /// Every numeric figure of the record that is not a timing, by its key.
    pub figures: serde_json::Map<String, serde_json::Value>,
}

/// One timing benchmark (a construction of a scheme on a mesh) at one commit.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TimingRecord {
    /// Benchmark mesh name.
    pub mesh: String,
    /// Scheme (variant label).
    pub scheme: String,
    /// The timing's key in the report (`construct_ms`).
    pub benchmark: String,
    /// Median of the runs, milliseconds.
    pub median_ms: f64,
    /// (slowest − fastest) / median of the runs; absent for one run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spread_rel: Option<f64>,
    /// Number of timed runs.
    pub runs: u64,
}

/// The timings of one run and the machine they were measured on.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Timings {
    /// The machine; absent when the report does not say (a merge of shards run on several
    /// machines).
    pub machine: Option<Machine>,
    /// The timings, in record order.
    pub records: Vec<TimingRecord>,
}

/// One run in the history.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Entry {
    /// Always [`FORMAT`].
    pub format: String,
    /// [`VERSION`].
    pub version: u32,
    /// The commit (`git rev-parse HEAD`), or `unknown`.
    pub commit: String,
    /// `git describe --always --dirty`, when known.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub describe: Option<String>,
    /// UTC date and time of the run (ISO 8601).
    pub date: String,
    /// The smoothlab version of the run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tool_version: Option<String>,
    /// Quality figures, in record order (records with an error are left out).
    pub quality: Vec<QualityRecord>,
    /// Timings, with their machine.
    pub timings: Timings,
}

impl Entry {
    /// The history entry of `report`.
    pub fn of(report: &Report) -> Entry {
        let mut quality = Vec::new();
        let mut timings = Vec::new();
        for r in report.records.iter().filter(|r| r.error.is_none()) {
            let figures = r
                .figures
                .iter()
                .filter(|(k, v)| v.is_number() && !TIMING_KEYS.contains(&k.as_str()))
                .map(|(k, v)| (k.clone(), v.clone()))
                .collect();
            quality.push(QualityRecord {
                mesh: r.mesh.clone(),
                scheme: r.scheme.clone(),
                figures,
            });
            let number = |key: &str| r.figures.get(key).and_then(serde_json::Value::as_f64);
            if let Some(median_ms) = number("construct_ms") {
                timings.push(TimingRecord {
                    mesh: r.mesh.clone(),
                    scheme: r.scheme.clone(),
                    benchmark: "construct_ms".into(),
                    median_ms,
                    spread_rel: number("construct_ms_spread_rel"),
                    runs: r
                        .figures
                        .get("construct_ms_runs")
                        .and_then(serde_json::Value::as_u64)
                        .unwrap_or(1),
                });
            }
        }
        Entry {
            format: FORMAT.into(),
            version: VERSION,
            commit: report.commit.clone(),
            describe: report.describe.clone(),
            date: report.date.clone(),
            tool_version: report.tool_version.clone(),
            quality,
            timings: Timings {
                machine: report.machine.clone(),
                records: timings,
            },
        }
    }

    /// The commit as the page shows it: the describe string, or the first 12 digits of the
    /// commit.
    pub fn short_commit(&self) -> String {
        self.describe
            .clone()
            .unwrap_or_else(|| self.commit.chars().take(12).collect())
    }

    /// The file name of the entry: `<YYYY-MM-DD>-<first 12 digits of the commit>.json`.
    pub fn file_name(&self) -> String {
        let day: String = self.date.chars().take(10).collect();
        let commit: String = self
            .commit
            .chars()
            .filter(char::is_ascii_alphanumeric)
            .take(12)
            .collect();
        format!("{day}-{commit}.json")
    }

    /// A quality figure of a record.
    pub fn quality(&self, mesh: &str, scheme: &str, key: &str) -> Option<f64> {
        self.quality
            .iter()
            .find(|r| r.mesh == mesh && r.scheme == scheme)
            .and_then(|r| r.figures.get(key))
            .and_then(serde_json::Value::as_f64)
    }

    /// A timing of a record.
    pub fn timing(&self, mesh: &str, scheme: &str, benchmark: &str) -> Option<&TimingRecord> {
        self.timings
            .records
            .iter()
            .find(|t| t.mesh == mesh && t.scheme == scheme && t.benchmark == benchmark)
    }
}

/// Parses one history file, checking its format and version; errors name the file.
pub fn read_entry(path: &Path) -> Result<Entry> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let entry: Entry = serde_json::from_str(&text).map_err(|e| {
        Error::Invalid(format!(
            "{}: not a smoothlab history entry: {e}",
            path.display()
        ))
    })?;
    if entry.format != FORMAT || entry.version != VERSION {
        return Err(Error::Invalid(format!(
            "{}: format {} version {} is not {FORMAT} version {VERSION}",
            path.display(),
            entry.format,
            entry.version
        )));
    }
    Ok(entry)
}

/// The `.json` files of the history folder `dir`, sorted by name.
fn entry_files(dir: &Path) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    for item in std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))? {
        let path = item.map_err(|e| Error::io(dir, e))?.path();
        if path.extension().is_some_and(|e| e == "json") && path.is_file() {
            files.push(path);
        }
    }
    files.sort();
    Ok(files)
}

/// Reads every entry of the history folder `dir`, in run order (date, then commit). A missing
/// folder is an empty history; a file that is not an entry is an error naming it.
pub fn read_dir(dir: &Path) -> Result<Vec<Entry>> {
    if !dir.exists() {
        return Ok(Vec::new());
    }
    let mut entries = entry_files(dir)?
        .iter()
        .map(|p| read_entry(p))
        .collect::<Result<Vec<_>>>()?;
    sort(&mut entries);
    Ok(entries)
}

/// Sorts entries in run order: by date, then by commit.
fn sort(entries: &mut [Entry]) {
    entries.sort_by(|a, b| (&a.date, &a.commit).cmp(&(&b.date, &b.commit)));
}

/// Writes `entry` into the history folder `dir` (created if missing), replacing any entry of
/// the same commit; returns the file written.
pub fn record(dir: &Path, entry: &Entry) -> Result<PathBuf> {
    create_folder(dir)?;
    let path = dir.join(entry.file_name());
    for file in entry_files(dir)? {
        if file != path && read_entry(&file).is_ok_and(|e| e.commit == entry.commit) {
            std::fs::remove_file(&file).map_err(|e| Error::io(&file, e))?;
        }
    }
    let json = serde_json::to_string(entry)
        .map_err(|e| Error::Invalid(format!("history entry JSON: {e}")))?;
    write_atomic(&path, format!("{json}\n").as_bytes())?;
    Ok(path)
}

/// The history a page shows: the entries of `dir` with `current` in place of any entry of its
/// commit, in run order.
pub fn with_current(mut entries: Vec<Entry>, current: Entry) -> Vec<Entry> {
    entries.retain(|e| e.commit != current.commit);
    entries.push(current);
    sort(&mut entries);
    entries
}

/// A step change of one series: at entry `at` the value moved beyond tolerance from the one
/// before, and every later value stayed beyond it on the same side.
#[derive(Clone, Debug, PartialEq)]
pub struct Step {
    /// Index of the first entry of the new level.
    pub at: usize,
    /// The value before the step.
    pub before: f64,
    /// The value at the step.
    pub after: f64,
    /// Worse or better.
    pub verdict: Verdict,
}

/// The step changes of `series` (one value per entry, None where an entry lacks it), judged
/// by `judge(before, after)`: a step at `k` when the level before `k` (the first value, or
/// that of the last step) and the value at `k` differ beyond tolerance (`judge` says worse or
/// better) and every later known value is judged the same way against that level — sustained,
/// as asv's step detection asks; a spike that comes back is no step, and a slow drift is one
/// where it leaves the tolerance for good. A step at the last entry has nothing after it and
/// is reported.
pub fn steps(series: &[Option<f64>], judge: &dyn Fn(f64, f64) -> Verdict) -> Vec<Step> {
    let mut out = Vec::new();
    // The level: the first value, then the value of each step found. A change that does not
    // last (a spike) leaves it where it was, so the return from a spike is no step either.
    let mut level: Option<f64> = None;
    for (k, value) in series.iter().enumerate() {
        let Some(v) = *value else { continue };
        let Some(p) = level else {
            level = Some(v);
            continue;
        };
        let verdict = judge(p, v);
        if verdict == Verdict::Same {
            continue;
        }
        let sustained = series[k + 1..]
            .iter()
            .flatten()
            .all(|&later| judge(p, later) == verdict);
        if sustained {
            out.push(Step {
                at: k,
                before: p,
                after: v,
                verdict,
            });
            level = Some(v);
        }
    }
    out
}

/// The verdict on quality figure `key` moving from `before` to `after` with the default
/// thresholds of `compare` (None for a figure `compare` does not judge).
pub fn judge_quality(key: &str, before: f64, after: f64) -> Option<Verdict> {
    compare::judge_quality(key, before, after, Thresholds::default().quality_rel)
}

/// The verdict on a timing moving from `before` to `after` (medians, ms) with spreads
/// `spread`: beyond the default ratio of `compare` widened by the spread, and only from 1 ms.
pub fn judge_timing(before: f64, after: f64, spread: f64) -> Verdict {
    compare::judge_timing(before, after, spread, Thresholds::default().time_ratio)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::{REPORT_VERSION, Record};

    fn report(commit: &str, date: &str, g1: f64, ms: f64) -> Report {
        let mut figures = serde_json::Map::new();
        figures.insert("g1_max_rad".into(), g1.into());
        figures.insert("continuity_order".into(), 1.into());
        figures.insert("params".into(), serde_json::json!({"beta": "0.5"}));
        figures.insert("construct_ms".into(), ms.into());
        figures.insert("construct_ms_runs".into(), 5.into());
        figures.insert("construct_ms_spread_rel".into(), 0.1.into());
        Report {
            format: "smoothlab-report".into(),
            version: REPORT_VERSION,
            commit: commit.into(),
            date: date.into(),
            records: vec![
                Record {
                    mesh: "cube".into(),
                    scheme: "hb".into(),
                    figures,
                    error: None,
                },
                Record {
                    mesh: "cube".into(),
                    scheme: "gk".into(),
                    figures: serde_json::Map::new(),
                    error: Some("did not build".into()),
                },
            ],
            describe: None,
            dirty: None,
            tool_version: None,
            machine: Some(Machine::current()),
            shards: None,
        }
    }

    #[test]
    fn quality_and_timings_are_kept_apart() {
        let entry = Entry::of(&report(
            "abcdef0123456789",
            "2026-01-02T03:04:05Z",
            0.1,
            7.0,
        ));
        assert_eq!(entry.file_name(), "2026-01-02-abcdef012345.json");
        assert_eq!(entry.quality.len(), 1, "the failed record is left out");
        let keys: Vec<&str> = entry.quality[0]
            .figures
            .keys()
            .map(String::as_str)
            .collect();
        assert_eq!(keys, ["continuity_order", "g1_max_rad"]);
        assert_eq!(entry.timings.machine, Some(Machine::current()));
        let t = entry.timing("cube", "hb", "construct_ms").expect("timed");
        assert_eq!((t.median_ms, t.spread_rel, t.runs), (7.0, Some(0.1), 5));
    }

    #[test]
    fn a_commit_run_again_replaces_its_entry() {
        let dir = std::env::temp_dir().join(format!("smoothlab-history-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let a = Entry::of(&report("aaaa", "2026-01-02T00:00:00Z", 0.1, 7.0));
        let b = Entry::of(&report("bbbb", "2026-01-01T00:00:00Z", 0.2, 7.0));
        record(&dir, &a).expect("a");
        record(&dir, &b).expect("b");
        // aaaa again, a day later: its file of the first day goes.
        let a2 = Entry::of(&report("aaaa", "2026-01-03T00:00:00Z", 0.3, 7.0));
        record(&dir, &a2).expect("a again");
        let entries = read_dir(&dir).expect("history");
        let commits: Vec<(&str, f64)> = entries
            .iter()
            .map(|e| {
                (
                    e.commit.as_str(),
                    e.quality("cube", "hb", "g1_max_rad").unwrap(),
                )
            })
            .collect();
        assert_eq!(commits, [("bbbb", 0.2), ("aaaa", 0.3)]);
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 2);
        std::fs::write(dir.join("x.json"), "{\"format\": \"other\"}").unwrap();
        let err = read_dir(&dir).expect_err("not an entry");
        assert!(
            err.to_string()
                .contains("x.json: not a smoothlab history entry"),
            "{err}"
        );
        let _ = std::fs::remove_dir_all(&dir);
        assert!(read_dir(&dir).expect("missing folder").is_empty());
    }

    fn judge_g1(a: f64, b: f64) -> Verdict {
        judge_quality("g1_max_rad", a, b).expect("judged")
    }

    #[test]
    fn a_sustained_change_is_a_step_a_spike_is_not() {
        let at = |series: &[Option<f64>]| -> Vec<(usize, Verdict)> {
            steps(series, &judge_g1)
                .iter()
                .map(|s| (s.at, s.verdict))
                .collect()
        };
        // Rounding noise (1e-15) is no step; the jump at 3 stays.
        let s = [
            Some(1e-15),
            Some(3e-15),
            Some(2e-15),
            Some(0.1),
            Some(0.1),
            Some(0.101),
        ];
        assert_eq!(at(&s), [(3, Verdict::Worse)]);
        // A spike that comes back is no step (nor is its return); a drop at the last entry is.
        let s = [Some(0.1), Some(0.5), Some(0.1), Some(0.1), Some(0.01)];
        assert_eq!(at(&s), [(4, Verdict::Better)]);
        // Missing values are skipped over.
        let s = [Some(0.1), None, Some(0.3), None, Some(0.3)];
        assert_eq!(at(&s), [(2, Verdict::Worse)]);
        assert!(at(&[Some(0.1)]).is_empty());
        // A drift of 4 % a run is a step where it leaves the 5 % tolerance of the level.
        let s = [Some(0.1), Some(0.104), Some(0.108), Some(0.112)];
        assert_eq!(at(&s), [(2, Verdict::Worse)]);
        assert!(at(&[]).is_empty());
        // Counts move by one.
        let judge = |a, b| judge_quality("continuity_order", a, b).unwrap();
        let s = [Some(2.0), Some(2.0), Some(1.0)];
        assert_eq!(steps(&s, &judge)[0].at, 2);
        // Timings: within the ratio widened by the spread is no step.
        let judge = |a, b| judge_timing(a, b, 0.2);
        let s = [Some(10.0), Some(17.0), Some(10.0), Some(40.0), Some(41.0)];
        let found = steps(&s, &judge);
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!((found[0].at, found[0].verdict), (3, Verdict::Worse));
    }
}
