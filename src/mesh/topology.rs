//! Half-edge topology of an oriented manifold triangle mesh, stored as flat arrays: the twin of
//! every half-edge and, per vertex, the one-ring and its faces in counter-clockwise order (CSR).
//! Built in O(F) from the twins; every query is a slice into these arrays.
//!
//! Half-edge `3·f + e` runs from `faces[f][e]` to `faces[f][(e+1) % 3]`.

use crate::error::{Error, Result};

/// Marks a half-edge with no twin (a boundary edge).
pub(super) const NO_TWIN: u32 = u32::MAX;

/// Twins and ordered one-rings.
#[derive(Clone, Debug)]
pub(super) struct Topology {
    /// Twin of each half-edge, or [`NO_TWIN`].
    pub(super) twin: Vec<u32>,
    /// Vertex v's ring is `ring[ring_offsets[v]..ring_offsets[v+1]]`.
    ring_offsets: Vec<u32>,
    ring: Vec<u32>,
    /// Parallel to `ring`; a boundary vertex's last slot is unused (its fan has one face less
    /// than neighbours).
    ring_faces: Vec<u32>,
    /// True for vertices on a boundary edge.
    pub(super) boundary_vertex: Vec<bool>,
    /// Number of half-edges without a twin (= number of boundary edges).
    pub(super) boundary_half_edges: usize,
}

impl Topology {
    /// Builds the one-rings of consistently oriented faces with edge-manifold `twin`s. Fails with
    /// [`Error::NonManifoldVertex`] (naming the vertex through `name`) when the faces around a
    /// vertex form more than one fan.
    pub(super) fn build(
        faces: &[[u32; 3]],
        twin: Vec<u32>,
        vertex_count: usize,
        name: impl Fn(u32) -> usize,
    ) -> Result<Topology> {
        let half_edge_count = 3 * faces.len();
        let from = |he: usize| faces[he / 3][he % 3] as usize;

        // Outgoing half-edges of every vertex, by counting sort.
        let mut out_offsets = vec![0u32; vertex_count + 1];
        for he in 0..half_edge_count {
            out_offsets[from(he) + 1] += 1;
        }
        for v in 0..vertex_count {
            out_offsets[v + 1] += out_offsets[v];
        }
        let mut outgoing = vec![0u32; half_edge_count];
        let mut fill = out_offsets.clone();
        for he in 0..half_edge_count {
            let v = from(he);
            outgoing[fill[v] as usize] = he as u32;
            fill[v] += 1;
        }

        let mut boundary_vertex = vec![false; vertex_count];
        let mut boundary_half_edges = 0;
        for he in 0..half_edge_count {
            if twin[he] == NO_TWIN {
                boundary_vertex[from(he)] = true;
                boundary_half_edges += 1;
            }
        }

        // A vertex with k corners has k ring vertices, plus one closing the fan on a boundary.
        let mut ring_offsets = vec![0u32; vertex_count + 1];
        for v in 0..vertex_count {
            let corners = out_offsets[v + 1] - out_offsets[v];
            ring_offsets[v + 1] = ring_offsets[v] + corners + u32::from(boundary_vertex[v]);
        }
        let ring_len = ring_offsets[vertex_count] as usize;
        let mut ring = vec![0u32; ring_len];
        let mut ring_faces = vec![NO_TWIN; ring_len];
        let mut visited = vec![false; half_edge_count];

        for v in 0..vertex_count {
            let outs = &outgoing[out_offsets[v] as usize..out_offsets[v + 1] as usize];
            let base = ring_offsets[v] as usize;
            let mut fans = 0;
            // Open fans start at a boundary half-edge leaving v; closed fans anywhere.
            let open_starts = outs.iter().filter(|&&h| twin[h as usize] == NO_TWIN);
            let closed_starts = outs.iter().filter(|&&h| twin[h as usize] != NO_TWIN);
            for &start in open_starts.chain(closed_starts) {
                if visited[start as usize] {
                    continue;
                }
                let sink = (fans == 0).then_some((
                    &mut ring[base..ring_offsets[v + 1] as usize],
                    &mut ring_faces[base..ring_offsets[v + 1] as usize],
                ));
                walk_fan(faces, &twin, start as usize, &mut visited, sink);
                fans += 1;
            }
            if fans > 1 {
                return Err(Error::NonManifoldVertex {
                    vertex: name(v as u32),
                    fans,
                });
            }
        }
        Ok(Topology {
            twin,
            ring_offsets,
            ring,
            ring_faces,
            boundary_vertex,
            boundary_half_edges,
        })
    }

    /// The ordered neighbours of `v`.
    pub(super) fn one_ring(&self, v: u32) -> &[u32] {
        let v = v as usize;
        &self.ring[self.ring_offsets[v] as usize..self.ring_offsets[v + 1] as usize]
    }

    /// The faces between consecutive ring vertices of `v`.
    pub(super) fn ring_faces(&self, v: u32) -> &[u32] {
        let i = v as usize;
        let end = self.ring_offsets[i + 1] as usize - usize::from(self.boundary_vertex[i]);
        &self.ring_faces[self.ring_offsets[i] as usize..end]
    }
}

