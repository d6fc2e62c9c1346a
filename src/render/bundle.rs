//! Bundles of coherent rays: rays that leave one point (the eye of a perspective camera, for
//! a block of neighbouring pixels) traverse the BVH **once, together**. The bundle's cone of
//! directions is bounded by four planes through the common origin and one across its axis;
//! one walk down the CWBVH keeps every leaf whose BVH box, and then whose oriented box,
//! reaches into that cone, marks which of the bundle's rays point into the projection of the
//! oriented box from the origin (a bit per ray), and sorts the leaves by the distance from the
//! origin to their oriented box. Each ray then tests only the leaves with its bit, in that
//! order, and stops at the first that lies beyond its closest hit so far: no node of the BVH
//! is visited per ray.
//!
//! Exactness: a ray that meets a leaf's oriented box passes through the cone and through the
//! box's projection, so the leaf is a candidate with that ray's bit (every test is widened
//! beyond rounding); a leaf is skipped only when its box cannot hold a point closer than the
//! hit already found. The closest root is therefore the same root as the single-ray traversal
//! finds (where two leaves hold the same root, at a seam, the order may pick the other leaf's
//! copy of it).

use glam::{DVec2, DVec3, Vec3A};
use obvhs::cwbvh::CwBvh;

use crate::render::bvh::Leaf;
use crate::render::ray::{Ray64, RayPlanes};

/// Pixels per side of the square block of primary rays traced as one bundle.
pub(crate) const BUNDLE_SIDE: u32 = 8;

/// The most candidate leaves per ray a bundle is traced with. Each ray skips the candidates
/// its direction misses by one bit test, but the walk and the masks cost about one traversal
/// per candidate, so a bundle whose cone meets more leaves than it has rays (a surface divided
/// finely compared with the pixels, seen whole) is traced ray by ray (measured on a
/// 327,680-face icosphere: bundles there cost 5–30 % more than single rays).
pub(crate) const MAX_CANDIDATES_PER_RAY: usize = 1;

/// The most rays of a bundle: one bit each in [`Candidate::rays`].
pub(crate) const MAX_BUNDLE_RAYS: usize = 64;

/// Bundles traced ray by ray without an attempt after one that met too many leaves: the
/// next blocks of the same region likely do too (the walk up to the limit is wasted there).
/// Measured (results/benchmarks.md, 2026-12-06): 7 against 15 keeps the 327,680-face
/// icosphere's render time (every bundle there declines) and traces the scanned bunny seen
/// close up 2–3 % faster, where one dense block otherwise stopped 15 good ones; 3 costs the
/// icosphere 2 %.
pub(crate) const SKIP_AFTER_DECLINE: u32 = 7;

/// The cosine below which a ray is too far from the bundle's mean direction for a cone
/// bounded by four planes: such bundles are traced ray by ray.
const MIN_COSINE: f64 = 0.25;

/// Relative widening of the cone's tangent bounds: covers the rounding of the directions'
/// projections (about 1e-16) many times over and costs nothing measurable in candidates.
const WIDEN: f64 = 1e-9;

/// The cone of a bundle's directions from its common origin: the points `p` with
/// `normals[i] · (p − origin) ≤ 0` for its four side planes and the plane through the origin
/// across its axis (which drops boxes behind the origin that straddle two side planes).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Cone {
    origin: DVec3,
    /// The frame `(a, b, axis)` in which a direction `d` has tangent coordinates
    /// `(d·a, d·b) / d·axis`.
    frame: [DVec3; 3],
    normals: [DVec3; 5],
}

