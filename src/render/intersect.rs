//! Ray–patch intersection: BVH traversal in f32 with an f64 Newton solve per leaf.
//!
//! The ray `o + t d` is written as the intersection of two planes `n1·x = n1·o`,
//! `n2·x = n2·o` with `n1, n2 ⟂ d`, so a hit is a root of the 2×2 system
//! `F(u, v) = (n1·(S(u,v) − o), n2·(S(u,v) − o)) = 0` and `t = (S − o)·d` follows. Newton
//! runs in the leaf's own barycentrics `(s, t)` on the leaf's power form (see
//! [`crate::render::evaluate::local_point_and_tangents`]), specialised to the patch degree, and
//! starts where the ray meets the plane of the leaf's corners; a root is accepted when it lies in the leaf's sub-triangle
//! grown by [`NewtonSettings::domain_tolerance`] (so a ray through a seam between two leaves is
//! found by at least one of them). When Newton neither converges nor leaves the leaf (singular
//! Jacobian, oscillation), the leaf is split into four recursively and Newton retried from each
//! child whose control-net box the ray enters: seams never leak rays.
//!
//! The traversal closure only finds `(t, patch, u, v)`; full geometry is evaluated once for the
//! closest hit by the caller.

use glam::{DVec2, DVec3, Vec3A};
use obvhs::cwbvh::CwBvh;
use obvhs::ray::{Ray, RayHit};

use crate::geom::Aabb;
use crate::render::bvh::{Leaf, PatchBvh, SubdivisionCriterion, barycentric_in, split4};
use crate::render::evaluate::{
    local_point_and_tangents, point_and_tangents, second_derivative_bound,
};
use crate::render::modes::overlay::face_edge_mask;
pub use crate::render::ray::{Ray64, RayPlanes, ray_enters_box};
use crate::surface::{Patch, Surface};

/// The cheap result of the hit test: which patch, where in its domain, how far.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance along the ray.
    pub t: f64,
    /// Patch index in [`Surface::patches`].
    pub patch: u32,
    /// Patch parameter u (barycentric `(1−u−v, u, v)`).
    pub u: f64,
    /// Patch parameter v.
    pub v: f64,
}

/// Tunables of the per-leaf Newton solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonSettings {
    /// Iteration cap of one Newton run; beyond it the run counts as a failure.
    pub max_iterations: u32,
    /// Distance from the ray (relative to the scene's bounding-box diagonal) at which a root
    /// is accepted; [`Tracer::root_tolerance`] adds a few hundred ulps of the coordinates for
    /// scenes far from the origin. 1e-10 is ten times below the 1e-9 hit-accuracy contract and
    /// well above f64 evaluation noise, so Newton never stalls on rounding.
    pub residual_tolerance: f64,
    /// How far (in leaf-local barycentric units) outside its sub-triangle a root is still
    /// accepted, so that rays through seams are caught by both neighbours.
    pub domain_tolerance: f64,
    /// An iterate further than this (leaf-local barycentric units) outside the leaf means the
    /// ray meets the surface elsewhere: the run stops without counting as a failure. Valid
    /// because leaves are flat with a narrow normal cone, so the first Newton step is close to
    /// the planar intersection.
    pub escape_distance: f64,
    /// Levels of 4-splitting tried after a failed run.
    pub fallback_depth: u32,
}

impl Default for NewtonSettings {
    fn default() -> Self {
        NewtonSettings {
            max_iterations: 8,
            residual_tolerance: 1e-10,
            domain_tolerance: 1e-7,
            escape_distance: 1.0,
            fallback_depth: 4,
        }
    }
}

