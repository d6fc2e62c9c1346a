//! Measured geometric continuity order of a joint: the largest k such that the two surfaces,
//! written as height functions over their common tangent plane, have equal Taylor jets up to
//! order k (G^k). Zebra stripes only hint at this number: reflection lines are C^{k−1} on a G^k
//! surface.
//!
//! At a point P of the joint (side A), with `e1` the unit tangent of the joint, `n` the unit
//! normal of side A and `e2 = n × e1`, each side `S(u0 + s, v0 + t)` is a power series in (s, t)
//! from its exact partial derivatives ([`crate::surface::Patch::partials`]). Its coordinates
//! `x = (S − P)·e1`, `y = (S − P)·e2` are inverted as power series (series reversion, one order
//! per iteration) to give `(s, t)` as series in `(x, y)`, and the height `h = (S − P)·n` composed
//! with them is the height function `h(x, y)` up to order [`MAX_ORDER`]. Order m of the two sides
//! agrees when `max |h_A,ij − h_B,ij|` over `i + j = m` is at most `tolerance(m)` times the larger
//! magnitude of the order-m coefficients (or `L^{1−m}`, `L` the bounding-box diagonal, if that is
//! larger). Order 0 is the gap `|S_A − S_B| ≤ 1e-9 L`
//! ([`crate::tolerance::G0_GAP_REL`]); a joint with a larger gap has order −1.
//! The normals are oriented (`Su × Sv` of each side, every patch parametrised with its face's
//! orientation): where side B's normal points against side A's, the surface folds over the
//! joint and the order is 0, however well the two height functions agree (a face folded flat
//! onto its neighbour has identical ones).
//!
//! Tolerances grow one decade per order (`1e-8 · 10^m`: 1e-7 rad for the normal, 1e-6 for
//! curvature-level coefficients, 1e-3 at order 5), because each order of the reversion divides by
//! the parametrisation's speed once more; a genuine jump is O(1) relative. Patch kinds without
//! higher derivatives are measured up to order 2 and reported as at most 2.
//!
//! Rounding floor: the stored control points are known to about one ulp, so the order-m
//! coefficients of small, high-degree patches far from the origin are uncertain by
//! `~ d!/(d−m)! · 2^m · ε|b| / speed^m` — at order 4 of the degree-14 G^4 spline patches a few
//! 1e-3 relative, beyond the tolerance above. Where an order fails the tolerance, the measure
//! estimates this floor (`test_support::rounding_floor`: the spread of the coefficients under one-ulp
//! perturbations of both nets, times 10) and accepts the order if the sides differ by less
//! than the floor while the floor is below [`RESOLVABLE`] (10%) of the coefficients — a jump of
//! that size is still seen. An order with a larger floor cannot be resolved in f64: the measure
//! stops below it ([`Measured::unresolved`]) rather than claim it.
//!
//! High precision (compiled for the tests): `test_support::precise_measure` makes the same
//! comparison in double-double (`metrics::double_double`; the series arithmetic is generic
//! over the scalar) on nets with double-double points (`PreciseNet`) — stored f64 nets read
//! exactly, or nets a
//! construction computed in double-double — with the tolerance `precise_tolerance`. At the
//! inner joints of gk k = 4, where the f64 measure stops unresolved at order 4, it finds the
//! same order-4 differences of the stored nets as the f64 measure (to two digits): the f64
//! measure reads the stored surface correctly, and what leaves order 4 undetermined is the
//! rounding of the stored control points to f64, which no measure of the stored surface
//! undoes. So the measure of a stored surface (the metrics) stays in f64 with its floor, and
//! the order of a construction is settled by composing it in double-double (the gk tests:
//! G^5 there, differences ≤ 1e-15 of the scale).
//!
//! Cost: the order-m coefficients of the height function need the partial derivatives and the
//! reversion up to order m only, so both are evaluated one order at a time, as far as the
//! comparison goes. Each coefficient is computed once, its sums in the order of the full
//! truncated series arithmetic, so its value does not depend on how far the evaluation went.
//! Along a joint, a point stops once its sides agree to the lowest order found at the points
//! before it (the joint's order is the minimum), and the rounding floor is estimated only where
//! it can decide the order — a difference above [`RESOLVABLE`] of the scale ends the order
//! whatever the floor — from perturbed nets drawn once per joint. A G1 joint costs the first
//! derivatives at four points and the second at one.

use std::cell::OnceCell;
use std::fmt::Debug;
use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub};

use glam::{DVec2, DVec3};

use crate::bezier::TriangleBezier;
use crate::bezier::triangle::{de_casteljau_step, point_count};
use crate::surface::{Joint, Patch, Surface, UV_CORNERS, edge_uv};
use crate::tolerance::G0_GAP_REL;

/// The scalar of the continuity measure's series arithmetic: f64, or double-double for the
/// high-precision measure of the tests (`metrics::double_double`).
pub(crate) trait Real:
    Copy
    + Debug
    + PartialEq
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
{
    /// Zero.
    const ZERO: Self;
    /// The nearest f64 (for a double-double: its high part).
    fn to_f64(self) -> f64;
}

impl Real for f64 {
    const ZERO: f64 = 0.0;
    fn to_f64(self) -> f64 {
        self
    }
}

/// Highest order compared (a joint that agrees to this order is reported as this order).
pub(crate) const MAX_ORDER: usize = 5;
const TERMS: usize = (MAX_ORDER + 1) * (MAX_ORDER + 2) / 2;

/// Fractions along a joint where the order is measured (the joint's order is the minimum).
pub(crate) const ORDER_SAMPLES: [f64; 4] = [0.125, 0.375, 0.625, 0.875];

/// The relative tolerance for order m.
pub(crate) fn tolerance(m: usize) -> f64 {
    1e-8 * 10f64.powi(m as i32)
}

/// A bivariate power series truncated at total order [`MAX_ORDER`]; coefficient of `x^i y^j`
/// at [`term`]`(i, j)` (by total order, then i descending — the order of `Patch::partials`).
/// The scalar is f64, or a double-double for the high-precision measure of the tests.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Series<T = f64>([T; TERMS]);

/// The largest difference between the order-`m` coefficients of the two height series `ha`
/// and `hb`, and the largest of those coefficients in magnitude.
fn order_difference(ha: &Series, hb: &Series, m: usize) -> (f64, f64) {
    let (mut diff, mut mag) = (0.0_f64, 0.0_f64);
    for i in 0..=m {
        let k = term(i, m - i);
        diff = diff.max((ha.0[k] - hb.0[k]).abs());
        mag = mag.max(ha.0[k].abs()).max(hb.0[k].abs());
    }
    (diff, mag)
}

/// Index of the coefficient of `x^i y^j`.
fn term(i: usize, j: usize) -> usize {
    let m = i + j;
    m * (m + 1) / 2 + (m - i)
}

impl<T: Real> Series<T> {
    const ZERO: Series<T> = Series([T::ZERO; TERMS]);

    /// The highest total order with a non-zero coefficient (0 for a constant or zero series).
    fn top_order(&self) -> usize {
        (0..=MAX_ORDER)
            .rev()
            .find(|&m| (0..=m).any(|i| self.0[term(i, m - i)] != T::ZERO))
            .unwrap_or(0)
    }

    /// The coefficient of `x^a y^b` in the product `self · other`, where `self` has no terms
    /// below total order `low_self` and `other` none below `low_other`. Only the coefficients of
    /// the two factors below order `a + b` are read. The products are summed in the order in
    /// which the whole truncated product accumulates them (over the terms of `self` by order,
    /// then by power of x; the zero terms below the lowest orders left out), so the value is
    /// that coefficient of the whole product, to the bit.
    fn product_coefficient(
        &self,
        low_self: usize,
        other: &Series<T>,
        low_other: usize,
        a: usize,
        b: usize,
    ) -> T {
        let m = a + b;
        let mut sum = T::ZERO;
        for m1 in low_self..=m.saturating_sub(low_other) {
            let m2 = m - m1;
            for i1 in a.saturating_sub(m2)..=m1.min(a) {
                sum += self.0[term(i1, m1 - i1)] * other.0[term(a - i1, m2 - (a - i1))];
            }
        }
        sum
    }
}

