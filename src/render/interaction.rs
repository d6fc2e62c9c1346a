//! The hit record: what the renderer knows about the closest hit of a ray once it has been
//! shaded — the exact local geometry of the patch there (pbrt's surface interaction). Modes,
//! the path tracer and the tracers all speak this one type.

use glam::DVec3;

use crate::geom::{Curvature, Jet};
use crate::render::intersect::{Hit, Ray64};

/// Everything a mode may read about the closest hit, evaluated once.
#[derive(Clone, Copy, Debug)]
pub struct ShadingPoint {
    /// The hit test's result.
    pub hit: Hit,
    /// Mesh face of the patch.
    pub face: u32,
    /// Piece of the face.
    pub piece: u8,
    /// Position, derivatives at `(u, v)`.
    pub jet: Jet,
    /// Unit patch normal `Su × Sv / |Su × Sv|` (orientation of the patch).
    pub normal: DVec3,
    /// The normal turned towards the viewer (hits on both sides of a surface shade alike).
    pub facing_normal: DVec3,
    /// Unit ray direction.
    pub view: DVec3,
    /// Curvatures with respect to [`ShadingPoint::normal`], None at singular points.
    pub curvature: Option<Curvature>,
}

impl ShadingPoint {
    /// True if the patch normal faces away from the eye: the hit is on the back of the surface
    /// (on a closed surface seen from outside, never).
    pub fn is_back_face(&self) -> bool {
        self.normal.dot(self.view) > 0.0
    }

    /// Evaluates the full local geometry of `hit` on `jet` (from the hit's patch).
    pub fn new(hit: Hit, face: u32, piece: u8, jet: Jet, ray: &Ray64) -> ShadingPoint {
        ShadingPoint::with_normal(hit, face, piece, jet, jet.normal(), ray)
    }

    /// The local geometry of `hit` with a given unit `normal` (the tessellated path shades
    /// with interpolated vertex normals instead of the jet's).
    pub fn with_normal(
        hit: Hit,
        face: u32,
        piece: u8,
        jet: Jet,
        normal: DVec3,
        ray: &Ray64,
    ) -> ShadingPoint {
        let facing_normal = if normal.dot(ray.dir) > 0.0 {
            -normal
        } else {
            normal
        };
        ShadingPoint {
            hit,
            face,
            piece,
            jet,
            normal,
            facing_normal,
            view: ray.dir,
            curvature: jet.curvature(),
        }
    }
}
