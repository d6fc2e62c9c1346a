//! Text in images: one TrueType font (DejaVu Sans, embedded in the binary; licence in
//! `assets/fonts/LICENSE`) rasterised with anti-aliasing by `ab_glyph`. Two calls:
//! [`draw_text`] paints a line into an 8-bit RGB image, [`text_width`] measures it, so labels
//! can be centred or wrapped ([`wrap`]) before they are drawn. [`ascent`] and [`line_height`] place lines;
//! [`FONT_FAMILY`] names the font for vector output (SVG) that must match the raster.
//!
//! Sizes are em sizes in pixels, as CSS and SVG `font-size` mean them (the full height of a
//! line, ascent + descent, is about 1.16 em for this font), so an SVG `<text>` with the same
//! `font-size` and font matches the raster. Positions are in pixels and may be fractional (glyphs are placed with sub-pixel offsets);
//! the same call always paints the same pixels, whatever the thread count.

use std::sync::OnceLock;

use ab_glyph::{Font, FontRef, PxScale, ScaleFont, point};
use image::RgbImage;

/// The font file, embedded.
const FONT_BYTES: &[u8] = include_bytes!("../assets/fonts/DejaVuSans.ttf");

/// The family name of the embedded font, for SVG `font-family`.
pub const FONT_FAMILY: &str = "DejaVu Sans";

/// The parsed embedded font (parsed once).
fn font() -> &'static FontRef<'static> {
    static FONT: OnceLock<FontRef<'static>> = OnceLock::new();
    FONT.get_or_init(|| {
        // The bytes are a fixed, valid font compiled into the binary; the unit test
        // `the_embedded_font_parses` checks it.
        FontRef::try_from_slice(FONT_BYTES).expect("the embedded font parses")
    })
}

/// The `ab_glyph` scale (which measures ascent + descent) of em size `px_size`.
fn scale(px_size: f32) -> PxScale {
    let f = font();
    let em = f.units_per_em().unwrap_or(2048.0);
    PxScale::from(px_size * f.height_unscaled() / em)
}

/// Distance from the top of a line of em size `px_size` to its baseline, pixels.
pub fn ascent(px_size: f32) -> f32 {
    font().as_scaled(scale(px_size)).ascent()
}

/// Height of one line of em size `px_size` (ascent + descent + line gap), pixels.
pub fn line_height(px_size: f32) -> f32 {
    let f = font().as_scaled(scale(px_size));
    f.ascent() - f.descent() + f.line_gap()
}

/// Advance width of `text` at em size `px_size`, pixels, kerning included: the distance from the
/// first glyph's origin to the pen position after the last glyph.
pub fn text_width(px_size: f32, text: &str) -> f32 {
    let f = font().as_scaled(scale(px_size));
    let mut width = 0.0;
    let mut previous = None;
    for c in text.chars() {
        let id = f.glyph_id(c);
        if let Some(p) = previous {
            width += f.kern(p, id);
        }
        width += f.h_advance(id);
        previous = Some(id);
    }
    width
}

/// `text` broken at spaces into lines no wider than `max_width` pixels at `size` (a longer
/// word gets a line of its own).
pub fn wrap(text: &str, size: f32, max_width: f32) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split_whitespace() {
        match lines.last_mut() {
            Some(line) if text_width(size, &format!("{line} {word}")) <= max_width => {
                line.push(' ');
                line.push_str(word);
            }
            _ => lines.push(word.to_string()),
        }
    }
    lines
}

/// Paints `text` at em size `px_size` in colour `rgb` into `img`, the line's top-left corner at
/// `(x, y)` (the baseline is at `y + ascent(px_size)`), blending by glyph coverage. Pixels
/// outside the image are skipped; characters the font lacks show as its missing-glyph box.
pub fn draw_text(img: &mut RgbImage, x: f32, y: f32, px_size: f32, rgb: [u8; 3], text: &str) {
    let (w, h) = (img.width(), img.height());
    rasterise(x, y, px_size, text, |px, py, a| {
        if px < 0 || py < 0 || px >= i64::from(w) || py >= i64::from(h) {
            return;
        }
        let pixel = img.get_pixel_mut(px as u32, py as u32);
        for (channel, ink) in pixel.0.iter_mut().zip(rgb) {
            let blended = f32::from(*channel) * (1.0 - a) + f32::from(ink) * a;
            *channel = blended.round().clamp(0.0, 255.0) as u8;
        }
    });
}