/// Taylor series of a patch side at `(u0, v0)` projected on the frame: (x, y, h) in (s, t)
/// up to `order`, constant terms removed (the gap is checked separately).
fn frame_series(partials: &[DVec3; TERMS], frame: [DVec3; 3], order: usize) -> [Series; 3] {
    let factorial = |n: usize| (1..=n).map(|k| k as f64).product::<f64>();
    std::array::from_fn(|axis| {
        let mut s = Series::ZERO;
        for m in 1..=order {
            for i in 0..=m {
                let p = partials[term(i, m - i)];
                s.0[term(i, m - i)] = p.dot(frame[axis]) / (factorial(i) * factorial(m - i));
            }
        }
        s
    })
}

/// The height function `h(x, y)` of one side from its frame series, by series reversion one
/// order at a time.
///
/// With `(x, y) = A(s, t) + (X, Y)(s, t)`, `A` the linear part, the inverse satisfies
/// `(s, t) = A⁻¹[(x, y) − (X, Y)(s, t)]`. The order-m coefficients of the right-hand side
/// involve those of `(s, t)` below order m only, so the order-m coefficients of the monomials
/// `s^i t^j` (`monomials`, kept for every order), then of `(s, t)`, then of `h(s, t)` follow
/// from the lower orders, each computed once. Sums run in the order of a full truncated
/// composition (term by term of the outer series, by order then power of x).
#[derive(Clone, Debug)]
struct HeightSeries<T = f64> {
    /// `x` without its linear part.
    x_rest: Series<T>,
    /// `y` without its linear part.
    y_rest: Series<T>,
    /// The height `h(s, t)`.
    h: Series<T>,
    /// `A⁻¹`, row-major.
    inv: [T; 4],
    /// `s^i t^j` at `term(i, j)` (`s` at `term(1, 0)`, `t` at `term(0, 1)`; the constant is
    /// not used), as series in `(x, y)`.
    monomials: [Series<T>; TERMS],
    /// The height function `h(x, y)`.
    height: Series<T>,
    /// Highest total order of a monomial that is needed.
    top: usize,
    /// Orders of `monomials` and `height` computed so far.
    order: usize,
    /// Orders of the frame series known.
    known: usize,
}

impl<T: Real> HeightSeries<T> {
    /// The reversion of the frame series `xyh`, known up to order `known` (at least 1); `None`
    /// if the linear part is singular.
    fn new(xyh: &[Series<T>; 3], known: usize) -> Option<HeightSeries<T>> {
        let (x, y) = (&xyh[0], &xyh[1]);
        let (a, b, c, d) = (
            x.0[term(1, 0)],
            x.0[term(0, 1)],
            y.0[term(1, 0)],
            y.0[term(0, 1)],
        );
        let det = a * d - b * c;
        if det.to_f64().abs() <= 1e-300 || !det.to_f64().is_finite() {
            return None;
        }
        let mut series = HeightSeries {
            x_rest: Series::ZERO,
            y_rest: Series::ZERO,
            h: Series::ZERO,
            inv: [d / det, -b / det, -c / det, a / det],
            monomials: [Series::ZERO; TERMS],
            height: Series::ZERO,
            top: 0,
            order: 0,
            known: 0,
        };
        series.extend(xyh, known);
        Some(series)
    }

    /// Takes the same frame series known to a higher order (the lower orders are unchanged).
    fn extend(&mut self, xyh: &[Series<T>; 3], known: usize) {
        let rest = |s: &Series<T>| {
            let mut s = *s;
            s.0[..3].fill(T::ZERO);
            s
        };
        self.x_rest = rest(&xyh[0]);
        self.y_rest = rest(&xyh[1]);
        self.h = xyh[2];
        self.known = known;
        // Monomials of every order up to the known one while more orders may follow (their
        // low-order coefficients are the factors of higher ones).
        self.top = if known < MAX_ORDER {
            known
        } else {
            [&self.x_rest, &self.y_rest, &self.h]
                .map(Series::top_order)
                .into_iter()
                .max()
                .unwrap_or(0)
        };
    }

    /// Computes the coefficients up to order `m` (at most the known order).
    fn advance_to(&mut self, m: usize) {
        debug_assert!(m <= self.known);
        while self.order < m {
            self.order += 1;
            self.next_order();
        }
    }

    /// The coefficients of order `self.order` from the lower ones.
    fn next_order(&mut self) {
        let m = self.order;
        if m == 1 {
            let [s, t] = [term(1, 0), term(0, 1)];
            self.monomials[s].0[s] = self.inv[0];
            self.monomials[s].0[t] = self.inv[1];
            self.monomials[t].0[s] = self.inv[2];
            self.monomials[t].0[t] = self.inv[3];
        } else {
            self.next_monomial_order(m);
            let inv = self.inv;
            for a in 0..=m {
                let k = term(a, m - a);
                let rx = self.compose_coefficient(&self.x_rest, 2, m, k);
                let ry = self.compose_coefficient(&self.y_rest, 2, m, k);
                self.monomials[term(1, 0)].0[k] = -inv[0] * rx + -inv[1] * ry;
                self.monomials[term(0, 1)].0[k] = -inv[2] * rx + -inv[3] * ry;
            }
        }
        for a in 0..=m {
            let k = term(a, m - a);
            self.height.0[k] = self.compose_coefficient(&self.h, 1, m, k);
        }
    }

    /// The order-m coefficients of the monomials of total order 2 to m: `s^i = s^{i−1}·s`,
    /// `t^j = t^{j−1}·t`, `s^i t^j = s^i·t^j`. They read the monomials below order m only.
    fn next_monomial_order(&mut self, m: usize) {
        for p in 2..=m.min(self.top) {
            for i in 0..=p {
                let j = p - i;
                let (left, low_left, right, low_right) = match (i, j) {
                    (i, 0) => (term(i - 1, 0), i - 1, term(1, 0), 1),
                    (0, j) => (term(0, j - 1), j - 1, term(0, 1), 1),
                    (i, j) => (term(i, 0), i, term(0, j), j),
                };
                for a in 0..=m {
                    let value = self.monomials[left].product_coefficient(
                        low_left,
                        &self.monomials[right],
                        low_right,
                        a,
                        m - a,
                    );
                    self.monomials[term(i, j)].0[term(a, m - a)] = value;
                }
            }
        }
    }

    /// Coefficient `k` (of order m) of `outer(s, t)` for an outer series without terms below
    /// order `low`, from the monomials (terms of the outer series in order, zero ones skipped).
    fn compose_coefficient(&self, outer: &Series<T>, low: usize, m: usize, k: usize) -> T {
        let mut sum = T::ZERO;
        for p in low..=m.min(self.top) {
            for i in 0..=p {
                let c = outer.0[term(i, p - i)];
                if c != T::ZERO {
                    sum += c * self.monomials[term(i, p - i)].0[k];
                }
            }
        }
        sum
    }
}

/// Nets up to this degree are evaluated in stack arrays; higher degrees through
/// [`TriangleBezier::partials`].
const MAX_STACK_DEGREE: usize = 16;

/// Control points of a net of degree [`MAX_STACK_DEGREE`].
const STACK_POINTS: usize = point_count(MAX_STACK_DEGREE);

