//! Sector charts around an irregular vertex of valence n [UP §2, Fig. 2.4; §4, Fig. 4.1].
//!
//! The faces `(v, w_s, w_{s+1})` around `v` (`w = one_ring(v)`) are its n sectors. Sector `s`
//! is laid on the grid with `v ↦ (0,0)`, `w_s ↦ (1,0)`, `w_{s+1} ↦ (1,1)`; the net vertex at
//! ring `ρ`, sector `s`, position `t < ρ` (counted from the sector's first edge) sits at the
//! lattice point `ρ·(1,0) + t·(0,1)`. The six lattice wedges between consecutive grid
//! directions then hold the sectors `s, s+1, s+2` and `s−2, s−1` (wedges 0, 1, 2 and 4, 5,
//! indices mod n), and wedge 3, opposite the sector, holds only points of the rings that
//! coalesce with `v`: that is the chart of UP's Fig. 2.4 subnet with the multiple vertex
//! "replaced by a regular triangular net whose vertices are all equal to the multiple vertex".
//! Two neighbouring sector charts name every lattice point outside wedge 3 alike, so the
//! patches they give join C^k.

use std::collections::{HashMap, VecDeque};

use glam::DVec3;

use crate::bezier::TriangleBezier;
use crate::mesh::Mesh;
use crate::schemes::gk::box_spline::{ControlSite, GridTriangle, PatchStencil, grid_distance};
use crate::schemes::gk::chart::{RING_DIRECTIONS, face_of};

/// What a lattice point of a sector chart stands for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum SectorPoint {
    /// The irregular vertex itself or a point of wedge 3 (must coalesce with it).
    Centre,
    /// The net vertex on ring `ring ≥ 1`, in sector `sector`, at position `t < ring`.
    Net {
        /// Ring (grid distance from the irregular vertex).
        ring: usize,
        /// Sector, mod n.
        sector: usize,
        /// Position along the sector's part of the ring.
        t: usize,
    },
}

/// Where the lattice point `p` of the chart of sector `sector` lies in a valence-`n` net.
pub(crate) fn classify(p: [i32; 2], sector: usize, n: usize) -> SectorPoint {
    if p == [0, 0] {
        return SectorPoint::Centre;
    }
    // p = a·D_w + b·D_{w+1} with a ≥ 1, b ≥ 0 in exactly one wedge w.
    for w in 0..6 {
        let (d0, d1) = (RING_DIRECTIONS[w], RING_DIRECTIONS[(w + 1) % 6]);
        let det = d0[0] * d1[1] - d0[1] * d1[0];
        let a = (p[0] * d1[1] - p[1] * d1[0]) / det;
        let b = (d0[0] * p[1] - d0[1] * p[0]) / det;
        if a >= 1 && b >= 0 && a * d0[0] + b * d1[0] == p[0] && a * d0[1] + b * d1[1] == p[1] {
            if w == 3 {
                return SectorPoint::Centre;
            }
            let shift = if w < 3 { w as i64 } else { w as i64 - 6 };
            return SectorPoint::Net {
                ring: (a + b) as usize,
                sector: (sector as i64 + shift).rem_euclid(n as i64) as usize,
                t: b as usize,
            };
        }
    }
    unreachable!("the six wedges cover the lattice")
}

/// The net vertices of rings `1..=radius` around `v`: `[sector][ring − 1][t]`.
#[derive(Clone, Debug)]
pub(crate) struct Rings {
    /// The irregular vertex.
    pub centre: u32,
    /// Mesh vertex per sector, ring and position.
    pub vertices: Vec<Vec<Vec<u32>>>,
}

impl Rings {
    /// Walks each sector of `v` out to ring `radius` (every vertex except `v` must have
    /// valence 6 there); `None` if the walk meets an irregular vertex or runs into itself.
    pub(crate) fn around(mesh: &Mesh, v: u32, radius: usize) -> Option<Rings> {
        let ring = mesh.one_ring(v);
        let n = ring.len();
        let vertices = ring
            .iter()
            .map(|&first| Self::sector(mesh, v, first, radius))
            .collect::<Option<Vec<_>>>()?;
        let rings = Rings {
            centre: v,
            vertices,
        };
        // Neighbouring sectors must meet: t = ρ of sector s is t = 0 of sector s+1.
        for s in 0..n {
            let next = &rings.vertices[(s + 1) % n];
            for (i, next_ring) in next.iter().enumerate() {
                if next_ring[0] != rings.vertices[s][i][i + 1] {
                    return None;
                }
            }
        }
        Some(rings)
    }

