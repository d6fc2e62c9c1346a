//! Thumbnails that changed against a baseline report: each of the new report's thumbnails is
//! compared pixel by pixel with the baseline's thumbnail of the same mesh, scheme and mode
//! (the baseline's `thumbs/` beside its `metrics.json`). Where any pixel differs, the page
//! shows before, after and a difference image side by side with the count of changed pixels.
//!
//! The baseline's PNG is copied into the report folder ([`BEFORE`]) and the difference image
//! written beside it ([`DIFF`]), so the page stays one self-contained folder.

use std::path::Path;

use crate::error::{Error, Result};
use crate::files::{create_folder, write_atomic};

/// One thumbnail of a report: what it shows and its path relative to the report folder.
#[derive(Clone, Debug, PartialEq)]
pub struct Thumbnail {
    /// Benchmark mesh.
    pub mesh: String,
    /// Scheme (variant label).
    pub scheme: String,
    /// Thumbnail mode.
    pub mode: String,
    /// Path relative to the report folder (the same in the baseline's folder).
    pub name: String,
}

/// Folder (in the report folder) of the baseline's thumbnails that changed.
pub const BEFORE: &str = "thumbs-baseline";

/// Folder (in the report folder) of the difference images.
pub const DIFF: &str = "thumbs-diff";

/// One thumbnail that differs from the baseline's.
#[derive(Clone, Debug, PartialEq)]
pub struct ImageChange {
    /// Benchmark mesh.
    pub mesh: String,
    /// Scheme (variant label).
    pub scheme: String,
    /// Thumbnail mode.
    pub mode: String,
    /// The baseline's thumbnail, relative to the report folder.
    pub before: String,
    /// The new thumbnail, relative to the report folder.
    pub after: String,
    /// The difference image, relative to the report folder (`None` when the sizes differ).
    pub diff: Option<String>,
    /// Pixels that differ in any channel (all of them when the sizes differ).
    pub changed: usize,
    /// Pixels of the new thumbnail.
    pub pixels: usize,
    /// Largest difference of one 8-bit channel (255 when the sizes differ).
    pub max_delta: u8,
}

/// What the comparison of the thumbnails found.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ImageChanges {
    /// Thumbnails compared (present in both reports).
    pub compared: usize,
    /// Those that differ, in page order.
    pub changes: Vec<ImageChange>,
    /// New thumbnails the baseline has none of.
    pub missing: usize,
}

/// Compares the thumbnails `thumbnails` (in `out_dir`) with the baseline's of the same names
/// in `baseline_dir`, writing the copies and difference images of those that changed.
pub fn compare_thumbnails(
    baseline_dir: &Path,
    out_dir: &Path,
    thumbnails: &[Thumbnail],
) -> Result<ImageChanges> {
    let mut found = ImageChanges::default();
    for t in thumbnails {
        let name = t.name.clone();
        let old_path = baseline_dir.join(&name);
        if !old_path.is_file() {
            found.missing += 1;
            continue;
        }
        let old_bytes = std::fs::read(&old_path).map_err(|e| Error::io(&old_path, e))?;
        let new_path = out_dir.join(&name);
        let new_bytes = std::fs::read(&new_path).map_err(|e| Error::io(&new_path, e))?;
        found.compared += 1;
        if old_bytes == new_bytes {
            continue;
        }
        let (old, new) = (
            decode(&old_path, &old_bytes)?,
            decode(&new_path, &new_bytes)?,
        );
        let Some(change) = pixel_change(&old, &new) else {
            continue;
        };
        let file = Path::new(&name)
            .file_name()
            .map_or_else(|| name.clone(), |f| f.to_string_lossy().into_owned());
        let before = format!("{BEFORE}/{file}");
        create_folder(&out_dir.join(BEFORE))?;
        write_atomic(&out_dir.join(&before), &old_bytes)?;
        let diff = match change.image {
            Some(image) => {
                let diff = format!("{DIFF}/{file}");
                create_folder(&out_dir.join(DIFF))?;
                write_atomic(&out_dir.join(&diff), &png(&image)?)?;
                Some(diff)
            }
            None => None,
        };
        found.changes.push(ImageChange {
            mesh: t.mesh.clone(),
            scheme: t.scheme.clone(),
            mode: t.mode.clone(),
            before,
            after: name,
            diff,
            changed: change.changed,
            pixels: (new.width() * new.height()) as usize,
            max_delta: change.max_delta,
        });
    }
    Ok(found)
}

/// The difference of two images: changed pixels, largest channel difference, and an image
/// showing them (the new image dimmed to grey, changed pixels in magenta); no image when the
/// sizes differ. `None` when every pixel is equal.
struct PixelChange {
    changed: usize,
    max_delta: u8,
    image: Option<image::RgbImage>,
}

