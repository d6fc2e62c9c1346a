//! Folded one-rings unfolded by edge flips.
//!
//! A one-ring whose faces fold over themselves — no direction sees them all from the front
//! side ([`super::front_facing`]), as at the crumpled spots of a scan — admits no surface
//! through its vertex without a fold: every scheme that interpolates the vertex with one
//! tangent plane turns over some face there. Often the fold is only in how the vertices are
//! joined: the two faces of one edge of the ring form a quadrilateral whose other diagonal
//! joins the same four vertices without folding. Such an edge is flipped (its two faces
//! `(a, b, c)` and `(b, a, d)` become `(a, d, c)` and `(d, b, c)`), when
//!
//! * `c` and `d` are not joined already (the mesh stays manifold, no edge is doubled),
//! * neither new face is a sliver (`2·area / longest edge² ≥` [`MIN_NEW_AREA_RATIO`]),
//! * fewer of the four corners' rings are folded after the flip, and none that was not.
//!
//! Among the flips that qualify at a vertex, the one that moves the surface least (the
//! smallest tetrahedron of the four corners relative to their span) is made. Vertices stay
//! where they are, so the surface still interpolates every one; only rings that fold change.

use std::collections::HashSet;

use glam::DVec3;

use super::front_facing::{FrontFacing, MIN_FRONT_MARGIN, front_facing_by};
use super::repair::area_ratio;
use super::topology::NO_TWIN;

/// The smallest `2·area / longest edge²` (about the sine of the smallest angle) of a face a
/// flip may make: a flip that unfolds a ring with a needle in its place is not made.
pub(super) const MIN_NEW_AREA_RATIO: f64 = 1e-3;

/// How often the folded rings are revisited: a flip can make a flip at a neighbour possible.
const PASSES: usize = 4;

/// One flip made: the edge `(a, b)` replaced by `(c, d)`, and the folded vertex it was made
/// for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Flip {
    /// The edge removed, as its first face ran it.
    pub removed: [u32; 2],
    /// The edge that replaces it.
    pub added: [u32; 2],
    /// The vertex whose ring folded.
    pub vertex: u32,
}

/// The working state: faces, twins and the incidences a flip changes.
struct Rings<'a> {
    positions: &'a [DVec3],
    faces: &'a mut [[u32; 3]],
    twin: &'a mut [u32],
    /// The faces around each vertex.
    around: Vec<Vec<u32>>,
    /// Every edge as `(min, max)`.
    edges: HashSet<(u32, u32)>,
}

