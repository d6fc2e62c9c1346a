//! The normals mode: the unit patch normal as a colour, `(n + 1) / 2` (sRGB-encoded values, so
//! the image shows the components as they are).

use glam::DVec3;

use crate::render::interaction::ShadingPoint;
use crate::render::modes::{Footprint, ModeKind, palette};

/// The normals mode (no parameters).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Normals;

impl ModeKind for Normals {
    const NAME: &'static str = "normals";
    const HELP: &'static str = "The normal as a colour.";

    fn shade(&self, sp: &ShadingPoint, _footprint: Option<&Footprint>) -> DVec3 {
        palette::srgb_to_linear(0.5 * (sp.normal + DVec3::ONE))
    }
}
