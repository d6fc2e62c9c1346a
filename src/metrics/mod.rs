//! How smooth is a surface, really? Figures measured on a built [`Surface`] against the mesh
//! it was built from, for every scheme alike:
//!
//! * along every joint of two patch edges ([`Surface::joints`], sampled as described in
//!   [`joints`]): the G0 gap, the normal-angle jump (max and mean; separately for joints
//!   between mesh faces and inside a face) and the relative jumps of Gaussian and mean
//!   curvature;
//! * at every patch corner that sits on a mesh vertex ([`Surface::vertex_corners`]): the
//!   interpolation error;
//! * on a grid over every patch: the regularity `min |Su × Sv| / mean |Su × Sv|`, and the
//!   folds: samples where the patch's normal points against its face's normal.
//!
//! Lengths are relative to the bounding-box diagonal of the mesh vertices. The result
//! serialises to the metrics JSON of docs/guide/contracts.md. Joints and patches are measured in parallel;
//! the per-item results are collected in order and reduced sequentially, so every figure
//! (including the mean) is bit-for-bit the same for any thread count.

pub(crate) mod continuity;
#[cfg(test)]
pub(crate) mod double_double;
pub(crate) mod energy;
pub(crate) mod joints;
pub(crate) mod network;
pub(crate) mod patchwise;
pub(crate) mod vertex_curvature;

use std::collections::BTreeMap;

use glam::DVec3;
use rayon::prelude::*;
use serde::Serialize;

use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::surface::{LocalFrame, Surface};

pub use crate::surface::JOINT_SAMPLES;
pub use continuity::joint_order;
pub use joints::{CurvatureFloor, JointStats, normal_angle};
pub use network::network_undulation;
pub use vertex_curvature::vertex_curvature;

/// The keys every object of the metrics JSON has: the contract in docs/guide/contracts.md (`continuity_order`
/// included) and the regularity figure. Tools reading the JSON may rely on them.
pub const CONTRACT_KEYS: [&str; 14] = [
    "scheme",
    "params",
    "faces",
    "patches",
    "construct_ms",
    "interp_max_rel",
    "g0_max_rel",
    "g1_max_rad",
    "g1_mean_rad",
    "g1_between_faces_max_rad",
    "g1_inside_faces_max_rad",
    "curvature_jump_max_rel",
    "continuity_order",
    "min_regularity_rel",
];

