//! The acceleration structure of the exact renderer: every patch's `(u, v)` domain is split into
//! sub-triangles until each piece is nearly flat with a narrow normal cone and a bounded tilt
//! (a ray steeper than it meets the piece at most once), and an obvhs
//! compressed wide BVH (PLOC build + reinsertion) is built over the pieces' conservative boxes.
//!
//! A leaf is `(patch, sub-triangle of the patch's (u, v) domain)`. Each Bézier patch with
//! leaves also keeps its power form over its domain (built once here, one per patch, see
//! [`power_coefficients`]), which its leaves evaluate through their domain maps
//! ([`LeafMap`](crate::render::evaluate::LeafMap)), so that Newton evaluates a cheap polynomial
//! instead of running de Casteljau on the patch; each leaf keeps a second-derivative bound
//! valid on it.
//! Its box is the box of the
//! sub-patch's Bézier control net (convex-hull property: it contains the sub-patch), rounded
//! outward to f32 and padded by a small fraction of the scene size so that the f32 traversal ray,
//! which differs from the f64 ray by rounding, still enters every box the f64 ray enters.

use std::time::{Duration, Instant};

use glam::{DVec2, DVec3, Vec3, Vec3A};
use obvhs::BvhBuildParams;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::builder::build_cwbvh;
use rayon::prelude::*;

use crate::bezier::TriangleBezier;
use crate::bezier::triangle::point_count;
use crate::blend::BlendPatch;
use crate::error::{Error, Result};
use crate::geom::Aabb;
use crate::render::evaluate::{power_coefficients, second_derivative_bounds};
use crate::surface::{Patch, PatchGeometry, Surface, UV_CORNERS};

/// When a piece of a patch is small enough to be a BVH leaf.
///
/// A piece is split into four (at its edge midpoints) until its control net lies within
/// `flatness × size` of the plane through its three corners (`size` = diagonal of the net's
/// box), the normals of all control-net triangles lie within `max_cone_deg` of that plane's
/// normal ([`is_leaf`]) **and**, for a piece of a Bézier patch, no chord of the piece is
/// steeper against the plane than `max_tilt` (a sine; see [`tilt`]). Flatness keeps the box
/// tight; the narrow cone keeps Newton, started at the piece's centroid, inside its basin of
/// quadratic convergence; the tilt proves that a ray steeper than it meets the piece at most
/// once, so only rays nearly along the piece need the search for a second root. (A blend's
/// nets bound no chord of the blend, so its pieces are not split for the tilt.)
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SubdivisionCriterion {
    /// Largest allowed distance of a control point from the corner plane, relative to size.
    pub flatness: f64,
    /// Largest allowed angle (degrees) between a control-net triangle normal and the corner
    /// plane normal.
    pub max_cone_deg: f64,
    /// Largest allowed [`tilt`] (sine of the steepest chord against the corner plane): rays
    /// steeper than this meet a leaf at most once.
    pub max_tilt: f64,
    /// Splits always stop at this depth (a piece then covers 4^-depth of the patch domain).
    pub max_depth: u32,
    /// Splits never stop before this depth.
    pub min_depth: u32,
}

impl Default for SubdivisionCriterion {
    fn default() -> Self {
        SubdivisionCriterion {
            flatness: 0.05,
            max_cone_deg: 25.0,
            max_tilt: 0.5,
            max_depth: 7,
            min_depth: 0,
        }
    }
}

/// One BVH primitive: a sub-triangle of one patch's `(u, v)` domain, with the surface points
/// at its corners (they span the plane from which Newton starts) and an oriented box around
/// the sub-patch's control net in the frame of that plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Leaf {
    /// Patch index in [`Surface::patches`].
    pub patch: u32,
    /// Corners of the sub-triangle in the patch's `(u, v)` coordinates (counter-clockwise).
    /// Stored in f32: corners are dyadic fractions from repeated halving, exact in f32 up to
    /// depth 23.
    pub uv: [[f32; 2]; 3],
    /// Surface points at the three corners (f32 is plenty for a start point). They span the
    /// leaf's affine map `A(s, t) = c0 + (c1 − c0) s + (c2 − c0) t`.
    pub corners: [Vec3; 3],
    /// Bound, in leaf-local `(s, t)` units, on how far from the ray's meeting point with the
    /// corner plane a root of the leaf can lie, for a ray perpendicular to that plane (divide
    /// by the cosine of the ray's angle to the plane normal otherwise); see [`affine_radius`].
    pub affine_radius: f32,
    /// Bound on the sine of the angle between any chord of the sub-patch and the corner plane
    /// (see [`tilt`]): a ray steeper than that meets the leaf at most once. Infinite when
    /// there is no bound (a blend's nets do not bound its derivatives).
    pub tilt: f32,
    /// Oriented box: rows of the frame (first edge, in-plane normal to it, plane normal).
    pub axes: [Vec3; 3],
    /// Oriented box: smallest coordinates of the control points in the frame at `corners[0]`.
    pub lo: Vec3,
    /// Oriented box: largest coordinates.
    pub hi: Vec3,
    /// Outward unit normals, in the box frame's first two coordinates, of the corner
    /// triangle's edges `0→1`, `1→2`, `2→0`: with [`Leaf::edge_hi`] they bound the sub-patch by
    /// a triangular prism, much tighter than the box's sides near the triangle's slanted edges.
    pub edge_normals: [[f32; 2]; 3],
    /// Largest `edge_normals[e] · (x, y)` over the control points (and so the sub-patch), grown
    /// by [`PRISM_PAD`].
    pub edge_hi: [f32; 3],
    /// Start of the power-form coefficients of the leaf's patch in [`PatchBvh::power`]
    /// (shared by the patch's leaves); for a blend leaf (no power form), its entry in
    /// [`PatchBvh::blend_second_bounds`].
    pub power: u32,
    /// Degree of the power form; 0 when the leaf has none (the patch is then evaluated whole).
    pub degree: u8,
    /// Bounds `[tangential, normal]` on |∂²S/∂δ²| over the leaf for unit leaf-local directions
    /// δ, split against the corner plane's normal ([`second_derivative_bounds`] of a Bézier
    /// sub-net, [`sampled_second_bounds`] of a blend); infinite when unknown.
    pub second_bound: [f32; 2],
    /// Levels the in-leaf search goes deeper than
    /// [`NewtonSettings::fallback_depth`](crate::render::intersect::NewtonSettings): a piece
    /// whose splits stopped narrowing it became a leaf above [`SubdivisionCriterion::max_depth`]
    /// ([`Stall`]), and searching it this much deeper reaches sub-triangles as small as those of
    /// a leaf at that depth. 0 for every other leaf.
    pub extra_search: u8,
}

impl Leaf {
    /// A leaf of `patch` over the sub-triangle `tri` whose sub-patch lies in the convex hull of
    /// the control nets `nets` (one for a Bézier patch, the three sub-surfaces of a blend) and
    /// has corner points `corners`.
    ///
    /// The oriented box is computed with the frame exactly as stored (f32 origin and axes,
    /// used in f64), so it contains every control point — hence, by the convex-hull property,
    /// the sub-patch — whatever the rounding of the frame; a relative 1e-9 pad covers the f64
    /// arithmetic. The affine radius is measured against the stored (f32) corners, the plane
    /// Newton starts from.
    ///
    /// Its tilt is left infinite (no bound); the BVH build sets it for Bézier pieces.
    pub fn new(patch: u32, tri: [DVec2; 3], corners: [DVec3; 3], nets: &[&TriangleBezier]) -> Leaf {
        let points = || nets.iter().flat_map(|n| n.control_points());
        let stored = corners.map(|p| p.as_vec3());
        let affine_radius = f32_up(affine_radius(stored.map(|p| p.as_dvec3()), nets));
        let origin = corners[0].as_vec3().as_dvec3();
        let x = (corners[1] - corners[0]).normalize_or_zero();
        let plane = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
        let z = plane.normalize_or_zero();
        let axes = if x == DVec3::ZERO || z == DVec3::ZERO {
            [DVec3::X, DVec3::Y, DVec3::Z]
        } else {
            [x, z.cross(x), z]
        };
        let axes = axes.map(|a| a.as_vec3());
        let frame = axes.map(|a| a.as_dvec3());
        let mut lo = DVec3::INFINITY;
        let mut hi = DVec3::NEG_INFINITY;
        for p in points().chain(corners) {
            let q = p - origin;
            let c = DVec3::new(frame[0].dot(q), frame[1].dot(q), frame[2].dot(q));
            lo = lo.min(c);
            hi = hi.max(c);
        }
        let pad = 1e-9 * (hi - lo).max_element().max(origin.abs().max_element());
        // The prism's edge planes, from the corners in the stored frame.
        let flat = |p: DVec3| {
            let q = p - origin;
            glam::DVec2::new(frame[0].dot(q), frame[1].dot(q))
        };
        let corner_xy = corners.map(flat);
        let mut edge_normals = [[0.0_f32; 2]; 3];
        let mut edge_hi = [f32::INFINITY; 3];
        for e in 0..3 {
            let along = corner_xy[(e + 1) % 3] - corner_xy[e];
            let normal = DVec2::new(along.y, -along.x).normalize_or_zero();
            if normal == DVec2::ZERO || !normal.is_finite() {
                continue;
            }
            let stored = normal.as_vec2();
            let n = stored.as_dvec2();
            let reach = points()
                .chain(corners)
                .map(|p| n.dot(flat(p)))
                .fold(f64::NEG_INFINITY, f64::max);
            edge_normals[e] = stored.to_array();
            edge_hi[e] = f32_up(reach + pad + PRISM_PAD * (hi - lo).max_element());
        }
        let (lo, hi) = (lo - DVec3::splat(pad), hi + DVec3::splat(pad));
        let down = |v: DVec3| Vec3::new(f32_down(v.x), f32_down(v.y), f32_down(v.z));
        let up = |v: DVec3| Vec3::new(f32_up(v.x), f32_up(v.y), f32_up(v.z));
        Leaf {
            patch,
            uv: tri.map(|c| [c.x as f32, c.y as f32]),
            corners: stored,
            affine_radius,
            tilt: f32::INFINITY,
            axes,
            lo: down(lo),
            hi: up(hi),
            edge_normals,
            edge_hi,
            power: 0,
            degree: 0,
            second_bound: [f32::INFINITY; 2],
            extra_search: 0,
        }
    }

