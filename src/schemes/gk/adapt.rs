//! Adaptation step of Construction 2.1 [UP §2]: joining the p-patch `p = q ∘ x` to the
//! surrounding surface. UP only says "e.g. by exchanging certain control points"; this is the
//! design used here.
//!
//! On each of the 3n ring triangles the final patch is `P = E(r) + D'`, where `E(r)` is the
//! surface ring `r` degree-elevated to 2d and `D'` is a correction of degree 2d built from
//! `D = q ∘ x − E(r)`:
//!
//! * at the inner boundary of the ring (the rows `≤ k` along an inner edge, the points within
//!   k of an inner vertex) `D' = D`, so `P = q ∘ x` there to order k and `P` joins the inner
//!   p-patches `q ∘ x_s` with G^k (C^k in the chart across the inner edges);
//! * at the outer boundary (rows `≤ k` along an outer edge, points within k of an outer
//!   vertex) `D' = 0`, so `P = r` there to order k and `P` joins the regular surface C^k;
//! * the remaining ("free") points lie in a band of `k + 1` rows in between. They minimise
//!   the thin-plate energy `Σ ∫ |D'_xx|² + 2|D'_xy|² + |D'_yy|²` of the correction over the
//!   3n triangles (each the unit equilateral triangle of the lattice), subject to the C^k
//!   conditions across the 3n ring joints (the lattice parallelogram conditions: across an
//!   edge `P Q` of triangles `(P, Q, a)` and `(Q, P, b)`, `b = P + Q − a` has barycentric
//!   coordinates `(1, 1, −1)`, and row t of the second patch is the blossom of the first at
//!   `P^{i_P} Q^{i_Q} b^t`). The correction so bends as little as it can: its second
//!   derivatives, which add to the curvature of `P`, are spread over the whole band. (The
//!   closest points to a radial blend `φ D`, tried first, bent the correction at the band's
//!   edges and left a visible ring of low curvature in the curvature images at k = 3, 4.)
//!
//! This is "a small constrained solve": with the energy `½ fᵀ A f + fᵀ A_fp p` (A block
//! diagonal, one block per triangle, positive definite because the prescribed rows fix the
//! linear polynomials) and the conditions `M f = g`, the minimiser is
//! `f = f* + A⁻¹ Mᵀ (M A⁻¹ Mᵀ)⁻¹ (g − M f*)` with `f* = −A⁻¹ A_fp p` the unconstrained one.
//! The blocks, `M` and the solve of `M A⁻¹ Mᵀ` depend only on (n, k), so they are computed
//! once per valence and order and cached. `M A⁻¹ Mᵀ` is block-circulant over the n sectors
//! (every sector is the same up to the rotation by one sector), so a discrete Fourier
//! transform over the sector index splits it into `n/2 + 1` blocks of one sector's size,
//! factored once: O(n R³) instead of O(n³ R³) for R conditions per sector, and valence 200
//! costs what valence 3 did times 200 (see [`Adaptation::new`]). Each hole then costs a few
//! sparse products and the transforms, O(n² R). Conditions that involve no free point hold already (D is C^k, and
//! so is 0) and are left out.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use crate::bezier::gram::{factorial, multi_indices, thin_plate_matrix};
use crate::bezier::triangle::{index, point_count};
use crate::linalg::{Matrix, invert};

/// What the adaptation does with one control point of a ring triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PointRole {
    /// Taken from `q ∘ x` (`D' = D`).
    Inner,
    /// Taken from `r` (`D' = 0`).
    Outer,
    /// Solved for.
    Free,
}

/// Ring triangle `tau` of a sector (0 = `Δ(1,0)`, 1 = `∇(1,0)`, 2 = `Δ(1,1)`), point `a`
/// (multi-index) of degree `degree`, order `k`.
pub(crate) fn role(tau: usize, a: [usize; 3], degree: usize, k: usize) -> PointRole {
    // Δ(1,0), Δ(1,1): corner 0 is on the inner boundary, edge 1–2 on the outer one.
    // ∇(1,0): edge 0–2 is on the inner boundary, corner 1 on the outer one.
    let inner_level = if tau == 1 { degree - a[1] } else { a[0] };
    if inner_level >= degree - k {
        PointRole::Inner
    } else if inner_level <= k {
        PointRole::Outer
    } else {
        PointRole::Free
    }
}