/// The partial derivatives of the orders `from..=to` of a Bézier net at `uv` into `out` (at
/// `term(i, j)`), as [`TriangleBezier::partials`] computes them: `d!/(d−m)!` times the blossom
/// at `i` copies of `∂/∂u`, then `j` of `∂/∂v`, then `d − m` of the point (`m = i + j`), one
/// de Casteljau step per argument in that order. The steps along the directions are shared by
/// the terms they begin, and the lower orders are not evaluated.
fn bezier_partials(
    net: &TriangleBezier,
    uv: DVec2,
    from: usize,
    to: usize,
    out: &mut [DVec3; TERMS],
) {
    let d = net.degree();
    if d > MAX_STACK_DEGREE {
        let all = net.partials(uv.x, uv.y, to);
        out[from * (from + 1) / 2..all.len()].copy_from_slice(&all[from * (from + 1) / 2..]);
        return;
    }
    let x = DVec3::new(1.0 - uv.x - uv.y, uv.x, uv.y);
    let (du, dv) = (DVec3::new(-1.0, 1.0, 0.0), DVec3::new(-1.0, 0.0, 1.0));
    for m in from..=to.min(MAX_ORDER) {
        for i in 0..=m {
            out[term(i, m - i)] = DVec3::ZERO;
        }
    }
    // `along_u`: the net after i steps along ∂/∂u; `along_uv`: then j along ∂/∂v.
    let mut along_u = [DVec3::ZERO; STACK_POINTS];
    let mut along_uv = [DVec3::ZERO; STACK_POINTS];
    let mut at_point = [DVec3::ZERO; STACK_POINTS];
    along_u[..point_count(d)].copy_from_slice(net.offsets());
    for i in 0..=to.min(d) {
        if i > 0 {
            de_casteljau_step(&mut along_u, d - i + 1, du);
        }
        along_uv[..point_count(d - i)].copy_from_slice(&along_u[..point_count(d - i)]);
        for j in 0..=(to - i).min(d - i) {
            if j > 0 {
                de_casteljau_step(&mut along_uv, d - i - j + 1, dv);
            }
            let m = i + j;
            if m < from {
                continue;
            }
            let rest = d - m;
            at_point[..point_count(rest)].copy_from_slice(&along_uv[..point_count(rest)]);
            for degree in (1..=rest).rev() {
                de_casteljau_step(&mut at_point, degree, x);
            }
            let falling: f64 = (d + 1 - m..=d).map(|k| k as f64).product();
            out[term(i, j)] = falling * at_point[0];
        }
    }
    if from == 0 {
        // The position; derivatives do not see the origin.
        out[term(0, 0)] += net.origin();
    }
}

/// Where the partial derivatives of a side come from.
#[derive(Clone, Copy)]
enum Source<'a> {
    /// A Bézier net (of a patch, or a perturbed copy for the rounding floor): exact partials
    /// of any order, evaluated order by order.
    Net(&'a TriangleBezier),
    /// Another kind of patch: exact partials of all orders at once, or only those of its jet.
    Patch(&'a Patch),
}

impl<'a> Source<'a> {
    /// The source of the partial derivatives of `patch`.
    fn of(patch: &'a Patch) -> Source<'a> {
        match patch.as_bezier() {
            Some(net) => Source::Net(net),
            None => Source::Patch(patch),
        }
    }

    /// Evaluates the partial derivatives at `uv` of the orders `from..=to` (at least) into
    /// `out`. Returns the highest order now evaluated and the highest order this side
    /// provides: [`MAX_ORDER`], or 2 for patch kinds without higher derivatives (whose jet is
    /// taken).
    fn partials(
        self,
        uv: DVec2,
        from: usize,
        to: usize,
        out: &mut [DVec3; TERMS],
    ) -> (usize, usize) {
        let patch = match self {
            Source::Net(net) => {
                bezier_partials(net, uv, from, to, out);
                return (to, MAX_ORDER);
            }
            Source::Patch(patch) => patch,
        };
        match patch.partials(uv.x, uv.y, MAX_ORDER) {
            Some(all) => {
                out[..all.len()].copy_from_slice(&all);
                (MAX_ORDER, MAX_ORDER)
            }
            None => {
                let j = patch.jet(uv.x, uv.y);
                out[..6].copy_from_slice(&[j.p, j.du, j.dv, j.duu, j.duv, j.dvv]);
                (2, 2)
            }
        }
    }
}

/// Both sides of a joint at one point, with their height functions in side A's tangent frame,
/// evaluated as far as the orders asked for.
#[derive(Clone)]
struct JointPoint<'a> {
    sources: [Source<'a>; 2],
    uvs: [DVec2; 2],
    /// The partial derivatives of both sides.
    partials: [[DVec3; TERMS]; 2],
    /// Highest order of the partials evaluated, per side.
    evaluated: [usize; 2],
    /// Highest order both sides provide.
    limit: usize,
    frame: [DVec3; 3],
    heights: [HeightSeries; 2],
}

impl<'a> JointPoint<'a> {
    /// The partial derivatives of the sides `sources` at `uvs` of the orders `from..=to` (of
    /// all orders for patches that have them only together); what
    /// [`JointPoint::new`] takes.
    fn evaluate(
        sources: [Source<'a>; 2],
        uvs: [DVec2; 2],
        from: usize,
        to: usize,
    ) -> Evaluated<'a> {
        let mut partials = [[DVec3::ZERO; TERMS]; 2];
        let (ea, limit_a) = sources[0].partials(uvs[0], from, to, &mut partials[0]);
        let (eb, limit_b) = sources[1].partials(uvs[1], from, to, &mut partials[1]);
        Evaluated {
            sources,
            uvs,
            partials,
            evaluated: [ea, eb],
            limit: limit_a.min(limit_b),
        }
    }

    /// The joint point from its evaluated partials (orders 1 at least); `None` where a side is
    /// singular. `edge_a` is side A's edge (its direction is `e1`).
    fn new(evaluated: Evaluated<'a>, edge_a: usize) -> Option<JointPoint<'a>> {
        let Evaluated {
            sources,
            uvs,
            partials,
            evaluated,
            limit,
        } = evaluated;
        let pa = &partials[0];
        let w = UV_CORNERS[(edge_a + 1) % 3] - UV_CORNERS[edge_a];
        let e1 = (pa[1] * w.x + pa[2] * w.y).try_normalize()?;
        let n = pa[1].cross(pa[2]).try_normalize()?;
        let frame = [e1, n.cross(e1), n];
        let known = evaluated[0].min(evaluated[1]).min(limit);
        let heights = [
            HeightSeries::new(&frame_series(&partials[0], frame, known), known)?,
            HeightSeries::new(&frame_series(&partials[1], frame, known), known)?,
        ];
        Some(JointPoint {
            sources,
            uvs,
            partials,
            evaluated,
            limit,
            frame,
            heights,
        })
    }

    /// True if side B's normal `Su × Sv` points to the same side of the common tangent plane
    /// as side A's (a fold over the joint otherwise).
    fn same_orientation(&self) -> bool {
        let b = &self.partials[1];
        b[1].cross(b[2]).dot(self.frame[2]) > 0.0
    }

    /// The order-m height coefficients of both sides (`m ≤ limit`).
    fn heights_at(&mut self, m: usize) -> [&Series; 2] {
        if m > self.heights[0].known {
            for side in 0..2 {
                if self.evaluated[side] < m {
                    let (evaluated, _) = self.sources[side].partials(
                        self.uvs[side],
                        self.evaluated[side] + 1,
                        m,
                        &mut self.partials[side],
                    );
                    self.evaluated[side] = evaluated;
                }
            }
            let known = self.evaluated[0].min(self.evaluated[1]).min(self.limit);
            for (height, p) in self.heights.iter_mut().zip(&self.partials) {
                height.extend(&frame_series(p, self.frame, known), known);
            }
        }
        for height in &mut self.heights {
            height.advance_to(m);
        }
        [&self.heights[0].height, &self.heights[1].height]
    }
}

/// Partial derivatives of both sides of a joint at one point, as [`JointPoint::evaluate`]
/// gives them.
struct Evaluated<'a> {
    sources: [Source<'a>; 2],
    uvs: [DVec2; 2],
    partials: [[DVec3; TERMS]; 2],
    evaluated: [usize; 2],
    limit: usize,
}

/// A jump this large relative to the order-m coefficients is always detected: an order whose
/// rounding floor exceeds it cannot be resolved in f64 and is not claimed.
pub(crate) const RESOLVABLE: f64 = 0.1;

/// Perturbed evaluations behind `test_support::rounding_floor`.
const FLOOR_TRIALS: usize = 4;

/// Factor between the spread of [`FLOOR_TRIALS`] one-ulp perturbations and the floor: the
/// stored points carry a few ulps from their construction, and a sample maximum falls short
/// of the true one.
const FLOOR_SAFETY: f64 = 10.0;

/// The control nets of both sides of a joint, every point moved by one ulp of the net's
/// largest coordinate in a deterministic pseudo-random direction, once per floor trial;
/// `None` unless both sides are Bézier patches.
type PerturbedNets = Option<Vec<[TriangleBezier; 2]>>;

/// The [`PerturbedNets`] of `joint` (the same for every point along it).
fn perturbed_nets(surface: &Surface, joint: &Joint) -> PerturbedNets {
    let nets = [joint.a, joint.b].map(|side| surface.patches[side.patch as usize].as_bezier());
    let [Some(net_a), Some(net_b)] = nets else {
        return None;
    };
    let mut state = 0x9e37_79b9_7f4a_7c15_u64 ^ (joint.a.patch as u64) << 32 ^ joint.b.patch as u64;
    let mut unit = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let mut perturb = |net: &TriangleBezier| {
        // One ulp of the stored offsets: the rounding the net was stored with.
        let ulp = f64::EPSILON * net.offset_magnitude();
        let moved = net
            .offsets()
            .iter()
            .map(|p| *p + ulp * DVec3::new(unit(), unit(), unit()))
            .collect();
        TriangleBezier::with_origin(net.degree(), net.origin(), moved)
    };
    Some(
        (0..FLOOR_TRIALS)
            .map(|_| {
                let a = perturb(net_a);
                [a, perturb(net_b)]
            })
            .collect(),
    )
}

/// The rounding floor at one joint point, per order, evaluated as far as asked.
struct Floor<'a> {
    /// The joint point on every perturbed pair of nets (`None` where a perturbed side is
    /// singular: that trial does not count).
    trials: Vec<Option<JointPoint<'a>>>,
    /// The floor per order, known up to `known`.
    values: [f64; MAX_ORDER + 1],
    known: usize,
}

impl<'a> Floor<'a> {
    /// The floor at the domain points `uvs` of a joint with perturbed nets `nets` (side A on
    /// edge `edge_a`), first asked for at order `first`.
    fn new(nets: &'a PerturbedNets, uvs: [DVec2; 2], edge_a: usize, first: usize) -> Self {
        let trials = nets.iter().flatten().map(|pair| {
            let sources = [Source::Net(&pair[0]), Source::Net(&pair[1])];
            JointPoint::new(JointPoint::evaluate(sources, uvs, 1, first), edge_a)
        });
        Floor {
            trials: trials.collect(),
            values: [0.0; MAX_ORDER + 1],
            known: 0,
        }
    }

    /// The floor of order m: how far the order-m coefficients of either side move under the
    /// perturbations, times [`FLOOR_SAFETY`] (zero without perturbed nets). `exact` is the
    /// unperturbed point, already evaluated to order m.
    fn at(&mut self, m: usize, exact: &mut JointPoint<'_>) -> f64 {
        while self.known < m {
            self.known += 1;
            let order = self.known;
            let [ha, hb] = exact.heights_at(order);
            let f = &mut self.values[order];
            for trial in self.trials.iter_mut().flatten() {
                let [pa, pb] = trial.heights_at(order);
                for i in 0..=order {
                    let k = term(i, order - i);
                    *f = f
                        .max(FLOOR_SAFETY * (pa.0[k] - ha.0[k]).abs())
                        .max(FLOOR_SAFETY * (pb.0[k] - hb.0[k]).abs());
                }
            }
        }
        self.values[m]
    }
}

/// The unperturbed sides of `joint` at fraction `s`, partials evaluated up to `order`: the
/// distance between them, and the joint point (`None` where a side is singular).
fn exact_point<'a>(
    surface: &'a Surface,
    joint: &Joint,
    s: f64,
    order: usize,
) -> (f64, Option<JointPoint<'a>>) {
    let sb = if joint.reversed { 1.0 - s } else { s };
    let uvs = [
        edge_uv(joint.a.edge as usize, s),
        edge_uv(joint.b.edge as usize, sb),
    ];
    let sources = [joint.a, joint.b].map(|side| Source::of(&surface.patches[side.patch as usize]));
    let evaluated = JointPoint::evaluate(sources, uvs, 0, order);
    let gap = (evaluated.partials[0][0] - evaluated.partials[1][0]).length();
    (gap, JointPoint::new(evaluated, joint.a.edge as usize))
}

/// A measured order and why the measure stopped there.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Measured {
    /// The order the two sides agree to.
    pub order: i32,
    /// `true` if the next order could not be resolved (its rounding floor exceeds
    /// [`RESOLVABLE`] of the coefficients) rather than found to differ; always `false` at
    /// [`MAX_ORDER`] and for a gap or a singular side.
    pub unresolved: bool,
}

