//! The diffuse mode: plain light grey lit from the eye, a quiet background for the
//! curve-network tubes.

use glam::DVec3;

use crate::render::interaction::ShadingPoint;
use crate::render::modes::{Footprint, ModeKind};

/// The diffuse mode (no parameters).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Diffuse;

impl ModeKind for Diffuse {
    const NAME: &'static str = "diffuse";
    const HELP: &'static str = "Plain grey lit from the eye.";

    fn shade(&self, sp: &ShadingPoint, _footprint: Option<&Footprint>) -> DVec3 {
        let facing = sp.facing_normal.dot(-sp.view).max(0.0);
        DVec3::splat(0.12 + 0.6 * facing)
    }
}
