//! Image files: PNG (8-bit, sRGB transfer) and EXR (linear f32) with the channels of DESIGN.md:
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

use std::path::Path;

use crate::error::{Error, Result};
use crate::render::film::Frame;
use crate::render::modes::palette::linear_to_srgb;

/// The EXR channel names, in the order of DESIGN.md (the file stores them sorted by name, as
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

/// Writes the frame as an 8-bit sRGB PNG.
pub fn write_png(frame: &Frame, path: &Path) -> Result<()> {
    let img = image::RgbImage::from_raw(frame.width, frame.height, srgb8(frame))
        .ok_or_else(|| Error::Invalid("frame buffer does not match its size".into()))?;
    img.save_with_format(path, image::ImageFormat::Png)
        .map_err(|e| match e {
            image::ImageError::IoError(io) => Error::io(path, io),
            other => Error::Invalid(format!("{}: {other}", path.display())),
        })
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

/// Writes the frame as a linear f32 EXR with the channels of [`EXR_CHANNELS`].
pub fn write_exr(frame: &Frame, path: &Path) -> Result<()> {
    use exr::prelude::{
        AnyChannel, AnyChannels, Encoding, FlatSamples, Image, Layer, LayerAttributes, SmallVec,
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
        Encoding::FAST_LOSSLESS,
        AnyChannels::sort(channels),
    );
    Image::from_layer(layer)
        .write()
        .to_file(path)
        .map_err(|e| match e {
            exr::error::Error::Io(io) => Error::io(path, io),
            other => Error::Invalid(format!("{}: {other}", path.display())),
        })
}

/// Writes `NAME.png` and `NAME.exr` for output stem `stem` (creating its directory).
pub fn write_outputs(frame: &Frame, stem: &Path) -> Result<()> {
    if let Some(dir) = stem.parent()
        && !dir.as_os_str().is_empty()
    {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    }
    write_png(frame, &stem.with_extension("png"))?;
    write_exr(frame, &stem.with_extension("exr"))
}