    /// Sector starting at the edge `v → first`, with one extra point per ring (t = ρ, the
    /// next sector's first point) so that neighbouring sectors can be checked to meet.
    fn sector(mesh: &Mesh, v: u32, first: u32, radius: usize) -> Option<Vec<Vec<u32>>> {
        let r = radius as i32;
        let in_wedge = |p: [i32; 2]| p[0] >= 1 && p[1] >= 0 && p[1] <= p[0] && p[0] <= r;
        let mut at: HashMap<[i32; 2], u32> = HashMap::from([([1, 0], first)]);
        let start = offset(mesh, first, v, 3)?;
        let mut queue = VecDeque::from([([1, 0], first, start)]);
        let mut expanded = std::collections::HashSet::from([[1, 0]]);
        while let Some((p, x, off)) = queue.pop_front() {
            let ring = mesh.one_ring(x);
            for (dir, step) in RING_DIRECTIONS.iter().enumerate() {
                let q = [p[0] + step[0], p[1] + step[1]];
                if !in_wedge(q) {
                    continue;
                }
                let y = ring[(off + dir) % 6];
                if *at.entry(q).or_insert(y) != y {
                    return None;
                }
                if q[0] < r && expanded.insert(q) {
                    queue.push_back((q, y, offset(mesh, y, x, dir + 3)?));
                }
            }
        }
        // In the chart, ring ρ of the sector is the column x = ρ, t = y.
        (1..=r)
            .map(|rho| {
                (0..=rho)
                    .map(|t| at.get(&[rho, t]).copied())
                    .collect::<Option<Vec<u32>>>()
            })
            .collect()
    }

    /// The vertex for a classified point (None for [`SectorPoint::Centre`]).
    pub(crate) fn vertex(&self, point: SectorPoint) -> Option<u32> {
        match point {
            SectorPoint::Centre => Some(self.centre),
            SectorPoint::Net { ring, sector, t } => self
                .vertices
                .get(sector)?
                .get(ring.checked_sub(1)?)?
                .get(t)
                .copied(),
        }
    }

    /// The mesh face of the lattice triangle with corners `corners` in the chart of `sector`.
    pub(crate) fn face(&self, mesh: &Mesh, sector: usize, corners: [[i32; 2]; 3]) -> Option<u32> {
        let n = self.vertices.len();
        let [x, y, z] = corners.map(|c| self.vertex(classify(c, sector, n)));
        face_of(mesh, x?, y?, z?)
    }
}

/// A control point of a sector chart: a net vertex (box splines) or a dual point at a
/// lattice triangle (half-box splines), already resolved to "the multiple vertex" where the
/// construction coalesces it [UP §2, §3].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum SectorSite {
    /// Coalesced with the irregular vertex (the multiple vertex).
    Multiple,
    /// The net vertex at this point.
    Vertex(SectorPoint),
    /// The dual point of the lattice triangle with these corners (in the chart's order): the
    /// centroid of the corners' control points, each resolved as a vertex site (so the
    /// n-gon's own dual points are the multiple vertex).
    Face([[i32; 2]; 3]),
}

/// Number of vertex rings of the triangle net that coalesce with the irregular vertex:
/// `k/2 − 1` for box splines [UP §2], `(k−1)/2` for half-box splines, whose dual points are
/// then the centroids of the coalesced triangle net [UP §3, §4].
pub(crate) fn coalesced_rings(k: usize) -> usize {
    if k.is_multiple_of(2) {
        k / 2 - 1
    } else {
        (k - 1) / 2
    }
}

/// How the control point at `site` (a stencil site of a patch translated into the chart of
/// `sector`) is read for smoothness order `k` around a vertex of valence `n`. `None` if the
/// point lies opposite the sector but outside the coalesced rings (the chart would name it
/// differently from its neighbours; never the case for the stencils of rings 1 and 2).
pub(crate) fn resolve(site: ControlSite, sector: usize, n: usize, k: usize) -> Option<SectorSite> {
    let coalesced = coalesced_rings(k);
    let ring_of = |p: [i32; 2]| grid_distance(p, [0, 0]) as usize;
    match site {
        ControlSite::Vertex(p) => match classify(p, sector, n) {
            SectorPoint::Centre if ring_of(p) <= coalesced => Some(SectorSite::Multiple),
            SectorPoint::Centre => None,
            SectorPoint::Net { ring, .. } if ring <= coalesced => Some(SectorSite::Multiple),
            point => Some(SectorSite::Vertex(point)),
        },
        ControlSite::Face(f) => {
            // A dual point is the centroid of its three corners, each read as a vertex.
            let corners = f.corners();
            let readable = corners
                .iter()
                .all(|&c| resolve(ControlSite::Vertex(c), sector, n, k).is_some());
            readable.then_some(SectorSite::Face(corners))
        }
    }
}

