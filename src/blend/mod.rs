//! Boundary-blended patches: a non-polynomial patch `S = Σ w_i S_i` that blends three
//! polynomial sub-surfaces `S_0, S_1, S_2` (Bézier triangles over the same domain) with
//! rational weights ([`weights`]) — Nielson's side-vertex blend and Fang–Mann's `C^t` blend
//! \[FM\]. Sub-surface `i` "owns" the edge opposite corner `i` (where `b_i = 0`): its weight is
//! one there.
//!
//! What the rest of smoothlab needs from a patch, a blend provides exactly:
//! * **Position and derivatives** ([`BlendPatch::jet`]): `S = S_{c+1} + w_{c+2}(S_{c+2} −
//!   S_{c+1}) + w_c (S_c − S_{c+1})` differentiated by the Leibniz rule, with the weight
//!   derivatives from the quotient rule ([`scalar_jet`]). `c` is the corner nearest to the
//!   point; the differences are evaluated from difference nets, so near corner `c`, where
//!   `S_{c+2} − S_{c+1}` vanishes like the distance `r` while the weight gradients grow like
//!   `1/r`, their product keeps full relative accuracy instead of amplifying rounding.
//! * **Corners** (within [`CORNER_RADIUS`] of a corner, barycentrically): the weights have no
//!   limit there ([FM, "Restrictions of Nielson's Method"]). The position is the blend with the
//!   weight of the far sub-surface dropped (it is `O(r^{t+1})` or multiplies a difference that
//!   is `O(r²)`), so a corner evaluates to the common vertex. The derivatives are those of the
//!   mean of the two sub-surfaces through the corner. Both interpolate the vertex and its
//!   normal, so the normal is the vertex normal; for Nielson's blend, whose sub-surfaces share
//!   the corner's first derivatives, this is the true limit of the first derivatives; for
//!   Fang–Mann's it is a bounded, direction-independent stand-in for derivatives whose limit
//!   depends on the direction of approach. Curvature at a corner has no limit in either
//!   family; the value reported there is that of the mean sub-surface.
//! * **Bounds** ([`BlendPatch::sub_triangle_bounds`]): the weights are non-negative and sum to
//!   one, so every point is a convex combination of the three sub-surfaces at the same
//!   parameter and the blend over a sub-triangle lies in the union of the sub-surfaces'
//!   sub-triangle control-net boxes.

pub(crate) mod scalar_jet;
pub(crate) mod taylor;
pub(crate) mod weights;

use glam::DVec3;

use crate::bezier::TriangleBezier;
use crate::geom::{Aabb, Jet};
use scalar_jet::{Scalar, ScalarJet, ScalarJet1};
pub(crate) use weights::WeightFamily;

/// Points whose two smaller barycentric coordinates sum to less than this are evaluated as
/// corner points (see the module documentation). Chosen so that the weight derivatives
/// (`~1/r` and `~1/r²`) stay far from overflow while the normal of the corner evaluation
/// differs from the exact one by `O(r)`, below 1e-9 rad.
pub(crate) const CORNER_RADIUS: f64 = 1e-9;

/// Three sub-surfaces of one degree and the weights that blend them.
#[derive(Clone, Debug, PartialEq)]
pub struct BlendPatch {
    family: WeightFamily,
    sub_surfaces: [TriangleBezier; 3],
    /// `differences[c] = S_{c+2} − S_{c+1}` (indices mod 3): zero at corner `c` for both
    /// families, since both sub-surfaces through a corner interpolate its vertex.
    differences: [TriangleBezier; 3],
}

/// `acc += f · d` for a scalar jet `f` and a vector jet `d` (Leibniz rule to order two).
#[inline(always)]
fn add_product(acc: &mut Jet, f: ScalarJet, d: &Jet) {
    acc.p += f.v * d.p;
    acc.du += f.du * d.p + f.v * d.du;
    acc.dv += f.dv * d.p + f.v * d.dv;
    acc.duu += f.duu * d.p + 2.0 * f.du * d.du + f.v * d.duu;
    acc.duv += f.duv * d.p + f.du * d.dv + f.dv * d.du + f.v * d.duv;
    acc.dvv += f.dvv * d.p + 2.0 * f.dv * d.dv + f.v * d.dvv;
}

/// Index of the largest barycentric coordinate (the nearest corner).
#[inline(always)]
fn nearest_corner(b: [f64; 3]) -> usize {
    if b[0] >= b[1] && b[0] >= b[2] {
        0
    } else if b[1] >= b[2] {
        1
    } else {
        2
    }
}

