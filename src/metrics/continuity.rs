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

use glam::DVec3;

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

    fn mul(&self, other: &Series) -> Series {
        let mut out = Series::ZERO;
        for m1 in 0..=MAX_ORDER {
            for i1 in 0..=m1 {
                let a = self.0[term(i1, m1 - i1)];
                if a == 0.0 {
                    continue;
                }
                for m2 in 0..=MAX_ORDER - m1 {
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
        let mut s_pow = [Series::one(); MAX_ORDER + 1];
        let mut t_pow = [Series::one(); MAX_ORDER + 1];
        for k in 1..=MAX_ORDER {
            s_pow[k] = s_pow[k - 1].mul(s);
            t_pow[k] = t_pow[k - 1].mul(t);
        }
        let mut out = Series::ZERO;
        for m in 0..=MAX_ORDER {
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

/// The measured order of `joint` at fraction `s` along it; `diag` is the length scale L.
pub fn order_at(surface: &Surface, joint: &Joint, s: f64, diag: f64) -> i32 {
    let sb = if joint.reversed { 1.0 - s } else { s };
    let (uv_a, uv_b) = (
        edge_uv(joint.a.edge as usize, s),
        edge_uv(joint.b.edge as usize, sb),
    );
    let (pa, order_a) = patch_partials(surface, joint.a.patch, uv_a);
    let (pb, order_b) = patch_partials(surface, joint.b.patch, uv_b);
    if (pa[0] - pb[0]).length() > 1e-9 * diag {
        return -1;
    }
    let e = joint.a.edge as usize;
    let w = UV_CORNERS[(e + 1) % 3] - UV_CORNERS[e];
    let Some(e1) = (pa[1] * w.x + pa[2] * w.y).try_normalize() else {
        return 0;
    };
    let Some(n) = pa[1].cross(pa[2]).try_normalize() else {
        return 0;
    };
    let e2 = n.cross(e1);
    let frame = [e1, e2, n];
    let order = order_a.min(order_b);
    let (Some(ha), Some(hb)) = (
        height_function(&frame_series(&pa, frame, order)),
        height_function(&frame_series(&pb, frame, order)),
    ) else {
        return 0;
    };
    let mut agreed = 0;
    for m in 1..=order {
        let (mut diff, mut mag) = (0.0_f64, 0.0_f64);
        for i in 0..=m {
            let k = term(i, m - i);
            diff = diff.max((ha.0[k] - hb.0[k]).abs());
            mag = mag.max(ha.0[k].abs()).max(hb.0[k].abs());
        }
        let scale = mag.max(diag.powi(1 - m as i32));
        if diff > tolerance(m) * scale {
            break;
        }
        agreed = m;
    }
    agreed as i32
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
    use crate::bezier::gram::{factorial, multi_indices};
    use crate::linalg::invert;
    use crate::surface::{Patch, PatchEdge, PatchGeometry};
    use glam::DVec2;

    /// The degree-d patch interpolating `f(u, v)` at the domain points (exact when f is a
    /// polynomial map of degree ≤ d).
    fn interpolate(d: usize, f: &dyn Fn(DVec2) -> DVec3) -> TriangleBezier {
        let idx = multi_indices(d);
        let bary = |m: &[usize; 3]| m.map(|x| x as f64 / d as f64);
        let basis: Vec<Vec<f64>> = idx
            .iter()
            .map(|at| {
                let l = bary(at);
                idx.iter()
                    .map(|m| {
                        factorial(d) / (factorial(m[0]) * factorial(m[1]) * factorial(m[2]))
                            * l[0].powi(m[0] as i32)
                            * l[1].powi(m[1] as i32)
                            * l[2].powi(m[2] as i32)
                    })
                    .collect()
            })
            .collect();
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
            domain: [DVec3::X, DVec3::Y, DVec3::Z],
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

    /// The measure is geometric: side B read through a non-affine (cubic) map of its domain that
    /// fixes the shared edge is the same surface (all orders agree although the parametrisations
    /// are only C⁰ across the edge), and a G2 join stays G2.
    #[test]
    fn orders_are_geometric_not_parametric() {
        let phi = |uv: DVec2| {
            let bump = 0.6 * (1.0 - uv.x - uv.y) * uv.x * uv.y;
            DVec2::new(uv.x + bump, uv.y - bump)
        };
        let quad = |p: DVec2| 0.3 * p.x * p.x - 0.2 * p.x * p.y + 0.1 * p.y * p.y;
        let (surface, joint) = two_sided(&quad, &quad, &phi, 6);
        assert_eq!(joint_order(&surface, &joint, 2f64.sqrt()), MAX_ORDER as i32);
        let g2 = move |p: DVec2| quad(p) + 0.4 * (p.x + p.y - 1.0).powi(3);
        let (surface, joint) = two_sided(&quad, &g2, &phi, 9);
        assert_eq!(joint_order(&surface, &joint, 2f64.sqrt()), 2);
    }
}
