//! Integrals of products of Bernstein polynomials over a triangle, for energies and projections
//! measured in the L² sense: `∫_T λ^α dA = 2·Area · α! / (|α|+2)!` (products of factorials over the
//! three components), hence `∫ B^m_α B^m_β = 2·Area · m!² (α+β)! / (α! β! (2m+2)!)`.

use glam::DVec2;

use crate::bezier::triangle::{index, point_count};
use crate::linalg::Matrix;

/// Multi-indices (i, j, k) of degree `d` in the storage order of [`crate::bezier`].
pub(crate) fn multi_indices(d: usize) -> Vec<[usize; 3]> {
    let mut out = Vec::with_capacity(point_count(d));
    for i in (0..=d).rev() {
        for j in (0..=d - i).rev() {
            out.push([i, j, d - i - j]);
        }
    }
    out
}

/// `n!` as a float.
pub(crate) fn factorial(n: usize) -> f64 {
    (1..=n).map(|k| k as f64).product()
}

/// Gram matrix `∫ B_α B_β dA` of the degree-`m` Bernstein basis over a triangle of area `area`.
pub(crate) fn bernstein_gram(m: usize, area: f64) -> Vec<Vec<f64>> {
    let idx = multi_indices(m);
    let fact3 = |a: [usize; 3]| a.iter().map(|&x| factorial(x)).product::<f64>();
    idx.iter()
        .map(|a| {
            idx.iter()
                .map(|b| {
                    let sum = [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
                    2.0 * area * factorial(m).powi(2) * fact3(sum)
                        / (fact3(*a) * fact3(*b) * factorial(2 * m + 2))
                })
                .collect()
        })
        .collect()
}

/// Thin-plate energy matrix `Q` of the degree-`d` patches over the 2-D triangle `corners`:
/// `∫ |S_xx|² + 2|S_xy|² + |S_yy|² dx dy = Σ_{α,β} Q_αβ b_α·b_β`. Per barycentric pair of
/// directions, `D_a D_b S = d(d−1) Σ_γ (Δ_a Δ_b b)_γ B^{d−2}_γ`, and the products are integrated
/// with [`bernstein_gram`] (Farin, CAGD §17.6 for the derivatives).
pub(crate) fn thin_plate_matrix(d: usize, corners: [DVec2; 3]) -> Matrix {
    let count = point_count(d);
    let area2 = (corners[1] - corners[0]).perp_dot(corners[2] - corners[0]);
    // ∇λ_i = rot90(c_{i+2} − c_{i+1}) / (2A).
    let grad: [DVec2; 3] =
        std::array::from_fn(|i| (corners[(i + 2) % 3] - corners[(i + 1) % 3]).perp() / area2);
    let gx = grad.map(|g| g.x);
    let gy = grad.map(|g| g.y);
    let low = multi_indices(d - 2);
    let gram = bernstein_gram(d - 2, area2.abs() / 2.0);
    let scale = ((d * (d - 1)) as f64).powi(2);
    let mut q = vec![vec![0.0; count]; count];
    for (a, b, weight) in [(gx, gx, 1.0), (gx, gy, 2.0), (gy, gy, 1.0)] {
        // Row γ: coefficient γ of D_a D_b S as a combination of the control points.
        let rows: Vec<Vec<f64>> = low
            .iter()
            .map(|g| {
                let mut row = vec![0.0; count];
                for (s, a_s) in a.iter().enumerate() {
                    for (t, b_t) in b.iter().enumerate() {
                        let mut m = *g;
                        m[s] += 1;
                        m[t] += 1;
                        row[index(d, m[0], m[1])] += a_s * b_t;
                    }
                }
                row
            })
            .collect();
        for (g1, r1) in rows.iter().enumerate() {
            for (g2, r2) in rows.iter().enumerate() {
                let w = weight * scale * gram[g1][g2];
                for (i, x) in r1.iter().enumerate().filter(|(_, x)| **x != 0.0) {
                    for (j, y) in r2.iter().enumerate().filter(|(_, y)| **y != 0.0) {
                        q[i][j] += w * x * y;
                    }
                }
            }
        }
    }
    q
}

/// Degree elevation `d → d+1` as a matrix: row β of the result holds the weights of the degree-d
/// points in point β of the elevated patch, `b'_β = Σ_k (β_k/(d+1)) b_{β−e_k}`.
pub(crate) fn elevation_matrix(d: usize) -> Vec<Vec<f64>> {
    let low = multi_indices(d);
    multi_indices(d + 1)
        .iter()
        .map(|beta| {
            low.iter()
                .map(|alpha| {
                    let diff: Vec<i64> = (0..3).map(|k| beta[k] as i64 - alpha[k] as i64).collect();
                    match diff.iter().position(|&x| x == 1) {
                        Some(k) if diff.iter().filter(|&&x| x == 0).count() == 2 => {
                            beta[k] as f64 / (d + 1) as f64
                        }
                        _ => 0.0,
                    }
                })
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bezier::TriangleBezier;
    use crate::bezier::test_support::domain_point_collocation;
    use glam::DVec3;

    /// The Gram matrix integrates products exactly: its total is the triangle's area
    /// (partition of unity squared), and ∫ B_{(3,0,0)}² = ∫ λ0⁶ = 2A·6!/8!.
    #[test]
    fn bernstein_gram_sums_to_area() {
        let g = bernstein_gram(3, 0.7);
        let total: f64 = g.iter().flatten().sum();
        crate::assert_near!(total, 0.7, 1e-14);
        crate::assert_near!(g[0][0], 2.0 * 0.7 / 56.0, 1e-15);
    }

    /// The matrix reproduces [`TriangleBezier::elevate`].
    #[test]
    fn elevation_matrix_matches_elevate() {
        let patch = TriangleBezier::from_fn(4, |i, j, k| {
            DVec3::new(
                i as f64 * 0.3 + (j * k) as f64,
                (j * j) as f64,
                k as f64 - 0.5 * i as f64,
            )
        });
        let m = elevation_matrix(4);
        let elevated = patch.elevate();
        for (row, expected) in m.iter().zip(elevated.offsets()) {
            let p: DVec3 = row.iter().zip(patch.offsets()).map(|(w, p)| *w * *p).sum();
            assert!((p - *expected).length() < 1e-13);
        }
    }

    /// A quadratic function has constant second derivatives: the thin-plate energy of its
    /// degree-d form over a triangle equals (f_xx² + 2 f_xy² + f_yy²) × area, for d = 2..9.
    #[test]
    fn thin_plate_energy_of_a_quadratic_is_exact() {
        let corners = [
            DVec2::new(0.2, 0.1),
            DVec2::new(1.3, 0.4),
            DVec2::new(0.5, 1.2),
        ];
        let f = |p: DVec2| 1.5 * p.x * p.x + 2.0 * p.x * p.y - 0.5 * p.y * p.y + p.x;
        let area = (corners[1] - corners[0]).perp_dot(corners[2] - corners[0]) / 2.0;
        let expected = (3.0f64.powi(2) + 2.0 * 2.0f64.powi(2) + 1.0) * area;
        for d in 2..=9 {
            // Coefficients of f: interpolate its values at the domain points.
            let idx = multi_indices(d);
            let at = |m: &[usize; 3]| m.map(|x| x as f64 / d as f64);
            let collocation = domain_point_collocation(d);
            let inverse =
                crate::linalg::invert(&collocation).expect("domain points are unisolvent");
            let values: Vec<f64> = idx
                .iter()
                .map(|m| {
                    let l = at(m);
                    f(l[0] * corners[0] + l[1] * corners[1] + l[2] * corners[2])
                })
                .collect();
            let coef: Vec<f64> = inverse
                .iter()
                .map(|row| row.iter().zip(&values).map(|(a, b)| a * b).sum())
                .collect();
            let q = thin_plate_matrix(d, corners);
            let energy: f64 = (0..idx.len())
                .map(|i| {
                    (0..idx.len())
                        .map(|j| coef[i] * q[i][j] * coef[j])
                        .sum::<f64>()
                })
                .sum();
            assert!(
                (energy - expected).abs() < 1e-9 * expected,
                "d = {d}: {energy} vs {expected}"
            );
        }
    }
}