/// What the measure at one point has to establish.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Goal {
    /// The order, and why it stops there ([`Measured::unresolved`]).
    Reason,
    /// The order only, and only up to a bound: the measure stops as soon as the sides agree to
    /// it (the bound is the lowest order found so far along the joint, whose order is the
    /// minimum), and does not tell an unresolved order from a difference.
    OrderUpTo(i32),
}

/// `test_support::measure_at` towards `goal`, with the rounding floor consulted if `nets` is given: the
/// perturbed nets of the joint are drawn into it on first use (a joint's points share them).
fn measure_with_floor(
    surface: &Surface,
    joint: &Joint,
    s: f64,
    diag: f64,
    nets: Option<&OnceCell<PerturbedNets>>,
    goal: Goal,
) -> Measured {
    let plain = |order| Measured {
        order,
        unresolved: false,
    };
    let (gap, point) = exact_point(surface, joint, s, 1);
    if gap > G0_GAP_REL * diag {
        return plain(-1);
    }
    let Some(mut point) = point else {
        return plain(0);
    };
    if !point.same_orientation() {
        return plain(0);
    }
    let mut floor = None;
    let mut agreed = 0;
    let mut unresolved = false;
    for m in 1..=point.limit {
        if matches!(goal, Goal::OrderUpTo(bound) if agreed as i32 >= bound) {
            break;
        }
        let [ha, hb] = point.heights_at(m);
        let (diff, mag) = order_difference(ha, hb, m);
        let scale = mag.max(diag.powi(1 - m as i32));
        if diff > tolerance(m) * scale {
            let Some(nets) = nets else {
                break;
            };
            if goal != Goal::Reason && diff > RESOLVABLE * scale {
                // Only a floor above RESOLVABLE of the scale could cover this difference, and
                // such an order is not claimed either: the order stops here, whatever the floor.
                break;
            }
            let floor = floor
                .get_or_insert_with(|| {
                    let nets = nets.get_or_init(|| perturbed_nets(surface, joint));
                    Floor::new(nets, point.uvs, joint.a.edge as usize, m)
                })
                .at(m, &mut point);
            if floor > RESOLVABLE * scale {
                unresolved = true;
                break;
            }
            if diff > floor {
                break;
            }
        }
        agreed = m;
    }
    Measured {
        order: agreed as i32,
        unresolved,
    }
}

/// The order of a joint: the minimum over [`ORDER_SAMPLES`].
pub fn joint_order(surface: &Surface, joint: &Joint, diag: f64) -> i32 {
    let nets = OnceCell::new();
    ORDER_SAMPLES.iter().fold(MAX_ORDER as i32, |lowest, &s| {
        let goal = Goal::OrderUpTo(lowest);
        lowest.min(measure_with_floor(surface, joint, s, diag, Some(&nets), goal).order)
    })
}

/// What the tests of other modules read of a joint's measurement.
#[cfg(test)]
pub(crate) mod test_support {
    use super::*;

    use crate::bezier::triangle::de_casteljau_rows;

    use crate::metrics::double_double::DoubleDouble;

