//! A labelled grid of equally sized images: column labels above, row labels at the left, an
//! optional title (all wrapped at spaces to fit), gutters in the theme's ground, and the cells'
//! legend strips beside the cells, never over them ([`SheetLegends`]: one per column when the
//! cells of a column share it, else one per cell). One [`SheetLayout`] places everything; it
//! is drawn twice: as a raster ([`compose`], text by [`crate::text`] in the
//! embedded DejaVu Sans) and as SVG ([`svg`]: the cells embedded as PNG, every label a
//! `<text>` element in the same font at the same place), so a paper can scale the labels.

use std::fmt::Write as _;
use std::io::Cursor;

use base64::Engine as _;
use image::{Rgb, RgbImage};

use crate::error::{Error, Result};
use crate::render::film::Frame;
use crate::render::output::srgb8;
use crate::render::theme::Theme;
use crate::report::page::escape;
use crate::text::{FONT_FAMILY, ascent, draw_text, line_height, text_width, wrap};

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

/// Where a label's `x` is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Anchor {
    /// At the start of the text.
    Start,
    /// At the middle of the text.
    Middle,
}

/// One line of text of a sheet.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct TextItem {
    /// The text.
    pub text: String,
    /// Anchor position, pixels from the left.
    pub x: f32,
    /// Baseline, pixels from the top.
    pub baseline: f32,
    /// Font size (em, as SVG `font-size`), pixels.
    pub size: f32,
    /// What `x` marks.
    pub anchor: Anchor,
}

impl TextItem {
    /// Left end of the text as drawn.
    pub(crate) fn left(&self) -> f32 {
        match self.anchor {
            Anchor::Start => self.x,
            Anchor::Middle => self.x - 0.5 * text_width(self.size, &self.text),
        }
    }

    /// Top of the line as drawn (the `y` of [`draw_text`]).
    pub(crate) fn top(&self) -> f32 {
        self.baseline - ascent(self.size)
    }
}

/// Everything placed on a sheet.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct SheetLayout {
    /// Sheet width, pixels.
    pub width: u32,
    /// Sheet height, pixels.
    pub height: u32,
    /// Top-left corner of each cell, in the order of the frames.
    pub cells: Vec<[u32; 2]>,
    /// Top-left corner of each legend strip drawn, with the cell whose strip it is.
    pub legends: Vec<(usize, [u32; 2])>,
    /// Cell size.
    pub cell: [u32; 2],
    /// Every line of text.
    pub texts: Vec<TextItem>,
}

/// Label font size (em, pixels) for cells of height `cell_height`: 8 % of it, between 10 and
/// 24 pixels.
pub(crate) fn label_size(cell_height: u32) -> f32 {
    (0.08 * cell_height as f32).clamp(10.0, 24.0).round()
}

/// The legend strips of a sheet's cells: each cell image wider than the cell carries its strip
/// right of the image (as the PNG of a render does). A column whose cells' strips are all the
/// same (the same mode and range: a figure's curvature column) shows it once, beside its
/// first cell that has one; any other column shows every cell's strip beside that cell.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct SheetLegends {
    /// Width each column reserves right of its cells for strips (0: none).
    pub widths: Vec<u32>,
    /// The cells whose strips are drawn, in sheet order.
    pub drawn: Vec<usize>,
}

impl SheetLegends {
    /// The strips of `images` (row-major, `columns` per row) of cells `cell_width` wide.
    pub(crate) fn of(images: &[&RgbImage], columns: usize, cell_width: u32) -> SheetLegends {
        let columns = columns.max(1);
        let mut widths = vec![0; columns];
        let mut drawn = Vec::new();
        for (c, width) in widths.iter_mut().enumerate() {
            let with: Vec<usize> = (c..images.len())
                .step_by(columns)
                .filter(|&k| images[k].width() > cell_width)
                .collect();
            let strips: Vec<RgbImage> = with
                .iter()
                .map(|&k| legend_strip(images[k], cell_width))
                .collect();
            *width = strips.iter().map(RgbImage::width).max().unwrap_or(0);
            if strips.windows(2).all(|w| w[0] == w[1]) {
                drawn.extend(with.first());
            } else {
                drawn.extend(with);
            }
        }
        drawn.sort_unstable();
        SheetLegends { widths, drawn }
    }
}

