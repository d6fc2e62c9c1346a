//! The thin-plate energy that chooses the six free control points of an HB00 macro-patch
//! (`free=energy`, the paper's colour plate [HB00 §9]).
//!
//! `E = Σ_pieces ∫ |S_xx|² + 2|S_xy|² + |S_yy|² dx dy`, with the face taken as the equilateral
//! triangle of side 1 (a fixed reference domain, so the minimiser is affine invariant: E is a
//! quadratic form in the control points with scalar coefficients, the same for x, y and z).
//! Per piece, `D_a D_b S = d(d−1) Σ_γ (Δ_a Δ_b b)_γ B^{d−2}_γ` with barycentric directions
//! `a, b`, and `∫ B^m_α B^m_β = 2·Area · m!² (α+β)! / (α! β! (2m+2)!)` (products of factorials over
//! the three components).

use glam::{DVec2, DVec3};

use super::macro_patch::{QUINTIC, free_point_columns, piece_domains};
use crate::bezier::gram::{bernstein_gram, multi_indices};
use crate::bezier::triangle::index;
use crate::linalg::invert;

const DEGREE: usize = 5;
const NETS: usize = 4 * QUINTIC;

/// Thin-plate energy matrix (21 × 21) of a quintic over the 2-D triangle `corners`.
fn thin_plate_matrix(corners: [DVec2; 3]) -> Vec<Vec<f64>> {
    let area2 = (corners[1] - corners[0]).perp_dot(corners[2] - corners[0]);
    // ∇λ_i = rot90(c_{i+2} − c_{i+1}) / (2A).
    let grad: [DVec2; 3] =
        std::array::from_fn(|i| (corners[(i + 2) % 3] - corners[(i + 1) % 3]).perp() / area2);
    let gx = grad.map(|g| g.x);
    let gy = grad.map(|g| g.y);
    let low = multi_indices(DEGREE - 2);
    let gram = bernstein_gram(DEGREE - 2, area2.abs() / 2.0);
    let scale = ((DEGREE * (DEGREE - 1)) as f64).powi(2);
    let mut qm = vec![vec![0.0; QUINTIC]; QUINTIC];
    for (a, b, weight) in [(gx, gx, 1.0), (gx, gy, 2.0), (gy, gy, 1.0)] {
        // Rows: coefficient γ of D_a D_b S as a combination of the 21 control points.
        let rows: Vec<[f64; QUINTIC]> = low
            .iter()
            .map(|g| {
                let mut row = [0.0; QUINTIC];
                for (s, a_s) in a.iter().enumerate() {
                    for (t, b_t) in b.iter().enumerate() {
                        let mut m = *g;
                        m[s] += 1;
                        m[t] += 1;
                        row[index(DEGREE, m[0], m[1])] += a_s * b_t;
                    }
                }
                row
            })
            .collect();
        for (g1, r1) in rows.iter().enumerate() {
            for (g2, r2) in rows.iter().enumerate() {
                let w = weight * scale * gram[g1][g2];
                for i in 0..QUINTIC {
                    if r1[i] == 0.0 {
                        continue;
                    }
                    for j in 0..QUINTIC {
                        qm[i][j] += w * r1[i] * r2[j];
                    }
                }
            }
        }
    }
    qm
}

