//! One sextic Loop patch per face [HB00 §3]: the boundary curves (quartic, elevated twice), the
//! first inner rows from the quintic cross-boundary tangents `Φ E' + Ψ V` (eq. 3), and the one
//! remaining middle control point `b(2,2,2)` chosen "so that H has quintic precision".
//!
//! Quintic precision is made exact here: `b(2,2,2)` minimises the L² norm of the degree-6 part
//! of the patch, `‖(I − Π₅) H‖` with `Π₅` the L²-orthogonal projection onto quintics. When the
//! other 27 points come from a quintic, that minimum is zero and the quintic is reproduced
//! (tested). The weights are one constant row, computed once.

use std::sync::OnceLock;

use glam::DVec3;

use super::vertex::LoopHalfEdge;
use crate::bezier::gram::{bernstein_gram, elevation_matrix};
use crate::bezier::triangle::{index, point_count};
use crate::bezier::{CurveBezier, TriangleBezier};
use crate::linalg::{Matrix, invert, multiply, transpose};
use crate::schemes::vertex_rings::PsiRule;

/// Degree of Loop's patches.
pub(crate) const DEGREE: usize = 6;

/// Index in a sextic of the point with weight `w[r]` at corner `(k + r) % 3`.
fn rot(k: usize, w: [usize; 3]) -> usize {
    let mut at = [0; 3];
    for r in 0..3 {
        at[(k + r) % 3] = w[r];
    }
    index(DEGREE, at[0], at[1])
}

/// The boundary curve of edge `X → Y` (quartic, eq. 2) and the cross-boundary derivative
/// towards the third corner of the face on its "+" side (quintic, eq. 3), from the data of both
/// ends (that face is on the "−" side of `Y → X`), `Ψ` by `psi`: linear (eq. 4, `ΨV` a
/// quartic elevated to a quintic) or quadratic with the rule's middle coefficient (`ΨV` a
/// quintic, the degree eq. 3 allows). `[x, y]` are `X` and `Y` in the face's frame
/// ([`crate::schemes::vertex_rings::FaceFrame`]): the curve's points, offsets from their vertex
/// in the table, are placed in it.
pub(crate) fn edge_curves(
    here: &LoopHalfEdge,
    there: &LoopHalfEdge,
    psi: PsiRule,
    [x, y]: [DVec3; 2],
) -> (CurveBezier, CurveBezier) {
    let boundary = CurveBezier::new(vec![
        x + here.f[0],
        x + here.f[1],
        x + here.f[2],
        y + there.f[1],
        y + there.f[0],
    ]);
    let (near, far) = (here.side(false), there.side(true));
    // V seen from Y is −V(1−u) (as in HB00: Φ̃ = 1 − Φ, Ψ̃ = Ψ), so its cubic, in X's order:
    let v = CurveBezier::new(vec![near.v[0], near.v[1], -far.v[1], -far.v[0]]);
    let phi = [near.phi0, 0.5, 1.0 - far.phi0];
    let phi_e = boundary.derivative().times_scalar_polynomial(&phi);
    let psi_v = match psi {
        PsiRule::Linear => v.times_scalar_polynomial(&[near.psi0, far.psi0]).elevate(),
        PsiRule::Harmonic => {
            v.times_scalar_polynomial(&[near.psi0, psi.middle(near.psi0, far.psi0), far.psi0])
        }
    };
    let cross = CurveBezier::new(
        phi_e
            .points()
            .iter()
            .zip(psi_v.points())
            .map(|(a, b)| *a + *b)
            .collect(),
    );
    (boundary, cross)
}

