//! Certified Newton on one piece of a patch: the ray–piece root is found, or its absence is
//! proved, or the run says it cannot tell.
//!
//! A piece is a sub-triangle of a patch's domain in its own barycentrics `(s, t)` (the unit
//! triangle `T`), with three bounds computed from its control nets ([`PieceBounds`]). The ray
//! `o + t d` is the intersection of two planes ([`RayPlanes`]), so a hit is a root of
//! `F(s, t) = P (S(s, t) − o) = 0` (`P`: the projection onto the planes' normals).
//!
//! Two facts decide that a piece holds no root, so that a ray reported as a miss is a real miss:
//! - **Affine start** ([`planar_start`]). `|S − A| ≤ δ` on `T` for the affine map `A` of the
//!   corners, so a root `x*` satisfies `|x* − x₀| ≤ r_A / cos θ` where `x₀` is the ray's meeting
//!   point with the corner plane and `r_A` = [`Leaf::affine_radius`](crate::render::bvh::Leaf):
//!   a ray meeting the plane further than that outside `T` cannot meet the piece.
//! - **Newton's error bound** ([`newton`]). With `M` bounding `|D²S(a, b)|` for unit directions on
//!   `T` (polarisation of the bound on `|D²S(δ, δ)|`), `F(x) − F(x*) = J̄ (x − x*)` with
//!   `|J(x) − J̄| ≤ M |x − x*| / 2`, so the Newton target `x_N = x − J(x)⁻¹ F(x)` satisfies
//!   `|x_N − x*| ≤ M |x − x*|² / (2 σ)`, `σ ≥ |det J| / ‖J‖_F` the smallest singular value of
//!   `J(x)`. `|x − x*|` is at most the distance from `x` to the farthest corner of `T` and at
//!   most `|x − x₀| + r_A / cos θ`; a target further than the bound outside `T` proves that `T`
//!   holds no root.
//! - **The residual's Taylor bound** ([`taylor_excludes`]). `F(x) = F(y) + J(y)(x − y) + R`
//!   with `|R| ≤ M |x − y|² / 2`; when some direction keeps that above the tolerance over a
//!   triangle, it holds no root. It needs no division by `σ`, so it settles the rays that pass
//!   just beside a silhouette, where `J` is nearly singular and Newton's bound is useless. For a
//!   blend, whose `M` is only sampled, the caller applies it to the three polynomial
//!   sub-surfaces with their proved bounds instead (the blend is their convex combination).
//!
//! Otherwise the iterate is projected back onto `T` (projection onto a convex set containing
//! the root never increases the distance to it), so iterates stay where the bounds hold and
//! converge to a root inside `T` whenever `M |x − x*| / (2σ) < 1`. A run that reaches the
//! iteration cap (or stalls on the boundary of `T`) without either outcome is
//! [`Newton::Failed`]. Most such runs belong to rays that pass just outside the piece, close to
//! a root of the polynomial's extension beyond `T`; [`search`] then applies the same error bound
//! to sub-triangles of `T` (from each one's centroid, where `|x − x*|` is at most the
//! sub-triangle's size, so the bound shrinks four-fold per level) until every sub-triangle is
//! excluded or holds a root. It evaluates the same piece, so it needs no allocation.

use glam::{DVec2, DVec3};

use crate::render::ray::{Ray64, RayPlanes};

/// Tunables of the per-piece Newton solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonSettings {
    /// Iteration cap of one Newton run; beyond it a run goes on (up to twice the cap) only
    /// while every step at least halves the residual, then counts as undecided.
    pub max_iterations: u32,
    /// Distance from the ray (relative to the scene's bounding-box diagonal) at which a root
    /// is accepted; [`crate::render::Tracer::root_tolerance`] adds a few hundred ulps of the
    /// coordinates. 1e-10 is ten times below the 1e-9 hit-accuracy contract and well above f64
    /// evaluation noise, so Newton never stalls on rounding.
    pub residual_tolerance: f64,
    /// Levels of 4-splitting of the piece's domain searched after an undecided run (see
    /// [`search`]).
    pub fallback_depth: u32,
}

impl Default for NewtonSettings {
    fn default() -> Self {
        NewtonSettings {
            max_iterations: 8,
            residual_tolerance: 1e-10,
            fallback_depth: 8,
        }
    }
}