/// The Bézier net of the patch over lattice triangle `triangle` of a sector chart, reading the
/// control point at each chart site through `value` (`None` if a site cannot be read).
pub(crate) fn sector_patch(
    k: usize,
    triangle: GridTriangle,
    mut value: impl FnMut(ControlSite) -> Option<DVec3>,
) -> Option<TriangleBezier> {
    let stencil = PatchStencil::reference(k, triangle.up);
    let offset = [triangle.i, triangle.j];
    let mut complete = true;
    let net = stencil.apply(|site| {
        let moved = match site {
            ControlSite::Vertex(p) => ControlSite::Vertex([p[0] + offset[0], p[1] + offset[1]]),
            ControlSite::Face(f) => ControlSite::Face(f.translated(offset)),
        };
        match value(moved) {
            Some(x) => x,
            None => {
                complete = false;
                DVec3::ZERO
            }
        }
    });
    complete.then(|| TriangleBezier::new(stencil.degree, net))
}

/// Ring offset of `x` so that `one_ring(x)[(offset + dir) % 6]` is its neighbour in grid
/// direction `dir`, given that `neighbour` lies in direction `dir_of_neighbour`.
fn offset(mesh: &Mesh, x: u32, neighbour: u32, dir_of_neighbour: usize) -> Option<usize> {
    let ring = mesh.one_ring(x);
    if ring.len() != 6 {
        return None;
    }
    let at = ring.iter().position(|&w| w == neighbour)?;
    Some((at + 6 - dir_of_neighbour % 6) % 6)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::schemes::gk::refine::prepare;
    use crate::testing::closed_test_meshes;

    #[test]
    fn wedges_name_sectors_and_rings() {
        let n = 5;
        assert_eq!(classify([0, 0], 2, n), SectorPoint::Centre);
        assert_eq!(
            classify([2, 1], 2, n),
            SectorPoint::Net {
                ring: 2,
                sector: 2,
                t: 1
            }
        );
        // Wedge 1, between (1,1) and (0,1): the next sector.
        assert_eq!(
            classify([1, 2], 2, n),
            SectorPoint::Net {
                ring: 2,
                sector: 3,
                t: 1
            }
        );
        // Wedge 5, between (0,−1) and (1,0): the previous sector, wrapping mod n.
        assert_eq!(
            classify([1, -1], 0, n),
            SectorPoint::Net {
                ring: 2,
                sector: 4,
                t: 1
            }
        );
        assert_eq!(classify([-2, -1], 0, n), SectorPoint::Centre);
    }

    /// Around every irregular vertex of the prepared test nets, the sector walk finds rings
    /// of n·ρ distinct vertices, and each ring vertex is a mesh neighbour of the next.
    #[test]
    fn rings_around_irregular_vertices() {
        for (name, mesh) in closed_test_meshes() {
            let net = prepare(&mesh, 4).unwrap();
            let m = &net.mesh;
            for v in (0..m.vertex_count() as u32).filter(|&v| m.valence(v) != 6) {
                let rings = Rings::around(m, v, 4).unwrap_or_else(|| panic!("{name}: {v}"));
                let n = m.valence(v);
                for rho in 1..=4usize {
                    let mut all: Vec<u32> = (0..n)
                        .flat_map(|s| rings.vertices[s][rho - 1][..rho].to_vec())
                        .collect();
                    assert_eq!(all.len(), n * rho);
                    for (i, &x) in all.iter().enumerate() {
                        let y = all[(i + 1) % all.len()];
                        assert!(m.one_ring(x).contains(&y), "{name}: ring {rho}");
                    }
                    all.sort_unstable();
                    all.dedup();
                    assert_eq!(all.len(), n * rho, "{name}: ring {rho} distinct");
                }
            }
        }
    }
}
