//! Curvature maps: Gaussian, mean, largest |κ|, κ1 or κ2 through a diverging colour map over a
//! symmetric range, fixed (for comparable figures) or chosen from a percentile of the values in
//! view.

use glam::DVec3;

use crate::geom::Curvature;
use crate::render::interaction::ShadingPoint;
use crate::render::modes::palette;

/// Which curvature to show.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CurvatureQuantity {
    /// K = κ1 κ2.
    Gaussian,
    /// H = (κ1 + κ2) / 2.
    Mean,
    /// max(|κ1|, |κ2|).
    MaxAbs,
    /// Larger principal curvature.
    K1,
    /// Smaller principal curvature.
    K2,
}

impl CurvatureQuantity {
    /// Names accepted in scenes and on the command line.
    pub const NAMES: &'static [&'static str] = &["gaussian", "mean", "maxabs", "k1", "k2"];

    /// The quantity called `name`.
    pub fn by_name(name: &str) -> crate::Result<CurvatureQuantity> {
        Ok(match name {
            "gaussian" => CurvatureQuantity::Gaussian,
            "mean" => CurvatureQuantity::Mean,
            "maxabs" => CurvatureQuantity::MaxAbs,
            "k1" => CurvatureQuantity::K1,
            "k2" => CurvatureQuantity::K2,
            _ => {
                return Err(crate::Error::Invalid(format!(
                    "unknown curvature quantity '{name}' (known: {})",
                    Self::NAMES.join(", ")
                )));
            }
        })
    }

    /// The quantity's value.
    pub fn value(self, c: &Curvature) -> f64 {
        match self {
            CurvatureQuantity::Gaussian => c.gaussian,
            CurvatureQuantity::Mean => c.mean,
            CurvatureQuantity::MaxAbs => c.k1.abs().max(c.k2.abs()),
            CurvatureQuantity::K1 => c.k1,
            CurvatureQuantity::K2 => c.k2,
        }
    }
}

/// How the colour range is chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CurvatureRange {
    /// `[−r, r]` with r the given percentile (0..100) of |value| over a coarse pre-pass of the
    /// view.
    Auto {
        /// Percentile of |value|.
        percentile: f64,
    },
    /// `[−r, r]` with this r.
    Fixed(f64),
}

/// Parameters of the curvature mode.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurvatureParams {
    /// The quantity shown.
    pub quantity: CurvatureQuantity,
    /// How the range is chosen.
    pub range: CurvatureRange,
    /// Draw a colour bar at the right edge of the image.
    pub legend: bool,
    /// The half-range in use (set before rendering from `range`).
    pub half_range: f64,
}

impl Default for CurvatureParams {
    fn default() -> Self {
        CurvatureParams {
            quantity: CurvatureQuantity::Mean,
            range: CurvatureRange::Auto { percentile: 95.0 },
            legend: false,
            half_range: 1.0,
        }
    }
}

impl CurvatureParams {
    /// Colour of the hit; singular points (no curvature) are black.
    pub fn shade(&self, sp: &ShadingPoint) -> DVec3 {
        match &sp.curvature {
            Some(c) => palette::diverging(
                self.quantity.value(c) / self.half_range.max(crate::tolerance::DIVISION_GUARD),
            ),
            None => DVec3::ZERO,
        }
    }
}

/// The `percentile` (0..100) of `|values|`, 0 for no values. Sorts `values`.
pub fn abs_percentile(values: &mut [f64], percentile: f64) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    for v in values.iter_mut() {
        *v = v.abs();
    }
    values.sort_by(f64::total_cmp);
    let rank = (percentile.clamp(0.0, 100.0) / 100.0 * (values.len() - 1) as f64).round();
    values[rank as usize]
}

/// Paints a vertical colour bar (top = +range, bottom = −range) into the right edge of a linear
/// RGB image, framed in black, with a black tick at zero.
pub fn draw_legend(rgb: &mut [[f32; 3]], width: u32, height: u32) {
    let (w, h) = (width as usize, height as usize);
    let bar_w = (w / 40).max(4);
    let margin = (w / 40).max(2);
    let top = h / 10;
    let bottom = h - h / 10;
    if bar_w + 2 * margin >= w || bottom <= top + 2 {
        return;
    }
    let x0 = w - margin - bar_w;
    for y in top..bottom {
        let s = 1.0 - 2.0 * (y - top) as f64 / (bottom - 1 - top) as f64;
        let c = palette::diverging(s);
        for x in x0..x0 + bar_w {
            let frame = y == top || y == bottom - 1 || x == x0 || x == x0 + bar_w - 1;
            let zero = y == (top + bottom) / 2;
            rgb[y * w + x] = if frame || zero {
                [0.0; 3]
            } else {
                [c.x as f32, c.y as f32, c.z as f32]
            };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentile_of_absolute_values() {
        let mut v = vec![-4.0, 1.0, -2.0, 3.0, 0.0];
        assert_eq!(abs_percentile(&mut v, 100.0), 4.0);
        let mut v = vec![-4.0, 1.0, -2.0, 3.0, 0.0];
        assert_eq!(abs_percentile(&mut v, 50.0), 2.0);
        assert_eq!(abs_percentile(&mut [], 50.0), 0.0);
    }

    #[test]
    fn quantities_of_a_saddle() {
        let c = Curvature {
            gaussian: -2.0,
            mean: -0.5,
            k1: 1.0,
            k2: -2.0,
        };
        assert_eq!(CurvatureQuantity::MaxAbs.value(&c), 2.0);
        assert_eq!(CurvatureQuantity::K2.value(&c), -2.0);
        assert!(CurvatureQuantity::by_name("bogus").is_err());
    }
}
