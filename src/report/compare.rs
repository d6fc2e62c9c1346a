//! `smoothlab compare OLD.json NEW.json`: what changed between two reports, per scheme × mesh,
//! and whether anything got worse beyond its tolerance (quality) or noise threshold (timing).
//!
//! A quality figure regresses when it moves in its bad direction by more than
//! `abs + rel · |old|` (each figure has its own `abs`, the tolerance of the measurement — e.g.
//! 1e-9 rad for normal jumps that are exact zeros up to rounding — and the common `rel`); the
//! continuity order regresses when it drops at all; a timing regresses when `new / old` exceeds
//! the ratio threshold (timings under 1 ms are too noisy to judge and are skipped). A record in
//! OLD that NEW lacks is a regression too.

use super::{Record, Report};
use crate::error::{Error, Result};

/// Which way is better.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Better {
    Lower,
    Higher,
}

/// A tracked quality figure: key, better direction, absolute tolerance.
const QUALITY: &[(&str, Better, f64)] = &[
    ("interp_max_rel", Better::Lower, 1e-12),
    ("g0_max_rel", Better::Lower, 1e-12),
    ("g1_max_rad", Better::Lower, 1e-9),
    ("g1_between_faces_max_rad", Better::Lower, 1e-9),
    ("g1_inside_faces_max_rad", Better::Lower, 1e-9),
    ("curvature_jump_max_rel", Better::Lower, 1e-6),
    ("continuity_order", Better::Higher, 0.0),
    ("min_regularity_rel", Better::Higher, 0.0),
    ("network_undulation_max_rad", Better::Lower, 1e-6),
    ("bending_energy", Better::Lower, 1e-9),
    ("distance_max_rel", Better::Lower, 1e-12),
    ("normal_error_max_rad", Better::Lower, 1e-9),
];

/// Tracked timings (milliseconds).
const TIMINGS: &[&str] = &["construct_ms", "render_ms"];

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

/// Compares two reports; every changed figure is listed, regressions flagged.
pub fn compare(old: &Report, new: &Report, t: Thresholds) -> Vec<Change> {
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
            let regression = match (a, b) {
                (Some(a), Some(b)) => worse(a, b, better, abs, t.quality_rel),
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
        for &key in TIMINGS {
            if let (Some(a), Some(b)) = (number(o, key), number(n, key))
                && a >= 1.0
            {
                let ratio = b / a;
                if !(1.0 / t.time_ratio..=t.time_ratio).contains(&ratio) {
                    changes.push(Change {
                        record: name.clone(),
                        key: key.into(),
                        old: Some(a),
                        new: Some(b),
                        regression: ratio > t.time_ratio,
                    });
                }
            }
        }
    }
    changes
}

/// The comparison as text, regressions marked.
pub fn to_text(changes: &[Change]) -> String {
    if changes.is_empty() {
        return "no changes\n".into();
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
    out
}

#[cfg(test)]
mod tests {
    use super::*;

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
            }],
        }
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
        let changes = compare(&old, &noise, Thresholds::default());
        assert!(changes.iter().all(|c| !c.regression), "{changes:?}");

        let broken = report(&[
            ("g1_max_rad", 0.2),
            ("continuity_order", 0.0),
            ("construct_ms", 40.0),
        ]);
        let changes = compare(&old, &broken, Thresholds::default());
        let flagged: Vec<&str> = changes
            .iter()
            .filter(|c| c.regression)
            .map(|c| c.key.as_str())
            .collect();
        assert_eq!(flagged, ["g1_max_rad", "continuity_order", "construct_ms"]);
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
    fn a_missing_record_is_a_regression() {
        let old = report(&[("g1_max_rad", 0.0)]);
        let mut new = old.clone();
        new.records.clear();
        let changes = compare(&old, &new, Thresholds::default());
        assert!(changes.iter().any(|c| c.regression), "{changes:?}");
    }
}
