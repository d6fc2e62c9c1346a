//! One HB00 macro-patch in Bézier form [HB00 §8]: four quintic triangles over the 4-split of a
//! mesh face, joined C¹ inside the face.
//!
//! Pieces (corners given in face-barycentric coordinates, `a_k` the face corners, `m_kl` the edge
//! midpoints): piece k ∈ {0,1,2} is the corner triangle `[a_k, m_{k,k+1}, m_{k+2,k}]`, piece 3 the
//! middle triangle `[m_12, m_20, m_01]`.
//!
//! Step 1 [HB00 eqs. 24–33]: the two macro-edge rows of each corner piece. The boundary row is
//! the cubic curve piece degree-elevated twice (eq. 30); the first inner row comes from the
//! cross-boundary derivative `Φ E' ± Ψ V` (eq. 25), a cubic on each half edge, elevated to a
//! quartic and matched with the quintic's cross derivative (eq. 31). The printed result (eqs.
//! 32, 33) is this computation expanded; it is computed here from its definition instead of being
//! transcribed from the OCR text.
//!
//! Step 2 [HB00 §8.3, Fig. 13]: C¹ fill. Along the inner edge between corner piece k and the middle
//! piece, with edge points `e_0..e_5` (from `m_{k,k+1}` to `m_{k+2,k}`), corner-piece row `c_0..c_4`
//! and middle-piece row `d_0..d_4`, C¹ holds iff `c_m + d_m = e_m + e_{m+1}` (Fig. 12). m = 0 and
//! m = 4 hold by construction (§8.3: the six points around a macro-edge midpoint form an affine
//! regular hexagon). The rest: (a) choose the middle piece's three twists `T_c` — free;
//! (b) `e_2 = T + c_1 − e_1`, `e_3 = T' + c_3 − e_4`; (c) choose the three points `D_k` of the middle
//! piece — free; (d) `c_2 = e_2 + e_3 − D_k`. So six points per face are free ([`FreeRule`]).

use std::sync::OnceLock;

use glam::DVec3;

use crate::bezier::triangle::index;

/// Number of control points of a quintic triangle.
pub(crate) const QUINTIC: usize = 21;

/// The quintic control nets of the four pieces (corner pieces 0, 1, 2, then the middle).
pub(crate) type MacroNets = [[DVec3; QUINTIC]; 4];

/// Everything about one half of a macro edge, `X → m_XY`, in the orientation of `X`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct HalfEdgeCurve {
    /// Cubic boundary piece `b0..b3` on `[0, ½]` (b3 is the edge midpoint, eq. 16).
    pub b: [DVec3; 4],
    /// Quadratic piece `v0, v1, v2` of the cross-boundary function `V` on `[0, ½]` (eq. 27).
    pub v: [DVec3; 3],
    /// `Φ(0) = cos(2π/n_X)`; `Φ(½) = ½` (eq. 28).
    pub phi0: f64,
    /// `Ψ(0)` and `Ψ(½)` (eq. 29, linear over the whole edge).
    pub psi: [f64; 2],
}

/// How the six free control points of a macro-patch are chosen (`--param free=…`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum FreeRule {
    /// Minimise the thin-plate energy `∫ |S_xx|² + 2|S_xy|² + |S_yy|²` of the macro-patch over an
    /// equilateral domain (HB00 §9, colour plate). Affine invariant; one constant 6 × 84 linear map.
    Energy,
    /// Middle-piece twists by the parallelogram rule at each corner (zero twist in the piece's
    /// own corner coordinates), `D_k` the midpoint of its two neighbouring twists.
    ZeroTwist,
}

/// The face-barycentric corners of the four pieces (see the module doc).
pub(crate) fn piece_domains() -> [[DVec3; 3]; 4] {
    let a = crate::surface::WHOLE_FACE;
    let m = |k: usize, l: usize| 0.5 * (a[k] + a[l]);
    [
        [a[0], m(0, 1), m(2, 0)],
        [a[1], m(1, 2), m(0, 1)],
        [a[2], m(2, 0), m(1, 2)],
        [m(1, 2), m(2, 0), m(0, 1)],
    ]
}

