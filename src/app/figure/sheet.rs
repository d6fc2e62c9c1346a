//! A labelled grid of equally sized images: column labels above, row labels at the left
//! (wrapped at spaces to fit), an optional title, dark gutters. Text uses the built-in
//! bitmap font, so sheets need no font files.

use image::{Rgb, RgbImage};

use crate::app::figure::font::{ADVANCE, draw_text, text_height, text_width};
use crate::render::film::Frame;
use crate::render::output::srgb8;

/// Background of the sheet (sRGB).
const BACKGROUND: [u8; 3] = [24, 24, 24];
/// Label colour (sRGB).
const INK: [u8; 3] = [235, 235, 235];
/// Gutter between cells and around the sheet, pixels.
const GUTTER: u32 = 4;

/// Labels of a grid.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SheetLabels {
    /// Title line above everything (empty: none).
    pub title: String,
    /// One label per row.
    pub rows: Vec<String>,
    /// One label per column.
    pub columns: Vec<String>,
}

/// Font scale for cells of height `cell_height`: 2 from 160 pixels up, else 1.
fn font_scale(cell_height: u32) -> u32 {
    if cell_height >= 160 { 2 } else { 1 }
}

/// `text` broken at spaces into lines of at most `max_chars` characters (a longer word gets a
/// line of its own).
pub fn wrap(text: &str, max_chars: usize) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split_whitespace() {
        match lines.last_mut() {
            Some(line) if line.chars().count() + 1 + word.chars().count() <= max_chars => {
                line.push(' ');
                line.push_str(word);
            }
            _ => lines.push(word.to_string()),
        }
    }
    lines
}

/// Composes `frames` (row-major, `labels.rows.len()` × `labels.columns.len()`, all
/// `cell_width` × `cell_height`) into one labelled sheet.
pub fn compose(frames: &[&Frame], labels: &SheetLabels, cell: [u32; 2]) -> RgbImage {
    let [cw, ch] = cell;
    let cols = labels.columns.len().max(1) as u32;
    let rows = frames.len().div_ceil(cols as usize).max(1) as u32;
    let scale = font_scale(ch);
    let line = text_height(scale) + 2 * scale;
    // Row labels get at most 60 % of a cell's width, wrapped to fit.
    let max_chars = ((cw * 3 / 5) / (ADVANCE * scale)).max(6) as usize;
    let wrapped: Vec<Vec<String>> = labels.rows.iter().map(|l| wrap(l, max_chars)).collect();
    let label_width = wrapped
        .iter()
        .flatten()
        .map(|l| text_width(l, scale))
        .max()
        .unwrap_or(0);
    let left = if label_width > 0 {
        label_width + 3 * GUTTER
    } else {
        GUTTER
    };
    let title_height = if labels.title.is_empty() {
        0
    } else {
        line + GUTTER
    };
    let top = title_height + line + GUTTER;
    let width = left + cols * (cw + GUTTER);
    let height = top + rows * (ch + GUTTER);
    let mut sheet = RgbImage::from_pixel(width, height, Rgb(BACKGROUND));
    if !labels.title.is_empty() {
        draw_text(
            &mut sheet,
            i64::from(GUTTER),
            i64::from(GUTTER),
            &labels.title,
            scale,
            INK,
        );
    }
    for (c, label) in labels.columns.iter().enumerate() {
        let x0 = left + c as u32 * (cw + GUTTER);
        let tw = text_width(label, scale);
        let x = i64::from(x0) + (i64::from(cw) - i64::from(tw)).max(0) / 2;
        draw_text(
            &mut sheet,
            x,
            i64::from(title_height + GUTTER),
            label,
            scale,
            INK,
        );
    }
    for (r, lines) in wrapped.iter().enumerate() {
        let y0 = top + r as u32 * (ch + GUTTER);
        let block = lines.len() as u32 * line;
        let mut y = i64::from(y0) + (i64::from(ch) - i64::from(block)).max(0) / 2;
        for l in lines {
            draw_text(&mut sheet, i64::from(GUTTER), y, l, scale, INK);
            y += i64::from(line);
        }
    }
    for (k, frame) in frames.iter().enumerate() {
        let (c, r) = (k as u32 % cols, k as u32 / cols);
        let (x0, y0) = (left + c * (cw + GUTTER), top + r * (ch + GUTTER));
        let bytes = srgb8(frame);
        for y in 0..frame.height.min(ch) {
            for x in 0..frame.width.min(cw) {
                let i = ((y * frame.width + x) * 3) as usize;
                sheet.put_pixel(x0 + x, y0 + y, Rgb([bytes[i], bytes[i + 1], bytes[i + 2]]));
            }
        }
    }
    sheet
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat_frame(w: u32, h: u32, value: f32) -> Frame {
        Frame {
            width: w,
            height: h,
            rgb: vec![[value; 3]; (w * h) as usize],
            geometry: vec![None; (w * h) as usize],
        }
    }

    #[test]
    fn words_wrap_at_spaces() {
        assert_eq!(wrap("hb g0=-3.7 g1=4.6", 10), vec!["hb g0=-3.7", "g1=4.6"]);
        assert_eq!(
            wrap("averyveryverylongword x", 5),
            vec!["averyveryverylongword", "x"]
        );
        assert!(wrap("   ", 5).is_empty());
    }

    #[test]
    fn sheet_holds_every_cell_and_its_labels() {
        let frames: Vec<Frame> = (0..6).map(|k| flat_frame(40, 30, k as f32 / 5.0)).collect();
        let refs: Vec<&Frame> = frames.iter().collect();
        let labels = SheetLabels {
            title: "Title".into(),
            rows: vec!["row one".into(), "row two".into()],
            columns: vec!["a".into(), "b".into(), "c".into()],
        };
        let sheet = compose(&refs, &labels, [40, 30]);
        let unlabelled = compose(
            &refs,
            &SheetLabels {
                columns: labels.columns.clone(),
                ..SheetLabels::default()
            },
            [40, 30],
        );
        assert!(
            sheet.width() > unlabelled.width(),
            "row labels take a margin"
        );
        assert!(
            sheet.height() > unlabelled.height(),
            "the title takes a line"
        );
        // The last cell is white and sits in the bottom-right corner.
        let (w, h) = (sheet.width(), sheet.height());
        assert_eq!(sheet.get_pixel(w - GUTTER - 1, h - GUTTER - 1).0, [255; 3]);
        // Label ink exists left of the first column.
        let ink = sheet
            .enumerate_pixels()
            .filter(|(x, _, p)| *x < GUTTER + 30 && p.0 == INK)
            .count();
        assert!(ink > 0);
    }
}
