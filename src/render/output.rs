//! Image files: PNG (8-bit, sRGB transfer) and EXR (linear f32) with the channels of the README's Contracts:
//! `R, G, B, Z, N.X, N.Y, N.Z, P.X, P.Y, P.Z, u, v, patch_id, face_id, K, H`.
//!
//! Geometry channels describe the ray through the pixel centre: `Z` is the distance from the
//! ray origin (rays have unit direction), `N` the unit patch normal (patch orientation), `P` the
//! hit point, `(u, v)` the patch parameters (barycentric `(1−u−v, u, v)` of patch `patch_id` in
//! the JSON export's indexing), `face_id` the mesh face, `K`/`H` Gaussian/mean curvature.
//! Ids are stored as f32 and are exact below 2^24.
//!
//! Pixels whose centre ray misses hold the background colour in R, G, B and these values, so
//! that no NaN is ever written: `Z = −1`, `N = P = 0`, `u = v = −1`, `patch_id = face_id = −1`,
//! `K = H = 0`.

use std::io::Cursor;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::files::{check_writable, create_folder, ends_with_separator, write_atomic};
use crate::render::film::Frame;
use crate::render::modes::palette::linear_to_srgb;

/// The EXR channel names, in the order of the README's Contracts (the file stores them sorted by name, as
/// the format requires).
pub const EXR_CHANNELS: [&str; 16] = [
    "R", "G", "B", "Z", "N.X", "N.Y", "N.Z", "P.X", "P.Y", "P.Z", "u", "v", "patch_id", "face_id",
    "K", "H",
];

/// 8-bit sRGB-encoded RGB bytes of the frame, rows top to bottom.
pub fn srgb8(frame: &Frame) -> Vec<u8> {
    frame
        .rgb
        .iter()
        .flat_map(|c| c.map(|x| (linear_to_srgb(f64::from(x)) * 255.0 + 0.5) as u8))
        .collect()
}

/// Writes the frame as an 8-bit sRGB PNG (atomically, see [`write_atomic`]).
pub fn write_png(frame: &Frame, path: &Path) -> Result<()> {
    let img = image::RgbImage::from_raw(frame.width, frame.height, srgb8(frame))
        .ok_or_else(|| Error::Invalid("frame buffer does not match its size".into()))?;
    write_rgb_png(&img, path)
}

/// Writes an 8-bit RGB image as a PNG (atomically, see [`write_atomic`]).
pub fn write_rgb_png(img: &image::RgbImage, path: &Path) -> Result<()> {
    let mut bytes = Cursor::new(Vec::new());
    img.write_to(&mut bytes, image::ImageFormat::Png)
        .map_err(|e| Error::Invalid(format!("{}: {e}", path.display())))?;
    write_atomic(path, bytes.get_ref())
}

/// The 16 channels as planes of f32, in [`EXR_CHANNELS`] order.
pub fn exr_planes(frame: &Frame) -> Vec<Vec<f32>> {
    let n = frame.rgb.len();
    let mut planes = vec![Vec::with_capacity(n); EXR_CHANNELS.len()];
    for (rgb, geometry) in frame.rgb.iter().zip(&frame.geometry) {
        let values: [f32; 16] = match geometry {
            Some(g) => [
                rgb[0],
                rgb[1],
                rgb[2],
                g.hit.t as f32,
                g.normal.x as f32,
                g.normal.y as f32,
                g.normal.z as f32,
                g.position.x as f32,
                g.position.y as f32,
                g.position.z as f32,
                g.hit.u as f32,
                g.hit.v as f32,
                g.hit.patch as f32,
                g.face as f32,
                finite_or_zero(g.gaussian),
                finite_or_zero(g.mean),
            ],
            None => [
                rgb[0], rgb[1], rgb[2], -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0, -1.0, -1.0, -1.0,
                0.0, 0.0,
            ],
        };
        for (plane, v) in planes.iter_mut().zip(values) {
            plane.push(if v.is_finite() { v } else { 0.0 });
        }
    }
    planes
}

fn finite_or_zero(x: f64) -> f32 {
    let f = x as f32;
    if f.is_finite() { f } else { 0.0 }
}

/// The EXR encoding: RLE in 64-pixel tiles, written in increasing-y order (the compressor
/// works in parallel, but the file is the same bytes for any thread count and run).
const EXR_ENCODING: exr::prelude::Encoding = exr::prelude::Encoding {
    line_order: exr::prelude::LineOrder::Increasing,
    ..exr::prelude::Encoding::FAST_LOSSLESS
};