/// Counters of one worker, summed in a fixed order afterwards (integers: exact, deterministic).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct IntersectCounters {
    /// Newton runs started from a leaf centroid.
    pub newton_runs: u64,
    /// Runs whose root was accepted inside their leaf.
    pub roots_accepted: u64,
    /// Sum of iterations of accepted runs.
    pub accepted_iterations: u64,
    /// Largest iteration count of an accepted run.
    pub accepted_iterations_max: u32,
    /// Runs that neither converged nor left the leaf (the fallback subdivision then searched
    /// the leaf). Most are rays that miss the leaf while Newton wanders in the polynomial's
    /// extension near it.
    pub newton_unconverged: u64,
    /// Real Newton failures: unconverged runs where the fallback then found a root in the leaf
    /// (Newton missed a hit that exists).
    pub newton_failures: u64,
    /// Roots found by the fallback subdivision (one per real failure).
    pub fallback_roots: u64,
    /// Extra Newton runs from the corner-child centroids of a leaf after a grazing ray's run
    /// from the centroid found no root in the leaf (see [`GRAZING_RESTARTS`]).
    pub grazing_restarts: u64,
}

impl IntersectCounters {
    /// Adds `other` into `self`.
    pub fn add(&mut self, other: &IntersectCounters) {
        self.newton_runs += other.newton_runs;
        self.roots_accepted += other.roots_accepted;
        self.accepted_iterations += other.accepted_iterations;
        self.accepted_iterations_max = self
            .accepted_iterations_max
            .max(other.accepted_iterations_max);
        self.newton_unconverged += other.newton_unconverged;
        self.newton_failures += other.newton_failures;
        self.fallback_roots += other.fallback_roots;
        self.grazing_restarts += other.grazing_restarts;
    }
}

/// A surface ready for ray queries: the patches and their BVH.
pub struct Tracer<'s> {
    /// The surface.
    pub surface: &'s Surface,
    /// Its BVH.
    pub bvh: PatchBvh,
    /// Newton tunables.
    pub newton: NewtonSettings,
    /// Absolute root tolerance: see [`Tracer::root_tolerance`].
    pub tolerance: f64,
    /// Bounding box of the surface.
    pub bounds: Aabb,
    /// Per patch, which edges lie on mesh-face edges (for the boundary overlay).
    pub face_edges: Vec<u8>,
    /// Per patch, a bound on |∂²S/∂δ²| for unit `(u, v)` directions δ (see
    /// [`second_derivative_bound`]); infinite when unknown.
    pub second_bounds: Vec<f64>,
}

/// Outcome of one Newton run.
enum Newton {
    /// Converged to `(u, v)` (leaf-local `(s, t)` for a leaf run) after `iterations` steps, at surface point `p`.
    Root(DVec2, u32, DVec3),
    /// The iterate left the leaf: the ray meets the surface elsewhere (or not at all).
    Escaped,
    /// Neither: singular Jacobian, non-finite values or the iteration cap.
    Failed,
}