impl Cone {
    /// The cone around unit directions `dirs` from `origin`, or `None` when it would not be
    /// narrower than a half-space (a direction more than ~75° from the mean) or a direction
    /// is not finite. `tangents` receives each direction's tangent coordinates.
    pub(crate) fn around(
        origin: DVec3,
        dirs: impl Iterator<Item = DVec3> + Clone,
        tangents: &mut Vec<DVec2>,
    ) -> Option<Cone> {
        tangents.clear();
        let axis = dirs.clone().sum::<DVec3>().normalize_or_zero();
        if axis == DVec3::ZERO || !axis.is_finite() || !origin.is_finite() {
            return None;
        }
        let (a, b) = axis.any_orthonormal_pair();
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for d in dirs {
            let along = d.dot(axis);
            if along.is_nan() || along < MIN_COSINE {
                return None;
            }
            let tangent = [d.dot(a) / along, d.dot(b) / along];
            for k in 0..2 {
                lo[k] = lo[k].min(tangent[k]);
                hi[k] = hi[k].max(tangent[k]);
            }
            tangents.push(DVec2::from(tangent));
        }
        let widen = |x: f64, outward: f64| x + outward * WIDEN * (1.0 + x.abs());
        let (lo, hi) = (lo.map(|x| widen(x, -1.0)), hi.map(|x| widen(x, 1.0)));
        // x ≤ hi·z, x ≥ lo·z (and the same for y) in the frame (a, b, axis) at the origin.
        Some(Cone {
            origin,
            frame: [a, b, axis],
            normals: [
                a - axis * hi[0],
                axis * lo[0] - a,
                b - axis * hi[1],
                axis * lo[1] - b,
                -axis,
            ],
        })
    }

    /// True when the leaf's oriented box (the points `q` with `lo ≤ axes · (q − corner) ≤ hi`,
    /// [`Leaf::ray_meets_box`]) lies wholly outside one of the cone's planes. The box's
    /// frame is orthonormal to f32 rounding; the margin covers that many times over.
    fn excludes_leaf(&self, leaf: &Leaf) -> bool {
        let (lo, hi) = (leaf.lo.as_dvec3(), leaf.hi.as_dvec3());
        let axes = leaf.axes.map(|a| a.as_dvec3());
        let offset = leaf.corners[0].as_dvec3() - self.origin;
        let margin =
            1e-6 * lo.abs().max(hi.abs()).max_element() + 1e-12 * offset.abs().max_element();
        self.normals.iter().any(|n| {
            let local = DVec3::new(axes[0].dot(*n), axes[1].dot(*n), axes[2].dot(*n));
            let corner = DVec3::select(local.cmplt(DVec3::ZERO), hi, lo);
            n.dot(offset) + local.dot(corner) > margin * n.length()
        })
    }

    /// The rays (bit `i` for `tangents[i]`) whose directions fall in the projection of the
    /// leaf's oriented box from the origin: the only rays of the bundle that can meet it. The
    /// box's corners are off by the frame's f32 rounding (well below `1e-6` of the box); the
    /// bounds of their projection are widened by that, so no ray meeting the box is left out.
    /// Every ray when the box reaches to the origin's plane across the axis.
    fn ray_mask(&self, leaf: &Leaf, tangents: &[DVec2]) -> u64 {
        let all = all_rays(tangents.len());
        let (lo, hi) = (leaf.lo.as_dvec3(), leaf.hi.as_dvec3());
        let axes = leaf.axes.map(|a| a.as_dvec3());
        let offset = leaf.corners[0].as_dvec3() - self.origin;
        let [a, b, axis] = self.frame;
        let error =
            1e-6 * lo.abs().max(hi.abs()).max_element() + 1e-12 * offset.abs().max_element();
        let (mut min, mut max) = (DVec2::INFINITY, DVec2::NEG_INFINITY);
        let mut nearest = f64::INFINITY;
        for corner in 0..8 {
            let pick = |bit: usize, k: usize| if corner & bit == 0 { lo[k] } else { hi[k] };
            let q = offset + axes[0] * pick(1, 0) + axes[1] * pick(2, 1) + axes[2] * pick(4, 2);
            let z = q.dot(axis);
            nearest = nearest.min(z);
            let t = DVec2::new(q.dot(a), q.dot(b)) / z;
            min = min.min(t);
            max = max.max(t);
        }
        let in_front = nearest > 2.0 * error && min.is_finite() && max.is_finite();
        if !in_front {
            return all;
        }
        // A corner moved by `error` moves its projection by at most about
        // `error · (1 + |t|) · √2 / (z − error)`.
        let reach = min.abs().max(max.abs()).max_element();
        let widen = 2.0 * error * (1.0 + reach) / (nearest - error) + WIDEN * (1.0 + reach);
        let (min, max) = (min - DVec2::splat(widen), max + DVec2::splat(widen));
        // Without short-circuits (`&`, not `&&`): no branch per ray, and the compiler
        // compares several rays per instruction.
        let mut mask = 0;
        for (i, t) in tangents.iter().enumerate().take(64) {
            let inside = (t.x >= min.x) & (t.x <= max.x) & (t.y >= min.y) & (t.y <= max.y);
            mask |= u64::from(inside) << i;
        }
        mask
    }

