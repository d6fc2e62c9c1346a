//! Shading modes: each turns the exact local geometry of the closest hit (normal, curvatures,
//! patch and face) into a linear RGB colour. Every quantity is evaluated from the patch itself
//! at the hit, never interpolated, so stripes and colours do not depend on any mesh density.

pub mod curvature;
pub mod diffuse;
pub mod highlight;
pub mod isophote;
pub mod keys;
pub mod normals;
pub mod overlay;
pub mod palette;
pub mod patches;
pub mod shaded;
pub mod stripes;
pub mod zebra;

use glam::DVec3;

use crate::render::camera::Camera;
use crate::render::interaction::ShadingPoint;
use crate::render::intersect::IntersectCounters;
use crate::render::stats::RenderStats;
use crate::render::theme::{Legend, LegendStyle, Theme};
use crate::render::trace::SurfaceTracer;

pub use curvature::{
    CurvatureMap, CurvatureParams, CurvatureQuantity, CurvatureRange, CurvatureSign,
};
pub use diffuse::Diffuse;
pub use highlight::HighlightParams;
pub use isophote::IsophoteParams;
pub use keys::{Flag, Key, Keys};
pub use normals::Normals;
pub use overlay::Overlay;
pub use patches::Patches;
pub use stripes::Footprint;
pub use zebra::{ZebraAxis, ZebraParams};

/// What a mode's scene-dependent set-up sees before a frame is rendered: the tracer (bounds,
/// probe rays), the camera and the image size.
pub struct Setup<'a, T: SurfaceTracer> {
    /// The surface's tracer.
    pub tracer: &'a T,
    /// The camera of the frame.
    pub camera: &'a Camera,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
}

/// The identity of one camera sample, for modes whose colour is a random estimate (the path
/// tracer), and the rays it traced beyond the camera ray.
pub struct Sample<'a> {
    /// Render seed.
    pub seed: u64,
    /// Pixel index (row-major).
    pub pixel: u64,
    /// Sample index in the pixel.
    pub sample: u32,
    /// Intersection counters of the tile.
    pub counters: &'a mut IntersectCounters,
    /// Secondary rays traced.
    pub rays: u64,
    /// Secondary rays that hit.
    pub hits: u64,
}

/// A render mode: one type holding its parameters, and everything about the mode — its name,
/// help, scene keys and command-line flags with their checks, its set-up from the scene, its
/// colour of a hit, its legend beside the image, its cost. One file per mode implements
/// it; one line of `modes!` registers it. Nothing outside `render/modes/` names a mode.
///
/// Every method has the plain answer as default; a mode overrides what it has.
pub trait ModeKind: Clone + std::fmt::Debug + PartialEq + Default + Send + Sync {
    /// Name in `--mode`, scene files (`render.mode`) and figure specs; also its section's
    /// name (`[zebra]`).
    const NAME: &'static str;
    /// One line for `render -h`.
    const HELP: &'static str;
    /// The keys of its section.
    const KEYS: &'static [Key] = &[];
    /// Its command-line flags, each setting one key of its section.
    const FLAGS: &'static [Flag] = &[];
    /// Cost of a sample relative to a directly shaded one (sharding balances on it).
    const COST: f64 = 1.0;

    /// Reads the keys of its section into `self` (the defaults), checking each.
    fn configure(&mut self, keys: &Keys<'_>) -> crate::Result<()> {
        let _ = keys;
        Ok(())
    }

    /// Linear RGB of a hit, point-sampled, or box-filtered over `footprint` when given (the
    /// change of the hit across one sample cell, see [`ModeKind::filtered`]).
    fn shade(&self, sp: &ShadingPoint, footprint: Option<&Footprint>) -> DVec3;

    /// The colour of a camera sample whose closest hit is `sp`: [`ModeKind::shade`] unless the
    /// mode traces further rays (the path tracer).
    fn radiance<T: SurfaceTracer>(
        &self,
        tracer: &T,
        sp: &ShadingPoint,
        footprint: Option<&Footprint>,
        sample: &mut Sample<'_>,
    ) -> DVec3 {
        let _ = (tracer, sample);
        self.shade(sp, footprint)
    }