    /// The rounding floor of the height coefficients of `joint` at fraction `s`, per order: how
    /// far they move when every stored control point of the two patches moves by one ulp of the
    /// largest coordinate (deterministic pseudo-random directions), times `FLOOR_SAFETY`. High
    /// derivatives of small, high-degree patches far from the origin are this uncertain in f64
    /// whatever the measure does (`d!/(d−m)!` times the m-th differences of points known to
    /// `ε |b|`, divided by the speed to the m-th power). Zero for patch kinds without a control
    /// net.
    pub(crate) fn rounding_floor(surface: &Surface, joint: &Joint, s: f64) -> [f64; MAX_ORDER + 1] {
        let mut floor = [0.0; MAX_ORDER + 1];
        let nets = perturbed_nets(surface, joint);
        let (_, exact) = exact_point(surface, joint, s, MAX_ORDER);
        let (Some(mut exact), Some(_)) = (exact, &nets) else {
            return floor;
        };
        let mut estimate = Floor::new(&nets, exact.uvs, joint.a.edge as usize, MAX_ORDER);
        for (m, f) in floor.iter_mut().enumerate().skip(1) {
            *f = estimate.at(m, &mut exact);
        }
        floor
    }

    /// [`order_at`] with the reason it stopped.
    pub(crate) fn measure_at(surface: &Surface, joint: &Joint, s: f64, diag: f64) -> Measured {
        measure_with_floor(
            surface,
            joint,
            s,
            diag,
            Some(&OnceCell::new()),
            Goal::Reason,
        )
    }

    /// A triangular Bézier net with double-double control points (`b(i,j,k)` at
    /// [`crate::bezier::triangle::index`]`(d, i, j)`, as in [`TriangleBezier`]): a stored f64 net
    /// read exactly, or a net constructed in double-double, for [`precise_measure`].
    #[derive(Clone, Debug, PartialEq)]
    pub(crate) struct PreciseNet {
        degree: usize,
        points: Vec<[DoubleDouble; 3]>,
    }

    impl PreciseNet {
        /// The net of degree `degree` with control points `points`; panics unless there are
        /// `(d+1)(d+2)/2` of them.
        pub fn new(degree: usize, points: Vec<[DoubleDouble; 3]>) -> Self {
            assert_eq!(points.len(), point_count(degree), "degree-{degree} net");
            PreciseNet { degree, points }
        }

        /// The f64 net `net`, exactly.
        pub fn from_net(net: &TriangleBezier) -> Self {
            let origin = net.origin().to_array().map(DoubleDouble::from_f64);
            let points = net
                .offsets()
                .iter()
                .map(|p| {
                    let p = p.to_array().map(DoubleDouble::from_f64);
                    std::array::from_fn(|c| origin[c] + p[c])
                })
                .collect();
            PreciseNet::new(net.degree(), points)
        }

        /// The net rounded to f64.
        pub fn to_net(&self) -> TriangleBezier {
            let points = self
                .points
                .iter()
                .map(|p| DVec3::from_array(p.map(DoubleDouble::to_f64)))
                .collect();
            TriangleBezier::new(self.degree, points)
        }

        /// The degree.
        pub fn degree(&self) -> usize {
            self.degree
        }

        /// Control point `b(i,j,k)` (`k = d − i − j`).
        pub fn point(&self, i: usize, j: usize) -> [DoubleDouble; 3] {
            self.points[crate::bezier::triangle::index(self.degree, i, j)]
        }

        /// Moves control point `b(i,j,k)` by `delta`.
        pub fn displace(&mut self, i: usize, j: usize, delta: DVec3) {
            let p = &mut self.points[crate::bezier::triangle::index(self.degree, i, j)];
            for (c, d) in p.iter_mut().zip(delta.to_array()) {
                *c += DoubleDouble::from_f64(d);
            }
        }
    }

    /// One de Casteljau step in double-double, as [`de_casteljau_step`] (same layout, in place).
    fn precise_step(net: &mut [[DoubleDouble; 3]], m: usize, w: [DoubleDouble; 3]) {
        de_casteljau_rows(net, m, |t, b_j, b_k| {
            let old = *t;
            *t = std::array::from_fn(|c| w[0] * old[c] + w[1] * b_j[c] + w[2] * b_k[c]);
        });
    }

    /// The partial derivatives of orders `0..=MAX_ORDER` of `net` at `uv` in double-double, by
    /// the blossom steps of [`bezier_partials`].
    fn precise_partials(net: &PreciseNet, uv: DVec2) -> [[DoubleDouble; 3]; TERMS] {
        let dd = DoubleDouble::from_f64;
        let d = net.degree;
        let x = [dd(1.0) - dd(uv.x) - dd(uv.y), dd(uv.x), dd(uv.y)];
        let du = [dd(-1.0), dd(1.0), dd(0.0)];
        let dv = [dd(-1.0), dd(0.0), dd(1.0)];
        let mut out = [[DoubleDouble::ZERO; 3]; TERMS];
        let mut along_u = net.points.clone();
        for i in 0..=MAX_ORDER.min(d) {
            if i > 0 {
                precise_step(&mut along_u, d - i + 1, du);
            }
            let mut along_uv = along_u[..point_count(d - i)].to_vec();
            for j in 0..=(MAX_ORDER - i).min(d - i) {
                if j > 0 {
                    precise_step(&mut along_uv, d - i - j + 1, dv);
                }
                let m = i + j;
                let rest = d - m;
                let mut at_point = along_uv[..point_count(rest)].to_vec();
                for degree in (1..=rest).rev() {
                    precise_step(&mut at_point, degree, x);
                }
                let falling: f64 = (d + 1 - m..=d).map(|k| k as f64).product();
                out[term(i, j)] = at_point[0].map(|c| c * dd(falling));
            }
        }
        out
    }

    /// [`frame_series`] in double-double for all orders (the frame's f64 vectors taken as exact).
    fn precise_frame_series(
        partials: &[[DoubleDouble; 3]; TERMS],
        frame: [DVec3; 3],
    ) -> [Series<DoubleDouble>; 3] {
        let dd = DoubleDouble::from_f64;
        let factorial = |n: usize| (1..=n).map(|k| k as f64).product::<f64>();
        std::array::from_fn(|axis| {
            let f = frame[axis];
            let mut s = Series::ZERO;
            for m in 1..=MAX_ORDER {
                for i in 0..=m {
                    let p = partials[term(i, m - i)];
                    let along = p[0] * dd(f.x) + p[1] * dd(f.y) + p[2] * dd(f.z);
                    s.0[term(i, m - i)] = along / dd(factorial(i) * factorial(m - i));
                }
            }
            s
        })
    }

    /// The relative tolerance of order m in [`PreciseMeasure::order`]: `1e-14 · 10^m` (1e-10 at
    /// order 4), growing one decade per order as [`tolerance`] does. Double-double arithmetic
    /// rounds at ~1e-32; what sets the tolerance is the input of a construction in double-double:
    /// its f64 data (for the gk inner patches, the rotated planar patches `x_s`, whose shared
    /// edges differ by an ulp) place the two sides' points ~1e-16 apart, which moves the
    /// height coefficients of small patches by up to ~1e-13 of their scale (measured: at most
    /// 4e-13, at order 5). A construction error of 1e-6 of a patch's size shows as 1e-5 or more.
    pub(crate) fn precise_tolerance(m: usize) -> f64 {
        1e-14 * 10f64.powi(m as i32)
    }

    /// One order of the high-precision comparison: the largest difference of the two sides'
    /// order-m height coefficients and their scale (as in the f64 measure: the larger magnitude
    /// of the coefficients, or `L^{1−m}`).
    #[derive(Clone, Copy, Debug, PartialEq)]
    pub(crate) struct PreciseTerm {
        /// `max |h_A,ij − h_B,ij|` over `i + j = m`.
        pub difference: f64,
        /// The scale the difference is relative to.
        pub scale: f64,
    }

