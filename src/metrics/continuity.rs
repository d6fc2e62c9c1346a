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
//! larger). Order 0 is the gap `|S_A − S_B| ≤ 1e-9 L`; a joint with a larger gap has order −1.
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
//! estimates this floor ([`rounding_floor`]: the spread of the coefficients under one-ulp
//! perturbations of both nets, times 10) and accepts the order if the sides differ by less
//! than the floor while the floor is below [`RESOLVABLE`] (10%) of the coefficients — a jump of
//! that size is still seen. An order with a larger floor cannot be resolved in f64: the measure
//! stops below it ([`Measured::unresolved`]) rather than claim it.

use glam::DVec3;

use crate::bezier::TriangleBezier;
use crate::surface::{Joint, Surface, UV_CORNERS, edge_uv};

/// Highest order compared (a joint that agrees to this order is reported as this order).
pub const MAX_ORDER: usize = 5;
const TERMS: usize = (MAX_ORDER + 1) * (MAX_ORDER + 2) / 2;

/// Fractions along a joint where the order is measured (the joint's order is the minimum).
pub const ORDER_SAMPLES: [f64; 4] = [0.125, 0.375, 0.625, 0.875];

/// The relative tolerance for order m.
pub fn tolerance(m: usize) -> f64 {
    1e-8 * 10f64.powi(m as i32)
}

/// A bivariate power series truncated at total order [`MAX_ORDER`]; coefficient of `x^i y^j`
/// at [`term`]`(i, j)` (by total order, then i descending — the order of `Patch::partials`).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Series([f64; TERMS]);

/// Index of the coefficient of `x^i y^j`.
fn term(i: usize, j: usize) -> usize {
    let m = i + j;
    m * (m + 1) / 2 + (m - i)
}

impl Series {
    const ZERO: Series = Series([0.0; TERMS]);

    fn one() -> Series {
        let mut s = Series::ZERO;
        s.0[0] = 1.0;
        s
    }

    fn linear(a: f64, b: f64) -> Series {
        let mut s = Series::ZERO;
        s.0[term(1, 0)] = a;
        s.0[term(0, 1)] = b;
        s
    }

    fn add_scaled(&self, other: &Series, k: f64) -> Series {
        Series(std::array::from_fn(|i| self.0[i] + k * other.0[i]))
    }

    /// The highest total order with a non-zero coefficient (0 for a constant or zero series).
    fn top_order(&self) -> usize {
        (0..=MAX_ORDER)
            .rev()
            .find(|&m| (0..=m).any(|i| self.0[term(i, m - i)] != 0.0))
            .unwrap_or(0)
    }

    /// The product, truncated at `MAX_ORDER`. Terms beyond either factor's [`Series::top_order`]
    /// are zero and skipped (flat and low-degree patches cost almost nothing).
    fn mul(&self, other: &Series) -> Series {
        let mut out = Series::ZERO;
        let other_top = other.top_order();
        for m1 in 0..=self.top_order() {
            for i1 in 0..=m1 {
                let a = self.0[term(i1, m1 - i1)];
                if a == 0.0 {
                    continue;
                }
                for m2 in 0..=(MAX_ORDER - m1).min(other_top) {
                    for i2 in 0..=m2 {
                        out.0[term(i1 + i2, m1 - i1 + m2 - i2)] += a * other.0[term(i2, m2 - i2)];
                    }
                }
            }
        }
        out
    }

    /// `self(s(x,y), t(x,y))` for series `s`, `t` without constant term.
    fn compose(&self, s: &Series, t: &Series) -> Series {
        // Powers beyond the order of `self` are never used.
        let top = self.top_order();
        let mut s_pow = [Series::one(); MAX_ORDER + 1];
        let mut t_pow = [Series::one(); MAX_ORDER + 1];
        for k in 1..=top {
            s_pow[k] = s_pow[k - 1].mul(s);
            t_pow[k] = t_pow[k - 1].mul(t);
        }
        let mut out = Series::ZERO;
        for m in 0..=top {
            for i in 0..=m {
                let c = self.0[term(i, m - i)];
                if c != 0.0 {
                    out = out.add_scaled(&s_pow[i].mul(&t_pow[m - i]), c);
                }
            }
        }
        out
    }

    /// The series without its constant and linear terms.
    fn nonlinear(&self) -> Series {
        let mut s = *self;
        s.0[..3].fill(0.0);
        s
    }
}

