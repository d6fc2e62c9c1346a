//! Box and half-box splines over the three-directional grid in exact Bézier form [UP §2, §3].
//!
//! The grid has directions `v1 = (1,0)`, `v2 = (0,1)`, `v3 = (1,1)`; its triangles are
//! `Δ(i,j) = {(i,j), (i+1,j), (i+1,j+1)}` and `∇(i,j) = {(i,j), (i+1,j+1), (i,j+1)}`, both
//! counter-clockwise, with their corners in that order.
//!
//! The splines are built exactly as the paper defines them: starting from the hat function
//! `N_1` (the Courant element, value 1 at `(1,1)`, support `V·[0,1]³`) or from the indicator
//! functions `H_1^Δ`, `H_1^∇` of `Δ(0,0)`, `∇(0,0)`, each step of
//! `N_m = ∫_{[0,1]³} N_{m−1}(u − V t) dt` is three directional integrations
//! `g(x) = ∫_0^1 f(x − t v) dt`, one per direction `v`. One such integration is carried out on
//! the Bézier nets of the pieces: with `I(x) = ∫_0^∞ f(x − t v) dt` we have `D_v I = f` and
//! `g = I − I(· − v)`. On a triangle whose edge from corner `a` to corner `b` is `v`, the
//! derivative of a degree-`(d+1)` net is `D_v I = (d+1) Σ_α (c_{α+e_b} − c_{α+e_a}) B^d_α`
//! (Farin, CAGD §17.5), so `c_{α+e_b} = c_{α+e_a} + f_α/(d+1)`, started from the values of `I`
//! on the edge `a–c`, which `I` shares with the upstream neighbour (`I` is continuous across
//! every grid line that is not parallel to `v`). Triangles are processed in the order of their
//! centroids along `v`, so the upstream neighbour is always done first.
//!
//! All coefficients are kept as integers over one common denominator (each integration
//! multiplies it by the new degree), so the Bézier nets are exact: no table is typed in for
//! any `k`, and the k = 2 net is Loop's quartic box-spline net digit for digit.
//!
//! Smoothness orders and degrees [UP §2, §3]: `N_m` has `k = 2(m−1)`, `d = 3m − 2`;
//! `H_m^{Δ,∇}` have `k = 2m − 3`, `d = 3(m−1)`.

use std::collections::{BTreeMap, HashMap};
use std::sync::{Arc, Mutex, OnceLock};

use crate::bezier::gram::multi_indices;

/// A triangle of the three-directional grid.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) struct GridTriangle {
    /// First lattice coordinate of its first corner.
    pub i: i32,
    /// Second lattice coordinate of its first corner.
    pub j: i32,
    /// True for `Δ(i,j)`, false for `∇(i,j)`.
    pub up: bool,
}

impl GridTriangle {
    /// `Δ(0,0)`, the reference triangle of a patch.
    pub(crate) const UP: GridTriangle = GridTriangle {
        i: 0,
        j: 0,
        up: true,
    };
    /// `∇(0,0)`.
    pub(crate) const DOWN: GridTriangle = GridTriangle {
        i: 0,
        j: 0,
        up: false,
    };

    /// The three corners, counter-clockwise, in the order of the Bézier net's corners
    /// `b(d,0,0)`, `b(0,d,0)`, `b(0,0,d)`.
    pub(crate) fn corners(&self) -> [[i32; 2]; 3] {
        let (i, j) = (self.i, self.j);
        if self.up {
            [[i, j], [i + 1, j], [i + 1, j + 1]]
        } else {
            [[i, j], [i + 1, j + 1], [i, j + 1]]
        }
    }

    /// The same triangle moved by `offset`.
    pub(crate) fn translated(&self, offset: [i32; 2]) -> GridTriangle {
        GridTriangle {
            i: self.i + offset[0],
            j: self.j + offset[1],
            up: self.up,
        }
    }

    /// Three times its centroid (integers).
    fn centroid3(&self) -> [i32; 2] {
        let c = self.corners();
        [c[0][0] + c[1][0] + c[2][0], c[0][1] + c[1][1] + c[2][1]]
    }

