//! Splitting work into shards and checking that partial results belong together.
//!
//! A run with `--shard I/N` does a deterministic part of a work list — report items (a mesh
//! with every scheme variant measured on it) or frames — and writes a partial result that
//! `smoothlab merge` combines. Every shard computes the same split from the same work list:
//! [`assign`] is a greedy longest-processing-time split over estimated costs (largest cost
//! first, each to the least-loaded shard, ties to the lower index), a pure function of the costs.
//! The partial results carry a [`Manifest`] (the kind of work, `I`, `N`, the work list's
//! [`fingerprint`], the tool version), so that `merge` refuses parts of different runs and
//! names the shards that are missing.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

/// The most shards a run may be split into.
pub const MAX_SHARDS: u32 = 100_000;

/// One shard of a run: `index` (0-based) of `count`, written `I/N` on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// This shard, `0 ≤ index < count` (Slurm's `SLURM_ARRAY_TASK_ID` with `--array=0-N-1`,
    /// Kubernetes' `JOB_COMPLETION_INDEX`, GNU parallel's `{%}` − 1 or `{#}` − 1).
    pub index: u32,
    /// The number of shards of the run.
    pub count: u32,
}

impl Shard {
    /// The whole run as one shard.
    pub const WHOLE: Shard = Shard { index: 0, count: 1 };
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl FromStr for Shard {
    type Err = String;

    /// Parses `I/N` with `0 ≤ I < N ≤` [`MAX_SHARDS`].
    fn from_str(text: &str) -> std::result::Result<Shard, String> {
        let (i, n) = text
            .split_once('/')
            .ok_or_else(|| format!("shard '{text}' is not I/N (e.g. 0/4)"))?;
        let parse = |s: &str, what: &str| {
            s.trim()
                .parse::<u32>()
                .map_err(|_| format!("shard '{text}': {what} '{s}' is not a whole number ≥ 0"))
        };
        let (index, count) = (parse(i, "index")?, parse(n, "count")?);
        if count == 0 || count > MAX_SHARDS {
            return Err(format!(
                "shard '{text}': the count must be in 1..={MAX_SHARDS}"
            ));
        }
        if index >= count {
            return Err(format!(
                "shard '{text}': the index must be below the count (shards are numbered 0..{})",
                count - 1
            ));
        }
        Ok(Shard { index, count })
    }
}

/// The shard of every work item: greedy longest-processing-time over `costs` — items in
/// decreasing cost (ties: lower position first), each to the shard with the least cost so far
/// (ties: lower shard). A pure function of the costs, so every shard computes the same split.
/// A cost that is not finite or is negative counts as 0.
pub fn assign(costs: &[f64], count: u32) -> Vec<u32> {
    let count = count.max(1) as usize;
    let cost = |k: usize| {
        let c = costs[k];
        if c.is_finite() && c > 0.0 { c } else { 0.0 }
    };
    let mut order: Vec<usize> = (0..costs.len()).collect();
    order.sort_by(|&a, &b| cost(b).total_cmp(&cost(a)).then(a.cmp(&b)));
    let mut load = vec![0.0_f64; count];
    let mut out = vec![0_u32; costs.len()];
    for k in order {
        let mut best = 0;
        for (s, l) in load.iter().enumerate() {
            if *l < load[best] {
                best = s;
            }
        }
        load[best] += cost(k);
        out[k] = best as u32;
    }
    out
}

/// The items (positions) of `shard` under [`assign`], in work-list order.
pub fn items_of(costs: &[f64], shard: Shard) -> Vec<usize> {
    assign(costs, shard.count)
        .iter()
        .enumerate()
        .filter(|(_, s)| **s == shard.index)
        .map(|(k, _)| k)
        .collect()
}

/// The fingerprint of a work list's canonical text: FNV-1a (64 bits) as 16 hex digits. It only
/// has to tell different work lists apart (parts of different runs), not resist forgery, so a
/// few lines here do instead of a hashing crate.
pub fn fingerprint(text: &str) -> String {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    for byte in text.bytes() {
        hash ^= u64::from(byte);
        hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{hash:016x}")
}

/// Relative cost per mesh face of building and measuring each scheme (report work: the
/// construction, timed up to 6 times, the metrics and the two thumbnails), `flat` = 1.
/// Measured once: `smoothlab report --meshes LIST --scheme S` on `scenes/bunny.obj` (1000
/// faces), one scheme at a time, wall time minus the 0.15 s a report spends on its page and
/// plots — flat 0.29 s, pn 0.46, hb 1.36, loop94 0.93, piper 0.94, nielson 1.55, fang-mann 1.66,
/// gk 8.26 — on 2 cores shared with other work (load about 10, so ±20 %). Only the ratios
/// matter, and only for balancing shards.
const SCHEME_COST: &[(&str, f64)] = &[
    ("flat", 1.0),
    ("pn", 2.0),
    ("hb", 9.0),
    ("loop94", 6.0),
    ("piper", 6.0),
    ("nielson", 10.0),
    ("fang-mann", 11.0),
    ("gk", 58.0),
];

/// The relative cost per face of `scheme` ([`SCHEME_COST`]); a scheme missing from the table
/// costs as much as the dearest one (a wrong guess only unbalances the shards).
pub fn scheme_cost(scheme: &str) -> f64 {
    SCHEME_COST
        .iter()
        .find(|(name, _)| *name == scheme)
        .map_or_else(
            || SCHEME_COST.iter().map(|(_, c)| *c).fold(0.0, f64::max),
            |(_, c)| *c,
        )
}

/// What a partial result carries so that `merge` can check that the parts belong together
/// and that none is missing.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Manifest {
    /// Always `smoothlab-partial`.
    pub format: String,
    /// Format version of partial results ([`PARTIAL_VERSION`]).
    pub version: u32,
    /// The kind of work: `report` or `frames`.
    pub kind: String,
    /// Which shard wrote it.
    pub shard: Shard,
    /// [`fingerprint`] of the whole work list.
    pub fingerprint: String,
    /// Number of items in the whole work list.
    pub items: usize,
    /// The smoothlab version that wrote it.
    pub tool_version: String,
}

/// The format version of partial results that this build writes and reads.
pub const PARTIAL_VERSION: u32 = 1;

impl Manifest {
    /// The manifest of `shard` of a work list of `items` items whose canonical text is `work`.
    pub fn new(kind: &str, shard: Shard, work: &str, items: usize) -> Manifest {
        Manifest {
            format: "smoothlab-partial".into(),
            version: PARTIAL_VERSION,
            kind: kind.into(),
            shard,
            fingerprint: fingerprint(work),
            items,
            tool_version: env!("CARGO_PKG_VERSION").into(),
        }
    }
}

/// Checks that `parts` (each named by its file, for the messages) are shards of one run:
/// same kind, shard count, work list and tool version, no shard twice. Returns the shard count
/// and the indices of the missing shards (empty when the set is complete).
pub fn check_parts(parts: &[(String, &Manifest)]) -> Result<(u32, Vec<u32>)> {
    let Some((first_name, first)) = parts.first() else {
        return Err(Error::Invalid("merge: no partial results given".into()));
    };
    // Every manifest is checked before its shard count sizes anything.
    for (name, m) in parts {
        if m.format != "smoothlab-partial" || m.version != PARTIAL_VERSION {
            return Err(Error::Invalid(format!(
                "{name}: not a smoothlab partial result of version {PARTIAL_VERSION}"
            )));
        }
        let Shard { index, count } = m.shard;
        if count == 0 || count > MAX_SHARDS {
            return Err(Error::Invalid(format!(
                "{name}: manifest.shard.count {count} is not in 1..={MAX_SHARDS}: the part is \
                 damaged"
            )));
        }
        if index >= count {
            return Err(Error::Invalid(format!(
                "{name}: manifest.shard.index {index} is not below manifest.shard.count \
                 {count}: the part is damaged"
            )));
        }
    }
    let mut seen: Vec<Option<&str>> = vec![None; first.shard.count as usize];
    for (name, m) in parts {
        let differs = |what: &str, a: &dyn fmt::Display, b: &dyn fmt::Display| {
            Error::Invalid(format!(
                "{name}: {what} {a} differs from {b} of {first_name}: the parts are not \
                 shards of one run"
            ))
        };
        if m.kind != first.kind {
            return Err(differs("kind", &m.kind, &first.kind));
        }
        if m.shard.count != first.shard.count {
            return Err(differs("shard count", &m.shard.count, &first.shard.count));
        }
        if m.fingerprint != first.fingerprint || m.items != first.items {
            return Err(differs(
                "work list",
                &format!("{} ({} items)", m.fingerprint, m.items),
                &format!("{} ({} items)", first.fingerprint, first.items),
            ));
        }
        if m.tool_version != first.tool_version {
            return Err(differs(
                "tool version",
                &m.tool_version,
                &first.tool_version,
            ));
        }
        let slot = seen
            .get_mut(m.shard.index as usize)
            .ok_or_else(|| Error::Invalid(format!("{name}: shard {} is out of range", m.shard)))?;
        if let Some(other) = slot {
            return Err(Error::Invalid(format!(
                "{name}: shard {} is also in {other}",
                m.shard
            )));
        }
        *slot = Some(name.as_str());
    }
    let missing = (0..first.shard.count)
        .filter(|&i| seen[i as usize].is_none())
        .collect();
    Ok((first.shard.count, missing))
}

/// Reads the part files `parts` (JSON of one `kind` of partial result, e.g. "figure") and
/// checks with [`check_parts`] that they are the shards of one run and that none is missing;
/// a missing shard is an error ending in `not_merged`. The parts come back in the order given.
pub fn read_complete_parts<T: serde::de::DeserializeOwned>(
    parts: &[std::path::PathBuf],
    kind: &str,
    manifest: impl Fn(&T) -> &Manifest,
    not_merged: &str,
) -> Result<Vec<(std::path::PathBuf, T)>> {
    let mut read = Vec::new();
    for path in parts {
        let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
        let part: T = serde_json::from_str(&text).map_err(|e| {
            Error::Invalid(format!(
                "{}: not a smoothlab {kind} part: {e}",
                path.display()
            ))
        })?;
        read.push((path.clone(), part));
    }
    let named: Vec<(String, &Manifest)> = read
        .iter()
        .map(|(p, part)| (p.display().to_string(), manifest(part)))
        .collect();
    let (count, missing) = check_parts(&named)?;
    if !missing.is_empty() {
        return Err(Error::Invalid(format!(
            "merge: {}; {not_merged}",
            missing_text(&missing, count)
        )));
    }
    Ok(read)
}

/// The one-line description of missing shards, e.g. `shards 1/4, 3/4 missing`.
pub fn missing_text(missing: &[u32], count: u32) -> String {
    let names: Vec<String> = missing.iter().map(|i| format!("{i}/{count}")).collect();
    format!(
        "shard{} {} missing (no partial result given)",
        if missing.len() == 1 { "" } else { "s" },
        names.join(", ")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_parse_and_refuse_bad_input() {
        assert_eq!("2/4".parse(), Ok(Shard { index: 2, count: 4 }));
        assert_eq!(" 0 / 1 ".parse(), Ok(Shard::WHOLE));
        for bad in ["4/4", "1/0", "x/2", "-1/3", "3", "1/2/3", ""] {
            let err = bad.parse::<Shard>().expect_err(bad);
            assert!(err.contains(&format!("'{bad}'")), "{bad}: {err}");
        }
        assert_eq!(Shard { index: 3, count: 8 }.to_string(), "3/8");
    }

    #[test]
    fn the_greedy_split_balances_costs_not_counts() {
        // One heavy item and six light ones: the heavy one alone on a shard.
        let costs = [1.0, 1.0, 12.0, 1.0, 1.0, 1.0, 1.0];
        let shards = assign(&costs, 2);
        assert_eq!(shards, [1, 1, 0, 1, 1, 1, 1]);
        // Every item exactly once, loads within the largest item of each other.
        let costs: Vec<f64> = (0..50).map(|k| f64::from((k * 37) % 11 + 1)).collect();
        let shards = assign(&costs, 4);
        let mut load = [0.0; 4];
        for (c, s) in costs.iter().zip(&shards) {
            load[*s as usize] += c;
        }
        let (lo, hi) = (
            load.iter().copied().fold(f64::MAX, f64::min),
            load.iter().copied().fold(0.0, f64::max),
        );
        assert!(hi - lo <= 11.0, "{load:?}");
        let all: Vec<usize> = (0..4)
            .flat_map(|i| items_of(&costs, Shard { index: i, count: 4 }))
            .collect();
        let mut sorted = all.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..50).collect::<Vec<_>>());
        // Equal costs: round robin.
        assert_eq!(assign(&[1.0; 5], 3), [0, 1, 2, 0, 1]);
        // Bad costs count as nothing instead of poisoning the loads.
        assert_eq!(assign(&[f64::NAN, -1.0, 2.0], 2), [1, 1, 0]);
    }

