//! Sampling along joints: the two patch edges of a [`Joint`] are evaluated at the same
//! domain points and compared — position gap (G0), normal angle (G1), Gaussian and mean
//! curvature (G2 indicators).
//!
//! Sample placement: [`JOINT_SAMPLES`](crate::surface::JOINT_SAMPLES) points at fractions `s = i/16` for `i = 1..15` plus
//! `s = 1/1024` and `s = 1 − 1/1024` near (not at) the two ends. The ends themselves are left
//! out because a corner where several patches meet is where a parametrisation may be singular
//! (`Su × Sv = 0`), and there the normal is undefined rather than discontinuous. All fractions
//! are dyadic, so `s` and `1 − s` are exact and both sides are evaluated at exactly the same
//! domain point.

use glam::DVec3;

use crate::geom::Jet;
use crate::surface::{Joint, Surface, edge_uv};

pub(crate) use crate::surface::joint_fractions;

/// The angle between two (not necessarily unit) normals, `atan2(|n0 × n1|, n0 · n1)`:
/// accurate to machine precision near 0 and near π, where `acos` of the dot product loses
/// half the digits. Opposite normals (an orientation flip) give π.
pub fn normal_angle(n0: DVec3, n1: DVec3) -> f64 {
    n0.cross(n1).length().atan2(n0.dot(n1))
}

/// Curvature floors below which a curvature counts as "flat": relative jumps are taken
/// against `max(|K0|, |K1|, gaussian)` and `max(|H0|, |H1|, mean)` so that two nearly flat
/// sides with tiny, noisy curvatures do not show a relative jump of order one. smoothlab uses
/// the curvature of a sphere whose radius is the bounding-box diagonal: `1/diag²` and `1/diag`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurvatureFloor {
    /// Floor for Gaussian curvature (units 1/length²).
    pub gaussian: f64,
    /// Floor for mean curvature (units 1/length).
    pub mean: f64,
}

impl CurvatureFloor {
    /// The floors for a model of bounding-box diagonal `diag`.
    pub fn for_diagonal(diag: f64) -> Self {
        CurvatureFloor {
            gaussian: 1.0 / (diag * diag),
            mean: 1.0 / diag,
        }
    }
}

/// What one joint measures.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct JointStats {
    /// True if the two sides belong to different mesh faces.
    pub between_faces: bool,
    /// Largest distance between the two sides (absolute, model units).
    pub gap_max: f64,
    /// Largest normal angle (rad) over the regular samples.
    pub angle_max: f64,
    /// Largest normal angle (rad) over the regular samples whose angle exceeds its
    /// [`normal_rounding`] bound (0 when rounding accounts for every sample's angle).
    pub angle_beyond_rounding_max: f64,
    /// Sum of the normal angles over the regular samples (for the mean).
    pub angle_sum: f64,
    /// Number of samples where both sides are regular (enter the angle figures).
    pub regular_samples: usize,
    /// Samples where one side has `Su × Sv = 0` (left out of the angle and curvature figures).
    pub singular_samples: usize,
    /// Largest relative jump of the Gaussian curvature.
    pub gaussian_jump_max: f64,
    /// Largest relative jump of the mean curvature.
    pub mean_jump_max: f64,
}

/// Samples one joint. Each side's normal is its own `Su × Sv`, so the comparison assumes
/// what every scheme guarantees: a patch is parametrised with the orientation of its face,
/// and the mesh is consistently oriented. A patch with the opposite orientation shows up
/// honestly as a jump of π (and as a sign change of the mean curvature).
pub(crate) fn measure_joint(surface: &Surface, joint: &Joint, floor: CurvatureFloor) -> JointStats {
    let mut stats = JointStats {
        between_faces: joint.between_faces,
        ..JointStats::default()
    };
    let [rounding_a, rounding_b] =
        [joint.a.patch, joint.b.patch].map(|p| surface.patches[p as usize].derivative_rounding());
    for s in joint_fractions() {
        let [jet_a, jet_b] = sides_at(surface, joint, s);
        stats.gap_max = stats.gap_max.max((jet_a.p - jet_b.p).length());
        let (cross_a, cross_b) = (jet_a.cross(), jet_b.cross());
        if cross_a == DVec3::ZERO || cross_b == DVec3::ZERO {
            stats.singular_samples += 1;
            continue;
        }
        let angle = normal_angle(cross_a, cross_b);
        stats.angle_max = stats.angle_max.max(angle);
        if angle > normal_rounding(&jet_a, rounding_a) + normal_rounding(&jet_b, rounding_b) {
            stats.angle_beyond_rounding_max = stats.angle_beyond_rounding_max.max(angle);
        }
        stats.angle_sum += angle;
        stats.regular_samples += 1;
        let (gaussian, mean) = curvature_jumps(&jet_a, &jet_b, floor);
        stats.gaussian_jump_max = stats.gaussian_jump_max.max(gaussian);
        stats.mean_jump_max = stats.mean_jump_max.max(mean);
    }
    stats
}