    /// Unit normal of the plane of the stored corners (zero when they are collinear): the
    /// direction against which [`Leaf::second_bound`] is split.
    pub fn normal(&self) -> DVec3 {
        let [a, b, c] = self.corners.map(|p| p.as_dvec3());
        (b - a).cross(c - a).normalize_or_zero()
    }

    /// Maps leaf-local barycentrics `(s, t)` (weights of the second and third corner) to the
    /// patch's `(u, v)`.
    pub fn patch_uv(&self, s: f64, t: f64) -> DVec2 {
        let tri = self.tri();
        tri[0] + (tri[1] - tri[0]) * s + (tri[2] - tri[0]) * t
    }

    /// Corners of the sub-triangle in `(u, v)`.
    pub fn tri(&self) -> [DVec2; 3] {
        self.uv
            .map(|c| DVec2::new(f64::from(c[0]), f64::from(c[1])))
    }

    /// Centroid of the sub-triangle.
    pub fn centroid(&self) -> DVec2 {
        let t = self.tri();
        (t[0] + t[1] + t[2]) / 3.0
    }

    /// True if the ray `origin + t dir`, `t ∈ [t_min, t_max]`, meets the oriented box and the
    /// edge prism (a conservative test: false means the ray cannot meet the sub-patch).
    pub fn ray_meets_box(&self, origin: DVec3, dir: DVec3, t_min: f64, t_max: f64) -> bool {
        self.ray_meets_box_from(self.box_coordinates(origin), dir, t_min, t_max)
    }

    /// The coordinates of `point` in the oriented box's frame (`axes · (point − corner)`, the
    /// first corner stored): what [`Leaf::ray_meets_box`] computes of a ray's origin, so rays
    /// that share their origin (a bundle's) compute it once per leaf.
    pub fn box_coordinates(&self, point: DVec3) -> DVec3 {
        let q = point - self.corners[0].as_dvec3();
        DVec3::new(
            self.axes[0].as_dvec3().dot(q),
            self.axes[1].as_dvec3().dot(q),
            self.axes[2].as_dvec3().dot(q),
        )
    }

    /// [`Leaf::ray_meets_box`] for the ray whose origin has box coordinates `local_origin`
    /// ([`Leaf::box_coordinates`]): the test of [`BoxFromOrigin::meets`], bit for bit, with
    /// each slab's and edge's offsets from the origin made only when the test gets to it
    /// (a single ray's test mostly ends at a slab).
    pub fn ray_meets_box_from(
        &self,
        local_origin: DVec3,
        dir: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> bool {
        box_and_prism_test(
            |axis| self.axes[axis].as_dvec3(),
            |axis| self.slab_from(local_origin, axis),
            |e| self.edge_from(local_origin, e),
            dir,
            (t_min, t_max),
        )
    }

    /// The box's slab along `axis` as offsets from the point with box coordinates `o`:
    /// `(lo − o, hi − o)`.
    #[inline(always)]
    fn slab_from(&self, o: DVec3, axis: usize) -> (f64, f64) {
        let (lo, hi) = (self.lo[axis], self.hi[axis]);
        (f64::from(lo) - o[axis], f64::from(hi) - o[axis])
    }

    /// The prism's edge `e` seen from the point with box coordinates `o`: its outward normal
    /// `n` in f64 and `h − n · o`, how far `o` lies inside its half-plane.
    #[inline(always)]
    fn edge_from(&self, o: DVec3, e: usize) -> (DVec2, f64) {
        let [nx, ny] = self.edge_normals[e].map(f64::from);
        let n = DVec2::new(nx, ny);
        (n, f64::from(self.edge_hi[e]) - (n.x * o.x + n.y * o.y))
    }
}

/// A leaf's oriented box and edge prism seen from one origin: what the box test
/// ([`Leaf::ray_meets_box`]) computes of the origin alone — the slab offsets `lo − o`,
/// `hi − o` and the prism's `h − n·o` — made once, so that the rays of a bundle (which share
/// their origin) pay only for their directions. The same test, bit for bit.
#[derive(Clone, Copy, Debug)]
pub struct BoxFromOrigin {
    /// The box frame's rows in f64.
    axes: [DVec3; 3],
    /// Per axis, `(lo − o, hi − o)` for the origin's coordinate `o` in the box frame.
    slabs: [(f64, f64); 3],
    /// Per edge of the prism, its outward normal in f64 and `h − n·o`: how far the origin
    /// lies inside the edge's half-plane.
    edges: [(DVec2, f64); 3],
}

impl BoxFromOrigin {
    /// The box and prism of `leaf` seen from the point with box coordinates `local_origin`
    /// ([`Leaf::box_coordinates`]).
    pub fn new(leaf: &Leaf, local_origin: DVec3) -> BoxFromOrigin {
        BoxFromOrigin {
            axes: leaf.axes.map(|a| a.as_dvec3()),
            slabs: [0, 1, 2].map(|axis| leaf.slab_from(local_origin, axis)),
            edges: [0, 1, 2].map(|e| leaf.edge_from(local_origin, e)),
        }
    }

    /// True if the ray from the origin along `dir`, `t ∈ [t_min, t_max]`, meets the oriented
    /// box and the edge prism (a conservative test: false means the ray cannot meet the
    /// sub-patch). Slab by slab, then the prism's three edge half-planes `n · (x, y) ≤ h`.
    pub fn meets(&self, dir: DVec3, t_min: f64, t_max: f64) -> bool {
        box_and_prism_test(
            |axis| self.axes[axis],
            |axis| self.slabs[axis],
            |e| self.edges[e],
            dir,
            (t_min, t_max),
        )
    }
}

/// The oriented box and edge prism test of the ray along `dir` over `interval`, from the
/// box frame's rows `axis(i)`, the slab offsets `slab(i) = (lo − o, hi − o)` and the edges
/// `edge(e) = (n, h − n · o)` of the origin `o`, each asked for only when the test gets to
/// it: slab by slab (written out: as a loop the compiler kept it rolled), then the prism's
/// three edge half-planes `n · (x, y) ≤ h`. True when some part of the interval is left.
#[inline(always)]
fn box_and_prism_test(
    axis: impl Fn(usize) -> DVec3,
    slab: impl Fn(usize) -> (f64, f64),
    edge: impl Fn(usize) -> (DVec2, f64),
    dir: DVec3,
    mut interval: (f64, f64),
) -> bool {
    let dx = axis(0).dot(dir);
    if clip_to_slab_empties(&mut interval, dx, slab(0)) {
        return false;
    }
    let dy = axis(1).dot(dir);
    if clip_to_slab_empties(&mut interval, dy, slab(1)) {
        return false;
    }
    if clip_to_slab_empties(&mut interval, axis(2).dot(dir), slab(2)) {
        return false;
    }
    !(0..3).any(|e| {
        let (n, room) = edge(e);
        clip_to_half_plane_empties(&mut interval, n.x * dx + n.y * dy, room)
    })
}

/// Clips the ray interval `(near, far)` to a slab whose sides lie `lo`, `hi` (offsets from
/// the origin) along an axis on which the ray's direction is `d`; true when nothing is left.
/// Parallel to the slab (`d = 0`), the ray lies in it or not at all (`o < lo` is `lo − o > 0`).
#[inline(always)]
fn clip_to_slab_empties(interval: &mut (f64, f64), d: f64, (lo, hi): (f64, f64)) -> bool {
    if d == 0.0 {
        return lo > 0.0 || hi < 0.0;
    }
    let inv = 1.0 / d;
    let (t0, t1) = (lo * inv, hi * inv);
    let (near, far) = interval;
    *near = near.max(t0.min(t1));
    *far = far.min(t0.max(t1));
    *near > *far
}

/// Clips the ray interval `(near, far)` to the half-plane `n · (x, y) ≤ h` whose boundary lies
/// `room = h − n · o` from the origin, for a direction with `n · (dx, dy) = d`; true when
/// nothing is left.
#[inline(always)]
fn clip_to_half_plane_empties(interval: &mut (f64, f64), d: f64, room: f64) -> bool {
    if d == 0.0 {
        return room < 0.0;
    }
    let reach = room / d;
    let (near, far) = interval;
    if d > 0.0 {
        *far = far.min(reach);
    } else {
        *near = near.max(reach);
    }
    *near > *far
}

/// The largest f32 not above `x`.
fn f32_down(x: f64) -> f32 {
    let f = x as f32;
    if f64::from(f) > x { f.next_down() } else { f }
}

/// The smallest f32 not below `x`.
fn f32_up(x: f64) -> f32 {
    let f = x as f32;
    if f64::from(f) < x { f.next_up() } else { f }
}

/// The four sub-triangles of `tri` split at its edge midpoints, all counter-clockwise like
/// `tri`; the middle one last.
pub(crate) fn split4(tri: [DVec2; 3]) -> [[DVec2; 3]; 4] {
    let m01 = 0.5 * (tri[0] + tri[1]);
    let m12 = 0.5 * (tri[1] + tri[2]);
    let m20 = 0.5 * (tri[2] + tri[0]);
    [
        [tri[0], m01, m20],
        [m01, tri[1], m12],
        [m20, m12, tri[2]],
        [m01, m12, m20],
    ]
}

/// The barycentric corners (in a parent's domain) of the four children of [`split4`].
pub(crate) const CHILD_CORNERS: [[DVec3; 3]; 4] = {
    let c0 = DVec3::new(1.0, 0.0, 0.0);
    let c1 = DVec3::new(0.0, 1.0, 0.0);
    let c2 = DVec3::new(0.0, 0.0, 1.0);
    let m01 = DVec3::new(0.5, 0.5, 0.0);
    let m12 = DVec3::new(0.0, 0.5, 0.5);
    let m20 = DVec3::new(0.5, 0.0, 0.5);
    [
        [c0, m01, m20],
        [m01, c1, m12],
        [m20, m12, c2],
        [m01, m12, m20],
    ]
};

/// An f64 box as an f32 box that contains it, grown by `pad` on every side.
pub(crate) fn outward_f32(b: &Aabb, pad: f64) -> obvhs::aabb::Aabb {
    let lo = b.min - DVec3::splat(pad);
    let hi = b.max + DVec3::splat(pad);
    obvhs::aabb::Aabb::new(
        Vec3A::new(f32_down(lo.x), f32_down(lo.y), f32_down(lo.z)),
        Vec3A::new(f32_up(hi.x), f32_up(hi.y), f32_up(hi.z)),
    )
}

/// The box padding for a scene with bounds `scene`: covers the f32 rounding of traversal rays
/// whose origin and hit distance are within about ten scene sizes of the scene.
pub(crate) fn box_padding(scene: &Aabb) -> f64 {
    let extent = scene
        .diagonal()
        .max(scene.min.abs().max_element())
        .max(scene.max.abs().max_element());
    1e-5 * extent.max(f64::MIN_POSITIVE)
}

/// The frame in which a BVH holds its surface: world point `p` is `(p − centre) × scale` there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UnitFrame {
    /// The world point at the frame's origin.
    pub centre: DVec3,
    /// The scale (a power of two for the tracer's unit frame, so that applying it is exact).
    pub scale: f64,
}