/// Index of `b(i,j,k)` of a quintic.
fn q(i: usize, j: usize) -> usize {
    index(5, i, j)
}

/// Index in the middle piece of the point with weight `w[r]` at middle corner `(k + r) % 3`.
/// Middle corner c is the midpoint opposite face corner c.
fn mid(k: usize, w: [usize; 3]) -> usize {
    let mut at = [0; 3];
    for r in 0..3 {
        at[(k + r) % 3] = w[r];
    }
    q(at[0], at[1])
}

/// Product of a linear and a quadratic Bernstein polynomial (cubic Bernstein coefficients).
fn linear_times_quadratic(a: [f64; 2], b: [DVec3; 3]) -> [DVec3; 4] {
    [
        a[0] * b[0],
        (a[1] * b[0] + 2.0 * a[0] * b[1]) / 3.0,
        (2.0 * a[1] * b[1] + a[0] * b[2]) / 3.0,
        a[1] * b[2],
    ]
}

/// Cross-boundary derivative `Φ E' + sign Ψ V` on a half edge (eq. 25), as a quartic in the
/// half-edge parameter `s = 2u`.
fn cross_derivative(h: &HalfEdgeCurve, sign: f64) -> [DVec3; 5] {
    let b = h.b;
    let tangent = [
        6.0 * (b[1] - b[0]),
        6.0 * (b[2] - b[1]),
        6.0 * (b[3] - b[2]),
    ];
    let phi_e = linear_times_quadratic([h.phi0, 0.5], tangent);
    let psi_v = linear_times_quadratic(h.psi, h.v);
    let c: [DVec3; 4] = std::array::from_fn(|m| phi_e[m] + sign * psi_v[m]);
    std::array::from_fn(|j| {
        let t = j as f64 / 4.0;
        let lo = if j > 0 { c[j - 1] } else { DVec3::ZERO };
        let hi = if j < 4 { c[j] } else { DVec3::ZERO };
        t * lo + (1.0 - t) * hi
    })
}

/// The quintic form of a cubic piece (eq. 30).
fn elevate_cubic_to_quintic(b: [DVec3; 4]) -> [DVec3; 6] {
    [
        b[0],
        0.4 * b[0] + 0.6 * b[1],
        0.1 * b[0] + 0.6 * b[1] + 0.3 * b[2],
        0.3 * b[1] + 0.6 * b[2] + 0.1 * b[3],
        0.6 * b[2] + 0.4 * b[3],
        b[3],
    ]
}

/// Builds the four quintic nets of a macro-patch. `corners[k] = (X→Y, X→Z)` for face corner
/// `X = a_k`, `Y = a_{k+1}`, `Z = a_{k+2}`.
pub(crate) fn macro_patch(
    corners: &[(HalfEdgeCurve, HalfEdgeCurve); 3],
    free: FreeRule,
) -> MacroNets {
    let mut nets = [[DVec3::ZERO; QUINTIC]; 4];
    for (k, (to_y, to_z)) in corners.iter().enumerate() {
        corner_rows(&mut nets[k], to_y, to_z);
    }
    copy_known_middle_edge_points(&mut nets);
    let (twists, d_points) = match free {
        FreeRule::ZeroTwist => zero_twist_free_points(&nets),
        FreeRule::Energy => {
            let mut trial = nets;
            complete(&mut trial, [DVec3::ZERO; 3], [DVec3::ZERO; 3]);
            energy_free_points(&trial)
        }
    };
    complete(&mut nets, twists, d_points);
    nets
}

