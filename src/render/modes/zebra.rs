//! Reflection lines (zebra).
//!
//! The eye ray is mirrored at the hit and looks up an environment of infinitely long
//! light tubes parallel to `axis`, spread evenly around it: the stripe index is the angle of the
//! reflected direction around `axis`. A G¹ break of the surface shows as a kink of the stripes,
//! a G² break as a kink of their direction field.

use glam::DVec3;

use crate::error::{Error, Problem, Result};
use crate::render::interaction::ShadingPoint;
use crate::render::modes::keys::{self, Flag, Key, Keys};
use crate::render::modes::stripes::{
    FILTER_KEY, Footprint, NO_STRIPE_FILTER, filtered_square_wave, readable_stripes,
};
use crate::render::modes::{ModeKind, Setup};
use crate::render::stats::RenderStats;
use crate::render::trace::SurfaceTracer;

/// Linear-light brightness of a bright stripe and of a dark one.
pub(crate) const BRIGHT: f64 = 0.9;
pub(crate) const DARK: f64 = 0.015;

/// Where the light tubes of the zebra environment run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ZebraAxis {
    /// Tubes parallel to this world direction; the stripe index is the angle of the reflected
    /// direction around it. Its two poles (reflected direction along ±axis), where every
    /// stripe meets, fall inside the view of a closed surface.
    World(DVec3),
    /// Tubes attached to the view: the reflected direction is measured from the direction back
    /// along the ray (azimuthal equidistant projection around it) and the stripes are its
    /// lines of constant image-horizontal coordinate, so they run vertically on screen. The
    /// only pole is the reflected direction along the ray, i.e. the silhouette, never inside
    /// the view.
    View,
    /// As [`ZebraAxis::View`], with stripes running horizontally on screen.
    ViewHorizontal,
}

impl ZebraAxis {
    /// Names of the view-attached axes accepted in scenes and on the command line.
    pub const VIEW_NAMES: [&'static str; 2] = ["view", "view-horizontal"];

    /// `view`, `view-horizontal` or a world direction `X,Y,Z` (non-zero).
    pub fn parse(text: &str) -> crate::Result<ZebraAxis> {
        match text.trim() {
            "view" => return Ok(ZebraAxis::View),
            "view-horizontal" => return Ok(ZebraAxis::ViewHorizontal),
            _ => {}
        }
        let parts: Vec<Option<f64>> = text
            .split(',')
            .map(|p| p.trim().parse::<f64>().ok().filter(|x| x.is_finite()))
            .collect();
        match parts.as_slice() {
            [Some(x), Some(y), Some(z)] if DVec3::new(*x, *y, *z).length() > 0.0 => {
                Ok(ZebraAxis::World(DVec3::new(*x, *y, *z).normalize()))
            }
            _ => Err(Error::config(
                "zebra axis",
                Problem::Neither {
                    value: format!("'{text}'"),
                    forms: "view, view-horizontal nor a non-zero X,Y,Z".into(),
                },
            )),
        }
    }
}

/// Parameters of the zebra (reflection line) mode.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ZebraParams {
    /// Where the light tubes run.
    pub axis: ZebraAxis,
    /// Number of bright stripes per full turn (2π) of the reflected direction; with
    /// `auto_stripes`, the most a view is given.
    pub stripes: f64,
    /// Choose the stripe count from the view before a frame: `stripes`, or fewer where they
    /// would be narrower than [`READABLE_PERIOD_PX`](super::stripes::READABLE_PERIOD_PX) on screen ([`readable_stripes`]). Set
    /// by default; off as soon as `stripes` or `width` is given.
    pub auto_stripes: bool,
    /// Fraction of each period that is bright.
    pub duty: f64,
    /// Linear RGB of the bright stripes.
    pub bright: DVec3,
    /// Linear RGB of the dark stripes.
    pub dark: DVec3,
    /// The image's up direction (filled in from the camera before rendering; used by the
    /// view-attached axes).
    pub view_up: DVec3,
    /// Box-filter the stripes over each sample's screen footprint (see
    /// [`crate::render::modes::stripes`]); false: point samples.
    pub filter: bool,
    /// Shift of the stripes, in periods (0 to 1 moves them by one period; used by stripe
    /// sweeps).
    pub shift: f64,
    /// Shade hits on the back of the surface (patch normal facing away from the eye) with
    /// [`crate::render::modes::palette::back_face`]; set for open surfaces, whose back shows.
    pub tint_back_faces: bool,
}