    /// The two sides of a joint point compared in double-double: the height functions of
    /// `test_support::measure_at` from double-double partial derivatives and series arithmetic, to
    /// [`MAX_ORDER`]. The frame is side A's, computed in f64 and then taken as exact: both sides
    /// are read in the same (orthonormal to ~1e-16) frame, so their height functions agree
    /// exactly where the surfaces do. Rounding in double-double is ~1e-32 relative, so what the
    /// comparison sees is the nets' own defect: for stored f64 nets, that of the stored surface
    /// (its points taken as exact); for nets constructed in double-double, that of the
    /// construction.
    #[derive(Clone, Debug, PartialEq)]
    pub(crate) struct PreciseMeasure {
        /// `|S_A − S_B|` at the point.
        pub gap: f64,
        /// True if side B's normal points against side A's (a fold: order 0 at most).
        pub folded: bool,
        /// Orders 1..=[`MAX_ORDER`] (index m − 1).
        pub terms: Vec<PreciseTerm>,
    }

    impl PreciseMeasure {
        /// The order the sides agree to: −1 for a gap above [`G0_GAP_REL`]` L`, else the largest m such
        /// that every order up to m differs by at most [`precise_tolerance`]`(m)` of its scale.
        pub fn order(&self, diag: f64) -> i32 {
            self.order_within(diag, precise_tolerance)
        }

        /// [`PreciseMeasure::order`] with the relative tolerance `tolerance(m)` of order m (e.g.
        /// the f64 measure's [`tolerance`], to read stored f64 nets exactly against it).
        pub fn order_within(&self, diag: f64, tolerance: impl Fn(usize) -> f64) -> i32 {
            if self.gap > G0_GAP_REL * diag {
                return -1;
            }
            if self.folded {
                return 0;
            }
            self.terms
                .iter()
                .zip(1..)
                .take_while(|(t, m)| t.difference <= tolerance(*m) * t.scale)
                .count() as i32
        }

        /// The largest `difference / scale` of order `m`.
        pub fn relative(&self, m: usize) -> f64 {
            let t = self.terms[m - 1];
            t.difference / t.scale
        }
    }

    /// The sides `nets` at domain points `uvs` (side A on edge `edge_a`) compared in
    /// double-double; `None` where a side is singular.
    fn precise_point(
        nets: [&PreciseNet; 2],
        uvs: [DVec2; 2],
        edge_a: usize,
        diag: f64,
    ) -> Option<PreciseMeasure> {
        let partials = [0, 1].map(|side| precise_partials(nets[side], uvs[side]));
        let rounded = |p: [DoubleDouble; 3]| DVec3::from_array(p.map(DoubleDouble::to_f64));
        let (du, dv) = (rounded(partials[0][1]), rounded(partials[0][2]));
        let w = UV_CORNERS[(edge_a + 1) % 3] - UV_CORNERS[edge_a];
        let e1 = (du * w.x + dv * w.y).try_normalize()?;
        let n = du.cross(dv).try_normalize()?;
        let frame = [e1, n.cross(e1), n];
        let folded = rounded(partials[1][1])
            .cross(rounded(partials[1][2]))
            .dot(n)
            <= 0.0;
        let gap = DVec3::from_array(std::array::from_fn(|c| {
            (partials[0][0][c] - partials[1][0][c]).to_f64()
        }))
        .length();
        let [ha, hb] = partials.map(|p| {
            let mut h = HeightSeries::new(&precise_frame_series(&p, frame), MAX_ORDER)?;
            h.advance_to(MAX_ORDER);
            Some(h.height)
        });
        let (ha, hb) = (ha?, hb?);
        let terms = (1..=MAX_ORDER)
            .map(|m| {
                let (mut diff, mut mag) = (0.0_f64, 0.0_f64);
                for i in 0..=m {
                    let k = term(i, m - i);
                    diff = diff.max((ha.0[k] - hb.0[k]).abs().to_f64());
                    mag = mag.max(ha.0[k].abs().to_f64()).max(hb.0[k].abs().to_f64());
                }
                PreciseTerm {
                    difference: diff,
                    scale: mag.max(diag.powi(1 - m as i32)),
                }
            })
            .collect();
        Some(PreciseMeasure { gap, folded, terms })
    }

    /// The order measure of `test_support::measure_at` in double-double on the nets `nets` of the two sides
    /// of `joint` (side A's first) at fraction `s`; `diag` is the length scale L. `None` where a
    /// side is singular.
    pub(crate) fn precise_measure(
        nets: [&PreciseNet; 2],
        joint: &Joint,
        s: f64,
        diag: f64,
    ) -> Option<PreciseMeasure> {
        let sb = if joint.reversed { 1.0 - s } else { s };
        let uvs = [
            edge_uv(joint.a.edge as usize, s),
            edge_uv(joint.b.edge as usize, sb),
        ];
        precise_point(nets, uvs, joint.a.edge as usize, diag)
    }

