//! The generalized (half-)box-spline surface [UP §2, §3]: one Bézier patch of degree `d` for
//! every face of the prepared net whose subnet is regular, none for the others (the holes).
//!
//! Box splines (even k) take their control points at the net's vertices. Half-box splines
//! (odd k) take them at the vertices of the hexagonal dual net, which are placed at the face
//! centroids of the triangle net; an irregular (n-sided) mesh of the dual net is then exactly
//! an irregular vertex of the triangle net.

use std::collections::{HashMap, VecDeque};

use glam::DVec3;
use rayon::prelude::*;

use crate::bezier::TriangleBezier;
use crate::mesh::Mesh;
use crate::schemes::gk::box_spline::{ControlSite, Family, PatchStencil};
use crate::schemes::gk::chart::{Chart, chart, face_of};
use crate::schemes::gk::sector::coalesced_rings;

/// Chart radius of a patch's subnet: `k/2` for box splines, `(k+1)/2` for half-box splines
/// (the corners of the triangles that reach within `(k−1)/2` of the patch).
pub(crate) fn subnet_radius(k: usize) -> i32 {
    match Family::for_order(k) {
        Family::Box { m } => m as i32 - 1,
        Family::HalfBox { m } => m as i32 - 1,
    }
}

/// The control points patches are built from: vertex positions (even k) or dual points at
/// the face centroids (odd k), with the rings around each irregular vertex coalesced into
/// its multiple vertex [UP §2, §3] (see [`crate::schemes::gk::sector::coalesced_rings`]).
///
/// The vertices within `k/2 − 1` (even k) resp. `(k−1)/2` (odd k) edges of an irregular
/// vertex move to its multiple vertex (placed by [`crate::schemes::gk::hole::placed_multiple`]
/// where rings coalesce, k ≥ 3; the irregular vertex itself for k ≤ 2). For half-box
/// splines the dual points are then the centroids of the faces of this coalesced net: the
/// hexagonal net is the dual of a triangle net with coalesced rings, exactly as the plane
/// parametrization is the dual of the Fig. 4.1 net [UP §4]. So the n-gon's own dual points
/// coincide in the multiple vertex and the surface ring has the structure of the planar
/// ring, which `q ∘ x` then matches (coalescing whole dual rings instead, as UP §3 may be
/// read, leaves the surface ring without a planar counterpart: on the deformed icosahedron at
/// k = 3, `max |q ∘ x − r|` over the ring's Bézier points was 62% of q's quadratic
/// coefficients times the ring radius squared, against 3% for the primal coalescing).
pub(crate) struct ControlNet<'a> {
    mesh: &'a Mesh,
    /// Control points at the vertices (even k), and the corners the dual points average.
    positions: Vec<DVec3>,
    /// Control points at the faces (odd k).
    centroids: Vec<DVec3>,
    /// The multiple vertex of each irregular vertex.
    multiple: HashMap<u32, DVec3>,
}

impl<'a> ControlNet<'a> {
    /// The control net of `mesh` for smoothness order `k`, each multiple vertex at its
    /// irregular vertex.
    pub(crate) fn new(mesh: &'a Mesh, k: usize) -> Self {
        let multiple = (0..mesh.vertex_count() as u32)
            .filter(|&v| mesh.valence(v) != 6)
            .map(|v| (v, mesh.positions()[v as usize]))
            .collect();
        Self::with_multiples(mesh, k, multiple)
    }

    /// The control net with the coalesced rings of each irregular vertex at `multiple[v]`.
    pub(crate) fn with_multiples(mesh: &'a Mesh, k: usize, multiple: HashMap<u32, DVec3>) -> Self {
        let mut positions = mesh.positions().to_vec();
        let mut irregular: Vec<u32> = multiple.keys().copied().collect();
        irregular.sort_unstable();
        let rings = coalesced_rings(k);
        let (owner, dist) = distances(mesh, &irregular, rings + 1);
        for v in 0..mesh.vertex_count() {
            if dist[v] <= rings {
                positions[v] = multiple[&owner[v]];
            }
        }
        let centroids = mesh
            .faces()
            .iter()
            .map(|f| dual_point(f.map(|c| positions[c as usize])))
            .collect();
        ControlNet {
            mesh,
            positions,
            centroids,
            multiple,
        }
    }

    /// The control point at vertex `v` (even k).
    pub(crate) fn vertex(&self, v: u32) -> DVec3 {
        self.positions[v as usize]
    }

    /// The multiple vertex of irregular vertex `v`.
    pub(crate) fn multiple(&self, v: u32) -> Option<DVec3> {
        self.multiple.get(&v).copied()
    }

    /// The control point at `site` of `chart`, if the chart holds it.
    pub(crate) fn value(&self, chart: &Chart, site: ControlSite) -> Option<DVec3> {
        match site {
            ControlSite::Vertex(p) => chart.get(&p).map(|&v| self.positions[v as usize]),
            ControlSite::Face(f) => {
                let [x, y, z] = f.corners().map(|c| chart.get(&c).copied());
                let face = face_of(self.mesh, x?, y?, z?)?;
                Some(self.centroids[face as usize])
            }
        }
    }
}

/// The dual point of a triangle with these corner control points: its centroid.
pub(crate) fn dual_point(corners: [DVec3; 3]) -> DVec3 {
    (corners[0] + corners[1] + corners[2]) / 3.0
}

/// For every vertex, the nearest of `sources` and the distance to it in edges (`usize::MAX`
/// beyond `depth`).
fn distances(mesh: &Mesh, sources: &[u32], depth: usize) -> (Vec<u32>, Vec<usize>) {
    let mut dist = vec![usize::MAX; mesh.vertex_count()];
    let mut owner = vec![u32::MAX; mesh.vertex_count()];
    let mut queue: VecDeque<u32> = sources.iter().copied().collect();
    for &s in sources {
        dist[s as usize] = 0;
        owner[s as usize] = s;
    }
    while let Some(v) = queue.pop_front() {
        if dist[v as usize] >= depth {
            continue;
        }
        for &w in mesh.one_ring(v) {
            if dist[w as usize] == usize::MAX {
                dist[w as usize] = dist[v as usize] + 1;
                owner[w as usize] = owner[v as usize];
                queue.push_back(w);
            }
        }
    }
    (owner, dist)
}

/// The patch of every face of `mesh` (`None` where the subnet is irregular), in face order.
pub(crate) fn regular_patches(net: &ControlNet, k: usize) -> Vec<Option<TriangleBezier>> {
    let stencil = PatchStencil::reference(k, true);
    let mesh = net.mesh;
    let radius = subnet_radius(k);
    mesh.faces()
        .par_iter()
        .map(|face| {
            let chart = chart(mesh, *face, radius)?;
            let mut complete = true;
            let points = stencil.apply(|site| {
                net.value(&chart, site).unwrap_or_else(|| {
                    complete = false;
                    DVec3::ZERO
                })
            });
            complete.then(|| TriangleBezier::new(stencil.degree, points))
        })
        .collect()
}