    /// Whether it wants each sample's [`Footprint`] (the stripe filter).
    fn filtered(&self) -> bool {
        false
    }

    /// The mode with its scene-dependent parameters filled in before a frame (light
    /// placement, the camera's up, an automatic colour range, recorded in `stats`).
    fn set_up<T: SurfaceTracer>(&self, setup: &Setup<'_, T>, stats: &mut RenderStats) -> Self {
        let _ = (setup, stats);
        self.clone()
    }

    /// Its legend, a strip `height` pixels tall drawn in `style`, that the PNG places right
    /// of the image (None: no legend).
    fn legend(&self, height: u32, style: &LegendStyle) -> Option<Legend> {
        let _ = (height, style);
        None
    }

    /// The mode as `theme` shows it (the paper theme's default colour map of the curvature
    /// mode).
    fn themed(&self, theme: Theme) -> Self {
        let _ = theme;
        self.clone()
    }

    /// The mode with back-face hits tinted where it shows surface quality (what an open
    /// surface is rendered with, so that its other side stands out).
    fn with_back_faces_tinted(&self) -> Self {
        self.clone()
    }

    /// Frame `shift` (0 to 1: one period) of a stripe sweep at a fixed camera; None: the mode
    /// has no stripes to move.
    fn swept(&self, shift: f64) -> Option<Self> {
        let _ = shift;
        None
    }

    /// Whether its colours follow a scale fitted to the scene (a half-range, as the
    /// curvature map's), which figures share across cells and animations across frames.
    fn has_scale(&self) -> bool {
        false
    }

    /// Whether that scale is chosen from the view (automatic) rather than given.
    fn scale_is_automatic(&self) -> bool {
        false
    }

    /// The mode with its scale fixed to `half_range`.
    fn with_scale(&self, half_range: f64) -> Self {
        let _ = half_range;
        self.clone()
    }

    /// The automatic scale this mode would choose for the view of `setup` (None: no scale).
    fn measure_scale<T: SurfaceTracer>(&self, setup: &Setup<'_, T>) -> Option<f64> {
        let _ = setup;
        None
    }

    /// Whether [`ModeKind::set_up`] chooses parameters from the view (an automatic scale,
    /// an automatic stripe count), which every later frame of an animation takes from the
    /// first ([`ModeKind::pinned`]).
    fn chosen_from_view(&self) -> bool {
        false
    }

    /// The mode with the parameters its set-up chose for a frame (recorded in `stats`)
    /// fixed: what every later frame of an animation is rendered with.
    fn pinned(&self, stats: &RenderStats) -> Self {
        let _ = stats;
        self.clone()
    }
}

