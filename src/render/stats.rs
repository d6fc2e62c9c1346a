//! Named render statistics, written by `--stats F.json` with exactly the keys of docs/guide/contracts.md
//! (plus a few extra keys after them).

use serde::Serialize;

use crate::error::{Error, Result};
use crate::render::intersect::IntersectCounters;

/// What one render did and what it cost.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct RenderStats {
    /// Rays traced (camera rays, geometry rays through pixel centres, path-tracing rays).
    pub rays: u64,
    /// Pixels rendered (summed over the frames of an animation).
    pub pixels: u64,
    /// Rays per pixel: `rays / pixels` (a geometry ray through the pixel centre plus one ray
    /// per sample, the centre ray alone at 1 spp; more in `shaded` mode, with its bounces).
    pub rays_per_pixel: f64,
    /// Rays per second of `render_ms` (all threads together).
    pub rays_per_s: f64,
    /// Pixels per second of `render_ms` (all threads together).
    pub pixels_per_s: f64,
    /// Rays that hit the surface.
    pub hits: u64,
    /// Rays that hit nothing.
    pub misses: u64,
    /// Mean Newton iterations per accepted root.
    pub newton_iter_mean: f64,
    /// Largest Newton iteration count of an accepted root.
    pub newton_iter_max: u32,
    /// Newton runs that missed a root the fallback subdivision then found in their leaf.
    pub newton_failures: u64,
    /// Leaf subdivision plus BVH build, milliseconds.
    pub bvh_build_ms: f64,
    /// Rendering (all rays and shading), milliseconds.
    pub render_ms: f64,
    /// BVH leaves (sub-patches, or triangles on the tessellated path).
    pub leaves: u64,
    /// Bytes of the surface representation traced: patches (or triangles and normals) plus BVH.
    pub memory_bytes: u64,
    /// Newton runs started (one per leaf the traversal reached).
    pub newton_runs: u64,
    /// Leaves whose hit only the fallback subdivision found: after a failed Newton run, or
    /// after a run whose root lay outside the ray's interval.
    pub fallback_roots: u64,
    /// Newton runs that could neither find a root in their leaf nor prove there is none (the
    /// fallback searched the leaf; most find nothing: the ray misses that leaf).
    pub newton_unconverged: u64,
    /// Pieces the fallback left undecided at its deepest level: rays there may have missed a
    /// root. 0 unless rays graze the surface along a tangency.
    pub newton_undecided: u64,
    /// Newton runs proved misses by their leaf's boundary (a ray that meets the leaf at most
    /// once and whose projected boundary does not wind around it), most of which would
    /// otherwise have ended undecided and searched the leaf.
    pub newton_boundary_cleared: u64,
    /// Number of patches.
    pub patches: u64,
    /// Where `memory_bytes` goes: bytes by part of the traced representation (exact path:
    /// `bvh_nodes`, `leaves`, `power_forms`, `blend_bounds`, `whole_patches`, `control_points`,
    /// `face_edges`; tessellated path: `vertices`, `triangles`, `bvh_nodes`), summing to it.
    #[serde(skip_serializing_if = "MemoryParts::is_empty")]
    pub memory_parts: MemoryParts,
    /// Half-range of the curvature colour map, when in curvature mode.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub curvature_half_range: Option<f64>,
    /// Bright stripes per turn the zebra mode chose from the view (its automatic stripe
    /// count), when in zebra mode without a given count.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub zebra_stripes: Option<f64>,
}

/// Bytes by named part, written as a JSON object in the parts' order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MemoryParts(pub Vec<(&'static str, u64)>);

impl MemoryParts {
    /// True when no part is known (no render).
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// Bytes of all parts together.
    pub fn total(&self) -> u64 {
        self.0.iter().map(|(_, bytes)| bytes).sum()
    }
}

impl Serialize for MemoryParts {
    fn serialize<S: serde::Serializer>(
        &self,
        serializer: S,
    ) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut map = serializer.serialize_map(Some(self.0.len()))?;
        for (name, bytes) in &self.0 {
            map.serialize_entry(name, bytes)?;
        }
        map.end()
    }
}

impl RenderStats {
    /// Fills the Newton fields from summed counters.
    pub fn set_newton(&mut self, c: &IntersectCounters) {
        self.newton_iter_mean = if c.roots_accepted > 0 {
            c.accepted_iterations as f64 / c.roots_accepted as f64
        } else {
            0.0
        };
        self.newton_iter_max = c.accepted_iterations_max;
        self.newton_failures = c.newton_failures;
        self.newton_runs = c.newton_runs;
        self.fallback_roots = c.fallback_roots;
        self.newton_unconverged = c.newton_unconverged;
        self.newton_undecided = c.undecided;
        self.newton_boundary_cleared = c.boundary_cleared;
    }

    /// Fills the rates (`rays_per_pixel`, `rays_per_s`, `pixels_per_s`) from the counts and
    /// `render_ms`.
    pub fn set_rates(&mut self) {
        let per = |count: u64, over: f64| if over > 0.0 { count as f64 / over } else { 0.0 };
        self.rays_per_pixel = per(self.rays, self.pixels as f64);
        self.rays_per_s = per(self.rays, self.render_ms * 1e-3);
        self.pixels_per_s = per(self.pixels, self.render_ms * 1e-3);
    }

    /// Writes the statistics as pretty JSON to `path` (atomically, see
    /// [`crate::files::write_atomic`]).
    pub fn write_json(&self, path: &std::path::Path) -> Result<()> {
        let text = serde_json::to_string_pretty(self)
            .map_err(|e| Error::Invalid(format!("statistics to JSON: {e}")))?;
        crate::files::write_atomic(path, (text + "\n").as_bytes())
    }
}