    /// The six triangles that have `p` as a corner.
    fn around(p: [i32; 2]) -> [GridTriangle; 6] {
        let t = |i, j, up| GridTriangle { i, j, up };
        let [x, y] = p;
        [
            t(x, y, true),
            t(x, y, false),
            t(x - 1, y, true),
            t(x - 1, y - 1, true),
            t(x - 1, y - 1, false),
            t(x, y - 1, false),
        ]
    }

    /// The other triangle that has both `p` and `q` as corners (`p`, `q` adjacent corners).
    fn across(&self, p: [i32; 2], q: [i32; 2]) -> GridTriangle {
        GridTriangle::around(p)
            .into_iter()
            .find(|t| t != self && t.corners().contains(&q))
            .expect("every grid edge has two triangles")
    }
}

/// Hexagonal (grid) distance between two lattice points: the fewest steps along `±v1, ±v2, ±v3`.
pub(crate) fn grid_distance(p: [i32; 2], q: [i32; 2]) -> i32 {
    let (x, y) = (p[0] - q[0], p[1] - q[1]);
    if x * y >= 0 {
        x.abs().max(y.abs())
    } else {
        x.abs() + y.abs()
    }
}

/// The three grid directions `v1, v2, v3` [UP Fig. 2.1].
pub(crate) const DIRECTIONS: [[i32; 2]; 3] = [[1, 0], [0, 1], [1, 1]];

/// A piecewise polynomial over the grid: one Bézier net per triangle of its support, with
/// integer coefficients over a common denominator.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct GridSpline {
    /// Polynomial degree of every piece.
    pub degree: usize,
    /// The common denominator of all coefficients.
    pub denominator: i64,
    /// Bézier coefficient numerators per triangle, in the storage order of [`crate::bezier`].
    pub pieces: BTreeMap<GridTriangle, Vec<i64>>,
}

impl GridSpline {
    /// The hat function `N_1`: piecewise linear, 1 at `(1,1)`, 0 at every other lattice point.
    pub(crate) fn hat() -> GridSpline {
        let peak = [1, 1];
        let pieces = GridTriangle::around(peak)
            .into_iter()
            .map(|t| {
                let net = t.corners().map(|c| i64::from(c == peak)).to_vec();
                (t, net)
            })
            .collect();
        GridSpline {
            degree: 1,
            denominator: 1,
            pieces,
        }
    }

    /// The indicator function of one grid triangle (`H_1^Δ` or `H_1^∇` for `Δ(0,0)`, `∇(0,0)`).
    pub(crate) fn indicator(triangle: GridTriangle) -> GridSpline {
        GridSpline {
            degree: 0,
            denominator: 1,
            pieces: BTreeMap::from([(triangle, vec![1])]),
        }
    }