/// The bounds of one piece that certify its misses (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PieceBounds {
    /// Surface points at the piece's corners `(s, t) = (0, 0), (1, 0), (0, 1)`.
    pub corners: [DVec3; 3],
    /// `δ / σ_min(J_A)`: see [`crate::render::bvh::affine_radius`].
    pub affine_radius: f64,
    /// Bounds `[tangential, normal]` on `|D²S(δ, δ)|` over the piece for unit `(s, t)`
    /// directions δ, split against the corner plane's normal (see
    /// [`crate::render::evaluate::second_derivative_bounds`]).
    pub second_bound: [f64; 2],
    /// True when `second_bound` is a proof (control-net bound), false when it is sampled
    /// (blends): only a proved bound lets a root be accepted from the Taylor estimate alone.
    pub proved: bool,
}

/// Outcome of one Newton run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Newton {
    /// A root at `(s, t)` in the piece after `iterations` steps, with surface point `p`.
    Root(DVec2, u32, DVec3),
    /// Proved: the piece holds no root.
    NoRoot,
    /// Neither within the iteration budget (singular Jacobian, slow convergence near a
    /// tangency): the caller splits the piece.
    Failed,
}

/// Where a Newton run starts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Start {
    /// The ray meets the corner plane at `at` (`(s, t)`, possibly outside `T`); a root lies
    /// within `radius` of it.
    At {
        /// The meeting point.
        at: DVec2,
        /// `affine_radius / cos θ`.
        radius: f64,
        /// `sin θ`: the share of the normal part of the second derivative that the ray sees.
        sin: f64,
    },
    /// Proved by the affine bound: the ray cannot meet the piece.
    Outside,
    /// The ray is parallel to the corner plane (or the plane is degenerate): no start point and
    /// no bound; Newton starts at the centroid.
    Unbounded,
}

impl Start {
    /// True when the ray may meet the piece more than once: it runs within 30° of the corner
    /// plane (leaves have normal cones of at most 25°, so a steeper ray meets a leaf once).
    pub fn may_meet_twice(&self) -> bool {
        match *self {
            Start::At { sin, .. } => sin > 30f64.to_radians().cos(),
            Start::Outside => false,
            Start::Unbounded => true,
        }
    }

    /// Where the roots can lie and how curved the piece looks along the ray: the start point,
    /// the radius about it that holds every root, and half the bound on the second derivative
    /// of the projected residual (`(tangential + sin θ · normal) / 2`); None when the start
    /// proves there is no root.
    fn region(&self, bounds: &PieceBounds) -> Option<(DVec2, f64, f64)> {
        let [tangential, normal] = bounds.second_bound;
        match *self {
            Start::Outside => None,
            Start::At { at, radius, sin } => Some((at, radius, 0.5 * (tangential + sin * normal))),
            Start::Unbounded => Some((
                DVec2::splat(1.0 / 3.0),
                f64::INFINITY,
                0.5 * (tangential + normal),
            )),
        }
    }
}

/// The start of Newton for `ray` on a piece with corners `corners` and affine radius
/// `affine_radius` (see [`Start`]). Möller–Trumbore barycentrics of the ray–plane point.
pub fn planar_start(corners: [DVec3; 3], affine_radius: f64, ray: &Ray64) -> Start {
    let [a, b, c] = corners;
    let (e1, e2) = (b - a, c - a);
    let pvec = ray.dir.cross(e2);
    let det = e1.dot(pvec);
    let area = e1.cross(e2).length();
    // det = −d · (e1 × e2), so |det| / |e1 × e2| is the cosine of the ray's angle to the normal.
    let cos = det.abs() / area;
    if cos.is_nan() || cos <= 0.0 || cos.is_infinite() {
        return Start::Unbounded;
    }
    let tvec = ray.origin - a;
    let s = tvec.dot(pvec) / det;
    let t = ray.dir.dot(tvec.cross(e1)) / det;
    let at = DVec2::new(s, t);
    let radius = affine_radius / cos;
    if !at.is_finite() || !radius.is_finite() {
        return Start::Unbounded;
    }
    if distance_to_unit_triangle(at) > radius * (1.0 + 1e-9) + 1e-12 {
        return Start::Outside;
    }
    let sin = (1.0 - cos.min(1.0).powi(2)).sqrt();
    Start::At { at, radius, sin }
}