/// Walks the fan of faces around the source vertex of half-edge `start` counter-clockwise:
/// from `h = v→w` in face (v, w, x) to the twin of `x→v`, which is `v→x` in the next face. Stops
/// at a boundary or back at `start`. When `sink` is given, writes the ring vertices and faces
/// into it (the fan closing vertex of an open fan goes into the extra last slot).
fn walk_fan(
    faces: &[[u32; 3]],
    twin: &[u32],
    start: usize,
    visited: &mut [bool],
    mut sink: Option<(&mut [u32], &mut [u32])>,
) {
    let mut h = start;
    let mut k = 0;
    loop {
        visited[h] = true;
        let (f, e) = (h / 3, h % 3);
        if let Some((ring, ring_faces)) = sink.as_mut() {
            ring[k] = faces[f][(e + 1) % 3];
            ring_faces[k] = f as u32;
        }
        k += 1;
        let incoming = 3 * f + (e + 2) % 3;
        let next = twin[incoming];
        if next == NO_TWIN {
            if let Some((ring, _)) = sink.as_mut() {
                ring[k] = faces[f][(e + 2) % 3];
            }
            return;
        }
        h = next as usize;
        if visited[h] {
            return;
        }
    }
}

#[cfg(test)]
mod tests {
    use std::collections::{BTreeSet, HashSet};

    use crate::mesh::Mesh;
    use crate::mesh::generate::{self, SCENES, analytic};

    /// Every generated valid mesh, by name.
    fn all_generated() -> Vec<(String, Mesh)> {
        let mut meshes: Vec<(String, Mesh)> = SCENES
            .iter()
            .map(|scene| (scene.name.to_string(), scene.mesh().unwrap()))
            .collect();
        for n in 3..=16 {
            let (positions, faces) = generate::valence_fan(n).unwrap();
            let mesh = Mesh::from_triangles(positions, faces).unwrap().0;
            meshes.push((format!("valence-fan-{n}"), mesh));
        }
        for rings in 1..=3 {
            let (positions, faces) = generate::disk(rings);
            let mesh = Mesh::from_triangles(positions, faces).unwrap().0;
            meshes.push((format!("disk-{rings}"), mesh));
        }
        let sphere = analytic::sphere(2);
        let mesh = Mesh::from_triangles(sphere.positions, sphere.faces)
            .unwrap()
            .0;
        meshes.push(("sphere-2".to_string(), mesh));
        meshes
    }

    /// True if `face` is (v, a, b) up to rotation of its corners.
    fn is_face(face: [u32; 3], v: u32, a: u32, b: u32) -> bool {
        (0..3).any(|r| face[r] == v && face[(r + 1) % 3] == a && face[(r + 2) % 3] == b)
    }

    #[test]
    fn one_ring_order_matches_the_faces_on_every_generated_mesh() {
        for (name, mesh) in all_generated() {
            for v in 0..mesh.vertex_count() as u32 {
                let ring = mesh.one_ring(v);
                let ring_faces = mesh.ring_faces(v);
                let n = ring.len();
                let boundary = mesh.is_boundary_vertex(v);
                assert_eq!(
                    ring_faces.len(),
                    if boundary { n - 1 } else { n },
                    "{name} v{v}"
                );
                for (j, &f) in ring_faces.iter().enumerate() {
                    let face = mesh.faces()[f as usize];
                    assert!(
                        is_face(face, v, ring[j], ring[(j + 1) % n]),
                        "{name}: vertex {v}, ring {ring:?}, face {f} = {face:?}"
                    );
                }
                let distinct: HashSet<u32> = ring.iter().copied().collect();
                assert_eq!(distinct.len(), n, "{name}: ring of {v} repeats a vertex");
                // Every face at v appears exactly once in its ring.
                let at_v = mesh.faces().iter().filter(|f| f.contains(&v)).count();
                assert_eq!(ring_faces.len(), at_v, "{name} v{v}");
            }
        }
    }

    #[test]
    fn boundary_fans_start_and_end_on_boundary_edges() {
        let (positions, faces) = generate::disk(3);
        let (mesh, _) = Mesh::from_triangles(positions, faces).unwrap();
        assert!(!mesh.is_closed());
        let mut rim = 0;
        for v in 0..mesh.vertex_count() as u32 {
            if !mesh.is_boundary_vertex(v) {
                assert_eq!(mesh.valence(v), 6);
                continue;
            }
            rim += 1;
            let ring = mesh.one_ring(v);
            let ring_faces = mesh.ring_faces(v);
            // (v, ring[0]) runs along the first face, and nothing lies beyond it.
            let first = ring_faces[0];
            let e = mesh.faces()[first as usize]
                .iter()
                .position(|&c| c == v)
                .unwrap();
            assert_eq!(mesh.faces()[first as usize][(e + 1) % 3], ring[0]);
            assert_eq!(mesh.neighbor(first, e), None, "vertex {v}");
            // (ring[n-1], v) closes the last face, also on the boundary.
            let last = *ring_faces.last().unwrap();
            let e = mesh.faces()[last as usize]
                .iter()
                .position(|&c| c == *ring.last().unwrap())
                .unwrap();
            assert_eq!(mesh.faces()[last as usize][(e + 1) % 3], v);
            assert_eq!(mesh.neighbor(last, e), None, "vertex {v}");
        }
        assert_eq!(rim, 18, "a 3-ring hexagonal disk has 6·3 rim vertices");
        assert!(mesh.first_boundary_edge().is_some());
    }