impl UnitFrame {
    /// World coordinates themselves.
    pub const IDENTITY: UnitFrame = UnitFrame {
        centre: DVec3::ZERO,
        scale: 1.0,
    };

    /// The point `p` in this frame.
    pub fn map(&self, p: DVec3) -> DVec3 {
        (p - self.centre) * self.scale
    }
}

/// The patch BVH: leaves in traversal order plus the obvhs wide BVH over their boxes, all in
/// the frame given to [`PatchBvh::build_in`].
pub struct PatchBvh {
    /// The obvhs BVH; its primitive ids index [`PatchBvh::leaves`] directly.
    pub bvh: CwBvh,
    /// Leaves, reordered so that BVH primitive id `i` is `leaves[i]`.
    pub leaves: Vec<Leaf>,
    /// Wall time of subdivision plus BVH build.
    pub build_time: Duration,
    /// Padding added to every leaf box (world units).
    pub padding: f64,
    /// Bounds of the surface's control points in the BVH's frame.
    pub scene: Aabb,
    /// Power-form coefficients of the patches evaluated by their leaves, each patch's run
    /// starting at its leaves' [`Leaf::power`].
    pub power: Vec<DVec3>,
    /// Per blend leaf (at [`Leaf::power`]): a proved bound on `|D²S_i(δ, δ)|` over the leaf
    /// for unit leaf-local directions δ and each of the blend's three polynomial sub-surfaces
    /// `S_i` ([`second_derivative_bounds`] of their sub-nets, tangential plus normal part).
    /// The blend is a convex combination of them, which lets the in-leaf search exclude a
    /// sub-triangle with a proof ([`crate::render::newton::taylor_excludes`]).
    pub blend_second_bounds: Vec<f64>,
    /// The patches without a power form (blends, and Bézier patches above
    /// [`MAX_POWER_DEGREE`]), in the BVH's frame: their leaves evaluate the whole patch.
    whole: Vec<Patch>,
    /// Per patch, its position in [`PatchBvh::whole`] (`u32::MAX`: it has power forms);
    /// empty when no patch is evaluated whole.
    whole_index: Vec<u32>,
}

/// Patches per work item of the parallel subdivision: large enough that the items' own
/// buffers cost little, small enough to balance two to dozens of threads.
const SUBDIVISION_CHUNK: usize = 512;

/// Patches per round of the parallel subdivision (see [`PatchBvh::build_in`]): 64 work items.
const SUBDIVISION_ROUND: usize = 64 * SUBDIVISION_CHUNK;

/// What the subdivision of a run of patches produces, in patch order.
#[derive(Default)]
struct Pieces {
    leaves: Vec<Leaf>,
    boxes: Vec<obvhs::aabb::Aabb>,
    /// Blend leaves' bounds for [`PatchBvh::blend_second_bounds`] ([`Leaf::power`] indexes
    /// them).
    blend_second_bounds: Vec<f64>,
    /// Patches evaluated whole, with their index in the surface.
    whole: Vec<(u32, Patch)>,
}

impl Pieces {
    /// Appends one leaf with its box (f32, grown by `padding`) and, for a blend leaf, its
    /// sub-surfaces' bound.
    fn push(&mut self, mut leaf: Leaf, bounds: &Aabb, padding: f64, sub: Option<f64>) {
        if let Some(sub) = sub {
            leaf.power = self.blend_second_bounds.len() as u32;
            self.blend_second_bounds.push(sub);
        }
        self.leaves.push(leaf);
        self.boxes.push(outward_f32(bounds, padding));
    }
}

impl PatchBvh {
    /// Subdivides every patch of `surface` by `criterion` and builds the BVH, in the
    /// surface's own coordinates.
    pub fn build(surface: &Surface, criterion: &SubdivisionCriterion) -> Result<PatchBvh> {
        PatchBvh::build_in(surface, UnitFrame::IDENTITY, criterion)
    }

    /// [`PatchBvh::build`] with the surface mapped into `frame`, one patch at a time (the
    /// surface is never copied whole): leaves, power forms and patches evaluated whole are in
    /// that frame, bit for bit as if the surface had been mapped first.
    pub fn build_in(
        surface: &Surface,
        frame: UnitFrame,
        criterion: &SubdivisionCriterion,
    ) -> Result<PatchBvh> {
        let start = Instant::now();
        if surface.patches.is_empty() {
            return Err(Error::Invalid(format!(
                "surface of scheme '{}' has no patches to render",
                surface.scheme
            )));
        }
        let unit_bounds = |patch: &Patch| match &patch.geometry {
            PatchGeometry::Bezier(net) => net
                .control_points()
                .fold(Aabb::EMPTY, |b, p| b.union_point(frame.map(p))),
            PatchGeometry::Blend(_) => patch.mapped(|p| frame.map(p)).full_bounds(),
        };
        let scene = surface
            .patches
            .par_iter()
            .map(unit_bounds)
            .reduce(|| Aabb::EMPTY, Aabb::union);
        if !scene.min.is_finite() || !scene.max.is_finite() {
            let bad = surface
                .patches
                .iter()
                .position(|p| {
                    let b = unit_bounds(p);
                    !b.min.is_finite() || !b.max.is_finite()
                })
                .unwrap_or(0);
            return Err(Error::Invalid(format!(
                "patch {bad} of scheme '{}' has a non-finite control point",
                surface.scheme
            )));
        }
        let padding = box_padding(&scene);
        // Per-patch subdivision is independent; chunks of patches are collected in patch
        // order, which keeps the leaf list (and so the BVH) identical for any thread count.
        // The chunks are made a round at a time and appended before the next round: their
        // buffers, freed in the workers' allocator arenas, are reused by the next round instead
        // of all being alive at once and then kept by the arenas (a process peak of about
        // 200 MB at a million patches).
        let mut all = Pieces::default();
        for (r, round) in surface.patches.chunks(SUBDIVISION_ROUND).enumerate() {
            let chunks: Vec<Pieces> = round
                .par_chunks(SUBDIVISION_CHUNK)
                .enumerate()
                .map(|(c, patches)| {
                    let mut pieces = Pieces::default();
                    for (k, patch) in patches.iter().enumerate() {
                        let index = (r * SUBDIVISION_ROUND + c * SUBDIVISION_CHUNK + k) as u32;
                        let unit = patch.mapped(|p| frame.map(p));
                        let whole = match &unit.geometry {
                            PatchGeometry::Bezier(net) => {
                                subdivide_patch(&mut pieces, index, net, criterion, padding);
                                net.degree() > MAX_POWER_DEGREE
                            }
                            PatchGeometry::Blend(blend) => {
                                subdivide_blend(
                                    &mut pieces,
                                    index,
                                    &unit,
                                    blend,
                                    criterion,
                                    padding,
                                );
                                true
                            }
                        };
                        if whole {
                            pieces.whole.push((index, unit));
                        }
                    }
                    pieces
                })
                .collect();
            // Exact capacities: grown by doubling, the leaves could hold up to twice their
            // memory at the peak of a large build.
            let leaves: usize = chunks.iter().map(|c| c.leaves.len()).sum();
            all.leaves.reserve_exact(leaves);
            all.boxes.reserve_exact(leaves);
            for chunk in chunks {
                let blend = all.blend_second_bounds.len() as u32;
                all.leaves.extend(chunk.leaves.iter().map(|leaf| Leaf {
                    power: leaf.power + blend,
                    ..*leaf
                }));
                all.boxes.extend_from_slice(&chunk.boxes);
                all.blend_second_bounds
                    .extend_from_slice(&chunk.blend_second_bounds);
                all.whole.extend(chunk.whole);
            }
        }
        let Pieces {
            leaves,
            boxes,
            blend_second_bounds: blend_bounds,
            whole,
        } = all;
        let bvh = build_cwbvh(&boxes, build_params(), &mut Duration::default());
        drop(boxes);
        // Leaves and their power forms in traversal order, so that neighbouring BVH leaves
        // are neighbours in memory too; the forms are made only now, straight into place.
        let (mut leaves, blend_second_bounds) =
            traversal_order(leaves, &blend_bounds, &bvh.primitive_indices);
        let power = power_forms(surface, frame, &mut leaves);
        let mut whole_index = Vec::new();
        if !whole.is_empty() {
            whole_index = vec![u32::MAX; surface.patches.len()];
            for (k, (patch, _)) in whole.iter().enumerate() {
                whole_index[*patch as usize] = k as u32;
            }
        }
        Ok(PatchBvh {
            bvh,
            leaves,
            build_time: start.elapsed(),
            padding,
            scene,
            power,
            blend_second_bounds,
            whole: whole.into_iter().map(|(_, patch)| patch).collect(),
            whole_index,
        })
    }

