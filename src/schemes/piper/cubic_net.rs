//! Steps 1–4 of [Piper87 §3.8]: the candidate cubic net of a face from its corners and vertex
//! normals, its split at the centroid into three cubic sub-nets, the centre-point adjustment
//! between the sub-nets of two faces that share an edge, and the elevation to degree four.
//!
//! Nets are fixed-size arrays in the module order of [`crate::bezier::triangle`]
//! (`b(i,j,k)`, i from d down to 0, then j from d−i down to 0).

use glam::DVec3;

use crate::bezier::TriangleBezier;
use crate::bezier::hermite2d::tangent_length;
use crate::bezier::triangle::index;

/// A cubic control net (10 points).
pub(crate) type Cubic = [DVec3; 10];
/// A quartic control net (15 points).
pub(crate) type Quartic = [DVec3; 15];

/// How far the boundary control point next to a vertex sits along the projected edge
/// (`--param scaling=…`). `b210 = b300 + s (q − b300)` with `q` the other end of the edge
/// projected into the tangent plane at `b300` [Piper87 §3.8 step 1].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum EdgeScaling {
    /// Farin's 2-D rule [Piper87 eqs. 3–4] in the plane of the chord and the projected edge:
    /// the point projects onto the chord at its first third when the angle between chord and
    /// tangent plane is at most 60°, else the leg is ⅔ of the chord. Invariant under
    /// similarities (rotation, translation, uniform scale), reproduces planes with a
    /// uniform parametrisation, and never crosses.
    Farin,
    /// The leg length of the cubic that best matches a circular arc with these end tangents:
    /// `‖leg‖ = 2‖chord‖ / (3(1 + cos Θ))`, the classical `(4/3) R tan(φ/4)` written in the chord
    /// and the angle Θ between chord and tangent plane. A third of the chord on flat data
    /// (planes reproduced with a uniform parametrisation), growing smoothly to ⅔ of it at 90°
    /// (where Farin's rule has already switched branches at 60°). Invariant under
    /// similarities; never crosses. The default.
    Circle,
    /// The thesis's factor with the distance measured in chord lengths:
    /// `s = 1/3 + ‖q − b300‖ / (9 ‖b030 − b300‖)`. Scale invariant; never crosses.
    Relative,
    /// The thesis's factor as printed, `s = 1/3 + ‖q − b300‖ / 9` [Piper87 §3.8 step 1], with
    /// `‖q − b300‖` in the mesh's units: the surface changes when the mesh is scaled.
    Thesis,
}

/// Step 1, one boundary point along `leg`, the chord `other − vertex` projected orthogonally
/// onto the curve's tangent directions at `vertex` (the tangent plane, `q − b300` of
/// [Piper87 §3.8 step 1]; on a sharp edge the crease line of [`crate::mesh::crease_tangent`]),
/// scaled by the rule `scaling`; `None` when the leg vanishes (the chord is across every
/// tangent direction).
///
/// The crossing guard [Piper87 §3.8 step 1, Fig. 15]: the two points of an edge cross when
/// they pass each other along the chord, which gives cusps. Whatever the scaling, the factor
/// is capped so that the point's projection onto the chord stays in the half of the edge next
/// to its vertex: then the two points of an edge can touch at the chord's midpoint but never
/// cross. Only [`EdgeScaling::Thesis`] can reach the cap (when `‖q − b300‖` is more than
/// 1.5 units); the other rules stay within the first third (`Farin`) or 4/9 (`Relative`).
pub(crate) fn edge_point_along(
    vertex: DVec3,
    leg: DVec3,
    other: DVec3,
    scaling: EdgeScaling,
    shorten: bool,
) -> Option<DVec3> {
    let chord_length = (other - vertex).length();
    let leg_length = leg.length();
    if leg_length <= 1e-9 * chord_length || !leg_length.is_finite() {
        return None;
    }
    // The angle between the chord and the tangent plane: cos Θ = ‖leg‖ / ‖chord‖.
    let cos_theta = leg_length / chord_length;
    let factor = match scaling {
        EdgeScaling::Farin => tangent_length(chord_length, cos_theta) / leg_length,
        EdgeScaling::Circle => 2.0 * chord_length / (3.0 * (1.0 + cos_theta)) / leg_length,
        EdgeScaling::Relative => 1.0 / 3.0 + cos_theta / 9.0,
        EdgeScaling::Thesis => 1.0 / 3.0 + leg_length / 9.0,
    };
    // A leg that swerves off its faces (see `swerving_legs` in mod.rs): no longer than the
    // relative rule's.
    let factor = if shorten {
        factor.min(1.0 / 3.0 + cos_theta / 9.0)
    } else {
        factor
    };
    // The leg is an orthogonal projection of the chord, so the chord projection of
    // factor·leg is factor·‖leg‖²/‖chord‖; keep it ≤ ‖chord‖/2.
    let crossing_cap = 0.5 / (cos_theta * cos_theta);
    Some(vertex + factor.min(crossing_cap) * leg)
}