fn key(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

impl Rings<'_> {
    fn corners(&self, face: u32) -> [DVec3; 3] {
        self.faces[face as usize].map(|v| self.positions[v as usize])
    }

    /// Whether no direction sees every face around `v` from the front by
    /// [`MIN_FRONT_MARGIN`] (faces of zero area constrain nothing).
    fn folded(&self, v: u32) -> bool {
        let mut normals = Vec::with_capacity(self.around[v as usize].len());
        let mut sum = DVec3::ZERO;
        for &f in &self.around[v as usize] {
            let p = self.corners(f);
            let cross = (p[1] - p[0]).cross(p[2] - p[0]);
            sum += cross.normalize_or_zero();
            if let Some(n) = cross.try_normalize() {
                normals.push(n);
            }
        }
        let Some(&first) = normals.first() else {
            return false;
        };
        let estimate = sum.try_normalize().unwrap_or(first);
        front_facing_by(estimate, &normals, MIN_FRONT_MARGIN) == FrontFacing::Folded
    }

    /// The flip of half-edge `he`'s edge, if it is an interior edge whose flip keeps the mesh
    /// manifold: the two faces, the corners `[a, b, c, d]` and the edge's place in each face.
    fn flippable(&self, he: u32) -> Option<([u32; 2], [u32; 4], [u32; 2])> {
        let other = self.twin[he as usize];
        if other == NO_TWIN {
            return None;
        }
        let (f1, e1) = (he / 3, he % 3);
        let (f2, e2) = (other / 3, other % 3);
        let [a, b, c] = [0, 1, 2].map(|k| self.faces[f1 as usize][((e1 + k) % 3) as usize]);
        let d = self.faces[f2 as usize][((e2 + 2) % 3) as usize];
        if f1 == f2 || c == d || self.edges.contains(&key(c, d)) {
            return None;
        }
        // Outer edges shared between the two faces would be doubled by the flip.
        let outer = [(f1, e1 + 1), (f1, e1 + 2), (f2, e2 + 1), (f2, e2 + 2)];
        if outer.iter().any(|&(f, e)| {
            let t = self.twin[(3 * f + e % 3) as usize];
            t != NO_TWIN && (t / 3 == f1 || t / 3 == f2)
        }) {
            return None;
        }
        Some(([f1, f2], [a, b, c, d], [e1, e2]))
    }

    /// Replaces faces `(a, b, c)`, `(b, a, d)` by `(a, d, c)`, `(d, b, c)` in the faces and
    /// the incidences (not the twins; [`Rings::flip`] does those). Returns the faces as they
    /// were, for [`Rings::restore`].
    fn set_flipped(&mut self, [f1, f2]: [u32; 2], [a, b, c, d]: [u32; 4]) -> [[u32; 3]; 2] {
        let was = [self.faces[f1 as usize], self.faces[f2 as usize]];
        self.faces[f1 as usize] = [a, d, c];
        self.faces[f2 as usize] = [d, b, c];
        self.around[a as usize].retain(|&f| f != f2);
        self.around[b as usize].retain(|&f| f != f1);
        self.around[c as usize].push(f2);
        self.around[d as usize].push(f1);
        was
    }

    /// Undoes [`Rings::set_flipped`].
    fn restore(&mut self, [f1, f2]: [u32; 2], [a, b, c, d]: [u32; 4], was: [[u32; 3]; 2]) {
        [self.faces[f1 as usize], self.faces[f2 as usize]] = was;
        self.around[a as usize].push(f2);
        self.around[b as usize].push(f1);
        self.around[c as usize].retain(|&f| f != f2);
        self.around[d as usize].retain(|&f| f != f1);
    }

    /// Makes the flip for good: faces, incidences, edges and twins.
    fn flip(&mut self, faces: [u32; 2], corners: [u32; 4], [e1, e2]: [u32; 2]) {
        let [f1, f2] = faces;
        let [a, b, c, d] = corners;
        let twin_of = |f: u32, e: u32| self.twin[(3 * f + e % 3) as usize];
        let (t_bc, t_ca) = (twin_of(f1, e1 + 1), twin_of(f1, e1 + 2));
        let (t_ad, t_db) = (twin_of(f2, e2 + 1), twin_of(f2, e2 + 2));
        self.set_flipped(faces, corners);
        // New f1 = (a, d, c): a→d, d→c, c→a; new f2 = (d, b, c): d→b, b→c, c→d.
        let links = [
            (3 * f1, t_ad),
            (3 * f1 + 1, 3 * f2 + 2),
            (3 * f1 + 2, t_ca),
            (3 * f2, t_db),
            (3 * f2 + 1, t_bc),
            (3 * f2 + 2, 3 * f1 + 1),
        ];
        for (he, t) in links {
            self.twin[he as usize] = t;
            if t != NO_TWIN {
                self.twin[t as usize] = he;
            }
        }
        self.edges.remove(&key(a, b));
        self.edges.insert(key(c, d));
    }
}

/// `|(b−a)·((c−a)×(d−a))| / L³` with `L` the longest of the six distances: how far the four
/// corners are from a plane, relative to their span (0 for a planar quadrilateral).
fn relative_volume(p: [DVec3; 4]) -> f64 {
    let mut longest = 0.0f64;
    for i in 0..4 {
        for j in i + 1..4 {
            longest = longest.max(p[i].distance(p[j]));
        }
    }
    let volume = (p[1] - p[0]).dot((p[2] - p[0]).cross(p[3] - p[0])).abs();
    if longest > 0.0 {
        volume / longest.powi(3)
    } else {
        0.0
    }
}

