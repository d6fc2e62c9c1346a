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
//! The blocks, `M` and `(M A⁻¹ Mᵀ)⁻¹` depend only on (n, k), so they are computed once per
//! valence and order and cached; each hole then costs a few sparse and one dense
//! matrix–vector products. Conditions that involve no free point hold already (D is C^k, and
//! so is 0) and are left out.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use glam::{DVec2, DVec3};

use crate::bezier::gram::{factorial, multi_indices, thin_plate_matrix};
use crate::bezier::triangle::{index, point_count};
use crate::linalg::{Matrix, invert};

/// What the adaptation does with one control point of a ring triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PointRole {
    /// Taken from `q ∘ x` (`D' = D`).
    Inner,
    /// Taken from `r` (`D' = 0`).
    Outer,
    /// Solved for.
    Free,
}

/// Ring triangle `tau` of a sector (0 = `Δ(1,0)`, 1 = `∇(1,0)`, 2 = `Δ(1,1)`), point `a`
/// (multi-index) of degree `degree`, order `k`.
pub fn role(tau: usize, a: [usize; 3], degree: usize, k: usize) -> PointRole {
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
pub struct Adaptation {
    degree: usize,
    roles: [Vec<PointRole>; 3],
    fairing: [Fairing; 3],
    /// First free unknown of each ring triangle (its free points are numbered in a row).
    first_free: Vec<usize>,
    /// The kept conditions: (global point, coefficient), free and prescribed alike.
    rows: Vec<Vec<(usize, f64)>>,
    /// Free-unknown number of each global point (usize::MAX if not free).
    free_of: Vec<usize>,
    /// `(M A⁻¹ Mᵀ)⁻¹`.
    inverse: Matrix,
}

/// The rows of `M` that are independent of the rows before them, from the Gram matrix
/// `M Mᵀ` by a Cholesky factorisation that skips a row whose pivot falls below `1e-10` of its
/// diagonal (C^k conditions of neighbouring joints meet at the ring's inner and outer
/// vertices and repeat each other there).
fn independent_rows(gram: &[Vec<f64>]) -> Vec<usize> {
    let mut kept: Vec<usize> = Vec::new();
    let mut factor: Vec<Vec<f64>> = Vec::new(); // rows of L over the kept rows
    for (i, gram_row) in gram.iter().enumerate() {
        let mut row = Vec::with_capacity(kept.len());
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
    kept
}

/// Adaptations by (valence, order, degree).
type AdaptationCache = HashMap<(usize, usize, usize), Arc<Adaptation>>;

impl Adaptation {
    /// The cached adaptation for valence `n`, order `k`, patch degree `degree` (= 2d); `None`
    /// if the independent conditions still give a singular system (never for the valences
    /// and orders tested).
    pub fn get(n: usize, k: usize, degree: usize) -> Option<Arc<Adaptation>> {
        static CACHE: OnceLock<Mutex<AdaptationCache>> = OnceLock::new();
        let cache = CACHE.get_or_init(Default::default);
        if let Some(a) = cache.lock().ok()?.get(&(n, k, degree)) {
            return Some(a.clone());
        }
        let built = Arc::new(Adaptation::new(n, k, degree)?);
        cache.lock().ok()?.insert((n, k, degree), built.clone());
        Some(built)
    }

    fn new(n: usize, k: usize, degree: usize) -> Option<Adaptation> {
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
        let mut adaptation = Adaptation {
            degree,
            roles,
            fairing,
            first_free,
            rows,
            free_of,
            inverse: Vec::new(),
        };
        // M A⁻¹ Mᵀ over the free columns, rows of M sparse and A⁻¹ block diagonal.
        let sparse: Vec<Vec<(usize, f64)>> = adaptation
            .rows
            .iter()
            .map(|r| adaptation.free_part(r))
            .collect();
        let weighted: Vec<Vec<(usize, f64)>> = sparse.iter().map(|a| adaptation.weigh(a)).collect();
        let mut scatter = vec![0.0; unknowns];
        let gram: Matrix = weighted
            .iter()
            .map(|wa| {
                for (j, c) in wa {
                    scatter[*j] += c;
                }
                let out = sparse
                    .iter()
                    .map(|b| b.iter().map(|(j, c)| c * scatter[*j]).sum())
                    .collect();
                for (j, _) in wa {
                    scatter[*j] = 0.0;
                }
                out
            })
            .collect();
        let independent = independent_rows(&gram);
        let gram: Matrix = independent
            .iter()
            .map(|&i| independent.iter().map(|&j| gram[i][j]).collect())
            .collect();
        adaptation.rows = independent
            .iter()
            .map(|&i| adaptation.rows[i].clone())
            .collect();
        adaptation.inverse = invert(&gram)?;
        Some(adaptation)
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

    /// `g − M f` for the kept conditions, prescribed points at their values (`D` inner, 0
    /// outer).
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

    /// `f += A⁻¹ Mᵀ (M A⁻¹ Mᵀ)⁻¹ residual`: the least-energy change that removes `residual`.
    fn correct(&self, f: &mut [DVec3], residual: &[DVec3]) {
        let y: Vec<DVec3> = self
            .inverse
            .iter()
            .map(|row| row.iter().zip(residual).map(|(w, r)| *w * *r).sum())
            .collect();
        let mut pushed = vec![DVec3::ZERO; f.len()];
        for (row, yi) in self.rows.iter().zip(&y) {
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

    /// The correction `D'` for the differences `D` (all 3n nets, `3s + tau` order).
    pub fn apply(&self, differences: &[Vec<DVec3>]) -> Vec<Vec<DVec3>> {
        let count = point_count(self.degree);
        // The unconstrained minimiser f* = −A⁻¹ A_fp p, triangle by triangle.
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
        // f += A⁻¹ Mᵀ (M A⁻¹ Mᵀ)⁻¹ (g − M f); the second round removes what rounding left
        // of the residual (iterative refinement).
        for _ in 0..2 {
            let residual = self.residual(&f, differences);
            self.correct(&mut f, &residual);
        }
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
}