/// The angle (rad) by which derivatives off by `delta` (from [`crate::surface::Patch::derivative_rounding`]) may turn
/// the normal `Su × Sv` of `jet`: `δ(|Su| + |Sv|) / |Su × Sv|` to first order. Small where the
/// parametrisation is regular; large near a singular point, where `Su` and `Sv` are nearly
/// parallel and the normal is only as well defined as their rounding allows (e.g. at the
/// wide corner of a needle face whose tangent plane is tilted against it).
pub(crate) fn normal_rounding(jet: &Jet, delta: f64) -> f64 {
    delta * (jet.du.length() + jet.dv.length()) / jet.cross().length()
}

/// The jets of both sides of `joint` at fraction `s` along side `a` (the same domain point).
pub(crate) fn sides_at(surface: &Surface, joint: &Joint, s: f64) -> [Jet; 2] {
    let s_b = if joint.reversed { 1.0 - s } else { s };
    let uv_a = edge_uv(joint.a.edge as usize, s);
    let uv_b = edge_uv(joint.b.edge as usize, s_b);
    let jet_a = surface.patches[joint.a.patch as usize].jet(uv_a.x, uv_a.y);
    let jet_b = surface.patches[joint.b.patch as usize].jet(uv_b.x, uv_b.y);
    [jet_a, jet_b]
}

/// What a joint does at one point: the gap between its sides and the angle between their
/// normals (`None` where a side is singular, `Su × Sv = 0`) — [`measure_joint`]'s figures at a
/// single fraction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct JumpAt {
    /// Distance between the two sides' points.
    pub gap: f64,
    /// Angle between the sides' normals (rad).
    pub normal_angle: Option<f64>,
}

/// The jump across `joint` at fraction `s` along side `a`.
pub(crate) fn jump_at(surface: &Surface, joint: &Joint, s: f64) -> JumpAt {
    let [a, b] = sides_at(surface, joint, s);
    let (cross_a, cross_b) = (a.cross(), b.cross());
    JumpAt {
        gap: (a.p - b.p).length(),
        normal_angle: (cross_a != DVec3::ZERO && cross_b != DVec3::ZERO)
            .then(|| normal_angle(cross_a, cross_b)),
    }
}

/// Relative jumps `|K0 − K1| / max(|K0|, |K1|, floor)` of Gaussian and mean curvature
/// between two jets at the same surface point (0 where a curvature is undefined).
fn curvature_jumps(a: &Jet, b: &Jet, floor: CurvatureFloor) -> (f64, f64) {
    match (a.curvature(), b.curvature()) {
        (Some(ka), Some(kb)) => (
            relative_jump(ka.gaussian, kb.gaussian, floor.gaussian),
            relative_jump(ka.mean, kb.mean, floor.mean),
        ),
        _ => (0.0, 0.0),
    }
}

fn relative_jump(x0: f64, x1: f64, floor: f64) -> f64 {
    (x0 - x1).abs() / x0.abs().max(x1.abs()).max(floor)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::JOINT_SAMPLES;

    #[test]
    fn fractions_are_increasing_and_symmetric() {
        let s = joint_fractions();
        assert!(s.windows(2).all(|w| w[0] < w[1]), "{s:?}");
        for i in 0..JOINT_SAMPLES {
            // Dyadic fractions: 1 − s is exact, so both sides see the same point.
            assert_eq!(s[i], 1.0 - s[JOINT_SAMPLES - 1 - i]);
        }
        assert!(s[0] > 0.0 && s[JOINT_SAMPLES - 1] < 1.0);
    }

    #[test]
    fn normal_angle_is_accurate_near_zero_and_pi() {
        let n0 = DVec3::Z;
        let tiny = 1e-12_f64;
        let n1 = DVec3::new(tiny.sin(), 0.0, tiny.cos());
        let a = normal_angle(n0, n1);
        assert!((a - tiny).abs() < 1e-24, "angle {a}");
        // acos would say 0 here: cos(1e-12) rounds to 1.
        assert_eq!(n0.dot(n1).acos(), 0.0);
        assert!((normal_angle(n0, -n1) - (std::f64::consts::PI - tiny)).abs() < 1e-15);
        // Lengths do not matter.
        assert!((normal_angle(3.0 * n0, 0.5 * n1) - tiny).abs() < 1e-24);
    }

    #[test]
    fn relative_jump_uses_the_floor() {
        assert_eq!(relative_jump(2.0, 1.0, 0.1), 0.5);
        assert_eq!(relative_jump(1e-9, -1e-9, 1.0), 2e-9);
        assert_eq!(relative_jump(0.0, 0.0, 1.0), 0.0);
    }
}