    /// A lower bound on the distance from the cone's origin to the leaf's oriented box, whose
    /// frame holds the origin at `local` ([`Leaf::box_coordinates`]).
    fn distance_to_leaf(&self, leaf: &Leaf, local: DVec3) -> f64 {
        let (lo, hi) = (leaf.lo.as_dvec3(), leaf.hi.as_dvec3());
        let q = self.origin - leaf.corners[0].as_dvec3();
        // The frame's rows are unit to f32 rounding: lengths in it are exact to ~1e-7.
        let outside = (local - local.clamp(lo, hi)).length();
        (outside * (1.0 - 1e-6) - 1e-12 * q.abs().max_element()).max(0.0)
    }

    /// True when the box `[lo, hi]` lies wholly outside one of the cone's planes (a
    /// conservative test: a box near the cone's edges may be kept though it misses it).
    fn excludes(&self, lo: DVec3, hi: DVec3) -> bool {
        let (lo, hi) = (lo - self.origin, hi - self.origin);
        let margin = 1e-12 * lo.abs().max(hi.abs()).max_element();
        self.normals.iter().any(|n| {
            // The box's corner furthest into the plane's inner side.
            let corner = DVec3::select(n.cmplt(DVec3::ZERO), hi, lo);
            n.dot(corner) > margin
        })
    }
}

/// The ray mask with a bit for each of `count` rays (every bit from [`MAX_BUNDLE_RAYS`] on).
pub(crate) fn all_rays(count: usize) -> u64 {
    match count {
        n if n >= MAX_BUNDLE_RAYS => u64::MAX,
        n => (1 << n) - 1,
    }
}

/// A leaf some ray of a bundle may meet.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Candidate {
    /// Leaf (primitive) index of the BVH.
    pub leaf: u32,
    /// A lower bound on the distance from the bundle's origin to the leaf's oriented box:
    /// no point of the leaf is closer to the origin, so no ray of the bundle meets it at a
    /// smaller `t`.
    pub near: f64,
    /// The rays of the bundle (bit `i` for ray `i`) that can meet the leaf's oriented box.
    pub rays: u64,
    /// The bundle's origin in the frame of the leaf's oriented box
    /// ([`Leaf::box_coordinates`]), shared by its rays' box tests
    /// ([`BoxFromOrigin`](crate::render::bvh::BoxFromOrigin)).
    pub origin_in_box: DVec3,
}

/// One ray of a bundle while its candidates are tested: the ray and its planes in the
/// tracer's unit frame and its interval, which ends at its closest hit so far.
#[derive(Clone, Copy, Debug)]
pub(crate) struct BundleRay {
    /// The ray, unit frame.
    pub ray: Ray64,
    /// Its two planes ([`RayPlanes::new`]).
    pub planes: RayPlanes,
    /// The start of its interval.
    pub t_min: f64,
    /// The end of its interval: the distance of its closest hit so far.
    pub best_t: f64,
}

/// Buffers a worker reuses from bundle to bundle, and how many coming bundles skip the
/// attempt (after one met too many leaves, [`SKIP_AFTER_DECLINE`]).
#[derive(Debug, Default)]
pub struct BundleScratch {
    stack: Vec<u32>,
    pub(crate) tangents: Vec<DVec2>,
    pub(crate) candidates: Vec<Candidate>,
    pub(crate) bundle_rays: Vec<BundleRay>,
    skip: u32,
}