fn pixel_change(old: &image::RgbImage, new: &image::RgbImage) -> Option<PixelChange> {
    if old.dimensions() != new.dimensions() {
        return Some(PixelChange {
            changed: (new.width() * new.height()) as usize,
            max_delta: 255,
            image: None,
        });
    }
    let mut image = image::RgbImage::new(new.width(), new.height());
    let (mut changed, mut max_delta) = (0, 0u8);
    for ((a, b), out) in old.pixels().zip(new.pixels()).zip(image.pixels_mut()) {
        let delta = (0..3).map(|c| a[c].abs_diff(b[c])).max().unwrap_or(0);
        if delta > 0 {
            changed += 1;
            max_delta = max_delta.max(delta);
            *out = image::Rgb([255, 0, 255]);
        } else {
            let grey = ((u16::from(b[0]) + u16::from(b[1]) + u16::from(b[2])) / 6) as u8;
            *out = image::Rgb([grey, grey, grey]);
        }
    }
    (changed > 0).then_some(PixelChange {
        changed,
        max_delta,
        image: Some(image),
    })
}

fn decode(path: &Path, bytes: &[u8]) -> Result<image::RgbImage> {
    image::load_from_memory_with_format(bytes, image::ImageFormat::Png)
        .map(|i| i.to_rgb8())
        .map_err(|e| Error::Invalid(format!("{}: not a readable PNG: {e}", path.display())))
}

fn png(image: &image::RgbImage) -> Result<Vec<u8>> {
    let mut bytes = std::io::Cursor::new(Vec::new());
    image
        .write_to(&mut bytes, image::ImageFormat::Png)
        .map_err(|e| Error::Invalid(format!("difference image: {e}")))?;
    Ok(bytes.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(w: u32, h: u32, f: impl Fn(u32, u32) -> [u8; 3]) -> image::RgbImage {
        image::RgbImage::from_fn(w, h, |x, y| image::Rgb(f(x, y)))
    }

    #[test]
    fn changed_pixels_are_counted_and_marked() {
        let old = image(4, 3, |x, y| [x as u8 * 10, y as u8 * 10, 7]);
        assert!(pixel_change(&old, &old).is_none(), "equal images");
        let mut new = old.clone();
        new.put_pixel(1, 2, image::Rgb([10, 20, 9]));
        new.put_pixel(3, 0, image::Rgb([0, 0, 7]));
        let change = pixel_change(&old, &new).expect("a change");
        assert_eq!(change.changed, 2);
        assert_eq!(change.max_delta, 30, "pixel (3, 0) lost 30 in red");
        let marked = change.image.expect("difference image");
        let magenta: Vec<_> = marked
            .enumerate_pixels()
            .filter(|(_, _, p)| p.0 == [255, 0, 255])
            .map(|(x, y, _)| (x, y))
            .collect();
        assert_eq!(magenta, [(3, 0), (1, 2)]);
    }

    #[test]
    fn a_size_change_counts_every_pixel() {
        let change = pixel_change(&image(4, 3, |_, _| [0; 3]), &image(5, 3, |_, _| [0; 3]))
            .expect("a change");
        assert_eq!((change.changed, change.max_delta), (15, 255));
        assert!(change.image.is_none());
    }

    #[test]
    fn only_changed_thumbnails_are_copied_and_diffed() {
        let root =
            std::env::temp_dir().join(format!("smoothlab-image-changes-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        let (old_dir, new_dir) = (root.join("old"), root.join("new"));
        for dir in [&old_dir, &new_dir] {
            create_folder(&dir.join("thumbs")).expect("folder");
        }
        const THUMB_MODES: [&str; 2] = ["zebra", "curvature"];
        let name = |scheme: &str, mode: &str| format!("thumbs/m-{scheme}-{mode}.png");
        let thumbs: Vec<Thumbnail> = ["a", "b"]
            .iter()
            .flat_map(|scheme| {
                THUMB_MODES.map(|mode| Thumbnail {
                    mesh: "m".into(),
                    scheme: scheme.to_string(),
                    mode: mode.into(),
                    name: name(scheme, mode),
                })
            })
            .collect();
        let write = |dir: &Path, scheme: &str, mode: &str, img: &image::RgbImage| {
            write_atomic(&dir.join(name(scheme, mode)), &png(img).expect("png")).expect("write");
        };
        let plain = image(4, 4, |_, _| [50, 60, 70]);
        let mut dotted = plain.clone();
        dotted.put_pixel(2, 2, image::Rgb([50, 61, 70]));
        for mode in THUMB_MODES {
            write(&new_dir, "a", mode, &plain);
            write(&new_dir, "b", mode, &plain);
            write(&old_dir, "a", mode, &plain);
        }
        // The baseline's b: its first mode differs by one pixel, its second is missing.
        write(&old_dir, "b", THUMB_MODES[0], &dotted);
        let found = compare_thumbnails(&old_dir, &new_dir, &thumbs).expect("compare");
        assert_eq!((found.compared, found.missing), (3, 1));
        assert_eq!(found.changes.len(), 1);
        let c = &found.changes[0];
        assert_eq!(
            (
                c.scheme.as_str(),
                c.mode.as_str(),
                c.changed,
                c.pixels,
                c.max_delta
            ),
            ("b", THUMB_MODES[0], 1, 16, 1)
        );
        assert!(new_dir.join(&c.before).is_file() && new_dir.join(&c.after).is_file());
        assert!(new_dir.join(c.diff.as_ref().expect("diff")).is_file());
        let copied = std::fs::read(new_dir.join(&c.before)).expect("copy");
        assert_eq!(copied, png(&dotted).expect("png"), "the baseline's bytes");
        let _ = std::fs::remove_dir_all(&root);
    }
}
