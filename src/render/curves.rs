//! The curve network of a surface as polylines for the tube overlay [HB00 §3 Fig. 2, §9 Fig. 14]:
//! the boundary curves (images of the mesh edges) and, for Bézier schemes, their control
//! polygons.
//!
//! A mesh edge `a → b` is located on the surface of its first face exactly as the undulation
//! measure does (`metrics::network`): the face-barycentric segment from corner `a` to corner `b`
//! is mapped through [`Surface::locate`], so every scheme (one patch per face or a split face)
//! gets its network. Control polygons are the boundary rows of the patches whose edges lie on
//! the mesh edge, reduced in degree while the reduction is exact, so a curve built at a lower
//! degree and degree-elevated into the patch shows its own polygon (Loop's quartic boundary in a
//! sextic patch, HB00's cubic halves in quintic patches).

use glam::DVec3;

use crate::mesh::{Mesh, MeshEdge};
use crate::render::tubes::{CurveKind, Polyline};
use crate::surface::{Patch, Surface};
use crate::tolerance::DOMAIN_ZERO;

/// Dense samples per boundary curve (segments of its polyline).
pub(crate) const CURVE_SEGMENTS: usize = 48;

/// Relative size (to the polygon's extent) below which a degree reduction counts as exact:
/// what inverse elevation leaves of f64 round-off for degrees ≤ 8.
pub(crate) const EXACT_REDUCTION_REL: f64 = 1e-12;

/// Default tube radius relative to the bounding-box diagonal of the surface.
pub(crate) const DEFAULT_RADIUS_REL: f64 = 0.003;

/// Which curves the overlay draws and how thick.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurveOverlay {
    /// The boundary curves (images of the mesh edges).
    pub curves: bool,
    /// Their Bézier control polygons (Bézier schemes).
    pub control_polygons: bool,
    /// Tube radius relative to the surface's bounding-box diagonal.
    pub radius_rel: f64,
    /// Only this mesh edge (index into [`Mesh::edges`]).
    pub edge: Option<usize>,
}

impl Default for CurveOverlay {
    fn default() -> Self {
        CurveOverlay {
            curves: false,
            control_polygons: false,
            radius_rel: DEFAULT_RADIUS_REL,
            edge: None,
        }
    }
}

impl CurveOverlay {
    /// True if anything is drawn.
    pub fn enabled(&self) -> bool {
        self.curves || self.control_polygons
    }

    /// The tubes of this overlay on `surface` (None when nothing is drawn).
    pub fn tubes(
        &self,
        surface: &Surface,
        mesh: &Mesh,
    ) -> crate::Result<Option<std::sync::Arc<crate::render::tubes::Tubes>>> {
        if !self.enabled() {
            return Ok(None);
        }
        let lines =
            network_polylines(surface, mesh, self.curves, self.control_polygons, self.edge)?;
        let radius = self.radius_rel * surface.bounds().diagonal();
        Ok(Some(std::sync::Arc::new(crate::render::tubes::Tubes::new(
            &lines, radius,
        )?)))
    }
}

/// Unit barycentric vector of face corner `c`.
fn corner(c: usize) -> DVec3 {
    let mut e = [0.0; 3];
    e[c] = 1.0;
    DVec3::from_array(e)
}

/// Face corners of the edge's end points in its first face.
fn edge_corners(mesh: &Mesh, edge: &MeshEdge) -> Option<(u32, usize, usize)> {
    let face = edge.faces.0;
    let corners = mesh.faces().get(face as usize)?;
    let ca = corners.iter().position(|&v| v == edge.a)?;
    let cb = corners.iter().position(|&v| v == edge.b)?;
    Some((face, ca, cb))
}

/// The boundary curve of `edge` sampled at `CURVE_SEGMENTS + 1` points from vertex `a` to `b`,
/// `None` if part of the edge is not covered by a patch of its face.
pub(crate) fn boundary_curve(
    surface: &Surface,
    face_patches: &[Vec<u32>],
    mesh: &Mesh,
    edge: &MeshEdge,
) -> Option<Vec<DVec3>> {
    let (face, ca, cb) = edge_corners(mesh, edge)?;
    let (ea, eb) = (corner(ca), corner(cb));
    (0..=CURVE_SEGMENTS)
        .map(|i| {
            let t = i as f64 / CURVE_SEGMENTS as f64;
            let (pi, uv) = surface.locate(face_patches, face, ea + t * (eb - ea))?;
            Some(surface.patches[pi as usize].eval(uv.x, uv.y))
        })
        .collect()
}