/// Step 1 for one face: the candidate cubic net of corners `p` (face order, `b300 = p[0]`,
/// `b030 = p[1]`, `b003 = p[2]`) with unit corner normals `n` (a vertex's normal, or its
/// sector's at a vertex cut by sharp edges). Boundary points by [`edge_point_along`], the centre by
/// Farin's C⁰ rule [Piper87 §3.8 step 1]:
/// `b111 = ¼(b201 + b102 + b012 + b021 + b120 + b210) − ⅙(b300 + b030 + b003)`.
///
/// `creases[e]` is set for a sharp edge `e` (corner `e` → `e + 1`): the normals of the
/// neighbour's sectors at its two ends. Its points then leave each end along the crease
/// direction of the two sectors there ([`crate::mesh::crease_tangent`], the same for both
/// faces bit for bit), so the faces on either side build one boundary curve.
///
/// On error returns the corner `(from, to)` (indices 0..3 into the face) where the edge has
/// no tangent direction.
pub(crate) fn candidate_net(
    p: [DVec3; 3],
    n: [DVec3; 3],
    creases: [Option<[DVec3; 2]>; 3],
    shorten: [[bool; 2]; 3],
    scaling: EdgeScaling,
) -> Result<Cubic, (usize, usize)> {
    let point = |from: usize, to: usize| {
        // Edge e runs from corner e to corner e + 1; `from` is its end 0 or 1.
        let (e, end) = if to == (from + 1) % 3 {
            (from, 0)
        } else {
            (to, 1)
        };
        let chord = p[to] - p[from];
        let leg = match creases[e] {
            Some(other) => crate::mesh::crease_tangent(chord, n[from], other[end]),
            None => chord - chord.dot(n[from]) * n[from],
        };
        edge_point_along(p[from], leg, p[to], scaling, shorten[e][end]).ok_or((from, to))
    };
    let b210 = point(0, 1)?;
    let b120 = point(1, 0)?;
    let b021 = point(1, 2)?;
    let b012 = point(2, 1)?;
    let b102 = point(2, 0)?;
    let b201 = point(0, 2)?;
    let b111 = 0.25 * (b201 + b102 + b012 + b021 + b120 + b210) - (p[0] + p[1] + p[2]) / 6.0;
    let mut net = [DVec3::ZERO; 10];
    for (ijk, value) in [
        ((3, 0), p[0]),
        ((0, 3), p[1]),
        ((0, 0), p[2]),
        ((2, 1), b210),
        ((1, 2), b120),
        ((0, 2), b021),
        ((0, 1), b012),
        ((1, 0), b102),
        ((2, 0), b201),
        ((1, 1), b111),
    ] {
        net[index(3, ijk.0, ijk.1)] = value;
    }
    Ok(net)
}

/// Face-barycentric corners of piece `k` (0, 1, 2) of the Clough–Tocher split: face corner
/// `k`, face corner `k+1` and the centroid. The piece's edge 0 is the face's edge `k`
/// (`faces[f][k] → faces[f][k+1]`, the edge [`crate::mesh::Mesh::neighbor`] numbers `k`);
/// its edge 1 runs from corner `k+1` to the centroid, its edge 2 from the centroid to corner `k`.
pub(crate) fn piece_domain(k: usize) -> [DVec3; 3] {
    let unit = crate::surface::WHOLE_FACE;
    [unit[k], unit[(k + 1) % 3], DVec3::splat(1.0 / 3.0)]
}

