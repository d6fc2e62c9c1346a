//! Triangular Bézier patches of any degree: storage order, de Casteljau evaluation, blossom,
//! and the position-and-derivatives jet the ray tracer and the metrics read. Subdivision,
//! elevation, edge curves and bounds are in [`crate::bezier::triangle_forms`].
//!
//! The standard facts used here are those of Farin, *Curves and Surfaces for CAGD*, ch. 17
//! (triangular patches), as recalled in [Piper87 §3.2–3.7]: the de Casteljau recursion
//! [Piper87 eq. 8], directional derivatives from the intermediate de Casteljau points
//! [Piper87 eq. 10], degree elevation [Piper87 §3.6] and subdivision through the blossom
//! [Piper87 eq. 15].
//!
//! Every algorithm works on a control net stored in the module order (see [`index`]) and is
//! built from one in-place kernel, `de_casteljau_step`, which lowers a net of degree `m` to
//! degree `m − 1` at one barycentric argument. For degree ≤ 8 the working net
//! lives in a fixed-size stack array, so [`TriangleBezier::eval`], [`TriangleBezier::jet`] and
//! [`TriangleBezier::blossom`] do not allocate.

use glam::DVec3;

use crate::error::{Error, Result};
use crate::geom::Jet;

/// Number of control points of a triangular patch of degree `d`: (d+1)(d+2)/2.
pub(crate) const fn point_count(degree: usize) -> usize {
    (degree + 1) * (degree + 2) / 2
}

/// Position of `b(i,j,k)` in the point list of a degree-`d` patch (`i+j+k = d`).
///
/// The rows with a larger `i` come first: there are `(d−i)(d−i+1)/2` points with first index
/// above `i`; inside row `i`, `j` runs from `d−i` down to 0.
pub(crate) const fn index(degree: usize, i: usize, j: usize) -> usize {
    let rest = degree - i;
    rest * (rest + 1) / 2 + (rest - j)
}

/// One de Casteljau step in place [Piper87 eq. 8]: the first `point_count(m)` entries of `net`,
/// a net of degree `m ≥ 1`, are replaced in their first `point_count(m − 1)` entries by
/// `b'(i,j,k) = w0 b(i+1,j,k) + w1 b(i,j+1,k) + w2 b(i,j,k+1)`.
///
/// `w` need not sum to one: with a general argument this is one step of the blossom.
/// In place is safe because the new row `i` (`m − i` points) lands exactly where the old row
/// `i+1` was, and it reads only that old row and the old row `i`, which lies after it and has
/// not been overwritten yet. Rows are handled as slices, so the inner loop has no index checks.
#[inline(always)]
pub(crate) fn de_casteljau_step(net: &mut [DVec3], m: usize, w: DVec3) {
    de_casteljau_rows(net, m, |t, b_j, b_k| {
        *t = w.x * *t + w.y * *b_j + w.z * *b_k;
    });
}

/// The in-place row walk of [`de_casteljau_step`] for points of any type: `combine(t, b_j,
/// b_k)` replaces the old `t = b(i+1, j, k)` by the new `b'(i, j, k)` from it, `b_j =
/// b(i, j+1, k)` and `b_k = b(i, j, k+1)`. Shared with the double-double evaluation of the
/// continuity measure.
#[inline(always)]
pub(crate) fn de_casteljau_rows<T>(
    net: &mut [T],
    m: usize,
    mut combine: impl FnMut(&mut T, &T, &T),
) {
    // Old row i (first index i, m−i+1 points) starts at (m−i)(m−i+1)/2.
    let row_start = |i: usize| (m - i) * (m - i + 1) / 2;
    for i in (0..m).rev() {
        let len = m - i;
        let (head, tail) = net.split_at_mut(row_start(i));
        let target = &mut head[row_start(i + 1)..];
        let row_i = &tail[..=len];
        // target[n] holds old b(i+1, len−1−n, ·); row_i[n] = b(i, len−n, ·), row_i[n+1] = b(i, len−1−n, ·).
        for ((t, b_j), b_k) in target.iter_mut().zip(row_i).zip(&row_i[1..]) {
            combine(t, b_j, b_k);
        }
    }
}

