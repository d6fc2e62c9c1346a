//! Shading modes: each turns the exact local geometry of the closest hit (normal, curvatures,
//! patch and face) into a linear RGB colour. Every quantity is evaluated from the patch itself
//! at the hit, never interpolated, so stripes and colours do not depend on any mesh density.

pub mod curvature;
pub mod isophote;
pub mod overlay;
pub mod palette;
pub mod stripes;
pub mod zebra;

use glam::DVec3;

use crate::render::interaction::ShadingPoint;

pub use curvature::{
    CurvatureMap, CurvatureParams, CurvatureQuantity, CurvatureRange, CurvatureSign,
};
pub use isophote::IsophoteParams;
pub use overlay::Overlay;
pub use stripes::Footprint;
pub use zebra::{HighlightParams, ZebraAxis, ZebraParams};

/// A shading mode with its parameters.
#[derive(Clone, Debug, PartialEq)]
pub enum Mode {
    /// Reflection lines of an environment of parallel light stripes.
    Zebra(ZebraParams),
    /// View-independent highlight lines (Beier–Chen) of an array of parallel line lights.
    Highlight(HighlightParams),
    /// Bands of constant `n·L`.
    Isophote(IsophoteParams),
    /// A curvature quantity through a diverging colour map.
    Curvature(CurvatureParams),
    /// The normal as a colour, `(n + 1) / 2`.
    Normals,
    /// One colour per face, shaded lighter or darker per piece.
    Patches,
    /// Plain light grey lit from the eye: a quiet background for the curve-network tubes.
    Diffuse,
    /// Path-traced clear-coat material in a studio environment.
    Shaded(crate::render::shaded::ShadedParams),
}

/// Mode names accepted by `--mode` and scene files.
pub const MODE_NAMES: &[&str] = &[
    "zebra",
    "highlight",
    "isophote",
    "curvature",
    "normals",
    "patches",
    "diffuse",
    "shaded",
];

impl Mode {
    /// The mode called `name` with default parameters.
    pub fn by_name(name: &str) -> crate::Result<Mode> {
        Ok(match name {
            "zebra" => Mode::Zebra(ZebraParams::default()),
            "highlight" => Mode::Highlight(HighlightParams::default()),
            "isophote" => Mode::Isophote(IsophoteParams::default()),
            "curvature" => Mode::Curvature(CurvatureParams::default()),
            "normals" => Mode::Normals,
            "patches" => Mode::Patches,
            "diffuse" => Mode::Diffuse,
            "shaded" => Mode::Shaded(Default::default()),
            _ => {
                return Err(crate::Error::Invalid(format!(
                    "unknown render mode '{name}' (known: {})",
                    MODE_NAMES.join(", ")
                )));
            }
        })
    }

    /// The mode's name.
    pub fn name(&self) -> &'static str {
        match self {
            Mode::Zebra(_) => "zebra",
            Mode::Highlight(_) => "highlight",
            Mode::Isophote(_) => "isophote",
            Mode::Curvature(_) => "curvature",
            Mode::Normals => "normals",
            Mode::Patches => "patches",
            Mode::Diffuse => "diffuse",
            Mode::Shaded(_) => "shaded",
        }
    }

    /// The mode with back-face hits tinted ([`palette::back_face`]) where it shows surface
    /// quality (zebra, curvature): what an open surface is rendered with, so that its other
    /// side stands out. Other modes are returned as they are.
    pub fn with_back_faces_tinted(&self) -> Mode {
        match self {
            Mode::Zebra(p) => Mode::Zebra(ZebraParams {
                tint_back_faces: true,
                ..*p
            }),
            Mode::Curvature(p) => Mode::Curvature(CurvatureParams {
                tint_back_faces: true,
                ..*p
            }),
            other => other.clone(),
        }
    }

    /// True for the stripe modes, which filter their stripes over the sample's
    /// [`Footprint`] when given one.
    pub fn uses_footprint(&self) -> bool {
        match self {
            Mode::Zebra(p) => p.filter,
            Mode::Highlight(p) => p.filter,
            Mode::Isophote(p) => p.filter,
            _ => false,
        }
    }

    /// Linear RGB of a hit for the direct (non path-traced) modes, point-sampled; `Shaded` is
    /// handled by the path tracer and gets a plain diffuse preview here.
    pub fn shade(&self, sp: &ShadingPoint) -> DVec3 {
        self.shade_filtered(sp, None)
    }

    /// As [`Mode::shade`], the stripe modes box-filtered over `footprint` (the change of the
    /// hit across one sample cell) when given.
    pub fn shade_filtered(&self, sp: &ShadingPoint, footprint: Option<&Footprint>) -> DVec3 {
        match self {
            Mode::Zebra(p) => p.shade(sp, footprint),
            Mode::Highlight(p) => p.shade(sp, footprint),
            Mode::Isophote(p) => p.shade(sp, footprint),
            Mode::Curvature(p) => p.shade(sp),
            Mode::Normals => palette::srgb_to_linear(0.5 * (sp.normal + DVec3::ONE)),
            Mode::Patches => {
                let base = palette::face_colour(sp.face, sp.piece);
                base * (0.3 + 0.7 * sp.facing_normal.dot(-sp.view).max(0.0))
            }
            Mode::Diffuse => {
                let facing = sp.facing_normal.dot(-sp.view).max(0.0);
                DVec3::splat(0.12 + 0.6 * facing)
            }
            Mode::Shaded(_) => DVec3::splat(0.8 * sp.facing_normal.dot(-sp.view).max(0.0)),
        }
    }
}

/// Fractional part in `[0, 1)`, also for negative numbers.
pub(crate) fn fract(x: f64) -> f64 {
    x - x.floor()
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::geom::Jet;
    use crate::render::intersect::{Hit, Ray64};

    /// A hit at the origin with patch normal +z, seen along `dir`.
    fn hit(dir: DVec3) -> ShadingPoint {
        let jet = Jet {
            p: DVec3::ZERO,
            du: DVec3::X,
            dv: DVec3::Y,
            ..Jet::default()
        };
        let ray = Ray64::new(DVec3::new(0.0, 0.0, -dir.z.signum()), dir);
        let hit = Hit {
            t: 1.0,
            patch: 0,
            u: 0.0,
            v: 0.0,
        };
        ShadingPoint::new(hit, 0, 0, jet, &ray)
    }

    /// Back faces change colour only with the tint on, front faces never.
    #[test]
    fn back_faces_are_tinted_only_when_asked_and_only_on_the_back() {
        let (front, back) = (hit(-DVec3::Z), hit(DVec3::Z));
        assert!(!front.is_back_face() && back.is_back_face());
        for mode in [
            Mode::Zebra(ZebraParams::default()),
            Mode::Curvature(CurvatureParams::default()),
        ] {
            let tinted = mode.with_back_faces_tinted();
            assert_eq!(tinted.shade(&front), mode.shade(&front), "{}", mode.name());
            assert_ne!(tinted.shade(&back), mode.shade(&back), "{}", mode.name());
        }
    }
}