    /// Bytes held by the BVH, by part: its nodes with their index list, the leaves, their
    /// power forms, the blend leaves' bounds and the patches evaluated whole (with their index).
    pub fn memory_parts(&self) -> [(&'static str, usize); 5] {
        let whole = std::mem::size_of_val(self.whole_index.as_slice())
            + self
                .whole
                .iter()
                .map(|p| std::mem::size_of::<Patch>() + p.control_points().count() * 24)
                .sum::<usize>();
        [
            (
                "bvh_nodes",
                std::mem::size_of_val(self.bvh.nodes.as_slice())
                    + std::mem::size_of_val(self.bvh.primitive_indices.as_slice()),
            ),
            ("leaves", std::mem::size_of_val(self.leaves.as_slice())),
            ("power_forms", std::mem::size_of_val(self.power.as_slice())),
            (
                "blend_bounds",
                std::mem::size_of_val(self.blend_second_bounds.as_slice()),
            ),
            ("whole_patches", whole),
        ]
    }

    /// Bytes held by the BVH: the sum of [`PatchBvh::memory_parts`].
    pub fn memory_bytes(&self) -> usize {
        self.memory_parts().iter().map(|(_, bytes)| bytes).sum()
    }

    /// The patch `patch` in the BVH's frame, if its leaves evaluate it whole (no power form).
    pub fn whole_patch(&self, patch: u32) -> Option<&Patch> {
        let k = *self.whole_index.get(patch as usize)?;
        self.whole.get(k as usize)
    }
}

/// `leaves` (with the blend bounds `blend` they index) rearranged so that leaf `i` is the old
/// leaf `order[i]`; in place when there are no blend leaves.
fn traversal_order(leaves: Vec<Leaf>, blend: &[f64], order: &[u32]) -> (Vec<Leaf>, Vec<f64>) {
    if blend.is_empty() {
        let mut leaves = leaves;
        permute_blocks(&mut leaves, 1, order);
        return (leaves, Vec::new());
    }
    let mut blend_second_bounds = Vec::with_capacity(blend.len());
    let leaves = order
        .iter()
        .map(|&o| {
            let mut leaf = leaves[o as usize];
            if let Some(&bound) = blend.get(leaf.power as usize).filter(|_| leaf.degree == 0) {
                leaf.power = blend_second_bounds.len() as u32;
                blend_second_bounds.push(bound);
            }
            leaf
        })
        .collect();
    (leaves, blend_second_bounds)
}

/// Leaves per work item when the power forms are made.
const POWER_CHUNK: usize = 1024;

/// The power forms of the patches that `leaves` evaluate by one: every Bézier patch with a
/// leaf of degree `1..=MAX_POWER_DEGREE`, its net in `frame` ([`power_coefficients`] over the
/// patch's whole domain), in patch order, made in parallel straight into one array; each such
/// leaf's [`Leaf::power`] is set to the start of its patch's run. One form per patch, not per
/// leaf: a leaf evaluates its patch's form through its domain map
/// ([`LeafMap`](crate::render::evaluate::LeafMap)).
fn power_forms(surface: &Surface, frame: UnitFrame, leaves: &mut [Leaf]) -> Vec<DVec3> {
    let mut start = vec![u32::MAX; surface.patches.len()];
    for leaf in leaves.iter().filter(|leaf| leaf.degree > 0) {
        start[leaf.patch as usize] = 0;
    }
    let mut patches = Vec::new();
    let mut total = 0;
    for (patch, at) in start.iter_mut().enumerate() {
        if *at == u32::MAX {
            continue;
        }
        let Some(net) = surface.patches[patch].as_bezier() else {
            continue;
        };
        *at = total as u32;
        total += point_count(net.degree());
        patches.push((patch, net));
    }
    for leaf in leaves.iter_mut().filter(|leaf| leaf.degree > 0) {
        leaf.power = start[leaf.patch as usize];
    }
    let mut power = vec![DVec3::ZERO; total];
    let mut work = Vec::new();
    let mut rest = power.as_mut_slice();
    for chunk in patches.chunks(POWER_CHUNK) {
        let size = chunk.iter().map(|(_, net)| point_count(net.degree())).sum();
        let (head, tail) = rest.split_at_mut(size);
        work.push((chunk, head));
        rest = tail;
    }
    work.into_par_iter().for_each(|(chunk, out)| {
        let mut at = 0;
        for (_, net) in chunk {
            // The net's points mapped as `TriangleBezier::map_points` maps them (to a net
            // with origin zero), straight into the form: no net or vector per patch, which
            // at millions of patches cost more than the forms themselves.
            let len = point_count(net.degree());
            let point = |i, j| DVec3::ZERO + frame.map(net.point(i, j));
            power_coefficients(net.degree(), point, &mut out[at..at + len]);
            at += len;
        }
    });
    power
}

/// Rearranges `data`, blocks of `block` items, in place so that block `i` becomes the old
/// block `order[i]` (`order` a permutation), following its cycles.
fn permute_blocks<T: Copy>(data: &mut [T], block: usize, order: &[u32]) {
    let mut placed = vec![false; order.len()];
    let mut held = Vec::with_capacity(block);
    for start in 0..order.len() {
        if placed[start] {
            continue;
        }
        held.clear();
        held.extend_from_slice(&data[start * block..(start + 1) * block]);
        let mut i = start;
        loop {
            placed[i] = true;
            let from = order[i] as usize;
            if from == start {
                data[i * block..(i + 1) * block].copy_from_slice(&held);
                break;
            }
            data.copy_within(from * block..(from + 1) * block, i * block);
            i = from;
        }
    }
}

/// PLOC with a medium search radius and a little reinsertion: reinsertion pays for itself
/// once a frame has more rays than the scene has leaves, which is every frame here.
pub(crate) fn build_params() -> BvhBuildParams {
    let mut params = BvhBuildParams::medium_build();
    params.max_prims_per_leaf = 3;
    params
}

/// Leaves of one patch into `out`: recursive 4-split of the control net until [`is_leaf`]
/// and the tilt pass, or the piece stalls ([`Stall`]), each with its box and its power-form
/// coefficients.
fn subdivide_patch(
    out: &mut Pieces,
    patch: u32,
    net: &TriangleBezier,
    criterion: &SubdivisionCriterion,
    padding: f64,
) {
    // Each piece with its parent's shortfall (None for the whole patch) and how many splits in
    // a row have not narrowed it.
    let mut stack = vec![(UV_CORNERS, net.clone(), 0u32, None::<Shortfall>, 0u32)];
    while let Some((tri, piece, depth, parent, stalls)) = stack.pop() {
        let d = piece.degree();
        let corners = [piece.point(d, 0), piece.point(0, d), piece.point(0, 0)];
        // Against the corners as the leaf stores them: the plane its rays are measured from.
        let stored = corners.map(|p| p.as_vec3().as_dvec3());
        let piece_tilt = || tilt(stored, &piece);
        let mut known_tilt = None;
        let passes = depth >= criterion.min_depth
            && depth < criterion.max_depth
            && is_leaf(&piece, criterion)
            && *known_tilt.insert(piece_tilt()) <= criterion.max_tilt;
        let mut shortfall = None;
        let mut stalls = stalls;
        // Below the resolution of the stored corners the leaf's plane is rounding, and no
        // split makes it better (a feature 1e-8 of the scene far from its centre).
        let unresolved = !passes && Stall::below_stored_resolution(&piece, stored);
        let mut stalled = false;
        if !passes && !unresolved && depth < criterion.max_depth {
            let here = Shortfall::of(&piece, stored);
            if let Some(parent) = parent {
                stalls = if here.stalled_from(&parent, criterion) {
                    stalls + 1
                } else {
                    0
                };
                stalled = depth >= criterion.min_depth && stalls >= Stall::SPLITS;
            }
            shortfall = Some(here);
        }
        if passes || stalled || unresolved || depth >= criterion.max_depth {
            let mut leaf = Leaf::new(patch, tri, corners, &[&piece]);
            leaf.tilt = f32_up(known_tilt.unwrap_or_else(piece_tilt));
            leaf.second_bound = second_derivative_bounds(&piece, leaf.normal()).map(f32_up);
            if stalled {
                leaf.extra_search = (criterion.max_depth - depth).min(u32::from(u8::MAX)) as u8;
            }
            if (1..=MAX_POWER_DEGREE).contains(&d) {
                // Its power form is made after the BVH, in traversal order ([`power_forms`]).
                leaf.degree = d as u8;
            }
            out.push(leaf, &piece.control_bounds(), padding, None);
            continue;
        }
        let child_tris = split4(tri);
        // Pushed in reverse so that leaves come out in child order (deterministic layout).
        for c in (0..4).rev() {
            stack.push((
                child_tris[c],
                piece.subdivide(CHILD_CORNERS[c]),
                depth + 1,
                shortfall,
                stalls,
            ));
        }
    }
}

/// When splitting a Bézier piece has stopped helping: the piece folds over and the split did
/// not narrow it.
///
/// The criterion's measures ([`Shortfall`]) shrink in proportion to a piece's size where the
/// patch is regular: a split about halves them. Along a fold of the surface (it doubles back:
/// its normal turns through 180° across a curve of the domain, as over the folded faces of a
/// scan) every piece across the curve holds both normals, its control net's normal cone stays
/// above 90° however small it gets, and splitting it only makes more pieces along the curve,
/// down to [`SubdivisionCriterion::max_depth`]. So a piece that fails the criterion, whose
/// control net turns over (a net normal at [`Stall::FOLD_CONE_DEG`] or more from its corner
/// plane's normal, or no corner plane at all) and none of whose failing measures shrank to
/// [`Stall::RATIO`] of its parent's, for [`Stall::SPLITS`] splits in a row, becomes a leaf as it
/// is, searched as deep as a leaf at `max_depth` ([`Leaf::extra_search`]). A leaf is correct at
/// any size (its bounds come from its own control net, and Newton plus the in-leaf search find
/// its roots); only its speed depends on the criterion.
///
/// A regular surface never turns over within a piece that small, so where the criterion is
/// met today the leaves are the same (the 3.7k-face bunny and the shipped scenes: bit-identical
/// images). Pieces that are merely distorted (the tilt's stretch above one) are not stopped:
/// their measures do shrink, only slowly, and stopping them changed the leaves of clean meshes.
pub(crate) struct Stall;

impl Stall {
    /// A split narrows a measure when the child's is at most this fraction of the parent's
    /// (about one half where the patch is regular).
    pub(crate) const RATIO: f64 = 0.8;
    /// Splits in a row that narrow no failing measure of a folded piece before it stops.
    pub(crate) const SPLITS: u32 = 1;
    /// A control-net normal this far (degrees) from the corner plane's normal: the net turns
    /// over.
    pub(crate) const FOLD_CONE_DEG: f64 = 90.0;

