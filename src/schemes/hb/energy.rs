//! The thin-plate energy that chooses the six free control points of an HB00 macro-patch
//! (`free=energy`, the paper's colour plate [HB00 §9]).
//!
//! `E = Σ_pieces ∫ |S_xx|² + 2|S_xy|² + |S_yy|² dx dy`, with the face taken as the equilateral
//! triangle of side 1 (a fixed reference domain, so the minimiser is affine invariant: E is a
//! quadratic form in the control points with scalar coefficients, the same for x, y and z),
//! one [`thin_plate_matrix`] per piece.

use glam::{DVec2, DVec3};

use crate::bezier::gram::thin_plate_matrix;
use crate::linalg::invert;

const DEGREE: usize = 5;
/// Control points of one quintic piece.
const QUINTIC: usize = (DEGREE + 1) * (DEGREE + 2) / 2;
/// Control points of the four pieces, piece by piece.
pub(super) const NETS: usize = 4 * QUINTIC;

/// The constant 6 × 84 map `L = −(GᵀQG)⁻¹ GᵀQ` from the nets completed with zero free points to
/// the energy-minimising free points (three middle twists, then the three points `D_k`), for
/// the columns `g` of `G` (the nets each free point alone produces) and the pieces'
/// face-barycentric `domains`.
pub(super) fn free_point_map(g: &[[f64; NETS]; 6], domains: &[[DVec3; 3]; 4]) -> [[f64; NETS]; 6] {
    let equilateral = [
        DVec2::new(0.0, 0.0),
        DVec2::new(1.0, 0.0),
        DVec2::new(0.5, 3f64.sqrt() / 2.0),
    ];
    let to_2d = |b: DVec3| b.x * equilateral[0] + b.y * equilateral[1] + b.z * equilateral[2];
    let pieces: Vec<Vec<Vec<f64>>> = domains
        .iter()
        .map(|d| thin_plate_matrix(DEGREE, d.map(to_2d)))
        .collect();
    let q_times = |col: &[f64; NETS]| -> [f64; NETS] {
        std::array::from_fn(|i| {
            let (piece, a) = (i / QUINTIC, i % QUINTIC);
            (0..QUINTIC)
                .map(|b| pieces[piece][a][b] * col[piece * QUINTIC + b])
                .sum()
        })
    };
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