    /// `g(x) = ∫_0^1 f(x − t·direction) dt`, exactly (see the module doc).
    pub(crate) fn integrate(&self, direction: [i32; 2]) -> GridSpline {
        let d = self.degree;
        let high = multi_indices(d + 1);
        let position: HashMap<[usize; 3], usize> =
            high.iter().enumerate().map(|(n, a)| (*a, n)).collect();
        let low = multi_indices(d);
        let low_position: HashMap<[usize; 3], usize> =
            low.iter().enumerate().map(|(n, a)| (*a, n)).collect();

        // Window: the support grown by two triangles on every side.
        let (mut lo, mut hi) = ([i32::MAX; 2], [i32::MIN; 2]);
        for t in self.pieces.keys() {
            lo = [lo[0].min(t.i), lo[1].min(t.j)];
            hi = [hi[0].max(t.i), hi[1].max(t.j)];
        }
        let mut window: Vec<GridTriangle> = (lo[0] - 2..=hi[0] + 2)
            .flat_map(|i| {
                (lo[1] - 2..=hi[1] + 2)
                    .flat_map(move |j| [true, false].map(|up| GridTriangle { i, j, up }))
            })
            .collect();
        let along = |t: &GridTriangle| {
            let c = t.centroid3();
            c[0] * direction[0] + c[1] * direction[1]
        };
        window.sort_by_key(along);

        let mut ray: HashMap<GridTriangle, Vec<i64>> = HashMap::new();
        for t in &window {
            let corners = t.corners();
            // The edge a → b that runs along `direction`, and the third corner c.
            let (a, b) = (0..3)
                .flat_map(|a| (0..3).map(move |b| (a, b)))
                .find(|&(a, b)| {
                    a != b
                        && corners[b][0] - corners[a][0] == direction[0]
                        && corners[b][1] - corners[a][1] == direction[1]
                })
                .expect("every grid triangle has an edge along each grid direction");
            let c = 3 - a - b;
            let upstream = t.across(corners[a], corners[c]);
            let mut net = vec![0i64; high.len()];
            if let Some(up_net) = ray.get(&upstream) {
                // The upstream triangle's corner slots of our a and c.
                let uc = upstream.corners();
                let slot = |p: [i32; 2]| uc.iter().position(|&q| q == p).expect("shared corner");
                let (ua, uc_) = (slot(corners[a]), slot(corners[c]));
                for (n, beta) in high.iter().enumerate() {
                    if beta[b] == 0 {
                        let mut up_index = [0usize; 3];
                        up_index[ua] = beta[a];
                        up_index[uc_] = beta[c];
                        net[n] = up_net[position[&up_index]];
                    }
                }
            }
            let f = self.pieces.get(t);
            // Rows by increasing β_b: c_{α+e_b} = c_{α+e_a} + f_α (numerators over the new
            // denominator, which is the old one times d+1).
            for level in 1..=d + 1 {
                for (n, beta) in high.iter().enumerate() {
                    if beta[b] != level {
                        continue;
                    }
                    let mut alpha = *beta;
                    alpha[b] -= 1;
                    let mut from = alpha;
                    from[a] += 1;
                    let f_alpha = f.map_or(0, |f| f[low_position[&alpha]]);
                    net[n] = net[position[&from]] + f_alpha;
                }
            }
            ray.insert(*t, net);
        }

        let mut pieces = BTreeMap::new();
        for t in &window {
            let shifted = t.translated([-direction[0], -direction[1]]);
            let here = &ray[t];
            let net: Vec<i64> = match ray.get(&shifted) {
                Some(behind) => here.iter().zip(behind).map(|(x, y)| x - y).collect(),
                None => here.clone(),
            };
            if net.iter().any(|&x| x != 0) {
                pieces.insert(*t, net);
            }
        }
        GridSpline {
            degree: d + 1,
            denominator: self.denominator * (d as i64 + 1),
            pieces,
        }
    }

    /// One step of the paper's recursion: integration along `v1`, `v2`, `v3` in turn.
    pub(crate) fn convolve_with_box(&self) -> GridSpline {
        DIRECTIONS
            .iter()
            .fold(self.clone(), |s, &dir| s.integrate(dir))
    }
}

/// Which spline family a smoothness order uses, with its recursion index `m`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Family {
    /// Box spline `N_m`, even `k = 2(m−1)`, control points at net vertices.
    Box {
        /// Recursion index.
        m: usize,
    },
    /// Half-box splines `H_m^Δ`, `H_m^∇`, odd `k = 2m − 3`, control points at net faces
    /// (vertices of the hexagonal dual net).
    HalfBox {
        /// Recursion index.
        m: usize,
    },
}

impl Family {
    /// The family of smoothness order `k ≥ 1` [UP §2, §3].
    pub(crate) fn for_order(k: usize) -> Family {
        if k.is_multiple_of(2) {
            Family::Box { m: k / 2 + 1 }
        } else {
            Family::HalfBox { m: (k + 3) / 2 }
        }
    }

    /// Polynomial degree of a patch: `3m − 2` or `3(m − 1)`.
    pub(crate) fn degree(&self) -> usize {
        match *self {
            Family::Box { m } => 3 * m - 2,
            Family::HalfBox { m } => 3 * (m - 1),
        }
    }
}

/// Where a control point of a regular net sits on the grid.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) enum ControlSite {
    /// A net vertex at a lattice point (box splines).
    Vertex([i32; 2]),
    /// A vertex of the hexagonal net, dual to a grid triangle (half-box splines).
    Face(GridTriangle),
}