/// Runs `f` on a mutable copy of `points`, held in a stack array when the net has degree
/// ≤ 8 (so the hot evaluation paths never allocate), on the heap above.
#[inline(always)]
fn with_working_net<R>(points: &[DVec3], f: impl FnOnce(&mut [DVec3]) -> R) -> R {
    #[inline(always)]
    fn on_stack<const N: usize, R>(points: &[DVec3], f: impl FnOnce(&mut [DVec3]) -> R) -> R {
        let mut net: [DVec3; N] = std::array::from_fn(|n| points[n]);
        f(&mut net)
    }
    match points.len() {
        1 => on_stack::<1, R>(points, f),
        3 => on_stack::<3, R>(points, f),
        6 => on_stack::<6, R>(points, f),
        10 => on_stack::<10, R>(points, f),
        15 => on_stack::<15, R>(points, f),
        21 => on_stack::<21, R>(points, f),
        28 => on_stack::<28, R>(points, f),
        36 => on_stack::<36, R>(points, f),
        45 => on_stack::<45, R>(points, f),
        _ => f(&mut points.to_vec()),
    }
}

/// Position and `(u, v)` derivatives of a degree-`d` patch (`d ≥ 2`) from its de Casteljau net
/// of degree 2 at `w` (the six points `b^{d−2}(w)` in module order).
///
/// The last two de Casteljau levels hold the blossom values `b[e_a, w^{d−1}]` and
/// `b[e_a, e_b, w^{d−2}]`, so with the directions `∂/∂u = e1 − e0`, `∂/∂v = e2 − e0`
/// the first derivatives are `d·(r_010 − r_100)` etc. and the second ones
/// `d(d−1)·q[a, b]` [Piper87 eq. 10; Farin, CAGD §17.6].
#[inline(always)]
fn jet_from_quadratic_level(q: &[DVec3], degree: usize, w: DVec3) -> Jet {
    let (q200, q110, q101, q020, q011, q002) = (q[0], q[1], q[2], q[3], q[4], q[5]);
    let r100 = w.x * q200 + w.y * q110 + w.z * q101;
    let r010 = w.x * q110 + w.y * q020 + w.z * q011;
    let r001 = w.x * q101 + w.y * q011 + w.z * q002;
    let d = degree as f64;
    let dd = d * (d - 1.0);
    Jet {
        p: w.x * r100 + w.y * r010 + w.z * r001,
        du: d * (r010 - r100),
        dv: d * (r001 - r100),
        duu: dd * (q020 - 2.0 * q110 + q200),
        duv: dd * (q011 - q110 - q101 + q200),
        dvv: dd * (q002 - 2.0 * q101 + q200),
    }
}

/// The first `N` points split into their coordinates, one array each: the layout of the
/// de Casteljau steps of [`de_casteljau_step_by_coordinate`].
#[inline(always)]
pub(crate) fn by_coordinate<const N: usize>(points: &[DVec3]) -> [[f64; N]; 3] {
    let points = &points[..N];
    [
        std::array::from_fn(|n| points[n].x),
        std::array::from_fn(|n| points[n].y),
        std::array::from_fn(|n| points[n].z),
    ]
}

/// [`de_casteljau_step`] on a net held one coordinate per array ([`by_coordinate`]): each
/// coordinate of a new point by the same operations as the `DVec3` step (so the same bits),
/// but a row's points lie side by side in memory and the compiler packs several of them into
/// one vector instruction.
#[inline(always)]
pub(crate) fn de_casteljau_step_by_coordinate<const N: usize>(
    net: &mut [[f64; N]; 3],
    m: usize,
    w: DVec3,
) {
    for coordinate in net {
        de_casteljau_rows(coordinate, m, |t, b_j, b_k| {
            *t = w.x * *t + w.y * *b_j + w.z * *b_k;
        });
    }
}

/// [`TriangleBezier::jet`] of a net of degree `D` (`N` points, `2 ≤ D`): the same de Casteljau
/// steps as the general path, in the same order (so the same bits), with the degree known to
/// the compiler, which unrolls the rows and drops their index checks. The jet at every ray hit
/// and every fold-test sample of the schemes runs through here. The net is walked one
/// coordinate at a time ([`de_casteljau_step_by_coordinate`]).
#[inline(always)]
fn jet_of_degree<const D: usize, const N: usize>(points: &[DVec3], w: DVec3) -> Jet {
    let mut coordinates = by_coordinate::<N>(points);
    for m in (3..=D).rev() {
        de_casteljau_step_by_coordinate(&mut coordinates, m, w);
    }
    let [x, y, z] = &coordinates;
    let quadratic: [DVec3; 6] = std::array::from_fn(|n| DVec3::new(x[n], y[n], z[n]));
    jet_from_quadratic_level(&quadratic, D, w)
}