impl<'s> Tracer<'s> {
    /// Builds the BVH of `surface` with `criterion`.
    pub fn new(
        surface: &'s Surface,
        criterion: &SubdivisionCriterion,
        newton: NewtonSettings,
    ) -> crate::Result<Tracer<'s>> {
        let bvh = PatchBvh::build(surface, criterion)?;
        let bounds = surface.bounds();
        let magnitude = bounds.min.abs().max(bounds.max.abs()).max_element();
        let tolerance =
            newton.residual_tolerance * bounds.diagonal() + 256.0 * f64::EPSILON * magnitude;
        Ok(Tracer {
            surface,
            bvh,
            newton,
            tolerance,
            bounds,
            face_edges: surface.patches.iter().map(face_edge_mask).collect(),
            second_bounds: surface
                .patches
                .iter()
                .map(|p| p.as_bezier().map_or(f64::INFINITY, second_derivative_bound))
                .collect(),
        })
    }

    /// [`Tracer::new`] with the default subdivision criterion and Newton settings (those of
    /// `smoothlab render` without scene overrides).
    pub fn with_default_settings(surface: &'s Surface) -> crate::Result<Tracer<'s>> {
        Tracer::new(
            surface,
            &SubdivisionCriterion::default(),
            NewtonSettings::default(),
        )
    }

    /// Largest distance of an accepted root from its ray:
    /// `residual_tolerance × diagonal + 256 ε × max |coordinate|`.
    pub fn root_tolerance(&self) -> f64 {
        self.tolerance
    }

    /// The closest hit with `t ∈ (t_min, t_max)`, or None.
    pub fn closest_hit(
        &self,
        ray: &Ray64,
        t_min: f64,
        t_max: f64,
        counters: &mut IntersectCounters,
    ) -> Option<Hit> {
        let planes = RayPlanes::new(ray);
        closest_in_bvh(
            &self.bvh.bvh,
            self.bvh.padding,
            ray,
            t_min,
            t_max,
            |id, best_t| {
                self.intersect_leaf(&self.bvh.leaves[id], ray, &planes, t_min, best_t, counters)
            },
        )
    }

    /// The closest hit by testing every leaf (no BVH): the reference for tests.
    pub fn closest_hit_brute_force(
        &self,
        ray: &Ray64,
        t_min: f64,
        t_max: f64,
        counters: &mut IntersectCounters,
    ) -> Option<Hit> {
        let planes = RayPlanes::new(ray);
        let mut best: Option<Hit> = None;
        let mut best_t = t_max;
        for leaf in &self.bvh.leaves {
            if let Some(hit) = self.intersect_leaf(leaf, ray, &planes, t_min, best_t, counters) {
                best_t = hit.t;
                best = Some(hit);
            }
        }
        best
    }

    /// The hit of `ray` with one leaf, if it lies in `(t_min, t_max)`.
    pub fn intersect_leaf(
        &self,
        leaf: &Leaf,
        ray: &Ray64,
        planes: &RayPlanes,
        t_min: f64,
        t_max: f64,
        counters: &mut IntersectCounters,
    ) -> Option<Hit> {
        if !leaf.ray_meets_box(ray.origin, ray.dir, t_min, t_max) {
            return None;
        }
        let patch = &self.surface.patches[leaf.patch as usize];
        let tri = leaf.tri();
        let (start, grazing) = match planar_start(leaf, ray, START_REJECTION) {
            Start::Outside => return None,
            Start::At(st) => (st, false),
            Start::Grazing => (DVec2::splat(1.0 / 3.0), true),
        };
        counters.newton_runs += 1;
        let mut run = self.solve_leaf(leaf, tri, start, planes);
        if grazing && !self.root_in_leaf(&run) {
            // A grazing ray may meet a flat piece twice, with the two roots close together
            // (a silhouette): Newton from the centroid can settle on the one outside the leaf
            // or fail. Restarting from the corner children's centroids finds the root inside.
            // Only the centroid run's failure sends the leaf to the fallback: a restart from a
            // corner that fails mostly wanders off a grazing ray that misses the piece.
            let mut failed = matches!(run, Newton::Failed);
            for restart in GRAZING_RESTARTS {
                counters.newton_runs += 1;
                counters.grazing_restarts += 1;
                let retry = self.solve_leaf(leaf, tri, restart, planes);
                if self.root_in_leaf(&retry) {
                    run = retry;
                    failed = false;
                    break;
                }
            }
            if failed {
                run = Newton::Failed;
            }
        }
        match run {
            Newton::Root(st, iterations, p) => {
                let hit = self.accept_local(leaf, st, p, ray, t_min, t_max)?;
                counters.roots_accepted += 1;
                counters.accepted_iterations += u64::from(iterations);
                counters.accepted_iterations_max = counters.accepted_iterations_max.max(iterations);
                Some(hit)
            }
            Newton::Escaped => None,
            Newton::Failed => {
                counters.newton_unconverged += 1;
                let hit = self.fallback(
                    leaf.patch,
                    patch,
                    tri,
                    ray,
                    planes,
                    t_min,
                    t_max,
                    self.newton.fallback_depth,
                );
                if hit.is_some() {
                    counters.newton_failures += 1;
                    counters.fallback_roots += 1;
                }
                hit
            }
        }
    }

    /// One Newton run in `leaf` from the leaf-local `start`, on the leaf's power form when it
    /// has one (degree dispatched once per run, not per evaluation); roots in leaf-local `(s, t)`.
    fn solve_leaf(&self, leaf: &Leaf, tri: [DVec2; 3], start: DVec2, planes: &RayPlanes) -> Newton {
        match leaf.degree {
            1 => self.newton_local::<1>(leaf, start, planes),
            2 => self.newton_local::<2>(leaf, start, planes),
            3 => self.newton_local::<3>(leaf, start, planes),
            4 => self.newton_local::<4>(leaf, start, planes),
            5 => self.newton_local::<5>(leaf, start, planes),
            6 => self.newton_local::<6>(leaf, start, planes),
            // No power form: Newton on the whole patch, the root mapped back to the leaf.
            _ => match self.newton(leaf.patch, tri, leaf.patch_uv(start.x, start.y), planes) {
                Newton::Root(uv, iterations, p) => {
                    let local = barycentric_in(tri, uv);
                    Newton::Root(DVec2::new(local.y, local.z), iterations, p)
                }
                other => other,
            },
        }
    }

    /// True if `run` converged to a root inside the leaf grown by the domain tolerance.
    fn root_in_leaf(&self, run: &Newton) -> bool {
        match run {
            Newton::Root(st, ..) => {
                st.x.min(st.y).min(1.0 - st.x - st.y) >= -self.newton.domain_tolerance
            }
            _ => false,
        }
    }

    /// Recursive 4-split of a leaf domain whose Newton run failed: each child the ray's box
    /// test admits is retried from its own centroid. Only runs on failures, so the allocation in
    /// [`Patch::bounds`] stays out of the common path.
    #[allow(clippy::too_many_arguments)]
    fn fallback(
        &self,
        patch_index: u32,
        patch: &Patch,
        tri: [DVec2; 3],
        ray: &Ray64,
        planes: &RayPlanes,
        t_min: f64,
        t_max: f64,
        depth: u32,
    ) -> Option<Hit> {
        if depth == 0 {
            return None;
        }
        let mut best: Option<Hit> = None;
        let mut best_t = t_max;
        for child in split4(tri) {
            let bounds = patch.bounds(child);
            if !ray_enters_box(ray, &bounds, self.bvh.padding, t_min, best_t) {
                continue;
            }
            let centroid = (child[0] + child[1] + child[2]) / 3.0;
            let found = match self.newton(patch_index, child, centroid, planes) {
                Newton::Root(uv, _, p) => {
                    self.accept(patch_index, child, uv, p, ray, t_min, best_t)
                }
                Newton::Escaped => None,
                Newton::Failed => self.fallback(
                    patch_index,
                    patch,
                    child,
                    ray,
                    planes,
                    t_min,
                    best_t,
                    depth - 1,
                ),
            };
            if let Some(hit) = found {
                best_t = hit.t;
                best = Some(hit);
            }
        }
        best
    }

    /// Newton on the two-plane system from `start`, for a root in the sub-triangle `tri`.
    fn newton(
        &self,
        patch_index: u32,
        tri: [DVec2; 3],
        start: DVec2,
        planes: &RayPlanes,
    ) -> Newton {
        let patch = &self.surface.patches[patch_index as usize];
        let second_bound = 2.0 * self.second_bounds[patch_index as usize];
        let settings = &self.newton;
        let tolerance = self.tolerance;
        let mut uv = start;
        let mut iterations = 0;
        loop {
            let (p, su, sv) = point_and_tangents(patch, uv.x, uv.y);
            let f = planes.residual(p);
            if !f.is_finite() {
                return Newton::Failed;
            }
            if f.length() <= tolerance {
                return Newton::Root(uv, iterations, p);
            }
            if iterations == settings.max_iterations {
                return Newton::Failed;
            }
            let Some(step) = planes.newton_step(f, su, sv) else {
                return Newton::Failed;
            };
            uv -= step;
            iterations += 1;
            // Taylor: after an exact Newton step the residual is at most ½ M |Δ|² (M bounds
            // the second derivatives on the patch), and so is the error of the linearised
            // point. When that is below tolerance the step is the last one and no further
            // evaluation is needed. Only inside the patch domain, where M is valid.
            let taylor = 0.5 * second_bound * step.length_squared();
            if taylor <= tolerance && uv.x >= 0.0 && uv.y >= 0.0 && uv.x + uv.y <= 1.0 {
                let p_new = p - su * step.x - sv * step.y;
                return Newton::Root(uv, iterations, p_new);
            }
            let local = barycentric_in(tri, uv);
            if local.min_element() < -settings.escape_distance {
                return Newton::Escaped;
            }
        }
    }

    /// Newton on the two-plane system in the leaf-local barycentrics `(s, t)` of `leaf`, on its
    /// degree-`D` power form, from `start`. The Taylor stop uses the leaf's own
    /// second-derivative bound, valid only inside the leaf, so it applies only to steps that
    /// start and end there (the leaf triangle is convex).
    fn newton_local<const D: usize>(
        &self,
        leaf: &Leaf,
        start: DVec2,
        planes: &RayPlanes,
    ) -> Newton {
        let coefficients = &self.bvh.power[leaf.power as usize..];
        let second_bound = 2.0 * leaf.second_bound;
        let settings = &self.newton;
        let tolerance = self.tolerance;
        let inside = |st: DVec2| st.x >= 0.0 && st.y >= 0.0 && st.x + st.y <= 1.0;
        let mut st = start;
        let mut iterations = 0;
        let mut previous = f64::INFINITY;
        loop {
            let (p, ss, tt) = local_point_and_tangents::<D>(coefficients, st.x, st.y);
            let f = planes.residual(p);
            if !f.is_finite() {
                return Newton::Failed;
            }
            let residual = f.length_squared();
            if residual <= tolerance * tolerance {
                return Newton::Root(st, iterations, p);
            }
            // Past the iteration cap a run goes on (up to twice the cap) only while every step
            // at least halves the residual: near an almost double root (a silhouette) Newton
            // converges linearly, steadily but slower than quadratically.
            if iterations >= settings.max_iterations
                && (iterations >= 2 * settings.max_iterations || residual > 0.25 * previous)
            {
                return Newton::Failed;
            }
            previous = residual;
            let Some(step) = planes.newton_step(f, ss, tt) else {
                return Newton::Failed;
            };
            let was_inside = inside(st);
            st -= step;
            iterations += 1;
            // Taylor: after an exact Newton step the residual, and the error of the linearised
            // point, are at most ½ M |Δ|²; below tolerance no further evaluation is needed.
            let taylor = 0.5 * second_bound * step.length_squared();
            if taylor <= tolerance && was_inside && inside(st) {
                return Newton::Root(st, iterations, p - ss * step.x - tt * step.y);
            }
            if st.x.min(st.y).min(1.0 - st.x - st.y) < -settings.escape_distance {
                return Newton::Escaped;
            }
        }
    }

    /// A leaf-local root `(s, t)` as a hit, if it lies in the leaf grown by the domain tolerance
    /// and its distance is in `(t_min, t_max)`.
    fn accept_local(
        &self,
        leaf: &Leaf,
        st: DVec2,
        p: DVec3,
        ray: &Ray64,
        t_min: f64,
        t_max: f64,
    ) -> Option<Hit> {
        if st.x.min(st.y).min(1.0 - st.x - st.y) < -self.newton.domain_tolerance {
            return None;
        }
        let t = (p - ray.origin).dot(ray.dir);
        if t > t_min && t < t_max {
            let uv = leaf.patch_uv(st.x, st.y);
            Some(Hit {
                t,
                patch: leaf.patch,
                u: uv.x,
                v: uv.y,
            })
        } else {
            None
        }
    }

    /// A converged root as a hit, if it lies in the sub-triangle `tri` grown by the domain
    /// tolerance and its distance is in `(t_min, t_max)`.
    #[allow(clippy::too_many_arguments)]
    fn accept(
        &self,
        patch_index: u32,
        tri: [DVec2; 3],
        uv: DVec2,
        p: DVec3,
        ray: &Ray64,
        t_min: f64,
        t_max: f64,
    ) -> Option<Hit> {
        if !in_grown_triangle(tri, uv, self.newton.domain_tolerance) {
            return None;
        }
        let t = (p - ray.origin).dot(ray.dir);
        if t > t_min && t < t_max {
            Some(Hit {
                t,
                patch: patch_index,
                u: uv.x,
                v: uv.y,
            })
        } else {
            None
        }
    }
}