/// Step 2: the candidate net split at the centroid into three cubic sub-nets, piece `k` over
/// [`piece_domain`]`(k)` [Piper87 §3.8 step 2, eq. 15].
///
/// Points that two pieces share are written once and copied, so that they agree bit for bit:
/// the outer row of piece `k` is the face net's edge `k` itself (subdivision leaves a
/// boundary curve's control points unchanged), the edge from corner `k` to the centroid is
/// copied from piece `k` into piece `k−1`, and the centroid point is the net's value there.
pub(crate) fn split_at_centroid(net: &Cubic) -> [Cubic; 3] {
    let patch = TriangleBezier::new(3, net.to_vec());
    let mut pieces = [[DVec3::ZERO; 10]; 3];
    for (k, piece) in pieces.iter_mut().enumerate() {
        piece.copy_from_slice(patch.subdivide(piece_domain(k)).offsets());
        for (l, &p) in patch.edge_curve(k).points().iter().enumerate() {
            piece[index(3, 3 - l, l)] = p;
        }
    }
    let centre = patch.eval(DVec3::splat(1.0 / 3.0));
    for k in 0..3 {
        let previous = (k + 2) % 3;
        // Corner k → centroid: j = 0 in piece k, i = 0 in piece k−1.
        for l in 0..3 {
            pieces[previous][index(3, 0, 3 - l)] = pieces[k][index(3, 3 - l, 0)];
        }
        pieces[k][index(3, 0, 0)] = centre;
    }
    pieces
}

/// Step 3 for one shared edge: the centre points `b111` of the two sub-nets on either side,
/// moved so that they and the two inner control points `s1, s2` of the common edge are
/// coplanar [Piper87 §3.8 step 3, Figs. 16–17].
///
/// `s1 → s2` runs in the direction of face P, whose sub-net centre is `centre_p` and whose
/// height over the common edge is `height_p`; Q the same on the other side.
///
/// The thesis projects each centre onto the plane through the edge and the other centre, and
/// scales the two displacements by `f` and `1 − f` with `f = h₁/(h₁ + h₂)` (the taller
/// triangle moves more, so small triangles are not distorted); it notes that the projected
/// points are not coplanar yet, and the scaled ones are coplanar only to first order in the
/// angle between the two planes. Here both centres are projected onto one plane through the
/// edge whose normal is the same height-weighted blend of the normals of the two planes
/// `(edge, centre)`: exactly coplanar, with the same weighting (P turns by about
/// `h_P/(h_P + h_Q)` of the angle).
///
/// Returns the centres unchanged when a centre lies on the edge line or the two planes'
/// normals cancel (a fold); step 5 makes the join G¹ regardless.
pub(crate) fn coplanar_centres(
    s1: DVec3,
    s2: DVec3,
    centre_p: DVec3,
    centre_q: DVec3,
    height_p: f64,
    height_q: f64,
) -> (DVec3, DVec3) {
    let along = s2 - s1;
    // Normals of the planes (edge, centre), both oriented like face P's normal (P lies to the
    // left of s1 → s2, Q to the right).
    let normal_p = along.cross(centre_p - s1);
    let normal_q = (centre_q - s1).cross(along);
    let tiny = |n: DVec3, c: DVec3| n.length() <= 1e-12 * along.length() * (c - s1).length();
    if tiny(normal_p, centre_p) || tiny(normal_q, centre_q) {
        return (centre_p, centre_q);
    }
    let blend = height_q * normal_p.normalize() + height_p * normal_q.normalize();
    if blend.length() <= 1e-12 * (height_p + height_q) {
        return (centre_p, centre_q);
    }
    let m = blend.normalize();
    let project = |c: DVec3| c - (c - s1).dot(m) * m;
    (project(centre_p), project(centre_q))
}