impl Default for ZebraParams {
    fn default() -> Self {
        ZebraParams {
            axis: ZebraAxis::View,
            stripes: 16.0,
            auto_stripes: true,
            duty: 0.5,
            bright: DVec3::splat(BRIGHT),
            dark: DVec3::splat(DARK),
            view_up: DVec3::Y,
            filter: true,
            shift: 0.0,
            tint_back_faces: false,
        }
    }
}

impl ZebraParams {
    /// The stripe phase (in periods) of a hit at normal `n` seen along unit `view`.
    pub fn phase(&self, n: DVec3, view: DVec3) -> f64 {
        self.stripes * self.turns(n, view) - self.shift
    }

    /// The angle of the reflected direction about the light tubes, in full turns: the phase
    /// of one stripe per turn, which [`ZebraParams::phase`] multiplies by the stripe count.
    fn turns(&self, n: DVec3, view: DVec3) -> f64 {
        self.turns_and_slopes(n, view, None).0
    }

    /// The width, in turns, of the interval [`ZebraParams::turns`] sweeps over the footprint
    /// `f` of a hit at normal `n` seen along `view`, given its `slopes` from
    /// [`ZebraParams::turns_and_slopes`]: `|∂τ/∂x| + |∂τ/∂y|`, the quantity
    /// [`Footprint::phase_width`] estimates by central differences (one evaluation of the
    /// angle with its derivatives, where the differences take four). The differences are
    /// kept for the degenerate cases the derivative does not cover (view along the image's
    /// up direction, reflected direction along a pole).
    fn turns_width(&self, sp: &ShadingPoint, f: &Footprint, slopes: Option<[f64; 2]>) -> f64 {
        match slopes {
            Some([a, b]) if (a.abs() + b.abs()).is_finite() => a.abs() + b.abs(),
            _ => f.phase_width(sp, |_, n, v| self.turns(n, v)),
        }
    }