/// Taylor series of a patch side at `(u0, v0)` projected on the frame: (x, y, h) in (s, t),
/// constant terms removed (the gap is checked separately).
fn frame_series(partials: &[DVec3], frame: [DVec3; 3], order: usize) -> [Series; 3] {
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

/// The height function `h(x, y)` of a side given its frame series, by series reversion.
fn height_function(xyh: &[Series; 3]) -> Option<Series> {
    let (x, y, h) = (&xyh[0], &xyh[1], &xyh[2]);
    let (a, b, c, d) = (
        x.0[term(1, 0)],
        x.0[term(0, 1)],
        y.0[term(1, 0)],
        y.0[term(0, 1)],
    );
    let det = a * d - b * c;
    if det.abs() <= 1e-300 || !det.is_finite() {
        return None;
    }
    // (s, t) = A⁻¹ [(x, y) − nonlinear(X, Y)(s, t)], one more correct order per round.
    let inv = [d / det, -b / det, -c / det, a / det];
    let (xn, yn) = (x.nonlinear(), y.nonlinear());
    let mut s = Series::linear(inv[0], inv[1]);
    let mut t = Series::linear(inv[2], inv[3]);
    for _ in 1..MAX_ORDER {
        let (rx, ry) = (xn.compose(&s, &t), yn.compose(&s, &t));
        s = Series::linear(inv[0], inv[1])
            .add_scaled(&rx, -inv[0])
            .add_scaled(&ry, -inv[1]);
        t = Series::linear(inv[2], inv[3])
            .add_scaled(&rx, -inv[2])
            .add_scaled(&ry, -inv[3]);
    }
    Some(h.compose(&s, &t))
}

/// Partial derivatives of a patch at `uv` up to `MAX_ORDER` (exact), or up to order 2 from the
/// jet for patch kinds without higher derivatives; the second value is the usable order.
fn patch_partials(surface: &Surface, patch: u32, uv: glam::DVec2) -> (Vec<DVec3>, usize) {
    let p = &surface.patches[patch as usize];
    match p.partials(uv.x, uv.y, MAX_ORDER) {
        Some(all) => (all, MAX_ORDER),
        None => {
            let j = p.jet(uv.x, uv.y);
            let mut all = vec![DVec3::ZERO; TERMS];
            all[..6].copy_from_slice(&[j.p, j.du, j.dv, j.duu, j.duv, j.dvv]);
            (all, 2)
        }
    }
}

/// A jump this large relative to the order-m coefficients is always detected: an order whose
/// rounding floor exceeds it cannot be resolved in f64 and is not claimed.
pub const RESOLVABLE: f64 = 0.1;

/// Perturbed evaluations behind [`rounding_floor`].
const FLOOR_TRIALS: u64 = 4;

/// Factor between the spread of [`FLOOR_TRIALS`] one-ulp perturbations and the floor: the
/// stored points carry a few ulps from their construction, and a sample maximum falls short
/// of the true one.
const FLOOR_SAFETY: f64 = 10.0;

/// Height functions of both sides of `joint` at fraction `s` in side A's tangent frame, from
/// the partials of the two patches (`None` where a side is singular).
fn heights(partials: [&[DVec3]; 2], edge_a: usize, order: usize) -> Option<(Series, Series)> {
    let pa = partials[0];
    let w = UV_CORNERS[(edge_a + 1) % 3] - UV_CORNERS[edge_a];
    let e1 = (pa[1] * w.x + pa[2] * w.y).try_normalize()?;
    let n = pa[1].cross(pa[2]).try_normalize()?;
    let frame = [e1, n.cross(e1), n];
    Some((
        height_function(&frame_series(pa, frame, order))?,
        height_function(&frame_series(partials[1], frame, order))?,
    ))
}

/// The rounding floor of the height coefficients of `joint` at fraction `s`, per order: how
/// far they move when every stored control point of the two patches moves by one ulp of the
/// largest coordinate (deterministic pseudo-random directions), times `FLOOR_SAFETY`. High
/// derivatives of small, high-degree patches far from the origin are this uncertain in f64
/// whatever the measure does (`d!/(d−m)!` times the m-th differences of points known to
/// `ε |b|`, divided by the speed to the m-th power). Zero for patch kinds without a control
/// net.
pub fn rounding_floor(surface: &Surface, joint: &Joint, s: f64) -> [f64; MAX_ORDER + 1] {
    let mut floor = [0.0; MAX_ORDER + 1];
    let sides = [joint.a, joint.b];
    let uvs = [
        edge_uv(joint.a.edge as usize, s),
        edge_uv(
            joint.b.edge as usize,
            if joint.reversed { 1.0 - s } else { s },
        ),
    ];
    let nets: Option<Vec<_>> = sides
        .iter()
        .map(|side| surface.patches[side.patch as usize].as_bezier())
        .collect();
    let Some(nets) = nets else {
        return floor;
    };
    let exact: Vec<Vec<DVec3>> = nets
        .iter()
        .zip(uvs)
        .map(|(net, uv)| net.partials(uv.x, uv.y, MAX_ORDER))
        .collect();
    let Some((ha, hb)) = heights([&exact[0], &exact[1]], joint.a.edge as usize, MAX_ORDER) else {
        return floor;
    };
    let mut state = 0x9e37_79b9_7f4a_7c15_u64 ^ (joint.a.patch as u64) << 32 ^ joint.b.patch as u64;
    let mut unit = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    for _ in 0..FLOOR_TRIALS {
        let perturbed: Vec<Vec<DVec3>> = nets
            .iter()
            .zip(uvs)
            .map(|(net, uv)| {
                let ulp = f64::EPSILON
                    * net
                        .points()
                        .iter()
                        .map(|p| p.abs().max_element())
                        .fold(0.0, f64::max);
                let moved: Vec<DVec3> = net
                    .points()
                    .iter()
                    .map(|p| *p + ulp * DVec3::new(unit(), unit(), unit()))
                    .collect();
                TriangleBezier::new(net.degree(), moved).partials(uv.x, uv.y, MAX_ORDER)
            })
            .collect();
        let Some((pa, pb)) = heights(
            [&perturbed[0], &perturbed[1]],
            joint.a.edge as usize,
            MAX_ORDER,
        ) else {
            continue;
        };
        for (m, f) in floor.iter_mut().enumerate().skip(1) {
            for i in 0..=m {
                let k = term(i, m - i);
                *f = f
                    .max(FLOOR_SAFETY * (pa.0[k] - ha.0[k]).abs())
                    .max(FLOOR_SAFETY * (pb.0[k] - hb.0[k]).abs());
            }
        }
    }
    floor
}

/// The measured order of `joint` at fraction `s` along it; `diag` is the length scale L.
///
/// Order m agrees when the coefficients differ by at most `tolerance(m)` of their scale, or
/// — for high derivatives of small high-degree patches — by at most their [`rounding_floor`]
/// while that floor is below [`RESOLVABLE`] of the scale (a genuine jump of that size would
/// still be seen). An order whose floor is larger is not resolved and not claimed.
pub fn order_at(surface: &Surface, joint: &Joint, s: f64, diag: f64) -> i32 {
    measure_at(surface, joint, s, diag).order
}

/// A measured order and why the measure stopped there.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Measured {
    /// The order the two sides agree to.
    pub order: i32,
    /// `true` if the next order could not be resolved (its rounding floor exceeds
    /// [`RESOLVABLE`] of the coefficients) rather than found to differ; always `false` at
    /// [`MAX_ORDER`] and for a gap or a singular side.
    pub unresolved: bool,
}