/// Step 4: a cubic sub-net as a quartic [Piper87 §3.6, §3.8 step 4].
pub(crate) fn elevate(net: &Cubic) -> Quartic {
    let elevated = TriangleBezier::new(3, net.to_vec()).elevate();
    let mut out = [DVec3::ZERO; 15];
    out.copy_from_slice(elevated.offsets());
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The control point next to `vertex` (unit normal `normal`) on
    /// the edge towards `other`, or `None` when the normal is along the edge (no tangent
    /// direction for it). [`edge_point_along`] with the chord projected into the tangent plane.
    fn edge_point(
        vertex: DVec3,
        normal: DVec3,
        other: DVec3,
        scaling: EdgeScaling,
    ) -> Option<DVec3> {
        let chord = other - vertex;
        edge_point_along(
            vertex,
            chord - chord.dot(normal) * normal,
            other,
            scaling,
            false,
        )
    }

    fn unit_sphere_face() -> ([DVec3; 3], [DVec3; 3]) {
        let p = [
            DVec3::new(1.0, 0.1, 0.2).normalize(),
            DVec3::new(0.1, 1.0, -0.1).normalize(),
            DVec3::new(0.2, 0.0, 1.0).normalize(),
        ];
        (p, p)
    }

    /// Corners interpolated, the two boundary points next to each corner in its tangent
    /// plane, and the centre point by Farin's rule.
    #[test]
    fn candidate_net_interpolates_and_is_tangent_at_the_corners() {
        let (p, n) = unit_sphere_face();
        for scaling in [
            EdgeScaling::Farin,
            EdgeScaling::Relative,
            EdgeScaling::Thesis,
        ] {
            let net =
                candidate_net(p, n, [None; 3], [[false; 2]; 3], scaling).expect("regular data");
            let patch = TriangleBezier::new(3, net.to_vec());
            for (c, (i, j)) in [(3, 0), (0, 3), (0, 0)].into_iter().enumerate() {
                assert_eq!(patch.point(i, j), p[c]);
            }
            for (corner, neighbours) in [
                (0, [(2, 1), (2, 0)]),
                (1, [(1, 2), (0, 2)]),
                (2, [(0, 1), (1, 0)]),
            ] {
                for (i, j) in neighbours {
                    let off_plane = (patch.point(i, j) - p[corner]).dot(n[corner]);
                    assert!(
                        off_plane.abs() <= 1e-15,
                        "{scaling:?} b({i},{j}): {off_plane}"
                    );
                }
            }
            let edge_sum: DVec3 = [(2, 1), (1, 2), (0, 2), (0, 1), (1, 0), (2, 0)]
                .iter()
                .map(|&(i, j)| patch.point(i, j))
                .sum();
            let expected = 0.25 * edge_sum - (p[0] + p[1] + p[2]) / 6.0;
            assert!((patch.point(1, 1) - expected).length() <= 1e-15);
        }
    }

    /// Farin's rule puts the point's chord projection at the first third (angles ≤ 60°); the
    /// thesis rule at `s‖leg‖²/‖chord‖` with `s = 1/3 + ‖leg‖/9`.
    #[test]
    fn edge_point_rules() {
        let (a, b) = (DVec3::ZERO, DVec3::new(1.2, 0.0, 0.4));
        let n = DVec3::Z;
        let chord = b - a;
        let farin = edge_point(a, n, b, EdgeScaling::Farin).unwrap();
        assert!((farin.dot(chord) / chord.length() - chord.length() / 3.0).abs() <= 1e-15);
        assert_eq!(farin.z, 0.0);
        // leg = (1.2, 0, 0), s = 1/3 + 1.2/9.
        let thesis = edge_point(a, n, b, EdgeScaling::Thesis).unwrap();
        let s = 1.0 / 3.0 + 1.2 / 9.0;
        assert!(
            (thesis - DVec3::new(1.2 * s, 0.0, 0.0)).length() <= 1e-15,
            "{thesis}"
        );
        // cos Θ = 3/√10.
        let relative = edge_point(a, n, b, EdgeScaling::Relative).unwrap();
        let s = 1.0 / 3.0 + 3.0 / 10f64.sqrt() / 9.0;
        assert!((relative - DVec3::new(1.2 * s, 0.0, 0.0)).length() <= 1e-15);
        // Three times longer, the thesis factor (2/3) would pass the midpoint: capped there.
        let thesis = edge_point(a, n, 3.0 * b, EdgeScaling::Thesis).unwrap();
        let along = thesis.dot(chord.normalize());
        assert!((along - 1.5 * chord.length()).abs() <= 1e-15, "{along}");
        // Normal along the edge: no tangent direction.
        assert!(edge_point(a, chord.normalize(), b, EdgeScaling::Farin).is_none());
    }

    /// On a large edge the thesis factor would carry the two points past each other (Fig. 15);
    /// the guard stops them at the chord's midpoint. Farin's rule never needs it.
    #[test]
    fn crossing_guard_keeps_the_edge_points_in_order() {
        let (a, b) = (DVec3::ZERO, DVec3::new(12.0, 0.0, 0.0));
        let (na, nb) = (
            DVec3::new(-0.3, 0.0, 1.0).normalize(),
            DVec3::new(0.3, 0.0, 1.0).normalize(),
        );
        for scaling in [
            EdgeScaling::Farin,
            EdgeScaling::Relative,
            EdgeScaling::Thesis,
        ] {
            let near_a = edge_point(a, na, b, scaling).unwrap();
            let near_b = edge_point(b, nb, a, scaling).unwrap();
            let (ta, tb) = (near_a.x / 12.0, near_b.x / 12.0);
            assert!(
                ta <= 0.5 + 1e-15 && tb >= 0.5 - 1e-15,
                "{scaling:?}: {ta} {tb}"
            );
        }
        // Unguarded, the thesis factor here is 1/3 + ‖leg‖/9 ≈ 1.52: far past the midpoint.
        let leg = 12.0 - 12.0 * 0.3 * 0.3 / 1.09;
        assert!((1.0 / 3.0 + leg / 9.0) * leg / 12.0 > 1.0);
    }

    /// The three sub-nets describe the same cubic as the candidate net over their domains,
    /// and their shared points agree bit for bit.
    #[test]
    fn split_reproduces_the_net_and_shares_points_exactly() {
        let (p, n) = unit_sphere_face();
        let net = candidate_net(p, n, [None; 3], [[false; 2]; 3], EdgeScaling::Farin).unwrap();
        let whole = TriangleBezier::new(3, net.to_vec());
        let pieces = split_at_centroid(&net);
        for (k, piece) in pieces.iter().enumerate() {
            let sub = TriangleBezier::new(3, piece.to_vec());
            let [c0, c1, c2] = piece_domain(k);
            for (u, v) in [(0.1, 0.2), (0.5, 0.3), (0.0, 0.6), (0.25, 0.75)] {
                let face_bary = (1.0 - u - v) * c0 + u * c1 + v * c2;
                let d = sub.eval(DVec3::new(1.0 - u - v, u, v)) - whole.eval(face_bary);
                assert!(d.length() <= 1e-15, "piece {k} at ({u},{v}): {d}");
            }
            let previous = &pieces[(k + 2) % 3];
            for l in 0..=3 {
                assert_eq!(piece[index(3, 3 - l, 0)], previous[index(3, 0, 3 - l)]);
            }
        }
    }

    /// After the adjustment the two centres and the edge points are coplanar; equal heights
    /// move both centres by the same amount, and the taller side moves more.
    #[test]
    fn centre_adjustment_makes_the_four_points_coplanar() {
        let (s1, s2) = (DVec3::ZERO, DVec3::X);
        let (cp, cq) = (DVec3::new(0.4, 1.0, 0.3), DVec3::new(0.6, -1.0, 0.1));
        for (hp, hq) in [(1.0, 1.0), (3.0, 1.0), (0.5, 2.0)] {
            let (np, nq) = coplanar_centres(s1, s2, cp, cq, hp, hq);
            let volume = (s2 - s1).cross(np - s1).dot(nq - s1);
            assert!(volume.abs() <= 1e-15, "not coplanar: {volume}");
            let (move_p, move_q) = ((np - cp).length(), (nq - cq).length());
            if hp == hq {
                assert!((move_p - move_q).abs() <= 0.2 * move_p.max(move_q));
            } else {
                assert_eq!(
                    hp > hq,
                    move_p > move_q,
                    "heights {hp}, {hq}: {move_p} {move_q}"
                );
            }
            // Points move only across the plane, not along the edge.
            assert!((np - cp).dot(s2 - s1).abs() <= 1e-15);
        }
    }
}