/// Where Newton starts in a leaf.
enum Start {
    /// At these leaf-local barycentrics `(s, t)`: where the ray meets the plane of the leaf's
    /// corner points.
    At(DVec2),
    /// The ray meets the corner plane further than the escape distance outside the leaf: it
    /// cannot meet this flat piece (no evaluation needed).
    Outside,
    /// The ray runs within ~6° of the corner plane, where the planar guess is unreliable:
    /// start at the centroid and let Newton decide.
    Grazing,
}

/// The start point of Newton in `leaf` (see [`Start`]). The leaf is flat to a few percent of
/// its size with a narrow normal cone, so the planar intersection is within that flatness of
/// the true root, one Newton step closer than the centroid; the early rejection needs a margin
/// of at least flatness / tan(angle to the plane), which `escape` covers for every ray steeper
/// than the grazing limit ([`START_REJECTION`]).
fn planar_start(leaf: &Leaf, ray: &Ray64, escape: f64) -> Start {
    let [a, b, c] = leaf.corners.map(|p| p.as_dvec3());
    let (e1, e2) = (b - a, c - a);
    let normal = e1.cross(e2);
    let along = ray.dir.dot(normal);
    let len = normal.length();
    if along.is_nan() || along.abs() <= GRAZING_COS * len {
        return Start::Grazing;
    }
    // Möller–Trumbore barycentrics of the ray–plane point.
    let pvec = ray.dir.cross(e2);
    let det = e1.dot(pvec);
    let tvec = ray.origin - a;
    let b1 = tvec.dot(pvec) / det;
    let qvec = tvec.cross(e1);
    let b2 = ray.dir.dot(qvec) / det;
    let b0 = 1.0 - b1 - b2;
    if b0.min(b1).min(b2) < -escape || !b1.is_finite() || !b2.is_finite() {
        return Start::Outside;
    }
    Start::At(DVec2::new(b1, b2))
}

