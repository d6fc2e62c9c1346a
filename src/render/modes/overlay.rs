//! Thin lines along patch and face boundaries, in any mode. The distance of a hit from a
//! boundary `u = 0`, `v = 0` or `u + v = 1` is the parameter value divided by the length of its
//! surface gradient (first fundamental form), compared with the pixel's footprint at the hit, so
//! lines keep a constant width on screen whatever the parametrisation.

use glam::DVec3;

use crate::render::interaction::ShadingPoint;

/// Which boundaries to draw and how wide.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Overlay {
    /// Lines along every patch edge.
    pub patch_edges: bool,
    /// Lines along patch edges that lie on mesh-face edges (drawn 1.6 × wider).
    pub face_edges: bool,
    /// Line width in pixels.
    pub width_px: f64,
}

impl Default for Overlay {
    fn default() -> Self {
        Overlay {
            patch_edges: false,
            face_edges: false,
            width_px: 1.2,
        }
    }
}

impl Overlay {
    /// The overlays' names in scenes (`render.overlay`) and on the command line
    /// (`--overlay`), each with what `render --help` says of it.
    pub const CHOICES: [(&'static str, &'static str); 4] = [
        ("none", "No lines."),
        ("faces", "Lines along mesh-face boundaries."),
        ("patches", "Lines along every patch boundary."),
        ("both", "Both."),
    ];

    /// The names of [`Overlay::CHOICES`].
    pub const NAMES: [&'static str; 4] = crate::error::names(Self::CHOICES);

    /// The overlay called `name` (one of [`Overlay::NAMES`]) at the default width.
    pub fn by_name(name: &str) -> Option<Overlay> {
        let (face_edges, patch_edges) = match name {
            "none" => (false, false),
            "faces" => (true, false),
            "patches" => (false, true),
            "both" => (true, true),
            _ => return None,
        };
        Some(Overlay {
            face_edges,
            patch_edges,
            ..Overlay::default()
        })
    }

    /// True if this overlay draws anything.
    pub fn enabled(&self) -> bool {
        self.patch_edges || self.face_edges
    }

    /// `colour` with the boundary lines painted over it; `footprint` is the world size of a
    /// pixel at the hit, `face_edges` the patch's [`crate::surface::Patch::face_edge_mask`].
    pub fn apply(&self, colour: DVec3, sp: &ShadingPoint, footprint: f64, face_edges: u8) -> DVec3 {
        let jet = &sp.jet;
        let (e, f, g) = (jet.du.dot(jet.du), jet.du.dot(jet.dv), jet.dv.dot(jet.dv));
        let det = e * g - f * f;
        if det.is_nan() || det <= 0.0 {
            return colour;
        }
        let (u, v) = (sp.hit.u, sp.hit.v);
        // Edge 0 is v = 0, edge 1 is u + v = 1, edge 2 is u = 0; |∇u|² = G/D, |∇v|² = E/D,
        // |∇(u+v)|² = (E − 2F + G)/D.
        let distances = [
            v.abs() * (det / e).sqrt(),
            (1.0 - u - v).abs() * (det / (e - 2.0 * f + g)).sqrt(),
            u.abs() * (det / g).sqrt(),
        ];
        let half = 0.5 * self.width_px * footprint;
        for (edge, d) in distances.into_iter().enumerate() {
            let on_face = face_edges & (1 << edge) != 0;
            if self.face_edges && on_face && d <= 1.6 * half {
                return DVec3::splat(0.0);
            }
            if self.patch_edges && d <= half {
                return if on_face {
                    DVec3::splat(0.0)
                } else {
                    DVec3::new(0.02, 0.02, 0.06)
                };
            }
        }
        colour
    }
}