/// Writes the frame as a linear f32 EXR with the channels of [`EXR_CHANNELS`] (atomically, see
/// [`write_atomic`]).
pub fn write_exr(frame: &Frame, path: &Path) -> Result<()> {
    use exr::prelude::{
        AnyChannel, AnyChannels, FlatSamples, Image, Layer, LayerAttributes, SmallVec,
        WritableImage,
    };
    let channels: SmallVec<[AnyChannel<FlatSamples>; 4]> = EXR_CHANNELS
        .iter()
        .zip(exr_planes(frame))
        .map(|(name, plane)| AnyChannel::new(*name, FlatSamples::F32(plane)))
        .collect();
    let layer = Layer::new(
        (frame.width as usize, frame.height as usize),
        LayerAttributes::named("smoothlab"),
        EXR_ENCODING,
        AnyChannels::sort(channels),
    );
    let mut bytes = Cursor::new(Vec::new());
    Image::from_layer(layer)
        .write()
        .to_buffered(&mut bytes)
        .map_err(|e| Error::Invalid(format!("{}: {e}", path.display())))?;
    write_atomic(path, bytes.get_ref())
}

/// The image extensions an output name may end with; any other suffix (`run.v2`) is part of
/// the name.
const IMAGE_EXTENSIONS: [&str; 2] = ["png", "exr"];

/// `stem` with `.ext` appended (unlike [`Path::with_extension`], which would replace a `.v2`).
pub fn with_suffix(stem: &Path, ext: &str) -> PathBuf {
    let mut name = stem.as_os_str().to_owned();
    name.push(".");
    name.push(ext);
    PathBuf::from(name)
}

/// The stem of output name `name`: `name` itself, or without its extension when that is
/// `.png` or `.exr` (any case), so that `-o out/run.png` and `-o out/run` both write
/// `out/run.png` and `out/run.exr`, and `-o out/run.v2` writes `out/run.v2.png`.
pub fn output_stem(name: &Path) -> PathBuf {
    match name.extension().and_then(|e| e.to_str()) {
        Some(ext) if IMAGE_EXTENSIONS.iter().any(|x| x.eq_ignore_ascii_case(ext)) => {
            name.with_extension("")
        }
        _ => name.to_path_buf(),
    }
}

/// The files written for output name `name` (see [`output_stem`]): `[STEM.png, STEM.exr]`.
pub fn output_files(name: &Path) -> [PathBuf; 2] {
    let stem = output_stem(name);
    IMAGE_EXTENSIONS.map(|ext| with_suffix(&stem, ext))
}

/// Prepares the outputs of name `name` before rendering: creates the folder of the stem if
/// missing and checks that every file of [`output_files`] can be written there (see
/// [`check_writable`]). A name that is a folder (`out/`, or an existing folder) or a device
/// (`/dev/null`) is an error naming it.
pub fn prepare_outputs(name: &Path) -> Result<[PathBuf; 2]> {
    let stem = output_stem(name);
    let meta = std::fs::metadata(&stem).ok();
    if ends_with_separator(name) || meta.as_ref().is_some_and(std::fs::Metadata::is_dir) {
        return Err(Error::Invalid(format!(
            "output name {}: is a folder; give a file name stem such as {}",
            name.display(),
            stem.join("render").display()
        )));
    }
    if meta.is_some_and(|m| !m.is_file()) {
        return Err(Error::Invalid(format!(
            "output name {}: is not a regular file; give a file name stem (NAME writes \
             NAME.png and NAME.exr)",
            name.display()
        )));
    }
    if let Some(folder) = stem.parent() {
        create_folder(folder)?;
    }
    let files = output_files(name);
    for file in &files {
        check_writable(file)?;
    }
    Ok(files)
}

/// Writes the frame to the files of [`prepare_outputs`]: PNG and EXR.
pub fn write_outputs(frame: &Frame, [png, exr]: &[PathBuf; 2]) -> Result<()> {
    write_png(frame, png)?;
    write_exr(frame, exr)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_image_extensions_are_replaced() {
        let names = |name: &str| output_files(Path::new(name)).map(|p| p.display().to_string());
        assert_eq!(names("o/run.v2"), ["o/run.v2.png", "o/run.v2.exr"]);
        assert_eq!(names("o/run.PNG"), ["o/run.png", "o/run.exr"]);
        assert_eq!(names("run.exr"), ["run.png", "run.exr"]);
        assert_eq!(
            names("bunny-pn-zebra"),
            ["bunny-pn-zebra.png", "bunny-pn-zebra.exr"]
        );
    }

    #[test]
    fn folders_and_devices_are_not_output_names() {
        for name in ["/dev/null", "/tmp", "/tmp/"] {
            let err = prepare_outputs(Path::new(name)).expect_err(name);
            assert!(err.to_string().contains(name), "{err}");
        }
    }
}