/// The control points of edge `e` of a Bézier patch (corner e → corner e+1).
fn patch_edge_points(patch: &Patch, e: usize) -> Option<Vec<DVec3>> {
    let b = patch.as_bezier()?;
    let d = b.degree();
    let at = |i: usize, j: usize| b.point(i, j);
    Some(
        (0..=d)
            .map(|s| match e {
                0 => at(d - s, s),
                1 => at(0, d - s),
                _ => at(s, 0),
            })
            .collect(),
    )
}

/// The control polygons of the patch edges that lie on `edge` (in its first face), each
/// reduced by [`reduce_exact`]; ordered along the edge from `a` to `b` and oriented that way.
pub(crate) fn control_polygons(
    surface: &Surface,
    face_patches: &[Vec<u32>],
    mesh: &Mesh,
    edge: &MeshEdge,
) -> Vec<Vec<DVec3>> {
    let Some((face, ca, cb)) = edge_corners(mesh, edge) else {
        return Vec::new();
    };
    let off = 3 - ca - cb;
    let mut pieces: Vec<(f64, Vec<DVec3>)> = Vec::new();
    for &pi in face_patches.get(face as usize).map_or(&[][..], |v| v) {
        let patch = &surface.patches[pi as usize];
        for e in 0..3 {
            let (s, t) = (patch.domain[e], patch.domain[(e + 1) % 3]);
            // On the mesh edge: the weight of the opposite face corner vanishes at both ends.
            if s[off].abs() > DOMAIN_ZERO || t[off].abs() > DOMAIN_ZERO {
                continue;
            }
            let Some(mut points) = patch_edge_points(patch, e) else {
                continue;
            };
            // Position along a → b is the weight of b; orient the polygon from a to b.
            let (ws, wt) = (s[cb], t[cb]);
            if ws > wt {
                points.reverse();
            }
            pieces.push((ws.min(wt), reduce_exact(&points)));
        }
    }
    pieces.sort_by(|x, y| x.0.total_cmp(&y.0));
    pieces.into_iter().map(|(_, p)| p).collect()
}

/// One step of exact degree reduction: the degree n−1 polygon whose elevation is `points`, if
/// there is one (inverse elevation from the first point, checked at the last).
pub(crate) fn reduce_once(points: &[DVec3]) -> Option<Vec<DVec3>> {
    let n = points.len().checked_sub(1)?;
    if n < 2 {
        return None;
    }
    let nf = n as f64;
    // Elevation: P_i = (i/n) Q_{i−1} + (1 − i/n) Q_i, solved for Q_i left to right.
    let mut reduced = Vec::with_capacity(n);
    reduced.push(points[0]);
    for i in 1..n {
        let w = i as f64 / nf;
        let q = (points[i] - w * reduced[i - 1]) / (1.0 - w);
        reduced.push(q);
    }
    let extent = points
        .iter()
        .map(|p| (*p - points[0]).length())
        .fold(0.0, f64::max);
    let miss = (points[n] - reduced[n - 1]).length();
    (miss <= EXACT_REDUCTION_REL * extent.max(f64::MIN_POSITIVE)).then_some(reduced)
}

/// `points` reduced in degree as long as the reduction is exact.
pub(crate) fn reduce_exact(points: &[DVec3]) -> Vec<DVec3> {
    let mut current = points.to_vec();
    while let Some(lower) = reduce_once(&current) {
        current = lower;
    }
    current
}