/// The measured figures of one surface (one scheme on one mesh). Field names are the keys of
/// the metrics JSON contract (docs/guide/contracts.md). Figures over an empty set (e.g. joints inside
/// faces, for a scheme with one patch per face) are `None`, written as `null`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Metrics {
    /// Scheme name.
    pub scheme: String,
    /// The scheme's parameters, defaults filled in.
    pub params: BTreeMap<String, String>,
    /// Number of mesh faces.
    pub faces: usize,
    /// Number of patches.
    pub patches: usize,
    /// Wall-clock time of the construction, in milliseconds.
    pub construct_ms: f64,
    /// Largest `|S(corner) − vertex|` over patch corners on mesh vertices, relative to the
    /// bounding-box diagonal.
    pub interp_max_rel: Option<f64>,
    /// Largest gap between the two sides of a joint, relative to the diagonal.
    pub g0_max_rel: Option<f64>,
    /// Largest normal-angle jump over all joints (rad).
    pub g1_max_rad: Option<f64>,
    /// Mean normal-angle jump over all regular joint samples (rad).
    pub g1_mean_rad: Option<f64>,
    /// Largest normal-angle jump over joints between different mesh faces (rad).
    pub g1_between_faces_max_rad: Option<f64>,
    /// Largest normal-angle jump over joints inside one mesh face (rad).
    pub g1_inside_faces_max_rad: Option<f64>,
    /// Largest normal-angle jump over the joint samples where rounding does not account for
    /// it (rad): samples whose angle is within the rounding of the f64 nets and their
    /// evaluation ([`joints::normal_rounding`], large only near a singular point of the
    /// parametrisation) count 0. What a G1 scheme must keep ≤ 1e-9 rad.
    pub g1_beyond_rounding_max_rad: Option<f64>,
    /// Largest relative jump of Gaussian or mean curvature over all joints
    /// (see [`CurvatureFloor`] for the floor of the relative measure).
    pub curvature_jump_max_rel: Option<f64>,
    /// Largest relative jump of the Gaussian curvature.
    pub gaussian_jump_max_rel: Option<f64>,
    /// Largest relative jump of the mean curvature.
    pub mean_jump_max_rel: Option<f64>,
    /// Smallest `min |Su × Sv| / mean |Su × Sv|` over the patches (0 = a singular point).
    pub min_regularity_rel: Option<f64>,
    /// Largest undulation of one boundary curve, turning against its overall bending (rad;
    /// see [`network`]).
    pub network_undulation_max_rad: f64,
    /// Sum of the boundary-curve undulations (rad).
    pub network_undulation_total_rad: f64,
    /// Largest number of inflections of one boundary curve in its chord plane.
    pub network_inflections_max: usize,
    /// Boundary curves with at least one inflection.
    pub network_curves_with_inflections: usize,
    /// Largest distance of a boundary curve from its chord, relative to the chord length.
    pub network_chord_deviation_max_rel: f64,
    /// The lowest measured geometric continuity order over all joints ([`continuity`]; −1 = a
    /// gap, up to [`continuity::MAX_ORDER`]).
    pub continuity_order: Option<i32>,
    /// The lowest order over joints between mesh faces.
    pub continuity_order_between_faces: Option<i32>,
    /// The lowest order over joints inside a mesh face.
    pub continuity_order_inside_faces: Option<i32>,
    /// The most common joint order (ties: the lower).
    pub continuity_order_typical: Option<i32>,
    /// Number of joints (pairs of patch edges) measured.
    pub joints: usize,
    /// Of which between different mesh faces.
    pub joints_between_faces: usize,
    /// Samples taken along each joint.
    pub samples_per_joint: usize,
    /// Joint samples where a side has `Su × Sv = 0`, left out of the G1 and curvature figures.
    pub singular_samples: usize,
    /// Samples where a patch's normal points against its mesh face's normal: the surface
    /// folds back over its face there ([`patchwise::folds`], on the regularity grid of
    /// every patch). 0 for a surface that follows its mesh.
    pub folds: usize,
    /// Patches with at least one such sample.
    pub folded_patches: usize,
    /// Mesh vertices where the mesh is curved but the surface has a flat point (both principal
    /// curvatures ~0; see [`vertex_curvature()`]).
    pub vertex_flat_points: usize,
    /// Mesh vertices where the mesh is curved (those the vertex figures are measured at).
    pub vertex_curved: usize,
    /// Smallest ratio `|H| / |H_mesh|` of the surface's mean curvature at a mesh vertex to the
    /// mesh's discrete one ([`vertex_curvature()`]; 1 on a sphere reproduced exactly).
    pub vertex_mean_curvature_ratio_min: Option<f64>,
    /// Largest ratio `|H| / |H_mesh|`.
    pub vertex_mean_curvature_ratio_max: Option<f64>,
    /// Joints along the mesh's sharp edges ([`crate::mesh::SharpEdges`]): counted in
    /// `joints` and in `g0_max_rel`, but left out of every G1, curvature-jump and
    /// continuity-order figure, which measure the smooth joints only.
    pub sharp_joints: usize,
    /// Of the sharp edges, those the construction made sharp where its smooth surface folded,
    /// at spikes of the mesh and round the faces that still folded
    /// ([`Surface::spike_face_pairs`]); their joints are among `sharp_joints`. 0 on most
    /// meshes.
    pub spike_edges: usize,
    /// Largest gap between the two sides of a sharp joint, relative to the diagonal (G0
    /// across the creases; `None` without sharp edges).
    pub sharp_g0_max_rel: Option<f64>,
    /// Largest normal angle across a sharp joint (rad): the crease as built.
    pub sharp_g1_max_rad: Option<f64>,
    /// The repairs loading made to the mesh ([`crate::mesh::Mesh::repairs`]): each with its
    /// `kind`, `count`, `first` element in the input's numbering and `detail`. Empty for a
    /// mesh that loaded as written.
    pub repairs: Vec<crate::mesh::Repair>,
}