/// The Bézier net of one patch as a linear combination of the control points of its regular
/// subnet [UP Fig. 2.2]: `b_α = Σ_site weights[site][α] · c_site / denominator`.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct PatchStencil {
    /// Polynomial degree of the patch.
    pub degree: usize,
    /// Common denominator of the weights.
    pub denominator: i64,
    /// The subnet, in increasing site order, with the weight numerators of each Bézier point.
    pub entries: Vec<(ControlSite, Vec<i64>)>,
}

/// Reference stencils by (order, orientation).
type StencilCache = HashMap<(usize, bool), Arc<PatchStencil>>;

impl PatchStencil {
    /// The stencil over the reference triangle `Δ(0,0)` (`up`) or `∇(0,0)`, computed once per
    /// order and orientation (the derivation by repeated integration is the costly part of
    /// building small nets).
    pub(crate) fn reference(k: usize, up: bool) -> Arc<PatchStencil> {
        static CACHE: OnceLock<Mutex<StencilCache>> = OnceLock::new();
        let cache = CACHE.get_or_init(Default::default);
        let mut map = cache
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        map.entry((k, up))
            .or_insert_with(|| Arc::new(PatchStencil::new(k, GridTriangle { i: 0, j: 0, up })))
            .clone()
    }

    /// The stencil of the patch over grid triangle `target` for smoothness order `k`.
    ///
    /// Box splines: the control point at lattice point `p` weighs `N_m(x − p + (m,m))` (the
    /// centre of `N_m` is `(m,m)`). Half-box splines: the control point of grid triangle `F`
    /// weighs `H_m^{type F}(x − origin(F) + (m−1, m−1))`.
    pub(crate) fn new(k: usize, target: GridTriangle) -> PatchStencil {
        let mut entries = Vec::new();
        let family = Family::for_order(k);
        let spline_of =
            |start: GridSpline, steps: usize| (0..steps).fold(start, |s, _| s.convolve_with_box());
        let mut denominator = 1;
        match family {
            Family::Box { m } => {
                let spline = spline_of(GridSpline::hat(), m - 1);
                denominator = spline.denominator;
                let centre = m as i32;
                for (piece, net) in &spline.pieces {
                    if piece.up == target.up {
                        let p = [target.i + centre - piece.i, target.j + centre - piece.j];
                        entries.push((ControlSite::Vertex(p), net.clone()));
                    }
                }
            }
            Family::HalfBox { m } => {
                let shift = m as i32 - 1;
                for basis in [GridTriangle::UP, GridTriangle::DOWN] {
                    let spline = spline_of(GridSpline::indicator(basis), m - 1);
                    denominator = spline.denominator;
                    for (piece, net) in &spline.pieces {
                        if piece.up == target.up {
                            let face = GridTriangle {
                                i: target.i + shift - piece.i,
                                j: target.j + shift - piece.j,
                                up: basis.up,
                            };
                            entries.push((ControlSite::Face(face), net.clone()));
                        }
                    }
                }
            }
        }
        entries.sort_by_key(|e| e.0);
        PatchStencil {
            degree: family.degree(),
            denominator,
            entries,
        }
    }

