//! The evaluation Newton needs, and nothing more: position and first derivatives.
//!
//! Two forms:
//! - [`point_and_tangents`]: a whole patch at `(u, v)`, by de Casteljau down to the linear level
//!   on a stack copy of the net (no allocation, no second derivatives). Falls back to
//!   [`Patch::jet`] for degrees above [`MAX_STACK_DEGREE`] and for non-polynomial patch kinds.
//! - [`local_point_and_tangents`]: a patch in power form over its domain,
//!   `S(s, t) = Σ c_jk s^j t^k` with `(s, t)` the barycentrics of its second and third corner
//!   ([`power_coefficients`], computed once per patch at BVH build), which a BVH leaf evaluates
//!   in its own coordinates through its domain map ([`leaf_point_and_tangents`], [`LeafMap`]).
//!   Nested Horner with the degree as a constant needs about a third of de Casteljau's
//!   arithmetic. Its rounding is a few ulps of the coefficients' sizes, which for a patch in the
//!   tracer's unit frame are those of its position: far below the root tolerance.

use glam::{DVec2, DVec3};

use crate::bezier::triangle::{index, point_count};

use crate::bezier::TriangleBezier;
use crate::surface::Patch;

/// Largest degree evaluated on the stack (28 control points).
pub(crate) const MAX_STACK_DEGREE: usize = 6;

/// `S(u, v)`, `∂S/∂u`, `∂S/∂v` at barycentric `(1−u−v, u, v)`.
pub(crate) fn point_and_tangents(patch: &Patch, u: f64, v: f64) -> (DVec3, DVec3, DVec3) {
    if let Some(blend) = patch.as_blend() {
        return blend.point_and_tangents(u, v);
    }
    let Some(net) = patch.as_bezier() else {
        let jet = patch.jet(u, v);
        return (jet.p, jet.du, jet.dv);
    };
    net_point_and_tangents(net, u, v)
}

/// [`point_and_tangents`] of a Bézier triangle: de Casteljau on the stack up to degree
/// [`MAX_STACK_DEGREE`], its jet above.
pub(crate) fn net_point_and_tangents(
    net: &TriangleBezier,
    u: f64,
    v: f64,
) -> (DVec3, DVec3, DVec3) {
    let d = net.degree();
    if d == 0 || d > MAX_STACK_DEGREE {
        let jet = net.jet(u, v);
        return (jet.p, jet.du, jet.dv);
    }
    let w = DVec3::new(1.0 - u - v, u, v);
    let mut b = [DVec3::ZERO; point_count(MAX_STACK_DEGREE)];
    // In the storage order, the points with first index i form "row" r = d − i, starting at
    // T(r) = r(r+1)/2, with position s = r − j along it. One de Casteljau step maps rows r−1
    // and r of degree m to row r−1 of degree m−1:
    //   b'[T(r−1)+s] = w0 b[T(r−1)+s] + w1 b[T(r)+s] + w2 b[T(r)+s+1],
    // so it runs in place with r ascending and streams through memory. The first step reads
    // the net directly (no copy).
    let src = net.offsets();
    if d == 1 {
        b[..3].copy_from_slice(src);
    } else {
        for r in 1..=d {
            let (prev, row) = (r * (r - 1) / 2, r * (r + 1) / 2);
            for s in 0..r {
                b[prev + s] = w.x * src[prev + s] + w.y * src[row + s] + w.z * src[row + s + 1];
            }
        }
    }
    for m in (2..d).rev() {
        for r in 1..=m {
            let (prev, row) = (r * (r - 1) / 2, r * (r + 1) / 2);
            for s in 0..r {
                b[prev + s] = w.x * b[prev + s] + w.y * b[row + s] + w.z * b[row + s + 1];
            }
        }
    }
    // The linear level b(1,0,0), b(0,1,0), b(0,0,1): its plane is the tangent plane
    // [Farin, CAGD §17.3].
    let (b100, b010, b001) = (b[index(1, 1, 0)], b[index(1, 0, 1)], b[index(1, 0, 0)]);
    let scale = d as f64;
    (
        net.origin() + (w.x * b100 + w.y * b010 + w.z * b001),
        (b010 - b100) * scale,
        (b001 - b100) * scale,
    )
}