/// A triangular Bézier patch `B(w0,w1,w2) = Σ b(i,j,k) d!/(i!j!k!) w0^i w1^j w2^k`.
///
/// The control points are stored as offsets from an origin of the patch's own (zero unless the
/// construction chose one, e.g. a corner of its mesh face): a patch far from the origin of its
/// frame keeps the precision of its own size, so its derivatives — differences of offsets,
/// which the continuity measures read — are not rounded at the size of the frame (a face
/// 1e-7 of the mesh wide keeps 1e-16 of its own width, not of the mesh's). Positions add the
/// origin; derivatives never see it.
#[derive(Clone, Debug, PartialEq)]
pub struct TriangleBezier {
    degree: usize,
    origin: DVec3,
    points: Vec<DVec3>,
}

impl TriangleBezier {
    /// A patch from its control points in the module's order. Panics if the count is wrong
    /// (use [`TriangleBezier::try_new`] for points that come from outside the program).
    pub fn new(degree: usize, points: Vec<DVec3>) -> Self {
        assert_eq!(
            points.len(),
            point_count(degree),
            "a degree-{degree} triangle has {} control points",
            point_count(degree)
        );
        TriangleBezier {
            degree,
            origin: DVec3::ZERO,
            points,
        }
    }

    /// A patch whose control points are `origin + offsets[n]` (see [`TriangleBezier`]): the
    /// offsets are kept as given, so a construction that computes them relative to a point
    /// near the patch keeps their precision. Panics if the count is wrong.
    pub fn with_origin(degree: usize, origin: DVec3, offsets: Vec<DVec3>) -> Self {
        TriangleBezier {
            origin,
            ..TriangleBezier::new(degree, offsets)
        }
    }

    /// This net moved by `origin`, without touching its stored points: a net built in a face's
    /// own frame (points relative to the face's origin), placed where the face is.
    pub fn placed_at(self, origin: DVec3) -> Self {
        TriangleBezier {
            origin: self.origin + origin,
            ..self
        }
    }

    /// A patch from control points read from outside (a file): the count must be
    /// `(d+1)(d+2)/2` and every coordinate finite, else an error names the point at fault.
    pub fn try_new(degree: usize, points: Vec<DVec3>) -> Result<Self> {
        if points.len() != point_count(degree) {
            return Err(Error::Invalid(format!(
                "a degree-{degree} triangular patch needs {} control points, got {}",
                point_count(degree),
                points.len()
            )));
        }
        if let Some(n) = points.iter().position(|p| !p.is_finite()) {
            return Err(Error::Invalid(format!(
                "control point {n} of a degree-{degree} triangular patch is not finite"
            )));
        }
        Ok(TriangleBezier {
            degree,
            origin: DVec3::ZERO,
            points,
        })
    }

    /// A patch whose point `b(i,j,k)` is `f(i, j, k)`.
    pub fn from_fn(degree: usize, mut f: impl FnMut(usize, usize, usize) -> DVec3) -> Self {
        let mut points = Vec::with_capacity(point_count(degree));
        for i in (0..=degree).rev() {
            for j in (0..=degree - i).rev() {
                points.push(f(i, j, degree - i - j));
            }
        }
        TriangleBezier::new(degree, points)
    }

    /// Polynomial degree.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The point the control points are stored relative to (see [`TriangleBezier`]).
    pub fn origin(&self) -> DVec3 {
        self.origin
    }

    /// The control points relative to [`TriangleBezier::origin`], in the module's order: what
    /// differences of control points (derivatives) are computed from.
    pub fn offsets(&self) -> &[DVec3] {
        &self.points
    }

