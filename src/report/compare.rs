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
//! Timings under 1 ms (before or after) are too noisy to judge and are skipped.
//!
//! Every change gets a [`Verdict`]: WORSE (a regression), BETTER (an improvement beyond the
//! same tolerance the other way) or same within tolerance. A change that does not show at the
//! four significant digits of the text (`2.000e0 → 2.000e0`, a last-digit drift) and is within
//! tolerance is counted but not listed. Two `metrics --json` outputs of one scheme each are
//! compared with each other whatever their schemes (`metrics --scheme hb` against
//! `metrics --scheme pn` on one mesh).

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
    ("g1_beyond_rounding_max_rad", Better::Lower, NORMAL_RAD),
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
    /// Every changed figure that shows at four significant digits or is judged better or
    /// worse, with its verdict.
    pub changes: Vec<Change>,
    /// Figures that changed within tolerance below the fourth significant digit: counted,
    /// not listed.
    pub unlisted: usize,
    /// Figures the new report has and the old one lacks (written by a later version): counted,
    /// not listed, no verdict.
    pub new_figures: usize,
    /// Lines telling what was not judged and why (timings skipped, machines differ).
    pub notes: Vec<String>,
}

impl Comparison {
    /// True if any change is a regression.
    pub fn failed(&self) -> bool {
        self.changes.iter().any(Change::regression)
    }

    /// How many listed changes have the verdict `verdict`.
    pub fn count(&self, verdict: Verdict) -> usize {
        self.changes.iter().filter(|c| c.verdict == verdict).count()
    }

    /// One line of counts: `N regression(s), N improvement(s), N within tolerance among N
    /// change(s)`, then the last-digit changes that are not listed, if any (no line break).
    pub fn summary(&self) -> String {
        let mut line = format!(
            "{} regression(s), {} improvement(s), {} within tolerance among {} change(s)",
            self.count(Verdict::Worse),
            self.count(Verdict::Better),
            self.count(Verdict::Same),
            self.changes.len()
        );
        if self.unlisted > 0 {
            line += &format!("; {} last-digit change(s) not listed", self.unlisted);
        }
        if self.new_figures > 0 {
            line += &format!("; {} figure(s) new in the new report", self.new_figures);
        }
        line
    }
}

/// How a change is judged.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// Worse beyond its tolerance (or threshold): a regression, the comparison fails.
    Worse,
    /// Better beyond its tolerance (or threshold): an improvement.
    Better,
    /// Changed, but within tolerance either way (or not judged, e.g. a figure a report lacks).
    Same,
}

impl Verdict {
    /// The word of the text and the page: `WORSE`, `BETTER`, `same`.
    pub fn word(self) -> &'static str {
        match self {
            Verdict::Worse => "WORSE",
            Verdict::Better => "BETTER",
            Verdict::Same => "same",
        }
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
    /// Worse, better or the same within tolerance.
    pub verdict: Verdict,
}

/// The key of the change that says a record of the old report is missing from the new one.
pub const MISSING_RECORD: &str = "(record)";

impl Change {
    /// True if this is a regression.
    pub fn regression(&self) -> bool {
        self.verdict == Verdict::Worse
    }

    /// `new / old` when both are known and `old` is not zero.
    pub fn ratio(&self) -> Option<f64> {
        match (self.old, self.new) {
            (Some(a), Some(b)) if a != 0.0 => Some(b / a),
            _ => None,
        }
    }

    /// The relative change as text: `+12.5%` / `-40.0%` for ratios between 0.1 and 10,
    /// `x2.5e3` / `x1.0e-4` beyond them, `from 0` when the old value is zero, empty when a value
    /// is missing.
    pub fn ratio_text(&self) -> String {
        match (self.old, self.new, self.ratio()) {
            (_, _, Some(r)) if (0.1..=10.0).contains(&r) => format!("{:+.1}%", (r - 1.0) * 1e2),
            (_, _, Some(r)) => format!("x{r:.1e}"),
            (Some(_), Some(_), None) => "from 0".into(),
            _ => String::new(),
        }
    }
}

/// A value as the text and the page show it: four significant digits (`1.234e-5`), integers as
/// they are, `-` when missing.
pub fn number_text(x: Option<f64>) -> String {
    match x {
        Some(x) if x.fract() == 0.0 && x.abs() < 1e15 => format!("{x:.0}"),
        Some(x) => format!("{x:.3e}"),
        None => "-".into(),
    }
}

fn number(r: &Record, key: &str) -> Option<f64> {
    r.figures.get(key).and_then(serde_json::Value::as_f64)
}