/// The power form of a Bézier triangle over its own domain: coefficients `c_jk` with
/// `S(s, t) = Σ_{j+k ≤ d} c_jk s^j t^k` at barycentric `(1−s−t, s, t)`, stored row by row (`j`
/// ascending, then `k` ascending; row `j` holds `d−j+1` entries, see [`power_index`]).
///
/// With `f(j, k) = b(d−j−k, j, k)` and forward differences Δ₁ in `j`, Δ₂ in `k`, the Taylor
/// coefficients at the first corner are `c_jk = d! / (j! k! (d−j−k)!) · Δ₁^j Δ₂^k f(0, 0)`, the
/// triangular form of the univariate `c_j = C(d, j) Δ^j b_0` [Farin, CAGD §17.3].
///
/// The net is given by `point(i, j)`, its control point `b(i, j, ·)`, and the form written
/// into `c` (`point_count(d)` entries): no net or vector is made, so the BVH build makes one
/// form per patch straight into its array.
pub(crate) fn power_coefficients(d: usize, point: impl Fn(usize, usize) -> DVec3, c: &mut [DVec3]) {
    for j in 0..=d {
        for k in 0..=d - j {
            c[power_index(d, j, k)] = point(d - j - k, j);
        }
    }
    // Differences in k along every row j, in place: row[k] becomes Δ₂^k f(j, 0).
    for j in 0..=d {
        let row = power_index(d, j, 0);
        let len = d - j;
        for order in 1..=len {
            for k in (order..=len).rev() {
                c[row + k] -= c[row + k - 1];
            }
        }
    }
    // Then differences in j along every column k: entry (j, k) becomes Δ₁^j Δ₂^k f(0, 0).
    for k in 0..=d {
        let len = d - k;
        for order in 1..=len {
            for j in (order..=len).rev() {
                let (at, below) = (power_index(d, j, k), power_index(d, j - 1, k));
                c[at] -= c[below];
            }
        }
    }
    let factorial = |n: usize| (1..=n).map(|x| x as f64).product::<f64>();
    for j in 0..=d {
        for k in 0..=d - j {
            let multinomial = factorial(d) / (factorial(j) * factorial(k) * factorial(d - j - k));
            c[power_index(d, j, k)] *= multinomial;
        }
    }
}

/// Position of `c_jk` in [`power_coefficients`] of degree `d`: rows `0..j` hold
/// `(d+1) + d + … + (d−j+2)` entries.
pub(crate) const fn power_index(d: usize, j: usize, k: usize) -> usize {
    j * (d + 1) - j * (j.saturating_sub(1)) / 2 + k
}

/// `S(s, t)`, `∂S/∂s`, `∂S/∂t` of the degree-`D` power form `c` ([`power_coefficients`]), by
/// Horner in `t` inside each row and in `s` across rows; `c` must hold `(D+1)(D+2)/2`
/// coefficients (`D` ≤ [`MAX_STACK_DEGREE`]).
///
/// The rows are written out one by one (from row `MAX_STACK_DEGREE` down, those above `D`
/// dropped at compile time), so each row's start and length are constants and its Horner
/// loop unrolls: a loop over the rows would compute their starts and check their bounds at
/// run time, and the compiler does not unroll it.
#[inline]
pub(crate) fn local_point_and_tangents<const D: usize>(
    c: &[DVec3],
    s: f64,
    t: f64,
) -> (DVec3, DVec3, DVec3) {
    const { assert!(D <= MAX_STACK_DEGREE) };
    let c = &c[..point_count(D)];
    let (mut p, mut ps, mut pt) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
    macro_rules! row {
        ($j:literal) => {
            if $j <= D {
                row!(always $j);
            }
        };
        (always $j:literal) => {
            {
                let start = power_index(D, $j, 0);
                // Row polynomial q_j(t) = Σ_k c_jk t^k and its derivative.
                let mut q = c[start + D - $j];
                let mut qt = DVec3::ZERO;
                for k in (0..D - $j).rev() {
                    qt = qt * t + q;
                    q = q * t + c[start + k];
                }
                ps = ps * s + p;
                p = p * s + q;
                pt = pt * s + qt;
            }
        };
    }
    row!(6);
    row!(5);
    row!(4);
    row!(3);
    row!(2);
    row!(1);
    row!(always 0);
    (p, ps, pt)
}