/// The constant 6 × 84 map `L = −(GᵀQG)⁻¹ GᵀQ` from the nets completed with zero free points to
/// the energy-minimising free points (three middle twists, then the three points `D_k`).
pub(super) fn free_point_map() -> [[f64; NETS]; 6] {
    let equilateral = [
        DVec2::new(0.0, 0.0),
        DVec2::new(1.0, 0.0),
        DVec2::new(0.5, 3f64.sqrt() / 2.0),
    ];
    let to_2d = |b: DVec3| b.x * equilateral[0] + b.y * equilateral[1] + b.z * equilateral[2];
    let pieces: Vec<Vec<Vec<f64>>> = piece_domains()
        .iter()
        .map(|d| thin_plate_matrix(d.map(to_2d)))
        .collect();
    let q_times = |col: &[f64; NETS]| -> [f64; NETS] {
        std::array::from_fn(|i| {
            let (piece, a) = (i / QUINTIC, i % QUINTIC);
            (0..QUINTIC)
                .map(|b| pieces[piece][a][b] * col[piece * QUINTIC + b])
                .sum()
        })
    };
    let g = free_point_columns();
    let qg: Vec<[f64; NETS]> = g.iter().map(q_times).collect();
    // H = GᵀQG (6 × 6, symmetric positive definite).
    let mut h = [[0.0; 6]; 6];
    for r in 0..6 {
        for c in 0..6 {
            h[r][c] = (0..NETS).map(|i| g[r][i] * qg[c][i]).sum();
        }
    }
    let h_inv = invert(&h.iter().map(|r| r.to_vec()).collect())
        .expect("the thin-plate energy is positive definite on the free points");
    std::array::from_fn(|r| {
        std::array::from_fn(|i| -(0..6).map(|c| h_inv[r][c] * qg[c][i]).sum::<f64>())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bezier::gram::factorial;

    /// A quadratic function has constant second derivatives: the thin-plate energy of its
    /// quintic form over a triangle equals (f_xx² + 2 f_xy² + f_yy²) × area.
    #[test]
    fn thin_plate_energy_of_a_quadratic_is_exact() {
        let corners = [
            DVec2::new(0.2, 0.1),
            DVec2::new(1.3, 0.4),
            DVec2::new(0.5, 1.2),
        ];
        let f = |p: DVec2| 0.5 * 3.0 * p.x * p.x + 2.0 * p.x * p.y - 0.5 * p.y * p.y + p.x;
        // Quintic Bézier coefficients of f: interpolate its values at the 21 domain points.
        let idx = multi_indices(5);
        let pts: Vec<DVec2> = idx
            .iter()
            .map(|m| {
                (m[0] as f64 * corners[0] + m[1] as f64 * corners[1] + m[2] as f64 * corners[2])
                    / 5.0
            })
            .collect();
        // Solve the 21×21 interpolation system B c = f(pts) by Gaussian elimination.
        let n = idx.len();
        let mut a: Vec<Vec<f64>> = pts
            .iter()
            .map(|p| {
                let l = barycentric(corners, *p);
                let mut row: Vec<f64> = idx
                    .iter()
                    .map(|m| {
                        factorial(5) / (factorial(m[0]) * factorial(m[1]) * factorial(m[2]))
                            * l[0].powi(m[0] as i32)
                            * l[1].powi(m[1] as i32)
                            * l[2].powi(m[2] as i32)
                    })
                    .collect();
                row.push(f(*p));
                row
            })
            .collect();
        for c in 0..n {
            let piv = (c..n)
                .max_by(|&x, &y| a[x][c].abs().total_cmp(&a[y][c].abs()))
                .unwrap();
            a.swap(c, piv);
            let pivot_row = a[c].clone();
            for (r, row) in a.iter_mut().enumerate() {
                if r != c {
                    let fct = row[c] / pivot_row[c];
                    for (x, p) in row.iter_mut().zip(&pivot_row).skip(c) {
                        *x -= fct * p;
                    }
                }
            }
        }
        let coef: Vec<f64> = (0..n).map(|r| a[r][n] / a[r][r]).collect();
        let qm = thin_plate_matrix(corners);
        let energy: f64 = (0..n)
            .map(|i| (0..n).map(|j| coef[i] * qm[i][j] * coef[j]).sum::<f64>())
            .sum();
        let area = (corners[1] - corners[0]).perp_dot(corners[2] - corners[0]) / 2.0;
        let expected = (3.0f64.powi(2) + 2.0 * 2.0f64.powi(2) + 1.0) * area;
        assert!(
            (energy - expected).abs() < 1e-9 * expected,
            "{energy} vs {expected}"
        );
    }

    fn barycentric(c: [DVec2; 3], p: DVec2) -> [f64; 3] {
        let a2 = (c[1] - c[0]).perp_dot(c[2] - c[0]);
        let l1 = (p - c[0]).perp_dot(c[2] - c[0]) / a2;
        let l2 = (c[1] - c[0]).perp_dot(p - c[0]) / a2;
        [1.0 - l1 - l2, l1, l2]
    }
}
