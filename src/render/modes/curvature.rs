//! Curvature maps: Gaussian, mean, largest |κ|, κ1 or κ2 through a diverging or sequential
//! colour map (ColorBrewer RdBu, viridis) over a symmetric range, fixed (for comparable
//! figures) or chosen from a percentile of the values in view; the sign convention is
//! selectable and the legend names the quantity, its units, its sign convention and carries
//! numeric ticks.

use glam::DVec3;
use rayon::prelude::*;

use crate::error::{Error, Problem, Result};
use crate::geom::Curvature;
use crate::render::interaction::ShadingPoint;
use crate::render::intersect::IntersectCounters;
use crate::render::modes::keys::{self, Flag, Key, Keys, refused};
use crate::render::modes::{Footprint, ModeKind, Setup, palette};
use crate::render::stats::RenderStats;
use crate::render::theme::{Legend, LegendStyle, Theme};
use crate::render::trace::SurfaceTracer;
use crate::text::{draw_text_linear, line_height, text_width, wrap};

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
                return Err(Error::unknown_name("curvature quantity", name, Self::NAMES));
            }
        })
    }

    /// The quantity's name and symbol for legends.
    pub fn label(self) -> &'static str {
        match self {
            CurvatureQuantity::Gaussian => "Gaussian curvature K",
            CurvatureQuantity::Mean => "mean curvature H",
            CurvatureQuantity::MaxAbs => "max |κ|",
            CurvatureQuantity::K1 => "principal curvature κ1",
            CurvatureQuantity::K2 => "principal curvature κ2",
        }
    }

    /// The quantity's units, in the mesh's length unit.
    pub fn units(self) -> &'static str {
        match self {
            CurvatureQuantity::Gaussian => "1/length²",
            _ => "1/length",
        }
    }

    /// True if the quantity changes sign with the orientation of the normal.
    pub fn depends_on_sign(self) -> bool {
        matches!(
            self,
            CurvatureQuantity::Mean | CurvatureQuantity::K1 | CurvatureQuantity::K2
        )
    }

    /// The quantity's value under sign convention `sign` (κ1 ≥ κ2 in either).
    pub fn value_signed(self, c: &Curvature, sign: CurvatureSign) -> f64 {
        match sign {
            CurvatureSign::Normal => self.value(c),
            CurvatureSign::Convex => {
                let flipped = Curvature {
                    gaussian: c.gaussian,
                    mean: -c.mean,
                    k1: -c.k2,
                    k2: -c.k1,
                };
                self.value(&flipped)
            }
        }
    }

    /// The quantity's value with respect to the patch normal ([`CurvatureSign::Normal`]).
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

/// The sign convention of the signed curvatures (mean, κ1, κ2; Gaussian curvature does not
/// depend on it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CurvatureSign {
    /// Positive where the surface bends away from its normal: convex is positive when the
    /// normals point outwards (the mesh's faces wound counter-clockwise seen from outside).
    Convex,
    /// `κ = II/I` with respect to the patch normal `Su × Sv`, the convention of
    /// [`crate::geom::Curvature`] and of the EXR's `H` channel: convex is negative with
    /// outward normals.
    Normal,
}

impl CurvatureSign {
    /// Names accepted in scenes and on the command line.
    pub const NAMES: &'static [&'static str] = &["convex", "normal"];

    /// The convention called `name`.
    pub fn by_name(name: &str) -> crate::Result<CurvatureSign> {
        match name {
            "convex" => Ok(CurvatureSign::Convex),
            "normal" => Ok(CurvatureSign::Normal),
            _ => Err(Error::unknown_name(
                "curvature sign convention",
                name,
                Self::NAMES,
            )),
        }
    }

    /// The convention as stated on the legend.
    pub fn legend_note(self) -> &'static str {
        match self {
            CurvatureSign::Convex => "convex > 0 (outward normal)",
            CurvatureSign::Normal => "sign of II/I (patch normal)",
        }
    }
}