    /// The control points (origin added), in the module's order.
    pub fn control_points(&self) -> impl ExactSizeIterator<Item = DVec3> + '_ {
        self.points.iter().map(|&b| self.origin + b)
    }

    /// The largest coordinate magnitude of the offsets: the scale at which the stored net,
    /// and every difference of its points, is rounded.
    pub fn offset_magnitude(&self) -> f64 {
        self.points
            .iter()
            .fold(0.0, |m, b| m.max(b.abs().max_element()))
    }

    /// Offset of control point `b(i,j,k)` (k = d − i − j). Panics if `i + j > d`.
    pub fn offset(&self, i: usize, j: usize) -> DVec3 {
        assert!(
            i + j <= self.degree,
            "b({i},{j},·) of a degree-{} triangle",
            self.degree
        );
        self.points[index(self.degree, i, j)]
    }

    /// Control point `b(i,j,k)` (k = d − i − j), origin added. Panics if `i + j > d`.
    pub fn point(&self, i: usize, j: usize) -> DVec3 {
        self.origin + self.offset(i, j)
    }

    /// Sets control point `b(i,j,k)` to `p` (stored as `p − origin`). Panics if `i + j > d`.
    pub fn set_point(&mut self, i: usize, j: usize, p: DVec3) {
        assert!(
            i + j <= self.degree,
            "b({i},{j},·) of a degree-{} triangle",
            self.degree
        );
        self.points[index(self.degree, i, j)] = p - self.origin;
    }

    /// Point at barycentric coordinates `bary` by de Casteljau [Piper87 eq. 8]
    /// (need not sum to one for blossoms; here it should). Allocation-free for degree ≤ 8.
    pub fn eval(&self, bary: DVec3) -> DVec3 {
        let degree = self.degree;
        with_working_net(&self.points, |net| {
            for m in (1..=degree).rev() {
                de_casteljau_step(net, m, bary);
            }
            self.origin + net[0]
        })
    }

    /// Position and first/second derivatives with respect to `(u, v)`, barycentric `(1−u−v, u, v)`.
    /// Allocation-free for degree ≤ 8.
    ///
    /// de Casteljau runs down to degree 2; the last levels give the derivatives
    /// [Piper87 eq. 10] (see `jet_from_quadratic_level`). Degrees 0 and 1 have zero second
    /// derivatives.
    pub fn jet(&self, u: f64, v: f64) -> Jet {
        let w = DVec3::new(1.0 - u - v, u, v);
        let mut jet = self.offset_jet(w);
        jet.p += self.origin;
        jet
    }

    /// [`TriangleBezier::jet`] of the offsets at barycentric `w`.
    #[inline(always)]
    fn offset_jet(&self, w: DVec3) -> Jet {
        let b = &self.points;
        match self.degree {
            0 => Jet {
                p: b[0],
                ..Jet::default()
            },
            1 => Jet {
                p: w.x * b[0] + w.y * b[1] + w.z * b[2],
                du: b[1] - b[0],
                dv: b[2] - b[0],
                ..Jet::default()
            },
            2 => jet_of_degree::<2, 6>(b, w),
            3 => jet_of_degree::<3, 10>(b, w),
            4 => jet_of_degree::<4, 15>(b, w),
            5 => jet_of_degree::<5, 21>(b, w),
            6 => jet_of_degree::<6, 28>(b, w),
            degree => with_working_net(b, |net| {
                for m in (3..=degree).rev() {
                    de_casteljau_step(net, m, w);
                }
                jet_from_quadratic_level(net, degree, w)
            }),
        }
    }

    /// The blossom (polar form) at `d` barycentric arguments: symmetric, affine in each
    /// argument, and equal to the patch on the diagonal (Farin, CAGD §17.4). Computed by one
    /// de Casteljau step per argument. Panics unless `args.len() == d`.
    pub fn blossom(&self, args: &[DVec3]) -> DVec3 {
        let degree = self.degree;
        assert_eq!(
            args.len(),
            degree,
            "the blossom of a degree-{degree} patch takes {degree} arguments"
        );
        // The origin is a constant polynomial: its blossom is the product of the arguments'
        // weight sums (1 at points of the domain, 0 at directions).
        let origin_weight: f64 = args.iter().map(|w| w.x + w.y + w.z).product();
        with_working_net(&self.points, |net| {
            for (m, &w) in (1..=degree).rev().zip(args) {
                de_casteljau_step(net, m, w);
            }
            net[0]
        }) + origin_weight * self.origin
    }

    /// All partial derivatives `∂^{i+j} S / ∂u^i ∂v^j` at `(u, v)` for `i + j ≤ max_order`, by
    /// total order m, then i from m down to 0: `(0,0), (1,0), (0,1), (2,0), (1,1), (0,2), …`.
    /// Each is `d!/(d−m)!` times the blossom at `m` direction vectors and `d − m` copies of the
    /// point (Farin, CAGD §17.4); orders above the degree are zero.
    pub fn partials(&self, u: f64, v: f64, max_order: usize) -> Vec<DVec3> {
        let d = self.degree;
        let x = DVec3::new(1.0 - u - v, u, v);
        let (du, dv) = (DVec3::new(-1.0, 1.0, 0.0), DVec3::new(-1.0, 0.0, 1.0));
        let mut out = Vec::with_capacity((max_order + 1) * (max_order + 2) / 2);
        let mut args = Vec::with_capacity(d);
        for m in 0..=max_order {
            for i in (0..=m).rev() {
                if m > d {
                    out.push(DVec3::ZERO);
                    continue;
                }
                args.clear();
                args.extend(std::iter::repeat_n(du, i));
                args.extend(std::iter::repeat_n(dv, m - i));
                args.extend(std::iter::repeat_n(x, d - m));
                let falling: f64 = (d + 1 - m..=d).map(|k| k as f64).product();
                out.push(falling * self.blossom(&args));
            }
        }
        out
    }

    /// The patch with every control point mapped by `f` (exact for affine maps up to the
    /// rounding of the mapped points): the result has origin zero, its points in `f`'s
    /// coordinates (the user's, or a renderer's).
    pub fn map_points(&self, f: impl Fn(DVec3) -> DVec3) -> TriangleBezier {
        TriangleBezier::new(self.degree, self.control_points().map(f).collect())
    }

    /// [`TriangleBezier::map_points`] in place: no second net.
    pub(crate) fn map_points_in_place(&mut self, f: impl Fn(DVec3) -> DVec3) {
        let origin = std::mem::take(&mut self.origin);
        for p in &mut self.points {
            *p = f(origin + *p);
        }
    }

    /// The patch scaled about the frame's origin by `factor`: origin and offsets each
    /// multiplied, so a power of two scales it exactly, keeping its own precision.
    pub fn scaled(&self, factor: f64) -> TriangleBezier {
        TriangleBezier {
            degree: self.degree,
            origin: self.origin * factor,
            points: self.points.iter().map(|&b| b * factor).collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bezier::test_support::{bernstein_partial, bernstein_sum, rel_err, scale_of};
    use crate::testing::Rng;

    /// Degrees the property tests run over: 1..=7 as specified, plus 0 and the heap path above
    /// 8.
    const DEGREES: [usize; 10] = [0, 1, 2, 3, 4, 5, 6, 7, 9, 11];

    /// Parameters inside the domain and slightly outside (extrapolation must be right too).
    fn sample_params(rng: &mut Rng) -> Vec<(f64, f64)> {
        let mut params = vec![(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0 / 3.0, 1.0 / 3.0)];
        for _ in 0..12 {
            let w = rng.bary_inside();
            params.push((w.y, w.z));
        }
        params.push((-0.1, 0.3));
        params.push((0.7, 0.45));
        params
    }

    #[test]
    fn index_follows_the_documented_order() {
        for d in 0..=9 {
            let mut expected = 0;
            for i in (0..=d).rev() {
                for j in (0..=d - i).rev() {
                    assert_eq!(index(d, i, j), expected, "d={d} i={i} j={j}");
                    expected += 1;
                }
            }
            assert_eq!(expected, point_count(d));
            let patch =
                TriangleBezier::from_fn(d, |i, j, k| DVec3::new(i as f64, j as f64, k as f64));
            assert_eq!(patch.offsets()[0], DVec3::new(d as f64, 0.0, 0.0));
            assert_eq!(
                patch.offsets()[point_count(d) - 1],
                DVec3::new(0.0, 0.0, d as f64)
            );
            for i in 0..=d {
                for j in 0..=d - i {
                    assert_eq!(
                        patch.point(i, j),
                        DVec3::new(i as f64, j as f64, (d - i - j) as f64)
                    );
                }
            }
        }
    }

    #[test]
    fn set_point_and_try_new() {
        let mut patch = TriangleBezier::from_fn(3, |_, _, _| DVec3::ZERO);
        patch.set_point(1, 1, DVec3::ONE);
        assert_eq!(patch.offsets()[index(3, 1, 1)], DVec3::ONE);
        assert_eq!(
            patch.offsets().iter().filter(|p| **p == DVec3::ONE).count(),
            1
        );
        assert!(TriangleBezier::try_new(2, vec![DVec3::ZERO; 6]).is_ok());
        let err = TriangleBezier::try_new(2, vec![DVec3::ZERO; 5]).unwrap_err();
        assert!(
            err.to_string().contains("needs 6 control points, got 5"),
            "{err}"
        );
        let mut bad = vec![DVec3::ZERO; 6];
        bad[4].y = f64::NAN;
        let err = TriangleBezier::try_new(2, bad).unwrap_err();
        assert!(err.to_string().contains("control point 4"), "{err}");
    }

    #[test]
    fn eval_equals_the_bernstein_sum() {
        let mut rng = Rng::new(1);
        for d in DEGREES {
            for offset in [0.0, 5.0] {
                let patch = rng.triangle(d, offset);
                let scale = scale_of(patch.offsets());
                for (u, v) in sample_params(&mut rng) {
                    let w = DVec3::new(1.0 - u - v, u, v);
                    let err = rel_err(patch.eval(w), bernstein_sum(&patch, w), scale);
                    assert!(err <= 1e-12, "d={d} (u,v)=({u},{v}) rel err {err:e}");
                }
            }
        }
    }

    /// The exact `(u, v)` derivatives of the Bernstein sum by the chain rule through
    /// `w = (1−u−v, u, v)`: `∂u = ∂w1 − ∂w0`, `∂v = ∂w2 − ∂w0`.
    fn exact_jet(patch: &TriangleBezier, u: f64, v: f64) -> Jet {
        let w = DVec3::new(1.0 - u - v, u, v);
        let dw = |a: [usize; 3]| bernstein_partial(patch, w, a);
        Jet {
            p: dw([0, 0, 0]),
            du: dw([0, 1, 0]) - dw([1, 0, 0]),
            dv: dw([0, 0, 1]) - dw([1, 0, 0]),
            duu: dw([0, 2, 0]) - 2.0 * dw([1, 1, 0]) + dw([2, 0, 0]),
            duv: dw([0, 1, 1]) - dw([1, 1, 0]) - dw([1, 0, 1]) + dw([2, 0, 0]),
            dvv: dw([0, 0, 2]) - 2.0 * dw([1, 0, 1]) + dw([2, 0, 0]),
        }
    }

    fn jet_fields(jet: &Jet) -> [(&'static str, DVec3); 6] {
        [
            ("p", jet.p),
            ("du", jet.du),
            ("dv", jet.dv),
            ("duu", jet.duu),
            ("duv", jet.duv),
            ("dvv", jet.dvv),
        ]
    }

    #[test]
    fn jet_equals_exact_derivatives_of_the_bernstein_sum() {
        let mut rng = Rng::new(2);
        for d in DEGREES {
            let patch = rng.triangle(d, 1.0);
            // Derivatives grow like d(d−1)·|b|: measure relative to that.
            let scale = scale_of(patch.offsets()) * (d * d).max(1) as f64;
            for (u, v) in sample_params(&mut rng) {
                let jet = patch.jet(u, v);
                let exact = exact_jet(&patch, u, v);
                for ((name, got), (_, want)) in jet_fields(&jet).into_iter().zip(jet_fields(&exact))
                {
                    let err = rel_err(got, want, scale);
                    assert!(
                        err <= 1e-11,
                        "d={d} (u,v)=({u},{v}) {name}: rel err {err:e}"
                    );
                }
                assert_eq!(jet.p, patch.eval(DVec3::new(1.0 - u - v, u, v)), "d={d}");
            }
        }
    }

    /// Central differences of the position: every derivative of the jet, with the O(h²)
    /// truncation error of a central difference. Halving h must divide the error by ~4
    /// (or, for the low degrees where the difference quotient is exact, leave it at rounding).
    #[test]
    fn jet_matches_central_differences_with_second_order_truncation() {
        let mut rng = Rng::new(3);
        let central = |patch: &TriangleBezier, u: f64, v: f64, h: f64| {
            let p =
                |du: f64, dv: f64| patch.eval(DVec3::new(1.0 - u - v - du - dv, u + du, v + dv));
            Jet {
                p: p(0.0, 0.0),
                du: (p(h, 0.0) - p(-h, 0.0)) / (2.0 * h),
                dv: (p(0.0, h) - p(0.0, -h)) / (2.0 * h),
                duu: (p(h, 0.0) - 2.0 * p(0.0, 0.0) + p(-h, 0.0)) / (h * h),
                duv: (p(h, h) - p(h, -h) - p(-h, h) + p(-h, -h)) / (4.0 * h * h),
                dvv: (p(0.0, h) - 2.0 * p(0.0, 0.0) + p(0.0, -h)) / (h * h),
            }
        };
        let h = 1e-2;
        for d in DEGREES {
            let patch = rng.triangle(d, 0.0);
            let scale = scale_of(patch.offsets()) * (d * d).max(1) as f64;
            for (u, v) in sample_params(&mut rng) {
                let jet = patch.jet(u, v);
                let coarse = central(&patch, u, v, h);
                let fine = central(&patch, u, v, h / 2.0);
                for (((name, exact), (_, c)), (_, f)) in jet_fields(&jet)
                    .into_iter()
                    .zip(jet_fields(&coarse))
                    .zip(jet_fields(&fine))
                    .skip(1)
                {
                    let (err_coarse, err_fine) = ((c - exact).length(), (f - exact).length());
                    // Rounding in the difference quotients: ~ε·|b|/h² for the second ones.
                    let rounding = 1e-9 * scale;
                    if err_coarse > 1e3 * rounding {
                        let ratio = err_coarse / err_fine;
                        assert!(
                            (3.5..=4.5).contains(&ratio),
                            "d={d} (u,v)=({u},{v}) {name}: error ratio {ratio} for h → h/2 \
                             ({err_coarse:e} → {err_fine:e})"
                        );
                    } else {
                        assert!(
                            err_fine <= 1e3 * rounding,
                            "d={d} {name}: {err_coarse:e} → {err_fine:e}"
                        );
                    }
                }
            }
        }
    }

    /// Barycentric arguments that sum to one but lie anywhere near the domain.
    fn random_args(rng: &mut Rng, count: usize) -> Vec<DVec3> {
        (0..count)
            .map(|_| {
                let (u, v) = (rng.range(-0.5, 1.5), rng.range(-0.5, 1.5));
                DVec3::new(1.0 - u - v, u, v)
            })
            .collect()
    }

    #[test]
    fn blossom_on_the_diagonal_is_the_patch() {
        let mut rng = Rng::new(4);
        for d in DEGREES {
            let patch = rng.triangle(d, 2.0);
            let scale = scale_of(patch.offsets());
            for _ in 0..8 {
                let w = rng.bary_inside();
                let err = rel_err(patch.blossom(&vec![w; d]), patch.eval(w), scale);
                assert!(err <= 1e-12, "d={d}: rel err {err:e}");
            }
        }
    }

    #[test]
    fn blossom_is_symmetric() {
        let mut rng = Rng::new(5);
        for d in DEGREES.into_iter().filter(|&d| d >= 2) {
            let patch = rng.triangle(d, 0.0);
            let scale = scale_of(patch.offsets());
            for _ in 0..8 {
                let args = random_args(&mut rng, d);
                let value = patch.blossom(&args);
                let mut reversed = args.clone();
                reversed.reverse();
                let mut rotated = args.clone();
                rotated.rotate_left(1);
                let mut swapped = args.clone();
                swapped.swap(0, d - 1);
                for (name, permuted) in [
                    ("reversed", reversed),
                    ("rotated", rotated),
                    ("swapped", swapped),
                ] {
                    let err = rel_err(patch.blossom(&permuted), value, scale);
                    assert!(err <= 1e-12, "d={d} {name}: rel err {err:e}");
                }
            }
        }
    }

    /// `b[.., αx + (1−α)y, ..] = α b[.., x, ..] + (1−α) b[.., y, ..]` in every slot, also for α
    /// outside [0, 1].
    #[test]
    fn blossom_is_affine_in_each_argument() {
        let mut rng = Rng::new(6);
        for d in DEGREES.into_iter().filter(|&d| d >= 1) {
            let patch = rng.triangle(d, 1.0);
            let scale = scale_of(patch.offsets());
            for slot in 0..d {
                let mut args = random_args(&mut rng, d);
                let (x, y) = (random_args(&mut rng, 1)[0], random_args(&mut rng, 1)[0]);
                let alpha = rng.range(-1.0, 2.0);
                args[slot] = x;
                let at_x = patch.blossom(&args);
                args[slot] = y;
                let at_y = patch.blossom(&args);
                args[slot] = alpha * x + (1.0 - alpha) * y;
                let at_mix = patch.blossom(&args);
                let amplification = alpha.abs() + (1.0 - alpha).abs();
                let err = rel_err(
                    at_mix,
                    alpha * at_x + (1.0 - alpha) * at_y,
                    scale * amplification,
                );
                assert!(err <= 1e-12, "d={d} slot {slot} α={alpha}: rel err {err:e}");
            }
        }
    }

    /// `partials` agrees with `jet` to order 2, and a cubic's third derivatives are exact
    /// constants: S = (u³, u²v, v³) has S_uuu = (6,0,0), S_uuv = (0,2,0), S_vvv = (0,0,6).
    #[test]
    fn partials_match_the_jet_and_exact_third_derivatives() {
        let mut rng = Rng::new(77);
        for d in 1..=7 {
            let patch = rng.triangle(d, 0.0);
            let (u, v) = (0.23, 0.41);
            let p = patch.partials(u, v, 3);
            let j = patch.jet(u, v);
            for (got, want) in p.iter().zip([j.p, j.du, j.dv, j.duu, j.duv, j.dvv]) {
                assert!(
                    (*got - want).length() <= 1e-11 * (1.0 + want.length()),
                    "d={d}"
                );
            }
        }
        // With barycentric (w0, w1, w2) = (1−u−v, u, v): u³ = B_{030}, u²v = B_{021}/3,
        // v³ = B_{003}.
        let cubic = TriangleBezier::from_fn(3, |_, j, k| {
            DVec3::new(
                f64::from(u8::from(j == 3)),
                f64::from(u8::from(j == 2 && k == 1)) / 3.0,
                f64::from(u8::from(k == 3)),
            )
        });
        let p = cubic.partials(0.3, 0.2, 4);
        assert!(
            (p[6] - DVec3::new(6.0, 0.0, 0.0)).length() < 1e-13,
            "{}",
            p[6]
        );
        assert!(
            (p[7] - DVec3::new(0.0, 2.0, 0.0)).length() < 1e-13,
            "{}",
            p[7]
        );
        assert!(
            (p[9] - DVec3::new(0.0, 0.0, 6.0)).length() < 1e-13,
            "{}",
            p[9]
        );
        assert!(p[10..].iter().all(|x| *x == DVec3::ZERO));
    }

    /// A net stored with an origin is the net of the absolute points: positions add the
    /// origin, derivatives and directional blossoms do not see it, and subdivision, elevation,
    /// scaling and bounds carry it along — to the rounding of the absolute points.
    #[test]
    fn a_net_with_an_origin_is_the_net_of_its_absolute_points() {
        let mut rng = Rng::new(0x0f);
        let origin = DVec3::new(5.0, -3.0, 2.0);
        for d in DEGREES.into_iter().filter(|&d| d >= 1) {
            let local = rng.triangle(d, 0.0);
            let placed = local.clone().placed_at(origin);
            let absolute = TriangleBezier::new(d, placed.control_points().collect());
            let scale = scale_of(absolute.offsets()) * (d * d) as f64;
            let close = |a: DVec3, b: DVec3| rel_err(a, b, scale) <= 1e-14;
            for (u, v) in sample_params(&mut rng) {
                let (a, b) = (placed.jet(u, v), absolute.jet(u, v));
                assert!(
                    close(a.p, b.p) && close(a.du, b.du) && close(a.duv, b.duv),
                    "d = {d}"
                );
                // Derivatives are those of the offsets alone, bit for bit.
                assert_eq!(a.du, local.jet(u, v).du, "d = {d}");
                // Third derivatives grow like d³·|b|.
                let all = |n: &TriangleBezier| n.partials(u, v, d.min(3));
                let third = |a: &DVec3, b: DVec3| rel_err(*a, b, scale * d as f64) <= 1e-14;
                assert!(
                    all(&placed)
                        .iter()
                        .zip(all(&absolute))
                        .all(|(a, b)| third(a, b))
                );
            }
            let direction = DVec3::new(-1.0, 1.0, 0.0);
            let args: Vec<DVec3> = std::iter::once(direction)
                .chain(std::iter::repeat_n(rng.bary_inside(), d - 1))
                .collect();
            assert_eq!(placed.blossom(&args), local.blossom(&args), "d = {d}");
            let corners = [DVec3::X, DVec3::new(0.5, 0.5, 0.0), DVec3::splat(1.0 / 3.0)];
            let forms = [
                (
                    placed.subdivide(corners),
                    absolute.subdivide(corners),
                    origin,
                ),
                (placed.elevate(), absolute.elevate(), origin),
                (placed.scaled(0.5), absolute.scaled(0.5), 0.5 * origin),
            ];
            for (a, b, kept) in &forms {
                assert_eq!(a.origin(), *kept, "d = {d}");
                assert!(
                    a.control_points()
                        .zip(b.control_points())
                        .all(|(p, q)| close(p, q))
                );
            }
            let (a, b) = (placed.control_bounds(), absolute.control_bounds());
            assert!(close(a.min, b.min) && close(a.max, b.max), "d = {d}");
        }
    }
}