    /// [`ZebraParams::turns`] at unit normal `n` and unit view `v`, and, for a footprint whose
    /// two directions move the normal by `dn[k]` and the view by `dv[k]` (both then
    /// renormalised, as [`Footprint::phase_width`] does), its derivatives along them:
    /// forward-mode differentiation of the same formula, sharing its reflection, frame and
    /// angle. The derivatives are None where they are singular.
    ///
    /// View axes: azimuthal equidistant coordinates around −view, the angle `θ` of the
    /// reflected direction `r` from −view times the direction of its part `(x, y)` across the
    /// view. With `c = −r·v`, `|(x, y)| = sin θ = √(1 − c²)`, so the angle is `g(c) · x` (or
    /// `· y`) with `g(c) = acos c / √(1 − c²)` and `g′(c) = (c g − 1) / (1 − c²)`, which tends
    /// to `−1/3 − 4(1 − c)/15` as the reflected direction comes back along the ray (`c → 1`,
    /// normal incidence), where the series is used. World axis: `atan2(r·b₂, r·b₁)` and its
    /// derivative.
    fn turns_and_slopes(
        &self,
        n: DVec3,
        v: DVec3,
        moves: Option<([DVec3; 2], [DVec3; 2])>,
    ) -> (f64, Option<[f64; 2]>) {
        let k = v.dot(n);
        let r = v - 2.0 * k * n;
        // The moves of the unit normal and view: the parts of `dn`, `dv` across them.
        let moves = moves
            .map(|(dn, dv)| [0, 1].map(|i| (dn[i] - n * n.dot(dn[i]), dv[i] - v * v.dot(dv[i]))));
        let reflected_move =
            |(n1, v1): (DVec3, DVec3)| v1 - 2.0 * ((v1.dot(n) + v.dot(n1)) * n + k * n1);
        let (angle, slopes) = match self.axis {
            ZebraAxis::World(axis) => {
                let (b1, b2) = axis.normalize_or(DVec3::Y).any_orthonormal_pair();
                let (a, b) = (r.dot(b1), r.dot(b2));
                let norm = a * a + b * b;
                let slopes = moves.filter(|_| !norm.is_nan() && norm > 0.0).map(|moves| {
                    moves.map(|m| {
                        let r1 = reflected_move(m);
                        (a * r1.dot(b2) - b * r1.dot(b1)) / norm
                    })
                });
                (b.atan2(a), slopes)
            }
            ZebraAxis::View | ZebraAxis::ViewHorizontal => {
                let w = self.view_up - v * self.view_up.dot(v);
                let up = w.normalize_or(DVec3::Y);
                let right = v.cross(up);
                let (x, y) = (r.dot(right), r.dot(up));
                let across = x.hypot(y);
                // θ from its sine and cosine: `acos` of the cosine alone loses half the digits
                // near normal incidence (θ → 0).
                let cosine = -r.dot(v);
                let theta = across.atan2(cosine);
                let horizontal = self.axis == ZebraAxis::ViewHorizontal;
                let sel = if horizontal { y } else { x };
                let length = w.length();
                let c = cosine.clamp(-1.0, 1.0);
                // θ / sin θ, 1 at normal incidence (none where r runs along +v).
                let g = if across > 0.0 {
                    Some(if c == cosine { theta } else { across.atan2(c) } / across)
                } else {
                    (c > 0.0).then_some(1.0)
                };
                let slopes = moves
                    .zip(g)
                    .filter(|_| !length.is_nan() && length > 0.0)
                    .map(|(moves, g)| {
                        let e = 1.0 - c;
                        let g1 = if e < 1e-6 {
                            -1.0 / 3.0 - 4.0 / 15.0 * e
                        } else {
                            (c * g - 1.0) / (across * across)
                        };
                        moves.map(|(n1, v1)| {
                            let r1 = reflected_move((n1, v1));
                            let w1 = -(v1 * self.view_up.dot(v) + v * self.view_up.dot(v1));
                            let up1 = (w1 - up * up.dot(w1)) / length;
                            let right1 = v1.cross(up) + v.cross(up1);
                            let c1 = -(r1.dot(v) + r.dot(v1));
                            let sel1 = if horizontal {
                                r1.dot(up) + r.dot(up1)
                            } else {
                                r1.dot(right) + r.dot(right1)
                            };
                            g1 * c1 * sel + g * sel1
                        })
                    });
                let angle = if across > 0.0 {
                    theta * sel / across
                } else {
                    0.0
                };
                (angle, slopes)
            }
        };
        let tau = std::f64::consts::TAU;
        (angle / tau, slopes.map(|s| s.map(|s| s / tau)))
    }

    /// Bright or dark stripe at the hit, box-filtered over `footprint` when given. The filter
    /// width is the stripe count times the width in turns: the phase is linear in the count,
    /// and differences of the turns stay resolved for any count (differences of the phase
    /// itself lose every digit once the count is large).
    pub fn shade(&self, sp: &ShadingPoint, footprint: Option<&Footprint>) -> DVec3 {
        let filtered = footprint.filter(|_| self.filter);
        let (turns, slopes) =
            self.turns_and_slopes(sp.facing_normal, sp.view, filtered.map(|f| (f.dn, f.dv)));
        let phase = self.stripes * turns - self.shift;
        let width = match filtered {
            Some(f) => self.stripes.abs() * self.turns_width(sp, f, slopes),
            None => 0.0,
        };
        let bright = filtered_square_wave(phase, width, self.duty);
        let colour = self.dark.lerp(self.bright, bright);
        if self.tint_back_faces && sp.is_back_face() {
            super::palette::back_face(colour)
        } else {
            colour
        }
    }
}