    /// Units of f32 rounding of its corners below which a piece is smaller than the
    /// resolution of the plane a leaf stores ([`Stall::below_stored_resolution`]).
    pub(crate) const STORED_RESOLUTION_ULPS: f64 = 8.0;

    /// True when the corner triangle of the piece `net` is no higher than
    /// [`Stall::STORED_RESOLUTION_ULPS`] f32 roundings of its corners' coordinates (`stored`,
    /// as a leaf keeps them): the plane a leaf stores is then mostly rounding, the tilt
    /// measured against it fails at every depth, and splitting only multiplies the pieces (a
    /// mesh spanning eight orders of magnitude — one stray vertex 1e8 away from a model of
    /// unit size — made 16,384 leaves of every patch, 5.4 million for 382 patches). Such a
    /// piece becomes a leaf as it is, searched to the default depth only (deeper, as for a
    /// folded piece, made a close view of such a model take minutes). In the unit frame
    /// (coordinates up to about 1) that is a piece less than 1e-6 high: below any leaf of a
    /// clean mesh of a million faces.
    ///
    /// A corner triangle of height exactly zero (corners that coincide, as at a collapsed
    /// corner of a patch) is not rounding: its children have planes, so it is split as before
    /// unless the whole piece is that small.
    pub(crate) fn below_stored_resolution(net: &TriangleBezier, stored: [DVec3; 3]) -> bool {
        let d = net.degree();
        let [a, b, c] = [net.point(d, 0), net.point(0, d), net.point(0, 0)];
        let longest = (b - a).length().max((c - b).length()).max((a - c).length());
        let height = (b - a).cross(c - a).length() / longest;
        let magnitude = stored
            .iter()
            .map(|p| p.abs().max_element())
            .fold(0.0, f64::max);
        let resolution = Stall::STORED_RESOLUTION_ULPS * f64::from(f32::EPSILON) * magnitude;
        net.control_bounds().diagonal() <= resolution || (height > 0.0 && height <= resolution)
    }
}

/// The measures of [`SubdivisionCriterion`] of one Bézier piece, against its corner plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Shortfall {
    /// Largest distance of a control point from the corner plane, relative to the net's size;
    /// NaN when the corner triangle is degenerate.
    pub flatness: f64,
    /// Largest angle (degrees) between a control-net triangle normal and the plane's normal;
    /// NaN when the corner triangle is degenerate.
    pub cone_deg: f64,
    /// The [`tilt`] against the stored corners.
    pub tilt: f64,
    /// The tilt's stretch `K` with its rounding allowance ([`tilt_parts`]), uncapped: the
    /// tilt says nothing (is 1) from `K = 1` on, and `K` still shows whether a split narrowed
    /// it. NaN when the corner triangle is degenerate.
    pub stretch: f64,
}

impl Shortfall {
    /// The measures of `net`, whose corners as a leaf stores them are `stored`.
    pub(crate) fn of(net: &TriangleBezier, stored: [DVec3; 3]) -> Shortfall {
        let d = net.degree();
        let p0 = net.point(d, 0);
        let plane = (net.point(0, d) - p0).cross(net.point(0, 0) - p0);
        let size = net.control_bounds().diagonal();
        let plane_len = plane.length();
        let tilt = tilt(stored, net);
        let stretch = tilt_parts(stored, net).map_or(f64::NAN, |(_, k, r)| k + r);
        if !(plane_len > crate::tolerance::DIVISION_GUARD && size > 0.0) {
            return Shortfall {
                flatness: f64::NAN,
                cone_deg: f64::NAN,
                tilt,
                stretch,
            };
        }
        let normal = plane / plane_len;
        let flatness = net
            .control_points()
            .map(|b| (b - p0).dot(normal).abs())
            .fold(0.0, f64::max)
            / size;
        let mut cos = 1.0_f64;
        for i in 0..d {
            for j in 0..d - i {
                let a = net.point(i + 1, j);
                let n = (net.point(i, j + 1) - a).cross(net.point(i, j) - a);
                let len = n.length();
                // As in [`is_leaf`]: collapsed control points carry no direction.
                if len > 1e-12 * size * size {
                    cos = cos.min(n.dot(normal) / len);
                }
            }
        }
        Shortfall {
            flatness,
            cone_deg: cos.clamp(-1.0, 1.0).acos().to_degrees(),
            tilt,
            stretch,
        }
    }

    /// True when this piece, a child of a piece with measures `parent`, turns over
    /// ([`Stall::FOLD_CONE_DEG`], or has no corner plane) and no measure that fails
    /// `criterion` here shrank to [`Stall::RATIO`] of the parent's (for the tilt, neither it
    /// nor its stretch). A measure that is NaN here never shrank; one that was NaN in the
    /// parent did.
    pub(crate) fn stalled_from(
        &self,
        parent: &Shortfall,
        criterion: &SubdivisionCriterion,
    ) -> bool {
        let folded = self.cone_deg >= Stall::FOLD_CONE_DEG || self.flatness.is_nan();
        if !folded {
            return false;
        }
        let shrank = |here: f64, before: f64| {
            here.is_finite() && (!before.is_finite() || here <= Stall::RATIO * before)
        };
        // NaN fails.
        let fails = |here: f64, limit: f64| here.is_nan() || here > limit;
        let narrowed = (fails(self.flatness, criterion.flatness)
            && shrank(self.flatness, parent.flatness))
            || (fails(self.cone_deg, criterion.max_cone_deg)
                && shrank(self.cone_deg, parent.cone_deg))
            || (fails(self.tilt, criterion.max_tilt)
                && (shrank(self.tilt, parent.tilt) || shrank(self.stretch, parent.stretch)));
        !narrowed
    }
}

/// The leaves of a blended patch into `out`: its three sub-surfaces are split along the same
/// sub-triangles until each of their nets passes [`is_leaf`]. The blend over a piece is a
/// convex combination of the three sub-patches at the same parameter, so the box (and the
/// oriented box) around all three nets contains it; the start plane is spanned by the blend's
/// own points at the piece's corners.
fn subdivide_blend(
    out: &mut Pieces,
    patch_index: u32,
    patch: &Patch,
    blend: &BlendPatch,
    criterion: &SubdivisionCriterion,
    padding: f64,
) {
    let mut stack = vec![(UV_CORNERS, blend.sub_surfaces().clone(), 0u32)];
    while let Some((tri, nets, depth)) = stack.pop() {
        let done = depth >= criterion.max_depth
            || (depth >= criterion.min_depth && nets.iter().all(|n| is_leaf(n, criterion)));
        if done {
            let corners = tri.map(|c| patch.eval(c.x, c.y));
            let bounds = nets
                .iter()
                .fold(Aabb::EMPTY, |b, n| b.union(n.control_bounds()));
            let mut leaf = Leaf::new(patch_index, tri, corners, &nets.each_ref());
            let normal = leaf.normal();
            leaf.second_bound = sampled_second_bounds(blend, tri, normal).map(f32_up);
            // Rounded up like the leaves' own bounds, so that it stays a bound.
            let sub = nets
                .iter()
                .map(|n| {
                    let [tangential, along] = second_derivative_bounds(n, normal);
                    f64::from(f32_up(tangential + along))
                })
                .fold(0.0, f64::max);
            // No power form: Newton evaluates the blend itself.
            out.push(leaf, &bounds, padding, Some(sub));
            continue;
        }
        let child_tris = split4(tri);
        for c in (0..4).rev() {
            let children = nets.each_ref().map(|n| n.subdivide(CHILD_CORNERS[c]));
            stack.push((child_tris[c], children, depth + 1));
        }
    }
}
/// How far, in leaf-local `(s, t)` units, a piece's root can lie from the point where a ray
/// perpendicular to the corner plane meets that plane: `δ / σ_min(J_A)`.
///
/// `A(s, t) = c0 + (c1 − c0) s + (c2 − c0) t` is the affine map of the corners; degree-elevated
/// to degree d its control point `(i, j, k)` is `A(j/d, k/d)`, so `S − A` is a Bézier triangle
/// with control points `b(i,j,k) − A(j/d, k/d)` and `|S − A| ≤ δ`, the largest of them, over the
/// piece (convex hull; for a blend, a convex combination of sub-surfaces, the largest over the
/// three nets). A root `x*` puts `A(x*)` within `δ` of the ray, hence within `δ / cos θ` of the
/// ray's meeting point with the corner plane (θ: angle between ray and plane normal), and the
/// preimage under `A` shrinks distances by at most `1 / σ_min(J_A)`. Infinite for a degenerate
/// corner triangle.
pub(crate) fn affine_radius(corners: [DVec3; 3], nets: &[&TriangleBezier]) -> f64 {
    let (e1, e2) = (corners[1] - corners[0], corners[2] - corners[0]);
    let sigma = smallest_singular_value(e1, e2);
    if sigma.is_nan() || sigma <= 0.0 {
        return f64::INFINITY;
    }
    let mut deviation = 0.0_f64;
    for net in nets {
        let d = net.degree().max(1);
        for i in 0..=d {
            for j in 0..=d - i {
                let k = d - i - j;
                let affine = corners[0] + e1 * (j as f64 / d as f64) + e2 * (k as f64 / d as f64);
                deviation = deviation.max((net.point(i, j) - affine).length());
            }
        }
    }
    // A few ulps of the largest coordinate for the rounding of the differences above.
    let magnitude = corners
        .iter()
        .map(|c| c.abs().max_element())
        .fold(0.0, f64::max);
    (deviation + 8.0 * f64::EPSILON * magnitude) / sigma
}