/// The joints between ring triangles, as (triangle, edge, triangle, edge) with global triangle
/// numbers `3s + tau`; every edge runs the other way on the second triangle.
fn ring_joints(n: usize) -> Vec<(usize, usize, usize, usize)> {
    (0..n)
        .flat_map(|s| {
            let t = 3 * s;
            [
                (t, 2, t + 1, 0),
                (t + 1, 1, t + 2, 0),
                (t + 2, 2, (t + 3) % (3 * n), 0),
            ]
        })
        .collect()
}

/// The thin-plate fairing of one kind of ring triangle: the free points, the prescribed inner
/// points, and the energy blocks that map them.
#[derive(Debug)]
struct Fairing {
    /// Local indices of the free points.
    free: Vec<usize>,
    /// Local indices of the inner points (prescribed `D' = D`; outer ones are 0).
    inner: Vec<usize>,
    /// `−A_ff⁻¹ A_f,inner`: the unconstrained minimiser from the inner values.
    start: Matrix,
    /// `A_ff⁻¹`.
    inverse: Matrix,
}

impl Fairing {
    fn new(roles: &[PointRole], energy: &Matrix) -> Option<Fairing> {
        let pick = |role| {
            (0..roles.len())
                .filter(|&i| roles[i] == role)
                .collect::<Vec<_>>()
        };
        let (free, inner) = (pick(PointRole::Free), pick(PointRole::Inner));
        let block: Matrix = free
            .iter()
            .map(|&i| free.iter().map(|&j| energy[i][j]).collect())
            .collect();
        let inverse = invert(&block)?;
        let start = inverse
            .iter()
            .map(|row| {
                inner
                    .iter()
                    .map(|&c| {
                        -row.iter()
                            .zip(&free)
                            .map(|(w, &j)| w * energy[j][c])
                            .sum::<f64>()
                    })
                    .collect()
            })
            .collect();
        Some(Fairing {
            free,
            inner,
            start,
            inverse,
        })
    }
}

/// The precomputed adaptation for one valence and order.
#[derive(Debug)]
pub(crate) struct Adaptation {
    /// Valence.
    n: usize,
    degree: usize,
    roles: [Vec<PointRole>; 3],
    fairing: [Fairing; 3],
    /// First free unknown of each ring triangle (its free points are numbered in a row).
    first_free: Vec<usize>,
    /// The conditions that involve a free point: (global point, coefficient), free and
    /// prescribed alike; `per_sector` of them per sector, sector by sector, each sector's
    /// rows the rotation of sector 0's.
    rows: Vec<Vec<(usize, f64)>>,
    /// Conditions per sector.
    per_sector: usize,
    /// Free-unknown number of each global point (usize::MAX if not free).
    free_of: Vec<usize>,
    /// The solve of `M A⁻¹ Mᵀ y = r` per Fourier mode `m = 0..=n/2` over the sectors.
    modes: Vec<ModeSolve>,
}

/// The solve of one Fourier mode `m` of the block-circulant system `M A⁻¹ Mᵀ`: its Hermitian
/// block `Ĝ_m = G_0 + ω G_1 + ω⁻¹ G_{−1}` (`ω = e^{2πim/n}`, `G_δ` the coupling of a sector's
/// conditions with those of sector `+δ`), written as the real symmetric matrix
/// `[[Re Ĝ, −Im Ĝ], [Im Ĝ, Re Ĝ]]` (just `Re Ĝ` for the real modes `m = 0` and `m = n/2`),
/// reduced to its independent rows and factored.
#[derive(Debug)]
struct ModeSolve {
    /// The kept rows of the real form (`0..R` real parts, `R..2R` imaginary parts).
    kept: Vec<usize>,
    /// The Cholesky factor `L` (rows, lower triangular) of the real form over the kept rows
    /// and columns.
    factor: Matrix,
}

