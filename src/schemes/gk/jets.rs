//! Test support of the `gk` construction: derivatives of any order of Bézier triangles, and the
//! parametric jump of two patches that lie side by side in one lattice chart. The metrics
//! module measures geometric continuity; the `gk` construction is C^k (k up to 4) in its
//! lattice parametrisation, which the tests check with this directly: across an edge `P → Q` shared by patches
//! `A` (third corner `a`) and `B` (third corner `b`) of one chart, `b = P + Q − a`
//! (parallelogram), so both patches can be differentiated along the same two lattice vectors
//! `Q − P` and `a − P` (on `B`: `Q − b`), and C^r means that every mixed derivative of order
//! ≤ r agrees along the edge.

use glam::DVec3;

use crate::bezier::TriangleBezier;

/// The derivative `D_w B` along the barycentric direction `w` (components summing to zero):
/// `d Σ_α (w0 b_{α+e0} + w1 b_{α+e1} + w2 b_{α+e2}) B^{d−1}_α` (Farin, CAGD §17.5). A
/// degree-0 patch has derivative zero (returned as degree 0).
pub fn directional_derivative(patch: &TriangleBezier, w: DVec3) -> TriangleBezier {
    let d = patch.degree();
    if d == 0 {
        return TriangleBezier::new(0, vec![DVec3::ZERO]);
    }
    let scale = d as f64;
    TriangleBezier::from_fn(d - 1, |i, j, _| {
        scale
            * (w.x * patch.point(i + 1, j) + w.y * patch.point(i, j + 1) + w.z * patch.point(i, j))
    })
}

/// All derivatives of order `order`: `D_e^{order−t} D_n^t B` for `t = 0..=order`.
pub fn derivatives_of_order(
    patch: &TriangleBezier,
    e: DVec3,
    n: DVec3,
    order: usize,
) -> Vec<TriangleBezier> {
    (0..=order)
        .map(|t| {
            let mut q = patch.clone();
            for _ in 0..order - t {
                q = directional_derivative(&q, e);
            }
            for _ in 0..t {
                q = directional_derivative(&q, n);
            }
            q
        })
        .collect()
}

/// Largest coefficient length of a net (the scale a derivative is compared against).
fn net_scale(patch: &TriangleBezier) -> f64 {
    patch
        .control_points()
        .fold(0.0, |m: f64, p| m.max(p.length()))
}

/// Largest disagreement of the order-`order` derivatives of two patches of one lattice chart
/// along their shared edge, at 9 points, relative to the bound `d!/(d−r)! · 2^r · max|b|` that
/// the control nets put on any derivative of order `r`. Rounding in the control points shows
/// up at about machine precision in this measure, whatever the size of the derivatives.
///
/// `a_edge` runs from corner `a_edge` to `a_edge+1` of `a` (P → Q); `b_edge` is the same edge
/// on `b`, running the other way (Q → P), as between consistently oriented patches.
pub fn lattice_jump(
    a: &TriangleBezier,
    a_edge: usize,
    b: &TriangleBezier,
    b_edge: usize,
    order: usize,
) -> f64 {
    let unit = |c: usize| {
        let mut w = [0.0; 3];
        w[c % 3] = 1.0;
        DVec3::from_array(w)
    };
    // On A: P = corner a_edge, Q = a_edge+1, third corner a_edge+2.
    let (ap, aq, aa) = (unit(a_edge), unit(a_edge + 1), unit(a_edge + 2));
    // On B: Q = corner b_edge, P = b_edge+1, third corner b_edge+2.
    let (bq, bp, bb) = (unit(b_edge), unit(b_edge + 1), unit(b_edge + 2));
    let da = derivatives_of_order(a, aq - ap, aa - ap, order);
    let db = derivatives_of_order(b, bq - bp, bq - bb, order);
    let degree = a.degree().max(b.degree());
    let falling: f64 = (0..order)
        .map(|t| degree.saturating_sub(t) as f64 * 2.0)
        .product();
    let scale = (falling * net_scale(a).max(net_scale(b))).max(f64::MIN_POSITIVE);
    let mut worst: f64 = 0.0;
    for (x, y) in da.iter().zip(&db) {
        for step in 1..=9 {
            let s = step as f64 / 10.0;
            let pa = x.eval(ap * (1.0 - s) + aq * s);
            let pb = y.eval(bp * (1.0 - s) + bq * s);
            worst = worst.max((pa - pb).length() / scale);
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cubic polynomial map written over two triangles of one chart is C^∞ across their
    /// edge: all derivatives up to order 4 agree (order 3 is the first non-zero constant).
    #[test]
    fn one_polynomial_over_two_triangles_is_smooth() {
        let poly = |x: f64, y: f64| {
            DVec3::new(
                x * x * y - 2.0 * y * y * y,
                x + 0.5 * x * y * y,
                1.0 + x * x * x,
            )
        };
        // A = (0,0),(1,0),(1,1) and B = (0,0),(1,1),(0,1) share the diagonal: A's edge 2 runs
        // (1,1) → (0,0), B's edge 0 runs back.
        let fit = |c: [[f64; 2]; 3]| {
            let lin = TriangleBezier::from_fn(1, |i, j, _| {
                let p = if i == 1 {
                    c[0]
                } else if j == 1 {
                    c[1]
                } else {
                    c[2]
                };
                DVec3::new(p[0], p[1], 0.0)
            });
            // Degree-3 interpolation at the domain points is exact for a cubic.
            let domain = crate::bezier::gram::multi_indices(3);
            let values: Vec<DVec3> = domain
                .iter()
                .map(|a| {
                    let w = DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64) / 3.0;
                    let p = lin.eval(w);
                    poly(p.x, p.y)
                })
                .collect();
            solve_interpolation(3, &values)
        };
        let a = fit([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]);
        let b = fit([[0.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
        for order in 0..=4 {
            let jump = lattice_jump(&a, 2, &b, 0, order);
            assert!(jump < 1e-12, "order {order}: {jump}");
        }
    }

    /// Solves the interpolation problem at the domain points of degree `d` (test support).
    fn solve_interpolation(d: usize, values: &[DVec3]) -> TriangleBezier {
        let domain = crate::bezier::gram::multi_indices(d);
        let matrix: Vec<Vec<f64>> = domain
            .iter()
            .map(|a| {
                let w = DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64) / d as f64;
                (0..domain.len())
                    .map(|n| {
                        let mut unit = vec![DVec3::ZERO; domain.len()];
                        unit[n] = DVec3::X;
                        TriangleBezier::new(d, unit).eval(w).x
                    })
                    .collect()
            })
            .collect();
        let inv = crate::linalg::invert(&matrix).expect("interpolation is unisolvent");
        let points = inv
            .iter()
            .map(|row| row.iter().zip(values).map(|(w, v)| *w * *v).sum())
            .collect();
        TriangleBezier::new(d, points)
    }
}