/// [`order_at`] with the reason it stopped.
pub fn measure_at(surface: &Surface, joint: &Joint, s: f64, diag: f64) -> Measured {
    measure_with_floor(surface, joint, s, diag, true)
}

/// [`measure_at`], with the rounding floor consulted or not.
fn measure_with_floor(
    surface: &Surface,
    joint: &Joint,
    s: f64,
    diag: f64,
    use_floor: bool,
) -> Measured {
    let plain = |order| Measured {
        order,
        unresolved: false,
    };
    let sb = if joint.reversed { 1.0 - s } else { s };
    let (uv_a, uv_b) = (
        edge_uv(joint.a.edge as usize, s),
        edge_uv(joint.b.edge as usize, sb),
    );
    let (pa, order_a) = patch_partials(surface, joint.a.patch, uv_a);
    let (pb, order_b) = patch_partials(surface, joint.b.patch, uv_b);
    if (pa[0] - pb[0]).length() > 1e-9 * diag {
        return plain(-1);
    }
    let order = order_a.min(order_b);
    let Some((ha, hb)) = heights([&pa, &pb], joint.a.edge as usize, order) else {
        return plain(0);
    };
    let mut floor = None;
    let mut agreed = 0;
    let mut unresolved = false;
    for m in 1..=order {
        let (mut diff, mut mag) = (0.0_f64, 0.0_f64);
        for i in 0..=m {
            let k = term(i, m - i);
            diff = diff.max((ha.0[k] - hb.0[k]).abs());
            mag = mag.max(ha.0[k].abs()).max(hb.0[k].abs());
        }
        let scale = mag.max(diag.powi(1 - m as i32));
        if diff > tolerance(m) * scale {
            if !use_floor {
                break;
            }
            let floor = floor.get_or_insert_with(|| rounding_floor(surface, joint, s))[m];
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
    ORDER_SAMPLES
        .iter()
        .map(|&s| order_at(surface, joint, s, diag))
        .min()
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bezier::TriangleBezier;
    use crate::bezier::gram::{domain_point_collocation, multi_indices};
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
        let (pa, _) = patch_partials(surface, joint.a.patch, edge_uv(joint.a.edge as usize, s));
        let (pb, _) = patch_partials(
            surface,
            joint.b.patch,
            edge_uv(joint.b.edge as usize, 1.0 - s),
        );
        let (ha, hb) = heights([&pa, &pb], joint.a.edge as usize, MAX_ORDER).expect("regular");
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
                .map(|&s| measure_with_floor(&same, &joint, s, diag, false).order)
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