impl ModeSolve {
    /// The solution over the kept rows of `L Lᵀ y = rhs` (rhs read at the kept rows), written
    /// into `out` at the kept rows.
    fn solve(&self, rhs: &[DVec3], out: &mut [DVec3]) {
        let l = &self.factor;
        let mut z: Vec<DVec3> = Vec::with_capacity(l.len());
        for (i, row) in l.iter().enumerate() {
            let dot: DVec3 = row[..i].iter().zip(&z).map(|(a, b)| *a * *b).sum();
            z.push((rhs[self.kept[i]] - dot) / row[i]);
        }
        for i in (0..l.len()).rev() {
            let dot: DVec3 = (i + 1..l.len()).map(|j| l[j][i] * z[j]).sum();
            z[i] = (z[i] - dot) / l[i][i];
        }
        for (&i, x) in self.kept.iter().zip(z) {
            out[i] = x;
        }
    }
}

/// The rows of a symmetric positive semi-definite matrix that are independent of the rows
/// before them, and the Cholesky factor over them: the factorisation skips a row whose pivot
/// falls below `1e-10` of its diagonal (C^k conditions of neighbouring joints meet at the
/// ring's inner and outer vertices and repeat each other there).
fn factor_independent(gram: &[Vec<f64>]) -> ModeSolve {
    let mut kept: Vec<usize> = Vec::new();
    let mut factor: Vec<Vec<f64>> = Vec::new(); // rows of L over the kept rows
    for (i, gram_row) in gram.iter().enumerate() {
        let mut row = Vec::with_capacity(kept.len() + 1);
        for (jj, &j) in kept.iter().enumerate() {
            let dot: f64 = row.iter().zip(&factor[jj]).map(|(a, b)| a * b).sum();
            row.push((gram_row[j] - dot) / factor[jj][jj]);
        }
        let pivot = gram_row[i] - row.iter().map(|x| x * x).sum::<f64>();
        if pivot > 1e-10 * gram_row[i] {
            row.push(pivot.sqrt());
            factor.push(row);
            kept.push(i);
        }
    }
    ModeSolve { kept, factor }
}

/// Adaptations by (valence, order, degree).
type AdaptationCache = HashMap<(usize, usize, usize), Arc<Adaptation>>;

/// `cos` and `sin` of `2πj/n` for `j = 0..n`.
fn twiddles(n: usize) -> (Vec<f64>, Vec<f64>) {
    (0..n)
        .map(|j| {
            let angle = std::f64::consts::TAU * j as f64 / n as f64;
            (angle.cos(), angle.sin())
        })
        .unzip()
}

impl Adaptation {
    /// The cached adaptation for valence `n`, order `k`, patch degree `degree` (= 2d); `None`
    /// if a ring triangle's thin-plate block over its free points is singular (it is not for
    /// any order: the prescribed rows fix the linear polynomials).
    pub(crate) fn get(n: usize, k: usize, degree: usize) -> Option<Arc<Adaptation>> {
        static CACHE: OnceLock<Mutex<AdaptationCache>> = OnceLock::new();
        let cache = CACHE.get_or_init(Default::default);
        if let Some(a) = cache.lock().ok()?.get(&(n, k, degree)) {
            return Some(a.clone());
        }
        let built = Arc::new(Adaptation::new(n, k, degree)?);
        cache.lock().ok()?.insert((n, k, degree), built.clone());
        Some(built)
    }

    /// Conditions per sector for order `k` and patch degree `degree` (= 2d), from the layout
    /// of one sector: what the solve of valence n needs is `n/2 + 1` dense blocks of at most
    /// twice this size.
    pub(crate) fn conditions_per_sector(k: usize, degree: usize) -> usize {
        Self::layout(3, k, degree).map_or(0, |a| a.per_sector)
    }