/// A bound on the tangent (so also on the sine) of the angle between any chord
/// `S(x₂) − S(x₁)` of the Bézier triangle `net` and the plane of `corners` (capped at 1, where
/// it says nothing).
///
/// With `δ = x₂ − x₁` the chord is `∫ J(x(τ)) δ dτ = Σ β_m d (δ_s Δ₁b_m + δ_t Δ₂b_m)`, with
/// `β_m ≥ 0` summing to one (the derivative nets' Bernstein weights integrated along the
/// segment [Farin, CAGD §17.3]). In coordinates of the corner plane (orthonormal in-plane
/// axes, then the normal), let `M` map `δ` to `u = δ_s e₁ + δ_t e₂` (`e_i` the corner edges),
/// `g_m` the normal parts and `M + D_m` the in-plane parts of `d [Δ₁b_m Δ₂b_m]`. Then the
/// chord's normal part is `Σ β_m (M⁻ᵀ g_m) · u`, at most `H |u|` with `H = max |M⁻ᵀ g_m|` (the
/// steepest slope of the derivative net over the plane), and its in-plane part is
/// `u + Σ β_m D_m M⁻¹ u`, at least `(1 − K) |u|` with `K = max ‖D_m M⁻¹‖_F`. So every chord
/// makes an angle of tangent at most `H / (1 − K)` with the plane, and a ray at a larger angle
/// is parallel to no chord: it meets the piece at most once.
pub(crate) fn tilt(corners: [DVec3; 3], net: &TriangleBezier) -> f64 {
    let Some((slope, stretch, rounding)) = tilt_parts(corners, net) else {
        return 1.0;
    };
    let tangent = (slope + rounding) / (1.0 - stretch - rounding) * (1.0 + 1e-6);
    if tangent.is_nan() || tangent < 0.0 || stretch + rounding >= 1.0 {
        1.0
    } else {
        tangent.min(1.0)
    }
}

/// The parts of [`tilt`]'s bound: the steepest slope `H` of the derivative net over the corner
/// plane, its in-plane stretch `K` and the rounding allowance added to both; None when the
/// corner triangle is degenerate.
pub(crate) fn tilt_parts(corners: [DVec3; 3], net: &TriangleBezier) -> Option<(f64, f64, f64)> {
    let (e1, e2) = (corners[1] - corners[0], corners[2] - corners[0]);
    let normal = e1.cross(e2).normalize_or_zero();
    let d = net.degree();
    let x = e1.normalize_or_zero();
    if d == 0 || normal == DVec3::ZERO || x == DVec3::ZERO {
        return None;
    }
    let y = normal.cross(x);
    let flat = |v: DVec3| DVec2::new(v.dot(x), v.dot(y));
    // M = [flat(e1) flat(e2)] and its inverse (columns: the images of the unit δ's).
    let (m1, m2) = (flat(e1), flat(e2));
    let det = m1.perp_dot(m2);
    if !det.is_normal() {
        return None;
    }
    // Rows of M⁻¹: M⁻¹ = [[m2.y, −m2.x], [−m1.y, m1.x]] / det.
    let inv_rows = [DVec2::new(m2.y, -m2.x) / det, DVec2::new(-m1.y, m1.x) / det];
    let scale = d as f64;
    let (mut slope, mut stretch) = (0.0_f64, 0.0_f64);
    for i in 0..d {
        for j in 0..d - i {
            // b_m with m = (i, j, k), k = d − 1 − i − j; point(i, j) has weights (i, j, k).
            let base = net.point(i + 1, j);
            let s1 = (net.point(i, j + 1) - base) * scale;
            let s2 = (net.point(i, j) - base) * scale;
            // M⁻ᵀ g: the gradient over the plane of the height whose δ-derivatives are g
            // (component k: column k of M⁻¹ dotted with g).
            let g = DVec2::new(s1.dot(normal), s2.dot(normal));
            let h = DVec2::new(
                inv_rows[0].x * g.x + inv_rows[1].x * g.y,
                inv_rows[0].y * g.x + inv_rows[1].y * g.y,
            );
            slope = slope.max(h.length_squared());
            // D M⁻¹ with D = [flat(s1) − m1, flat(s2) − m2]: columns D·(M⁻¹ columns).
            let (c1, c2) = (flat(s1) - m1, flat(s2) - m2);
            let col = |k: usize| c1 * inv_rows[0][k] + c2 * inv_rows[1][k];
            stretch = stretch.max(col(0).length_squared() + col(1).length_squared());
        }
    }
    // Both were kept squared.
    let (slope, stretch) = (slope.sqrt(), stretch.sqrt());
    // Rounding: the differences carry a few ulps of the coordinates each; relative to the
    // corner edges that is a few ulps of magnitude / σ, well inside a relative 1e-6.
    let magnitude = corners
        .iter()
        .map(|c| c.abs().max_element())
        .fold(0.0, f64::max);
    let sigma = smallest_singular_value(e1, e2);
    let rounding = 64.0 * scale * f64::EPSILON * magnitude / sigma;
    Some((slope, stretch, rounding))
}

/// The smallest singular value of the 3×2 matrix `[a b]`: `|a × b| / σ_max`, with `σ_max²` the
/// larger eigenvalue of the Gram matrix (the product form avoids cancellation on slivers).
pub(crate) fn smallest_singular_value(a: DVec3, b: DVec3) -> f64 {
    let (aa, ab, bb) = (a.length_squared(), a.dot(b), b.length_squared());
    let largest = 0.5 * (aa + bb + ((aa - bb).powi(2) + 4.0 * ab * ab).sqrt());
    if largest > 0.0 {
        a.cross(b).length() / largest.sqrt()
    } else {
        0.0
    }
}

/// An estimate of the bounds of [`second_derivative_bounds`] for a blended patch over the
/// sub-triangle `tri`, in its leaf-local `(s, t)` units: the rational weights admit no
/// control-net bound, so the exact second derivatives are sampled at the corners, edge
/// midpoints and interior points of the piece and the largest `|S_ss| + |S_st| + |S_tt|` of
/// each part is doubled. Not a proof: the blend is the one patch kind whose misses are not
/// certified.
pub(crate) fn sampled_second_bounds(
    blend: &BlendPatch,
    tri: [DVec2; 3],
    normal: DVec3,
) -> [f64; 2] {
    let (e1, e2) = (tri[1] - tri[0], tri[2] - tri[0]);
    const SAMPLES: [(f64, f64); 10] = [
        (0.0, 0.0),
        (1.0, 0.0),
        (0.0, 1.0),
        (0.5, 0.0),
        (0.5, 0.5),
        (0.0, 0.5),
        (1.0 / 3.0, 1.0 / 3.0),
        (2.0 / 3.0, 1.0 / 6.0),
        (1.0 / 6.0, 2.0 / 3.0),
        (1.0 / 6.0, 1.0 / 6.0),
    ];
    let mut bound = [0.0_f64; 2];
    for (s, t) in SAMPLES {
        let uv = tri[0] + e1 * s + e2 * t;
        let jet = blend.jet(uv.x, uv.y);
        let second = |a: DVec2, b: DVec2| {
            jet.duu * (a.x * b.x) + jet.duv * (a.x * b.y + a.y * b.x) + jet.dvv * (a.y * b.y)
        };
        for q in [second(e1, e1), second(e1, e2), second(e2, e2)] {
            let along = q.dot(normal);
            bound = [
                bound[0].max((q - normal * along).length()),
                bound[1].max(along.abs()),
            ];
        }
    }
    bound.map(|b| {
        if b.is_finite() {
            6.0 * b
        } else {
            f64::INFINITY
        }
    })
}

/// Growth of the edge prism beyond the control points, relative to the leaf's box size. The
/// solver accepts roots only in the leaf's closed domain triangle (it projects its iterates
/// into it, [`crate::render::newton`]), so the pad covers the rounding of the prism's planes
/// and of the f32 bounds, with a wide margin for every degree up to 6.
pub(crate) const PRISM_PAD: f64 = 1e-5;

/// Largest degree given a power form (the degrees the intersection code specialises).
pub(crate) const MAX_POWER_DEGREE: usize = 6;