/// The period in degrees of a zebra width: `thin` (11.25°), `medium` (22.5°), `thick` (45°)
/// or a number of degrees in (0, 360].
pub fn zebra_width_deg(text: &str) -> Result<f64> {
    match text.trim() {
        "thin" => Ok(11.25),
        "medium" => Ok(22.5),
        "thick" => Ok(45.0),
        other => match other.parse::<f64>() {
            Ok(x) if x > 0.0 && x <= 360.0 => Ok(x),
            _ => Err(Error::config(
                "zebra.width",
                Problem::Neither {
                    value: format!("= {text}"),
                    forms: "thin, medium, thick nor degrees in (0, 360]".into(),
                },
            )),
        },
    }
}

impl ModeKind for ZebraParams {
    const NAME: &'static str = "zebra";
    const HELP: &'static str = "Reflection lines of parallel light tubes.";
    const KEYS: &'static [Key] = &[
        Key::new(
            "axis",
            "direction of the light tubes: \"view\", \"view-horizontal\" or [x, y, z] (default view)",
        ),
        Key::new(
            "stripes",
            "bright stripes per full turn (positive; default: 16, or fewer where a view would show them narrower than 12 pixels)",
        ),
        Key::new(
            "width",
            "period of the stripes: thin, medium, thick or degrees in (0, 360] (instead of stripes)",
        ),
        Key::new(
            "duty",
            "bright fraction of a period in [0, 1] (default 0.5)",
        ),
        Key::new(
            "bright",
            "linear RGB of the bright stripes (default [0.9, 0.9, 0.9])",
        ),
        Key::new(
            "dark",
            "linear RGB of the dark stripes (default [0.015, 0.015, 0.015])",
        ),
        FILTER_KEY,
    ];
    const FLAGS: &'static [Flag] = &[
        Flag::value(
            "zebra-axis",
            "axis",
            "AXIS",
            "Zebra light-tube axis: `view` (stripes vertical on screen, poles only on the silhouette), `view-horizontal`, or a world direction `X,Y,Z` [default: view].",
            keys::triple_or_text,
        ),
        Flag {
            replaces: &["width"],
            conflicts: &["zebra-width"],
            ..Flag::value(
                "zebra-stripes",
                "stripes",
                "N",
                "Zebra bright stripes per full turn of the reflected direction [default: 16, or fewer where they would be narrower than 12 pixels on screen].",
                keys::number,
            )
        },
        Flag {
            replaces: &["stripes"],
            conflicts: &["zebra-stripes"],
            hyphen_values: false,
            ..Flag::value(
                "zebra-width",
                "width",
                "WIDTH",
                "Zebra stripe period: thin (11.25°), medium (22.5°), thick (45°) or degrees.",
                keys::text,
            )
        },
        Flag::value(
            "zebra-duty",
            "duty",
            "F",
            "Bright fraction of a zebra period, 0..1 [default: 0.5].",
            keys::number,
        ),
        Flag {
            hyphen_values: false,
            ..Flag::value(
                "zebra-bright",
                "bright",
                "R,G,B",
                "Linear RGB of the bright zebra stripes `R,G,B` [default: 0.9,0.9,0.9].",
                keys::triple,
            )
        },
        Flag {
            hyphen_values: false,
            ..Flag::value(
                "zebra-dark",
                "dark",
                "R,G,B",
                "Linear RGB of the dark zebra stripes `R,G,B` [default: 0.015,0.015,0.015].",
                keys::triple,
            )
        },
        NO_STRIPE_FILTER,
    ];

    fn configure(&mut self, keys: &Keys<'_>) -> Result<()> {
        match keys.value("axis") {
            None => {}
            Some(toml::Value::String(name)) if ZebraAxis::VIEW_NAMES.contains(&name.as_str()) => {
                self.axis = ZebraAxis::parse(name)?;
            }
            Some(v @ toml::Value::Array(items)) if items.len() == 3 => {
                let a = keys.as_triple("axis", v)?;
                self.axis = ZebraAxis::World(keys::direction("zebra.axis", a)?);
            }
            Some(other) => {
                return Err(keys.error(
                    "axis",
                    Problem::Neither {
                        value: format!("= {other}"),
                        forms: "\"view\", \"view-horizontal\" nor [x, y, z]".into(),
                    },
                ));
            }
        }
        keys.one_of("stripes", "width")?;
        if let Some(s) = keys.positive("stripes")? {
            self.stripes = s;
            self.auto_stripes = false;
        }
        if let Some(w) = keys.value("width") {
            let text = match w {
                toml::Value::String(s) => s.clone(),
                other => other.to_string(),
            };
            self.stripes = 360.0 / zebra_width_deg(&text)?;
            self.auto_stripes = false;
        }
        if let Some(d) = keys.fraction("duty")? {
            self.duty = d;
        }
        if let Some(c) = keys.colour("bright")? {
            self.bright = c;
        }
        if let Some(c) = keys.colour("dark")? {
            self.dark = c;
        }
        if let Some(f) = keys.flag("filter")? {
            self.filter = f;
        }
        Ok(())
    }

    fn shade(&self, sp: &ShadingPoint, footprint: Option<&Footprint>) -> DVec3 {
        ZebraParams::shade(self, sp, footprint)
    }

    fn filtered(&self) -> bool {
        self.filter
    }

    /// The view-attached axes follow the camera's up.
    /// Takes the camera's up and, with `auto_stripes`, the view's stripe count (recorded in
    /// `stats.zebra_stripes`).
    fn set_up<T: SurfaceTracer>(&self, setup: &Setup<'_, T>, stats: &mut RenderStats) -> Self {
        let mut set = ZebraParams {
            view_up: setup.camera.up(),
            ..*self
        };
        if self.auto_stripes {
            set.stripes = readable_stripes(setup, self.stripes, |n, v| set.turns(n, v));
            set.auto_stripes = false;
            stats.zebra_stripes = Some(set.stripes);
        }
        set
    }

    fn chosen_from_view(&self) -> bool {
        self.auto_stripes
    }

    fn pinned(&self, stats: &RenderStats) -> Self {
        match stats.zebra_stripes {
            Some(stripes) if self.auto_stripes => ZebraParams {
                stripes,
                auto_stripes: false,
                ..*self
            },
            _ => *self,
        }
    }

    fn with_back_faces_tinted(&self) -> Self {
        ZebraParams {
            tint_back_faces: true,
            ..*self
        }
    }

    fn swept(&self, shift: f64) -> Option<Self> {
        Some(ZebraParams { shift, ..*self })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The stripe count is chosen from the view unless `stripes` or `width` is given; the
    /// set-up records the count it chose, and a pinned mode keeps it for later frames.
    #[test]
    fn stripe_count_is_chosen_from_the_view_unless_given() {
        use crate::render::camera::Camera;
        use crate::render::intersect::Tracer;
        assert!(ZebraParams::default().auto_stripes);
        for given in ["stripes = 16", "width = \"thin\""] {
            let table: toml::Table = toml::from_str(given).expect("toml");
            let mut p = ZebraParams::default();
            ModeKind::configure(
                &mut p,
                &Keys::new("zebra", &table, ZebraParams::KEYS).expect("keys"),
            )
            .expect("valid");
            assert!(!p.auto_stripes && !p.chosen_from_view(), "{given}");
        }
        let surface = crate::testing::surfaces::octahedron_sphere(3, 1.0, 0);
        let tracer = Tracer::with_default_settings(&surface).expect("tracer");
        let camera =
            Camera::frame(&surface.bounds(), Camera::DEFAULT_VIEW, 35.0, 1.0).expect("camera");
        let setup = |side: u32| Setup {
            tracer: &tracer,
            camera: &camera,
            width: side,
            height: side,
        };
        let auto = ZebraParams::default();
        let mut stats = RenderStats::default();
        let small = auto.set_up(&setup(24), &mut stats);
        let chosen = stats.zebra_stripes.expect("a chosen count");
        assert!(chosen < 16.0, "{chosen}");
        assert_eq!(small.stripes, chosen);
        assert!(!small.auto_stripes);
        // Pinned, the mode keeps that count at any size.
        let pinned = auto.pinned(&stats);
        let mut later = RenderStats::default();
        assert_eq!(pinned.set_up(&setup(1024), &mut later).stripes, chosen);
        assert_eq!(later.zebra_stripes, None);
        // A given count is kept and nothing is recorded.
        let given = ZebraParams {
            auto_stripes: false,
            ..auto
        };
        let mut none = RenderStats::default();
        assert_eq!(given.set_up(&setup(24), &mut none).stripes, 16.0);
        assert_eq!(none.zebra_stripes, None);
    }

    #[test]
    fn axes_parse() {
        assert_eq!(ZebraAxis::parse("view").expect("view"), ZebraAxis::View);
        assert_eq!(
            ZebraAxis::parse("0,2,0").expect("vector"),
            ZebraAxis::World(DVec3::Y)
        );
        for bad in ["0,0,0", "1,2", "up", "1,nan,0"] {
            let err = ZebraAxis::parse(bad).expect_err(bad).to_string();
            assert!(err.contains(bad), "{err}");
        }
    }

    /// A hit on the paraboloid `z = (x² + y²)/2` at the origin, seen from `eye`, with the
    /// footprint of a 1e-3 cell.
    fn curved_hit(eye: DVec3) -> (ShadingPoint, Footprint) {
        use crate::geom::Jet;
        use crate::render::intersect::{Hit, Ray64};
        let jet = Jet {
            p: DVec3::ZERO,
            du: DVec3::X,
            dv: DVec3::Y,
            duu: DVec3::Z,
            dvv: DVec3::Z,
            ..Jet::default()
        };
        let ray = Ray64::new(eye, -eye);
        let hit = Hit {
            t: eye.length(),
            patch: 0,
            u: 0.0,
            v: 0.0,
        };
        let sp = ShadingPoint::new(hit, 0, 0, jet, &ray);
        let right = Ray64::new(eye, DVec3::new(1e-3, 0.0, 0.0) - eye);
        let down = Ray64::new(eye, DVec3::new(0.0, 1e-3, 0.0) - eye);
        let footprint = Footprint::new(&sp, &ray, [&right, &down]).expect("footprint");
        (sp, footprint)
    }

    /// Stripe counts far beyond what one cell resolves shade as the mean grey, from the
    /// count where the filter covers many periods up to the largest finite count; a
    /// moderate count keeps its crisp stripe.
    #[test]
    fn unresolvable_stripe_counts_shade_as_the_mean_grey() {
        let (sp, footprint) = curved_hit(DVec3::new(0.3, 0.2, 5.0));
        let mean = DVec3::splat(DARK).lerp(DVec3::splat(BRIGHT), 0.5);
        for stripes in [1e8, 1e12, 1e15, 1e20, 1e300] {
            let z = ZebraParams {
                stripes,
                ..ZebraParams::default()
            };
            let got = z.shade(&sp, Some(&footprint));
            assert!((got - mean).abs().max_element() < 1e-3, "{stripes}: {got}");
        }
        let crisp = ZebraParams::default().shade(&sp, Some(&footprint));
        assert!(
            (crisp - mean).abs().max_element() > 0.3,
            "16 stripes: {crisp}"
        );
    }

    /// The view-attached stripes have no pole inside the view: the phase is smooth in the
    /// normal wherever the surface faces the eye, and its gradient stays bounded (the world
    /// axis's pole, by contrast, has an unbounded one).
    #[test]
    fn view_axis_has_no_pole_facing_the_eye() {
        let view = DVec3::new(0.1, -0.2, -1.0).normalize();
        let params = ZebraParams::default();
        let world = ZebraParams {
            axis: ZebraAxis::World(DVec3::Y),
            ..params
        };
        let gradient = |z: &ZebraParams, n: DVec3| {
            let h = 1e-6;
            let (a, b) = n.any_orthonormal_pair();
            let d1 =
                z.phase((n + a * h).normalize(), view) - z.phase((n - a * h).normalize(), view);
            let d2 =
                z.phase((n + b * h).normalize(), view) - z.phase((n - b * h).normalize(), view);
            (d1 - d1.round()).hypot(d2 - d2.round()) / (2.0 * h)
        };
        let mut worst: f64 = 0.0;
        for i in 0..40 {
            for j in 0..40 {
                // Normals within 80° of −view.
                let (s, t) = (
                    f64::from(i) / 39.0 * 2.0 - 1.0,
                    f64::from(j) / 39.0 * 2.0 - 1.0,
                );
                let (a, b) = view.any_orthonormal_pair();
                let tilt = 80f64.to_radians() * s.hypot(t).min(1.0);
                let dir = (a * s + b * t).normalize_or(a);
                let n = -view * tilt.cos() + dir * tilt.sin();
                worst = worst.max(gradient(&params, n));
            }
        }
        // 16 stripes per 2π, the reflected angle changes twice as fast as the normal: about
        // 16·2/2π ≈ 5 periods per radian of normal, and never much more.
        assert!(worst < 12.0, "view-attached phase gradient {worst}");
        // The world axis's pole: the normal halfway between −view and the axis.
        let pole = (DVec3::Y - view).normalize();
        assert!(gradient(&world, (pole + DVec3::X * 1e-4).normalize()) > 100.0);
    }

    /// The analytic slopes of the turns equal their central differences (Richardson-
    /// extrapolated, steps 1e-3 and 5e-4) to 1e-9 of `max(1, |slope|)` (measured: 9.6e-11) on
    /// random normals, views and footprints for each axis kind, including normals at and near
    /// normal incidence (the series branch) and views far off the image plane.
    #[test]
    fn turns_slopes_equal_their_differences() {
        use crate::testing::Rng;
        let mut rng = Rng::new(33);
        let unit = |rng: &mut Rng| {
            DVec3::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            )
            .normalize()
        };
        let axes = [
            ZebraAxis::View,
            ZebraAxis::ViewHorizontal,
            ZebraAxis::World(DVec3::new(0.3, 0.9, -0.2).normalize()),
        ];
        let mut worst: f64 = 0.0;
        let mut series = 0;
        for (case, axis) in (0..3000).map(|i| (i, axes[i % 3])) {
            let params = ZebraParams {
                axis,
                view_up: DVec3::new(0.1, 1.0, 0.05).normalize(),
                ..ZebraParams::default()
            };
            let v = unit(&mut rng);
            // Normals facing the eye; every tenth case within 1e-4 rad of normal incidence
            // (every hundredth exactly there).
            let n = match case % 100 {
                0 => -v,
                c if c % 10 == 0 => (-v + unit(&mut rng) * 1e-4).normalize(),
                _ => {
                    let m = unit(&mut rng);
                    if m.dot(v) < 0.0 { m } else { -m }
                }
            };
            let dn = [0, 1].map(|_| unit(&mut rng) * rng.range(1e-3, 1e-1));
            let dv = [0, 1].map(|_| unit(&mut rng) * rng.range(1e-4, 1e-2));
            if 1.0 + (v - 2.0 * v.dot(n) * n).dot(v) < 1e-6 {
                series += 1;
            }
            let Some(slopes) = params.turns_and_slopes(n, v, Some((dn, dv))).1 else {
                panic!("no slopes at n {n}, v {v}");
            };
            for k in 0..2 {
                let at =
                    |s: f64| params.turns((n + dn[k] * s).normalize(), (v + dv[k] * s).normalize());
                let central = |h: f64| {
                    let d = at(h) - at(-h);
                    (d - d.round()) / (2.0 * h)
                };
                let reference = (4.0 * central(5e-4) - central(1e-3)) / 3.0;
                let error = (slopes[k] - reference).abs() / reference.abs().max(1.0);
                worst = worst.max(error);
                assert!(
                    error < 1e-9,
                    "{axis:?} n {n} v {v}: slope {} against {reference}",
                    slopes[k]
                );
            }
        }
        assert!(series >= 30, "{series} cases on the series branch");
        eprintln!("turns slopes: worst relative difference {worst:.2e}, {series} on the series");
    }
}
