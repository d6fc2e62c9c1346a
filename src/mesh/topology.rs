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
