//! Step 5, between faces [Piper87 §3.8 step 5, eqs. 19–20]: the control points of two quartic
//! pieces that share a mesh edge, moved as little as possible so that the two pieces have the
//! same tangent plane all along the edge.
//!
//! Notation of [Piper87 Fig. 21], seen from face P: `S0 … S4` the common edge,
//! `R0 … R3` the next row of P's piece, `T0 … T3` the next row of Q's piece, all running
//! from `S0` to `S4`. With `I, J, K, L` the cubic blends of `S0..3`, `S1..4`, `R` and `T` at a
//! point of the edge, the tangent plane is continuous there iff `I, J, K, L` are coplanar
//! [Piper87 eq. 17]. Piper asks for linear weights `E, F, G, H` (in the edge parameter, `e1 …
//! h1` at `S0`, `e2 … h2` at `S4`) with `E + F + G + H = 0` and `EI + FJ + GK + HL = 0`
//! [Piper87 eq. 19]; expanded in Bernstein form this is `C0 = … = C4 = 0` [Piper87 eq. 20]:
//!
//! * `C0 = 0` and `C4 = 0` involve only points in the tangent planes at the two vertices and
//!   fix the weights, normalised by `g + h = 1` ([`end_weights`]);
//! * `C1 = C2 = C3 = 0` are three linear equations `A x = b` for `x = (R1, T1, R2, T2, S2)`
//!   with the 3×5 matrix `A` of the thesis, solved for the smallest change `x − y` of the
//!   current points `y` ([`solve_edge`]).
//!
//! The thesis's `C2` is garbled in the text (`2_e S1`); expanding `E·I + …` gives
//! `C2 = ½[(e2 S1 + f2 S2 + g2 R1 + h2 T1) + (e1 S2 + f1 S3 + g1 R2 + h1 T2)]`, which is what
//! its matrix `A` uses (tested in the unit tests against the C_i written out).
//!
//! The rows of `A` are dependent exactly when the weights at the two ends agree
//! (`e1 = e2, f1 = f2, g1 = g2, h1 = h2`); then the middle row is the sum of the others and
//! the thesis drops it. Numerically, "agree" must be decided with a tolerance, and near that
//! case the middle row `r2` and its right side are both differences of nearly equal terms.
//! So `r2` is replaced by the equivalent `r2 − r1 − r3`, whose coefficients and right side
//! are written directly in the differences `Δe = e2 − e1`, `Δg = g2 − g1` (using `C0 = C4 = 0`),
//! and then divided by `‖(Δe, Δg)‖`: a well-scaled row however small the differences are, and
//! the row is dropped (the thesis's two-row system) only when the differences are below
//! [`DEPENDENT_ROWS`] — rounding noise, where the row's residual is of that order too.

use glam::{DMat3, DVec3};

/// Below this `‖(Δe, Δg)‖` (the weights are dimensionless, of order one) the weights at the two
/// ends count as equal and the thesis's two-row system is solved.
pub(crate) const DEPENDENT_ROWS: f64 = 1e-12;

/// The control points of the two pieces at one shared edge, in face P's direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct EdgeNet {
    /// `S0 … S4`: the common boundary curve.
    pub s: [DVec3; 5],
    /// `R0 … R3`: P's next row.
    pub r: [DVec3; 4],
    /// `T0 … T3`: Q's next row.
    pub t: [DVec3; 4],
}

/// Weights `(e, f, g, h)` of [Piper87 eq. 19] at one end of the edge.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct EndWeights {
    /// Weight of `I` (the blend of `S0..3`).
    pub e: f64,
    /// Weight of `J` (the blend of `S1..4`).
    pub f: f64,
    /// Weight of `K` (P's row).
    pub g: f64,
    /// Weight of `L` (Q's row).
    pub h: f64,
}

/// Solves `along·x + (r − t)·g = −(t − vertex)` for `(x, g)` in the plane of the four points
/// (least squares in 3-D: the system is consistent when the points are coplanar). `None` when
/// `r − t` is parallel to the edge direction (P's and Q's points on one line with the edge).
fn plane_weights(vertex: DVec3, along: DVec3, r: DVec3, t: DVec3) -> Option<(f64, f64)> {
    let a = along - vertex;
    let w = r - t;
    let rhs = vertex - t;
    let det = a.cross(w).length_squared();
    if det <= 1e-24 * a.length_squared() * w.length_squared() {
        return None;
    }
    let (aa, aw, ww) = (a.dot(a), a.dot(w), w.dot(w));
    let (ar, wr) = (a.dot(rhs), w.dot(rhs));
    Some(((ww * ar - aw * wr) / det, (aa * wr - aw * ar) / det))
}