/// A leaf's domain in its patch: the affine map `(u, v) = origin + e1 s + e2 t` from the
/// leaf-local barycentrics `(1−s−t, s, t)` to the patch's, read off the leaf's sub-triangle
/// (corners `origin`, `origin + e1`, `origin + e2`). The corners are dyadic fractions (repeated
/// halving of the unit triangle), so `e1`, `e2` hold ±2⁻ᵏ or 0 and their products are exact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct LeafMap {
    /// The sub-triangle's first corner.
    pub origin: DVec2,
    /// Its second corner minus the first.
    pub e1: DVec2,
    /// Its third corner minus the first.
    pub e2: DVec2,
    /// True when the sub-triangle is the whole domain: the leaf's own coordinates are the
    /// patch's, and the patch's form is evaluated as it is.
    pub whole: bool,
}

impl LeafMap {
    /// The map of the sub-triangle `tri`.
    pub fn of(tri: [DVec2; 3]) -> LeafMap {
        LeafMap {
            origin: tri[0],
            e1: tri[1] - tri[0],
            e2: tri[2] - tri[0],
            whole: tri == crate::surface::UV_CORNERS,
        }
    }

    /// The patch coordinates of the leaf-local point `x`.
    pub fn apply(&self, x: DVec2) -> DVec2 {
        self.origin + self.e1 * x.x + self.e2 * x.y
    }
}

/// `S`, `∂S/∂s`, `∂S/∂t` at the leaf-local point `x` of the leaf with domain map `map`, from
/// its patch's degree-`D` power form `c` ([`power_coefficients`] over the patch's domain): the
/// form at `map.apply(x)` and the chain rule, `∂S/∂s = e1.x ∂S/∂u + e1.y ∂S/∂v` (likewise
/// `t` with `e2`). A leaf over the whole domain evaluates the form directly.
#[inline]
pub(crate) fn leaf_point_and_tangents<const D: usize>(
    c: &[DVec3],
    map: &LeafMap,
    x: DVec2,
) -> (DVec3, DVec3, DVec3) {
    if map.whole {
        return local_point_and_tangents::<D>(c, x.x, x.y);
    }
    let uv = map.apply(x);
    let (p, pu, pv) = local_point_and_tangents::<D>(c, uv.x, uv.y);
    (
        p,
        pu * map.e1.x + pv * map.e1.y,
        pu * map.e2.x + pv * map.e2.y,
    )
}