    /// Everything but the solve: roles, fairings, unknowns and conditions.
    fn layout(n: usize, k: usize, degree: usize) -> Option<Adaptation> {
        let count = point_count(degree);
        let indices = multi_indices(degree);
        let roles = [0, 1, 2].map(|tau| {
            indices
                .iter()
                .map(|a| role(tau, *a, degree, k))
                .collect::<Vec<_>>()
        });
        // Δ and ∇ triangles of the lattice are congruent equilateral triangles, and the
        // thin-plate energy is invariant under their rotations and reflections.
        let equilateral = [DVec2::ZERO, DVec2::X, DVec2::new(0.5, 3f64.sqrt() / 2.0)];
        let energy = thin_plate_matrix(degree, equilateral);
        let fairing = [
            Fairing::new(&roles[0], &energy)?,
            Fairing::new(&roles[1], &energy)?,
            Fairing::new(&roles[2], &energy)?,
        ];
        let triangles = 3 * n;
        let mut free_of = vec![usize::MAX; triangles * count];
        let mut first_free = Vec::with_capacity(triangles);
        let mut unknowns = 0;
        for t in 0..triangles {
            first_free.push(unknowns);
            for &i in &fairing[t % 3].free {
                free_of[t * count + i] = unknowns;
                unknowns += 1;
            }
        }
        let mut rows = Vec::new();
        for (x, ex, y, ey) in ring_joints(n) {
            for t in 0..=k {
                for ip in 0..=degree - t {
                    let iq = degree - t - ip;
                    let mut row = Vec::new();
                    let mut ya = [0usize; 3];
                    ya[ey] = iq;
                    ya[(ey + 1) % 3] = ip;
                    ya[(ey + 2) % 3] = t;
                    row.push((y * count + index(degree, ya[0], ya[1]), 1.0));
                    for g in multi_indices(t) {
                        let coef = factorial(t)
                            / (factorial(g[0]) * factorial(g[1]) * factorial(g[2]))
                            * if g[2] % 2 == 1 { -1.0 } else { 1.0 };
                        let mut xa = [0usize; 3];
                        xa[ex] = ip + g[0];
                        xa[(ex + 1) % 3] = iq + g[1];
                        xa[(ex + 2) % 3] = g[2];
                        row.push((x * count + index(degree, xa[0], xa[1]), -coef));
                    }
                    if row.iter().any(|(p, _)| free_of[*p] != usize::MAX) {
                        rows.push(row);
                    }
                }
            }
        }
        // Which conditions have a free point depends only on the roles, the same in every
        // sector, so the sectors have equally many.
        let per_sector = rows.len() / n;
        Some(Adaptation {
            n,
            degree,
            roles,
            fairing,
            first_free,
            rows,
            per_sector,
            free_of,
            modes: Vec::new(),
        })
    }

    /// The system `M A⁻¹ Mᵀ` (conditions × conditions, over the free unknowns) is
    /// block-circulant over the sectors: sector `s + 1`'s conditions and unknowns are sector
    /// `s`'s rotated by one sector, and a sector's conditions meet only those of its two
    /// neighbours (they share a ring triangle). The discrete Fourier transform over the sector
    /// index splits it into `n/2 + 1` independent blocks of one sector's size (modes `m` and
    /// `n − m` are complex conjugates), solved once here: O(n R³) time and O(n R²) memory for
    /// R conditions per sector, instead of O(n³ R³) and O(n² R²) for the whole system.
    fn new(n: usize, k: usize, degree: usize) -> Option<Adaptation> {
        let mut adaptation = Self::layout(n, k, degree)?;
        let blocks = adaptation.coupling_blocks();
        let (cos, sin) = twiddles(n);
        adaptation.modes = (0..=n / 2)
            .into_par_iter()
            .map(|m| factor_independent(&mode_matrix(&blocks, m, n, cos[m], sin[m])))
            .collect();
        Some(adaptation)
    }

    /// `[G_0, G_1, G_{−1}]`: the entries of `M A⁻¹ Mᵀ` between the conditions of sector 0 and
    /// those of sectors 0, 1 and n − 1.
    fn coupling_blocks(&self) -> [Matrix; 3] {
        let r = self.per_sector;
        let sparse: Vec<Vec<(usize, f64)>> = self.rows.iter().map(|x| self.free_part(x)).collect();
        let mut scatter = vec![0.0; self.free_of.iter().filter(|&&f| f != usize::MAX).count()];
        let mut blocks = [
            vec![vec![0.0; r]; r],
            vec![vec![0.0; r]; r],
            vec![vec![0.0; r]; r],
        ];
        for i in 0..r {
            let weighted = self.weigh(&sparse[i]);
            for (j, c) in &weighted {
                scatter[*j] += c;
            }
            for (block, sector) in blocks.iter_mut().zip([0, 1, self.n - 1]) {
                for (j, b) in sparse[sector * r..(sector + 1) * r].iter().enumerate() {
                    block[i][j] = b.iter().map(|(u, c)| c * scatter[*u]).sum();
                }
            }
            for (j, _) in &weighted {
                scatter[*j] = 0.0;
            }
        }
        blocks
    }