/// Step 1: boundary rows and first inner rows of corner piece `net` at `X` (j runs towards
/// `m_XY`, k towards `m_ZX`). The twist point b(3,1,1) lies in both inner rows; the two values
/// agree because the twists solve (II_T) — they are averaged to be symmetric in rounding.
fn corner_rows(net: &mut [DVec3; QUINTIC], to_y: &HalfEdgeCurve, to_z: &HalfEdgeCurve) {
    let (edge_y, edge_z) = (
        elevate_cubic_to_quintic(to_y.b),
        elevate_cubic_to_quintic(to_z.b),
    );
    // Face (X, Y, Z) is the "+" side of X→Y and the "−" side of X→Z (eq. 18). A corner piece
    // covers half the macro domain in each direction, so its cross derivative is ½ D, and the
    // quintic's first row is b + (1/5)(½ D) (eq. 31).
    let (cross_y, cross_z) = (cross_derivative(to_y, 1.0), cross_derivative(to_z, -1.0));
    for m in 0..6 {
        net[q(5 - m, m)] = edge_y[m];
        net[q(5 - m, 0)] = edge_z[m];
    }
    // m = 0 of each inner row is a boundary point of the other edge (kept from the curve, so
    // that neighbouring faces share it exactly); m = 1 is the twist point.
    for m in 2..5 {
        net[q(4 - m, m)] = edge_y[m] + cross_y[m] / 10.0;
        net[q(4 - m, 1)] = edge_z[m] + cross_z[m] / 10.0;
    }
    let twist_from_y = edge_y[1] + cross_y[1] / 10.0;
    let twist_from_z = edge_z[1] + cross_z[1] / 10.0;
    net[q(3, 1)] = 0.5 * (twist_from_y + twist_from_z);
}

/// The middle piece's corners and the edge points next to them come from the corner pieces.
fn copy_known_middle_edge_points(nets: &mut MacroNets) {
    for k in 0..3 {
        let corner = nets[k];
        // Inner edge of corner piece k, e_m = P_k(0, 5−m, m), runs from m_{k,k+1} (middle
        // corner k+2) to m_{k+2,k} (middle corner k+1).
        for m in [0, 1, 4, 5] {
            nets[3][mid(k, [0, m, 5 - m])] = corner[q(0, 5 - m)];
        }
    }
}

/// Step 2 (b) and (d), given the free points: middle twists `twists[c]` at middle corner c and
/// `d_points[k]`, the middle point with weight 1 at middle corner k and 2, 2 elsewhere.
fn complete(nets: &mut MacroNets, twists: [DVec3; 3], d_points: [DVec3; 3]) {
    for c in 0..3 {
        nets[3][mid(c, [3, 1, 1])] = twists[c];
        nets[3][mid(c, [1, 2, 2])] = d_points[c];
    }
    for k in 0..3 {
        let p = nets[k];
        let (e1, e4) = (p[q(0, 4)], p[q(0, 1)]);
        let (c1, c3) = (p[q(1, 3)], p[q(1, 1)]);
        let e2 = twists[(k + 2) % 3] + c1 - e1;
        let e3 = twists[(k + 1) % 3] + c3 - e4;
        let c2 = e2 + e3 - d_points[k];
        nets[k][q(0, 3)] = e2;
        nets[k][q(0, 2)] = e3;
        nets[k][q(1, 2)] = c2;
        nets[3][mid(k, [0, 2, 3])] = e2;
        nets[3][mid(k, [0, 3, 2])] = e3;
    }
}

/// [`FreeRule::ZeroTwist`]: parallelogram twists at the middle corners, `D_k` halfway between the
/// two twists of its row.
fn zero_twist_free_points(nets: &MacroNets) -> ([DVec3; 3], [DVec3; 3]) {
    let m = &nets[3];
    let twists: [DVec3; 3] =
        std::array::from_fn(|c| m[mid(c, [4, 1, 0])] + m[mid(c, [4, 0, 1])] - m[mid(c, [5, 0, 0])]);
    let d = std::array::from_fn(|k| 0.5 * (twists[(k + 1) % 3] + twists[(k + 2) % 3]));
    (twists, d)
}

