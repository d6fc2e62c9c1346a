//! Isophotes: curves of constant `n·L`. Bands alternate light and dark, so band borders are
//! isophotes; they are C⁰ across a G¹ surface and kink where it breaks. Bands are of equal width
//! in `n·L` (the default) or in the angle between `n` and `L` (`step_deg`: an isophote every so
//! many degrees).

use glam::DVec3;

use crate::error::{Problem, Result};
use crate::render::interaction::ShadingPoint;
use crate::render::modes::ModeKind;
use crate::render::modes::keys::{self, Flag, Key, Keys};
use crate::render::modes::stripes::{
    FILTER_KEY, Footprint, NO_STRIPE_FILTER, filtered_square_wave,
};

/// Parameters of the isophote mode.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IsophoteParams {
    /// Direction towards the light (world space).
    pub light: DVec3,
    /// Number of bands over `n·L ∈ [−1, 1]` (used when `step_deg` is None).
    pub bands: u32,
    /// Angle between neighbouring isophotes in degrees (bands of equal angle between `n` and
    /// `L`, the first border at this angle); None: `bands` bands of equal `n·L`.
    pub step_deg: Option<f64>,
    /// Box-filter the bands over each sample's screen footprint; false: point samples.
    pub filter: bool,
}

impl Default for IsophoteParams {
    fn default() -> Self {
        IsophoteParams {
            light: DVec3::new(0.3, 0.8, 0.5),
            bands: 16,
            step_deg: None,
            filter: true,
        }
    }
}

impl IsophoteParams {
    /// The band coordinate (bands from the start, 2 per light–dark period) at unit normal `n`.
    pub fn band(&self, n: DVec3) -> f64 {
        let light = self.light.normalize_or(DVec3::Y);
        let c = n.dot(light).clamp(-1.0, 1.0);
        match self.step_deg {
            Some(step) => c.acos().to_degrees() / step.max(1e-9),
            None => (c + 1.0) * 0.5 * f64::from(self.bands.max(1)),
        }
    }

    /// Band colour at the hit: even bands light, odd bands dark, each tinted by `n·L` so the
    /// shape stays readable; box-filtered over `footprint` when given.
    pub fn shade(&self, sp: &ShadingPoint, footprint: Option<&Footprint>) -> DVec3 {
        let light = self.light.normalize_or(DVec3::Y);
        let c = sp.facing_normal.dot(light).clamp(-1.0, 1.0);
        let mut band = self.band(sp.facing_normal);
        if self.step_deg.is_none() {
            // The last band is closed at n·L = 1.
            band = band.min(f64::from(self.bands.max(1)) - 0.5);
        }
        let width = match footprint {
            Some(f) if self.filter => f.phase_width(sp, |_, n, _| 0.5 * self.band(n)),
            _ => 0.0,
        };
        let light_fraction = filtered_square_wave(0.5 * band, width, 0.5);
        let shade = 0.55 + 0.45 * c;
        DVec3::new(0.05, 0.09, 0.25).lerp(DVec3::new(0.95, 0.78, 0.35), light_fraction) * shade
    }
}

impl ModeKind for IsophoteParams {
    const NAME: &'static str = "isophote";
    const HELP: &'static str = "Bands of constant n·L.";
    const KEYS: &'static [Key] = &[
        Key::new(
            "light",
            "direction towards the light (non-zero, default [0.3, 0.8, 0.5])",
        ),
        Key::new("bands", "bands of equal n·L (at least 1, default 16)"),
        Key::new(
            "step_deg",
            "an isophote every this many degrees in (0, 90] (instead of bands)",
        ),
        FILTER_KEY,
    ];
    const FLAGS: &'static [Flag] = &[
        Flag::value(
            "isophote-step",
            "step_deg",
            "DEG",
            "An isophote every DEG degrees between normal and light [default: 16 bands of equal n·L].",
            keys::number,
        ),
        NO_STRIPE_FILTER,
    ];

    fn configure(&mut self, keys: &Keys<'_>) -> Result<()> {
        if let Some(l) = keys.direction("light")? {
            self.light = l;
        }
        if let Some(b) = keys.count("bands")? {
            if b == 0 {
                return Err(keys.error(
                    "bands",
                    Problem::Must {
                        value: String::new(),
                        requirement: "be at least 1".into(),
                    },
                ));
            }
            self.bands = b;
        }
        if let Some(step) = keys.number("step_deg")? {
            if !(step > 0.0 && step <= 90.0) {
                return Err(keys.error(
                    "step_deg",
                    Problem::OutOfRange {
                        value: step.to_string(),
                        range: "(0, 90]".into(),
                    },
                ));
            }
            self.step_deg = Some(step);
        }
        if let Some(f) = keys.flag("filter")? {
            self.filter = f;
        }
        Ok(())
    }

    fn shade(&self, sp: &ShadingPoint, footprint: Option<&Footprint>) -> DVec3 {
        IsophoteParams::shade(self, sp, footprint)
    }

    fn filtered(&self) -> bool {
        self.filter
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angle_steps_put_borders_at_multiples_of_the_step() {
        let p = IsophoteParams {
            light: DVec3::Z,
            step_deg: Some(15.0),
            ..IsophoteParams::default()
        };
        let at = |deg: f64| {
            p.band(DVec3::new(
                deg.to_radians().sin(),
                0.0,
                deg.to_radians().cos(),
            ))
        };
        assert!((at(30.0) - 2.0).abs() < 1e-9);
        assert!((at(52.5) - 3.5).abs() < 1e-9);
        let cosine = IsophoteParams::default();
        assert!((cosine.band(cosine.light.normalize()) - 16.0).abs() < 1e-9);
    }
}