/// The legend strip of a cell image: the part right of the cell's `cell_width` pixels.
fn legend_strip(image: &RgbImage, cell_width: u32) -> RgbImage {
    let width = image.width().saturating_sub(cell_width);
    image::imageops::crop_imm(image, cell_width, 0, width, image.height()).to_image()
}

/// The image part of a cell image (its first `cell[0]` × `cell[1]` pixels).
fn cell_part(image: &RgbImage, cell: [u32; 2]) -> RgbImage {
    let (w, h) = (image.width().min(cell[0]), image.height().min(cell[1]));
    image::imageops::crop_imm(image, 0, 0, w, h).to_image()
}

/// Places `count` cells of size `cell` (row-major, `labels.columns.len()` per row), the
/// labels and the legend strips of `legends`.
pub(crate) fn layout(
    count: usize,
    labels: &SheetLabels,
    cell: [u32; 2],
    legends: &SheetLegends,
) -> SheetLayout {
    let [cw, ch] = cell;
    let cols = labels.columns.len().max(1) as u32;
    let legend_width = |c: u32| legends.widths.get(c as usize).copied().unwrap_or(0);
    // Left edge of column c, relative to the first.
    let column_x = |c: u32| (0..c).map(|c| cw + legend_width(c) + GUTTER).sum::<u32>();
    let rows = count.div_ceil(cols as usize).max(1) as u32;
    let size = label_size(ch);
    let title_size = (1.25 * size).round();
    let line = line_height(size).ceil() as u32;
    // Row labels get at most 60 % of a cell's width, wrapped to fit.
    let max_width = (0.6 * cw as f32).max(text_width(size, "mmmmmm"));
    let wrapped: Vec<Vec<String>> = labels
        .rows
        .iter()
        .map(|l| wrap(l, size, max_width))
        .collect();
    let label_width = wrapped
        .iter()
        .flatten()
        .map(|l| text_width(size, l).ceil() as u32)
        .max()
        .unwrap_or(0);
    let left = if label_width > 0 {
        label_width + 3 * GUTTER
    } else {
        GUTTER
    };
    let width = left + column_x(cols);
    // The title wraps to the sheet's width.
    let title_line = line_height(title_size).ceil() as u32;
    let title_lines = wrap(&labels.title, title_size, (width - 2 * GUTTER) as f32);
    let title_height = if title_lines.is_empty() {
        0
    } else {
        title_lines.len() as u32 * title_line + GUTTER
    };
    // Column labels wrap to the cell width; the header is as tall as the longest.
    let column_lines: Vec<Vec<String>> = labels
        .columns
        .iter()
        .map(|l| wrap(l, size, cw as f32))
        .collect();
    let header_lines = column_lines.iter().map(Vec::len).max().unwrap_or(1).max(1) as u32;
    let top = title_height + GUTTER + header_lines * line;
    let height = top + rows * (ch + GUTTER);
    let mut texts = Vec::new();
    for (k, l) in title_lines.iter().enumerate() {
        texts.push(TextItem {
            text: l.clone(),
            x: GUTTER as f32,
            baseline: (GUTTER + k as u32 * title_line) as f32 + ascent(title_size),
            size: title_size,
            anchor: Anchor::Start,
        });
    }
    for (c, lines) in column_lines.iter().enumerate() {
        let x0 = left + column_x(c as u32);
        // The last line sits right above the cells.
        let first = title_height + GUTTER + (header_lines - lines.len() as u32) * line;
        for (k, l) in lines.iter().enumerate() {
            texts.push(TextItem {
                text: l.clone(),
                x: x0 as f32 + 0.5 * cw as f32,
                baseline: (first + k as u32 * line) as f32 + ascent(size),
                size,
                anchor: Anchor::Middle,
            });
        }
    }
    for (r, lines) in wrapped.iter().enumerate() {
        let y0 = top + r as u32 * (ch + GUTTER);
        let block = lines.len() as u32 * line;
        let mut y = y0 + ch.saturating_sub(block) / 2;
        for l in lines {
            texts.push(TextItem {
                text: l.clone(),
                x: GUTTER as f32,
                baseline: y as f32 + ascent(size),
                size,
                anchor: Anchor::Start,
            });
            y += line;
        }
    }
    let cells: Vec<[u32; 2]> = (0..count as u32)
        .map(|k| {
            let (c, r) = (k % cols, k / cols);
            [left + column_x(c), top + r * (ch + GUTTER)]
        })
        .collect();
    let legends = legends
        .drawn
        .iter()
        .filter_map(|&k| cells.get(k).map(|[x, y]| (k, [x + cw, *y])))
        .collect();
    SheetLayout {
        width,
        height,
        cells,
        legends,
        cell,
        texts,
    }
}