    /// The free entries of a condition row, as (unknown, coefficient).
    fn free_part(&self, row: &[(usize, f64)]) -> Vec<(usize, f64)> {
        row.iter()
            .filter(|(p, _)| self.free_of[*p] != usize::MAX)
            .map(|(p, c)| (self.free_of[*p], *c))
            .collect()
    }

    /// `A⁻¹ a` for a sparse vector `a` over the free unknowns (sparse again: A⁻¹ acts within
    /// the triangles `a` touches).
    fn weigh(&self, a: &[(usize, f64)]) -> Vec<(usize, f64)> {
        let mut triangles: Vec<usize> = a.iter().map(|(j, _)| self.triangle_of(*j)).collect();
        triangles.sort_unstable();
        triangles.dedup();
        let mut out = Vec::new();
        for t in triangles {
            let first = self.first_free[t];
            let fairing = &self.fairing[t % 3];
            for (r, row) in fairing.inverse.iter().enumerate() {
                let value: f64 = a
                    .iter()
                    .filter(|(j, _)| (first..first + row.len()).contains(j))
                    .map(|(j, c)| row[j - first] * c)
                    .sum();
                out.push((first + r, value));
            }
        }
        out
    }

    /// The ring triangle of free unknown `j`.
    fn triangle_of(&self, j: usize) -> usize {
        self.first_free.partition_point(|&f| f <= j) - 1
    }

    /// `g − M f` for the conditions, prescribed points at their values (`D` inner, 0 outer).
    fn residual(&self, f: &[DVec3], differences: &[Vec<DVec3>]) -> Vec<DVec3> {
        let count = point_count(self.degree);
        self.rows
            .iter()
            .map(|row| {
                -row.iter()
                    .map(|&(p, c)| {
                        let x = if self.free_of[p] != usize::MAX {
                            f[self.free_of[p]]
                        } else if self.roles[(p / count) % 3][p % count] == PointRole::Inner {
                            differences[p / count][p % count]
                        } else {
                            DVec3::ZERO
                        };
                        c * x
                    })
                    .sum::<DVec3>()
            })
            .collect()
    }

    /// A solution `y` of `M A⁻¹ Mᵀ y = residual`, mode by mode: the residual's discrete
    /// Fourier transform over the sectors, each mode's block solved on its independent rows,
    /// and the transform back.
    fn multipliers(&self, residual: &[DVec3]) -> Vec<DVec3> {
        let (n, r) = (self.n, self.per_sector);
        let (cos, sin) = twiddles(n);
        let mut y = vec![DVec3::ZERO; residual.len()];
        for (m, mode) in self.modes.iter().enumerate() {
            let real = m == 0 || 2 * m == n;
            let mut rhs = vec![DVec3::ZERO; if real { r } else { 2 * r }];
            for (s, sector) in residual.chunks_exact(r).enumerate() {
                let (c, sn) = (cos[m * s % n], sin[m * s % n]);
                for (i, x) in sector.iter().enumerate() {
                    rhs[i] += c * *x;
                    if !real {
                        rhs[r + i] -= sn * *x;
                    }
                }
            }
            let mut solution = vec![DVec3::ZERO; rhs.len()];
            mode.solve(&rhs, &mut solution);
            // Modes m and n − m together: 2 Re(ŷ e^{2πims/n}).
            let weight = if real { 1.0 } else { 2.0 } / n as f64;
            for (s, sector) in y.chunks_exact_mut(r).enumerate() {
                let (c, sn) = (cos[m * s % n], sin[m * s % n]);
                for (i, out) in sector.iter_mut().enumerate() {
                    let mut x = c * solution[i];
                    if !real {
                        x -= sn * solution[r + i];
                    }
                    *out += weight * x;
                }
            }
        }
        y
    }