/// [`FreeRule::Energy`]: the control points are affine in the six free points,
/// `P = P0 + G f`, so the minimiser of `Pᵀ Q P` is `f = −(GᵀQG)⁻¹ GᵀQ P0 = L P0`, with `L` a
/// constant 6 × 84 matrix ([`energy_map`]). `trial` is the net completed with `f = 0`.
fn energy_free_points(trial: &MacroNets) -> ([DVec3; 3], [DVec3; 3]) {
    let map = energy_map();
    let free: [DVec3; 6] = std::array::from_fn(|r| {
        let mut acc = DVec3::ZERO;
        for (piece, net) in trial.iter().enumerate() {
            for (i, p) in net.iter().enumerate() {
                acc += map[r][piece * QUINTIC + i] * *p;
            }
        }
        acc
    });
    ([free[0], free[1], free[2]], [free[3], free[4], free[5]])
}

/// The constant map `L` of [`energy_free_points`], computed once.
fn energy_map() -> &'static [[f64; 4 * QUINTIC]; 6] {
    static MAP: OnceLock<[[f64; 4 * QUINTIC]; 6]> = OnceLock::new();
    MAP.get_or_init(|| super::energy::free_point_map(&free_point_columns(), &piece_domains()))
}

/// `G`: column r is the (x component of the) net produced by free point r = unit x and
/// everything else zero. Used to build the energy map.
pub(super) fn free_point_columns() -> [[f64; 4 * QUINTIC]; 6] {
    std::array::from_fn(|r| {
        let mut nets = [[DVec3::ZERO; QUINTIC]; 4];
        let mut t = [DVec3::ZERO; 3];
        let mut d = [DVec3::ZERO; 3];
        if r < 3 {
            t[r] = DVec3::X;
        } else {
            d[r - 3] = DVec3::X;
        }
        complete(&mut nets, t, d);
        std::array::from_fn(|i| nets[i / QUINTIC][i % QUINTIC].x)
    })
}

/// Test-only items: used by the unit tests of this and other modules, compiled only for them.
#[cfg(test)]
pub(crate) mod test_support {
    use super::*;

    /// How far the two computations of the points shared by a corner piece's two inner rows
    /// disagree: the twist b(3,1,1) from either edge, and b(4,0,1), b(4,1,0) from the cross
    /// derivative versus the boundary curve (eq. 19). Zero up to rounding when (II_T) and (19) hold.
    pub(crate) fn corner_mismatch(to_y: &HalfEdgeCurve, to_z: &HalfEdgeCurve) -> f64 {
        let (edge_y, edge_z) = (
            elevate_cubic_to_quintic(to_y.b),
            elevate_cubic_to_quintic(to_z.b),
        );
        let (cross_y, cross_z) = (cross_derivative(to_y, 1.0), cross_derivative(to_z, -1.0));
        let twist = (edge_y[1] + cross_y[1] / 10.0) - (edge_z[1] + cross_z[1] / 10.0);
        let b401 = (edge_y[0] + cross_y[0] / 10.0) - edge_z[1];
        let b410 = (edge_z[0] + cross_z[0] / 10.0) - edge_y[1];
        twist.length().max(b401.length()).max(b410.length())
    }
}

#[cfg(test)]
mod tests {
    use glam::{DMat2, DVec2, DVec3};

    use super::*;
    use crate::bezier::TriangleBezier;
    use crate::schemes::vertex_rings::FaceFrame;
    use crate::testing::{closed_test_meshes, params};