/// The face pairs `(f, g)`, `f < g`, sorted, across the sharp edges of `mesh` and the edges
/// the construction of `surface` (built on `mesh`) made sharp at spikes
/// ([`Surface::spike_face_pairs`]): the joints where the surface is G0 by design.
pub(crate) fn sharp_face_pairs(surface: &Surface, mesh: &Mesh) -> Vec<(u32, u32)> {
    let mut pairs = mesh.sharp_face_pairs();
    pairs.extend_from_slice(&surface.spike_face_pairs);
    pairs.sort_unstable();
    pairs.dedup();
    pairs
}

impl Metrics {
    /// Measures `surface`, built from `mesh` in `construct_ms` milliseconds (both in the
    /// user's coordinates).
    pub fn measure(surface: &Surface, mesh: &Mesh, construct_ms: f64) -> Metrics {
        let factor = unit_scale(mesh.positions());
        Self::measure_local(&surface.scaled(factor), &mesh.scaled(factor), construct_ms)
    }

    /// Measures `surface` given in the local `frame` of `mesh` (as
    /// [`crate::schemes::build_in_frame`] returns it; `mesh` in the user's coordinates): the
    /// mesh is mapped into the frame, so the figures do not depend on where the mesh lies or
    /// on its power-of-two scale. Every length figure is relative to the diagonal, so it is
    /// the same in the user's units.
    pub fn measure_in_frame(
        surface: &Surface,
        frame: &LocalFrame,
        mesh: &Mesh,
        construct_ms: f64,
    ) -> Metrics {
        Self::measure_local(
            surface,
            &mesh.framed(frame.centre, frame.scale),
            construct_ms,
        )
    }

    /// [`Metrics::measure`] on a surface and mesh whose diagonal is already in `[1, 2)`.
    fn measure_local(surface: &Surface, mesh: &Mesh, construct_ms: f64) -> Metrics {
        let network = network::network_undulation(surface, mesh);
        Metrics {
            network_undulation_max_rad: network.undulation_max_rad,
            network_undulation_total_rad: network.undulation_total_rad,
            network_inflections_max: network.inflections_max,
            network_curves_with_inflections: network.curves_with_inflections,
            network_chord_deviation_max_rel: network.chord_deviation_max_rel,
            repairs: mesh.repairs().to_vec(),
            ..Self::measure_normalised(
                surface,
                mesh.faces(),
                Some(&mesh.edge_ids()),
                mesh.positions(),
                &sharp_face_pairs(surface, mesh),
                construct_ms,
            )
        }
    }

    /// Measures `surface` against the mesh given as `faces` over `positions` (the form used
    /// by [`Metrics::measure`]; hand-made surfaces in tests use it directly). The curve-network
    /// figures need the mesh topology and are left at zero here, and mesh edges are known by
    /// their two vertices (see [`Surface::joints`]).
    pub fn measure_faces(
        surface: &Surface,
        faces: &[[u32; 3]],
        positions: &[DVec3],
        construct_ms: f64,
    ) -> Metrics {
        let factor = unit_scale(positions);
        let positions: Vec<DVec3> = positions.iter().map(|&p| p * factor).collect();
        Self::measure_normalised(
            &surface.scaled(factor),
            faces,
            None,
            &positions,
            &[],
            construct_ms,
        )
    }