    /// The Bézier net for control values looked up per site.
    pub(crate) fn apply<T>(&self, mut value: impl FnMut(ControlSite) -> T) -> Vec<T>
    where
        T: Copy + Default + std::ops::Add<Output = T> + std::ops::Mul<f64, Output = T>,
    {
        let count = self.entries.first().map_or(0, |e| e.1.len());
        let mut net = vec![T::default(); count];
        let scale = 1.0 / self.denominator as f64;
        for (site, weights) in &self.entries {
            let c = value(*site);
            for (b, &w) in net.iter_mut().zip(weights) {
                if w != 0 {
                    *b = *b + c * (w as f64 * scale);
                }
            }
        }
        net
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::bezier::TriangleBezier;
    use crate::schemes::gk::jets::lattice_jump;
    use crate::testing::Rng;

    /// Loop's quartic box-spline patch [issue 8]: the 12-point subnet numbered row by row
    /// 0 1 2 / 3 4 5 6 / 7 8 9 / 10 11, corners b400 = v4, b040 = v8, b004 = v5, ×1/24.
    const LOOP_K2: [[i64; 15]; 12] = [
        [2, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0],
        [2, 1, 3, 0, 1, 4, 0, 0, 1, 3, 0, 0, 0, 1, 2],
        [0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 2],
        [2, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0],
        [12, 12, 12, 8, 10, 8, 4, 6, 6, 4, 2, 3, 4, 3, 2],
        [2, 3, 4, 4, 6, 8, 3, 6, 10, 12, 2, 4, 8, 12, 12],
        [0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 2],
        [2, 3, 1, 4, 1, 0, 3, 1, 0, 0, 2, 1, 0, 0, 0],
        [2, 4, 3, 8, 6, 4, 12, 10, 6, 3, 12, 12, 8, 4, 2],
        [0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 3, 4, 3, 2],
        [0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0, 0],
        [0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 1, 0, 0, 0],
    ];

    /// Loop's points in a drawing with rows at y = 1, 0, −1, −2 and unit spacing, as
    /// (2x, y): v4 = (1,0), v8 = (1.5,−1), v5 = (2,0).
    const LOOP_DRAWING: [[i32; 2]; 12] = [
        [1, 1],
        [3, 1],
        [5, 1],
        [0, 0],
        [2, 0],
        [4, 0],
        [6, 0],
        [1, -1],
        [3, -1],
        [5, -1],
        [2, -2],
        [4, -2],
    ];

    /// The affine lattice map sending v4, v8, v5 to the corners (0,0), (1,0), (1,1) of Δ(0,0):
    /// with X − v4 = s(v8 − v4) + t(v5 − v4), the lattice point is (s + t, t).
    fn loop_to_lattice([x2, y]: [i32; 2]) -> [i32; 2] {
        let s = -y;
        let t2 = x2 - 2 + y; // 2t
        assert_eq!(t2 % 2, 0, "Loop's points are lattice points");
        let t = t2 / 2;
        [s + t, t]
    }

    #[test]
    fn k2_reproduces_loops_quartic_box_spline_net_exactly() {
        let stencil = PatchStencil::new(2, GridTriangle::UP);
        assert_eq!(stencil.degree, 4);
        assert_eq!(stencil.entries.len(), 12, "{:?}", stencil.entries);
        for (v, (drawn, row)) in LOOP_DRAWING.iter().zip(LOOP_K2).enumerate() {
            let site = ControlSite::Vertex(loop_to_lattice(*drawn));
            let (_, weights) = stencil
                .entries
                .iter()
                .find(|(s, _)| *s == site)
                .unwrap_or_else(|| panic!("v{v} at {site:?} is not in the subnet"));
            // Exact integer comparison: weights × 24 / denominator.
            for (n, (&w, &expected)) in weights.iter().zip(&row).enumerate() {
                assert_eq!(
                    w * 24,
                    expected * stencil.denominator,
                    "v{v}, Bézier point {n}"
                );
            }
        }
    }

    #[test]
    fn partition_of_unity_and_subnet_sizes() {
        for k in 1..=5 {
            for target in [GridTriangle::UP, GridTriangle::DOWN] {
                let stencil = PatchStencil::new(k, target);
                let expected_size = if k % 2 == 0 {
                    3 * (k + 2) * (k + 2) / 4
                } else {
                    (3 * k * k + 12 * k + 11) / 2
                };
                assert_eq!(stencil.entries.len(), expected_size, "k = {k} {target:?}");
                for n in 0..stencil.entries[0].1.len() {
                    let sum: i64 = stencil.entries.iter().map(|(_, w)| w[n]).sum();
                    assert_eq!(sum, stencil.denominator, "k = {k}, point {n}");
                    assert!(stencil.entries.iter().all(|(_, w)| w[n] >= 0));
                }
            }
        }
    }

    /// The subnet of a box-spline patch is every lattice point within grid distance k/2 of
    /// the triangle [UP Fig. 2.2]; a half-box patch's subnet is every triangle with a corner
    /// within grid distance (k−1)/2 of the target's corners.
    #[test]
    fn subnets_have_the_shape_of_fig_2_2() {
        let near = |p: [i32; 2], r: i32| {
            GridTriangle::UP
                .corners()
                .iter()
                .any(|&c| grid_distance(p, c) <= r)
        };
        for k in [2usize, 4] {
            for (site, _) in &PatchStencil::new(k, GridTriangle::UP).entries {
                let ControlSite::Vertex(p) = site else {
                    panic!("box splines have vertex sites")
                };
                assert!(near(*p, k as i32 / 2), "k = {k}: {p:?}");
            }
        }
        for k in [1usize, 3] {
            for (site, _) in &PatchStencil::new(k, GridTriangle::UP).entries {
                let ControlSite::Face(f) = site else {
                    panic!("half-box splines have face sites")
                };
                let touches = f.corners().iter().any(|&c| near(c, (k as i32 - 1) / 2));
                assert!(touches, "k = {k}: {f:?}");
            }
        }
    }

    /// Random control values on the grid: the patches over neighbouring triangles agree in
    /// every derivative of order ≤ k along their edge (to rounding), and not in order k+1.
    #[test]
    fn neighbouring_patches_join_with_exactly_c_k() {
        for k in 1..=4usize {
            let mut rng = Rng::new(17 + k as u64);
            let mut values: HashMap<ControlSite, DVec3> = HashMap::new();
            let mut value = |site: ControlSite| {
                *values
                    .entry(site)
                    .or_insert_with(|| DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64()))
            };
            let mut patch = |t: GridTriangle| {
                let stencil = PatchStencil::new(
                    k,
                    GridTriangle {
                        i: 0,
                        j: 0,
                        up: t.up,
                    },
                );
                // Translate the stencil's sites to the triangle.
                let net = stencil.apply(|site| {
                    value(match site {
                        ControlSite::Vertex(p) => ControlSite::Vertex([p[0] + t.i, p[1] + t.j]),
                        ControlSite::Face(f) => ControlSite::Face(f.translated([t.i, t.j])),
                    })
                });
                TriangleBezier::new(stencil.degree, net)
            };
            let centre = patch(GridTriangle::UP);
            let down = patch(GridTriangle::DOWN);
            // Δ(0,0) corners (0,0),(1,0),(1,1); ∇(0,0) corners (0,0),(1,1),(0,1); ∇(1,0)
            // corners (1,0),(2,1),(1,1); ∇(0,−1) corners (0,−1),(1,0),(0,0).
            let right = patch(GridTriangle {
                i: 1,
                j: 0,
                up: false,
            });
            let below = patch(GridTriangle {
                i: 0,
                j: -1,
                up: false,
            });
            let joints = [
                // Δ edge 2 (1,1)→(0,0) with ∇(0,0) edge 0 (0,0)→(1,1).
                (&centre, 2, &down, 0),
                // Δ edge 1 (1,0)→(1,1) with ∇(1,0) edge 2 (1,1)→(1,0).
                (&centre, 1, &right, 2),
                // Δ edge 0 (0,0)→(1,0) with ∇(0,−1) edge 1 (1,0)→(0,0).
                (&centre, 0, &below, 1),
            ];
            for (a, ea, b, eb) in joints {
                let jumps: Vec<f64> = (0..=k + 1)
                    .map(|order| lattice_jump(a, ea, b, eb, order))
                    .collect();
                let shown: Vec<String> = jumps.iter().map(|j| format!("{j:.1e}")).collect();
                eprintln!("k = {k}, edge {ea}: relative jumps by order {shown:?}");
                for (order, &jump) in jumps.iter().enumerate().take(k + 1) {
                    assert!(jump < 1e-12, "k = {k}, edge {ea}, order {order}: {jump:e}");
                }
                let jump = lattice_jump(a, ea, b, eb, k + 1);
                assert!(
                    jump > 1e-6,
                    "k = {k}, edge {ea}: order {} agrees ({jump:e})",
                    k + 1
                );
            }
        }
    }
}
