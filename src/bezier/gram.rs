//! Integrals of products of Bernstein polynomials over a triangle, for energies and projections
//! measured in the L² sense: `∫_T λ^α dA = 2·Area · α! / (|α|+2)!` (products of factorials over the
//! three components), hence `∫ B^m_α B^m_β = 2·Area · m!² (α+β)! / (α! β! (2m+2)!)`.

use crate::bezier::triangle::point_count;

/// Multi-indices (i, j, k) of degree `d` in the storage order of [`crate::bezier`].
pub fn multi_indices(d: usize) -> Vec<[usize; 3]> {
    let mut out = Vec::with_capacity(point_count(d));
    for i in (0..=d).rev() {
        for j in (0..=d - i).rev() {
            out.push([i, j, d - i - j]);
        }
    }
    out
}

/// `n!` as a float.
pub fn factorial(n: usize) -> f64 {
    (1..=n).map(|k| k as f64).product()
}

/// Gram matrix `∫ B_α B_β dA` of the degree-`m` Bernstein basis over a triangle of area `area`.
pub fn bernstein_gram(m: usize, area: f64) -> Vec<Vec<f64>> {
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

/// Degree elevation `d → d+1` as a matrix: row β of the result holds the weights of the degree-d
/// points in point β of the elevated patch, `b'_β = Σ_k (β_k/(d+1)) b_{β−e_k}`.
pub fn elevation_matrix(d: usize) -> Vec<Vec<f64>> {
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
    use glam::DVec3;

    /// The Gram matrix integrates products exactly: its total is the triangle's area
    /// (partition of unity squared), and ∫ B_{(3,0,0)}² = ∫ λ0⁶ = 2A·6!/8!.
    #[test]
    fn bernstein_gram_sums_to_area() {
        let g = bernstein_gram(3, 0.7);
        let total: f64 = g.iter().flatten().sum();
        assert!((total - 0.7).abs() < 1e-14, "{total}");
        assert!((g[0][0] - 2.0 * 0.7 / 56.0).abs() < 1e-15);
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
        for (row, expected) in m.iter().zip(elevated.points()) {
            let p: DVec3 = row.iter().zip(patch.points()).map(|(w, p)| *w * *p).sum();
            assert!((p - *expected).length() < 1e-13);
        }
    }
}
