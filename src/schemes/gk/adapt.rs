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
//! * the remaining ("free") points lie in a band of `k + 1` rows in between. They are the
//!   closest, in the least-squares sense, to the radial blend `φ D` (φ falling linearly from 1
//!   at the inner rows to 0 at the outer rows) subject to the C^k conditions across the 3n
//!   ring joints (the lattice parallelogram conditions: across an edge `P Q` of triangles
//!   `(P, Q, a)` and `(Q, P, b)`, `b = P + Q − a` has barycentric coordinates `(1, 1, −1)`, and
//!   row t of the second patch is the blossom of the first at `P^{i_P} Q^{i_Q} b^t`).
//!
//! This is "a small constrained solve": `min |f − f₀|²` subject to `M f = g` gives
//! `f = f₀ + Mᵀ (M Mᵀ)⁻¹ (g − M f₀)`. `M`, the blend weights and `(M Mᵀ)⁻¹` depend only on
//! (n, k), so they are computed once per valence and order and cached; each hole then costs a
//! few sparse and one dense matrix–vector products. Conditions that involve no free point hold
//! already (D is C^k, and so is 0) and are left out.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use glam::DVec3;

use crate::bezier::gram::{factorial, multi_indices};
use crate::bezier::triangle::{index, point_count};
use crate::linalg::invert;

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

/// The precomputed adaptation for one valence and order.
#[derive(Debug)]
pub struct Adaptation {
    degree: usize,
    roles: [Vec<PointRole>; 3],
    /// Global point (`triangle · N + index`) of each free unknown.
    free: Vec<usize>,
    /// Blend weight φ of each free unknown.
    blend: Vec<f64>,
    /// The kept conditions: (global point, coefficient), free and prescribed alike.
    rows: Vec<Vec<(usize, f64)>>,
    /// Free-unknown number of each global point (usize::MAX if not free).
    free_of: Vec<usize>,
    /// `(M Mᵀ)⁻¹`.
    inverse: Vec<Vec<f64>>,
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
        let triangles = 3 * n;
        let mut free = Vec::new();
        let mut blend = Vec::new();
        let mut free_of = vec![usize::MAX; triangles * count];
        let band = (degree - 2 * k) as f64;
        for t in 0..triangles {
            for (i, a) in indices.iter().enumerate() {
                if roles[t % 3][i] == PointRole::Free {
                    let inner_level = if t % 3 == 1 { degree - a[1] } else { a[0] };
                    free_of[t * count + i] = free.len();
                    free.push(t * count + i);
                    blend.push((inner_level - k) as f64 / band);
                }
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
        // M Mᵀ over the free columns.
        let dense: Vec<Vec<(usize, f64)>> = rows
            .iter()
            .map(|row| {
                row.iter()
                    .filter(|(p, _)| free_of[*p] != usize::MAX)
                    .map(|(p, c)| (free_of[*p], *c))
                    .collect()
            })
            .collect();
        let mut scatter = vec![0.0; free.len()];
        let gram: Vec<Vec<f64>> = dense
            .iter()
            .map(|a| {
                for (j, c) in a {
                    scatter[*j] += c;
                }
                let out = dense
                    .iter()
                    .map(|b| b.iter().map(|(j, c)| c * scatter[*j]).sum())
                    .collect();
                for (j, _) in a {
                    scatter[*j] = 0.0;
                }
                out
            })
            .collect();
        let independent = independent_rows(&gram);
        let gram: Vec<Vec<f64>> = independent
            .iter()
            .map(|&i| independent.iter().map(|&j| gram[i][j]).collect())
            .collect();
        let rows: Vec<Vec<(usize, f64)>> = independent.iter().map(|&i| rows[i].clone()).collect();
        let inverse = invert(&gram)?;
        Some(Adaptation {
            degree,
            roles,
            free,
            blend,
            rows,
            free_of,
            inverse,
        })
    }

    /// Number of free points and of conditions (for diagnostics).
    pub fn size(&self) -> (usize, usize) {
        (self.free.len(), self.rows.len())
    }

    /// The role of point `i` of ring triangle `tau`.
    pub fn role(&self, tau: usize, i: usize) -> PointRole {
        self.roles[tau][i]
    }

    /// The correction `D'` for the differences `D` (all 3n nets, `3s + tau` order).
    pub fn apply(&self, differences: &[Vec<DVec3>]) -> Vec<Vec<DVec3>> {
        let count = point_count(self.degree);
        let value_of = |p: usize| differences[p / count][p % count];
        let f0: Vec<DVec3> = self
            .free
            .iter()
            .zip(&self.blend)
            .map(|(&p, &phi)| phi * value_of(p))
            .collect();
        // Residual of the conditions at f₀, with prescribed points at their values.
        let residual: Vec<DVec3> = self
            .rows
            .iter()
            .map(|row| {
                -row.iter()
                    .map(|&(p, c)| {
                        let x = if self.free_of[p] != usize::MAX {
                            f0[self.free_of[p]]
                        } else if self.roles[(p / count) % 3][p % count] == PointRole::Inner {
                            value_of(p)
                        } else {
                            DVec3::ZERO
                        };
                        c * x
                    })
                    .sum::<DVec3>()
            })
            .collect();
        let y: Vec<DVec3> = self
            .inverse
            .iter()
            .map(|row| row.iter().zip(&residual).map(|(w, r)| *w * *r).sum())
            .collect();
        let mut f = f0;
        for (row, yi) in self.rows.iter().zip(&y) {
            for &(p, c) in row {
                if self.free_of[p] != usize::MAX {
                    f[self.free_of[p]] += c * *yi;
                }
            }
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