    /// `f += A⁻¹ Mᵀ y`: the least-energy change that moves the conditions by `M A⁻¹ Mᵀ y`.
    fn correct(&self, f: &mut [DVec3], y: &[DVec3]) {
        let mut pushed = vec![DVec3::ZERO; f.len()];
        for (row, yi) in self.rows.iter().zip(y) {
            for &(p, c) in row {
                if self.free_of[p] != usize::MAX {
                    pushed[self.free_of[p]] += c * *yi;
                }
            }
        }
        for (t, &first) in self.first_free.iter().enumerate() {
            let inverse = &self.fairing[t % 3].inverse;
            for (r, row) in inverse.iter().enumerate() {
                f[first + r] += row
                    .iter()
                    .zip(&pushed[first..first + row.len()])
                    .map(|(w, z)| *w * *z)
                    .sum::<DVec3>();
            }
        }
    }

    /// The unconstrained minimiser `f* = −A⁻¹ A_fp p`, triangle by triangle.
    fn unconstrained(&self, differences: &[Vec<DVec3>]) -> Vec<DVec3> {
        let mut f: Vec<DVec3> = Vec::with_capacity(self.free_of.len());
        for (t, net) in differences.iter().enumerate() {
            let fairing = &self.fairing[t % 3];
            f.extend(fairing.start.iter().map(|row| {
                row.iter()
                    .zip(&fairing.inner)
                    .map(|(w, &i)| *w * net[i])
                    .sum::<DVec3>()
            }));
        }
        f
    }

    /// The nets `D'` with the free points at `f`.
    fn nets(&self, f: &[DVec3], differences: &[Vec<DVec3>]) -> Vec<Vec<DVec3>> {
        let count = point_count(self.degree);
        differences
            .iter()
            .enumerate()
            .map(|(t, net)| {
                net.iter()
                    .enumerate()
                    .map(|(i, d)| match self.roles[t % 3][i] {
                        PointRole::Inner => *d,
                        PointRole::Outer => DVec3::ZERO,
                        PointRole::Free => f[self.free_of[t * count + i]],
                    })
                    .collect()
            })
            .collect()
    }

    /// The correction `D'` for the differences `D` (all 3n nets, `3s + tau` order).
    pub(crate) fn apply(&self, differences: &[Vec<DVec3>]) -> Vec<Vec<DVec3>> {
        let mut f = self.unconstrained(differences);
        // f += A⁻¹ Mᵀ (M A⁻¹ Mᵀ)⁻¹ (g − M f); the second round removes what rounding left
        // of the residual (iterative refinement).
        for _ in 0..2 {
            let residual = self.residual(&f, differences);
            let y = self.multipliers(&residual);
            self.correct(&mut f, &y);
        }
        self.nets(&f, differences)
    }
}