/// [`draw_text`] into a row-major buffer of linear RGB pixels `width` wide (the renderer's
/// film), `rgb` linear too.
pub fn draw_text_linear(
    img: &mut [[f32; 3]],
    width: u32,
    x: f32,
    y: f32,
    px_size: f32,
    rgb: [f32; 3],
    text: &str,
) {
    let w = i64::from(width);
    let h = (img.len() / width.max(1) as usize) as i64;
    rasterise(x, y, px_size, text, |px, py, a| {
        if px < 0 || py < 0 || px >= w || py >= h {
            return;
        }
        for (channel, ink) in img[(py * w + px) as usize].iter_mut().zip(rgb) {
            *channel = *channel * (1.0 - a) + ink * a;
        }
    });
}

/// Calls `put(x, y, coverage)` for every pixel a glyph of `text` covers (coverage in [0, 1]),
/// the line set at em size `px_size` with its top-left corner at `(x, y)`.
fn rasterise(x: f32, y: f32, px_size: f32, text: &str, mut put: impl FnMut(i64, i64, f32)) {
    let px_scale = scale(px_size);
    let f = font().as_scaled(px_scale);
    let baseline = y + f.ascent();
    let mut caret = x;
    let mut previous = None;
    for c in text.chars() {
        let id = f.glyph_id(c);
        if let Some(p) = previous {
            caret += f.kern(p, id);
        }
        previous = Some(id);
        let glyph = id.with_scale_and_position(px_scale, point(caret, baseline));
        caret += f.h_advance(id);
        let Some(outline) = font().outline_glyph(glyph) else {
            continue; // a space
        };
        let bounds = outline.px_bounds();
        let (x0, y0) = (bounds.min.x as i64, bounds.min.y as i64);
        outline.draw(|gx, gy, coverage| {
            put(
                x0 + i64::from(gx),
                y0 + i64::from(gy),
                coverage.clamp(0.0, 1.0),
            );
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_wrap_at_spaces() {
        let wide = text_width(12.0, "hb g0=-3.7");
        assert_eq!(
            wrap("hb g0=-3.7 g1=4.6", 12.0, wide),
            vec!["hb g0=-3.7", "g1=4.6"]
        );
        assert_eq!(
            wrap("averyveryverylongword x", 12.0, 10.0),
            vec!["averyveryverylongword", "x"]
        );
        assert!(wrap("   ", 12.0, 50.0).is_empty());
    }
    use image::Rgb;

    /// The linear-buffer variant paints the same pixels with the same coverage as the 8-bit
    /// one (up to the 8-bit rounding), and clips at every border.
    #[test]
    fn linear_buffer_gets_the_same_ink() {
        let (w, h) = (120u32, 40u32);
        let mut img = RgbImage::from_pixel(w, h, Rgb([0, 0, 0]));
        draw_text(&mut img, -3.0, 5.0, 22.0, [255, 255, 255], "Hgy-1.5 fang");
        let mut linear = vec![[0.0f32; 3]; (w * h) as usize];
        draw_text_linear(&mut linear, w, -3.0, 5.0, 22.0, [1.0; 3], "Hgy-1.5 fang");
        let mut lit = 0;
        for (i, p) in img.pixels().enumerate() {
            let coverage = linear[i][0];
            assert!((f32::from(p.0[0]) / 255.0 - coverage).abs() <= 0.5 / 255.0 + 1e-6);
            lit += usize::from(coverage > 0.5);
        }
        assert!(lit > 100, "{lit} pixels lit");
        draw_text_linear(&mut linear, w, 100.0, 30.0, 40.0, [1.0, 0.0, 0.0], "WWWW");
    }

    /// Ink pixels (any channel changed) of `text` drawn on black, and their column span.
    fn ink(text: &str, size: f32) -> (usize, u32, u32) {
        let mut img = RgbImage::from_pixel(400, 60, Rgb([0, 0, 0]));
        draw_text(&mut img, 10.0, 10.0, size, [255, 255, 255], text);
        let lit: Vec<(u32, u32)> = img
            .enumerate_pixels()
            .filter(|(_, _, p)| p.0 != [0, 0, 0])
            .map(|(x, y, _)| (x, y))
            .collect();
        let min = lit.iter().map(|p| p.0).min().unwrap_or(0);
        let max = lit.iter().map(|p| p.0).max().unwrap_or(0);
        (lit.len(), min, max)
    }

    #[test]
    fn the_embedded_font_parses() {
        assert!(FontRef::try_from_slice(FONT_BYTES).is_ok());
        assert!(ascent(20.0) > 10.0 && ascent(20.0) < 20.0);
        assert!(line_height(20.0) >= 20.0);
        // An em of DejaVu Sans: its capital M is about 0.73 em tall (1493 of 2048 units).
        let mut img = RgbImage::from_pixel(100, 100, Rgb([0, 0, 0]));
        draw_text(&mut img, 10.0, 10.0, 40.0, [255, 255, 255], "M");
        let rows: Vec<u32> = img
            .enumerate_pixels()
            .filter(|(_, _, p)| p.0[0] > 127)
            .map(|(_, y, _)| y)
            .collect();
        let tall = rows.iter().max().unwrap_or(&0) - rows.iter().min().unwrap_or(&0) + 1;
        assert!(
            (tall as f32 - 0.729 * 40.0).abs() <= 1.0,
            "M is {tall} px tall"
        );
    }

    #[test]
    fn widths_grow_with_text_and_size() {
        assert_eq!(text_width(16.0, ""), 0.0);
        let a = text_width(16.0, "gk");
        let b = text_width(16.0, "fang-mann");
        assert!(a > 0.0 && b > a, "{a} {b}");
        assert!((text_width(32.0, "fang-mann") - 2.0 * b).abs() < 0.05 * b);
        // Lower-case "p" and upper-case "P" are different glyphs of different widths.
        assert_ne!(text_width(16.0, "piper"), text_width(16.0, "Piper"));
    }

    #[test]
    fn drawn_ink_spans_the_measured_width() {
        for text in ["isophote", "piper", "fang-mann", "gk", "±2.48"] {
            let (count, min, max) = ink(text, 20.0);
            let width = text_width(20.0, text);
            let span = (max - min + 1) as f32;
            assert!(count > 0, "{text}: no ink");
            // Ink starts near the origin and ends within the advance (side bearings aside).
            assert!((9..=13).contains(&min), "{text}: starts at {min}");
            assert!(
                span <= width + 2.0 && span >= 0.7 * width,
                "{text}: {span} vs {width}"
            );
        }
        // Descenders reach below the baseline: "gp" has ink lower than "oa".
        let lowest = |text: &str| {
            let mut img = RgbImage::from_pixel(100, 60, Rgb([0, 0, 0]));
            draw_text(&mut img, 0.0, 0.0, 20.0, [255, 255, 255], text);
            img.enumerate_pixels()
                .filter(|(_, _, p)| p.0 != [0, 0, 0])
                .map(|(_, y, _)| y)
                .max()
                .unwrap_or(0)
        };
        assert!(lowest("gp") > lowest("oa") + 2);
        assert!((lowest("oa") as f32 - ascent(20.0)).abs() <= 1.5);
    }

    #[test]
    fn text_off_the_image_is_clipped() {
        // Drawn partly outside a small image, the text paints what the same text paints in
        // that window of a large image.
        let mut small = RgbImage::from_pixel(30, 30, Rgb([0, 0, 0]));
        draw_text(&mut small, -10.25, -5.5, 40.0, [255, 0, 0], "Wgk");
        let mut large = RgbImage::from_pixel(120, 100, Rgb([0, 0, 0]));
        draw_text(&mut large, 29.75, 34.5, 40.0, [255, 0, 0], "Wgk");
        let window = image::imageops::crop_imm(&large, 40, 40, 30, 30).to_image();
        assert!(small.pixels().any(|p| p.0 != [0, 0, 0]), "some ink inside");
        // The glyph positions differ by 40 pixels, so their f32 fractions may differ in the
        // last bit: coverage may round one level apart, never more.
        let close = |a: &RgbImage, b: &RgbImage| {
            a.pixels()
                .zip(b.pixels())
                .all(|(p, q)| p.0.iter().zip(q.0).all(|(x, y)| x.abs_diff(y) <= 1))
        };
        assert!(close(&small, &window));
        let before = small.clone();
        draw_text(&mut small, 100.0, 100.0, 40.0, [255, 0, 0], "gk");
        assert_eq!(small, before, "text wholly outside paints nothing");
    }
}