/// The verdict on a quality figure moving from `old` to `new`: worse or better when it moves
/// by more than `abs + rel · |old|` in the bad or the good direction.
fn judge(old: f64, new: f64, better: Better, abs: f64, rel: f64) -> Verdict {
    let allowed = abs + rel * old.abs();
    let (up, down) = (new > old + allowed, new < old - allowed);
    match (better, up, down) {
        (Better::Lower, true, _) | (Better::Higher, _, true) => Verdict::Worse,
        (Better::Lower, _, true) | (Better::Higher, true, _) => Verdict::Better,
        _ => Verdict::Same,
    }
}

/// The verdict on quality figure `key` moving from `old` to `new` with relative tolerance
/// `rel` (counts exactly); None when `key` is not a tracked quality figure.
pub fn judge_quality(key: &str, old: f64, new: f64, rel: f64) -> Option<Verdict> {
    let &(_, better, abs) = QUALITY.iter().find(|(k, _, _)| *k == key)?;
    let rel = if COUNTS.contains(&key) { 0.0 } else { rel };
    Some(judge(old, new, better, abs, rel))
}

/// The tracked quality figures, in the order of the comparison.
pub fn quality_keys() -> impl Iterator<Item = &'static str> {
    QUALITY.iter().map(|(k, _, _)| *k)
}

/// The verdict on a timing moving from `old` to `new` (ms): worse when `new / old` exceeds
/// `ratio · (1 + spread)`, better when it is below the inverse; the same when either is under
/// 1 ms (a sub-millisecond run held up once by the scheduler reads as a tenfold change).
pub fn judge_timing(old: f64, new: f64, spread: f64, ratio: f64) -> Verdict {
    let allowed = ratio * (1.0 + spread.max(0.0));
    let r = new / old;
    if old.is_nan() || old < 1.0 || new < 1.0 || (1.0 / allowed..=allowed).contains(&r) {
        Verdict::Same
    } else if r > allowed {
        Verdict::Worse
    } else {
        Verdict::Better
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

/// The pairs of records compared: every record of `old` with the record of `new` of the same
/// mesh and scheme (None when `new` lacks it). Two `metrics --json` outputs of one record each
/// are paired whatever their schemes, named `(metrics) / OLD -> NEW` when they differ.
fn pairs<'a>(old: &'a Report, new: &'a Report) -> Vec<(String, &'a Record, Option<&'a Record>)> {
    if single_metrics(old) && single_metrics(new) {
        let (o, n) = (&old.records[0], &new.records[0]);
        let name = if o.scheme == n.scheme {
            format!("{} / {}", o.mesh, o.scheme)
        } else {
            format!("{} / {} -> {}", o.mesh, o.scheme, n.scheme)
        };
        return vec![(name, o, Some(n))];
    }
    old.records
        .iter()
        .map(|o| {
            let n = new
                .records
                .iter()
                .find(|n| n.mesh == o.mesh && n.scheme == o.scheme);
            (format!("{} / {}", o.mesh, o.scheme), o, n)
        })
        .collect()
}

/// True for `metrics --json` output of one scheme.
fn single_metrics(r: &Report) -> bool {
    r.records.len() == 1 && r.records[0].mesh == METRICS_MESH
}

/// True when `a` and `b` agree to four significant digits (or are both missing).
fn shows_unchanged(a: Option<f64>, b: Option<f64>) -> bool {
    a.map(|x| format!("{x:.3e}")) == b.map(|x| format!("{x:.3e}"))
}

/// Compares two reports: quality always, timings as `timings` says; every change is judged
/// (worse, better, same within tolerance); last-digit changes within tolerance are counted in
/// [`Comparison::unlisted`] instead of listed.
pub fn compare(old: &Report, new: &Report, t: Thresholds, timings: TimingCheck) -> Comparison {
    let (judge_timings, note) = timings_judged(old, new, timings);
    let mut out = Comparison {
        notes: note.into_iter().collect(),
        ..Comparison::default()
    };
    for (name, o, n) in pairs(old, new) {
        let Some(n) = n else {
            out.changes.push(Change {
                record: name,
                key: MISSING_RECORD.into(),
                old: None,
                new: None,
                verdict: Verdict::Worse,
            });
            continue;
        };
        for key in quality_keys() {
            let (a, b) = (number(o, key), number(n, key));
            if a == b {
                continue;
            }
            if a.is_none() {
                out.new_figures += 1;
                continue;
            }
            let verdict = match (a, b) {
                (Some(a), Some(b)) => {
                    judge_quality(key, a, b, t.quality_rel).unwrap_or(Verdict::Same)
                }
                (Some(_), None) => Verdict::Worse,
                _ => Verdict::Same,
            };
            if verdict == Verdict::Same && shows_unchanged(a, b) {
                out.unlisted += 1;
                continue;
            }
            out.changes.push(Change {
                record: name.clone(),
                key: key.into(),
                old: a,
                new: b,
                verdict,
            });
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
                let verdict = judge_timing(a, b, spread, t.time_ratio);
                if verdict != Verdict::Same {
                    out.changes.push(Change {
                        record: name.clone(),
                        key: key.into(),
                        old: Some(a),
                        new: Some(b),
                        verdict,
                    });
                }
            }
        }
    }
    let added = new
        .records
        .iter()
        .filter(|n| {
            !old.records
                .iter()
                .any(|o| o.mesh == n.mesh && o.scheme == n.scheme)
        })
        .count();
    if added > 0 && !(single_metrics(old) && single_metrics(new)) {
        out.notes.push(format!(
            "{added} record(s) of the new report are not in the old one"
        ));
    }
    out
}