/// The sextic of a face from the three edges `a_k → a_{k+1}` (boundary, cross derivative).
pub(crate) fn sextic(edges: &[(CurveBezier, CurveBezier); 3]) -> TriangleBezier {
    let mut points = vec![DVec3::ZERO; point_count(DEGREE)];
    let mut twist_sum = [DVec3::ZERO; 3];
    for (k, (boundary, cross)) in edges.iter().enumerate() {
        let boundary = boundary.elevate().elevate();
        for m in 0..=DEGREE {
            points[rot(k, [DEGREE - m, m, 0])] = boundary.points()[m];
        }
        // Face (a_k, a_{k+1}, a_{k+2}) lies on the left of a_k → a_{k+1}, so the cross derivative
        // is the derivative along a_{k+2} − a_k: 6 (b(5−m, m, 1) − b(6−m, m, 0)) = cross_m.
        for m in 1..DEGREE - 1 {
            let p = boundary.points()[m] + cross.points()[m] / DEGREE as f64;
            match m {
                // The twist points lie in two first rows; both values agree when the twists solve
                // (II_T), and are averaged to stay symmetric in rounding.
                1 => twist_sum[k] += p,
                4 => twist_sum[(k + 1) % 3] += p,
                _ => points[rot(k, [DEGREE - 1 - m, m, 1])] = p,
            }
        }
    }
    for (k, sum) in twist_sum.iter().enumerate() {
        points[rot(k, [4, 1, 1])] = 0.5 * *sum;
    }
    let centre = index(DEGREE, 2, 2);
    points[centre] = quintic_precision_weights()
        .iter()
        .zip(&points)
        .map(|(w, p)| *w * *p)
        .sum();
    TriangleBezier::new(DEGREE, points)
}

/// `b(2,2,2) = Σ w_a b_a` (w at the centre itself is 0): the minimiser of the degree-6 part.
fn quintic_precision_weights() -> &'static [f64] {
    static WEIGHTS: OnceLock<Vec<f64>> = OnceLock::new();
    WEIGHTS.get_or_init(|| {
        let n = point_count(DEGREE);
        let e = elevation_matrix(DEGREE - 1);
        let g = bernstein_gram(DEGREE, 1.0);
        let et = transpose(&e);
        let etg = multiply(&et, &g);
        let gram_low = invert(&multiply(&etg, &e)).expect("Gram matrices are positive definite");
        let projection = multiply(&multiply(&e, &gram_low), &etg);
        let residual: Matrix = (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| f64::from(u8::from(i == j)) - projection[i][j])
                    .collect()
            })
            .collect();
        let m = multiply(&multiply(&transpose(&residual), &g), &residual);
        let c = index(DEGREE, 2, 2);
        (0..n)
            .map(|a| if a == c { 0.0 } else { -m[c][a] / m[c][c] })
            .collect()
    })
}

/// Test-only items: used by the unit tests of this and other modules, compiled only for them.
#[cfg(test)]
pub(crate) mod test_support {
    use super::*;

    /// Disagreement of the two values of each twist point, for tests and diagnostics.
    pub(crate) fn twist_mismatch(edges: &[(CurveBezier, CurveBezier); 3]) -> f64 {
        let first_row = |k: usize, m: usize| {
            let (boundary, cross) = &edges[k];
            let boundary = boundary.elevate().elevate();
            boundary.points()[m] + cross.points()[m] / DEGREE as f64
        };
        (0..3)
            .map(|k| (first_row(k, 1) - first_row((k + 2) % 3, 4)).length())
            .fold(0.0, f64::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A degree-elevated quintic with its centre point destroyed gets it back exactly.
    #[test]
    fn centre_point_reproduces_quintics() {
        let quintic = TriangleBezier::from_fn(5, |i, j, k| {
            DVec3::new(
                (i * j) as f64 * 0.1 - k as f64,
                (j + 2 * k) as f64 * 0.3,
                ((i + 1) * (k + 2)) as f64 * 0.05,
            )
        });
        let sextic = quintic.elevate();
        let c = index(DEGREE, 2, 2);
        let mut broken = sextic.offsets().to_vec();
        broken[c] = DVec3::splat(17.0);
        let recovered: DVec3 = quintic_precision_weights()
            .iter()
            .zip(&broken)
            .map(|(w, p)| *w * *p)
            .sum();
        assert!(
            (recovered - sextic.offsets()[c]).length() < 1e-12,
            "{recovered} vs {}",
            sextic.offsets()[c]
        );
        let weight_sum: f64 = quintic_precision_weights().iter().sum();
        assert!((weight_sum - 1.0).abs() < 1e-12, "affine: {weight_sum}");
    }
}