/// The closest of the hits `hit_of(primitive, t_max so far)` over the primitives of `bvh` whose
/// boxes the ray enters, with `t ∈ (t_min, t_max)`: the traversal shared by the exact and the
/// tessellated tracer.
///
/// The BVH is f32, so the traversal ray's interval is widened by `padding` (see
/// [`crate::render::bvh::box_padding`]) and every closer hit shrinks it to `t + padding`,
/// rounded to f32: rounding of t never culls a box that may still hold a closer f64 hit.
pub(crate) fn closest_in_bvh(
    bvh: &CwBvh,
    padding: f64,
    ray: &Ray64,
    t_min: f64,
    t_max: f64,
    mut hit_of: impl FnMut(usize, f64) -> Option<Hit>,
) -> Option<Hit> {
    // `+ 0.0` turns −0.0 into +0.0: obvhs picks the slab order from `d < 0` but the
    // inverse direction from the sign bit, and the two disagree on −0.0.
    let traversal = Ray::new(
        ray.origin.as_vec3a(),
        ray.dir.as_vec3a() + Vec3A::ZERO,
        (t_min - padding).max(0.0) as f32,
        if t_max.is_finite() {
            (t_max + padding) as f32
        } else {
            f32::INFINITY
        },
    );
    let mut best: Option<Hit> = None;
    let mut best_t = t_max;
    let mut record = RayHit::none();
    bvh.ray_traverse(traversal, &mut record, |_, id| match hit_of(id, best_t) {
        Some(hit) => {
            best_t = hit.t;
            best = Some(hit);
            (hit.t + padding) as f32
        }
        None => f32::INFINITY,
    });
    best
}

