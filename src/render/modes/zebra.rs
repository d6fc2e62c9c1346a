//! Reflection lines (zebra) and highlight lines.
//!
//! Zebra: the eye ray is mirrored at the hit and looks up an environment of infinitely long
//! light tubes parallel to `axis`, spread evenly around it: the stripe index is the angle of the
//! reflected direction around `axis`. A G¹ break of the surface shows as a kink of the stripes,
//! a G² break as a kink of their direction field.
//!
//! Highlight lines [Beier–Chen 1994]: the normal line through the hit meets the plane of an array
//! of parallel line lights; the stripe is the distance, across the lights, of that meeting point.
//! They depend on the normal only (not on the eye), so they stay put when the view turns.

use glam::DVec3;

use crate::render::interaction::ShadingPoint;
use crate::render::modes::fract;

/// Linear-light brightness of a bright stripe and of a dark one.
const BRIGHT: f64 = 0.9;
const DARK: f64 = 0.015;

/// Parameters of the zebra (reflection line) mode.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ZebraParams {
    /// Direction of the light tubes (world space).
    pub axis: DVec3,
    /// Number of bright stripes in a full turn around the axis.
    pub stripes: f64,
    /// Fraction of each period that is bright.
    pub duty: f64,
    /// Shift of the stripes, in periods (0 to 1 moves them by one period; used by stripe
    /// sweeps).
    pub phase: f64,
}

impl Default for ZebraParams {
    fn default() -> Self {
        ZebraParams {
            axis: DVec3::Y,
            stripes: 16.0,
            duty: 0.5,
            phase: 0.0,
        }
    }
}

impl ZebraParams {
    /// Bright or dark stripe at the hit.
    pub fn shade(&self, sp: &ShadingPoint) -> DVec3 {
        let n = sp.facing_normal;
        let reflected = sp.view - 2.0 * sp.view.dot(n) * n;
        let axis = self.axis.normalize_or(DVec3::Y);
        let (b1, b2) = axis.any_orthonormal_pair();
        let angle = reflected.dot(b2).atan2(reflected.dot(b1));
        let phase = fract(self.stripes * angle / std::f64::consts::TAU - self.phase);
        DVec3::splat(if phase < self.duty { BRIGHT } else { DARK })
    }
}

/// Parameters of the highlight-line mode: line lights in the plane through `origin` with normal
/// `plane_normal`, running along `direction`, `spacing` apart.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HighlightParams {
    /// A point of the light plane; None: one scene diagonal above the scene centre along
    /// `plane_normal`.
    pub origin: Option<DVec3>,
    /// Normal of the light plane.
    pub plane_normal: DVec3,
    /// Direction of the line lights (projected into the plane).
    pub direction: DVec3,
    /// Distance between neighbouring lights; None: a quarter of the scene diagonal.
    pub spacing: Option<f64>,
    /// Fraction of each period that is bright.
    pub duty: f64,
}

impl Default for HighlightParams {
    fn default() -> Self {
        HighlightParams {
            origin: None,
            plane_normal: DVec3::Y,
            direction: DVec3::X,
            spacing: None,
            duty: 0.5,
        }
    }
}

impl HighlightParams {
    /// Fills in the scene-dependent defaults from the scene's centre and diagonal.
    pub fn resolved(&self, center: DVec3, diagonal: f64) -> HighlightParams {
        let normal = self.plane_normal.normalize_or(DVec3::Y);
        HighlightParams {
            origin: Some(self.origin.unwrap_or(center + normal * diagonal)),
            plane_normal: normal,
            direction: self.direction,
            spacing: Some(self.spacing.unwrap_or(diagonal / 4.0)),
            duty: self.duty,
        }
    }

    /// Bright or dark stripe at the hit ([`HighlightParams::resolved`] first).
    pub fn shade(&self, sp: &ShadingPoint) -> DVec3 {
        let m = self.plane_normal;
        let origin = self.origin.unwrap_or(DVec3::ZERO);
        let spacing = self.spacing.unwrap_or(1.0);
        // The outward normal half-line (turned towards the viewer, so both sides of an open
        // surface behave alike) must reach the light plane; points facing away see no light.
        let n = sp.facing_normal;
        let p = sp.jet.p;
        let along = n.dot(m);
        let reach = (origin - p).dot(m);
        if along.abs() < 1e-9 || reach / along <= 0.0 {
            return DVec3::splat(DARK);
        }
        let meet = p + n * (reach / along);
        let across = m
            .cross(self.direction)
            .normalize_or(m.any_orthonormal_vector());
        let phase = fract((meet - origin).dot(across) / spacing);
        DVec3::splat(if phase < self.duty { BRIGHT } else { DARK })
    }
}