/// Flips edges of folded one-rings where that unfolds them (see the module documentation),
/// and returns the flips made.
/// `faces` must be consistently oriented with `twin` their half-edge twins (half-edge `3f + e`
/// runs from corner `e` to corner `e + 1` of face `f`); both are updated. Face numbers do not
/// change, so what each face remembers of its input face still holds.
pub(super) fn unfold_rings(
    positions: &[DVec3],
    faces: &mut [[u32; 3]],
    twin: &mut [u32],
) -> Vec<Flip> {
    let mut around = vec![Vec::new(); positions.len()];
    let mut edges = HashSet::with_capacity(faces.len() * 3 / 2);
    for (f, face) in faces.iter().enumerate() {
        for e in 0..3 {
            around[face[e] as usize].push(f as u32);
            edges.insert(key(face[e], face[(e + 1) % 3]));
        }
    }
    let mut rings = Rings {
        positions,
        faces,
        twin,
        around,
        edges,
    };
    let mut folded: Vec<bool> = (0..positions.len() as u32)
        .map(|v| rings.folded(v))
        .collect();
    let mut flips = Vec::new();
    for _ in 0..PASSES {
        let mut changed = false;
        for v in 0..positions.len() as u32 {
            if !folded[v as usize] {
                continue;
            }
            if let Some((faces, corners, edges, now)) = best_flip(&mut rings, &folded, v) {
                rings.flip(faces, corners, edges);
                for (&w, state) in corners.iter().zip(now) {
                    folded[w as usize] = state;
                }
                flips.push(Flip {
                    removed: [corners[0], corners[1]],
                    added: [corners[2], corners[3]],
                    vertex: v,
                });
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    flips
}

/// The flip at folded vertex `v` that unfolds most and moves the surface least: its faces,
/// corners, edge places and the corners' folded states after it.
#[allow(clippy::type_complexity)]
fn best_flip(
    rings: &mut Rings<'_>,
    folded: &[bool],
    v: u32,
) -> Option<([u32; 2], [u32; 4], [u32; 2], [bool; 4])> {
    let mut candidates: Vec<u32> = rings.around[v as usize]
        .iter()
        .flat_map(|&f| (0..3).map(move |e| 3 * f + e))
        .collect();
    candidates.sort_unstable();
    let mut seen = HashSet::new();
    let mut best: Option<((usize, f64), [u32; 2], [u32; 4], [u32; 2], [bool; 4])> = None;
    for he in candidates {
        let Some((faces, corners, edges)) = rings.flippable(he) else {
            continue;
        };
        if !seen.insert(key(corners[0], corners[1])) {
            continue;
        }
        let [a, b, c, d] = corners.map(|w| rings.positions[w as usize]);
        if area_ratio([a, d, c]) < MIN_NEW_AREA_RATIO || area_ratio([d, b, c]) < MIN_NEW_AREA_RATIO
        {
            continue;
        }
        let before = corners.map(|w| folded[w as usize]);
        let was = rings.set_flipped(faces, corners);
        let after = corners.map(|w| rings.folded(w));
        rings.restore(faces, corners, was);
        let count = |s: [bool; 4]| s.iter().filter(|&&x| x).count();
        let folds_none_anew = before.iter().zip(&after).all(|(&b, &a)| b || !a);
        if count(after) >= count(before) || !folds_none_anew {
            continue;
        }
        // Fewer folded corners first, then the smaller change of shape.
        let rank = (count(after), relative_volume([a, b, c, d]));
        if best.as_ref().is_none_or(|b| rank < b.0) {
            best = Some((rank, faces, corners, edges, after));
        }
    }
    best.map(|(_, faces, corners, edges, after)| (faces, corners, edges, after))
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::unfold_rings;
    use crate::mesh::front_facing::front_facing_normals;
    use crate::mesh::generate::bad::test_support::folded_dart;
    use crate::mesh::topology::NO_TWIN;

    /// Twins of a consistently oriented manifold triangle list.
    fn twins(faces: &[[u32; 3]]) -> Vec<u32> {
        let mut by_edge = std::collections::HashMap::new();
        for (f, face) in faces.iter().enumerate() {
            for e in 0..3 {
                by_edge.insert((face[e], face[(e + 1) % 3]), (3 * f + e) as u32);
            }
        }
        let mut twin = vec![NO_TWIN; faces.len() * 3];
        for (&(a, b), &he) in &by_edge {
            if let Some(&t) = by_edge.get(&(b, a)) {
                twin[he as usize] = t;
            }
        }
        twin
    }

    /// The vertices whose one-ring folds over itself.
    fn folded(positions: &[DVec3], faces: &[[u32; 3]]) -> Vec<u32> {
        let mut estimate = vec![DVec3::ZERO; positions.len()];
        for f in faces {
            let p = f.map(|v| positions[v as usize]);
            for &v in f {
                estimate[v as usize] += (p[1] - p[0]).cross(p[2] - p[0]);
            }
        }
        let estimate: Vec<DVec3> = estimate.iter().map(|n| n.normalize_or_zero()).collect();
        front_facing_normals(positions, faces, &estimate).folded
    }

    /// Runs the unfolding and checks that the twins it leaves are those of its faces.
    fn unfold(positions: &[DVec3], faces: &mut [[u32; 3]]) -> Vec<super::Flip> {
        let mut twin = twins(faces);
        let flips = unfold_rings(positions, faces, &mut twin);
        assert_eq!(twin, twins(faces), "twins kept up to date");
        flips
    }

    #[test]
    fn a_folded_pair_of_faces_is_flipped_to_the_other_diagonal() {
        // The dart alone: its two top faces.
        let (positions, _) = folded_dart();
        let mut faces = vec![[0, 1, 2], [1, 0, 3]];
        assert_eq!(folded(&positions, &faces), vec![0, 1]);
        let flips = unfold(&positions, &mut faces);
        assert_eq!(flips.len(), 1);
        assert_eq!((flips[0].removed, flips[0].added), ([0, 1], [2, 3]));
        assert_eq!(faces, vec![[0, 3, 2], [3, 1, 2]]);
        assert!(folded(&positions, &faces).is_empty());
    }

    #[test]
    fn a_closed_mesh_stays_closed_and_manifold_and_unfolds() {
        let (positions, mut faces) = folded_dart();
        assert!(!folded(&positions, &faces).is_empty());
        let flips = unfold(&positions, &mut faces);
        assert_eq!(flips.len(), 1);
        assert!(folded(&positions, &faces).is_empty(), "{faces:?}");
        assert!(twins(&faces).iter().all(|&t| t != NO_TWIN), "still closed");
        let mut edges: Vec<(u32, u32)> = faces
            .iter()
            .flat_map(|f| (0..3).map(move |e| (f[e].min(f[(e + 1) % 3]), f[e].max(f[(e + 1) % 3]))))
            .collect();
        edges.sort_unstable();
        let before = edges.len();
        edges.dedup();
        assert_eq!(2 * edges.len(), before, "every edge has exactly two faces");
    }

    /// Sharp features are not folds: a tetrahedron flattened to a thousandth of its width has
    /// dihedral angles near 180° at its rim, but every ring is seen from the front by some
    /// direction, so nothing is flipped.
    #[test]
    fn a_flattened_convex_solid_keeps_every_edge() {
        let positions = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(0.3, 0.3, 1e-3),
        ];
        let mut faces = vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]];
        let written = faces.clone();
        assert!(unfold(&positions, &mut faces).is_empty());
        assert_eq!(faces, written);
    }

    /// A fold that no flip of one edge can undo (the dart's faces are the whole mesh, and the
    /// other diagonal is taken already) is left as it is.
    #[test]
    fn a_fold_no_flip_undoes_is_left_alone() {
        let (positions, _) = folded_dart();
        // The dart cut along ab, plus a face on c and d that joins them already.
        let mut faces = vec![[0, 1, 2], [1, 0, 3], [3, 2, 1]];
        let written = faces.clone();
        let before = folded(&positions, &faces);
        assert!(!before.is_empty());
        assert!(unfold(&positions, &mut faces).is_empty());
        assert_eq!(faces, written);
    }
}