/// The comparison as text: one line per change, `VERDICT record figure old → new ratio`, then
/// the counts ([`Comparison::summary`]) and the notes.
pub fn to_text(comparison: &Comparison) -> String {
    let notes: String = comparison
        .notes
        .iter()
        .map(|n| format!("note: {n}\n"))
        .collect();
    let changes = &comparison.changes;
    if changes.is_empty() {
        let mut unlisted = Vec::new();
        if comparison.unlisted > 0 {
            unlisted.push(format!(
                "{} last-digit change(s) within tolerance",
                comparison.unlisted
            ));
        }
        if comparison.new_figures > 0 {
            unlisted.push(format!(
                "{} figure(s) new in the new report",
                comparison.new_figures
            ));
        }
        let unlisted = match unlisted.is_empty() {
            true => String::new(),
            false => format!(" ({} not listed)", unlisted.join(", ")),
        };
        return format!("no changes{unlisted}\n{notes}");
    }
    let record_width = changes.iter().map(|c| c.record.len()).max().unwrap_or(0);
    let key_width = changes.iter().map(|c| c.key.len()).max().unwrap_or(0);
    let mut out = String::new();
    for c in changes {
        let values = if c.key == MISSING_RECORD {
            "missing from the new report".to_string()
        } else {
            format!(
                "{:>10} → {:<10} {}",
                number_text(c.old),
                number_text(c.new),
                c.ratio_text()
            )
        };
        // `VERDICT RECORD` with one space (what scripts match, e.g. `WORSE mesh / hb`),
        // padded so that the figures line up.
        let head = format!("{} {}", c.verdict.word(), c.record);
        out += &format!(
            "{head:<width$}  {:<key_width$}  {}\n",
            c.key,
            values.trim_end(),
            width = record_width + 7
        );
    }
    out += &comparison.summary();
    out += "\n";
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
            .filter(|c| c.regression())
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

    /// A timing under 1 ms on either side is not judged: the baseline's 0.05 ms construction
    /// held up to 1.4 ms once by a loaded machine is no improvement when it reads 0.05 again.
    #[test]
    fn sub_millisecond_timings_are_not_judged() {
        let t = Thresholds::default();
        for (a, b) in [(1.4, 0.05), (0.05, 1.4), (0.2, 0.9)] {
            let old = report(&[("construct_ms", a)]);
            let new = report(&[("construct_ms", b)]);
            let comparison = compare(&old, &new, t, TimingCheck::SameMachine);
            assert!(
                comparison
                    .changes
                    .iter()
                    .all(|c| c.verdict == Verdict::Same),
                "{a} → {b}: {comparison:?}"
            );
        }
        // Both at 1 ms or more are judged.
        let old = report(&[("construct_ms", 1.0)]);
        let new = report(&[("construct_ms", 3.0)]);
        let comparison = compare(&old, &new, t, TimingCheck::SameMachine);
        assert_eq!(flagged(&comparison), ["construct_ms"]);
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
        // A report written before the figure existed compares without a verdict on it: the
        // new figures are counted, not listed.
        let before = report(&[]);
        let comparison = compare(&before, &more, t, TimingCheck::Skip);
        assert!(!comparison.failed(), "{comparison:?}");
        assert!(comparison.changes.is_empty(), "{comparison:?}");
        assert_eq!(comparison.new_figures, 2);
        assert!(
            to_text(&comparison)
                .starts_with("no changes (2 figure(s) new in the new report not listed)\n"),
            "{}",
            to_text(&comparison)
        );
    }

    #[test]
    fn a_missing_record_is_a_regression() {
        let old = report(&[("g1_max_rad", 0.0)]);
        let mut new = old.clone();
        new.records.clear();
        let comparison = compare(&old, &new, Thresholds::default(), TimingCheck::Skip);
        assert!(comparison.failed(), "{comparison:?}");
    }
    #[test]
    fn changes_are_judged_both_ways_with_their_ratio() {
        let t = Thresholds::default();
        let old = report(&[
            ("g1_max_rad", 0.1),
            ("curvature_jump_max_rel", 0.2),
            ("bending_energy", 2.0),
            ("interp_max_rel", 1e-3),
            ("continuity_order", 1.0),
        ]);
        let new = report(&[
            // Worse by 50 %, better by 50 %, the same within 5 %.
            ("g1_max_rad", 0.15),
            ("curvature_jump_max_rel", 0.1),
            ("bending_energy", 2.0 * (1.0 + 1e-13)),
            ("interp_max_rel", 1.01e-3),
            ("continuity_order", 2.0),
        ]);
        let c = compare(&old, &new, t, TimingCheck::Skip);
        let verdicts: Vec<(&str, Verdict)> = c
            .changes
            .iter()
            .map(|c| (c.key.as_str(), c.verdict))
            .collect();
        assert_eq!(
            verdicts,
            [
                ("interp_max_rel", Verdict::Same),
                ("g1_max_rad", Verdict::Worse),
                ("curvature_jump_max_rel", Verdict::Better),
                ("continuity_order", Verdict::Better),
            ]
        );
        // 2.000e0 -> 2.000e0 is no listed change.
        assert_eq!(c.unlisted, 1, "{c:?}");
        let text = to_text(&c);
        assert!(!text.contains("bending_energy"), "{text}");
        let line = |key: &str| {
            text.lines()
                .find(|l| l.contains(key))
                .unwrap_or_else(|| panic!("{key} in {text}"))
                .split_whitespace()
                .collect::<Vec<_>>()
                .join(" ")
        };
        assert_eq!(
            line("g1_max_rad"),
            "WORSE icosahedron / hb g1_max_rad 1.000e-1 → 1.500e-1 +50.0%"
        );
        assert_eq!(
            line("curvature_jump"),
            "BETTER icosahedron / hb curvature_jump_max_rel 2.000e-1 → 1.000e-1 -50.0%"
        );
        assert_eq!(
            line("interp_max_rel"),
            "same icosahedron / hb interp_max_rel 1.000e-3 → 1.010e-3 +1.0%"
        );
        assert_eq!(
            line("continuity_order"),
            "BETTER icosahedron / hb continuity_order 1 → 2 +100.0%"
        );
        assert!(
            text.contains(
                "1 regression(s), 2 improvement(s), 1 within tolerance among 4 change(s); \
                 1 last-digit change(s) not listed"
            ),
            "{text}"
        );
    }

    #[test]
    fn ratios_beyond_a_decade_and_from_zero_read_as_factors() {
        let change = |old: Option<f64>, new: Option<f64>| Change {
            record: "r".into(),
            key: "k".into(),
            old,
            new,
            verdict: Verdict::Same,
        };
        assert_eq!(change(Some(1e-15), Some(1e-2)).ratio_text(), "x1.0e13");
        assert_eq!(change(Some(4.0), Some(1e-4)).ratio_text(), "x2.5e-5");
        assert_eq!(change(Some(0.0), Some(1e-4)).ratio_text(), "from 0");
        assert_eq!(change(Some(1.0), None).ratio_text(), "");
        assert_eq!(change(Some(-2.0), Some(-1.0)).ratio_text(), "-50.0%");
        assert_eq!(number_text(Some(3.0)), "3");
        assert_eq!(number_text(Some(3.5)), "3.500e0");
        assert_eq!(number_text(None), "-");
    }

    #[test]
    fn two_single_scheme_metrics_outputs_compare_with_each_other() {
        let metrics = |scheme: &str, g1: f64| {
            let mut r = report(&[("g1_max_rad", g1)]);
            r.records[0].mesh = METRICS_MESH.into();
            r.records[0].scheme = scheme.into();
            r
        };
        let t = Thresholds::default();
        let c = compare(
            &metrics("hb", 0.1),
            &metrics("pn", 0.3),
            t,
            TimingCheck::Skip,
        );
        assert_eq!(c.changes.len(), 1, "{c:?}");
        assert_eq!(c.changes[0].record, "(metrics) / hb -> pn");
        assert_eq!(flagged(&c), ["g1_max_rad"]);
        assert!(
            c.notes.iter().all(|n| !n.contains("not in the old")),
            "{c:?}"
        );
        let same = compare(
            &metrics("hb", 0.1),
            &metrics("hb", 0.1),
            t,
            TimingCheck::Skip,
        );
        assert!(same.changes.is_empty(), "{same:?}");
    }

    #[test]
    fn a_missing_record_reads_as_missing() {
        let old = report(&[("g1_max_rad", 0.0)]);
        let mut new = old.clone();
        new.records[0].scheme = "pn".into();
        let c = compare(&old, &new, Thresholds::default(), TimingCheck::Skip);
        let text = to_text(&c);
        assert!(
            text.starts_with("WORSE icosahedron / hb   (record)  missing from the new report\n"),
            "{text}"
        );
        assert!(text.contains("note: 1 record(s) of the new report are not in the old one"));
    }
}