/// Certified Newton on a piece: `eval(s, t)` gives `S`, `∂S/∂s`, `∂S/∂t`; `tolerance` is the
/// accepted distance of a root from the ray. See the module documentation for why
/// [`Newton::NoRoot`] is a proof and iterates stay in `T`.
pub fn newton(
    eval: &impl Fn(DVec2) -> (DVec3, DVec3, DVec3),
    bounds: &PieceBounds,
    start: Start,
    planes: &RayPlanes,
    tolerance: f64,
    settings: &NewtonSettings,
) -> Newton {
    let Some((from, radius, half_m)) = start.region(bounds) else {
        return Newton::NoRoot;
    };
    let mut x = project_to_unit_triangle(from);
    let mut iterations = 0;
    let mut previous = f64::INFINITY;
    loop {
        let (p, ss, tt) = eval(x);
        let f = planes.residual(p);
        if !f.is_finite() {
            return Newton::Failed;
        }
        let residual = f.length_squared();
        if residual <= tolerance * tolerance {
            return Newton::Root(x, iterations, p);
        }
        // Past the cap a run goes on (up to twice the cap) only while every step at least
        // halves the residual: near an almost double root (a silhouette) Newton converges
        // linearly, steadily but slower than quadratically.
        if iterations >= settings.max_iterations
            && (iterations >= 2 * settings.max_iterations || residual > 0.25 * previous)
        {
            return Newton::Failed;
        }
        previous = residual;
        let (ju, jv) = (planes.project(ss), planes.project(tt));
        let Some(step) = planes.newton_step(f, ss, tt) else {
            return Newton::Failed;
        };
        let target = x - step;
        iterations += 1;
        let outside = distance_to_unit_triangle(target);
        // Taylor: after an exact Newton step the residual, and the error of the linearised
        // point, are at most ½ M |Δ|²; below tolerance no further evaluation is needed.
        if bounds.proved && outside == 0.0 && half_m * step.length_squared() <= tolerance {
            return Newton::Root(target, iterations, p - ss * step.x - tt * step.y);
        }
        if outside > 0.0 {
            let sigma = ju.perp_dot(jv).abs() / (ju.length_squared() + jv.length_squared()).sqrt();
            let reach = farthest_corner_distance(x).min((x - from).length() + radius);
            let error = half_m * reach * reach / sigma;
            if outside > error * (1.0 + 1e-9) + 1e-12 {
                return Newton::NoRoot;
            }
            // The Newton bound divides by σ, which vanishes at a silhouette; the residual's own
            // Taylor bound over `T` (every point of `T` within `farthest_corner_distance` of
            // `x`) does not.
            if bounds.proved
                && taylor_excludes(
                    &[(f, ju, jv)],
                    [DVec2::ZERO, DVec2::X, DVec2::Y],
                    x,
                    farthest_corner_distance(x),
                    2.0 * half_m,
                    tolerance,
                )
            {
                return Newton::NoRoot;
            }
        }
        let next = project_to_unit_triangle(target);
        if outside > 0.0 && (next - x).length_squared() < 1e-4 * step.length_squared() {
            // Stalled on the boundary: the target lies outside, in about the same place again.
            return Newton::Failed;
        }
        x = next;
    }
}