    #[test]
    fn neighbors_are_symmetric_and_share_the_reversed_edge() {
        for (name, mesh) in all_generated() {
            for f in 0..mesh.face_count() as u32 {
                for e in 0..3 {
                    let Some((g, e2)) = mesh.neighbor(f, e) else {
                        assert!(!mesh.is_closed(), "{name}: closed mesh with a boundary");
                        continue;
                    };
                    assert_eq!(mesh.neighbor(g, e2), Some((f, e)), "{name}");
                    let (face, other) = (mesh.faces()[f as usize], mesh.faces()[g as usize]);
                    assert_eq!(face[e], other[(e2 + 1) % 3], "{name}");
                    assert_eq!(face[(e + 1) % 3], other[e2], "{name}");
                }
            }
        }
    }

    #[test]
    fn edges_are_listed_once_with_their_faces() {
        for (name, mesh) in all_generated() {
            let edges = mesh.edges();
            assert_eq!(edges.len(), mesh.edge_count(), "{name}");
            let distinct: HashSet<(u32, u32)> = edges.iter().map(|e| (e.a, e.b)).collect();
            assert_eq!(distinct.len(), edges.len(), "{name}");
            let boundary = edges.iter().filter(|e| e.faces.1.is_none()).count();
            assert_eq!(boundary == 0, mesh.is_closed(), "{name}");
            assert_eq!(
                mesh.first_boundary_edge().is_none(),
                mesh.is_closed(),
                "{name}"
            );
            for edge in &edges {
                assert!(edge.a < edge.b);
                for f in [Some(edge.faces.0), edge.faces.1].into_iter().flatten() {
                    let face = mesh.faces()[f as usize];
                    assert!(face.contains(&edge.a) && face.contains(&edge.b), "{name}");
                }
            }
            // The valence counts every edge at a vertex.
            let mut degree = vec![0; mesh.vertex_count()];
            for edge in &edges {
                degree[edge.a as usize] += 1;
                degree[edge.b as usize] += 1;
            }
            for (v, &edges_at_v) in degree.iter().enumerate() {
                assert_eq!(mesh.valence(v as u32), edges_at_v, "{name} v{v}");
            }
        }
    }

    #[test]
    fn euler_characteristic_gives_the_genus_of_each_scene() {
        for scene in &SCENES {
            let mesh = scene.mesh().unwrap();
            assert!(mesh.is_closed(), "{}", scene.name);
            assert_eq!(
                3 * mesh.face_count(),
                2 * mesh.edge_count(),
                "{}",
                scene.name
            );
            assert_eq!(
                mesh.euler_characteristic(),
                2 - 2 * i64::from(scene.genus),
                "{}",
                scene.name
            );
        }
        for n in 3..=16 {
            let (positions, faces) = generate::valence_fan(n).unwrap();
            let mesh = Mesh::from_triangles(positions, faces).unwrap().0;
            assert_eq!(mesh.euler_characteristic(), 2, "valence fan {n}");
        }
        let (positions, faces) = generate::disk(2);
        let disk = Mesh::from_triangles(positions, faces).unwrap().0;
        assert_eq!(disk.euler_characteristic(), 1, "a disk");
    }

    #[test]
    fn valences_of_the_generated_meshes() {
        let valences = |mesh: &Mesh| -> Vec<usize> {
            (0..mesh.vertex_count() as u32)
                .map(|v| mesh.valence(v))
                .collect()
        };
        let scene = |name: &str| {
            SCENES
                .iter()
                .find(|s| s.name == name)
                .unwrap()
                .mesh()
                .unwrap()
        };
        let mixed: BTreeSet<usize> = valences(&scene("mixed-valence")).into_iter().collect();
        assert_eq!(mixed, BTreeSet::from([3, 4, 5, 6, 8, 15, 16]));
        assert!(valences(&scene("torus")).iter().all(|&n| n == 6));
        assert!(valences(&scene("icosahedron")).iter().all(|&n| n == 5));
        assert!(valences(&scene("octahedron")).iter().all(|&n| n == 4));
        assert!(valences(&scene("tetrahedron")).iter().all(|&n| n == 3));
        let mut cube = valences(&scene("cube"));
        cube.sort_unstable();
        assert_eq!(cube, [3, 4, 4, 4, 5, 5, 5, 6]);
        for n in 3..=16 {
            let (positions, faces) = generate::valence_fan(n).unwrap();
            let mesh = Mesh::from_triangles(positions, faces).unwrap().0;
            assert_eq!(mesh.valence(0), n);
            assert_eq!(mesh.valence(1), n);
        }
    }
}