/// Fills `scratch.candidates` with every leaf of `bvh` (leaf data `leaves`) whose BVH box and
/// oriented box reach into `cone`, sorted by distance from the cone's origin to the oriented
/// box (then by index: the order does not depend on the walk). False, and the candidates
/// incomplete, when there are more than `limit` (the next [`SKIP_AFTER_DECLINE`] calls then
/// return false at once).
pub(crate) fn gather(
    bvh: &CwBvh,
    leaves: &[Leaf],
    cone: &Cone,
    limit: usize,
    scratch: &mut BundleScratch,
) -> bool {
    if scratch.skip > 0 {
        scratch.skip -= 1;
        return false;
    }
    let BundleScratch {
        stack,
        tangents,
        candidates,
        ..
    } = scratch;
    stack.clear();
    candidates.clear();
    if bvh.nodes.is_empty() {
        return true;
    }
    stack.push(0);
    while let Some(index) = stack.pop() {
        let node = &bvh.nodes[index as usize];
        for child in 0..8 {
            if node.is_child_empty(child) {
                continue;
            }
            let aabb = node.child_aabb(child);
            let (lo, hi) = (dvec(aabb.min), dvec(aabb.max));
            if cone.excludes(lo, hi) {
                continue;
            }
            if !node.is_leaf(child) {
                stack.push(node.child_node_index(child));
                continue;
            }
            let (first, count) = node.child_primitives(child);
            for index in first..first + count {
                let leaf = &leaves[index as usize];
                if cone.excludes_leaf(leaf) {
                    continue;
                }
                if candidates.len() == limit {
                    scratch.skip = SKIP_AFTER_DECLINE;
                    return false;
                }
                let rays = cone.ray_mask(leaf, tangents);
                if rays == 0 {
                    continue;
                }
                let origin_in_box = leaf.box_coordinates(cone.origin);
                candidates.push(Candidate {
                    leaf: index,
                    near: cone.distance_to_leaf(leaf, origin_in_box),
                    rays,
                    origin_in_box,
                });
            }
        }
    }
    candidates.sort_unstable_by(|a, b| a.near.total_cmp(&b.near).then(a.leaf.cmp(&b.leaf)));
    true
}

fn dvec(v: Vec3A) -> DVec3 {
    DVec3::new(f64::from(v.x), f64::from(v.y), f64::from(v.z))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A box is excluded only when it lies outside the cone: boxes around points on every ray
    /// of the bundle are kept, boxes beside or behind the origin are dropped.
    #[test]
    fn the_cone_keeps_every_box_its_rays_meet() {
        let origin = DVec3::new(0.3, -0.2, 5.0);
        let dirs: Vec<DVec3> = (0..8)
            .flat_map(|i| (0..8).map(move |j| (i, j)))
            .map(|(i, j)| DVec3::new(0.01 * f64::from(i), 0.013 * f64::from(j), -1.0).normalize())
            .collect();
        let cone =
            Cone::around(origin, dirs.iter().copied(), &mut Vec::new()).expect("narrow bundle");
        for d in &dirs {
            for t in [1e-3, 0.5, 3.0, 1e4] {
                let p = origin + *d * t;
                // A box touching the ray at one corner only.
                assert!(!cone.excludes(p, p + DVec3::splat(1e-9)), "{d} at {t}");
                assert!(!cone.excludes(p - DVec3::splat(1e-9), p), "{d} at {t}");
            }
        }
        let behind = origin + DVec3::Z;
        assert!(cone.excludes(behind - DVec3::splat(0.1), behind + DVec3::splat(0.1)));
        let beside = origin + DVec3::new(2.0, 0.0, -1.0);
        assert!(cone.excludes(beside - DVec3::splat(0.1), beside + DVec3::splat(0.1)));
        // Directions spanning more than a half-space have no such cone.
        let wide = [DVec3::X, -DVec3::X, DVec3::Z];
        assert!(Cone::around(origin, wide.iter().copied(), &mut Vec::new()).is_none());
    }
}