    #[test]
    fn fingerprints_tell_work_lists_apart() {
        assert_eq!(fingerprint(""), "cbf29ce484222325");
        assert_ne!(fingerprint("a.obj flat"), fingerprint("a.obj pn"));
        assert_eq!(fingerprint("a.obj flat").len(), 16);
    }

    #[test]
    fn merge_checks_name_missing_and_foreign_parts() {
        let m = |i: u32, work: &str| Manifest::new("report", Shard { index: i, count: 3 }, work, 5);
        let (a, c) = (m(0, "w"), m(2, "w"));
        let (count, missing) = check_parts(&[("a".into(), &a), ("c".into(), &c)]).expect("one run");
        assert_eq!((count, missing.clone()), (3, vec![1]));
        assert_eq!(
            missing_text(&missing, count),
            "shard 1/3 missing (no partial result given)"
        );
        let foreign = m(1, "other");
        let err = check_parts(&[("a".into(), &a), ("f".into(), &foreign)]).expect_err("mixed");
        assert!(err.to_string().starts_with("f: work list"), "{err}");
        let err = check_parts(&[("a".into(), &a), ("b".into(), &a)]).expect_err("twice");
        assert!(err.to_string().contains("shard 0/3 is also in a"), "{err}");
        let mut frames = m(1, "w");
        frames.kind = "frames".into();
        let err = check_parts(&[("a".into(), &a), ("f".into(), &frames)]).expect_err("kinds");
        assert!(err.to_string().contains("kind frames"), "{err}");
    }

    #[test]
    fn damaged_shard_numbers_are_named_before_anything_is_sized() {
        let m = |index: u32, count: u32| {
            let mut m = Manifest::new("report", Shard { index: 0, count: 2 }, "w", 5);
            m.shard = Shard { index, count };
            m
        };
        let cases = [
            (
                m(0, 4_000_000_000),
                "d: manifest.shard.count 4000000000 is not in",
            ),
            (m(0, 0), "d: manifest.shard.count 0 is not in"),
            (
                m(7, 3),
                "d: manifest.shard.index 7 is not below manifest.shard.count 3",
            ),
        ];
        for (damaged, expected) in cases {
            // As the first part (whose count would size the list) and as a later one.
            for parts in [
                vec![("d".to_string(), &damaged)],
                vec![("a".to_string(), &m(0, 2)), ("d".to_string(), &damaged)],
            ] {
                let err = check_parts(&parts).expect_err("damaged");
                assert!(err.to_string().starts_with(expected), "{err}");
            }
        }
    }

    #[test]
    fn unknown_schemes_cost_the_most() {
        assert_eq!(scheme_cost("flat"), 1.0);
        assert_eq!(scheme_cost("future"), scheme_cost("gk"));
    }
}