    /// Per order m: (difference, scale, floor) of the height coefficients at fraction `s`.
    pub(crate) fn diagnose(surface: &Surface, joint: &Joint, s: f64, diag: f64) -> Vec<[f64; 3]> {
        let floor = rounding_floor(surface, joint, s);
        let (_, point) = exact_point(surface, joint, s, MAX_ORDER);
        let Some(mut point) = point else {
            return Vec::new();
        };
        (1..=point.limit)
            .map(|m| {
                let [ha, hb] = point.heights_at(m);
                let (diff, mag) = order_difference(ha, hb, m);
                [diff, mag.max(diag.powi(1 - m as i32)), floor[m]]
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::test_support::*;
    use super::*;
    use crate::bezier::TriangleBezier;
    use crate::bezier::gram::multi_indices;
    use crate::bezier::test_support::domain_point_collocation;
    use crate::linalg::invert;
    use crate::surface::{Patch, PatchEdge, PatchGeometry};
    use glam::DVec2;

    /// The degree-d patch interpolating `f(u, v)` at the domain points (exact when f is a
    /// polynomial map of degree ≤ d).
    fn interpolate(d: usize, f: &dyn Fn(DVec2) -> DVec3) -> TriangleBezier {
        let idx = multi_indices(d);
        let bary = |m: &[usize; 3]| m.map(|x| x as f64 / d as f64);
        let basis = domain_point_collocation(d);
        let inv = invert(&basis).expect("interpolation at domain points is regular");
        let values: Vec<DVec3> = idx
            .iter()
            .map(|m| {
                let l = bary(m);
                f(DVec2::new(l[1], l[2]))
            })
            .collect();
        let points = inv
            .iter()
            .map(|row| row.iter().zip(&values).map(|(a, b)| *a * *b).sum())
            .collect();
        TriangleBezier::new(d, points)
    }

    /// Side A: the graph of f over the triangle (0,0),(1,0),(0,1); side B: the graph of g over
    /// (1,1),(0,1),(1,0), read through the domain map `phi` of the unit triangle. They share the
    /// diagonal x + y = 1 (edge 1 of both, opposite directions) when `phi` fixes that edge.
    fn two_sided(
        f: &dyn Fn(DVec2) -> f64,
        g: &dyn Fn(DVec2) -> f64,
        phi: &dyn Fn(DVec2) -> DVec2,
        degree_b: usize,
    ) -> (Surface, Joint) {
        let a = interpolate(3, &|uv| DVec3::new(uv.x, uv.y, f(uv)));
        let b = interpolate(degree_b, &|uv| {
            let w = phi(uv);
            let p = DVec2::ONE + w.x * (DVec2::Y - DVec2::ONE) + w.y * (DVec2::X - DVec2::ONE);
            DVec3::new(p.x, p.y, g(p))
        });
        let patch = |face: u32, b: TriangleBezier| Patch {
            face,
            piece: 0,
            domain: crate::surface::WHOLE_FACE,
            geometry: PatchGeometry::Bezier(b),
        };
        let surface = Surface {
            scheme: "test".into(),
            warnings: Vec::new(),
            spike_face_pairs: Vec::new(),
            params: vec![],
            patches: vec![patch(0, a), patch(1, b)],
        };
        let joint = Joint {
            a: PatchEdge { patch: 0, edge: 1 },
            b: PatchEdge { patch: 1, edge: 1 },
            reversed: true,
            between_faces: true,
        };
        (surface, joint)
    }

    /// The truncated product with all terms summed in turn (zero terms of `a` skipped): the
    /// reference for [`Series::product_coefficient`].
    fn full_product(a: &Series, b: &Series) -> Series {
        let mut out = Series::ZERO;
        for m1 in 0..=MAX_ORDER {
            for i1 in 0..=m1 {
                let x = a.0[term(i1, m1 - i1)];
                if x == 0.0 {
                    continue;
                }
                for m2 in 0..=MAX_ORDER - m1 {
                    for i2 in 0..=m2 {
                        out.0[term(i1 + i2, m1 - i1 + m2 - i2)] += x * b.0[term(i2, m2 - i2)];
                    }
                }
            }
        }
        out
    }

    /// `outer(s, t)` with every power and monomial formed in full: the reference composition.
    fn full_composition(outer: &Series, s: &Series, t: &Series) -> Series {
        let mut one = Series::ZERO;
        one.0[0] = 1.0;
        let mut s_pow = [one; MAX_ORDER + 1];
        let mut t_pow = [one; MAX_ORDER + 1];
        for k in 1..=MAX_ORDER {
            s_pow[k] = full_product(&s_pow[k - 1], s);
            t_pow[k] = full_product(&t_pow[k - 1], t);
        }
        let mut out = Series::ZERO;
        for m in 0..=MAX_ORDER {
            for i in 0..=m {
                let c = outer.0[term(i, m - i)];
                if c != 0.0 {
                    let monomial = full_product(&s_pow[i], &t_pow[m - i]);
                    out = Series(std::array::from_fn(|k| out.0[k] + c * monomial.0[k]));
                }
            }
        }
        out
    }

    /// The height function by [`MAX_ORDER`] − 1 rounds of the fixed-point iteration
    /// `(s, t) ← A⁻¹[(x, y) − (X, Y)(s, t)]` on whole series: the reference for
    /// [`HeightSeries`].
    fn full_height_function(xyh: &[Series; 3]) -> Series {
        let (x, y, h) = (&xyh[0], &xyh[1], &xyh[2]);
        let (a, b, c, d) = (x.0[1], x.0[2], y.0[1], y.0[2]);
        let det = a * d - b * c;
        let inv = [d / det, -b / det, -c / det, a / det];
        let rest = |s: &Series| {
            let mut s = *s;
            s.0[..3].fill(0.0);
            s
        };
        let (x_rest, y_rest) = (rest(x), rest(y));
        let linear = |p: f64, q: f64| {
            let mut s = Series::ZERO;
            s.0[1] = p;
            s.0[2] = q;
            s
        };
        let axpy =
            |s: &Series, k: f64, r: &Series| Series(std::array::from_fn(|i| s.0[i] + k * r.0[i]));
        let (mut s, mut t) = (linear(inv[0], inv[1]), linear(inv[2], inv[3]));
        for _ in 1..MAX_ORDER {
            let rx = full_composition(&x_rest, &s, &t);
            let ry = full_composition(&y_rest, &s, &t);
            s = axpy(&axpy(&linear(inv[0], inv[1]), -inv[0], &rx), -inv[1], &ry);
            t = axpy(&axpy(&linear(inv[2], inv[3]), -inv[2], &rx), -inv[3], &ry);
        }
        full_composition(h, &s, &t)
    }

    /// A deterministic pseudo-random number in [−1, 1).
    fn next_unit(state: &mut u64) -> f64 {
        *state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }

    /// A random series with terms of total order `low..=high` only.
    fn random_series(state: &mut u64, low: usize, high: usize) -> Series {
        let mut s = Series::ZERO;
        for m in low..=high {
            for i in 0..=m {
                s.0[term(i, m - i)] = next_unit(state) * 4f64.powi(m as i32 - 2);
            }
        }
        s
    }

    /// Every coefficient of the product from [`Series::product_coefficient`] is the full
    /// product's to the bit, for factors of every lowest order; lower orders of the product
    /// are zero.
    #[test]
    fn product_coefficient_is_the_full_product() {
        let mut state = 7;
        for _ in 0..20 {
            for low_a in 0..=MAX_ORDER {
                for low_b in 0..=MAX_ORDER - low_a {
                    let a = random_series(&mut state, low_a, MAX_ORDER);
                    let b = random_series(&mut state, low_b, MAX_ORDER);
                    let full = full_product(&a, &b);
                    for m in 0..=MAX_ORDER {
                        for i in 0..=m {
                            let k = term(i, m - i);
                            if m < low_a + low_b {
                                assert_eq!(full.0[k], 0.0);
                                continue;
                            }
                            let got = a.product_coefficient(low_a, &b, low_b, i, m - i);
                            assert_eq!(got.to_bits(), full.0[k].to_bits(), "{low_a} {low_b} {k}");
                        }
                    }
                }
            }
        }
    }

    /// A random frame series: a regular linear part, higher terms up to order `top`.
    fn random_frame_series(state: &mut u64, top: usize) -> [Series; 3] {
        let mut xyh = [0; 3].map(|_| random_series(state, 1, top));
        xyh[0].0[1] += 2.0;
        xyh[1].0[2] += 1.5;
        xyh[2].0[1] *= 1e-3;
        xyh[2].0[2] *= 1e-3;
        xyh
    }

    /// [`HeightSeries`] gives the height function of the full iteration to the bit, whether
    /// its frame series is known to [`MAX_ORDER`] from the start or first to a lower order and
    /// then extended, and for outer series of every degree; lower orders do not depend on how
    /// far it went.
    #[test]
    fn height_series_is_the_full_reversion() {
        let mut state = 11;
        for top in 1..=MAX_ORDER {
            for _ in 0..20 {
                let xyh = random_frame_series(&mut state, top);
                let reference = full_height_function(&xyh);
                let mut whole = HeightSeries::new(&xyh, MAX_ORDER).expect("regular");
                whole.advance_to(MAX_ORDER);
                for first in 1..MAX_ORDER {
                    let truncated = |known: usize| {
                        let mut s = xyh;
                        for series in &mut s {
                            series.0[(known + 1) * (known + 2) / 2..].fill(0.0);
                        }
                        s
                    };
                    let mut staged = HeightSeries::new(&truncated(first), first).expect("regular");
                    staged.advance_to(first);
                    let known = (first + 1) * (first + 2) / 2;
                    assert_eq!(staged.height.0[..known], reference.0[..known]);
                    staged.extend(&xyh, MAX_ORDER);
                    staged.advance_to(MAX_ORDER);
                    assert_eq!(staged.height, reference, "top {top}, first {first}");
                }
                for k in 0..TERMS {
                    assert_eq!(whole.height.0[k].to_bits(), reference.0[k].to_bits(), "{k}");
                }
            }
        }
    }

    /// [`bezier_partials`] gives the partials of [`TriangleBezier::partials`] to the bit, for
    /// every range of orders and degrees up to and beyond [`MAX_STACK_DEGREE`]; orders outside
    /// the range are left as they were.
    #[test]
    fn bezier_partials_are_those_of_the_net() {
        let mut state = 5;
        for d in [0, 1, 2, 3, 4, 5, 6, 9, 12, 14, 16, 17] {
            let net = TriangleBezier::from_fn(d, |_, _, _| {
                DVec3::new(next_unit(&mut state), next_unit(&mut state), 0.5)
            });
            let uv = DVec2::new(0.3 * next_unit(&mut state).abs(), 0.25);
            let reference = net.partials(uv.x, uv.y, MAX_ORDER);
            for from in 0..=MAX_ORDER {
                for to in from..=MAX_ORDER {
                    let marker = DVec3::splat(7.0);
                    let mut out = [marker; TERMS];
                    bezier_partials(&net, uv, from, to, &mut out);
                    for m in 0..=MAX_ORDER {
                        for i in 0..=m {
                            let k = term(i, m - i);
                            let want = if (from..=to).contains(&m) {
                                reference[k]
                            } else {
                                marker
                            };
                            assert_eq!(
                                out[k].to_array().map(f64::to_bits),
                                want.to_array().map(f64::to_bits),
                                "d {d}, {from}..={to}, term {k}"
                            );
                        }
                    }
                }
            }
        }
    }

    fn base(p: DVec2) -> f64 {
        0.3 * p.x * p.x - 0.2 * p.x * p.y + 0.1 * p.y.powi(3) + 0.05 * p.x
    }

    /// `w = x + y − 1` vanishes on the shared diagonal; adding `c·w^k` to one side changes the
    /// jets exactly from order k on (k = 1: G0 only, k = 2: G1, k = 3: G2, k = 4: G3), one
    /// polynomial on both sides agrees to every measured order, a lifted side is not G0.
    #[test]
    fn hand_made_joins_of_known_order() {
        let id = |uv: DVec2| uv;
        for k in 1..=4 {
            let bump = move |p: DVec2| base(p) + 0.4 * (p.x + p.y - 1.0).powi(k);
            let (surface, joint) = two_sided(&base, &bump, &id, 4);
            let order = joint_order(&surface, &joint, 2f64.sqrt());
            assert_eq!(order, k - 1, "a jump at order {k}");
        }
        let (surface, joint) = two_sided(&base, &base, &id, 3);
        assert_eq!(joint_order(&surface, &joint, 2f64.sqrt()), MAX_ORDER as i32);
        let lifted = |p: DVec2| base(p) + 1e-3;
        let (surface, joint) = two_sided(&base, &lifted, &id, 3);
        assert_eq!(joint_order(&surface, &joint, 2f64.sqrt()), -1);
    }

    /// Side B of [`two_sided`] folded back over side A: the graph of the same function over
    /// A's own triangle, reached through the reflection in the shared diagonal. The two height
    /// functions are identical, but B's normal points against A's: a fold, order 0, also in
    /// double-double; unfolded, the same graph agrees to every order.
    #[test]
    fn a_fold_over_the_joint_is_order_zero() {
        let (mut surface, joint) = two_sided(&base, &base, &|uv| uv, 3);
        let diag = 2f64.sqrt();
        assert_eq!(joint_order(&surface, &joint, diag), MAX_ORDER as i32);
        let folded = interpolate(3, &|w| {
            // B's domain point w lies at (1 − w.x, 1 − w.y); its mirror image in x + y = 1.
            let q = DVec2::new(w.y, w.x);
            DVec3::new(q.x, q.y, base(q))
        });
        surface.patches[1].geometry = PatchGeometry::Bezier(folded.clone());
        let side_a = PreciseNet::from_net(surface.patches[0].as_bezier().expect("net"));
        let side_b = PreciseNet::from_net(&folded);
        for s in ORDER_SAMPLES {
            let heights = test_support::diagnose(&surface, &joint, s, diag);
            assert!(
                heights.iter().all(|[d, scale, _]| *d <= 1e-14 * scale),
                "{heights:?}"
            );
            let precise = precise_measure([&side_a, &side_b], &joint, s, diag).expect("regular");
            assert!(precise.folded);
            assert_eq!(precise.order(diag), 0);
        }
        assert_eq!(joint_order(&surface, &joint, diag), 0);
    }

    /// A non-affine (cubic) map of the unit triangle that fixes its edge x + y = 1.
    fn cubic_domain_map(uv: DVec2) -> DVec2 {
        let bump = 0.6 * (1.0 - uv.x - uv.y) * uv.x * uv.y;
        DVec2::new(uv.x + bump, uv.y - bump)
    }

    /// A homogeneous quadratic: its graph keeps its shape under `(x, y, z) ↦ s·(x, y, s z)`.
    fn homogeneous_quadratic(p: DVec2) -> f64 {
        0.3 * p.x * p.x - 0.2 * p.x * p.y + 0.1 * p.y * p.y
    }

    /// The measure is geometric: side B read through a non-affine (cubic) map of its domain that
    /// fixes the shared edge is the same surface (all orders agree although the parametrisations
    /// are only C⁰ across the edge), and a G2 join stays G2.
    #[test]
    fn orders_are_geometric_not_parametric() {
        let (phi, quad) = (cubic_domain_map, homogeneous_quadratic);
        let (surface, joint) = two_sided(&quad, &quad, &phi, 6);
        assert_eq!(joint_order(&surface, &joint, 2f64.sqrt()), MAX_ORDER as i32);
        let g2 = |p: DVec2| quad(p) + 0.4 * (p.x + p.y - 1.0).powi(3);
        let (surface, joint) = two_sided(&quad, &g2, &phi, 9);
        assert_eq!(joint_order(&surface, &joint, 2f64.sqrt()), 2);
    }

    /// The patches of [`two_sided`] elevated to degree 14, shrunk to a size of `size` at a
    /// distance of about 1 from the origin, heights scaled by `size²` so that the curvature
    /// stays O(1) (the graph of a homogeneous quadratic keeps its shape): a tiny piece of a
    /// gently curved surface, whose high derivatives are known only to the rounding of the
    /// stored points.
    fn small_and_high_degree(surface: &Surface, size: f64) -> Surface {
        let offset = DVec3::new(0.7, -0.5, 0.6);
        let mut out = surface.clone();
        for patch in &mut out.patches {
            let net = patch.as_bezier().expect("test patches are Bézier").clone();
            let elevated = (net.degree()..14).fold(net, |e, _| e.elevate());
            let shrink = |p: DVec3| offset + DVec3::new(size * p.x, size * p.y, size * size * p.z);
            patch.geometry = PatchGeometry::Bezier(elevated.map_points(shrink));
        }
        out
    }

    /// The largest difference of the two sides' order-m height coefficients at `s`.
    fn side_difference(surface: &Surface, joint: &Joint, s: f64, m: usize) -> f64 {
        let (_, point) = exact_point(surface, joint, s, MAX_ORDER);
        let mut point = point.expect("regular");
        let [ha, hb] = point.heights_at(m);
        (0..=m)
            .map(|i| (ha.0[term(i, m - i)] - hb.0[term(i, m - i)]).abs())
            .fold(0.0, f64::max)
    }

    /// Small degree-14 patches of a gently curved surface far from the origin (like the inner
    /// p-patches of G^4 splines): the two sides of one surface across a C⁰ reparametrised
    /// joint differ by less than the rounding floor at every order; at size 2e-2 order 4 is
    /// beyond the plain tolerances but resolved through the floor (G^4), order 5 is not; at
    /// size 1e-2 order 4 is not resolved either (G^3, never more than the data supports).
    /// A genuine jump at order 3 is caught at both sizes.
    #[test]
    fn rounding_floor_resolves_what_f64_data_supports() {
        let (phi, quad) = (cubic_domain_map, homogeneous_quadratic);
        let g2 = |p: DVec2| quad(p) + 0.4 * (p.x + p.y - 1.0).powi(3);
        let diag = 4.0;
        for (size, expected) in [(2e-2, 4), (1e-2, 3)] {
            let (same, joint) = two_sided(&quad, &quad, &phi, 6);
            let same = small_and_high_degree(&same, size);
            let (jump, _) = two_sided(&quad, &g2, &phi, 9);
            let jump = small_and_high_degree(&jump, size);
            for s in ORDER_SAMPLES {
                let floor = rounding_floor(&same, &joint, s);
                for (m, f) in floor.iter().enumerate().skip(1) {
                    let diff = side_difference(&same, &joint, s, m);
                    assert!(
                        diff <= *f,
                        "size {size}, s = {s}, order {m}: {diff:e} > floor {f:e}"
                    );
                }
            }
            let plain = ORDER_SAMPLES
                .iter()
                .map(|&s| measure_with_floor(&same, &joint, s, diag, None, Goal::Reason).order)
                .min();
            assert_eq!(
                plain,
                Some(3),
                "size {size}: the plain tolerances stop at order 3"
            );
            assert_eq!(joint_order(&same, &joint, diag), expected, "size {size}");
            assert_eq!(joint_order(&jump, &joint, diag), 2, "size {size}");
        }
    }
}
