//! Text in images: DejaVu Sans (embedded, `assets/fonts/`, Bitstream Vera licence beside it)
//! rasterised with `ab_glyph` into 8-bit or linear RGB buffers. Two calls only: measure a line
//! ([`text_width`]) and draw it ([`draw_text`]).

use std::sync::OnceLock;

use ab_glyph::{Font, FontRef, PxScale, ScaleFont};

/// The embedded font file.
const FONT_BYTES: &[u8] = include_bytes!("../assets/fonts/DejaVuSans.ttf");

/// The parsed font (parsed once; `None` only if the embedded file were broken).
fn font() -> Option<&'static FontRef<'static>> {
    static FONT: OnceLock<Option<FontRef<'static>>> = OnceLock::new();
    FONT.get_or_init(|| FontRef::try_from_slice(FONT_BYTES).ok())
        .as_ref()
}

/// Width in pixels of `text` set in one line at `px_size` pixels (the font's em height).
pub fn text_width(px_size: f32, text: &str) -> f32 {
    let Some(font) = font() else { return 0.0 };
    let scaled = font.as_scaled(PxScale::from(px_size));
    let mut width = 0.0;
    let mut previous = None;
    for c in text.chars() {
        let id = scaled.glyph_id(c);
        if let Some(p) = previous {
            width += scaled.kern(p, id);
        }
        width += scaled.h_advance(id);
        previous = Some(id);
    }
    width
}

/// Draws `text` in one line into `img` (`width × height` pixels of RGB, rows top to bottom),
/// its top-left corner at `(x, y)`, `px_size` pixels high, in colour `rgb`, blending each pixel
/// by the glyph's coverage. Glyphs outside the image are clipped.
pub fn draw_text(
    img: &mut [[f32; 3]],
    width: u32,
    x: f32,
    y: f32,
    px_size: f32,
    rgb: [f32; 3],
    text: &str,
) {
    let Some(font) = font() else { return };
    let (w, h) = (width as i64, (img.len() / width.max(1) as usize) as i64);
    let scaled = font.as_scaled(PxScale::from(px_size));
    let baseline = y + scaled.ascent();
    let mut pen = x;
    let mut previous = None;
    for c in text.chars() {
        let id = scaled.glyph_id(c);
        if let Some(p) = previous {
            pen += scaled.kern(p, id);
        }
        let glyph = id.with_scale_and_position(px_size, ab_glyph::point(pen, baseline));
        pen += scaled.h_advance(id);
        previous = Some(id);
        let Some(outlined) = font.outline_glyph(glyph) else {
            continue;
        };
        let bounds = outlined.px_bounds();
        outlined.draw(|gx, gy, coverage| {
            let px = bounds.min.x as i64 + i64::from(gx);
            let py = bounds.min.y as i64 + i64::from(gy);
            if px < 0 || py < 0 || px >= w || py >= h {
                return;
            }
            let a = coverage.clamp(0.0, 1.0);
            let dst = &mut img[(py * w + px) as usize];
            for (d, s) in dst.iter_mut().zip(rgb) {
                *d = *d * (1.0 - a) + s * a;
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_is_measured_and_drawn() {
        assert!(font().is_some(), "the embedded font parses");
        let narrow = text_width(12.0, "1");
        let wide = text_width(12.0, "11");
        assert!(
            narrow > 3.0 && (wide - 2.0 * narrow).abs() < 1e-3,
            "{narrow} {wide}"
        );
        assert!((text_width(24.0, "H") - 2.0 * text_width(12.0, "H")).abs() < 1e-3);
        let (w, h) = (40u32, 20u32);
        let mut img = vec![[0.0f32; 3]; (w * h) as usize];
        draw_text(&mut img, w, 2.0, 2.0, 14.0, [1.0, 1.0, 1.0], "H-1");
        let lit = img.iter().filter(|p| p[0] > 0.5).count();
        assert!(lit > 20, "{lit} pixels lit");
        // Clipped, never out of bounds.
        draw_text(&mut img, w, -30.0, 15.0, 30.0, [1.0, 0.0, 0.0], "WWWW");
    }
}