impl BlendPatch {
    /// A blend of `sub_surfaces` (sub-surface `i` owns the edge opposite corner `i`). Lower
    /// degrees are elevated to the highest one so that the difference nets exist.
    pub fn new(family: WeightFamily, sub_surfaces: [TriangleBezier; 3]) -> Self {
        let degree = sub_surfaces.iter().map(|s| s.degree()).max().unwrap_or(0);
        let sub_surfaces = sub_surfaces.map(|mut s| {
            while s.degree() < degree {
                s = s.elevate();
            }
            s
        });
        let difference = |a: &TriangleBezier, b: &TriangleBezier| {
            // (o_a + a_n) − (o_b + b_n), the offsets' difference first: exact to their own
            // rounding where the two share an origin.
            let shift = a.origin() - b.origin();
            let points = a
                .offsets()
                .iter()
                .zip(b.offsets())
                .map(|(p, q)| (*p - *q) + shift);
            TriangleBezier::new(degree, points.collect())
        };
        let differences = std::array::from_fn(|c| {
            difference(&sub_surfaces[(c + 2) % 3], &sub_surfaces[(c + 1) % 3])
        });
        BlendPatch {
            family,
            sub_surfaces,
            differences,
        }
    }

    /// The weight family.
    pub fn family(&self) -> WeightFamily {
        self.family
    }

    /// The three sub-surfaces (all of [`BlendPatch::degree`]).
    pub fn sub_surfaces(&self) -> &[TriangleBezier; 3] {
        &self.sub_surfaces
    }

    /// Degree of the sub-surfaces.
    pub fn degree(&self) -> usize {
        self.sub_surfaces[0].degree()
    }

    /// The weights `w_0, w_1, w_2` at `(u, v)` (barycentric `(1−u−v, u, v)`), with the corner
    /// convention of the module documentation.
    pub fn weights_at(&self, u: f64, v: f64) -> [f64; 3] {
        let b = [1.0 - u - v, u, v].map(|x| x.max(0.0));
        let c = nearest_corner(b);
        if b[(c + 1) % 3] + b[(c + 2) % 3] < CORNER_RADIUS {
            corner_weights(self.family, c, b)
        } else {
            weights::weights(self.family, b)
        }
    }

    /// Point at `(u, v)`.
    pub fn eval(&self, u: f64, v: f64) -> DVec3 {
        let bary = DVec3::new(1.0 - u - v, u, v);
        let w = self.weights_at(u, v);
        let c = nearest_corner([bary.x, bary.y, bary.z]);
        let (next, far) = ((c + 1) % 3, (c + 2) % 3);
        // S = S_next + w_far (S_far − S_next) + w_c (S_c − S_next).
        self.sub_surfaces[next].eval(bary) + w[far] * self.differences[c].eval(bary)
            - w[c] * self.differences[far].eval(bary)
    }

    /// Position and exact first and second derivatives at `(u, v)`.
    pub fn jet(&self, u: f64, v: f64) -> Jet {
        let raw = [1.0 - u - v, u, v];
        let c = nearest_corner(raw);
        let (next, far) = ((c + 1) % 3, (c + 2) % 3);
        let mut jet = self.sub_surfaces[next].jet(u, v);
        let towards_far = self.differences[c].jet(u, v);
        let clamped = raw.map(|x| x.max(0.0));
        if clamped[next] + clamped[far] < CORNER_RADIUS {
            let w = corner_weights(self.family, c, clamped);
            let mean_slope = ScalarJet::constant(0.5);
            let p = jet.p + w[far] * towards_far.p;
            add_product(&mut jet, mean_slope, &towards_far);
            jet.p = p;
            return jet;
        }
        let b = [
            ScalarJet::affine(raw[0], -1.0, -1.0),
            ScalarJet::affine(raw[1], 1.0, 0.0),
            ScalarJet::affine(raw[2], 0.0, 1.0),
        ]
        .map(Scalar::nonnegative);
        let w = weights::weights(self.family, b);
        let from_next_back = self.differences[far].jet(u, v);
        add_product(&mut jet, w[far], &towards_far);
        add_product(&mut jet, w[c].scale(-1.0), &from_next_back);
        jet
    }

    /// Position and first derivatives at `(u, v)` — what Newton needs, with first-order
    /// weight jets only. Equal to the corresponding parts of [`BlendPatch::jet`].
    pub fn point_and_tangents(&self, u: f64, v: f64) -> (DVec3, DVec3, DVec3) {
        let raw = [1.0 - u - v, u, v];
        let c = nearest_corner(raw);
        let (next, far) = ((c + 1) % 3, (c + 2) % 3);
        let clamped = raw.map(|x| x.max(0.0));
        if clamped[next] + clamped[far] < CORNER_RADIUS {
            let jet = self.jet(u, v);
            return (jet.p, jet.du, jet.dv);
        }
        let base = self.sub_surfaces[next].jet(u, v);
        let towards_far = self.differences[c].jet(u, v);
        let from_next_back = self.differences[far].jet(u, v);
        let b = [
            ScalarJet1 {
                v: raw[0],
                du: -1.0,
                dv: -1.0,
            },
            ScalarJet1 {
                v: raw[1],
                du: 1.0,
                dv: 0.0,
            },
            ScalarJet1 {
                v: raw[2],
                du: 0.0,
                dv: 1.0,
            },
        ]
        .map(Scalar::nonnegative);
        let w = weights::weights(self.family, b);
        let (wf, wc) = (w[far], w[c]);
        (
            base.p + wf.v * towards_far.p - wc.v * from_next_back.p,
            base.du + wf.du * towards_far.p + wf.v * towards_far.du
                - wc.du * from_next_back.p
                - wc.v * from_next_back.du,
            base.dv + wf.dv * towards_far.p + wf.v * towards_far.dv
                - wc.dv * from_next_back.p
                - wc.v * from_next_back.dv,
        )
    }