/// The polylines of the overlay: boundary curves and/or control polygons of every mesh edge, or
/// of edge `only` alone.
pub(crate) fn network_polylines(
    surface: &Surface,
    mesh: &Mesh,
    curves: bool,
    polygons: bool,
    only: Option<usize>,
) -> crate::Result<Vec<Polyline>> {
    let edges = mesh.edges();
    if let Some(e) = only
        && e >= edges.len()
    {
        return Err(crate::Error::Invalid(format!(
            "edge {e} does not exist (the mesh has {} edges)",
            edges.len()
        )));
    }
    let face_patches = surface.patches_by_face(mesh.face_count());
    let mut out = Vec::new();
    for (k, edge) in edges.iter().enumerate() {
        if only.is_some_and(|e| e != k) {
            continue;
        }
        if curves && let Some(points) = boundary_curve(surface, &face_patches, mesh, edge) {
            out.push(Polyline {
                edge: k,
                kind: CurveKind::Network,
                points,
            });
        }
        if polygons {
            for points in control_polygons(surface, &face_patches, mesh, edge) {
                out.push(Polyline {
                    edge: k,
                    kind: CurveKind::ControlPolygon,
                    points,
                });
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bezier::curve::CurveBezier;
    use crate::mesh::generate::icosahedron;
    use crate::schemes;

    fn icosahedron_mesh() -> Mesh {
        crate::testing::mesh(icosahedron())
    }

    #[test]
    fn exact_reduction_undoes_elevation_and_stops_at_the_true_degree() {
        let quartic = CurveBezier::new(vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(0.3, 0.7, -0.2),
            DVec3::new(0.5, -0.4, 0.9),
            DVec3::new(1.1, 0.2, 0.1),
            DVec3::new(1.4, 0.0, -0.3),
        ]);
        let sextic = quartic.elevate().elevate();
        let reduced = reduce_exact(sextic.points());
        assert_eq!(reduced.len(), 5, "back to the quartic");
        for (r, q) in reduced.iter().zip(quartic.points()) {
            assert!((*r - *q).length() <= 1e-14, "{r} vs {q}");
        }
        // A genuine quartic cannot be reduced.
        assert!(reduce_once(quartic.points()).is_none());
    }

    #[test]
    fn loop94_polygons_are_quartic_and_hb_polygons_are_two_cubics() {
        let mesh = icosahedron_mesh();
        let edge = mesh.edges()[0];
        let loop94 = schemes::build("loop94", &mesh, &[]).expect("loop94");
        let fp = loop94.patches_by_face(mesh.face_count());
        let polygons = control_polygons(&loop94, &fp, &mesh, &edge);
        assert_eq!(polygons.len(), 1);
        assert_eq!(
            polygons[0].len(),
            5,
            "Loop's boundary curves are quartic [HB00 eq. 2]"
        );
        let hb = schemes::build("hb", &mesh, &[]).expect("hb");
        let fp = hb.patches_by_face(mesh.face_count());
        let polygons = control_polygons(&hb, &fp, &mesh, &edge);
        assert_eq!(polygons.len(), 2, "two patch edges per mesh edge");
        let p = mesh.positions();
        let (a, b) = (p[edge.a as usize], p[edge.b as usize]);
        // Oriented and ordered from a to b, meeting in the middle.
        assert!((polygons[0][0] - a).length() < 1e-12);
        assert!((polygons[1].last().copied().expect("point") - b).length() < 1e-12);
        assert!((polygons[0].last().copied().expect("point") - polygons[1][0]).length() < 1e-12);
        for poly in &polygons {
            assert_eq!(poly.len(), 4, "HB00's boundary halves are cubic [HB00 §9]");
        }
    }

    #[test]
    fn boundary_curves_run_from_vertex_to_vertex_through_the_polygon_curve() {
        let mesh = icosahedron_mesh();
        let surface = schemes::build("loop94", &mesh, &[]).expect("loop94");
        let lines = network_polylines(&surface, &mesh, true, true, None).expect("lines");
        let edges = mesh.edges();
        assert_eq!(lines.len(), 2 * edges.len());
        let p = mesh.positions();
        let fp = surface.patches_by_face(mesh.face_count());
        for (k, edge) in edges.iter().enumerate() {
            let curve = boundary_curve(&surface, &fp, &mesh, edge).expect("curve");
            let scale = (p[edge.a as usize] - p[edge.b as usize]).length();
            assert!(
                (curve[0] - p[edge.a as usize]).length() <= 1e-12 * scale,
                "edge {k}"
            );
            assert!((curve[CURVE_SEGMENTS] - p[edge.b as usize]).length() <= 1e-12 * scale);
            // The sampled curve is the Bézier curve of its (reduced) control polygon.
            let polygon = CurveBezier::new(control_polygons(&surface, &fp, &mesh, edge).remove(0));
            for (i, q) in curve.iter().enumerate() {
                let t = i as f64 / CURVE_SEGMENTS as f64;
                assert!(
                    (polygon.eval(t) - *q).length() <= 1e-12 * scale,
                    "edge {k} t {t}"
                );
            }
        }
        assert!(network_polylines(&surface, &mesh, true, false, Some(edges.len())).is_err());
    }
}