/// The colour map of the curvature mode.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CurvatureMap {
    /// ColorBrewer RdBu: blue through white to red over `[−r, r]` (zero is white).
    Diverging,
    /// Moreland's cool–warm: blue through grey to red over `[−r, r]` (zero is a grey of
    /// lightness 88; see [`palette::cool_warm`]). The paper theme's default for the signed
    /// quantities.
    CoolWarm,
    /// viridis (perceptually uniform): dark blue to yellow over `[−r, r]`, or `[0, r]` for
    /// max |κ|.
    Sequential,
}

impl CurvatureMap {
    /// Names accepted in scenes and on the command line.
    pub const NAMES: &'static [&'static str] = &["diverging", "coolwarm", "sequential"];

    /// The map called `name`.
    pub fn by_name(name: &str) -> crate::Result<CurvatureMap> {
        match name {
            "diverging" => Ok(CurvatureMap::Diverging),
            "coolwarm" => Ok(CurvatureMap::CoolWarm),
            "sequential" => Ok(CurvatureMap::Sequential),
            _ => Err(Error::unknown_name(
                "curvature colour map",
                name,
                Self::NAMES,
            )),
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
    /// Draw a colour bar with the quantity's name, units, sign convention and numeric ticks
    /// in a strip right of the image (the PNG's; never over the image).
    pub legend: bool,
    /// The half-range in use (set before rendering from `range`).
    pub half_range: f64,
    /// Colour map; None: diverging for signed quantities (cool–warm in the paper theme, see
    /// [`ModeKind::themed`]), sequential for max |κ|.
    pub map: Option<CurvatureMap>,
    /// Sign convention of the signed quantities.
    pub sign: CurvatureSign,
    /// Shade hits on the back of the surface with
    /// [`crate::render::modes::palette::back_face`]; set for open surfaces, whose back shows.
    pub tint_back_faces: bool,
}

impl Default for CurvatureParams {
    fn default() -> Self {
        CurvatureParams {
            quantity: CurvatureQuantity::Mean,
            range: CurvatureRange::Auto { percentile: 95.0 },
            legend: true,
            half_range: 1.0,
            map: None,
            sign: CurvatureSign::Convex,
            tint_back_faces: false,
        }
    }
}

impl CurvatureParams {
    /// The colour map in use.
    pub fn colour_map(&self) -> CurvatureMap {
        self.map
            .unwrap_or(if self.quantity == CurvatureQuantity::MaxAbs {
                CurvatureMap::Sequential
            } else {
                CurvatureMap::Diverging
            })
    }

    /// The values at the bottom and top of the colour range.
    pub fn value_range(&self) -> (f64, f64) {
        let r = self.half_range.max(crate::tolerance::DIVISION_GUARD);
        if self.quantity == CurvatureQuantity::MaxAbs {
            (0.0, r)
        } else {
            (-r, r)
        }
    }

    /// Linear RGB of `value` (clamped to the range; NaN is the middle of the map).
    pub fn colour_of(&self, value: f64) -> DVec3 {
        let (lo, hi) = self.value_range();
        let t = if value.is_finite() {
            ((value - lo) / (hi - lo)).clamp(0.0, 1.0)
        } else {
            0.5
        };
        match self.colour_map() {
            CurvatureMap::Diverging => palette::rdbu(t),
            CurvatureMap::CoolWarm => palette::cool_warm(t),
            CurvatureMap::Sequential => palette::viridis(t),
        }
    }

    /// Colour of the hit; singular points (no curvature) are black.
    pub fn shade(&self, sp: &ShadingPoint) -> DVec3 {
        let colour = match &sp.curvature {
            Some(c) => self.colour_of(self.quantity.value_signed(c, self.sign)),
            None => DVec3::ZERO,
        };
        if self.tint_back_faces && sp.is_back_face() {
            super::palette::back_face(colour)
        } else {
            colour
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

/// Round tick values for a colour bar over `[lo, hi]`: the multiples of the largest step
/// `{1, 2, 2.5, 5} × 10^m` that puts at least four ticks in the range (at most eight), each
/// computed as `k · step` so that zero is exactly 0. A range that is empty or not finite gets
/// its two ends.
pub fn round_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let range = hi - lo;
    if !(range > 0.0 && range.is_finite()) {
        return if lo == hi { vec![lo] } else { vec![hi, lo] };
    }
    let exponent = (range / 4.0).log10().floor() as i32;
    for e in [exponent + 1, exponent] {
        for mantissa in [5.0, 2.5, 2.0, 1.0] {
            let step = mantissa * 10f64.powi(e);
            let (first, last) = ((lo / step).ceil() as i64, (hi / step).floor() as i64);
            // k · step may round just outside the range at its ends: those ticks are left out.
            let ticks: Vec<f64> = (first..=last)
                .rev()
                .map(|k| k as f64 * step)
                .filter(|t| (lo..=hi).contains(t))
                .collect();
            if ticks.len() >= 4 {
                return ticks;
            }
        }
    }
    vec![hi, lo]
}

/// The label of a tick at `x` on a bar whose ticks are `step` apart: the digits the step
/// needs and no more (`+0.5`, `-1`, `+2.5`), in exponent form beyond 1e-3..1e4.
pub fn round_tick_label(x: f64, step: f64) -> String {
    if x == 0.0 {
        return "0".into();
    }
    let magnitude = step.abs().log10().floor() as i32;
    if !(-3..=4).contains(&magnitude) || !(-3..=4).contains(&(x.abs().log10().floor() as i32)) {
        return tick_label(x);
    }
    // 2.5 × 10^m needs one digit more than 10^m.
    let extra = usize::from((step / 10f64.powi(magnitude) - 2.5).abs() < 1e-9);
    let digits = (-magnitude).max(0) as usize + extra;
    format!("{x:+.digits$}")
}

/// A tick label: at most three significant digits, no trailing zeros.
pub fn tick_label(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return "0".into();
    }
    let magnitude = x.abs().log10().floor() as i32;
    if !(-3..=4).contains(&magnitude) {
        return format!("{x:.2e}");
    }
    let digits = (2 - magnitude).max(0) as usize;
    let text = format!("{x:+.digits$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

/// The legend of `params`: a strip `height` pixels tall in `style`, on its ground the
/// quantity's name and units, the colour bar (top = top of the range) framed in ink with its
/// round ticks ([`round_ticks`]) labelled right of it, and the sign convention below it, all
/// wrapped to at most nine font sizes' width; the strip is as wide as its widest line. A
/// strip under 120 pixels tall gets the bare bar with its tick marks; None when not even the
/// bar fits (under about 12 pixels).
pub fn legend_strip(params: &CurvatureParams, height: u32, style: &LegendStyle) -> Option<Legend> {
    let h = height as usize;
    let font = style.font;
    let pad = (0.6 * font).round().max(2.0) as usize;
    let bar_w = (1.1 * font).round().max(4.0) as usize;
    let with_text = h >= 120;
    let (lo, hi) = params.value_range();
    let values = round_ticks(lo, hi);
    let step = match values.as_slice() {
        [a, b, ..] => a - b,
        _ => hi - lo,
    };
    let ticks: Vec<(f64, String)> = values
        .iter()
        .map(|&v| (v, round_tick_label(v, step)))
        .collect();
    let max_line = 9.0 * font;
    let mut head = wrap(params.quantity.label(), font, max_line);
    head.push(params.quantity.units().to_string());
    let note = if params.quantity.depends_on_sign() {
        wrap(params.sign.legend_note(), font, max_line)
    } else {
        Vec::new()
    };
    let line = line_height(font);
    let (top, bottom) = if with_text {
        let top = pad as f32 + head.len() as f32 * line + 0.6 * font;
        let below = pad as f32 + note.len() as f32 * line + 0.6 * font;
        (top.ceil() as usize, h.saturating_sub(below.ceil() as usize))
    } else {
        (h / 10, h - h / 10)
    };
    let tick_gap = 0.4 * font + 3.0;
    let text_w = if with_text {
        let tick_w = ticks
            .iter()
            .map(|(_, t)| text_width(font, t))
            .fold(0.0, f32::max);
        head.iter()
            .chain(&note)
            .map(|l| text_width(font, l))
            .fold(bar_w as f32 + tick_gap + tick_w, f32::max)
    } else {
        bar_w as f32
    };
    if bottom <= top + 8 {
        return None;
    }
    let width = (text_w.ceil() as usize + 2 * pad) as u32;
    let mut legend = Legend::blank(width, height, style.background);
    let (w, rgb) = (width as usize, &mut legend.rgb);
    // Glyph coverage of the text, blended in at the end.
    let mut cover = vec![[0.0f32; 3]; rgb.len()];
    let x0 = pad;
    for y in top..bottom {
        let t = 1.0 - (y - top) as f64 / (bottom - 1 - top) as f64;
        let c = params.colour_of(lo + (hi - lo) * t);
        for x in x0..x0 + bar_w {
            let frame = y == top || y == bottom - 1 || x == x0 || x == x0 + bar_w - 1;
            rgb[y * w + x] = if frame {
                style.ink
            } else {
                [c.x as f32, c.y as f32, c.z as f32]
            };
        }
    }
    let right = x0 + bar_w;
    for (value, label) in &ticks {
        // The tick at its value's height on the bar (top = hi).
        let t = if hi > lo {
            (hi - value) / (hi - lo)
        } else {
            0.0
        };
        let y = top + ((bottom - 1 - top) as f64 * t.clamp(0.0, 1.0)).round() as usize;
        // A tick mark across the bar's right edge.
        for x in right - 2..(right + 3).min(w) {
            rgb[y * w + x] = style.ink;
        }
        if with_text {
            let (x, y) = (right as f32 + tick_gap, y as f32 - 0.55 * font);
            draw_text_linear(&mut cover, width, x, y, font, [1.0; 3], label);
        }
    }
    if with_text {
        for (k, text) in head.iter().enumerate() {
            let y = pad as f32 + k as f32 * line;
            draw_text_linear(&mut cover, width, pad as f32, y, font, [1.0; 3], text);
        }
        for (k, text) in note.iter().enumerate() {
            let y = bottom as f32 + 0.6 * font + k as f32 * line;
            draw_text_linear(&mut cover, width, pad as f32, y, font, [1.0; 3], text);
        }
    }
    // Text blends into its ground by coverage in sRGB-encoded values, as the sheets' labels
    // do ([`crate::text::draw_text`]): blended in linear light, dark text on white thins out.
    let encode = |c: [f32; 3]| c.map(|x| palette::linear_to_srgb(f64::from(x)));
    let ink = encode(style.ink);
    for (px, a) in rgb.iter_mut().zip(&cover) {
        let a = f64::from(a[0]);
        if a > 0.0 {
            let g = encode(*px);
            let mix = |k: usize| g[k] * (1.0 - a) + ink[k] * a;
            let linear = palette::srgb_to_linear(DVec3::new(mix(0), mix(1), mix(2)));
            *px = linear.as_vec3().to_array();
        }
    }
    Some(legend)
}

impl ModeKind for CurvatureParams {
    const NAME: &'static str = "curvature";
    const HELP: &'static str = "A curvature quantity through a colour map, with a legend.";
    const KEYS: &'static [Key] = &[
        Key::new(
            "quantity",
            "gaussian, mean, maxabs, k1 or k2 (default mean)",
        ),
        Key::new(
            "range",
            "\"auto\" or a fixed positive half-range (default auto)",
        ),
        Key::new(
            "percentile",
            "percentile of |value| in view for the automatic range, in [0, 100] (default 95)",
        ),
        Key::new(
            "legend",
            "draw the colour bar in a strip right of the image (default true)",
        ),
        Key::new(
            "map",
            "diverging, coolwarm or sequential (default diverging, coolwarm in the paper theme; sequential for maxabs)",
        ),
        Key::new("sign", "convex or normal (default convex)"),
    ];
    const FLAGS: &'static [Flag] = &[
        Flag {
            value_name: "CURVATURE_QUANTITY",
            ..Flag::choice(
                "curvature-quantity",
                "quantity",
                "Curvature quantity [default: mean].",
                &[
                    ("gaussian", "K = κ1 κ2"),
                    ("mean", "H = (κ1 + κ2) / 2"),
                    ("maxabs", "max(|κ1|, |κ2|)"),
                    ("k1", "The larger principal curvature"),
                    ("k2", "The smaller principal curvature"),
                ],
            )
        },
        Flag {
            value_name: "CURVATURE_MAP",
            ..Flag::choice(
                "curvature-map",
                "map",
                "Curvature colour map [default: diverging, coolwarm with --theme paper; sequential for maxabs].",
                &[
                    ("diverging", "ColorBrewer RdBu over [−r, r], zero white"),
                    (
                        "coolwarm",
                        "Moreland's cool–warm over [−r, r], zero grey (the paper theme's default)",
                    ),
                    ("sequential", "viridis over [−r, r] ([0, r] for maxabs)"),
                ],
            )
        },
        Flag {
            value_name: "CURVATURE_SIGN",
            ..Flag::choice(
                "curvature-sign",
                "sign",
                "Sign convention of mean, κ1 and κ2 [default: convex].",
                &[
                    (
                        "convex",
                        "Positive where convex seen from the side the normal points to (outward normals)",
                    ),
                    (
                        "normal",
                        "II/I with respect to the patch normal (convex is negative with outward normals)",
                    ),
                ],
            )
        },
        Flag::value(
            "curvature-range",
            "range",
            "auto|R",
            "Curvature half-range: `auto` (95th percentile of |value| in view) or a number [default: auto].",
            keys::number_or_text,
        ),
        Flag::off(
            "no-legend",
            "legend",
            "No curvature legend (scene: `curvature.legend = false`).",
        ),
    ];

    fn configure(&mut self, keys: &Keys<'_>) -> Result<()> {
        if let Some(q) = keys.text("quantity")? {
            self.quantity = CurvatureQuantity::by_name(q)?;
        }
        let percentile = match keys.number("percentile")? {
            Some(x) if (0.0..=100.0).contains(&x) => x,
            Some(x) => {
                return Err(keys.error(
                    "percentile",
                    Problem::Other {
                        text: format!("{x} is not in [0, 100]"),
                    },
                ));
            }
            None => 95.0,
        };
        self.range = match keys.value("range") {
            None => CurvatureRange::Auto { percentile },
            Some(toml::Value::String(s)) if s == "auto" => CurvatureRange::Auto { percentile },
            Some(toml::Value::Float(x)) => {
                CurvatureRange::Fixed(keys::positive("curvature.range", *x)?)
            }
            Some(toml::Value::Integer(x)) => {
                CurvatureRange::Fixed(keys::positive("curvature.range", *x as f64)?)
            }
            Some(other) => {
                return Err(keys.error(
                    "range",
                    Problem::Neither {
                        value: other.to_string(),
                        forms: "\"auto\" nor a number".into(),
                    },
                ));
            }
        };
        if let Some(l) = keys.flag("legend")? {
            self.legend = l;
        }
        if let Some(m) = keys.text("map")? {
            self.map = Some(CurvatureMap::by_name(m).map_err(|e| refused(keys, "map", &e))?);
        }
        if let Some(sign) = keys.text("sign")? {
            self.sign = CurvatureSign::by_name(sign).map_err(|e| refused(keys, "sign", &e))?;
        }
        Ok(())
    }

    fn shade(&self, sp: &ShadingPoint, _footprint: Option<&Footprint>) -> DVec3 {
        CurvatureParams::shade(self, sp)
    }

    /// The half-range in use: the fixed one, or the percentile of |value| in view (recorded
    /// in the statistics either way).
    fn set_up<T: SurfaceTracer>(&self, setup: &Setup<'_, T>, stats: &mut RenderStats) -> Self {
        let mut p = *self;
        p.half_range = match p.range {
            CurvatureRange::Fixed(r) => r,
            CurvatureRange::Auto { percentile } => auto_range(setup, p.quantity, percentile),
        };
        stats.curvature_half_range = Some(p.half_range);
        p
    }

    /// The legend strip of [`legend_strip`], unless `legend = false`.
    fn legend(&self, height: u32, style: &LegendStyle) -> Option<Legend> {
        self.legend
            .then(|| legend_strip(self, height, style))
            .flatten()
    }

    /// In the paper theme, the default map of the signed quantities is cool–warm (its grey
    /// zero stays visible on white; RdBu's zero is near white).
    fn themed(&self, theme: Theme) -> Self {
        let paper_default = theme == Theme::Paper
            && self.map.is_none()
            && self.colour_map() == CurvatureMap::Diverging;
        CurvatureParams {
            map: if paper_default {
                Some(CurvatureMap::CoolWarm)
            } else {
                self.map
            },
            ..*self
        }
    }

    fn with_back_faces_tinted(&self) -> Self {
        CurvatureParams {
            tint_back_faces: true,
            ..*self
        }
    }

    fn has_scale(&self) -> bool {
        true
    }

    fn scale_is_automatic(&self) -> bool {
        matches!(self.range, CurvatureRange::Auto { .. })
    }

    fn with_scale(&self, half_range: f64) -> Self {
        CurvatureParams {
            range: CurvatureRange::Fixed(half_range),
            ..*self
        }
    }

    fn chosen_from_view(&self) -> bool {
        self.scale_is_automatic()
    }

    fn pinned(&self, stats: &RenderStats) -> Self {
        match stats.curvature_half_range {
            Some(r) if self.scale_is_automatic() => self.with_scale(r),
            _ => *self,
        }
    }

    /// The automatic range at the mode's percentile (95 when its range is fixed).
    fn measure_scale<T: SurfaceTracer>(&self, setup: &Setup<'_, T>) -> Option<f64> {
        let percentile = match self.range {
            CurvatureRange::Auto { percentile } => percentile,
            CurvatureRange::Fixed(_) => 95.0,
        };
        Some(auto_range(setup, self.quantity, percentile))
    }
}

/// The automatic half-range of the curvature map: the `percentile` of |value| seen through a
/// coarse grid of pixel centres (1 where nothing curved is in view).
fn auto_range<T: SurfaceTracer>(
    setup: &Setup<'_, T>,
    quantity: CurvatureQuantity,
    percentile: f64,
) -> f64 {
    let mut values = curvature_probe(setup, quantity);
    let r = abs_percentile(&mut values, percentile);
    if r > 0.0 && r.is_finite() { r } else { 1.0 }
}

/// Curvature values seen through a coarse grid (≤ 96 × 96) of pixel centres.
fn curvature_probe<T: SurfaceTracer>(
    setup: &Setup<'_, T>,
    quantity: CurvatureQuantity,
) -> Vec<f64> {
    let (tracer, camera) = (setup.tracer, setup.camera);
    let (w, h) = (setup.width.min(96), setup.height.min(96));
    let aspect = f64::from(setup.width) / f64::from(setup.height);
    let rows: Vec<Vec<f64>> = (0..h)
        .into_par_iter()
        .map(|y| {
            let mut counters = IntersectCounters::default();
            let mut row = Vec::new();
            for x in 0..w {
                let nx = 2.0 * (f64::from(x) + 0.5) / f64::from(w) - 1.0;
                let ny = 1.0 - 2.0 * (f64::from(y) + 0.5) / f64::from(h);
                let ray = camera.ray(nx, ny, aspect);
                if let Some(hit) = tracer.closest_hit(&ray, 0.0, f64::INFINITY, &mut counters) {
                    let sp = tracer.shading_point(&hit, &ray);
                    if let Some(c) = sp.curvature {
                        let value = quantity.value(&c);
                        if value.is_finite() {
                            row.push(value);
                        }
                    }
                }
            }
            row
        })
        .collect();
    rows.into_iter().flatten().collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The `[curvature]` keys set the parameters they name; bad values name the key.
    #[test]
    fn keys_configure_the_curvature_mode() {
        let table: toml::Table = toml::from_str(
            "quantity = \"gaussian\"\nrange = 2.5\nlegend = false\nsign = \"normal\"",
        )
        .expect("toml");
        let mut p = CurvatureParams::default();
        ModeKind::configure(
            &mut p,
            &Keys::new("curvature", &table, CurvatureParams::KEYS).expect("keys"),
        )
        .expect("valid");
        assert_eq!(p.quantity, CurvatureQuantity::Gaussian);
        assert_eq!(p.range, CurvatureRange::Fixed(2.5));
        assert!(!p.legend);
        assert_eq!(p.sign, CurvatureSign::Normal);
        for (bad, key) in [
            ("range = -1", "curvature.range"),
            ("range = \"x\"", "curvature.range"),
            ("percentile = 120", "curvature.percentile"),
            ("map = \"hot\"", "curvature.map"),
        ] {
            let table: toml::Table = toml::from_str(bad).expect("toml");
            let keys = Keys::new("curvature", &table, CurvatureParams::KEYS).expect("keys");
            let err = ModeKind::configure(&mut CurvatureParams::default(), &keys)
                .expect_err(bad)
                .to_string();
            assert!(err.contains(key), "{bad}: {err}");
        }
    }

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
        // Convex-positive flips the signed quantities and keeps κ1 ≥ κ2.
        let convex = CurvatureSign::Convex;
        assert_eq!(CurvatureQuantity::Mean.value_signed(&c, convex), 0.5);
        assert_eq!(CurvatureQuantity::K1.value_signed(&c, convex), 2.0);
        assert_eq!(CurvatureQuantity::K2.value_signed(&c, convex), -1.0);
        assert_eq!(CurvatureQuantity::Gaussian.value_signed(&c, convex), -2.0);
    }

    #[test]
    fn ticks_are_round_and_inside_the_range() {
        assert_eq!(round_ticks(-2.66, 2.66), [2.0, 1.0, 0.0, -1.0, -2.0]);
        assert_eq!(round_ticks(0.0, 1.0), [1.0, 0.75, 0.5, 0.25, 0.0]);
        assert_eq!(round_ticks(-0.3, 0.3), [0.2, 0.1, 0.0, -0.1, -0.2]);
        assert_eq!(round_ticks(3.0, 3.0), [3.0]);
        for (lo, hi) in [(-7.3e-4, 7.3e-4), (0.0, 123.0), (-1e6, 5.0), (1e-12, 3e-12)] {
            let ticks = round_ticks(lo, hi);
            assert!((4..=8).contains(&ticks.len()), "{lo} {hi}: {ticks:?}");
            assert!(ticks.iter().all(|t| (lo..=hi).contains(t)), "{ticks:?}");
            let step = ticks[0] - ticks[1];
            let mantissa = step / 10f64.powf(step.log10().floor());
            let round = [1.0, 2.0, 2.5, 5.0]
                .iter()
                .any(|m| (mantissa - m).abs() < 1e-9);
            assert!(round, "{lo} {hi}: step {step}");
        }
        assert_eq!(round_tick_label(0.0, 1.0), "0");
        assert_eq!(round_tick_label(-2.0, 1.0), "-2");
        assert_eq!(round_tick_label(0.75, 0.25), "+0.75");
        assert_eq!(round_tick_label(0.5, 0.25), "+0.50");
        assert_eq!(round_tick_label(0.2, 0.1), "+0.2");
        assert_eq!(round_tick_label(40.0, 20.0), "+40");
    }

    #[test]
    fn tick_labels_are_short() {
        assert_eq!(tick_label(0.0), "0");
        assert_eq!(tick_label(1.25), "+1.25");
        assert_eq!(tick_label(-0.5), "-0.5");
        assert_eq!(tick_label(12.345), "+12.3");
        assert_eq!(tick_label(2.0e-5), "2.00e-5");
    }

    /// The strip is as tall as asked, on its ground, with the bar (red at the top, blue at
    /// the bottom), ink text beside it, and as wide as its text; a short strip is the bare bar.
    #[test]
    fn the_legend_strip_holds_bar_and_text_on_its_ground() {
        let ground = [0.5f32; 3];
        let style = LegendStyle {
            background: ground,
            ink: [0.01; 3],
            font: 12.0,
        };
        let params = CurvatureParams::default();
        let legend = legend_strip(&params, 300, &style).expect("a legend");
        let (w, h) = (legend.width as usize, legend.height as usize);
        assert_eq!(h, 300);
        assert_eq!(legend.rgb.len(), w * h);
        // The bar's inside: pad 7, width 13.
        let column: Vec<[f32; 3]> = (0..h).map(|y| legend.rgb[y * w + 10]).collect();
        let red = column.iter().position(|p| p[0] > 2.0 * p[2] + 0.05);
        let blue = column.iter().rposition(|p| p[2] > 2.0 * p[0] + 0.05);
        assert!(
            red.is_some() && blue.is_some() && red < blue,
            "{red:?} {blue:?}"
        );
        // Dark text right of the bar and above it, the rest is the ground.
        let ink = |x0: usize, x1: usize, y0: usize, y1: usize| {
            (y0..y1)
                .flat_map(|y| (x0..x1).map(move |x| (x, y)))
                .filter(|&(x, y)| legend.rgb[y * w + x][0] < 0.25)
                .count()
        };
        assert!(ink(25, w, 60, 240) > 30, "tick labels");
        assert!(ink(0, w, 0, 30) > 30, "title");
        assert_eq!(legend.rgb[h / 2 * w + w - 1], ground);
        // The title "mean curvature H" and the note wrap at 9 font sizes.
        assert!(w as f32 <= 9.0 * 12.0 + 2.0 * 7.0 + 1.0, "{w}");
        assert!(w as f32 >= text_width(12.0, "convex > 0"), "{w}");
        // Without a legend, none; a strip of 100 pixels is the bar and its pads; at 10
        // pixels the bar has no room.
        let off = CurvatureParams {
            legend: false,
            ..params
        };
        assert!(ModeKind::legend(&off, 300, &style).is_none());
        let bare = legend_strip(&params, 100, &style).expect("the bar");
        assert_eq!(bare.width, 13 + 2 * 7);
        assert!(
            legend_strip(&params, 10, &style).is_none(),
            "no room for a bar"
        );
    }

    /// The paper theme turns only the default diverging map into cool–warm.
    #[test]
    fn the_paper_theme_greys_the_zero_of_the_default_map() {
        let p = CurvatureParams::default();
        assert_eq!(p.themed(Theme::Dark), p);
        let paper = p.themed(Theme::Paper);
        assert_eq!(paper.colour_map(), CurvatureMap::CoolWarm);
        assert!(palette::lightness(paper.colour_of(0.0)) < 90.0);
        assert!(
            palette::lightness(p.colour_of(0.0)) > 94.0,
            "RdBu's zero is near white"
        );
        let chosen = CurvatureParams {
            map: Some(CurvatureMap::Diverging),
            ..p
        };
        assert_eq!(chosen.themed(Theme::Paper), chosen);
        let maxabs = CurvatureParams {
            quantity: CurvatureQuantity::MaxAbs,
            ..p
        };
        assert_eq!(
            maxabs.themed(Theme::Paper).colour_map(),
            CurvatureMap::Sequential
        );
    }

    #[test]
    fn maps_follow_the_range() {
        let p = CurvatureParams {
            half_range: 2.0,
            ..CurvatureParams::default()
        };
        assert!(p.colour_of(2.0).x > p.colour_of(2.0).z, "positive is red");
        assert!(
            p.colour_of(-2.0).z > p.colour_of(-2.0).x,
            "negative is blue"
        );
        let s = CurvatureParams {
            quantity: CurvatureQuantity::MaxAbs,
            ..p
        };
        assert_eq!(s.colour_map(), CurvatureMap::Sequential);
        assert_eq!(s.value_range(), (0.0, 2.0));
        // viridis runs from dark to light.
        let (dark, light) = (s.colour_of(0.0), s.colour_of(2.0));
        assert!(light.length() > 2.0 * dark.length());
    }
}