/// The 8-bit sRGB image of a frame as its PNG holds it (the legend strip right of the image).
fn frame_image(frame: &Frame) -> RgbImage {
    RgbImage::from_raw(frame.png_width(), frame.height, srgb8(frame))
        .unwrap_or_else(|| RgbImage::new(frame.png_width(), frame.height))
}

/// Composes `frames` (row-major, `labels.rows.len()` × `labels.columns.len()`, all
/// `cell_width` × `cell_height`, each with its legend strip, if any) into one labelled sheet
/// in the colours of `theme`.
pub(crate) fn compose(
    frames: &[&Frame],
    labels: &SheetLabels,
    cell: [u32; 2],
    theme: Theme,
) -> RgbImage {
    let images: Vec<RgbImage> = frames.iter().map(|f| frame_image(f)).collect();
    let images: Vec<&RgbImage> = images.iter().collect();
    compose_images(&images, labels, cell, theme)
}

/// [`compose`] of the cells' 8-bit sRGB images (what a frame becomes in a PNG: the cell, then
/// its legend strip), so that a sheet can be composed from cell files: the same bytes as from
/// the frames.
pub(crate) fn compose_images(
    images: &[&RgbImage],
    labels: &SheetLabels,
    cell: [u32; 2],
    theme: Theme,
) -> RgbImage {
    let legends = SheetLegends::of(images, labels.columns.len(), cell[0]);
    let layout = layout(images.len(), labels, cell, &legends);
    let ground = Rgb(theme.sheet_background());
    let mut sheet = RgbImage::from_pixel(layout.width, layout.height, ground);
    for t in &layout.texts {
        let ink = theme.sheet_ink();
        draw_text(&mut sheet, t.left(), t.top(), t.size, ink, &t.text);
    }
    let paste = |sheet: &mut RgbImage, img: &RgbImage, [x0, y0]: [u32; 2]| {
        for (x, y, p) in img.enumerate_pixels() {
            sheet.put_pixel(x0 + x, y0 + y, *p);
        }
    };
    for (img, &at) in images.iter().zip(&layout.cells) {
        paste(&mut sheet, &cell_part(img, cell), at);
    }
    for &(k, at) in &layout.legends {
        let strip = legend_strip(images[k], cell[0]);
        paste(&mut sheet, &cell_part(&strip, [strip.width(), cell[1]]), at);
    }
    sheet
}

/// `#rrggbb` of an sRGB colour.
fn hex(rgb: [u8; 3]) -> String {
    format!("#{:02x}{:02x}{:02x}", rgb[0], rgb[1], rgb[2])
}

/// The sheet of [`compose`] as SVG: the same size and places, each cell an `<image>` holding
/// its PNG as a data URI, each label a `<text>` in [`FONT_FAMILY`] (positions in pixels, one
/// SVG user unit per pixel).
pub(crate) fn svg(
    frames: &[&Frame],
    labels: &SheetLabels,
    cell: [u32; 2],
    theme: Theme,
) -> Result<String> {
    let images: Vec<RgbImage> = frames.iter().map(|f| frame_image(f)).collect();
    let images: Vec<&RgbImage> = images.iter().collect();
    svg_images(&images, labels, cell, theme)
}