/// The flatness and normal-cone test of [`SubdivisionCriterion`] on one control net.
pub(crate) fn is_leaf(net: &TriangleBezier, criterion: &SubdivisionCriterion) -> bool {
    let d = net.degree();
    let p0 = net.point(d, 0);
    let p1 = net.point(0, d);
    let p2 = net.point(0, 0);
    let plane = (p1 - p0).cross(p2 - p0);
    let size = net.control_bounds().diagonal();
    let plane_len = plane.length();
    if plane_len.is_nan()
        || plane_len <= crate::tolerance::DIVISION_GUARD
        || size.is_nan()
        || size <= 0.0
    {
        // A degenerate corner triangle has no plane to be flat against.
        return d <= 1 && size == 0.0;
    }
    let normal = plane / plane_len;
    let flat_limit = criterion.flatness * size;
    if net
        .control_points()
        .any(|b| (b - p0).dot(normal).abs() > flat_limit)
    {
        return false;
    }
    let cos_limit = criterion.max_cone_deg.to_radians().cos();
    for i in (0..d).rev() {
        for j in (0..d - i).rev() {
            // The "upward" micro-triangle b(i+1,j,k), b(i,j+1,k), b(i,j,k+1), k = d−1−i−j.
            let a = net.point(i + 1, j);
            let b = net.point(i, j + 1);
            let c = net.point(i, j);
            let n = (b - a).cross(c - a);
            let len = n.length();
            // Collapsed control points (e.g. at a singular corner) carry no direction.
            if len > 1e-12 * size * size && n.dot(normal) < cos_limit * len {
                return false;
            }
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    /// No chord of a curved, unevenly parametrised net is steeper against the corner plane
    /// than its tilt, and on a paraboloid with an affine parametrisation the tilt is the
    /// steepest slope itself (the gradient is linear, so largest at a corner).
    #[test]
    fn tilt_bounds_every_chord_and_is_tight_on_a_paraboloid() {
        let mut rng = crate::testing::Rng::new(5);
        let mut bounded = 0;
        for case in 0..300 {
            let d = 1 + case % 6;
            let bend = rng.range(0.0, 0.1);
            let stretch = rng.range(0.0, 0.04);
            let seed = rng.next_u64();
            let mut noise = crate::testing::Rng::new(seed);
            let net = TriangleBezier::from_fn(d, |_, j, k| {
                let (s, t) = (j as f64 / d as f64, k as f64 / d as f64);
                DVec3::new(
                    s + 0.8 * t + stretch * noise.range(-1.0, 1.0),
                    0.2 * s + 0.5 * t + stretch * noise.range(-1.0, 1.0),
                    bend * noise.range(-1.0, 1.0),
                )
            });
            let corners = [net.point(d, 0), net.point(0, d), net.point(0, 0)];
            let bound = tilt(corners, &net);
            if bound >= 1.0 {
                continue;
            }
            bounded += 1;
            let normal = (corners[1] - corners[0])
                .cross(corners[2] - corners[0])
                .normalize();
            let at = |r: &mut crate::testing::Rng| {
                let b = r.bary_inside();
                net.eval(b)
            };
            for _ in 0..200 {
                let chord = at(&mut rng) - at(&mut rng);
                let sine = chord.dot(normal).abs() / chord.length();
                assert!(
                    sine <= bound,
                    "case {case}: chord sine {sine} > tilt {bound}"
                );
            }
        }
        assert!(bounded > 150, "only {bounded} of 300 nets had a bound");
        // h = κ (s² + t² − s − t) over a skewed triangle with corners 0, a, b in the plane
        // z = 0 (h vanishes at the corners): its gradient over the plane is M⁻ᵀ ∇h, M = [a b],
        // ∇h = κ (2s − 1, 2t − 1) linear, so steepest at a corner. The quadratic net (the
        // blossom's values): 0 at the corners, −κ/2 at the midpoints of the edges from the
        // first corner, −κ at the third edge's.
        let kappa = 0.2;
        let (a, b) = (DVec2::new(1.0, 0.1), DVec2::new(0.7, 0.8));
        let quad = TriangleBezier::from_fn(2, |i, j, k| {
            let z = match (i, j, k) {
                (1, 1, 0) | (1, 0, 1) => -0.5 * kappa,
                (0, 1, 1) => -kappa,
                _ => 0.0,
            };
            let xy = a * (j as f64 / 2.0) + b * (k as f64 / 2.0);
            DVec3::new(xy.x, xy.y, z)
        });
        let corners = [quad.point(2, 0), quad.point(0, 2), quad.point(0, 0)];
        let bound = tilt(corners, &quad);
        let inverse_transpose = glam::DMat2::from_cols(a, b).inverse().transpose();
        let steepest = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)]
            .map(|(s, t)| {
                (inverse_transpose * (DVec2::new(2.0 * s - 1.0, 2.0 * t - 1.0) * kappa)).length()
            })
            .into_iter()
            .fold(0.0, f64::max);
        assert!(
            bound >= steepest && bound <= steepest * (1.0 + 1e-5),
            "tilt {bound} against the steepest slope {steepest}"
        );
    }

    /// The leaves of one Bézier patch under `criterion`.
    fn leaves_of(net: &TriangleBezier, criterion: &SubdivisionCriterion) -> Vec<Leaf> {
        let mut pieces = Pieces::default();
        subdivide_patch(&mut pieces, 0, net, criterion, 0.0);
        pieces.leaves
    }

    /// Twice the area of the leaves' domain triangles (1 when they tile the patch's domain).
    fn doubled_area(leaves: &[Leaf]) -> f64 {
        leaves
            .iter()
            .map(|l| {
                let t = l.tri();
                (t[1] - t[0]).perp_dot(t[2] - t[0])
            })
            .sum()
    }

    /// A quadratic net that folds over in its own plane: along the edge from the first corner
    /// to the second, `x = 4s − 3s²` runs out to 4/3 and back to 1, so the surface doubles back
    /// across a curve of the domain and every piece across that curve holds normals `+z` and
    /// `−z`. Without the stall rule each of them is split to `max_depth`; with it the pieces
    /// across the fold stop as soon as a split no longer narrows them, and are searched deeper
    /// instead.
    #[test]
    fn a_fold_stops_splitting_with_a_bounded_piece_count() {
        let net = TriangleBezier::new(
            2,
            vec![
                DVec3::new(0.0, 0.0, 0.0), // b(2,0,0): corner 0
                DVec3::new(2.0, 0.0, 0.0), // b(1,1,0)
                DVec3::new(0.0, 0.5, 0.0), // b(1,0,1)
                DVec3::new(1.0, 0.0, 0.0), // b(0,2,0): corner 1
                DVec3::new(0.5, 0.5, 0.0), // b(0,1,1)
                DVec3::new(0.0, 1.0, 0.0), // b(0,0,2): corner 2
            ],
        );
        let criterion = SubdivisionCriterion::default();
        let root = Shortfall::of(&net, [net.point(2, 0), net.point(0, 2), net.point(0, 0)]);
        assert!(root.cone_deg > 170.0, "the net turns over: {root:?}");
        let leaves = leaves_of(&net, &criterion);
        assert_eq!(doubled_area(&leaves), 1.0, "the leaves tile the domain");
        let stalled: Vec<&Leaf> = leaves.iter().filter(|l| l.extra_search > 0).collect();
        assert!(!stalled.is_empty(), "the pieces across the fold stall");
        for leaf in &stalled {
            // Area of a leaf at depth k is 4^-k of the domain: its extra search reaches depth 7.
            let t = leaf.tri();
            let depth = (1.0 / (t[1] - t[0]).perp_dot(t[2] - t[0])).log(4.0).round() as u32;
            assert_eq!(u32::from(leaf.extra_search), criterion.max_depth - depth);
        }
        // Along the fold a depth-7 split makes hundreds of pieces.
        assert!(
            leaves.len() <= 100,
            "{} leaves ({} stalled)",
            leaves.len(),
            stalled.len()
        );
        // A deeper criterion changes nothing across the fold: the pieces already stopped.
        let deeper = SubdivisionCriterion {
            max_depth: 12,
            ..criterion
        };
        assert!(leaves_of(&net, &deeper).len() <= 2 * leaves.len());
    }

    /// A curved patch far smaller than the f32 resolution of where it lies (1e-9 across, half
    /// a unit from the frame's centre: a model of unit size beside a stray vertex 1e9 away)
    /// is one leaf: its stored corners cannot describe its plane, so the tilt fails at every
    /// depth and splitting would make 4^7 pieces of it. The same patch at unit size is split
    /// as usual, and one just above the resolution too.
    #[test]
    fn a_piece_below_the_stored_resolution_is_one_leaf() {
        let d = 5;
        let bump = |scale: f64, offset: DVec3| {
            TriangleBezier::from_fn(d, |_, j, k| {
                let (s, t) = (j as f64 / d as f64, k as f64 / d as f64);
                let (x, y) = (s + 0.3 * t, t);
                offset + DVec3::new(x, y, -0.8 * (x * x + y * y)) * scale
            })
        };
        let criterion = SubdivisionCriterion::default();
        let far = DVec3::splat(0.5);
        let unit = leaves_of(&bump(1.0, far), &criterion);
        assert!(unit.len() > 4, "{} leaves at unit size", unit.len());
        let tiny = bump(1e-9, far);
        let stored = [tiny.point(d, 0), tiny.point(0, d), tiny.point(0, 0)];
        assert!(Stall::below_stored_resolution(
            &tiny,
            stored.map(|p| p.as_vec3().as_dvec3())
        ));
        let leaves = leaves_of(&tiny, &criterion);
        assert_eq!(leaves.len(), 1, "one leaf below the resolution");
        assert_eq!(leaves[0].extra_search, 0);
        // 1e-4 across is over a thousand f32 roundings of its place: resolved, and split.
        let small = bump(1e-4, far);
        let stored = [small.point(d, 0), small.point(0, d), small.point(0, 0)];
        assert!(!Stall::below_stored_resolution(
            &small,
            stored.map(|p| p.as_vec3().as_dvec3())
        ));
        assert!(leaves_of(&small, &criterion).len() > 4);
    }

    /// A regular curved patch (a paraboloid cap, normals within 60° of each other) never
    /// stalls: its measures halve with every split, and its leaves all meet the criterion.
    #[test]
    fn a_regular_patch_never_stalls() {
        let d = 4;
        let net = TriangleBezier::from_fn(d, |_, j, k| {
            let (s, t) = (j as f64 / d as f64, k as f64 / d as f64);
            DVec3::new(s + 0.3 * t, t, 0.0)
        });
        // Lift the control points onto the paraboloid's blossom approximately: a bump.
        let bumped = TriangleBezier::new(
            d,
            net.control_points()
                .map(|p| DVec3::new(p.x, p.y, -0.8 * (p.x * p.x + p.y * p.y)))
                .collect(),
        );
        let criterion = SubdivisionCriterion::default();
        let leaves = leaves_of(&bumped, &criterion);
        assert!(
            leaves.len() > 4,
            "the bump is split ({} leaves)",
            leaves.len()
        );
        assert_eq!(doubled_area(&leaves), 1.0);
        assert!(leaves.iter().all(|l| l.extra_search == 0));
        assert!(
            leaves
                .iter()
                .all(|l| f64::from(l.tilt) <= criterion.max_tilt)
        );
    }

    /// One power form per patch, shared by its leaves: each Bézier leaf's run is its patch's
    /// net in the BVH's frame in power form, bit for bit, and the forms hold one run per patch
    /// with leaves, however many leaves it has.
    #[test]
    fn each_patch_has_one_power_form_shared_by_its_leaves() {
        let surface = crate::testing::surfaces::octahedron_sphere(5, 3.0, 1);
        let frame = UnitFrame {
            centre: DVec3::new(0.25, -0.5, 1.0),
            scale: 0.5,
        };
        let criterion = SubdivisionCriterion {
            flatness: 0.002,
            ..SubdivisionCriterion::default()
        };
        let bvh = PatchBvh::build_in(&surface, frame, &criterion).expect("bvh");
        let mut patches = std::collections::BTreeSet::new();
        for leaf in bvh.leaves.iter().filter(|leaf| leaf.degree > 0) {
            let PatchGeometry::Bezier(net) = &surface.patches[leaf.patch as usize].geometry else {
                panic!("octahedron patches are Bézier nets");
            };
            let mapped = net.map_points(|p| frame.map(p));
            let mut form = vec![DVec3::ZERO; point_count(5)];
            power_coefficients(5, |i, j| mapped.point(i, j), &mut form);
            let at = leaf.power as usize;
            assert_eq!(
                &bvh.power[at..at + form.len()],
                form.as_slice(),
                "leaf {leaf:?}"
            );
            patches.insert(leaf.patch);
        }
        assert_eq!(bvh.power.len(), patches.len() * point_count(5));
        assert!(
            bvh.leaves.len() >= 8 * patches.len(),
            "the patches should be split into many leaves: {} leaves, {} patches",
            bvh.leaves.len(),
            patches.len()
        );
    }

    #[test]
    fn split4_children_tile_the_parent() {
        let tri = UV_CORNERS;
        let children = split4(tri);
        let area = |t: [DVec2; 3]| 0.5 * (t[1] - t[0]).perp_dot(t[2] - t[0]);
        let total: f64 = children.iter().map(|c| area(*c)).sum();
        assert_eq!(total, area(tri), "children cover the parent's area");
        for c in children {
            assert!(area(c) > 0.0, "child {c:?} keeps the orientation");
        }
    }

    /// The box test as written directly, slab by slab from the origin's own coordinates (the
    /// form [`BoxFromOrigin`] rearranges): `o < lo` where it tests `lo − o > 0`.
    fn direct_box_test(leaf: &Leaf, origin: DVec3, dir: DVec3, t_min: f64, t_max: f64) -> bool {
        let local_origin = leaf.box_coordinates(origin);
        let (mut near, mut far) = (t_min, t_max);
        let mut local_dir = DVec3::ZERO;
        for axis in 0..3 {
            let (o, d) = (local_origin[axis], leaf.axes[axis].as_dvec3().dot(dir));
            local_dir[axis] = d;
            let (lo, hi) = (f64::from(leaf.lo[axis]), f64::from(leaf.hi[axis]));
            if d == 0.0 {
                if o < lo || o > hi {
                    return false;
                }
                continue;
            }
            let inv = 1.0 / d;
            let (t0, t1) = ((lo - o) * inv, (hi - o) * inv);
            near = near.max(t0.min(t1));
            far = far.min(t0.max(t1));
            if near > far {
                return false;
            }
        }
        for e in 0..3 {
            let n = DVec2::from(leaf.edge_normals[e].map(f64::from));
            let h = f64::from(leaf.edge_hi[e]);
            let o = n.x * local_origin.x + n.y * local_origin.y;
            let d = n.x * local_dir.x + n.y * local_dir.y;
            if d == 0.0 {
                if o > h {
                    return false;
                }
                continue;
            }
            let reach = (h - o) / d;
            if d > 0.0 {
                far = far.min(reach);
            } else {
                near = near.max(reach);
            }
            if near > far {
                return false;
            }
        }
        true
    }

    /// The box test of single rays ([`Leaf::ray_meets_box`]) and of bundles ([`BoxFromOrigin`])
    /// gives the direct slab test's answer for every ray: random ones, rays parallel to the box's
    /// sides and the prism's edge planes (a direction coordinate exactly 0) from origins
    /// inside, outside and exactly on them, and intervals that end before, inside and beyond
    /// the box.
    #[test]
    fn single_ray_and_bundle_box_tests_are_the_direct_slab_test() {
        // Corners on the x and y axes: the box frame is exactly the coordinate frame, so
        // directions along the axes meet slabs and edges at exactly zero.
        let net = TriangleBezier::from_fn(3, |i, j, k| {
            let (s, t) = (j as f64 / 3.0, k as f64 / 3.0);
            let bump = if i > 0 && j > 0 && k > 0 { 0.2 } else { 0.0 };
            DVec3::new(s, t, bump - 0.05 * (j * k) as f64)
        });
        let corners = [net.point(3, 0), net.point(0, 3), net.point(0, 0)];
        let leaf = Leaf::new(0, UV_CORNERS, corners, &[&net]);
        assert_eq!(leaf.axes, [Vec3::X, Vec3::Y, Vec3::Z]);
        let mut rng = crate::testing::Rng::new(17);
        let mut point_in = |lo: DVec3, hi: DVec3| {
            DVec3::new(
                rng.range(lo.x, hi.x),
                rng.range(lo.y, hi.y),
                rng.range(lo.z, hi.z),
            )
        };
        let around = (DVec3::new(-1.0, -1.0, -1.0), DVec3::new(2.0, 2.0, 1.0));
        let mut origins: Vec<DVec3> = (0..300).map(|_| point_in(around.0, around.1)).collect();
        let mut directions: Vec<DVec3> = (0..300)
            .map(|_| point_in(-DVec3::ONE, DVec3::ONE).normalize())
            .collect();
        // Origins on the box's faces and on the prism's edge planes.
        let (lo, hi) = (leaf.lo.as_dvec3(), leaf.hi.as_dvec3());
        for axis in 0..3 {
            for face in [lo[axis], hi[axis]] {
                let mut o = (lo + hi) * 0.5;
                o[axis] = face;
                origins.push(o);
            }
        }
        let edge_normals = leaf.edge_normals.map(|n| DVec2::from(n.map(f64::from)));
        for (n, h) in edge_normals.into_iter().zip(leaf.edge_hi.map(f64::from)) {
            // On the edge's plane: `n · (x, y) = h` exactly, nudged by ulps until so
            // (alternately in x and y: one ulp of one coordinate can step over `h`).
            let centre = (lo + hi) * 0.5;
            let mut o = centre + (n * (h - n.dot(centre.truncate()))).extend(0.0);
            for _ in 0..4 {
                o += (n * (h - (n.x * o.x + n.y * o.y))).extend(0.0);
            }
            for step in 0..256 {
                let v = n.x * o.x + n.y * o.y;
                if v == h {
                    break;
                }
                let (coordinate, along) = if step % 2 == 0 {
                    (&mut o.x, n.x)
                } else {
                    (&mut o.y, n.y)
                };
                if along != 0.0 {
                    *coordinate = if (v < h) == (along > 0.0) {
                        coordinate.next_up()
                    } else {
                        coordinate.next_down()
                    };
                }
            }
            origins.push(o);
        }
        for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
            directions.extend([axis, -axis]);
        }
        // Along each edge of the prism: `n · (dx, dy)` is exactly 0.
        directions.extend(edge_normals.map(|n| DVec3::new(-n.y, n.x, 0.0)));
        let intervals = [(0.0, f64::INFINITY), (0.0, 0.5), (0.5, 3.0), (-3.0, 0.0)];
        let (mut met, mut missed) = (0, 0);
        for &origin in &origins {
            for &dir in &directions {
                for (t_min, t_max) in intervals {
                    let direct = direct_box_test(&leaf, origin, dir, t_min, t_max);
                    let seen = BoxFromOrigin::new(&leaf, leaf.box_coordinates(origin));
                    for (path, answer) in [
                        ("single ray", leaf.ray_meets_box(origin, dir, t_min, t_max)),
                        ("bundle", seen.meets(dir, t_min, t_max)),
                    ] {
                        assert_eq!(
                            answer, direct,
                            "{path}: origin {origin}, direction {dir}, interval ({t_min}, {t_max})"
                        );
                    }
                    if direct { met += 1 } else { missed += 1 }
                }
            }
        }
        // Both answers occur often: the comparison is not between two constant answers.
        assert!(
            met > 10_000 && missed > 100_000,
            "{met} met, {missed} missed"
        );
    }

    #[test]
    fn outward_rounding_contains_the_f64_box() {
        let b = Aabb {
            min: DVec3::new(0.1, -0.3, 1.0 / 3.0),
            max: DVec3::new(0.7, 1e-9, 2.0 / 3.0),
        };
        let f = outward_f32(&b, 0.0);
        for axis in 0..3 {
            assert!(f64::from(f.min[axis]) <= b.min[axis], "min axis {axis}");
            assert!(f64::from(f.max[axis]) >= b.max[axis], "max axis {axis}");
        }
    }
}