    /// [`Metrics::measure_faces`] on a surface and mesh already scaled by [`unit_scale`];
    /// `edge_ids` number the mesh edges for [`Surface::joints`]; `sharp` are the face pairs `(f, g)`, `f < g`, across sharp edges, sorted (their joints
    /// are measured apart).
    fn measure_normalised(
        surface: &Surface,
        faces: &[[u32; 3]],
        edge_ids: Option<&[u32]>,
        positions: &[DVec3],
        sharp: &[(u32, u32)],
        construct_ms: f64,
    ) -> Metrics {
        let diag = diagonal(positions);
        let floor = CurvatureFloor::for_diagonal(diag);
        let all_joints = surface.joints(faces, edge_ids);
        let is_sharp = |j: &crate::surface::Joint| {
            let f = surface.patches[j.a.patch as usize].face;
            let g = surface.patches[j.b.patch as usize].face;
            j.between_faces && sharp.binary_search(&(f.min(g), f.max(g))).is_ok()
        };
        let (sharp_list, joint_list): (Vec<_>, Vec<_>) =
            all_joints.into_iter().partition(|j| is_sharp(j));
        let per_joint: Vec<JointStats> = joint_list
            .par_iter()
            .map(|j| joints::measure_joint(surface, j, floor))
            .collect();
        let per_sharp_joint: Vec<JointStats> = sharp_list
            .par_iter()
            .map(|j| joints::measure_joint(surface, j, floor))
            .collect();
        let sums = JointSums::reduce(&per_joint);
        let sharp_sums = JointSums::reduce(&per_sharp_joint);
        let orders: Vec<(bool, i32)> = joint_list
            .par_iter()
            .map(|j| (j.between_faces, continuity::joint_order(surface, j, diag)))
            .collect();
        let min_order = |keep: &dyn Fn(bool) -> bool| {
            orders
                .iter()
                .filter(|(b, _)| keep(*b))
                .map(|(_, o)| *o)
                .min()
        };
        let regularity = patchwise::min_regularity(surface);
        let folds = patchwise::folds(surface, faces, positions);
        let interp = patchwise::interpolation_error(surface, faces, positions);
        let at_vertices = vertex_curvature::vertex_curvature(surface, faces, positions);
        Metrics {
            scheme: surface.scheme.clone(),
            params: surface.params.iter().cloned().collect(),
            faces: faces.len(),
            patches: surface.patches.len(),
            construct_ms,
            interp_max_rel: interp.map(|e| e / diag),
            g0_max_rel: max_of(sums.gap_max, sharp_sums.gap_max).map(|g| g / diag),
            g1_max_rad: max_of(sums.angle_between, sums.angle_inside),
            g1_mean_rad: (sums.regular_samples > 0)
                .then(|| sums.angle_sum / sums.regular_samples as f64),
            g1_between_faces_max_rad: sums.angle_between,
            g1_inside_faces_max_rad: sums.angle_inside,
            g1_beyond_rounding_max_rad: sums.angle_beyond_rounding,
            curvature_jump_max_rel: max_of(sums.gaussian_jump, sums.mean_jump),
            gaussian_jump_max_rel: sums.gaussian_jump,
            mean_jump_max_rel: sums.mean_jump,
            min_regularity_rel: regularity,
            network_undulation_max_rad: 0.0,
            network_undulation_total_rad: 0.0,
            network_inflections_max: 0,
            network_curves_with_inflections: 0,
            network_chord_deviation_max_rel: 0.0,
            continuity_order: min_order(&|_| true),
            continuity_order_between_faces: min_order(&|b| b),
            continuity_order_inside_faces: min_order(&|b| !b),
            continuity_order_typical: typical_order(&orders),
            joints: per_joint.len() + per_sharp_joint.len(),
            joints_between_faces: per_joint.iter().filter(|j| j.between_faces).count()
                + per_sharp_joint.len(),
            samples_per_joint: JOINT_SAMPLES,
            singular_samples: sums.singular_samples + sharp_sums.singular_samples,
            folds: folds.samples,
            folded_patches: folds.patches,
            vertex_flat_points: at_vertices.flat_points,
            vertex_curved: at_vertices.curved_vertices,
            vertex_mean_curvature_ratio_min: at_vertices.mean_ratio_min,
            vertex_mean_curvature_ratio_max: at_vertices.mean_ratio_max,
            sharp_joints: per_sharp_joint.len(),
            spike_edges: surface.spike_face_pairs.len(),
            sharp_g0_max_rel: sharp_sums.gap_max.map(|g| g / diag),
            sharp_g1_max_rad: sharp_sums.angle_between,
            repairs: Vec::new(),
        }
    }
}

/// Bounding-box diagonal of the vertices; 1 for a degenerate (single-point) set so that
/// relative figures stay finite (a validated mesh never has one).
/// The power of two that brings the bounding-box diagonal of `positions` into `[1, 2)`.
///
/// Every figure is measured on the surface and mesh scaled by it, so that no product of
/// derivatives over- or underflows and every tolerance of the measurements is relative: a
/// mesh scaled by 1e50 or 1e-50 measures like the unscaled one. Scaling by a power of two is
/// exact, so the figures of a mesh of ordinary size do not change at all.
pub fn unit_scale(positions: &[DVec3]) -> f64 {
    let d = crate::geom::Aabb::from_points(positions).diagonal();
    if d > 0.0 && d.is_finite() {
        (-d.log2().floor()).exp2()
    } else {
        1.0
    }
}