    /// All partial derivatives `∂^{i+j} S / ∂u^i ∂v^j`, `i + j ≤ max_order` (at most
    /// [`taylor::ORDER`]), in the order of [`TriangleBezier::partials`], from the weights in
    /// truncated Taylor arithmetic and the sub-surfaces' exact partials. `None` within
    /// [`CORNER_RADIUS`] of a corner, where the weights have no expansion.
    pub fn partials(&self, u: f64, v: f64, max_order: usize) -> Option<Vec<DVec3>> {
        let raw = [1.0 - u - v, u, v];
        let c = nearest_corner(raw);
        let (next, far) = ((c + 1) % 3, (c + 2) % 3);
        let clamped = raw.map(|x| x.max(0.0));
        if clamped[next] + clamped[far] < CORNER_RADIUS {
            return None;
        }
        let order = taylor::ORDER;
        let series = |s: &TriangleBezier| taylor::from_partials(&s.partials(u, v, order));
        let mut total = series(&self.sub_surfaces[next]);
        let b = [
            taylor::Taylor::affine(raw[0], -1.0, -1.0),
            taylor::Taylor::affine(raw[1], 1.0, 0.0),
            taylor::Taylor::affine(raw[2], 0.0, 1.0),
        ]
        .map(Scalar::nonnegative);
        let w = weights::weights(self.family, b);
        taylor::add_product(&mut total, &w[far], &series(&self.differences[c]));
        taylor::add_product(
            &mut total,
            &w[c].scale(-1.0),
            &series(&self.differences[far]),
        );
        Some(taylor::to_partials(&total, max_order))
    }

    /// A box containing the blend over the sub-triangle with barycentric `corners`: the union
    /// of the sub-surfaces' boxes there (convex combination), grown by a bound on the rounding
    /// of the blend's own sums.
    pub fn sub_triangle_bounds(&self, corners: [DVec3; 3]) -> Aabb {
        let union = self.sub_surfaces.iter().fold(Aabb::EMPTY, |acc, s| {
            acc.union(s.sub_triangle_bounds(corners))
        });
        self.grown(union)
    }

    /// A box containing the whole blend.
    pub fn control_bounds(&self) -> Aabb {
        let union = self
            .sub_surfaces
            .iter()
            .fold(Aabb::EMPTY, |acc, s| acc.union(s.control_bounds()));
        self.grown(union)
    }

    /// `bounds` grown by `16 ε max|b|`: the blend adds two weighted differences to a
    /// sub-surface point, a few roundings of the largest coordinate magnitude.
    fn grown(&self, bounds: Aabb) -> Aabb {
        let magnitude = self
            .sub_surfaces
            .iter()
            .flat_map(|s| s.control_points())
            .fold(0.0_f64, |m, p| m.max(p.abs().max_element()));
        let margin = DVec3::splat(16.0 * f64::EPSILON * magnitude);
        Aabb {
            min: bounds.min - margin,
            max: bounds.max + margin,
        }
    }
}

/// Weights within [`CORNER_RADIUS`] of corner `c`: the weight of the sub-surface opposite
/// the corner is dropped, and the two sub-surfaces through the corner share the rest in the
/// ratio `b_{c+1}^p : b_{c+2}^p` (on the edge from the corner to `c+2`, owned by `S_{c+1}`,
/// that sub-surface has weight one) — the leading term of both families' weights there, so the
/// switch at the radius moves the point by `O(r^{p+1})`; ½ each at the corner itself.
fn corner_weights(family: WeightFamily, c: usize, b: [f64; 3]) -> [f64; 3] {
    let (next, far) = ((c + 1) % 3, (c + 2) % 3);
    let p = match family {
        WeightFamily::Nielson { power } => power,
        WeightFamily::FangMann { t } => t + 1,
    } as i32;
    let m = b[next].max(b[far]);
    let to_far = if m > 0.0 {
        let (x, y) = ((b[next] / m).powi(p), (b[far] / m).powi(p));
        x / (x + y)
    } else {
        0.5
    };
    let mut w = [0.0; 3];
    w[far] = to_far;
    w[next] = 1.0 - to_far;
    w
}

#[cfg(test)]
mod tests;