/// `C0 = 0` and `C4 = 0` [Piper87 step 5]: the weights at `S0` and at `S4`, with
/// `e + f + g + h = 0` and `g + h = 1`. The four points of each are coplanar (tangent plane at
/// the vertex), so the thesis drops one coordinate and solves 4×4; here the two remaining
/// unknowns are solved in the plane by least squares, which needs no choice of coordinate.
/// `None` at an end where `R` and `T` are in line with the edge.
pub(crate) fn end_weights(net: &EdgeNet) -> (Option<EndWeights>, Option<EndWeights>) {
    let (s, r, t) = (&net.s, &net.r, &net.t);
    // C0 = e1 S0 + f1 S1 + g1 R0 + h1 T0 with e1 = −1 − f1.
    let at_s0 = plane_weights(s[0], s[1], r[0], t[0]).map(|(f, g)| EndWeights {
        e: -1.0 - f,
        f,
        g,
        h: 1.0 - g,
    });
    // C4 = e2 S3 + f2 S4 + g2 R3 + h2 T3 with f2 = −1 − e2.
    let at_s4 = plane_weights(s[4], s[3], r[3], t[3]).map(|(e, g)| EndWeights {
        e,
        f: -1.0 - e,
        g,
        h: 1.0 - g,
    });
    (at_s0, at_s4)
}

/// The new `R1, T1, R2, T2, S2`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct EdgeSolution {
    /// `R1, R2`: P's row.
    pub r: [DVec3; 2],
    /// `T1, T2`: Q's row.
    pub t: [DVec3; 2],
    /// The middle point of the common edge.
    pub s2: DVec3,
    /// True if the weights at both ends agreed and the two-row system was solved.
    pub dependent_rows: bool,
}

/// `C1 = C2 = C3 = 0` [Piper87 step 5]: the smallest change (least squares over the 15
/// coordinates) of `R1, T1, R2, T2, S2` that satisfies `A x = b`, i.e. the thesis's
/// `A e = b − A y` solved by `e = Aᵀ (A Aᵀ)⁻¹ (b − A y)`. See the module doc for the middle row.
///
/// The equations are affine (each row's weights sum to the same on both sides), so they are
/// solved relative to the edge's midpoint, which keeps the numbers small.
pub(crate) fn solve_edge(net: &EdgeNet, w1: EndWeights, w2: EndWeights) -> EdgeSolution {
    let origin = 0.5 * (net.s[0] + net.s[4]);
    let s = net.s.map(|p| p - origin);
    let r = net.r.map(|p| p - origin);
    let t = net.t.map(|p| p - origin);
    let y = [r[1], t[1], r[2], t[2], s[2]];
    // 4 C1 = 0, divided by 3.
    let row1 = [w1.g, w1.h, 0.0, 0.0, w1.f];
    let rhs1 = -(w2.e * s[0] + w2.f * s[1] + w2.g * r[0] + w2.h * t[0] + 3.0 * w1.e * s[1]) / 3.0;
    // 4 C3 = 0, divided by 3.
    let row3 = [0.0, 0.0, w2.g, w2.h, w2.e];
    let rhs3 = -(w1.e * s[3] + w1.f * s[4] + w1.g * r[3] + w1.h * t[3] + 3.0 * w2.f * s[3]) / 3.0;
    // 2 C2 = 0 times 3, minus the two rows above (times 3): with Δf = −Δe and Δh = −Δg,
    // 3[Δg (R1 − T1 − R2 + T2) − 2Δe S2] = Δe (S0 − 4S1 − 4S3 + S4) + Δg (R0 − R3 − T0 + T3).
    let (de, dg) = (w2.e - w1.e, w2.g - w1.g);
    let spread = de.hypot(dg);
    let dependent_rows = spread <= DEPENDENT_ROWS;
    let correction = if dependent_rows {
        min_norm_correction(&[(row1, rhs1), (row3, rhs3)], &y)
    } else {
        let (de, dg) = (de / spread, dg / spread);
        let row2 = [dg, -dg, -dg, dg, -2.0 * de];
        let rhs2 =
            (de * (s[0] - 4.0 * s[1] - 4.0 * s[3] + s[4]) + dg * (r[0] - r[3] - t[0] + t[3])) / 3.0;
        min_norm_correction(&[(row1, rhs1), (row2, rhs2), (row3, rhs3)], &y)
    };
    let x: [DVec3; 5] = std::array::from_fn(|i| y[i] + correction[i] + origin);
    EdgeSolution {
        r: [x[0], x[2]],
        t: [x[1], x[3]],
        s2: x[4],
        dependent_rows,
    }
}

