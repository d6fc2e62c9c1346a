//! Highlight lines [Beier–Chen 1994]: the normal line through the hit meets the plane of an array
//! of parallel line lights; the stripe is the distance, across the lights, of that meeting point.
//! They depend on the normal only (not on the eye), so they stay put when the view turns.

use glam::DVec3;

use crate::error::{Problem, Result};
use crate::render::interaction::ShadingPoint;
use crate::render::modes::keys::{self, Flag, Key, Keys};
use crate::render::modes::stripes::{
    FILTER_KEY, Footprint, NO_STRIPE_FILTER, filtered_square_wave,
};
use crate::render::modes::zebra::{BRIGHT, DARK};
use crate::render::modes::{ModeKind, Setup};
use crate::render::stats::RenderStats;
use crate::render::trace::SurfaceTracer;

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
    /// Distance between neighbouring lights; None: the scene diagonal over `lines`.
    pub spacing: Option<f64>,
    /// Fraction of each period that is bright.
    pub duty: f64,
    /// Number of lights per scene diagonal when `spacing` is None.
    pub lines: f64,
    /// Box-filter the stripes over each sample's screen footprint; false: point samples.
    pub filter: bool,
}

impl Default for HighlightParams {
    fn default() -> Self {
        HighlightParams {
            origin: None,
            plane_normal: DVec3::Y,
            direction: DVec3::X,
            spacing: None,
            duty: 0.5,
            lines: 4.0,
            filter: true,
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
            spacing: Some(
                self.spacing
                    .unwrap_or(diagonal / self.lines.max(f64::MIN_POSITIVE)),
            ),
            ..*self
        }
    }

    /// The stripe phase (in periods) at point `p` with unit normal `n`; None where the normal
    /// half-line does not reach the light plane.
    pub fn phase(&self, p: DVec3, n: DVec3) -> Option<f64> {
        let m = self.plane_normal;
        let origin = self.origin.unwrap_or(DVec3::ZERO);
        let spacing = self.spacing.unwrap_or(1.0);
        let along = n.dot(m);
        let reach = (origin - p).dot(m);
        if along.abs() < 1e-9 || reach / along <= 0.0 {
            return None;
        }
        let meet = p + n * (reach / along);
        let across = m
            .cross(self.direction)
            .normalize_or(m.any_orthonormal_vector());
        Some((meet - origin).dot(across) / spacing)
    }

    /// Bright or dark stripe at the hit ([`HighlightParams::resolved`] first), box-filtered
    /// over `footprint` when given.
    pub fn shade(&self, sp: &ShadingPoint, footprint: Option<&Footprint>) -> DVec3 {
        // The outward normal half-line (turned towards the viewer, so both sides of an open
        // surface behave alike) must reach the light plane; points facing away see no light.
        let Some(phase) = self.phase(sp.jet.p, sp.facing_normal) else {
            return DVec3::splat(DARK);
        };
        let width = match footprint {
            Some(f) if self.filter => {
                f.phase_width(sp, |p, n, _| self.phase(p, n).unwrap_or(phase))
            }
            _ => 0.0,
        };
        DVec3::splat(DARK).lerp(
            DVec3::splat(BRIGHT),
            filtered_square_wave(phase, width, self.duty),
        )
    }
}

impl ModeKind for HighlightParams {
    const NAME: &'static str = "highlight";
    const HELP: &'static str = "View-independent highlight lines of parallel line lights.";
    const KEYS: &'static [Key] = &[
        Key::new(
            "origin",
            "a point of the light plane (default: one scene diagonal above the centre)",
        ),
        Key::new(
            "plane_normal",
            "normal of the light plane (non-zero, default [0, 1, 0])",
        ),
        Key::new(
            "direction",
            "direction of the line lights (non-zero, not along plane_normal; default [1, 0, 0])",
        ),
        Key::new(
            "spacing",
            "distance between lights (positive; instead of lines)",
        ),
        Key::new("lines", "lights per scene diagonal (positive, default 4)"),
        Key::new(
            "duty",
            "bright fraction of a period in [0, 1] (default 0.5)",
        ),
        FILTER_KEY,
    ];
    const FLAGS: &'static [Flag] = &[
        Flag {
            replaces: &["spacing"],
            ..Flag::value(
                "highlight-lines",
                "lines",
                "N",
                "Highlight lights per scene diagonal [default: 4].",
                keys::number,
            )
        },
        NO_STRIPE_FILTER,
    ];

    fn configure(&mut self, keys: &Keys<'_>) -> Result<()> {
        if let Some(o) = keys.point("origin")? {
            self.origin = Some(o);
        }
        if let Some(n) = keys.direction("plane_normal")? {
            self.plane_normal = n;
        }
        if let Some(d) = keys.direction("direction")? {
            self.direction = d;
        }
        keys.one_of("spacing", "lines")?;
        if let Some(s) = keys.positive("spacing")? {
            self.spacing = Some(s);
        }
        if let Some(n) = keys.positive("lines")? {
            self.lines = n;
        }
        if let Some(f) = keys.flag("filter")? {
            self.filter = f;
        }
        if let Some(d) = keys.fraction("duty")? {
            self.duty = d;
        }
        if self.plane_normal.cross(self.direction).length() < 1e-9 {
            return Err(keys.error(
                "direction",
                Problem::Must {
                    value: String::new(),
                    requirement: "not be parallel to highlight.plane_normal".into(),
                },
            ));
        }
        Ok(())
    }

    fn shade(&self, sp: &ShadingPoint, footprint: Option<&Footprint>) -> DVec3 {
        HighlightParams::shade(self, sp, footprint)
    }

    fn filtered(&self) -> bool {
        self.filter
    }

    /// The lights are placed from the scene's centre and diagonal.
    fn set_up<T: SurfaceTracer>(&self, setup: &Setup<'_, T>, _stats: &mut RenderStats) -> Self {
        let bounds = setup.tracer.bounds();
        self.resolved(bounds.center(), bounds.diagonal())
    }
}