/// The registry: one line per mode (`Variant(Type)`, `Type` implementing [`ModeKind`]). It
/// makes the [`Mode`] enum, the list of names and every dispatch (a `match`, no dynamic
/// dispatch in the render loop).
macro_rules! modes {
    ($($(#[$doc:meta])* $variant:ident($ty:ty),)*) => {
        /// A render mode with its parameters: one variant per registered [`ModeKind`].
        #[derive(Clone, Debug, PartialEq)]
        pub enum Mode {
            $($(#[$doc])* $variant($ty),)*
        }

        /// Mode names accepted by `--mode` and scene files, in registry order.
        pub const MODE_NAMES: &[&str] = &[$(<$ty as ModeKind>::NAME,)*];

        /// Every mode's name and one-line help, in registry order.
        pub const MODE_HELP: &[(&str, &str)] = &[$((<$ty as ModeKind>::NAME, <$ty as ModeKind>::HELP),)*];

        /// Every mode's name with its section's keys, in registry order.
        pub const MODE_KEYS: &[(&str, &[Key])] = &[$((<$ty as ModeKind>::NAME, <$ty as ModeKind>::KEYS),)*];

        /// Every mode's name with its command-line flags, in registry order.
        pub const MODE_FLAGS: &[(&str, &[Flag])] = &[$((<$ty as ModeKind>::NAME, <$ty as ModeKind>::FLAGS),)*];

        impl Mode {
            /// The mode called `name` with default parameters.
            pub fn by_name(name: &str) -> crate::Result<Mode> {
                $(if name == <$ty as ModeKind>::NAME {
                    return Ok(Mode::$variant(<$ty>::default()));
                })*
                Err(crate::Error::unknown_name("render mode", name, MODE_NAMES))
            }

            /// The mode's name.
            pub fn name(&self) -> &'static str {
                match self {
                    $(Mode::$variant(_) => <$ty as ModeKind>::NAME,)*
                }
            }

            /// Cost of a sample relative to a directly shaded one.
            pub fn cost(&self) -> f64 {
                match self {
                    $(Mode::$variant(_) => <$ty as ModeKind>::COST,)*
                }
            }

            /// Reads the keys of the mode's section (`table`, checked against its keys).
            pub fn configure(&mut self, table: &toml::Table) -> crate::Result<()> {
                match self {
                    $(Mode::$variant(p) => {
                        let keys = Keys::new(<$ty as ModeKind>::NAME, table, <$ty as ModeKind>::KEYS)?;
                        <$ty as ModeKind>::configure(p, &keys)
                    })*
                }
            }

            /// See [`ModeKind::shade`].
            pub fn shade_filtered(&self, sp: &ShadingPoint, footprint: Option<&Footprint>) -> DVec3 {
                match self {
                    $(Mode::$variant(p) => <$ty as ModeKind>::shade(p, sp, footprint),)*
                }
            }

            /// See [`ModeKind::radiance`].
            pub fn radiance<T: SurfaceTracer>(
                &self,
                tracer: &T,
                sp: &ShadingPoint,
                footprint: Option<&Footprint>,
                sample: &mut Sample<'_>,
            ) -> DVec3 {
                match self {
                    $(Mode::$variant(p) => <$ty as ModeKind>::radiance(p, tracer, sp, footprint, sample),)*
                }
            }

            /// See [`ModeKind::filtered`].
            pub fn uses_footprint(&self) -> bool {
                match self {
                    $(Mode::$variant(p) => <$ty as ModeKind>::filtered(p),)*
                }
            }

            /// See [`ModeKind::set_up`].
            pub fn set_up<T: SurfaceTracer>(&self, setup: &Setup<'_, T>, stats: &mut RenderStats) -> Mode {
                match self {
                    $(Mode::$variant(p) => Mode::$variant(<$ty as ModeKind>::set_up(p, setup, stats)),)*
                }
            }

            /// See [`ModeKind::legend`].
            pub fn legend(&self, height: u32, style: &LegendStyle) -> Option<Legend> {
                match self {
                    $(Mode::$variant(p) => <$ty as ModeKind>::legend(p, height, style),)*
                }
            }

            /// See [`ModeKind::themed`].
            pub fn themed(&self, theme: Theme) -> Mode {
                match self {
                    $(Mode::$variant(p) => Mode::$variant(<$ty as ModeKind>::themed(p, theme)),)*
                }
            }

            /// See [`ModeKind::with_back_faces_tinted`].
            pub fn with_back_faces_tinted(&self) -> Mode {
                match self {
                    $(Mode::$variant(p) => Mode::$variant(<$ty as ModeKind>::with_back_faces_tinted(p)),)*
                }
            }

            /// See [`ModeKind::swept`].
            pub fn swept(&self, shift: f64) -> Option<Mode> {
                match self {
                    $(Mode::$variant(p) => <$ty as ModeKind>::swept(p, shift).map(Mode::$variant),)*
                }
            }

            /// See [`ModeKind::has_scale`].
            pub fn has_scale(&self) -> bool {
                match self {
                    $(Mode::$variant(p) => <$ty as ModeKind>::has_scale(p),)*
                }
            }

            /// See [`ModeKind::scale_is_automatic`].
            pub fn scale_is_automatic(&self) -> bool {
                match self {
                    $(Mode::$variant(p) => <$ty as ModeKind>::scale_is_automatic(p),)*
                }
            }

            /// See [`ModeKind::with_scale`].
            pub fn with_scale(&self, half_range: f64) -> Mode {
                match self {
                    $(Mode::$variant(p) => Mode::$variant(<$ty as ModeKind>::with_scale(p, half_range)),)*
                }
            }

            /// See [`ModeKind::chosen_from_view`].
            pub fn chosen_from_view(&self) -> bool {
                match self {
                    $(Mode::$variant(p) => <$ty as ModeKind>::chosen_from_view(p),)*
                }
            }

            /// The mode with the parameters a render chose from its view (`stats`) fixed:
            /// what every later frame of an animation is rendered with, in the colours and
            /// stripes of the first ([`ModeKind::pinned`]).
            pub fn pinned(&self, stats: &RenderStats) -> Mode {
                match self {
                    $(Mode::$variant(p) => Mode::$variant(<$ty as ModeKind>::pinned(p, stats)),)*
                }
            }

            /// See [`ModeKind::measure_scale`].
            pub fn measure_scale<T: SurfaceTracer>(&self, setup: &Setup<'_, T>) -> Option<f64> {
                match self {
                    $(Mode::$variant(p) => <$ty as ModeKind>::measure_scale(p, setup),)*
                }
            }
        }
    };
}

modes! {
    /// Reflection lines of an environment of parallel light stripes.
    Zebra(ZebraParams),
    /// View-independent highlight lines (Beier–Chen) of an array of parallel line lights.
    Highlight(HighlightParams),
    /// Bands of constant `n·L`.
    Isophote(IsophoteParams),
    /// A curvature quantity through a diverging colour map.
    Curvature(CurvatureParams),
    /// The normal as a colour, `(n + 1) / 2`.
    Normals(Normals),
    /// One colour per face, shaded lighter or darker per piece.
    Patches(Patches),
    /// Plain light grey lit from the eye: a quiet background for the curve-network tubes.
    Diffuse(Diffuse),
    /// Path-traced clear-coat material in a studio environment.
    Shaded(crate::render::shaded::ShadedParams),
}

/// The keys of the section of mode `name` (none for a name not registered).
pub fn keys_of(name: &str) -> &'static [Key] {
    MODE_KEYS
        .iter()
        .find(|(mode, _)| *mode == name)
        .map_or(&[], |(_, keys)| keys)
}

/// The mode of a scene or command line that names none: the first registered.
pub const DEFAULT_MODE: &str = MODE_NAMES[0];

impl Default for Mode {
    /// The first registered mode with its defaults.
    fn default() -> Mode {
        // The registry above is not empty, and a registered name is always known.
        Mode::by_name(DEFAULT_MODE).unwrap_or(Mode::Zebra(ZebraParams::default()))
    }
}

impl Mode {
    /// The mode called `name` with the keys of its section (`table`) read and checked.
    pub fn configured(name: &str, table: &toml::Table) -> crate::Result<Mode> {
        let mut mode = Mode::by_name(name)?;
        mode.configure(table)?;
        Ok(mode)
    }

    /// Linear RGB of a hit, point-sampled (the path tracer's mode gives a plain diffuse
    /// preview here).
    pub fn shade(&self, sp: &ShadingPoint) -> DVec3 {
        self.shade_filtered(sp, None)
    }

    /// Whether a stripe sweep can move this mode's stripes.
    pub fn sweeps(&self) -> bool {
        self.swept(0.0).is_some()
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
            Mode::by_name("zebra").expect("zebra"),
            Mode::by_name("curvature").expect("curvature"),
        ] {
            let tinted = mode.with_back_faces_tinted();
            assert_eq!(tinted.shade(&front), mode.shade(&front), "{}", mode.name());
            assert_ne!(tinted.shade(&back), mode.shade(&back), "{}", mode.name());
        }
    }
}