/// `e = Aᵀ (A Aᵀ)⁻¹ (b − A y)`, each coordinate separately (A is shared), for two or three rows.
fn min_norm_correction(rows: &[([f64; 5], DVec3)], y: &[DVec3; 5]) -> [DVec3; 5] {
    let n = rows.len();
    let dot = |a: &[f64; 5], b: &[f64; 5]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let mut residual = [DVec3::ZERO; 3];
    for (res, (a, b)) in residual.iter_mut().zip(rows) {
        *res = *b - a.iter().zip(y).map(|(w, p)| *w * *p).sum::<DVec3>();
    }
    // Gram matrix A Aᵀ, padded to 3×3 with an identity block in the two-row case.
    let mut gram = DMat3::IDENTITY;
    for (i, (a, _)) in rows.iter().enumerate() {
        for (j, (b, _)) in rows.iter().enumerate() {
            gram.col_mut(j)[i] = dot(a, b);
        }
    }
    let inverse = gram.inverse();
    let mut multipliers = [DVec3::ZERO; 3];
    for (i, m) in multipliers.iter_mut().enumerate().take(n) {
        *m = (0..n).map(|j| inverse.col(j)[i] * residual[j]).sum();
    }
    std::array::from_fn(|c| {
        rows.iter()
            .zip(&multipliers)
            .map(|((a, _), m)| a[c] * *m)
            .sum()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `C0 … C4` of [Piper87 eq. 20] written out, for checking a solved edge.
    fn bernstein_conditions(net: &EdgeNet, w1: EndWeights, w2: EndWeights) -> [DVec3; 5] {
        let (s, r, t) = (&net.s, &net.r, &net.t);
        let first = |i: usize| w1.e * s[i] + w1.f * s[i + 1] + w1.g * r[i] + w1.h * t[i];
        let second = |i: usize| w2.e * s[i] + w2.f * s[i + 1] + w2.g * r[i] + w2.h * t[i];
        [
            first(0),
            (3.0 * first(1) + second(0)) / 4.0,
            (first(2) + second(1)) / 2.0,
            (first(3) + 3.0 * second(2)) / 4.0,
            second(3),
        ]
    }

    /// A random-looking edge net with the vertex-plane structure step 5 relies on: S1, R0, T0
    /// in a plane through S0, S3, R3, T3 in a plane through S4, P's row on one side.
    fn edge_net(seed: f64) -> EdgeNet {
        let wobble = |i: f64| 0.1 * (seed * 7.3 + i * 2.1).sin();
        let n0 = DVec3::new(wobble(1.0), -0.2 + wobble(2.0), 1.0).normalize();
        let n4 = DVec3::new(wobble(3.0), 0.1 + wobble(4.0), 1.0).normalize();
        let in_plane = |v: DVec3, n: DVec3| v - v.dot(n) * n;
        let (s0, s4) = (DVec3::ZERO, DVec3::new(1.0, 0.0, 0.05 * seed.cos()));
        let s1 = s0 + in_plane(DVec3::new(0.25, 0.02, 0.1), n0);
        let r0 = s0 + in_plane(DVec3::new(0.2, 0.3 + wobble(5.0), 0.0), n0);
        let t0 = s0 + in_plane(DVec3::new(0.22, -0.25, 0.0), n0);
        let s3 = s4 + in_plane(DVec3::new(-0.25, -0.01, 0.0), n4);
        let r3 = s4 + in_plane(DVec3::new(-0.2, 0.28, 0.0), n4);
        let t3 = s4 + in_plane(DVec3::new(-0.21, -0.3 + wobble(6.0), 0.0), n4);
        EdgeNet {
            s: [s0, s1, DVec3::new(0.5, 0.01, 0.1), s3, s4],
            r: [
                r0,
                DVec3::new(0.4, 0.3, 0.2),
                DVec3::new(0.6, 0.3, 0.15),
                r3,
            ],
            t: [
                t0,
                DVec3::new(0.4, -0.3, 0.1),
                DVec3::new(0.6, -0.3, 0.05),
                t3,
            ],
        }
    }

    fn solved(net: &EdgeNet, x: &EdgeSolution) -> EdgeNet {
        let mut out = *net;
        out.r[1] = x.r[0];
        out.r[2] = x.r[1];
        out.t[1] = x.t[0];
        out.t[2] = x.t[1];
        out.s[2] = x.s2;
        out
    }

    /// After the solve every C_i of eq. 20, written out independently of the matrix, vanishes.
    #[test]
    fn solution_satisfies_all_five_bernstein_conditions() {
        for seed in 0..20 {
            let net = edge_net(seed as f64);
            let (w1, w2) = end_weights(&net);
            let (w1, w2) = (w1.expect("regular end"), w2.expect("regular end"));
            for w in [w1, w2] {
                assert!((w.e + w.f + w.g + w.h).abs() <= 1e-15);
                assert!(
                    w.g > 0.0 && w.h > 0.0,
                    "R and T lie on opposite sides: {w:?}"
                );
            }
            let x = solve_edge(&net, w1, w2);
            assert!(!x.dependent_rows);
            let c = bernstein_conditions(&solved(&net, &x), w1, w2);
            let worst = c.iter().map(|v| v.length()).fold(0.0, f64::max);
            assert!(worst <= 1e-14, "seed {seed}: C = {c:?}");
        }
    }

    /// Mirror-symmetric data whose two ends are affinely alike (R0 and T0 project onto the
    /// middle of S0 S1, so `e = f = −½` at both ends): the weights at both ends agree, the
    /// rows of A are dependent, and the two-row system of the thesis still satisfies all of
    /// C0 … C4.
    #[test]
    fn dependent_rows_are_solved_with_two_rows() {
        let mirror = |p: DVec3| DVec3::new(1.0 - p.x, p.y, p.z);
        let s0 = DVec3::ZERO;
        let s1 = DVec3::new(0.25, 0.0, 0.0);
        let r0 = DVec3::new(0.125, 0.3, 0.0);
        let t0 = DVec3::new(0.125, -0.5, 0.0);
        let net = EdgeNet {
            s: [s0, s1, DVec3::new(0.5, 0.02, 0.1), mirror(s1), mirror(s0)],
            r: [
                r0,
                DVec3::new(0.4, 0.3, 0.1),
                DVec3::new(0.6, 0.35, 0.1),
                mirror(r0),
            ],
            t: [
                t0,
                DVec3::new(0.4, -0.3, 0.1),
                DVec3::new(0.6, -0.2, 0.1),
                mirror(t0),
            ],
        };
        let (w1, w2) = end_weights(&net);
        let (w1, w2) = (w1.unwrap(), w2.unwrap());
        assert!(
            (w1.e - w2.e).abs() <= 1e-15 && (w1.g - w2.g).abs() <= 1e-15,
            "{w1:?} {w2:?}"
        );
        assert!((w1.e + 0.5).abs() <= 1e-15 && (w1.g - 0.625).abs() <= 1e-15);
        let x = solve_edge(&net, w1, w2);
        assert!(x.dependent_rows);
        let c = bernstein_conditions(&solved(&net, &x), w1, w2);
        let worst = c.iter().map(|v| v.length()).fold(0.0, f64::max);
        assert!(worst <= 1e-15, "C = {c:?}");
    }

    /// Points that already satisfy the conditions are left where they are (least change).
    #[test]
    fn a_g1_net_is_a_fixed_point() {
        let net = edge_net(3.0);
        let (w1, w2) = end_weights(&net);
        let (w1, w2) = (w1.unwrap(), w2.unwrap());
        let once = solved(&net, &solve_edge(&net, w1, w2));
        let twice = solved(&once, &solve_edge(&once, w1, w2));
        for (a, b) in once
            .r
            .iter()
            .chain(&once.t)
            .zip(twice.r.iter().chain(&twice.t))
        {
            assert!((*a - *b).length() <= 1e-15);
        }
    }

    /// P's and Q's points on one line with the edge give no weights.
    #[test]
    fn collinear_end_has_no_weights() {
        let mut net = edge_net(1.0);
        net.r[0] = DVec3::new(0.3, 0.0, 0.0);
        net.t[0] = DVec3::new(0.1, 0.0, 0.0);
        net.s[1] = DVec3::new(0.2, 0.0, 0.0);
        assert!(end_weights(&net).0.is_none());
        assert!(end_weights(&net).1.is_some());
    }
}
