//! The generalized (half-)box-spline surface [UP §2, §3]: one Bézier patch of degree `d` for
//! every face of the prepared net whose subnet is regular, none for the others (the holes).
//!
//! Box splines (even k) take their control points at the net's vertices. Half-box splines
//! (odd k) take them at the vertices of the hexagonal dual net, which are placed at the face
//! centroids of the triangle net; an irregular (n-sided) mesh of the dual net is then exactly
//! an irregular vertex of the triangle net.

use glam::DVec3;
use rayon::prelude::*;

use crate::bezier::TriangleBezier;
use crate::mesh::Mesh;
use crate::schemes::gk::box_spline::{ControlSite, Family, GridTriangle, PatchStencil};
use crate::schemes::gk::chart::{Chart, chart, face_of};

/// Chart radius of a patch's subnet: `k/2` for box splines, `(k+1)/2` for half-box splines
/// (the corners of the triangles that reach within `(k−1)/2` of the patch).
pub fn subnet_radius(k: usize) -> i32 {
    match Family::for_order(k) {
        Family::Box { m } => m as i32 - 1,
        Family::HalfBox { m } => m as i32 - 1,
    }
}

/// The control points a patch is built from: vertex positions or dual (face-centroid) points.
pub struct ControlNet<'a> {
    mesh: &'a Mesh,
    centroids: Vec<DVec3>,
}

impl<'a> ControlNet<'a> {
    /// The control net of `mesh` for smoothness order `k`.
    pub fn new(mesh: &'a Mesh, k: usize) -> Self {
        let centroids = if !k.is_multiple_of(2) {
            mesh.faces()
                .iter()
                .map(|f| {
                    f.iter()
                        .map(|&v| mesh.positions()[v as usize])
                        .sum::<DVec3>()
                        / 3.0
                })
                .collect()
        } else {
            Vec::new()
        };
        ControlNet { mesh, centroids }
    }

    /// The control point at `site` of `chart`, if the chart holds it.
    pub fn value(&self, chart: &Chart, site: ControlSite) -> Option<DVec3> {
        match site {
            ControlSite::Vertex(p) => chart.get(&p).map(|&v| self.mesh.positions()[v as usize]),
            ControlSite::Face(f) => {
                let [x, y, z] = f.corners().map(|c| chart.get(&c).copied());
                let face = face_of(self.mesh, x?, y?, z?)?;
                Some(self.centroids[face as usize])
            }
        }
    }
}

/// The patch of every face of `mesh` (`None` where the subnet is irregular), in face order.
pub fn regular_patches(mesh: &Mesh, k: usize) -> Vec<Option<TriangleBezier>> {
    let stencil = PatchStencil::new(k, GridTriangle::UP);
    let net = ControlNet::new(mesh, k);
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