/// The search of a piece whose Newton run was undecided: the unit triangle is split into four
/// recursively (`depth` levels); a sub-triangle Δ is excluded when the residual's Taylor bound
/// about its centroid `y` keeps it away from zero ([`taylor_excludes`], with a proved bound
/// only), or when the Newton
/// target `x_N` from `y` lies further outside Δ than `M ρ² / (2σ)`, `ρ` the distance from `y`
/// to Δ's farthest corner (a root in Δ is within that of `x_N`, see the module documentation),
/// or when `exclude(Δ)` says so (a caller's own certified test: for a blend, [`taylor_excludes`]
/// on its three polynomial sub-surfaces); otherwise, if that target lies in Δ, Newton runs from `y`
/// over the whole piece, and a sub-triangle still open is split. Every root found goes to
/// `visit(s, t, p)`. Returns the number of sub-triangles left undecided at the last level (0:
/// every root of the piece was visited), or `None` when a run proved that the piece holds no
/// root.
#[allow(clippy::too_many_arguments)]
pub fn search(
    eval: impl Fn(DVec2) -> (DVec3, DVec3, DVec3),
    bounds: &PieceBounds,
    start: Start,
    planes: &RayPlanes,
    tolerance: f64,
    settings: &NewtonSettings,
    exclude: impl Fn([DVec2; 3]) -> bool,
    mut visit: impl FnMut(DVec2, DVec3),
) -> Option<u64> {
    // Every root lies within `radius` of `from` (the affine bound of the start).
    let (from, radius, half_m) = start.region(bounds)?;
    let once = !start.may_meet_twice();
    let mut undecided = 0;
    let mut stack: Vec<([DVec2; 3], u32)> = Vec::new();
    let unit = [DVec2::ZERO, DVec2::X, DVec2::Y];
    stack.push((unit, 0));
    while let Some((tri, level)) = stack.pop() {
        let y = (tri[0] + tri[1] + tri[2]) / 3.0;
        let size = tri
            .iter()
            .map(|c| (*c - y).length_squared())
            .fold(0.0, f64::max)
            .sqrt();
        // The sub-triangle lies in the disk of radius `size` about `y`.
        if (from - y).length() - size > radius * (1.0 + 1e-9) + 1e-12 {
            continue;
        }
        let (p, ss, tt) = eval(y);
        let f = planes.residual(p);
        let (ju, jv) = (planes.project(ss), planes.project(tt));
        let sigma = ju.perp_dot(jv).abs() / (ju.length_squared() + jv.length_squared()).sqrt();
        // A steep ray meets the piece once ([`Start::may_meet_twice`]). Otherwise: two roots in
        // the disk about `y` would make the mean Jacobian between them singular, but it differs
        // from `J(y)` by at most `2 half_m · size` there, so a root in Δ is the only one when
        // `σ` exceeds that. Else Δ is searched further, so that a ray meeting the piece twice
        // close together (grazing) finds the nearer root too.
        let unique = once || sigma > 2.0 * half_m * size * (1.0 + 1e-9);
        let root_here = f.length_squared() <= tolerance * tolerance;
        // Only a proved bound excludes by Taylor here; a blend's caller passes its own test.
        if !root_here
            && bounds.proved
            && taylor_excludes(&[(f, ju, jv)], tri, y, size, 2.0 * half_m, tolerance)
        {
            continue;
        }
        if root_here {
            visit(y, p);
            if unique || level == settings.fallback_depth {
                continue;
            }
        }
        // Newton over the whole piece from `y` only where the target from `y` stays in Δ.
        let mut promising = false;
        let mut found_inside = root_here;
        if level > 0
            && !root_here
            && let Some(step) = planes.newton_step(f, ss, tt)
        {
            let error = half_m * size * size / sigma;
            let outside = distance_to_triangle(y - step, tri);
            if outside > error * (1.0 + 1e-9) + 1e-12 {
                continue;
            }
            // Deep down, a root near the edge of Δ may have its target just outside: run too.
            // Deep down, a root near an edge of Δ may have its target just across it: run too.
            promising = outside == 0.0 || (level >= 4 && outside <= size);
        }
        if !root_here && exclude(tri) {
            continue;
        }
        if promising {
            let start = Start::At {
                at: y,
                radius: f64::INFINITY,
                sin: match start {
                    Start::At { sin, .. } => sin,
                    _ => 1.0,
                },
            };
            match newton(&eval, bounds, start, planes, tolerance, settings) {
                Newton::Root(st, _, p) => {
                    visit(st, p);
                    // A root elsewhere in the piece settles nothing about Δ; one inside it
                    // settles Δ when it is the only one there.
                    let inside = distance_to_triangle(st, tri) == 0.0;
                    if inside && unique {
                        continue;
                    }
                    found_inside = inside;
                }
                Newton::NoRoot => return None,
                Newton::Failed => {}
            }
        }
        if level == settings.fallback_depth {
            // A root in Δ at the last level leaves any other within Δ's tiny size.
            if !found_inside {
                undecided += 1;
            }
            continue;
        }
        let m01 = 0.5 * (tri[0] + tri[1]);
        let m12 = 0.5 * (tri[1] + tri[2]);
        let m20 = 0.5 * (tri[2] + tri[0]);
        for child in [
            [tri[0], m01, m20],
            [m01, tri[1], m12],
            [m20, m12, tri[2]],
            [m12, m20, m01],
        ] {
            stack.push((child, level + 1));
        }
    }
    Some(undecided)
}