/// The real symmetric form of mode `m`'s block `Ĝ_m = G_0 + ω G_1 + ω⁻¹ G_{−1}`
/// (`ω = cos + i sin` of `2πm/n`): `[[A, −B], [B, A]]` with `A = G_0 + cos (G_1 + G_{−1})`,
/// `B = sin (G_1 − G_{−1})`, or `A` alone for the real modes.
fn mode_matrix(blocks: &[Matrix; 3], m: usize, n: usize, cos: f64, sin: f64) -> Matrix {
    let [g0, g1, gm1] = blocks;
    let r = g0.len();
    let real = m == 0 || 2 * m == n;
    let size = if real { r } else { 2 * r };
    let mut out = vec![vec![0.0; size]; size];
    for i in 0..r {
        for j in 0..r {
            let a = g0[i][j] + cos * (g1[i][j] + gm1[i][j]);
            out[i][j] = a;
            if !real {
                let b = sin * (g1[i][j] - gm1[i][j]);
                out[r + i][r + j] = a;
                out[i][r + j] = -b;
                out[r + i][j] = b;
            }
        }
    }
    out
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// The whole system `M A⁻¹ Mᵀ` (all conditions of all sectors), as the solve built it
    /// before the Fourier split.
    pub(crate) fn dense_gram(a: &Adaptation) -> Matrix {
        let sparse: Vec<Vec<(usize, f64)>> = a.rows.iter().map(|x| a.free_part(x)).collect();
        let mut scatter = vec![0.0; a.free_of.iter().filter(|&&f| f != usize::MAX).count()];
        sparse
            .iter()
            .map(|row| {
                let weighted = a.weigh(row);
                for (j, c) in &weighted {
                    scatter[*j] += c;
                }
                let out = sparse
                    .iter()
                    .map(|b| b.iter().map(|(j, c)| c * scatter[*j]).sum())
                    .collect();
                for (j, _) in &weighted {
                    scatter[*j] = 0.0;
                }
                out
            })
            .collect()
    }

    /// The correction by the dense solve of the whole system on its independent rows (the
    /// construction before the Fourier split, O(n³R³)), for comparison.
    pub(crate) fn dense_apply(a: &Adaptation, differences: &[Vec<DVec3>]) -> Vec<Vec<DVec3>> {
        let gram = dense_gram(a);
        let kept = factor_independent(&gram).kept;
        let reduced: Matrix = kept
            .iter()
            .map(|&i| kept.iter().map(|&j| gram[i][j]).collect())
            .collect();
        let inverse = invert(&reduced).expect("the dense system is regular");
        let mut f = a.unconstrained(differences);
        for _ in 0..2 {
            let residual = a.residual(&f, differences);
            let mut y = vec![DVec3::ZERO; residual.len()];
            for (&i, row) in kept.iter().zip(&inverse) {
                y[i] = row.iter().zip(&kept).map(|(w, &j)| *w * residual[j]).sum();
            }
            a.correct(&mut f, &y);
        }
        a.nets(&f, differences)
    }

    /// The largest violation `|g − M f|` of the C^k conditions by the corrections `nets`.
    pub(crate) fn condition_residual(
        a: &Adaptation,
        nets: &[Vec<DVec3>],
        differences: &[Vec<DVec3>],
    ) -> f64 {
        let count = point_count(a.degree);
        let mut f = vec![DVec3::ZERO; a.free_of.iter().filter(|&&x| x != usize::MAX).count()];
        for (t, net) in nets.iter().enumerate() {
            for (i, x) in net.iter().enumerate() {
                if a.free_of[t * count + i] != usize::MAX {
                    f[a.free_of[t * count + i]] = *x;
                }
            }
        }
        a.residual(&f, differences)
            .iter()
            .fold(0.0f64, |m, r| m.max(r.length()))
    }

    /// The system is block-circulant as built: with P the rotation by one sector (of the
    /// conditions), `‖P G P⁻¹ − G‖_max / ‖G‖_max` is at rounding level (measured 0: the blocks
    /// are computed by the same operations), and sectors two or more apart do not couple —
    /// for every k and n = 3..=9.
    #[test]
    fn the_system_is_block_circulant_over_the_sectors() {
        for k in 1..=4 {
            let degree = 2 * crate::schemes::gk::box_spline::Family::for_order(k).degree();
            for n in 3..=9 {
                let a = Adaptation::layout(n, k, degree).unwrap();
                let r = a.per_sector;
                assert_eq!(a.rows.len(), n * r, "k = {k}, n = {n}");
                let g = dense_gram(&a);
                let scale = g.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
                let (mut shifted, mut far) = (0.0f64, 0.0f64);
                for i in 0..n * r {
                    for j in 0..n * r {
                        let rotated = g[(i + r) % (n * r)][(j + r) % (n * r)];
                        shifted = shifted.max((rotated - g[i][j]).abs());
                        let apart = (i / r + n - j / r) % n;
                        if apart > 1 && apart < n - 1 {
                            far = far.max(g[i][j].abs());
                        }
                    }
                }
                eprintln!(
                    "k = {k}, n = {n}: {} conditions, |PGP⁻¹ − G| / |G| = {:.1e}",
                    n * r,
                    shifted / scale
                );
                assert!(shifted <= 1e-15 * scale, "k = {k}, n = {n}: {shifted:e}");
                assert_eq!(far, 0.0, "k = {k}, n = {n}");
            }
        }
    }
}
