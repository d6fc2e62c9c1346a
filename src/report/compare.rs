//! `smoothlab compare OLD.json NEW.json`: what changed between two reports, per scheme × mesh,
//! and whether anything got worse beyond its tolerance (quality) or noise threshold (timing).
//! Quality and time are judged separately.
//!
//! Quality is always judged. A quality figure regresses when it moves in its bad direction by
//! more than `abs + rel · |old|` (each figure has its own `abs`, the tolerance of the
//! measurement, from `crate::tolerance` where it means "zero up to rounding" — e.g. 1e-9 rad for
//! normal jumps — and the common `rel`); the counts ([`COUNTS`]: the continuity order, the
//! folds) regress when they move the bad way at all. A record in OLD that NEW lacks is a
//! regression too.
//!
//! Timings depend on the machine, so they are judged only when asked ([`TimingCheck`]), and
//! then only between reports measured on the same machine ([`super::provenance::Machine`])
//! unless forced. A timing regresses when `new / old` exceeds the ratio threshold widened by
//! the recorded spread: `ratio · (1 + spread)`, with `spread` the larger of the two records'
//! `<timing>_spread_rel` ((slowest − fastest) / median of the runs), 0 when not recorded.
//! Timings under 1 ms are too noisy to judge and are skipped.

use super::{METRICS_MESH, Record, Report};
use crate::error::{Error, Result};
use crate::tolerance::{CURVATURE_REL, NORMAL_RAD, POSITION_REL};

/// Which way is better.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Better {
    Lower,
    Higher,
}

/// A tracked quality figure: key, better direction, absolute tolerance.
const QUALITY: &[(&str, Better, f64)] = &[
    ("interp_max_rel", Better::Lower, POSITION_REL),
    ("g0_max_rel", Better::Lower, POSITION_REL),
    ("g1_max_rad", Better::Lower, NORMAL_RAD),
    ("g1_between_faces_max_rad", Better::Lower, NORMAL_RAD),
    ("g1_inside_faces_max_rad", Better::Lower, NORMAL_RAD),
    ("curvature_jump_max_rel", Better::Lower, CURVATURE_REL),
    ("continuity_order", Better::Higher, 0.0),
    ("min_regularity_rel", Better::Higher, 0.0),
    ("folds", Better::Lower, 0.0),
    ("folded_patches", Better::Lower, 0.0),
    ("network_undulation_max_rad", Better::Lower, 1e-6),
    ("bending_energy", Better::Lower, 1e-9),
    ("distance_max_rel", Better::Lower, POSITION_REL),
    ("normal_error_max_rad", Better::Lower, NORMAL_RAD),
];

/// Quality figures that are counts: judged exactly, without the relative tolerance (one fold
/// more, or one order less, is a regression).
const COUNTS: &[&str] = &["continuity_order", "folds", "folded_patches"];

/// Tracked timings (milliseconds).
const TIMINGS: &[&str] = &["construct_ms", "render_ms"];

/// Whether timings are judged.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TimingCheck {
    /// Timings are not judged (`compare` without `--timings`).
    #[default]
    Skip,
    /// Judged when both reports carry the same machine fingerprint, else skipped with a note
    /// (`--timings`).
    SameMachine,
    /// Judged whatever machines the reports come from (`--force-timings`).
    Force,
}

/// The outcome of a comparison.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Comparison {
    /// Every changed figure, regressions flagged.
    pub changes: Vec<Change>,
    /// Lines telling what was not judged and why (timings skipped, machines differ).
    pub notes: Vec<String>,
}

impl Comparison {
    /// True if any change is a regression.
    pub fn failed(&self) -> bool {
        self.changes.iter().any(|c| c.regression)
    }
}

/// Thresholds of a comparison.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Thresholds {
    /// Relative tolerance of quality figures.
    pub quality_rel: f64,
    /// Largest accepted `new / old` timing ratio.
    pub time_ratio: f64,
}

impl Thresholds {
    /// Checks that the thresholds can fail a comparison: `quality_rel` finite and ≥ 0,
    /// `time_ratio` finite and ≥ 1. NaN or infinity would let every change pass, and a ratio
    /// below 1 would flag unchanged timings. The error names the command-line flag.
    pub fn check(&self) -> Result<()> {
        if !(self.quality_rel.is_finite() && self.quality_rel >= 0.0) {
            return Err(Error::Invalid(format!(
                "--quality-rel {} must be a finite number >= 0 (relative tolerance of quality \
                 figures)",
                self.quality_rel
            )));
        }
        if !(self.time_ratio.is_finite() && self.time_ratio >= 1.0) {
            return Err(Error::Invalid(format!(
                "--time-ratio {} must be a finite number >= 1 (largest accepted new/old timing \
                 ratio)",
                self.time_ratio
            )));
        }
        Ok(())
    }
}

