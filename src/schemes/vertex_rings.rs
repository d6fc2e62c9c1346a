//! Machinery shared by the vertex-local G¹ schemes (HB00, Loop94): data computed for every
//! directed edge `v → p_i` from the one-ring of `v` alone, stored in one flat table, the index
//! arithmetic from a face corner to its directed edges and their reverses, and the discrete
//! Fourier sums of a one-ring that both schemes build their tangents from [HB00 eqs. 12, 17].

use std::f64::consts::PI;

use glam::DVec3;
use rayon::prelude::*;

use crate::mesh::Mesh;

/// `Φ_i(0) = cos(2π/n)` [HB00 eq. 6].
pub fn phi0(n: usize) -> f64 {
    (2.0 * PI / n as f64).cos()
}

/// `Ψ_i(0) = sin(2π/n)` [HB00 eq. 20].
pub fn psi0(n: usize) -> f64 {
    (2.0 * PI / n as f64).sin()
}

/// Discrete Fourier sums of a one-ring `p_0..p_{n−1}` with `θ = 2π/n`:
/// `C = Σ cos(θj) p_j`, `S = Σ sin(θj) p_j`, so that every rotated sum is O(1).
#[derive(Clone, Copy, Debug)]
pub struct RingFourier {
    theta: f64,
    cos_part: DVec3,
    sin_part: DVec3,
    mean: DVec3,
}

impl RingFourier {
    /// The sums of `ring`.
    pub fn new(ring: &[DVec3]) -> RingFourier {
        let theta = 2.0 * PI / ring.len() as f64;
        let (mut cos_part, mut sin_part, mut mean) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
        for (j, p) in ring.iter().enumerate() {
            let (s, c) = (theta * j as f64).sin_cos();
            cos_part += c * *p;
            sin_part += s * *p;
            mean += *p;
        }
        RingFourier {
            theta,
            cos_part,
            sin_part,
            mean: mean / ring.len() as f64,
        }
    }

    /// Centroid of the ring.
    pub fn mean(&self) -> DVec3 {
        self.mean
    }

    /// `Σ_j cos(θ(j−i)) p_j` (the first-order Fourier component seen from edge i).
    pub fn cos_sum(&self, i: usize) -> DVec3 {
        let (s, c) = (self.theta * i as f64).sin_cos();
        c * self.cos_part + s * self.sin_part
    }

    /// `Σ_j sin(θ(j−i)) p_j`.
    pub fn sin_sum(&self, i: usize) -> DVec3 {
        let (s, c) = (self.theta * i as f64).sin_cos();
        c * self.sin_part - s * self.cos_part
    }

    /// `Σ_j [cos(θ(j−i)) + tan(θ/2) sin(θ(j−i))] p_j`: the preimage under the twist matrix
    /// `T` of (II_T) (`½(x_i + x_{i−1})`) of the cosine sums [HB00 §6, b̃¹].
    pub fn twist_preimage_sum(&self, i: usize) -> DVec3 {
        self.cos_sum(i) + (self.theta / 2.0).tan() * self.sin_sum(i)
    }
}

/// Per-directed-edge data of a closed mesh, computed vertex by vertex.
pub struct HalfEdgeTable<T> {
    /// `offsets[v] + i` is the edge `v → one_ring(v)[i]`.
    offsets: Vec<usize>,
    data: Vec<T>,
    /// `corner_ring[3f + k]`: position of `faces[f][k+1]` in the one-ring of `faces[f][k]`.
    corner_ring: Vec<u32>,
}

impl<T: Clone + Default + Send + Sync> HalfEdgeTable<T> {
    /// Runs `per_vertex(v, ring positions, ring valences, out)` for every vertex in parallel;
    /// `out[i]` is the entry of edge `v → ring[i]`.
    pub fn build(
        mesh: &Mesh,
        per_vertex: impl Fn(DVec3, &[DVec3], &[usize], &mut [T]) + Sync,
    ) -> HalfEdgeTable<T> {
        let nv = mesh.vertex_count();
        let mut offsets = Vec::with_capacity(nv + 1);
        let mut total = 0;
        for v in 0..nv {
            offsets.push(total);
            total += mesh.valence(v as u32);
        }
        offsets.push(total);
        let positions = mesh.positions();
        let mut data = vec![T::default(); total];
        let mut slices: Vec<&mut [T]> = Vec::with_capacity(nv);
        let mut rest = data.as_mut_slice();
        for v in 0..nv {
            let (head, tail) = rest.split_at_mut(offsets[v + 1] - offsets[v]);
            slices.push(head);
            rest = tail;
        }
        slices.into_par_iter().enumerate().for_each_init(
            || (Vec::new(), Vec::new()),
            |(ring_points, ring_valence), (v, out)| {
                let ring = mesh.one_ring(v as u32);
                ring_points.clear();
                ring_points.extend(ring.iter().map(|&p| positions[p as usize]));
                ring_valence.clear();
                ring_valence.extend(ring.iter().map(|&p| mesh.valence(p)));
                per_vertex(positions[v], ring_points, ring_valence, out);
            },
        );
        // (v, ring[j], ring[j+1]) is ring_faces(v)[j].
        let faces = mesh.faces();
        let mut corner_ring = vec![0u32; 3 * faces.len()];
        for v in 0..nv as u32 {
            for (j, &f) in mesh.ring_faces(v).iter().enumerate() {
                let k = faces[f as usize].iter().position(|&x| x == v).unwrap_or(0);
                corner_ring[3 * f as usize + k] = j as u32;
            }
        }
        HalfEdgeTable {
            offsets,
            data,
            corner_ring,
        }
    }
}