/// True when no point of the triangle `tri` (centroid `y`, every point within `size` of `y`)
/// can hold a root: the residual there lies in the convex hull of `parts` — maps `G_i` given
/// by their value `G_i(y)` and partial derivatives `(∂G_i/∂s, ∂G_i/∂t)` at `y`, each with
/// `|D²G_i(δ, δ)| ≤ second` for unit δ over `tri` — and some unit direction `n` keeps all of
/// them above `margin`.
///
/// By Taylor's theorem `n·G_i(x) ≥ n·G_i(y) + n·J_i (x − y) − ½ second |x − y|²`, and the linear
/// term is smallest at a corner of `tri`. A point with `|F| ≤ margin` has `n·F ≤ margin`, so a
/// lower bound above `margin` (grown by a relative 1e-9 and 1e-12 for rounding) for every part
/// excludes the triangle. The directions tried are the residual's at `y` (the sum of the parts)
/// and the two coordinate axes on its side. Unlike the Newton bound it does not divide by the
/// Jacobian's smallest singular value, so it still excludes a triangle near a silhouette, where
/// that Jacobian is nearly singular.
pub fn taylor_excludes(
    parts: &[(DVec2, DVec2, DVec2)],
    tri: [DVec2; 3],
    y: DVec2,
    size: f64,
    second: f64,
    margin: f64,
) -> bool {
    let sum = parts.iter().fold(DVec2::ZERO, |a, p| a + p.0);
    let drop = 0.5 * second * size * size;
    let limit = margin * (1.0 + 1e-9) + 1e-12;
    if !drop.is_finite() {
        return false;
    }
    let offsets = tri.map(|c| c - y);
    let clears = |n: DVec2| {
        parts.iter().all(|&(g, js, jt)| {
            let (a, b) = (n.dot(js), n.dot(jt));
            let linear = offsets
                .iter()
                .map(|o| a * o.x + b * o.y)
                .fold(f64::INFINITY, f64::min);
            n.dot(g) + linear - drop > limit
        })
    };
    let n = sum.normalize_or_zero();
    (n != DVec2::ZERO && clears(n))
        || (sum.x != 0.0 && clears(DVec2::new(sum.x.signum(), 0.0)))
        || (sum.y != 0.0 && clears(DVec2::new(0.0, sum.y.signum())))
}

/// Distance from `x` to the triangle `tri` (0 inside): through the affine map onto the unit
/// triangle only for the inside test, measured in `x`'s own units.
fn distance_to_triangle(x: DVec2, tri: [DVec2; 3]) -> f64 {
    let (e1, e2) = (tri[1] - tri[0], tri[2] - tri[0]);
    let q = x - tri[0];
    let det = e1.perp_dot(e2);
    let (a, b) = (q.perp_dot(e2) / det, e1.perp_dot(q) / det);
    if a >= 0.0 && b >= 0.0 && a + b <= 1.0 {
        return 0.0;
    }
    let to_segment = |p: DVec2, r: DVec2| {
        let pr = r - p;
        let h = ((x - p).dot(pr) / pr.length_squared()).clamp(0.0, 1.0);
        (p + pr * h - x).length()
    };
    to_segment(tri[0], tri[1])
        .min(to_segment(tri[1], tri[2]))
        .min(to_segment(tri[2], tri[0]))
}

/// Distance from `x` to the farthest corner of the unit triangle `T`: the largest distance
/// from `x` to any point of `T`.
fn farthest_corner_distance(x: DVec2) -> f64 {
    x.length_squared()
        .max((x - DVec2::X).length_squared())
        .max((x - DVec2::Y).length_squared())
        .sqrt()
}