impl Default for Thresholds {
    fn default() -> Self {
        Thresholds {
            quality_rel: 0.05,
            time_ratio: 1.5,
        }
    }
}

/// One line of the comparison.
#[derive(Clone, Debug, PartialEq)]
pub struct Change {
    /// `mesh / scheme`.
    pub record: String,
    /// The figure's key.
    pub key: String,
    /// Old value (None: missing).
    pub old: Option<f64>,
    /// New value (None: missing).
    pub new: Option<f64>,
    /// True if this is a regression.
    pub regression: bool,
}

fn number(r: &Record, key: &str) -> Option<f64> {
    r.figures.get(key).and_then(serde_json::Value::as_f64)
}

fn worse(old: f64, new: f64, better: Better, abs: f64, rel: f64) -> bool {
    let allowed = abs + rel * old.abs();
    match better {
        Better::Lower => new > old + allowed,
        Better::Higher => new < old - allowed,
    }
}

/// Checks that two reports can be compared: both `smoothlab report` output or both
/// `metrics --json` output (whose records have no benchmark mesh to match a report's).
pub fn check_comparable(old: &Report, new: &Report) -> Result<()> {
    let from_metrics = |r: &Report| r.records.iter().all(|r| r.mesh == METRICS_MESH);
    if from_metrics(old) != from_metrics(new) {
        let kind = |r: &Report| {
            if from_metrics(r) {
                "metrics --json output"
            } else {
                "a report"
            }
        };
        return Err(Error::Invalid(format!(
            "cannot compare {} with {}: compare two reports or two metrics --json outputs",
            kind(old),
            kind(new)
        )));
    }
    Ok(())
}

/// Whether the timings of `old` and `new` are judged under `check`, and if not, why.
fn timings_judged(old: &Report, new: &Report, check: TimingCheck) -> (bool, Option<String>) {
    match check {
        TimingCheck::Skip => (
            false,
            Some(
                "timings not judged (--timings judges them between reports of one machine)".into(),
            ),
        ),
        TimingCheck::Force => (true, None),
        TimingCheck::SameMachine => match (&old.machine, &new.machine) {
            (Some(a), Some(b)) if a == b => (true, None),
            (Some(a), Some(b)) => (
                false,
                Some(format!(
                    "timings not judged: measured on different machines ({} vs {}); \
                     --force-timings judges them anyway",
                    a.describe(),
                    b.describe()
                )),
            ),
            _ => (
                false,
                Some(
                    "timings not judged: a report records no machine fingerprint; \
                     --force-timings judges them anyway"
                        .into(),
                ),
            ),
        },
    }
}

/// Compares two reports: quality always, timings as `timings` says; every changed figure is
/// listed, regressions flagged.
pub fn compare(old: &Report, new: &Report, t: Thresholds, timings: TimingCheck) -> Comparison {
    let (judge_timings, note) = timings_judged(old, new, timings);
    let mut changes = Vec::new();
    for o in &old.records {
        let name = format!("{} / {}", o.mesh, o.scheme);
        let Some(n) = new
            .records
            .iter()
            .find(|n| n.mesh == o.mesh && n.scheme == o.scheme)
        else {
            changes.push(Change {
                record: name,
                key: "(record)".into(),
                old: Some(1.0),
                new: None,
                regression: true,
            });
            continue;
        };
        for &(key, better, abs) in QUALITY {
            let (a, b) = (number(o, key), number(n, key));
            let rel = if COUNTS.contains(&key) {
                0.0
            } else {
                t.quality_rel
            };
            let regression = match (a, b) {
                (Some(a), Some(b)) => worse(a, b, better, abs, rel),
                (Some(_), None) => true,
                _ => false,
            };
            if a != b {
                changes.push(Change {
                    record: name.clone(),
                    key: key.into(),
                    old: a,
                    new: b,
                    regression,
                });
            }
        }
        if !judge_timings {
            continue;
        }
        for &key in TIMINGS {
            if let (Some(a), Some(b)) = (number(o, key), number(n, key))
                && a >= 1.0
            {
                let spread_key = format!("{key}_spread_rel");
                let spread = [number(o, &spread_key), number(n, &spread_key)]
                    .into_iter()
                    .flatten()
                    .filter(|s| s.is_finite() && *s >= 0.0)
                    .fold(0.0, f64::max);
                let allowed = t.time_ratio * (1.0 + spread);
                let ratio = b / a;
                if !(1.0 / allowed..=allowed).contains(&ratio) {
                    changes.push(Change {
                        record: name.clone(),
                        key: key.into(),
                        old: Some(a),
                        new: Some(b),
                        regression: ratio > allowed,
                    });
                }
            }
        }
    }
    Comparison {
        changes,
        notes: note.into_iter().collect(),
    }
}

