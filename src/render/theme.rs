//! Themes and legends: the colours around a rendered image — the background of rays that miss,
//! the legend strip the PNG carries beside the image, the ground and labels of figure sheets.
//!
//! A legend never covers the image: a mode that has one
//! ([`crate::render::modes::ModeKind::legend`]) draws it into its own [`Legend`] strip as tall
//! as the image, on the image's background, and the PNG places it right of the image
//! ([`crate::render::output::srgb8`]); the EXR holds the image alone.

use glam::DVec3;

use crate::error::{Error, Problem, Result};

/// The colour scheme of images and figure sheets.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Theme {
    /// A dark background with light text: for screens.
    #[default]
    Dark,
    /// A white background with dark text: for printed papers. The curvature mode's default
    /// diverging map is then the cool–warm map, whose middle is grey, not white
    /// ([`crate::render::modes::CurvatureMap::CoolWarm`]).
    Paper,
}

impl Theme {
    /// The themes' names in scenes, figure specs and on the command line, each with what
    /// `render --help` says of it.
    pub const CHOICES: [(&'static str, &'static str); 2] = [
        ("dark", "Dark background, light legend text."),
        (
            "paper",
            "White background, dark legend text; the curvature map's zero is grey (cool–warm).",
        ),
    ];

    /// Names accepted in scenes, figure specs and on the command line.
    pub const NAMES: [&'static str; 2] = crate::error::names(Self::CHOICES);

    /// The theme called `name`; an unknown name is an error naming `key` (the scene or spec
    /// key, or the flag, it was given as).
    pub fn by_name(key: &str, name: &str) -> Result<Theme> {
        match name {
            "dark" => Ok(Theme::Dark),
            "paper" => Ok(Theme::Paper),
            _ => Err(Error::config(
                key,
                Problem::Refused {
                    reason: Error::unknown_name("theme", name, &Self::NAMES).to_string(),
                },
            )),
        }
    }

    /// The theme's name.
    pub fn name(self) -> &'static str {
        match self {
            Theme::Dark => "dark",
            Theme::Paper => "paper",
        }
    }

    /// Linear RGB of rays that miss (and of the legend strip): dark grey or white.
    pub fn background(self) -> DVec3 {
        match self {
            Theme::Dark => DVec3::splat(0.045),
            Theme::Paper => DVec3::ONE,
        }
    }

    /// Linear RGB of a legend's text and tick marks: light grey or near black.
    pub fn ink(self) -> [f32; 3] {
        match self {
            Theme::Dark => [0.9; 3],
            Theme::Paper => [0.01; 3],
        }
    }

    /// Ground of a figure sheet (sRGB).
    pub fn sheet_background(self) -> [u8; 3] {
        match self {
            Theme::Dark => [24; 3],
            Theme::Paper => [255; 3],
        }
    }

    /// Labels of a figure sheet (sRGB).
    pub fn sheet_ink(self) -> [u8; 3] {
        match self {
            Theme::Dark => [235; 3],
            Theme::Paper => [20; 3],
        }
    }
}

/// How a legend is drawn: its ground, its ink and its font size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LegendStyle {
    /// Linear RGB of the strip's ground (the image's background).
    pub background: [f32; 3],
    /// Linear RGB of text and tick marks.
    pub ink: [f32; 3],
    /// Font size (em), pixels.
    pub font: f32,
}

impl LegendStyle {
    /// The style of the legend of an image `height` pixels tall with background `background`
    /// in `theme`: the font 1/28 of the height, between 9 and 22 pixels.
    pub fn new(theme: Theme, background: DVec3, height: u32) -> LegendStyle {
        LegendStyle {
            background: background.as_vec3().to_array(),
            ink: theme.ink(),
            font: (height as f32 / 28.0).clamp(9.0, 22.0),
        }
    }
}

/// A legend strip: linear RGB, `width` × `height`, rows top to bottom, placed right of the
/// image it belongs to (the same height).
#[derive(Clone, Debug, PartialEq)]
pub struct Legend {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Linear RGB per pixel.
    pub rgb: Vec<[f32; 3]>,
}

impl Legend {
    /// A `width` × `height` strip of the colour `background`.
    pub fn blank(width: u32, height: u32, background: [f32; 3]) -> Legend {
        Legend {
            width,
            height,
            rgb: vec![background; width as usize * height as usize],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn themes_by_name_and_unknown_names_name_the_key() {
        for name in Theme::NAMES {
            assert_eq!(
                Theme::by_name("render.theme", name).expect(name).name(),
                name
            );
        }
        let err = Theme::by_name("render.theme", "sepia")
            .expect_err("sepia")
            .to_string();
        assert!(
            err.contains("render.theme") && err.contains("sepia") && err.contains("paper"),
            "{err}"
        );
        assert_eq!(Theme::default(), Theme::Dark);
    }

    /// Paper is white with dark ink, dark is dark with light ink: the ink stands out from the
    /// ground in both.
    #[test]
    fn ink_contrasts_with_the_ground() {
        for theme in [Theme::Dark, Theme::Paper] {
            let ground = theme.background().x as f32;
            assert!((theme.ink()[0] - ground).abs() > 0.8, "{theme:?}");
            let sheet = f32::from(theme.sheet_background()[0]);
            assert!((f32::from(theme.sheet_ink()[0]) - sheet).abs() > 200.0);
        }
        assert_eq!(Theme::Paper.background(), DVec3::ONE);
    }
}