/// Leaf-local start points tried after a grazing ray's run from the centroid found no root in
/// the leaf: the centroids of the three corner children of the leaf's 4-split.
const GRAZING_RESTARTS: [DVec2; 3] = [
    DVec2::new(1.0 / 6.0, 1.0 / 6.0),
    DVec2::new(2.0 / 3.0, 1.0 / 6.0),
    DVec2::new(1.0 / 6.0, 2.0 / 3.0),
];

/// Cosine of the angle between ray and corner-plane normal below which a ray counts as grazing
/// (about 11.5° from the plane).
const GRAZING_COS: f64 = 0.2;

/// How far (leaf-local barycentric units) outside its leaf a ray may meet the corner plane and
/// still be tried. A root in the leaf lies within flatness / tan(angle to plane) ≤ 0.05 / 0.2 =
/// 0.25 leaf sizes of the plane point for the default criterion, so 0.5 leaves a factor two.
const START_REJECTION: f64 = 0.5;

/// Where a leaf's root must lie: its sub-triangle grown by `tolerance` (leaf-local units).
pub fn in_grown_triangle(tri: [DVec2; 3], uv: DVec2, tolerance: f64) -> bool {
    barycentric_in(tri, uv).min_element() >= -tolerance
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::fixtures::{height_field_patch, octahedron_sphere};
    use crate::render::sampler::{sphere_direction, uniform};

    /// Every sampled point of a leaf's sub-patch lies in its oriented box.
    #[test]
    fn oriented_boxes_contain_their_sub_patches() {
        let surface = octahedron_sphere(4, 1.0, 1);
        let tracer = Tracer::with_default_settings(&surface).expect("tracer");
        for leaf in &tracer.bvh.leaves {
            let patch = &surface.patches[leaf.patch as usize];
            let tri = leaf.tri();
            for k in 0..30u64 {
                let a = uniform(5, k, 0, 0);
                let b = uniform(5, k, 0, 1) * (1.0 - a);
                let uv = tri[0] * (1.0 - a - b) + tri[1] * a + tri[2] * b;
                let p = patch.eval(uv.x, uv.y);
                // A zero-length ray at p meets the box iff p is inside.
                assert!(
                    leaf.ray_meets_box(p, DVec3::X, 0.0, 0.0),
                    "point {p} outside its leaf box"
                );
            }
        }
    }

    /// Vertical rays on a height field whose x, y are exactly u, v: the exact hit is known.
    #[test]
    fn vertical_rays_hit_the_height_field_exactly() {
        let surface = height_field_patch();
        let tracer = Tracer::with_default_settings(&surface).expect("tracer");
        let mut counters = IntersectCounters::default();
        let mut worst = 0.0_f64;
        for i in 0..2000u64 {
            let x = uniform(3, i, 0, 0);
            let y = uniform(3, i, 0, 1) * (1.0 - x);
            let ray = Ray64::new(DVec3::new(x, y, 5.0), -DVec3::Z);
            let hit = tracer
                .closest_hit(&ray, 0.0, f64::INFINITY, &mut counters)
                .unwrap_or_else(|| panic!("ray {i} at ({x}, {y}) missed"));
            let exact_t = 5.0 - surface.patches[0].eval(x, y).z;
            worst = worst
                .max((hit.u - x).abs())
                .max((hit.v - y).abs())
                .max((hit.t - exact_t).abs() / exact_t);
        }
        assert!(
            worst <= 1e-12,
            "largest parameter / relative t error {worst:e}"
        );
        assert_eq!(counters.newton_failures, 0, "{counters:?}");
    }

    /// Rays from inside a closed surface cannot escape: every one hits, including those through
    /// seams between leaves and between patches.
    #[test]
    fn closed_surface_is_watertight_from_inside() {
        let surface = octahedron_sphere(3, 1.0, 1);
        let tracer = Tracer::with_default_settings(&surface).expect("tracer");
        let mut counters = IntersectCounters::default();
        let mut misses = 0;
        let rays = 20_000u64;
        for i in 0..rays {
            let origin = DVec3::new(0.11, -0.07, 0.05) * (i % 5) as f64;
            let ray = Ray64::new(origin, sphere_direction(11, i));
            if tracer
                .closest_hit(&ray, 0.0, f64::INFINITY, &mut counters)
                .is_none()
            {
                misses += 1;
            }
        }
        assert_eq!(misses, 0, "{misses} of {rays} rays escaped; {counters:?}");
        // Rays aimed exactly at patch corners and edge midpoints (the seams themselves).
        for face in crate::render::fixtures::octahedron_faces() {
            for target in [
                face[0],
                0.5 * (face[0] + face[1]),
                (face[0] + face[1] + face[2]) / 3.0,
            ] {
                let ray = Ray64::new(DVec3::ZERO, target);
                assert!(
                    tracer
                        .closest_hit(&ray, 0.0, f64::INFINITY, &mut counters)
                        .is_some(),
                    "seam ray towards {target} escaped"
                );
            }
        }
    }

    /// The BVH's closest hit is the brute-force closest hit over all leaves.
    #[test]
    fn closest_hit_equals_brute_force() {
        let surface = octahedron_sphere(4, 1.3, 1);
        let tracer = Tracer::with_default_settings(&surface).expect("tracer");
        let mut counters = IntersectCounters::default();
        let (mut hits, mut t_sum_bvh, mut t_sum_brute) = (0, 0.0, 0.0);
        for i in 0..3000u64 {
            let origin = sphere_direction(5, i) * 3.0;
            let towards = sphere_direction(6, i) * 0.9;
            let ray = Ray64::new(origin, towards - origin);
            let fast = tracer.closest_hit(&ray, 0.0, f64::INFINITY, &mut counters);
            let slow = tracer.closest_hit_brute_force(&ray, 0.0, f64::INFINITY, &mut counters);
            match (fast, slow) {
                (None, None) => {}
                (Some(a), Some(b)) => {
                    hits += 1;
                    t_sum_bvh += a.t;
                    t_sum_brute += b.t;
                    assert!((a.t - b.t).abs() <= 1e-12 * b.t, "ray {i}: {a:?} vs {b:?}");
                    let (pa, pb) = (
                        surface.patches[a.patch as usize].eval(a.u, a.v),
                        surface.patches[b.patch as usize].eval(b.u, b.v),
                    );
                    assert!((pa - pb).length() <= 1e-12, "ray {i}: {pa} vs {pb}");
                }
                (a, b) => panic!("ray {i}: BVH {a:?}, brute force {b:?}"),
            }
        }
        assert!(hits > 2000, "most rays aim inside the sphere: {hits}");
        assert!((t_sum_bvh - t_sum_brute).abs() <= 1e-12 * t_sum_brute);
    }

    /// Every accepted hit lies on its ray and on its patch, far below the 1e-9 × diagonal
    /// budget, and Newton converges in few iterations from the leaf centroids.
    #[test]
    fn hits_lie_on_ray_and_patch() {
        let surface = octahedron_sphere(5, 2.0, 1);
        let tracer = Tracer::with_default_settings(&surface).expect("tracer");
        let diag = surface.bounds().diagonal();
        let mut counters = IntersectCounters::default();
        let mut worst = 0.0_f64;
        for i in 0..5000u64 {
            let origin = sphere_direction(8, i) * 6.0;
            let ray = Ray64::new(origin, sphere_direction(9, i) * 1.5 - origin);
            if let Some(hit) = tracer.closest_hit(&ray, 0.0, f64::INFINITY, &mut counters) {
                let p = surface.patches[hit.patch as usize].eval(hit.u, hit.v);
                worst = worst.max((p - ray.at(hit.t)).length() / diag);
            }
        }
        // Newton stops at a residual of `root_tolerance()`; that is the guarantee, and it is
        // below the contract of 1e-9 × diagonal.
        let bound = tracer.root_tolerance() / diag;
        assert!(bound < 1e-9, "{bound}");
        assert!(
            worst <= bound,
            "largest hit-to-ray distance {worst:e} × diagonal > {bound:e}"
        );
        let mean = counters.accepted_iterations as f64 / counters.roots_accepted as f64;
        assert!(mean <= 3.0, "mean Newton iterations {mean}; {counters:?}");
        assert!(counters.accepted_iterations_max <= 8, "{counters:?}");
        assert_eq!(counters.newton_failures, 0, "{counters:?}");
    }
}
