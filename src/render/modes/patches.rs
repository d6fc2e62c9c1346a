//! The patches mode: one colour per mesh face, lighter or darker per piece of the face, lit
//! from the eye, so that the patch layout of a scheme shows.

use glam::DVec3;

use crate::render::interaction::ShadingPoint;
use crate::render::modes::{Footprint, ModeKind, palette};

/// The patches mode (no parameters).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Patches;

impl ModeKind for Patches {
    const NAME: &'static str = "patches";
    const HELP: &'static str = "One colour per face and piece.";

    fn shade(&self, sp: &ShadingPoint, _footprint: Option<&Footprint>) -> DVec3 {
        let base = palette::face_colour(sp.face, sp.piece);
        base * (0.3 + 0.7 * sp.facing_normal.dot(-sp.view).max(0.0))
    }
}
