//! Isophotes: curves of constant `n·L`. Bands of equal width in `n·L` alternate light and dark,
//! so band borders are isophotes; they are C⁰ across a G¹ surface and kink where it breaks.

use glam::DVec3;

use crate::render::interaction::ShadingPoint;

/// Parameters of the isophote mode.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IsophoteParams {
    /// Direction towards the light (world space).
    pub light: DVec3,
    /// Number of bands over `n·L ∈ [−1, 1]`.
    pub bands: u32,
}

impl Default for IsophoteParams {
    fn default() -> Self {
        IsophoteParams {
            light: DVec3::new(0.3, 0.8, 0.5),
            bands: 16,
        }
    }
}

impl IsophoteParams {
    /// Band colour at the hit: even bands light, odd bands dark, each tinted by `n·L` so the
    /// shape stays readable.
    pub fn shade(&self, sp: &ShadingPoint) -> DVec3 {
        let light = self.light.normalize_or(DVec3::Y);
        let c = sp.facing_normal.dot(light).clamp(-1.0, 1.0);
        let bands = self.bands.max(1);
        let band = (((c + 1.0) * 0.5 * f64::from(bands)) as u32).min(bands - 1);
        let shade = 0.55 + 0.45 * c;
        if band.is_multiple_of(2) {
            DVec3::new(0.95, 0.78, 0.35) * shade
        } else {
            DVec3::new(0.05, 0.09, 0.25) * shade
        }
    }
}
