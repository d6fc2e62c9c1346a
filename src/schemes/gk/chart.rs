//! Lattice charts: the regular subnet of a face, found by walking the mesh. A face
//! `(a, b, c)` is laid on the grid triangle `Δ(0,0)` (a ↦ (0,0), b ↦ (1,0), c ↦ (1,1)); from a
//! valence-6 vertex whose neighbour in one grid direction is known, the neighbour in every
//! other direction follows from the counter-clockwise one-ring order, in which the six grid
//! directions `(1,0), (1,1), (0,1), (−1,0), (−1,−1), (0,−1)` also follow each other.
//!
//! A chart of radius `R` holds the lattice points within grid distance `R` of the triangle.
//! The points within `R − 1` are walked through, so their vertices must have valence 6: that
//! is exactly the condition for the subnet to be regular [UP §2, Fig. 2.2]. A point reached
//! twice with different vertices (a net too small to unfold) also makes the subnet irregular.

use std::collections::{HashMap, VecDeque};

use crate::mesh::Mesh;
use crate::schemes::gk::box_spline::{GridTriangle, grid_distance};

/// The six grid directions in counter-clockwise order.
pub(crate) const RING_DIRECTIONS: [[i32; 2]; 6] =
    [[1, 0], [1, 1], [0, 1], [-1, 0], [-1, -1], [0, -1]];

/// Mesh vertices at the lattice points of a chart.
pub(crate) type Chart = HashMap<[i32; 2], u32>;

/// Grid distance of `p` from the reference triangle `Δ(0,0)`.
pub(crate) fn distance_from_reference(p: [i32; 2]) -> i32 {
    GridTriangle::UP
        .corners()
        .iter()
        .map(|&c| grid_distance(p, c))
        .min()
        .unwrap_or(0)
}

/// Where `v`'s ring starts so that `one_ring(v)[(offset + dir) % 6]` lies in direction `dir`.
fn offset_of(mesh: &Mesh, v: u32, neighbour: u32, dir: usize) -> Option<usize> {
    let ring = mesh.one_ring(v);
    if ring.len() != 6 || mesh.is_boundary_vertex(v) {
        return None;
    }
    let at = ring.iter().position(|&w| w == neighbour)?;
    Some((at + 6 - dir % 6) % 6)
}

/// The chart of radius `radius` around `face`, or `None` if its subnet is not regular.
pub(crate) fn chart(mesh: &Mesh, face: [u32; 3], radius: i32) -> Option<Chart> {
    let [a, b, c] = face;
    let mut points: Chart = HashMap::from([([0, 0], a), ([1, 0], b), ([1, 1], c)]);
    if radius == 0 {
        return Some(points);
    }
    let mut queue = VecDeque::new();
    let mut expanded: HashMap<[i32; 2], usize> = HashMap::new();
    // Seed with a: b lies in direction 0 of it.
    let seed = offset_of(mesh, a, b, 0)?;
    expanded.insert([0, 0], seed);
    queue.push_back(([0, 0], a, seed));
    while let Some((p, v, offset)) = queue.pop_front() {
        let ring = mesh.one_ring(v);
        for (dir, step) in RING_DIRECTIONS.iter().enumerate() {
            let q = [p[0] + step[0], p[1] + step[1]];
            if distance_from_reference(q) > radius {
                continue;
            }
            let w = ring[(offset + dir) % 6];
            match points.get(&q) {
                Some(&seen) if seen != w => return None,
                _ => {
                    points.insert(q, w);
                }
            }
            if distance_from_reference(q) < radius && !expanded.contains_key(&q) {
                // From q, v lies in the opposite direction.
                let q_offset = offset_of(mesh, w, v, dir + 3)?;
                expanded.insert(q, q_offset);
                queue.push_back((q, w, q_offset));
            }
        }
    }
    Some(points)
}

/// The mesh face with corners `(x, y, z)` in this cyclic order, if there is one.
pub(crate) fn face_of(mesh: &Mesh, x: u32, y: u32, z: u32) -> Option<u32> {
    let ring = mesh.one_ring(x);
    let faces = mesh.ring_faces(x);
    (0..faces.len())
        .find_map(|j| (ring[j] == y && ring[(j + 1) % ring.len()] == z).then_some(faces[j]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate;
    use crate::testing::mesh;

    /// On the all-regular torus every chart of radius 2 is regular and holds the 27 points of
    /// a k = 4 subnet, all distinct; on an icosahedron (valence 5) no chart of radius ≥ 1 is.
    #[test]
    fn charts_unfold_regular_nets_only() {
        let torus = mesh(generate::torus());
        for face in torus.faces() {
            let chart = chart(&torus, *face, 2).expect("the torus is regular");
            assert_eq!(chart.len(), 27);
            let mut vertices: Vec<u32> = chart.values().copied().collect();
            vertices.sort_unstable();
            vertices.dedup();
            assert_eq!(vertices.len(), 27, "a 12 × 8 torus unfolds without overlap");
            // Neighbouring lattice points are mesh neighbours.
            for (p, &v) in &chart {
                for step in RING_DIRECTIONS {
                    if let Some(&w) = chart.get(&[p[0] + step[0], p[1] + step[1]]) {
                        assert!(torus.one_ring(v).contains(&w));
                    }
                }
            }
        }
        let ico = mesh(generate::icosahedron());
        assert!(ico.faces().iter().all(|f| chart(&ico, *f, 1).is_none()));
        assert!(ico.faces().iter().all(|f| chart(&ico, *f, 0).is_some()));
    }
}
