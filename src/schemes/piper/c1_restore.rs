//! Step 5, inside a face [Piper87 §3.8 step 5, Fig. 20]: after the centre adjustment and the
//! G¹ solve have moved points next to the outer edges, the three quartic pieces of the
//! Clough–Tocher split are made C¹ again by resetting the points marked M, N and O.
//!
//! Piece `k` has corners `(a_k, a_{k+1}, c)`; its neighbour across the inner edge `a_k → c` is
//! piece `k−1` with corners `(a_{k−1}, a_k, c)`. Because `c` is the centroid,
//! `a_{k−1} = −a_k − a_{k+1} + 3c`, and the C¹ condition across that edge (Farin, *CAGD*
//! §17.9) reads, for every multi-index `(i, 0, l)` of degree three on the edge,
//!
//! `3 p(i, 0, l+1) = p(i+1, 0, l) + p(i, 1, l) + p'(…)`,
//!
//! with `p'` the point of piece `k−1` opposite `p(i, 1, l)`: each inner-edge point is the
//! centroid of the three points around it — the edge point before it and the two points
//! beside it. In order away from the vertex:
//!
//! * `(3,0,0)`: the point next to the vertex, `R0`, is already right: it, the vertex and the
//!   two outer-edge points beside it are the one candidate cubic split at the centroid, and
//!   steps 3–5 do not move them;
//! * `(2,0,1)` → **M** `= (R0 + R1 + R2')/3`, from points the G¹ solve set;
//! * `(1,0,2)` → **N** `= (M + p(1,1,2) + p'(1,1,2))/3`, from M and the pieces' free inner points;
//! * `(0,0,3)` → **O** `= (N_0 + N_1 + N_2)/3`, the common centre point.
//!
//! M before N before O, as the thesis says. None of these points is in the two rows next to
//! an outer edge, so the G¹ joins between faces are untouched.

use glam::DVec3;

use crate::bezier::triangle::index;
use crate::schemes::piper::cubic_net::Quartic;

/// Resets M, N, O of the three quartic pieces of one face (piece `k` over
/// [`crate::schemes::piper::cubic_net::piece_domain`]`(k)`) so that they join C¹, and writes
/// every inner-edge point into both pieces that share it, bit for bit.
pub(crate) fn restore_c1(pieces: &mut [Quartic; 3]) {
    let at = |i: usize, j: usize| index(4, i, j);
    let previous = |k: usize| (k + 2) % 3;
    // Edge a_k → c: j = 0 in piece k (p(4−l, 0, l)), i = 0 in piece k−1 (p(0, 4−l, l)).
    let mut m = [DVec3::ZERO; 3];
    for (k, mk) in m.iter_mut().enumerate() {
        let (own, other) = (&pieces[k], &pieces[previous(k)]);
        *mk = (own[at(3, 0)] + own[at(2, 1)] + other[at(1, 2)]) / 3.0;
    }
    let mut n = [DVec3::ZERO; 3];
    for (k, nk) in n.iter_mut().enumerate() {
        let (own, other) = (&pieces[k], &pieces[previous(k)]);
        *nk = (m[k] + own[at(1, 1)] + other[at(1, 1)]) / 3.0;
    }
    let o = (n[0] + n[1] + n[2]) / 3.0;
    for k in 0..3 {
        let vertex = pieces[k][at(4, 0)];
        let next_to_vertex = pieces[k][at(3, 0)];
        let edge = [vertex, next_to_vertex, m[k], n[k], o];
        for (l, &p) in edge.iter().enumerate() {
            pieces[k][at(4 - l, 0)] = p;
            pieces[previous(k)][at(0, 4 - l)] = p;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bezier::TriangleBezier;
    use crate::schemes::piper::cubic_net::piece_domain;

    /// Pieces that come from one quartic are C¹ already: restoring changes nothing (to
    /// rounding). Pieces with perturbed interior points become C¹: the three pieces then
    /// have equal first derivatives (as maps of the face's barycentric coordinates) all along
    /// each inner edge.
    #[test]
    fn restores_c1_across_the_inner_edges() {
        let quartic = TriangleBezier::from_fn(4, |i, j, k| {
            let (x, y, z) = (i as f64, j as f64, k as f64);
            DVec3::new(x + 0.3 * y * y, y - 0.2 * x * z, (x * y + z).sin())
        });
        let split = |q: &TriangleBezier| -> [Quartic; 3] {
            std::array::from_fn(|k| {
                let mut out = [DVec3::ZERO; 15];
                out.copy_from_slice(q.subdivide(piece_domain(k)).offsets());
                out
            })
        };
        let mut pieces = split(&quartic);
        let before = pieces;
        restore_c1(&mut pieces);
        for (a, b) in before.iter().flatten().zip(pieces.iter().flatten()) {
            assert!((*a - *b).length() <= 1e-13, "{a} vs {b}");
        }
        // Move the points the G¹ solve and the centre adjustment may move.
        for (k, piece) in pieces.iter_mut().enumerate() {
            for (i, j) in [(2, 1), (1, 2), (1, 1), (2, 0), (1, 0), (0, 0)] {
                piece[index(4, i, j)] += DVec3::new(0.1 * k as f64, -0.05, 0.07 * (i + j) as f64);
            }
        }
        restore_c1(&mut pieces);
        let patches: Vec<TriangleBezier> = pieces
            .iter()
            .map(|p| TriangleBezier::new(4, p.to_vec()))
            .collect();
        for k in 0..3 {
            let (own, other) = (&patches[k], &patches[(k + 2) % 3]);
            for step in 0..=8 {
                let s = step as f64 / 8.0;
                // Edge a_k → c: (u, v) = (0, s) in piece k, (1 − s, s) in piece k−1.
                let (ja, jb) = (own.jet(0.0, s), other.jet(1.0 - s, s));
                assert!((ja.p - jb.p).length() <= 1e-14, "piece {k}: gap at {s}");
                // Compare derivatives along d_c = c − a_k and d_next = a_{k+1} − a_k. In
                // piece k these are ∂v and ∂u. In piece k−1 (corners a_{k−1}, a_k, c),
                // d_c = (c − a_{k−1}) − (a_k − a_{k−1}) = ∂v − ∂u, and since
                // a_{k+1} = 3c − a_k − a_{k−1}, d_next = 3(c − a_{k−1}) − 2(a_k − a_{k−1}).
                let other_dc = jb.dv - jb.du;
                let other_dnext = 3.0 * jb.dv - 2.0 * jb.du;
                let cross_a = ja.du;
                assert!(
                    (ja.dv - other_dc).length() <= 1e-12,
                    "piece {k}: along-edge derivative"
                );
                assert!(
                    (cross_a - other_dnext).length() <= 1e-12,
                    "piece {k}: cross derivative at {s}: {cross_a} vs {other_dnext}"
                );
            }
        }
    }
}