/// The projected Bézier net of a leaf ([`projected_net`] of the leaf's own power form) from
/// its patch's degree-`D` power form `c` and its domain map `map`, without the leaf's form
/// stored: the projected coefficients are re-expanded about the leaf's first corner (a
/// Taylor shift in `u`, then in `v`) and in the leaf's coordinates (`u − u₀ = e1.x s + e2.x t`,
/// `v − v₀ = e1.y s + e2.y t`; for a corner child's map, `e1.y = e2.x = 0`, a scaling of each
/// coefficient by powers of two), then turned into the net as [`projected_net`] does.
///
/// Returns the net, its magnitude (as [`projected_net`]'s) and a bound on what the
/// re-expansion adds to every entry's error: each re-expanded coefficient is a sum of
/// products whose absolute values, summed over all coefficients, are at most
/// `A = Σ_jk |c_jk|₁ R_u^j R_v^k + |offset|₁` (`R_u = |u₀| + |e1.x| + |e2.x|`, likewise
/// `R_v`; the projection's rows are unit vectors), and along no coefficient are there more than
/// 128 roundings (two shifts of at most `2D` each, the products, a sum of at most `(D+1)²`
/// terms), so the coefficients' errors sum to at most `128 ε A`; the net's entries weigh
/// each coefficient by at most 1 ([`projected_net`]), so that bounds each entry's added error.
/// A leaf over the whole domain is [`projected_net`] itself (added error 0).
pub(crate) fn projected_leaf_net<const D: usize>(
    c: &[DVec3],
    map: &LeafMap,
    project: impl Fn(DVec3) -> DVec2,
    offset: DVec2,
) -> ([DVec2; point_count(MAX_STACK_DEGREE)], f64, f64) {
    if map.whole {
        let (net, magnitude) = projected_net::<D>(c, project, offset);
        return (net, magnitude, 0.0);
    }
    let at = |j: usize, k: usize| power_index(D, j, k);
    let reach = map.origin.abs() + map.e1.abs() + map.e2.abs();
    let mut q = [DVec2::ZERO; point_count(MAX_STACK_DEGREE)];
    let mut absolute = offset.abs().element_sum();
    let mut reach_u = 1.0;
    for j in 0..=D {
        let mut weight = reach_u;
        for k in 0..=D - j {
            let i = at(j, k);
            q[i] = project(c[i]);
            absolute += c[i].abs().element_sum() * weight;
            weight *= reach.y;
        }
        reach_u *= reach.x;
    }
    q[0] -= offset;
    // Taylor shift in u about u₀ (none at u₀ = 0): for each power k of v, the row polynomial
    // in u (entries (j, k), j = 0..=D−k) becomes that of u − u₀, by synthetic division.
    for k in (0..D).filter(|_| map.origin.x != 0.0) {
        let n = D - k;
        for i in 0..n {
            for j in (i..n).rev() {
                let next = q[at(j + 1, k)];
                q[at(j, k)] += next * map.origin.x;
            }
        }
    }
    // Then in v about v₀, for each power j of u (entries (j, k), k = 0..=D−j).
    for j in (0..D).filter(|_| map.origin.y != 0.0) {
        let n = D - j;
        for i in 0..n {
            for k in (i..n).rev() {
                let next = q[at(j, k + 1)];
                q[at(j, k)] += next * map.origin.y;
            }
        }
    }
    let mut r = [DVec2::ZERO; point_count(MAX_STACK_DEGREE)];
    if map.e1.y == 0.0 && map.e2.x == 0.0 {
        // A corner child's map (u − u₀ = e1.x s, v − v₀ = e2.y t): each coefficient scales by
        // powers of two, exactly.
        let mut scale_j = 1.0;
        for j in 0..=D {
            let mut scale = scale_j;
            for k in 0..=D - j {
                r[at(j, k)] = q[at(j, k)] * scale;
                scale *= map.e2.y;
            }
            scale_j *= map.e1.x;
        }
    } else {
        substitute::<D>(&q, map.e1, map.e2, &mut r);
    }
    let mut magnitude = offset.abs().element_sum();
    for (i, r) in r.iter_mut().take(point_count(D)).enumerate() {
        *r *= InverseMultinomials::<D>::TABLE[i];
        magnitude += r.abs().element_sum();
    }
    let (sums, count) = RunningSums::<D>::STEPS;
    for &(to, from) in &sums[..count] {
        r[usize::from(to)] += r[usize::from(from)];
    }
    (r, magnitude, 128.0 * f64::EPSILON * absolute)
}