    /// Gauss–Legendre nodes and weights of 5 points on [0, 1] (exact to degree 9).
    fn gauss5() -> [(f64, f64); 5] {
        let nodes = [
            (0.0, 0.568_888_888_888_888_9),
            (0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
            (-0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
            (0.906_179_845_938_664, 0.236_926_885_056_189_1),
            (-0.906_179_845_938_664, 0.236_926_885_056_189_1),
        ];
        nodes.map(|(x, w)| (0.5 * (x + 1.0), 0.5 * w))
    }

    /// The thin-plate energy `Σ ∫ |S_xx|² + 2|S_xy|² + |S_yy|²` of the four pieces over the
    /// equilateral face of side 1, by quadrature of the evaluated second derivatives (exact: the
    /// integrand has degree 6, the collapsed-square rule below is exact to degree 9 in each
    /// variable). Independent of the Gram matrices the construction uses.
    fn thin_plate_energy(nets: &MacroNets) -> f64 {
        let equilateral = [
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(0.5, 3f64.sqrt() / 2.0),
        ];
        let to_2d = |b: DVec3| b.x * equilateral[0] + b.y * equilateral[1] + b.z * equilateral[2];
        let mut energy = 0.0;
        for (net, domain) in nets.iter().zip(piece_domains()) {
            let patch = TriangleBezier::new(5, net.to_vec());
            let corners = domain.map(to_2d);
            let a = DMat2::from_cols(corners[1] - corners[0], corners[2] - corners[0]);
            let a_inv = a.inverse();
            let jacobian = a.determinant().abs();
            for (x, wx) in gauss5() {
                for (s, ws) in gauss5() {
                    let (u, v) = (x, (1.0 - x) * s);
                    let jet = patch.jet(u, v);
                    for axis in 0..3 {
                        let h = DMat2::from_cols(
                            DVec2::new(jet.duu[axis], jet.duv[axis]),
                            DVec2::new(jet.duv[axis], jet.dvv[axis]),
                        );
                        let hx = a_inv.transpose() * h * a_inv;
                        let norm2 = hx.x_axis.length_squared() + hx.y_axis.length_squared();
                        energy += wx * ws * (1.0 - x) * jacobian * norm2;
                    }
                }
            }
        }
        energy
    }

    /// The free points `free=energy` picks minimise the thin-plate energy: measured
    /// independently by quadrature, the energy's derivative along each of the 18 free
    /// coordinates vanishes and its second derivative is positive, on every face of every
    /// closed test mesh. The displacement to the true minimiser, `|gradient / curvature|`, is
    /// at most 1e-9 of the face size; zero-twist's points, which do not minimise, have more
    /// energy.
    #[test]
    fn energy_rule_picks_the_thin_plate_minimiser() {
        for (name, mesh) in closed_test_meshes() {
            let (shape, _) = super::super::shape_params(&params(&super::super::SPEC, &[]))
                .expect("default parameters");
            let table = super::super::half_edge_table(&mesh, &shape).expect("pass 1");
            for (f, face) in mesh.faces().iter().enumerate().step_by(7) {
                let frame = FaceFrame::of(mesh.positions(), *face);
                let corners = super::super::face_corner_curves(&table, *face, f, shape.psi, &frame);
                let nets = macro_patch(&corners, FreeRule::Energy);
                let [p0, p1, p2] = frame.corners;
                let size = p0.distance(p1).max(p1.distance(p2)).max(p2.distance(p0));
                let twists: [DVec3; 3] = std::array::from_fn(|c| nets[3][mid(c, [3, 1, 1])]);
                let d: [DVec3; 3] = std::array::from_fn(|k| nets[3][mid(k, [1, 2, 2])]);
                let e0 = thin_plate_energy(&nets);
                for r in 0..6 {
                    for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
                        let energy_at = |step: f64| {
                            let (mut t, mut dd) = (twists, d);
                            if r < 3 {
                                t[r] += step * axis;
                            } else {
                                dd[r - 3] += step * axis;
                            }
                            let mut moved = nets;
                            complete(&mut moved, t, dd);
                            thin_plate_energy(&moved)
                        };
                        let (plus, minus) = (energy_at(size), energy_at(-size));
                        let gradient = (plus - minus) / (2.0 * size);
                        let curvature = (plus + minus - 2.0 * e0) / (size * size);
                        assert!(curvature > 0.0, "{name} face {f} point {r}: {curvature}");
                        let offset = (gradient / curvature).abs() / size;
                        assert!(
                            offset <= 1e-9,
                            "{name} face {f} point {r}: minimiser {offset} of the face away"
                        );
                    }
                }
                let zero_twist = thin_plate_energy(&macro_patch(&corners, FreeRule::ZeroTwist));
                assert!(zero_twist >= e0, "{name} face {f}: {zero_twist} < {e0}");
            }
        }
    }
}
