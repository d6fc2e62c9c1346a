//! The work list of `smoothlab report`: which meshes, and which scheme variants on each.
//!
//! An item is one mesh — a benchmark mesh, or a file of the user's data set (`report --meshes`)
//! — with every variant measured on it: a scheme with default parameters, or a point of a
//! parameter sweep (`report --sweep hb:beta=0.1,0.2`). The item is the unit of sharding, because
//! the results page frames all surfaces of a mesh with one camera and one curvature range.
//! Measuring an item never fails as a whole: a mesh that does not load, or a variant that does
//! not build, becomes records carrying the error ([`super::Record::error`]).

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use super::shard::scheme_cost;
use crate::mesh::LoadOptions;

/// Where an item's mesh comes from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MeshSource {
    /// The benchmark mesh of this name ([`super::benchmark_meshes`]).
    Benchmark(String),
    /// A mesh file, loaded when the item is measured.
    File(PathBuf),
}

/// One scheme with the parameters it is built with.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Variant {
    /// Registered scheme name.
    pub scheme: String,
    /// `name=value` pairs set (the rest take their defaults).
    pub params: Vec<(String, String)>,
    /// `name=value` pairs that replace the scheme's defaults for the run (`report --param`):
    /// applied before `params`, and not part of the label, so that the records keep the
    /// scheme's name (their `params` figure says the values used).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub defaults: Vec<(String, String)>,
}

impl Variant {
    /// A scheme with its default parameters.
    pub fn default_of(scheme: &str) -> Variant {
        Variant {
            scheme: scheme.to_string(),
            params: Vec::new(),
            defaults: Vec::new(),
        }
    }

    /// The name of the variant in the report's `scheme` field: the scheme name, followed by
    /// `:name=value` for each parameter set (`hb:beta=0.1`), the syntax of `--sweep`.
    pub fn label(&self) -> String {
        let mut label = self.scheme.clone();
        // `defaults` are not named: they stand for the scheme's defaults.
        for (name, value) in &self.params {
            label += &format!(":{name}={value}");
        }
        label
    }
}

impl Variant {
    /// The parameters the variant is built with: `defaults`, then `params` (a later pair of a
    /// name overrides an earlier one).
    pub fn build_params(&self) -> Vec<(String, String)> {
        self.defaults.iter().chain(&self.params).cloned().collect()
    }
}

/// One mesh and the variants measured on it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WorkItem {
    /// The mesh's name in the report (unique in the work list).
    pub mesh: String,
    /// Where the mesh comes from.
    pub source: MeshSource,
    /// Its number of triangles, as estimated before loading (for balancing shards).
    pub faces: usize,
    /// The variants, in the order of the report's records.
    pub variants: Vec<Variant>,
}

impl WorkItem {
    /// Estimated cost: faces × the sum of the variants' [`scheme_cost`] (at least 1 per item,
    /// so that a mesh whose faces could not be counted still weighs something).
    pub fn cost(&self) -> f64 {
        let per_face: f64 = self.variants.iter().map(|v| scheme_cost(&v.scheme)).sum();
        (self.faces.max(1) as f64 * per_face).max(1.0)
    }
}

/// The whole work of a report: the items in the order of the records, and how mesh files are
/// loaded.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WorkList {
    /// The items.
    pub items: Vec<WorkItem>,
    /// The weld tolerance mesh files are loaded with.
    pub weld_tolerance: f64,
    /// The crease angle mesh files are loaded with (none by default; left out of the JSON
    /// then, so lists without one keep their fingerprint).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub crease_angle: Option<f64>,
    /// Whether mesh files are loaded with `--strict` (every repair refused).
    #[serde(default)]
    pub strict: bool,
}

impl WorkList {
    /// A work list of `items` loaded with `load`.
    pub fn new(items: Vec<WorkItem>, load: &LoadOptions) -> WorkList {
        WorkList {
            items,
            weld_tolerance: load.weld_tolerance,
            crease_angle: load.crease_angle,
            strict: load.strict,
        }
    }

    /// How mesh files are loaded.
    pub fn load_options(&self) -> LoadOptions {
        LoadOptions {
            weld_tolerance: self.weld_tolerance,
            strict: self.strict,
            ..LoadOptions::default()
        }
        .with_crease_angle(self.crease_angle)
    }

    /// The estimated cost of every item ([`WorkItem::cost`]).
    pub fn costs(&self) -> Vec<f64> {
        self.items.iter().map(WorkItem::cost).collect()
    }

    /// The canonical text of the work list, the input of its fingerprint: compact JSON of the
    /// list (field order fixed by the types, numbers in shortest round-trip form).
    pub fn canonical(&self) -> String {
        serde_json::to_string(self).unwrap_or_default()
    }

    /// The number of records the work list makes (one per item and variant).
    pub fn record_count(&self) -> usize {
        self.items.iter().map(|i| i.variants.len()).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_and_costs() {
        let v = Variant {
            scheme: "hb".into(),
            params: vec![
                ("beta".into(), "0.1".into()),
                ("gamma0".into(), "-1".into()),
            ],
            defaults: vec![("beta".into(), "0.3".into())],
        };
        assert_eq!(v.label(), "hb:beta=0.1:gamma0=-1");
        assert_eq!(Variant::default_of("pn").label(), "pn");
        let item = |faces, schemes: &[&str]| WorkItem {
            mesh: "m".into(),
            source: MeshSource::File("m.obj".into()),
            faces,
            variants: schemes.iter().map(|s| Variant::default_of(s)).collect(),
        };
        assert_eq!(item(100, &["flat", "pn"]).cost(), 300.0);
        assert!(item(100, &["hb"]).cost() > item(100, &["flat"]).cost());
        assert_eq!(item(0, &["flat"]).cost(), 1.0);
        let list = WorkList::new(vec![item(4, &["flat"])], &LoadOptions::default());
        let other = WorkList::new(vec![item(5, &["flat"])], &LoadOptions::default());
        assert_ne!(list.canonical(), other.canonical());
        assert_eq!(list.record_count(), 1);
    }
}