impl<T> HalfEdgeTable<T> {
    /// The entry of directed edge `h`.
    pub fn get(&self, h: usize) -> &T {
        &self.data[h]
    }

    /// Index of the directed edge from `faces[f][k]` to the corner `step` (1 or 2) after it.
    pub fn directed(&self, face: [u32; 3], f: usize, k: usize, step: usize) -> usize {
        let x = face[k] as usize;
        let n = self.offsets[x + 1] - self.offsets[x];
        // Face (X, Y, Z) is (v, ring[j], ring[j+1]) around X with j = corner_ring.
        let j = self.corner_ring[3 * f + k] as usize;
        self.offsets[x] + (j + step - 1) % n
    }

    /// For each corner `X = a_k` of face `f`: the directed edges `[X→Y, Y→X, X→Z, Z→X]`
    /// (`Y = a_{k+1}`, `Z = a_{k+2}`).
    pub fn corner_edges(&self, face: [u32; 3], f: usize) -> [[usize; 4]; 3] {
        let forward: [usize; 3] = std::array::from_fn(|k| self.directed(face, f, k, 1));
        let backward: [usize; 3] = std::array::from_fn(|k| self.directed(face, f, k, 2));
        // X→Y reversed is a_{k+1} → a_k = backward[k+1]; X→Z reversed is forward[k+2].
        std::array::from_fn(|k| {
            [
                forward[k],
                backward[(k + 1) % 3],
                backward[k],
                forward[(k + 2) % 3],
            ]
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate;

    /// The rotated sums equal the direct sums, and the twist preimage satisfies
    /// ½(x_i + x_{i−1}) = cos-sum_i.
    #[test]
    fn fourier_sums_and_twist_preimage() {
        for n in 3..=12 {
            let ring: Vec<DVec3> = (0..n)
                .map(|j| DVec3::new(j as f64 * 0.37, (j * j) as f64 * 0.11, 1.0 / (j + 1) as f64))
                .collect();
            let f = RingFourier::new(&ring);
            let theta = 2.0 * PI / n as f64;
            for i in 0..n {
                let direct_cos: DVec3 = (0..n)
                    .map(|j| (theta * (j as f64 - i as f64)).cos() * ring[j])
                    .sum();
                let direct_sin: DVec3 = (0..n)
                    .map(|j| (theta * (j as f64 - i as f64)).sin() * ring[j])
                    .sum();
                assert!((f.cos_sum(i) - direct_cos).length() < 1e-13);
                assert!((f.sin_sum(i) - direct_sin).length() < 1e-13);
                let avg = 0.5 * (f.twist_preimage_sum(i) + f.twist_preimage_sum((i + n - 1) % n));
                assert!((avg - f.cos_sum(i)).length() < 1e-13, "n={n} i={i}");
            }
        }
    }

    /// Every corner's directed edges start and end at the right vertices.
    #[test]
    fn corner_edges_connect_the_face_corners() {
        let mesh = crate::testing::mesh(generate::mixed_valence());
        let table = HalfEdgeTable::<(u32, u32)>::build(&mesh, |_, _, _, _| {});
        // Rebuild the (from, to) pairs from the layout of the table.
        let mut ends = Vec::new();
        for v in 0..mesh.vertex_count() as u32 {
            ends.extend(mesh.one_ring(v).iter().map(|&w| (v, w)));
        }
        for (fi, face) in mesh.faces().iter().enumerate() {
            for (k, e) in table.corner_edges(*face, fi).iter().enumerate() {
                let (x, y, z) = (face[k], face[(k + 1) % 3], face[(k + 2) % 3]);
                assert_eq!(
                    [ends[e[0]], ends[e[1]], ends[e[2]], ends[e[3]]],
                    [(x, y), (y, x), (x, z), (z, x)]
                );
            }
        }
    }
}