/// The comparison as text, regressions marked, then the notes.
pub fn to_text(comparison: &Comparison) -> String {
    let notes: String = comparison
        .notes
        .iter()
        .map(|n| format!("note: {n}\n"))
        .collect();
    let changes = &comparison.changes;
    if changes.is_empty() {
        return format!("no changes\n{notes}");
    }
    let cell = |x: Option<f64>| x.map_or("-".to_string(), |x| format!("{x:.3e}"));
    let mut out = String::new();
    for c in changes {
        out += &format!(
            "{} {:<32} {:<28} {:>11} -> {:>11}\n",
            if c.regression { "WORSE" } else { "     " },
            c.record,
            c.key,
            cell(c.old),
            cell(c.new)
        );
    }
    let worse = changes.iter().filter(|c| c.regression).count();
    out += &format!("{worse} regression(s) among {} change(s)\n", changes.len());
    out + &notes
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::provenance::Machine;

    fn machine(cpu: &str) -> Machine {
        Machine {
            cpu: cpu.into(),
            logical_cores: 8,
            os: "linux".into(),
            arch: "x86_64".into(),
        }
    }

    fn report(values: &[(&str, f64)]) -> Report {
        let mut figures = serde_json::Map::new();
        for (k, v) in values {
            figures.insert(k.to_string(), (*v).into());
        }
        Report {
            format: "smoothlab-report".into(),
            version: 1,
            commit: "x".into(),
            date: "d".into(),
            records: vec![Record {
                mesh: "icosahedron".into(),
                scheme: "hb".into(),
                figures,
                error: None,
            }],
            describe: None,
            dirty: None,
            tool_version: None,
            machine: Some(machine("cpu A")),
            shards: None,
        }
    }

    fn flagged(comparison: &Comparison) -> Vec<&str> {
        comparison
            .changes
            .iter()
            .filter(|c| c.regression)
            .map(|c| c.key.as_str())
            .collect()
    }

    #[test]
    fn rounding_noise_is_not_a_regression_but_an_injected_one_is() {
        let old = report(&[
            ("g1_max_rad", 3e-15),
            ("continuity_order", 1.0),
            ("construct_ms", 10.0),
        ]);
        let noise = report(&[
            ("g1_max_rad", 7e-15),
            ("continuity_order", 1.0),
            ("construct_ms", 12.0),
        ]);
        let t = Thresholds::default();
        let comparison = compare(&old, &noise, t, TimingCheck::SameMachine);
        assert!(!comparison.failed(), "{comparison:?}");

        let broken = report(&[
            ("g1_max_rad", 0.2),
            ("continuity_order", 0.0),
            ("construct_ms", 40.0),
        ]);
        let comparison = compare(&old, &broken, t, TimingCheck::SameMachine);
        assert_eq!(
            flagged(&comparison),
            ["g1_max_rad", "continuity_order", "construct_ms"]
        );
        // Without --timings only quality is judged.
        let comparison = compare(&old, &broken, t, TimingCheck::Skip);
        assert_eq!(flagged(&comparison), ["g1_max_rad", "continuity_order"]);
        assert!(comparison.notes[0].starts_with("timings not judged"));
    }

    #[test]
    fn timings_of_another_machine_are_judged_only_when_forced() {
        let old = report(&[("g1_max_rad", 0.1), ("construct_ms", 10.0)]);
        let mut slower = report(&[("g1_max_rad", 0.1), ("construct_ms", 30.0)]);
        slower.machine = Some(machine("cpu B"));
        let t = Thresholds::default();
        let comparison = compare(&old, &slower, t, TimingCheck::SameMachine);
        assert!(comparison.changes.is_empty(), "{comparison:?}");
        assert!(
            comparison.notes[0].contains("different machines (cpu A, 8 logical cores"),
            "{:?}",
            comparison.notes
        );
        assert!(to_text(&comparison).starts_with("no changes\nnote: timings not judged"));
        let forced = compare(&old, &slower, t, TimingCheck::Force);
        assert_eq!(flagged(&forced), ["construct_ms"]);
        // A report without fingerprint (an earlier version) is not judged either.
        slower.machine = None;
        let comparison = compare(&old, &slower, t, TimingCheck::SameMachine);
        assert!(!comparison.failed());
        assert!(comparison.notes[0].contains("no machine fingerprint"));
    }

    #[test]
    fn the_recorded_spread_widens_the_timing_threshold() {
        let old = report(&[("construct_ms", 10.0), ("construct_ms_spread_rel", 0.05)]);
        let new = report(&[("construct_ms", 17.0), ("construct_ms_spread_rel", 0.2)]);
        let t = Thresholds::default();
        // 1.7 > 1.5, but within 1.5 · (1 + 0.2) = 1.8.
        let comparison = compare(&old, &new, t, TimingCheck::SameMachine);
        assert!(!comparison.failed(), "{comparison:?}");
        let steady = report(&[("construct_ms", 17.0), ("construct_ms_spread_rel", 0.01)]);
        // Beyond 1.5 · (1 + 0.05) = 1.575.
        let comparison = compare(&old, &steady, t, TimingCheck::SameMachine);
        assert_eq!(flagged(&comparison), ["construct_ms"]);
    }

    #[test]
    fn reports_and_metrics_output_do_not_mix() {
        let old = report(&[("g1_max_rad", 0.1)]);
        let mut metrics = old.clone();
        metrics.records[0].mesh = METRICS_MESH.into();
        assert!(check_comparable(&old, &old).is_ok());
        assert!(check_comparable(&metrics, &metrics).is_ok());
        let err = check_comparable(&old, &metrics).unwrap_err();
        assert!(
            err.to_string()
                .starts_with("cannot compare a report with metrics --json output"),
            "{err}"
        );
    }

    #[test]
    fn thresholds_that_cannot_fail_are_refused() {
        assert!(Thresholds::default().check().is_ok());
        let exact = Thresholds {
            quality_rel: 0.0,
            time_ratio: 1.0,
        };
        assert!(exact.check().is_ok(), "zero tolerance is a strict gate");
        for (quality_rel, time_ratio, flag) in [
            (f64::NAN, 1.5, "--quality-rel NaN"),
            (-0.1, 1.5, "--quality-rel -0.1"),
            (f64::INFINITY, 1.5, "--quality-rel inf"),
            (0.05, f64::NAN, "--time-ratio NaN"),
            (0.05, f64::INFINITY, "--time-ratio inf"),
            (0.05, 0.0, "--time-ratio 0"),
            (0.05, -1.0, "--time-ratio -1"),
            (0.05, 0.9, "--time-ratio 0.9"),
        ] {
            let t = Thresholds {
                quality_rel,
                time_ratio,
            };
            let err = t.check().expect_err(flag);
            assert!(err.to_string().starts_with(flag), "{err}");
        }
    }

    #[test]
    fn one_fold_more_is_a_regression_one_less_is_not() {
        let t = Thresholds::default();
        let old = report(&[("folds", 100.0), ("folded_patches", 40.0)]);
        // 101 is within 5 % of 100, but a count is judged exactly.
        let more = report(&[("folds", 101.0), ("folded_patches", 40.0)]);
        assert_eq!(
            flagged(&compare(&old, &more, t, TimingCheck::Skip)),
            ["folds"]
        );
        let fewer = report(&[("folds", 99.0), ("folded_patches", 39.0)]);
        let comparison = compare(&old, &fewer, t, TimingCheck::Skip);
        assert!(!comparison.failed(), "{comparison:?}");
        assert_eq!(comparison.changes.len(), 2, "{comparison:?}");
        // A report written before the figure existed compares without a verdict on it.
        let before = report(&[]);
        let comparison = compare(&before, &more, t, TimingCheck::Skip);
        assert!(!comparison.failed(), "{comparison:?}");
    }

    #[test]
    fn a_missing_record_is_a_regression() {
        let old = report(&[("g1_max_rad", 0.0)]);
        let mut new = old.clone();
        new.records.clear();
        let comparison = compare(&old, &new, Thresholds::default(), TimingCheck::Skip);
        assert!(comparison.failed(), "{comparison:?}");
    }
}