fn diagonal(positions: &[DVec3]) -> f64 {
    let d = crate::geom::Aabb::from_points(positions).diagonal();
    if d > 0.0 && d.is_finite() { d } else { 1.0 }
}

impl Metrics {
    /// Every real-valued figure with its JSON key.
    fn figures(&self) -> [(&'static str, Option<f64>); 19] {
        [
            ("construct_ms", Some(self.construct_ms)),
            ("interp_max_rel", self.interp_max_rel),
            ("g0_max_rel", self.g0_max_rel),
            ("g1_max_rad", self.g1_max_rad),
            ("g1_mean_rad", self.g1_mean_rad),
            ("g1_between_faces_max_rad", self.g1_between_faces_max_rad),
            ("g1_inside_faces_max_rad", self.g1_inside_faces_max_rad),
            (
                "g1_beyond_rounding_max_rad",
                self.g1_beyond_rounding_max_rad,
            ),
            ("curvature_jump_max_rel", self.curvature_jump_max_rel),
            ("gaussian_jump_max_rel", self.gaussian_jump_max_rel),
            ("mean_jump_max_rel", self.mean_jump_max_rel),
            ("min_regularity_rel", self.min_regularity_rel),
            (
                "network_undulation_max_rad",
                Some(self.network_undulation_max_rad),
            ),
            (
                "network_undulation_total_rad",
                Some(self.network_undulation_total_rad),
            ),
            (
                "network_chord_deviation_max_rel",
                Some(self.network_chord_deviation_max_rel),
            ),
            (
                "vertex_mean_curvature_ratio_min",
                self.vertex_mean_curvature_ratio_min,
            ),
            (
                "vertex_mean_curvature_ratio_max",
                self.vertex_mean_curvature_ratio_max,
            ),
            ("sharp_g0_max_rel", self.sharp_g0_max_rel),
            ("sharp_g1_max_rad", self.sharp_g1_max_rad),
        ]
    }

    /// An error naming the first figure that is NaN or infinite (a table must never show
    /// NaN, nor the JSON `null` for a figure that was measured).
    pub fn check_finite(&self) -> Result<()> {
        match self
            .figures()
            .into_iter()
            .find_map(|(name, x)| x.filter(|x| !x.is_finite()).map(|x| (name, x)))
        {
            Some((name, value)) => Err(Error::NonFiniteResult {
                what: format!("metric {name} of scheme '{}'", self.scheme),
                value,
            }),
            None => Ok(()),
        }
    }
}

/// The most common order (the lower one on ties).
fn typical_order(orders: &[(bool, i32)]) -> Option<i32> {
    let mut counts: BTreeMap<i32, usize> = BTreeMap::new();
    for (_, o) in orders {
        *counts.entry(*o).or_default() += 1;
    }
    let most = counts.values().copied().max()?;
    counts.into_iter().find(|(_, c)| *c == most).map(|(o, _)| o)
}

fn max_of(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    match (a, b) {
        (Some(x), Some(y)) => Some(x.max(y)),
        (x, None) => x,
        (None, y) => y,
    }
}

/// The joint figures reduced over all joints, in joint order.
#[derive(Default)]
struct JointSums {
    gap_max: Option<f64>,
    angle_between: Option<f64>,
    angle_inside: Option<f64>,
    angle_beyond_rounding: Option<f64>,
    angle_sum: f64,
    regular_samples: usize,
    singular_samples: usize,
    gaussian_jump: Option<f64>,
    mean_jump: Option<f64>,
}

impl JointSums {
    fn reduce(per_joint: &[JointStats]) -> JointSums {
        let mut sums = JointSums::default();
        for j in per_joint {
            sums.gap_max = max_of(sums.gap_max, Some(j.gap_max));
            sums.singular_samples += j.singular_samples;
            if j.regular_samples == 0 {
                continue;
            }
            let slot = if j.between_faces {
                &mut sums.angle_between
            } else {
                &mut sums.angle_inside
            };
            *slot = max_of(*slot, Some(j.angle_max));
            sums.angle_beyond_rounding = max_of(
                sums.angle_beyond_rounding,
                Some(j.angle_beyond_rounding_max),
            );
            sums.angle_sum += j.angle_sum;
            sums.regular_samples += j.regular_samples;
            sums.gaussian_jump = max_of(sums.gaussian_jump, Some(j.gaussian_jump_max));
            sums.mean_jump = max_of(sums.mean_jump, Some(j.mean_jump_max));
        }
        sums
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bezier::TriangleBezier;
    use crate::surface::{Patch, PatchGeometry};
    use glam::DVec2;

    const E0: DVec3 = DVec3::X;
    const E1: DVec3 = DVec3::Y;
    const E2: DVec3 = DVec3::Z;

    fn bezier_patch(face: u32, piece: u8, domain: [DVec3; 3], b: TriangleBezier) -> Patch {
        Patch {
            face,
            piece,
            domain,
            geometry: PatchGeometry::Bezier(b),
        }
    }

    fn surface(patches: Vec<Patch>) -> Surface {
        Surface {
            scheme: "test".into(),
            warnings: Vec::new(),
            spike_face_pairs: Vec::new(),
            params: vec![("p".into(), "1".into())],
            patches,
        }
    }

    /// A cubic graph surface over the plane triangle (0,0), (1,0), (0,1) with irregular
    /// heights: one polynomial, so any pieces of it join with every continuity.
    fn cubic() -> TriangleBezier {
        let corner = [DVec2::ZERO, DVec2::X, DVec2::Y];
        TriangleBezier::from_fn(3, |i, j, k| {
            let xy = (i as f64 * corner[0] + j as f64 * corner[1] + k as f64 * corner[2]) / 3.0;
            let z = 0.3 * (1.3 * i as f64 + 0.7 * j as f64 * j as f64 + 2.1 * k as f64).sin();
            DVec3::new(xy.x, xy.y, z)
        })
    }

    /// Faces (A,B,C) and (C,B,D) of a parallelogram in the cubic's domain, D = B + C − A.
    /// Face 0 is split into two pieces from B to the midpoint of C–A; face 1 is one piece.
    /// Everything is a piece of one polynomial, so every joint is exactly smooth.
    fn pieces_of_one_polynomial() -> (Surface, Vec<[u32; 3]>, Vec<DVec3>) {
        let t = cubic();
        let (a, b, c) = (E0, E1, E2);
        let d = b + c - a;
        let mid_ca = 0.5 * (c + a);
        let positions = vec![t.eval(a), t.eval(b), t.eval(c), t.eval(d)];
        let faces = vec![[0, 1, 2], [2, 1, 3]];
        let patches = vec![
            bezier_patch(0, 0, [E1, E2, 0.5 * (E2 + E0)], t.subdivide([b, c, mid_ca])),
            bezier_patch(0, 1, [E1, 0.5 * (E2 + E0), E0], t.subdivide([b, mid_ca, a])),
            bezier_patch(1, 0, [E0, E1, E2], t.subdivide([c, b, d])),
        ];
        (surface(patches), faces, positions)
    }

    #[test]
    fn pieces_of_one_polynomial_measure_zero() {
        let (s, faces, positions) = pieces_of_one_polynomial();
        let m = Metrics::measure_faces(&s, &faces, &positions, 1.5);
        assert_eq!((m.joints, m.joints_between_faces), (2, 1), "{m:?}");
        assert!(
            m.interp_max_rel.expect("corners on vertices") <= 1e-15,
            "{m:?}"
        );
        assert!(m.g0_max_rel.expect("joints") <= 1e-15, "{m:?}");
        assert!(
            m.g1_between_faces_max_rad.expect("between") <= 1e-12,
            "{m:?}"
        );
        assert!(m.g1_inside_faces_max_rad.expect("inside") <= 1e-12, "{m:?}");
        assert!(m.g1_mean_rad.expect("samples") <= 1e-12, "{m:?}");
        assert!(
            m.curvature_jump_max_rel.expect("curvature") <= 1e-10,
            "{m:?}"
        );
        assert!(m.min_regularity_rel.expect("patches") > 0.1, "{m:?}");
        assert_eq!(m.singular_samples, 0);
        assert_eq!((m.faces, m.patches, m.construct_ms), (2, 3, 1.5));
        assert_eq!(m.params.get("p").map(String::as_str), Some("1"));
    }

    /// The pieces of one polynomial mapped by an affine map that squeezes them towards a
    /// line far from the origin: still one polynomial, so exactly G1, but `Su` and `Sv` are
    /// nearly parallel (their sine ~1e-7) and the points' rounding turns the computed normals
    /// by ~1e-8 rad. `G1_max` shows that; the figure beyond rounding is 0. A real kink of the
    /// same squeezed surface is counted in full.
    #[test]
    fn rounding_near_a_singular_parametrisation_is_told_from_a_kink() {
        let squeeze = |p: DVec3| {
            DVec3::new(0.6, -0.4, 0.8) + DVec3::new(p.x + p.y + p.z, 1e-7 * p.y, 1e-7 * p.z)
        };
        let measure = |kink: f64| {
            let (mut s, faces, positions) = pieces_of_one_polynomial();
            let PatchGeometry::Bezier(net) = &mut s.patches[2].geometry else {
                unreachable!("Bézier pieces")
            };
            // An inner point of the one-piece face, next to its joint with face 0.
            let p = net.point(1, 1);
            net.set_point(1, 1, p + kink * DVec3::Z);
            let squeezed = Surface {
                patches: s.patches.iter().map(|p| p.mapped(squeeze)).collect(),
                ..s
            };
            let positions: Vec<DVec3> = positions.into_iter().map(squeeze).collect();
            Metrics::measure_faces(&squeezed, &faces, &positions, 0.0)
        };
        let smooth = measure(0.0);
        let raw = smooth.g1_max_rad.expect("joints");
        assert!(raw > 1e-9, "rounding shows in the raw figure: {raw:e}");
        assert_eq!(smooth.g1_beyond_rounding_max_rad, Some(0.0), "{smooth:?}");
        let kinked = measure(1e-5);
        let kink = kinked.g1_between_faces_max_rad.expect("joints");
        assert!(kink > 100.0 * raw, "{kink:e} vs {raw:e}");
        assert_eq!(kinked.g1_beyond_rounding_max_rad, Some(kink), "{kinked:?}");
    }

    fn linear(points: [DVec3; 3]) -> TriangleBezier {
        TriangleBezier::new(1, points.to_vec())
    }

    /// Two planar triangles over the common edge 1–2 (the x axis), face 1 rotated by
    /// `theta` about it: the mesh's dihedral kink.
    fn hinge(theta: f64) -> (Vec<[u32; 3]>, Vec<DVec3>) {
        let positions = vec![
            DVec3::new(0.5, -1.0, 0.0),
            DVec3::ZERO,
            DVec3::X,
            DVec3::new(0.5, theta.cos(), theta.sin()),
        ];
        (vec![[0, 1, 2], [2, 1, 3]], positions)
    }

    fn flat_surface(faces: &[[u32; 3]], positions: &[DVec3]) -> Surface {
        let patches = faces
            .iter()
            .enumerate()
            .map(|(f, fv)| {
                let corners = fv.map(|v| positions[v as usize]);
                bezier_patch(f as u32, 0, [E0, E1, E2], linear(corners))
            })
            .collect();
        surface(patches)
    }

    #[test]
    fn kink_measures_the_dihedral_angle() {
        let theta = 0.3;
        let (faces, positions) = hinge(theta);
        let m = Metrics::measure_faces(&flat_surface(&faces, &positions), &faces, &positions, 0.0);
        // The two face normals are (0,0,−1) and (0, sin θ, −cos θ).
        let between = m.g1_between_faces_max_rad.expect("one joint");
        assert!((between - theta).abs() <= 1e-15, "{between}");
        assert!((m.g1_mean_rad.expect("samples") - theta).abs() <= 1e-15);
        assert_eq!(m.g1_max_rad, m.g1_between_faces_max_rad);
        assert_eq!(
            m.g1_beyond_rounding_max_rad, m.g1_max_rad,
            "a kink is no rounding"
        );
        assert_eq!(m.g1_inside_faces_max_rad, None, "no joint inside a face");
        assert!(m.g0_max_rel.expect("joint") <= 1e-16);
        assert_eq!(m.interp_max_rel, Some(0.0));
        // Planes: K = H = 0 on both sides, no jump.
        assert_eq!(m.curvature_jump_max_rel, Some(0.0));
        let r = m.min_regularity_rel.expect("patches");
        assert!((r - 1.0).abs() <= 1e-14, "{r}");
    }

    #[test]
    fn gap_is_measured_exactly() {
        let (faces, positions) = hinge(0.0);
        let mut s = flat_surface(&faces, &positions);
        let delta = 1e-3;
        let lifted = s.patches[1]
            .as_bezier()
            .expect("polynomial")
            .map_points(|p| p + DVec3::new(0.0, 0.0, delta));
        s.patches[1].geometry = PatchGeometry::Bezier(lifted);
        let m = Metrics::measure_faces(&s, &faces, &positions, 0.0);
        let diag = crate::geom::Aabb::from_points(&positions).diagonal();
        let gap = m.g0_max_rel.expect("joint") * diag;
        assert!((gap - delta).abs() <= 1e-12 * delta, "gap {gap}");
        assert!((m.interp_max_rel.expect("corners") * diag - delta).abs() <= 1e-12 * delta);
        // Parallel planes: normals agree exactly.
        assert_eq!(m.g1_max_rad, Some(0.0));
    }

    /// A patch parametrised against its face's orientation has the opposite normal: an
    /// honest jump of π.
    #[test]
    fn orientation_flip_is_a_jump_of_pi() {
        let (faces, positions) = hinge(0.0);
        let mut s = flat_surface(&faces, &positions);
        let fv = faces[1].map(|v| positions[v as usize]);
        s.patches[1] = bezier_patch(1, 0, [E0, E2, E1], linear([fv[0], fv[2], fv[1]]));
        let m = Metrics::measure_faces(&s, &faces, &positions, 0.0);
        let jump = m.g1_max_rad.expect("joint");
        assert!((jump - std::f64::consts::PI).abs() <= 1e-15, "{jump}");
    }

    #[test]
    fn result_does_not_depend_on_thread_count() {
        let (s, faces, positions) = pieces_of_one_polynomial();
        let run = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("thread pool")
                .install(|| Metrics::measure_faces(&s, &faces, &positions, 0.0))
        };
        assert_eq!(run(1), run(3));
    }