/// The point of the unit triangle `T = {s, t ≥ 0, s + t ≤ 1}` closest to `x`.
pub fn project_to_unit_triangle(x: DVec2) -> DVec2 {
    if x.x >= 0.0 && x.y >= 0.0 && x.x + x.y <= 1.0 {
        return x;
    }
    let on_segment = |a: DVec2, b: DVec2| {
        let ab = b - a;
        let h = ((x - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
        a + ab * h
    };
    [
        on_segment(DVec2::ZERO, DVec2::X),
        on_segment(DVec2::X, DVec2::Y),
        on_segment(DVec2::Y, DVec2::ZERO),
    ]
    .into_iter()
    .min_by(|a, b| {
        (*a - x)
            .length_squared()
            .total_cmp(&(*b - x).length_squared())
    })
    .unwrap_or(DVec2::splat(1.0 / 3.0))
}

/// Distance from `x` to the unit triangle `T` (0 inside).
pub fn distance_to_unit_triangle(x: DVec2) -> f64 {
    (project_to_unit_triangle(x) - x).length()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A quadratic map with `|D²G(δ, δ)| ≤ 2 · 1.5` for unit δ, and its derivatives.
    fn quadratic(x: DVec2, shift: DVec2) -> (DVec2, DVec2, DVec2) {
        let g = DVec2::new(x.x * x.x + 0.5 * x.x * x.y, x.y - 0.75 * x.y * x.y) - shift;
        let gs = DVec2::new(2.0 * x.x + 0.5 * x.y, 0.0);
        let gt = DVec2::new(0.5 * x.x, 1.0 - 1.5 * x.y);
        (g, gs, gt)
    }

    #[test]
    fn taylor_exclusion_never_excludes_a_root_and_excludes_far_triangles() {
        // |D²G| ≤ |(2, 0.5; 0.5, 0)| + 1.5 ≤ 2.07 + 1.5 for unit directions: 4 bounds it.
        let second = 4.0;
        let mut excluded = 0;
        let mut tested = 0;
        for i in 0..40 {
            for j in 0..40 {
                let shift = DVec2::new(i as f64 / 20.0 - 0.5, j as f64 / 20.0 - 0.5);
                for tri in [
                    [DVec2::ZERO, DVec2::new(0.25, 0.0), DVec2::new(0.0, 0.25)],
                    [
                        DVec2::new(0.25, 0.25),
                        DVec2::new(0.5, 0.25),
                        DVec2::new(0.25, 0.5),
                    ],
                ] {
                    let y = (tri[0] + tri[1] + tri[2]) / 3.0;
                    let size = tri.iter().map(|c| (*c - y).length()).fold(0.0, f64::max);
                    let part = quadratic(y, shift);
                    let says = taylor_excludes(&[part], tri, y, size, second, 1e-10);
                    tested += 1;
                    if !says {
                        continue;
                    }
                    excluded += 1;
                    // A dense sample of the triangle: no point comes near a root.
                    for a in 0..=16 {
                        for b in 0..=16 - a {
                            let x = tri[0]
                                + (tri[1] - tri[0]) * (a as f64 / 16.0)
                                + (tri[2] - tri[0]) * (b as f64 / 16.0);
                            let g = quadratic(x, shift).0;
                            assert!(g.length() > 1e-10, "excluded {tri:?} holds {x} ({g})");
                        }
                    }
                }
            }
        }
        // Most shifts put the root far from these small triangles.
        assert!(excluded > tested / 2, "{excluded} of {tested} excluded");
        // A triangle holding the root is never excluded.
        let tri = [DVec2::ZERO, DVec2::new(0.5, 0.0), DVec2::new(0.0, 0.5)];
        let y = (tri[0] + tri[1] + tri[2]) / 3.0;
        let shift = quadratic(DVec2::new(0.1, 0.1), DVec2::ZERO).0;
        let size = tri.iter().map(|c| (*c - y).length()).fold(0.0, f64::max);
        assert!(!taylor_excludes(
            &[quadratic(y, shift)],
            tri,
            y,
            size,
            second,
            1e-10
        ));
    }

    #[test]
    fn projection_onto_the_unit_triangle() {
        let cases = [
            (DVec2::new(0.2, 0.3), DVec2::new(0.2, 0.3)),
            (DVec2::new(-1.0, 0.5), DVec2::new(0.0, 0.5)),
            (DVec2::new(0.5, -2.0), DVec2::new(0.5, 0.0)),
            (DVec2::new(1.0, 1.0), DVec2::new(0.5, 0.5)),
            (DVec2::new(-1.0, -1.0), DVec2::ZERO),
            (DVec2::new(3.0, -1.0), DVec2::X),
            (DVec2::new(-1.0, 3.0), DVec2::Y),
        ];
        for (x, expected) in cases {
            let p = project_to_unit_triangle(x);
            assert!((p - expected).length() < 1e-15, "{x} → {p}, not {expected}");
        }
        assert_eq!(distance_to_unit_triangle(DVec2::new(0.1, 0.1)), 0.0);
        assert!((distance_to_unit_triangle(DVec2::new(-0.25, 0.5)) - 0.25).abs() < 1e-15);
    }
}