/// [`svg`] of the cells' 8-bit sRGB images: the same text as from the frames.
pub(crate) fn svg_images(
    images: &[&RgbImage],
    labels: &SheetLabels,
    cell: [u32; 2],
    theme: Theme,
) -> Result<String> {
    let legends = SheetLegends::of(images, labels.columns.len(), cell[0]);
    let layout = layout(images.len(), labels, cell, &legends);
    let (w, h) = (layout.width, layout.height);
    let mut out = String::new();
    let _ = writeln!(out, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}">"#
    );
    if !labels.title.is_empty() {
        let _ = writeln!(out, "<title>{}</title>", escape(&labels.title));
    }
    let _ = writeln!(
        out,
        r#"<rect x="0" y="0" width="{w}" height="{h}" fill="{}"/>"#,
        hex(theme.sheet_background())
    );
    let cells = images.iter().map(|img| cell_part(img, cell));
    let strips = layout.legends.iter().map(|&(k, _)| {
        let strip = legend_strip(images[k], cell[0]);
        cell_part(&strip, [strip.width(), cell[1]])
    });
    let places = layout
        .cells
        .iter()
        .chain(layout.legends.iter().map(|(_, at)| at));
    for (k, (img, [x, y])) in cells.chain(strips).zip(places).enumerate() {
        let mut png = Cursor::new(Vec::new());
        img.write_to(&mut png, image::ImageFormat::Png)
            .map_err(|e| {
                Error::Invalid(format!(
                    "figure image {k} (cells, then legends) to PNG: {e}"
                ))
            })?;
        let data = base64::engine::general_purpose::STANDARD.encode(png.get_ref());
        let _ = writeln!(
            out,
            r#"<image x="{x}" y="{y}" width="{}" height="{}" href="data:image/png;base64,{data}"/>"#,
            img.width(),
            img.height()
        );
    }
    let _ = writeln!(
        out,
        r#"<g font-family="{FONT_FAMILY}, sans-serif" fill="{}">"#,
        hex(theme.sheet_ink())
    );
    for t in &layout.texts {
        let anchor = match t.anchor {
            Anchor::Start => "start",
            Anchor::Middle => "middle",
        };
        let _ = writeln!(
            out,
            r#"<text x="{}" y="{}" font-size="{}" text-anchor="{anchor}">{}</text>"#,
            t.x,
            t.baseline,
            t.size,
            escape(&t.text)
        );
    }
    let _ = writeln!(out, "</g>\n</svg>");
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat_frame(w: u32, h: u32, value: f32) -> Frame {
        Frame::blank(w, h, [value; 3])
    }

    /// A cell image 20 × 10 of grey `value`, with a 6-pixel strip of red `strip` right of it
    /// (0: no strip).
    fn cell_image(value: u8, strip: u8) -> RgbImage {
        let width = if strip > 0 { 26 } else { 20 };
        RgbImage::from_fn(width, 10, |x, _| {
            if x < 20 {
                Rgb([value; 3])
            } else {
                Rgb([strip, 0, 0])
            }
        })
    }

    /// A column whose cells carry the same strip shows it once, beside its first cell; a
    /// column whose strips differ shows each beside its cell; every cell stays whole.
    #[test]
    fn legends_go_beside_the_cells_once_per_column_when_shared() {
        let cell = [20, 10];
        let images = [
            cell_image(10, 200),
            cell_image(20, 100),
            cell_image(30, 0),
            cell_image(40, 200),
            cell_image(50, 150),
            cell_image(60, 0),
        ];
        let refs: Vec<&RgbImage> = images.iter().collect();
        let legends = SheetLegends::of(&refs, 3, 20);
        assert_eq!(legends.widths, [6, 6, 0]);
        assert_eq!(legends.drawn, [0, 1, 4]);
        let labels = SheetLabels {
            columns: vec!["a".into(), "b".into(), "c".into()],
            ..SheetLabels::default()
        };
        let sheet = compose_images(&refs, &labels, cell, Theme::Paper);
        let placed = layout(6, &labels, cell, &legends);
        assert_eq!(
            (sheet.width(), sheet.height()),
            (placed.width, placed.height)
        );
        for (img, [x0, y0]) in images.iter().zip(&placed.cells) {
            for (x, y, p) in cell_part(img, cell).enumerate_pixels() {
                assert_eq!(sheet.get_pixel(x0 + x, y0 + y), p);
            }
        }
        let drawn: Vec<usize> = placed.legends.iter().map(|(k, _)| *k).collect();
        assert_eq!(drawn, [0, 1, 4]);
        for &(k, [x0, y0]) in &placed.legends {
            assert_eq!([x0, y0], [placed.cells[k][0] + 20, placed.cells[k][1]]);
            for (x, y, p) in legend_strip(&images[k], 20).enumerate_pixels() {
                assert_eq!(sheet.get_pixel(x0 + x, y0 + y), p);
            }
        }
        // The shared strip is not drawn again beside cell 3: the ground is.
        let [x3, y3] = placed.cells[3];
        assert_eq!(
            sheet.get_pixel(x3 + 20, y3).0,
            Theme::Paper.sheet_background()
        );
        // The SVG places the same cells and strips.
        let text = svg_images(&refs, &labels, cell, Theme::Paper).expect("svg");
        assert_eq!(text.matches("<image ").count(), 6 + 3);
        assert!(text.contains("fill=\"#ffffff\""));
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
        let sheet = compose(&refs, &labels, [40, 30], Theme::Dark);
        let unlabelled = compose(
            &refs,
            &SheetLabels {
                columns: labels.columns.clone(),
                ..SheetLabels::default()
            },
            [40, 30],
            Theme::Dark,
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
        let first = layout(6, &labels, [40, 30], &SheetLegends::default()).cells[0][0];
        let ink = sheet
            .enumerate_pixels()
            .filter(|(x, _, p)| *x < first && p.0 != Theme::Dark.sheet_background())
            .count();
        assert!(ink > 0);
    }

    #[test]
    fn the_raster_draws_each_label_where_the_layout_puts_it() {
        let frames: Vec<Frame> = (0..2).map(|_| flat_frame(60, 50, 0.0)).collect();
        let refs: Vec<&Frame> = frames.iter().collect();
        let labels = SheetLabels {
            title: String::new(),
            rows: vec!["gk".into()],
            columns: vec!["isophote".into(), "fang-mann".into()],
        };
        let sheet = compose(&refs, &labels, [60, 50], Theme::Dark);
        let placed = layout(2, &labels, [60, 50], &SheetLegends::default());
        for t in &placed.texts {
            // The ink of the label spans its measured width (side bearings aside).
            let (x0, x1) = (
                t.left().floor() as u32,
                (t.left() + text_width(t.size, &t.text)),
            );
            let (y0, y1) = (t.top().floor() as u32, t.top() + line_height(t.size));
            let columns: Vec<u32> = sheet
                .enumerate_pixels()
                .filter(|(x, y, p)| {
                    *x >= x0.saturating_sub(1)
                        && (*x as f32) <= x1 + 1.0
                        && *y >= y0
                        && (*y as f32) <= y1
                        && p.0 != Theme::Dark.sheet_background()
                })
                .map(|(x, _, _)| x)
                .collect();
            let span = columns.iter().max().unwrap_or(&0) - columns.iter().min().unwrap_or(&0);
            let width = text_width(t.size, &t.text);
            assert!(
                span as f32 >= 0.7 * width && span as f32 <= width + 1.0,
                "{}: ink {span} vs width {width}",
                t.text
            );
        }
    }

    #[test]
    fn a_long_title_wraps_to_the_sheet_width() {
        let labels = SheetLabels {
            title: "HB00 Fig. 2: loop94 on the deformed icosahedron, two choices of alpha".into(),
            rows: vec!["row".into()],
            columns: vec!["a".into(), "b".into()],
        };
        let placed = layout(2, &labels, [60, 60], &SheetLegends::default());
        let size = placed.texts[0].size;
        let title: Vec<&TextItem> = placed.texts.iter().filter(|t| t.size == size).collect();
        assert!(title.len() > 1, "one line");
        for t in &title {
            assert!(
                t.left() + text_width(t.size, &t.text) <= placed.width as f32,
                "{}",
                t.text
            );
        }
        let joined: Vec<&str> = title.iter().map(|t| t.text.as_str()).collect();
        assert_eq!(joined.join(" "), labels.title);
        // The cells start below the last title line.
        let last = title.last().map_or(0.0, |t| t.top() + line_height(t.size));
        assert!(placed.cells[0][1] as f32 >= last);
    }

    #[test]
    fn the_svg_places_the_same_labels() {
        let frames: Vec<Frame> = (0..2).map(|_| flat_frame(20, 20, 0.5)).collect();
        let refs: Vec<&Frame> = frames.iter().collect();
        let labels = SheetLabels {
            title: "a < b & c".into(),
            rows: vec!["piper".into()],
            columns: vec!["isophote".into(), "gk".into()],
        };
        let text = svg(&refs, &labels, [20, 20], Theme::Dark).expect("svg");
        assert!(text.contains(">isophote</text>") && text.contains(">piper</text>"));
        assert!(text.contains("a &lt; b &amp; c"));
        assert_eq!(text.matches("<image ").count(), 2);
        assert!(text.contains("data:image/png;base64,"));
    }
}