    /// Built surfaces measure to the same JSON, byte for byte, on one thread and on two:
    /// a G1 scheme on a mesh with valences 3 to 16, and the G4 spline on the deformed
    /// icosahedron, whose order 4 is resolved through the rounding floor.
    #[test]
    fn built_surfaces_measure_the_same_on_any_thread_count() {
        use crate::mesh::{Mesh, generate};
        let g4 = vec![("k".to_string(), "4".to_string())];
        let cases = [
            ("hb", vec![], generate::mixed_valence()),
            ("gk", g4, generate::deformed_icosahedron()),
        ];
        for (scheme, params, (positions, faces)) in cases {
            let (mesh, _) = Mesh::from_triangles(positions, faces).expect("valid mesh");
            let surface = crate::schemes::build(scheme, &mesh, &params).expect("builds");
            let run = |threads| {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .expect("thread pool");
                let metrics = pool.install(|| Metrics::measure(&surface, &mesh, 0.0));
                serde_json::to_string(&metrics).expect("serialisable")
            };
            assert_eq!(run(1), run(2), "{scheme}");
        }
    }

    #[test]
    fn json_has_the_contract_keys() {
        let (s, faces, positions) = pieces_of_one_polynomial();
        let m = Metrics::measure_faces(&s, &faces, &positions, 0.0);
        let value = serde_json::to_value(&m).expect("serialisable");
        for key in CONTRACT_KEYS {
            assert!(value.get(key).is_some(), "missing key {key}");
        }
        // Pieces of one polynomial agree to every measured order.
        assert_eq!(
            value["continuity_order"],
            continuity::MAX_ORDER as i64,
            "{value}"
        );
        assert_eq!(value["params"]["p"], "1");
    }
}