/// The coefficients `r` (zero to start with) of `Σ q_jk x^j y^k` in `s`, `t` for
/// `x = e1.x s + e2.x t`, `y = e1.y s + e2.y t` (degree `D`, [`power_index`] order): each term
/// expanded through the powers of `x` and `y`.
fn substitute<const D: usize>(q: &[DVec2], e1: DVec2, e2: DVec2, r: &mut [DVec2]) {
    let at = |j: usize, k: usize| power_index(D, j, k);
    // Powers of x = e1.x s + e2.x t and y = e1.y s + e2.y t: entry a of power n is the
    // coefficient of s^a t^(n−a).
    const ROOM: usize = MAX_STACK_DEGREE + 1;
    let powers = |a: f64, b: f64| {
        let mut p = [[0.0; ROOM]; ROOM];
        p[0][0] = 1.0;
        for n in 1..=D {
            for m in 0..=n {
                let from_s = if m > 0 { p[n - 1][m - 1] * a } else { 0.0 };
                let from_t = if m < n { p[n - 1][m] * b } else { 0.0 };
                p[n][m] = from_s + from_t;
            }
        }
        p
    };
    let (xp, yp) = (powers(e1.x, e2.x), powers(e1.y, e2.y));
    for j in 0..=D {
        for k in 0..=D - j {
            let d = q[at(j, k)];
            let n = j + k;
            for a in 0..=n {
                let mut w = 0.0;
                for a1 in a.saturating_sub(k)..=a.min(j) {
                    w += xp[j][a1] * yp[k][a - a1];
                }
                r[at(a, n - a)] += d * w;
            }
        }
    }
}

/// `1 / multinomial(D; j, k) = j! k! (D−j−k)! / D!` in [`power_index`] order: the factors that
/// undo the last step of [`power_coefficients`].
struct InverseMultinomials<const D: usize>;

impl<const D: usize> InverseMultinomials<D> {
    const TABLE: [f64; point_count(MAX_STACK_DEGREE)] = {
        let factorial = [1.0, 1.0, 2.0, 6.0, 24.0, 120.0, 720.0];
        let mut table = [0.0; point_count(MAX_STACK_DEGREE)];
        let mut j = 0;
        while j <= D {
            let mut k = 0;
            while k <= D - j {
                table[power_index(D, j, k)] =
                    factorial[j] * factorial[k] * factorial[D - j - k] / factorial[D];
                k += 1;
            }
            j += 1;
        }
        table
    };
}

/// The Bézier net of the degree-`D` power form `c` ([`power_coefficients`]) after the affine
/// map `project` (applied to the constant coefficient, its linear part to the others): the
/// inverse of [`power_coefficients`] — divide by the multinomials, then undo the forward
/// differences in `j`, then in `k`, by running sums — on the projected coefficients. Entry
/// `power_index(D, j, k)` is `project(b(D−j−k, j, k))`. The weights of the running sums are
/// positive and the result is a convex combination's worth of the inputs, so each entry's
/// rounding is a few ulps of `Σ |c_jk|` (returned second, as the sum of the projected
/// coefficients' absolute coordinates).
pub(crate) fn projected_net<const D: usize>(
    c: &[DVec3],
    project: impl Fn(DVec3) -> DVec2,
    offset: DVec2,
) -> ([DVec2; point_count(MAX_STACK_DEGREE)], f64) {
    let mut q = [DVec2::ZERO; point_count(MAX_STACK_DEGREE)];
    let mut magnitude = offset.abs().element_sum();
    for (i, (q, &c)) in q.iter_mut().zip(&c[..point_count(D)]).enumerate() {
        *q = project(c) * InverseMultinomials::<D>::TABLE[i];
        magnitude += q.abs().element_sum();
    }
    q[0] -= offset;
    let (sums, count) = RunningSums::<D>::STEPS;
    for &(to, from) in &sums[..count] {
        q[usize::from(to)] += q[usize::from(from)];
    }
    (q, magnitude)
}

/// The running sums that undo the forward differences of [`power_coefficients`] in degree
/// `D`, as `(to, from)` index pairs of `q[to] += q[from]` in the order they are applied: the
/// differences in `j` along every column `k` (applied last) first, then those in `k` along
/// every row. A table made at compile time, so the loop over it needs no index arithmetic.
struct RunningSums<const D: usize>;

/// Room for the [`RunningSums`] of [`MAX_STACK_DEGREE`]: `Σ_{l ≤ 6} l(l+1)/2 = 56` per
/// direction.
const RUNNING_SUMS_ROOM: usize = 2 * 56;

impl<const D: usize> RunningSums<D> {
    /// The steps, and how many of them there are.
    const STEPS: ([(u8, u8); RUNNING_SUMS_ROOM], usize) = {
        let mut steps = [(0_u8, 0_u8); RUNNING_SUMS_ROOM];
        let mut n = 0;
        let mut k = 0;
        while k <= D {
            let len = D - k;
            let mut order = len;
            while order >= 1 {
                let mut j = order;
                while j <= len {
                    steps[n] = (power_index(D, j, k) as u8, power_index(D, j - 1, k) as u8);
                    n += 1;
                    j += 1;
                }
                order -= 1;
            }
            k += 1;
        }
        let mut j = 0;
        while j <= D {
            let row = power_index(D, j, 0);
            let len = D - j;
            let mut order = len;
            while order >= 1 {
                let mut k = order;
                while k <= len {
                    steps[n] = ((row + k) as u8, (row + k - 1) as u8);
                    n += 1;
                    k += 1;
                }
                order -= 1;
            }
            j += 1;
        }
        (steps, n)
    };
}

/// Bounds `[tangential, normal]` on the second derivative of a Bézier triangle in any unit
/// `(u, v)` direction over its domain, split against the unit vector `normal`: the part
/// perpendicular to `normal` and the component along it. For a ray at angle θ to `normal`, the
/// projection onto the plane perpendicular to the ray of a second derivative is at most
/// `tangential + sin θ · normal`.
///
/// With δ = δu (e1 − e0) + δv (e2 − e0), `D²S(δ, δ) = d(d−1) Σ B^{d−2}_{ijk} (δu² Q11 +
/// 2 δu δv Q12 + δv² Q22)` where Q are second differences of the control net [Farin, CAGD
/// §17.3]; for a unit δ each term is at most `max(|Q11|, |Q22|) + |Q12|` (δu² + δv² = 1,
/// 2|δu δv| ≤ 1), and the Bernstein weights sum to one, so `d(d−1)` times the largest of these
/// over the net bounds it — for each part of the split separately.
pub(crate) fn second_derivative_bounds(net: &TriangleBezier, normal: DVec3) -> [f64; 2] {
    let d = net.degree();
    if d < 2 {
        return [0.0; 2];
    }
    let mut largest = [0.0_f64; 2];
    for i in 0..=d - 2 {
        for j in 0..=d - 2 - i {
            // b(i+a, j+b, k+c) with (a, b, c) one of the six second-order offsets.
            let b00 = net.point(i + 2, j);
            let b01 = net.point(i + 1, j + 1);
            let b02 = net.point(i + 1, j);
            let b11 = net.point(i, j + 2);
            let b12 = net.point(i, j + 1);
            let b22 = net.point(i, j);
            let q = [
                b11 - 2.0 * b01 + b00,
                b12 - b01 - b02 + b00,
                b22 - 2.0 * b02 + b00,
            ];
            let along = q.map(|v| v.dot(normal));
            let across = [0, 1, 2].map(|m| (q[m] - normal * along[m]).length());
            largest[0] = largest[0].max(across[0].max(across[2]) + across[1]);
            largest[1] = largest[1].max(along[0].abs().max(along[2].abs()) + along[1].abs());
        }
    }
    largest.map(|m| (d * (d - 1)) as f64 * m)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bound on the second derivative of a Bézier triangle in any unit `(u, v)` direction over
    /// its domain: [`second_derivative_bounds`] with no normal direction singled out.
    fn second_derivative_bound(net: &TriangleBezier) -> f64 {
        second_derivative_bounds(net, DVec3::ZERO)[0]
    }
    use crate::surface::PatchGeometry;

    /// Runs the generic check `$f::<D>()` for every degree given a power form, 1..=6.
    macro_rules! every_power_degree {
        ($f:ident) => {
            $f::<1>();
            $f::<2>();
            $f::<3>();
            $f::<4>();
            $f::<5>();
            $f::<6>();
        };
    }

    /// A curved, non-symmetric control net of degree `degree`: a test patch with no special
    /// structure for the evaluators to exploit.
    fn wavy_net(degree: usize) -> TriangleBezier {
        TriangleBezier::from_fn(degree, |i, j, k| {
            let (i, j, k) = (i as f64, j as f64, k as f64);
            DVec3::new(
                j + 0.3 * i * k,
                k - 0.2 * j * j,
                (i * 1.7 + j * 0.3 - k).sin(),
            )
        })
    }

    #[test]
    fn matches_the_jet_for_every_stack_degree() {
        for d in 1..=MAX_STACK_DEGREE + 1 {
            let net = wavy_net(d);
            let patch = Patch {
                face: 0,
                piece: 0,
                domain: crate::surface::WHOLE_FACE,
                geometry: PatchGeometry::Bezier(net),
            };
            for (u, v) in [(0.0, 0.0), (0.2, 0.3), (0.7, 0.1), (0.0, 1.0), (0.33, 0.33)] {
                let jet = patch.jet(u, v);
                let (p, su, sv) = point_and_tangents(&patch, u, v);
                let err = (p - jet.p)
                    .length()
                    .max((su - jet.du).length())
                    .max((sv - jet.dv).length());
                assert!(err <= 1e-13, "degree {d} at ({u}, {v}): {err:e}");
            }
        }
    }

    /// The power form reproduces the de Casteljau jet (position and both tangents) for every
    /// degree the renderer specialises.
    #[test]
    fn power_form_matches_the_jet() {
        fn check<const D: usize>() {
            let net = wavy_net(D);
            let c = power_form_of(&net);
            assert_eq!(c.len(), point_count(D));
            let scale = net.control_bounds().diagonal();
            for (u, v) in [(0.0, 0.0), (0.2, 0.3), (0.7, 0.1), (0.0, 1.0), (1.0, 0.0)] {
                let jet = net.jet(u, v);
                let (p, su, sv) = local_point_and_tangents::<D>(&c, u, v);
                let err = (p - jet.p)
                    .length()
                    .max((su - jet.du).length() / D.max(1) as f64)
                    .max((sv - jet.dv).length() / D.max(1) as f64);
                assert!(err <= 1e-13 * scale, "degree {D} at ({u}, {v}): {err:e}");
            }
        }
        every_power_degree!(check);
    }

    /// [`power_coefficients`] of the net `net`, as a vector.
    fn power_form_of(net: &TriangleBezier) -> Vec<DVec3> {
        let mut c = vec![DVec3::ZERO; point_count(net.degree())];
        power_coefficients(net.degree(), |i, j| net.point(i, j), &mut c);
        c
    }

    /// An affine map onto a plane for the projected-net tests, and the offset they subtract.
    fn project(v: DVec3) -> DVec2 {
        DVec2::new(v.x + 0.5 * v.z, v.y - 0.25 * v.x)
    }
    const OFFSET: DVec2 = DVec2::new(0.3, -1.2);

    /// The projected net recovers the Bézier net from its power form: each entry is the
    /// affine map of the control point it stands for, to rounding.
    #[test]
    fn projected_net_inverts_the_power_form() {
        fn check<const D: usize>() {
            let net = wavy_net(D);
            let c = power_form_of(&net);
            let (q, magnitude) = projected_net::<D>(&c, project, OFFSET);
            assert!(magnitude > 0.0);
            for j in 0..=D {
                for k in 0..=D - j {
                    let expected = project(net.point(D - j - k, j)) - OFFSET;
                    let err = (q[power_index(D, j, k)] - expected).length();
                    assert!(
                        err <= 64.0 * f64::EPSILON * magnitude,
                        "degree {D} b({j},{k}): {err:e}"
                    );
                }
            }
        }
        every_power_degree!(check);
    }

    /// A leaf evaluated through its domain map on its patch's power form gives the point and
    /// tangents of its own sub-patch (the patch split down to it, in power form) to rounding,
    /// and its projected net ([`projected_leaf_net`]) is the sub-patch's within the bound it
    /// states, for every degree and for leaves down every child of the 4-split (the middle
    /// child turns the leaf's coordinates) to five splits deep.
    #[test]
    fn leaf_maps_give_the_sub_patch() {
        use crate::render::bvh::{CHILD_CORNERS, split4};
        use crate::surface::UV_CORNERS;
        fn check<const D: usize>() {
            let net = wavy_net(D);
            let c = power_form_of(&net);
            let abs_sum = |c: &[DVec3]| c.iter().map(|v| v.abs().element_sum()).sum::<f64>();
            let paths: [[usize; 5]; 5] = [
                [0, 0, 0, 0, 0],
                [3, 3, 3, 3, 3],
                [1, 3, 2, 3, 0],
                [2, 1, 3, 1, 3],
                [3, 0, 3, 2, 1],
            ];
            for path in paths {
                for depth in 0..=path.len() {
                    let (mut tri, mut piece) = (UV_CORNERS, net.clone());
                    for &child in &path[..depth] {
                        tri = split4(tri)[child];
                        piece = piece.subdivide(CHILD_CORNERS[child]);
                    }
                    let own = power_form_of(&piece);
                    let map = LeafMap::of(tri);
                    assert_eq!(map.whole, depth == 0);
                    let scale = abs_sum(&c) + abs_sum(&own);
                    for (s, t) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (0.2, 0.3), (0.7, 0.25)] {
                        let (p, ps, pt) = leaf_point_and_tangents::<D>(&c, &map, DVec2::new(s, t));
                        let (q, qs, qt) = local_point_and_tangents::<D>(&own, s, t);
                        let err = (p - q)
                            .abs()
                            .max_element()
                            .max((ps - qs).abs().max_element() / D as f64)
                            .max((pt - qt).abs().max_element() / D as f64);
                        assert!(
                            err <= 64.0 * f64::EPSILON * scale,
                            "degree {D}, path {:?} at ({s}, {t}): {err:e}",
                            &path[..depth]
                        );
                    }
                    let (a, ma, reexpansion) = projected_leaf_net::<D>(&c, &map, project, OFFSET);
                    let (b, mb) = projected_net::<D>(&own, project, OFFSET);
                    assert_eq!(reexpansion == 0.0, depth == 0);
                    for i in 0..point_count(D) {
                        let err = (a[i] - b[i]).abs().max_element();
                        assert!(
                            err <= 64.0 * f64::EPSILON * (ma + mb) + reexpansion,
                            "degree {D}, path {:?}, net entry {i}: {err:e}",
                            &path[..depth]
                        );
                    }
                }
            }
        }
        every_power_degree!(check);
    }

    #[test]
    fn power_index_walks_the_rows() {
        let d = 5;
        let mut next = 0;
        for j in 0..=d {
            for k in 0..=d - j {
                assert_eq!(power_index(d, j, k), next, "c({j},{k})");
                next += 1;
            }
        }
    }

    /// The second-derivative bound holds at sampled points in sampled directions.
    #[test]
    fn second_derivative_bound_holds() {
        let surface = crate::testing::surfaces::octahedron_sphere(5, 1.7, 0);
        for patch in &surface.patches {
            let net = patch.as_bezier().expect("Bézier patch");
            let bound = second_derivative_bound(net);
            for k in 0..50u64 {
                let u = crate::render::sampler::uniform(4, k, 0, 0);
                let v = crate::render::sampler::uniform(4, k, 0, 1) * (1.0 - u);
                let jet = patch.jet(u, v);
                let angle = std::f64::consts::TAU * crate::render::sampler::uniform(4, k, 0, 2);
                let (du, dv) = (angle.cos(), angle.sin());
                let d2 = jet.duu * du * du + 2.0 * jet.duv * du * dv + jet.dvv * dv * dv;
                assert!(
                    d2.length() <= bound * (1.0 + 1e-12),
                    "{} > {bound}",
                    d2.length()
                );
            }
        }
    }
}
