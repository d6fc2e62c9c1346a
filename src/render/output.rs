//! Image files: PNG (8-bit, sRGB transfer, with an `sRGB` chunk and `tEXt` metadata) and EXR
//! (linear f32) with the channels of docs/guide/contracts.md:
//! `R, G, B, Z, N.X, N.Y, N.Z, P.X, P.Y, P.Z, u, v, patch_id, face_id, K, H`, plus the ids as
//! u32 in `id.patch` and `id.face` (miss: `u32::MAX`), and header attributes for the camera
//! and the command line (see [`OutputMeta`]).
//!
//! Geometry channels describe the ray through the pixel centre: `Z` is the distance from the
//! ray origin (rays have unit direction), `N` the unit patch normal (patch orientation), `P` the
//! hit point, `(u, v)` the patch parameters (barycentric `(1−u−v, u, v)` of patch `patch_id` in
//! the JSON export's indexing), `face_id` the mesh face as the input numbers it (the polygon a triangle was cut from), `K`/`H` Gaussian/mean curvature.
//! Ids are stored as f32 (exact below 2^24) and as u32.
//!
//! Pixels whose centre ray misses hold the background colour in R, G, B and these values, so
//! that no NaN is ever written: `Z = −1`, `N = P = 0`, `u = v = −1`, `patch_id = face_id = −1`,
//! `K = H = 0`.

use std::io::Cursor;
use std::path::{Path, PathBuf};

use crate::error::{Error, Problem, Result};
use crate::files::{check_writable, create_folder, ends_with_separator, utf8_path, write_atomic};
use crate::render::camera::{Camera, Projection};
use crate::render::film::Frame;
use crate::render::modes::palette::linear_to_srgb;

/// The integer id channels of the EXR (u32; `u32::MAX` where the centre ray misses).
pub const EXR_ID_CHANNELS: [&str; 2] = ["id.patch", "id.face"];

/// How the EXR is compressed (all lossless).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ExrCompression {
    /// Uncompressed.
    None,
    /// Run-length (fast, the default).
    #[default]
    Rle,
    /// zlib per scan line.
    Zips,
    /// zlib per 16 scan lines.
    Zip,
    /// Wavelet + Huffman.
    Piz,
}

impl ExrCompression {
    /// The compressions' names in scenes and on the command line, each with what
    /// `render --help` says of it.
    pub const CHOICES: [(&'static str, &'static str); 5] = [
        ("none", "Uncompressed."),
        ("rle", "Run-length (fast)."),
        ("zips", "zlib per scan line."),
        ("zip", "zlib per 16 scan lines."),
        ("piz", "Wavelet + Huffman."),
    ];

    /// Names accepted in scenes and on the command line.
    pub const NAMES: [&'static str; 5] = crate::error::names(Self::CHOICES);

    /// The compression called `name`.
    pub fn by_name(name: &str) -> Result<ExrCompression> {
        Ok(match name {
            "none" => ExrCompression::None,
            "rle" => ExrCompression::Rle,
            "zips" => ExrCompression::Zips,
            "zip" => ExrCompression::Zip,
            "piz" => ExrCompression::Piz,
            _ => {
                return Err(Error::unknown_name("EXR compression", name, &Self::NAMES));
            }
        })
    }

    fn exr(self) -> exr::prelude::Compression {
        use exr::prelude::Compression;
        match self {
            ExrCompression::None => Compression::Uncompressed,
            ExrCompression::Rle => Compression::RLE,
            ExrCompression::Zips => Compression::ZIP1,
            ExrCompression::Zip => Compression::ZIP16,
            ExrCompression::Piz => Compression::PIZ,
        }
    }
}

/// What the image files record about how they were made.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OutputMeta {
    /// The command line (PNG `tEXt` `Comment`, EXR `comments`).
    pub command: Option<String>,
    /// The camera (PNG `tEXt` `Camera`, EXR text attribute `smoothlab.camera`, both
    /// `eye X,Y,Z target X,Y,Z up X,Y,Z fov_deg F` or `… ortho_height H`).
    pub camera: Option<Camera>,
}

impl OutputMeta {
    /// One line describing the camera: `eye X,Y,Z target X,Y,Z up X,Y,Z fov_deg F` (or
    /// `ortho_height H`).
    pub fn camera_text(&self) -> Option<String> {
        let c = self.camera?;
        let v = |p: glam::DVec3| format!("{},{},{}", p.x, p.y, p.z);
        let projection = match c.projection {
            Projection::Perspective { fov_deg } => format!("fov_deg {fov_deg}"),
            Projection::Orthographic { height } => format!("ortho_height {height}"),
        };
        Some(format!(
            "eye {} target {} up {} {projection}",
            v(c.eye),
            v(c.target),
            v(c.up())
        ))
    }
}

/// What [`write_outputs`] writes besides the PNG.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputOptions {
    /// The EXR's compression; None: no EXR.
    pub exr: Option<ExrCompression>,
    /// Metadata of both files.
    pub meta: OutputMeta,
}

impl Default for OutputOptions {
    fn default() -> Self {
        OutputOptions {
            exr: Some(ExrCompression::default()),
            meta: OutputMeta::default(),
        }
    }
}

/// The EXR channel names, in the order of docs/guide/contracts.md (the file stores them sorted by name, as
/// the format requires).
pub const EXR_CHANNELS: [&str; 16] = [
    "R", "G", "B", "Z", "N.X", "N.Y", "N.Z", "P.X", "P.Y", "P.Z", "u", "v", "patch_id", "face_id",
    "K", "H",
];

/// Peak bytes per pixel that writing the outputs of a frame adds to the frame itself: the
/// sRGB bytes and the PNG encoder's buffer, and with `exr` the EXR's 18 four-byte planes and
/// its encoder's chunks. Measured on 2048 × 2048 renders (peak resident memory less the
/// frame's [`Frame::bytes`]): 6 B without the EXR, 115 B with it; these are rounded up.
pub fn output_bytes_per_pixel(exr: bool) -> f64 {
    const PNG: f64 = 8.0;
    const EXR: f64 = 120.0;
    if exr { PNG + EXR } else { PNG }
}

/// 8-bit sRGB-encoded RGB bytes of the PNG of the frame, [`Frame::png_width`] ×
/// `frame.height`, rows top to bottom: each row of the image followed by that row of the
/// legend strip, if any (the legend lies beside the image, never over it).
///
/// Runs of equal values (the background, the inside of a stripe) are encoded once: the last
/// value and its byte are remembered, so the transfer function (a `powf`) runs only where the
/// value changes. The bytes are those of encoding every value.
pub fn srgb8(frame: &Frame) -> Vec<u8> {
    let w = frame.width.max(1) as usize;
    match &frame.legend {
        Some(legend) => {
            let strip = legend.rgb.chunks(legend.width.max(1) as usize);
            let rows = frame.rgb.chunks(w).zip(strip);
            encode_srgb8(rows.flat_map(|(a, b)| a.iter().chain(b)), frame.rgb.len())
        }
        None => image_srgb8(frame),
    }
}

/// 8-bit sRGB-encoded RGB bytes of the image alone, `frame.width` × `frame.height`, encoded
/// as [`srgb8`] encodes them.
fn image_srgb8(frame: &Frame) -> Vec<u8> {
    encode_srgb8(frame.rgb.iter(), frame.rgb.len())
}

/// The sRGB bytes of `pixels` (about `count` of them), each run of equal values encoded once.
fn encode_srgb8<'a>(pixels: impl Iterator<Item = &'a [f32; 3]>, count: usize) -> Vec<u8> {
    let encode = |x: f32| (linear_to_srgb(f64::from(x)) * 255.0 + 0.5) as u8;
    let mut last: Option<(u32, u8)> = None;
    let mut bytes = Vec::with_capacity(3 * count);
    for &x in pixels.flatten() {
        let byte = match last {
            Some((bits, byte)) if bits == x.to_bits() => byte,
            _ => {
                let byte = encode(x);
                last = Some((x.to_bits(), byte));
                byte
            }
        };
        bytes.push(byte);
    }
    bytes
}

/// Writes the frame as an 8-bit sRGB PNG (atomically, see [`write_atomic`]).
pub fn write_png(frame: &Frame, path: &Path) -> Result<()> {
    write_png_with(frame, path, &OutputMeta::default())
}

/// Writes the frame as an 8-bit sRGB PNG with `meta` in `tEXt` chunks.
pub fn write_png_with(frame: &Frame, path: &Path, meta: &OutputMeta) -> Result<()> {
    let img = image::RgbImage::from_raw(frame.png_width(), frame.height, srgb8(frame))
        .ok_or_else(|| Error::Invalid("frame buffer does not match its size".into()))?;
    let mut text = Vec::new();
    if let Some(command) = &meta.command {
        text.push(("Comment", command.clone()));
    }
    if let Some(camera) = meta.camera_text() {
        text.push(("Camera", camera));
    }
    write_png_bytes(&img, path, &text)
}

/// Writes an 8-bit RGB image as a PNG (atomically, see [`write_atomic`]).
pub fn write_rgb_png(img: &image::RgbImage, path: &Path) -> Result<()> {
    write_png_bytes(img, path, &[])
}

/// The PNG of `img`: an `sRGB` chunk (perceptual intent; the pixels are sRGB-encoded), a
/// `Software` text and the `(keyword, text)` pairs, as `tEXt` when Latin-1, else `iTXt`.
fn write_png_bytes(img: &image::RgbImage, path: &Path, text: &[(&str, String)]) -> Result<()> {
    let err = |e: png::EncodingError| Error::Invalid(format!("{}: {e}", path.display()));
    let mut bytes = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut bytes, img.width(), img.height());
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        let software = format!("smoothlab {}", env!("CARGO_PKG_VERSION"));
        encoder
            .add_text_chunk("Software".into(), software)
            .map_err(err)?;
        for (keyword, value) in text {
            if value.chars().all(|c| u32::from(c) < 256) {
                encoder.add_text_chunk((*keyword).into(), value.clone())
            } else {
                encoder.add_itxt_chunk((*keyword).into(), value.clone())
            }
            .map_err(err)?;
        }
        let mut writer = encoder.write_header().map_err(err)?;
        writer.write_image_data(img.as_raw()).map_err(err)?;
        writer.finish().map_err(err)?;
    }
    write_atomic(path, &bytes)
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
                g.normal[0],
                g.normal[1],
                g.normal[2],
                g.position[0],
                g.position[1],
                g.position[2],
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

fn finite_or_zero(x: impl Into<f64>) -> f32 {
    let f = x.into() as f32;
    if f.is_finite() { f } else { 0.0 }
}

/// The EXR encoding: `compression` in 64-pixel tiles (RLE by default), written in
/// increasing-y order (the compressor works in parallel, but the file is the same bytes for
/// any thread count and run).
fn exr_encoding(compression: ExrCompression) -> exr::prelude::Encoding {
    exr::prelude::Encoding {
        line_order: exr::prelude::LineOrder::Increasing,
        compression: compression.exr(),
        ..exr::prelude::Encoding::FAST_LOSSLESS
    }
}

/// The u32 id planes of [`EXR_ID_CHANNELS`]: patch and face, `u32::MAX` where the centre ray
/// misses.
pub fn exr_id_planes(frame: &Frame) -> [Vec<u32>; 2] {
    let ids = |f: &dyn Fn(&crate::render::film::PixelGeometry) -> u32| {
        frame
            .geometry
            .iter()
            .map(|g| g.as_ref().map_or(u32::MAX, f))
            .collect::<Vec<u32>>()
    };
    [ids(&|g| g.hit.patch), ids(&|g| g.face)]
}

/// `text` as an EXR attribute text (Latin-1; other characters become `?`).
fn exr_text(text: &str) -> exr::prelude::Text {
    let latin1: String = text
        .chars()
        .map(|c| if u32::from(c) < 256 { c } else { '?' })
        .collect();
    exr::prelude::Text::new_or_none(&latin1).unwrap_or_default()
}

/// Writes the frame as a linear f32 EXR with the channels of [`EXR_CHANNELS`] and
/// [`EXR_ID_CHANNELS`], RLE-compressed (atomically, see [`write_atomic`]).
pub fn write_exr(frame: &Frame, path: &Path) -> Result<()> {
    write_exr_with(
        frame,
        path,
        ExrCompression::default(),
        &OutputMeta::default(),
    )
}

/// Writes the frame as EXR with `compression` and `meta` as header attributes.
pub fn write_exr_with(
    frame: &Frame,
    path: &Path,
    compression: ExrCompression,
    meta: &OutputMeta,
) -> Result<()> {
    use exr::prelude::{
        AnyChannel, AnyChannels, AttributeValue, FlatSamples, Image, Layer, LayerAttributes,
        SmallVec, WritableImage,
    };
    let mut channels: SmallVec<[AnyChannel<FlatSamples>; 4]> = EXR_CHANNELS
        .iter()
        .zip(exr_planes(frame))
        .map(|(name, plane)| AnyChannel::new(*name, FlatSamples::F32(plane)))
        .collect();
    for (name, plane) in EXR_ID_CHANNELS.iter().zip(exr_id_planes(frame)) {
        channels.push(AnyChannel::new(*name, FlatSamples::U32(plane)));
    }
    let mut attributes = LayerAttributes::named("smoothlab");
    attributes.software_name = Some(exr_text(&format!(
        "smoothlab {}",
        env!("CARGO_PKG_VERSION")
    )));
    // Custom attributes live in a hash map whose order is written as is: one entry at most,
    // so that the file's bytes do not depend on the map's random order.
    if let Some(command) = &meta.command {
        attributes.comments = Some(exr_text(command));
    }
    if let Some(camera) = meta.camera_text() {
        attributes.other.insert(
            exr_text("smoothlab.camera"),
            AttributeValue::Text(exr_text(&camera)),
        );
    }
    let layer = Layer::new(
        (frame.width as usize, frame.height as usize),
        attributes,
        exr_encoding(compression),
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

/// Checks an output name (a stem that files are named after: `NAME.png`, `NAME-000.png`, …)
/// before anything is derived from it: valid UTF-8 ([`utf8_path`]), not a folder (`out/`, an
/// existing folder, `..`: the files would be hidden ones such as `out/.png`) and not a device.
pub fn check_output_name(name: &Path) -> Result<()> {
    utf8_path(name)?;
    let stem = output_stem(name);
    let meta = std::fs::metadata(&stem).ok();
    if ends_with_separator(name)
        || stem.file_name().is_none()
        || meta.as_ref().is_some_and(std::fs::Metadata::is_dir)
    {
        return Err(Error::config(
            "output name",
            Problem::Other {
                text: format!(
                    "{}: is a folder; give a file name stem such as {}",
                    name.display(),
                    stem.join("render").display()
                ),
            },
        ));
    }
    if meta.is_some_and(|m| !m.is_file()) {
        return Err(Error::config(
            "output name",
            Problem::Other {
                text: format!(
                    "{}: is not a regular file; give a file name stem (NAME writes NAME.png and \
                     NAME.exr)",
                    name.display()
                ),
            },
        ));
    }
    Ok(())
}

/// Prepares the outputs of name `name` before rendering: creates the folder of the stem if
/// missing and checks that every file of [`output_files`] can be written there (see
/// [`check_writable`]). A name that is a folder (`out/`, or an existing folder) or a device
/// (`/dev/null`) is an error naming it.
pub fn prepare_outputs(name: &Path) -> Result<[PathBuf; 2]> {
    check_output_name(name)?;
    let stem = output_stem(name);
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
pub fn write_outputs(frame: &Frame, files: &[PathBuf; 2]) -> Result<()> {
    write_outputs_with(frame, files, &OutputOptions::default())
}

/// Writes the frame to the files of [`prepare_outputs`] as `options` say: the PNG, and the EXR
/// unless `options.exr` is None.
pub fn write_outputs_with(
    frame: &Frame,
    [png, exr]: &[PathBuf; 2],
    options: &OutputOptions,
) -> Result<()> {
    write_png_with(frame, png, &options.meta)?;
    match options.exr {
        Some(compression) => write_exr_with(frame, exr, compression, &options.meta),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::test_support::assert_config_error;

    /// An output name that is a folder or not a regular file is a configuration error of the
    /// output name, worded as before.
    #[test]
    fn bad_output_names_are_config_errors() {
        let is_name_error: fn(&Problem) -> bool = |p| matches!(p, Problem::Other { .. });
        let err = check_output_name(Path::new("out/")).expect_err("folder");
        assert_config_error(
            &err,
            "output name",
            is_name_error,
            format!(
                "output name out/: is a folder; give a file name stem such as {}",
                Path::new("out").join("render").display()
            ),
        );
        #[cfg(unix)]
        {
            let err = check_output_name(Path::new("/dev/null")).expect_err("device");
            assert_config_error(
                &err,
                "output name",
                is_name_error,
                "output name /dev/null: is not a regular file; give a file name stem (NAME \
                 writes NAME.png and NAME.exr)",
            );
        }
    }

    /// The remembered last value gives the bytes of encoding every value on its own.
    #[test]
    fn srgb8_is_the_transfer_of_every_value() {
        let values = [
            0.0,
            0.045,
            0.045,
            0.5,
            0.5,
            1.0,
            2.0,
            -1.0,
            f32::NAN,
            0.003,
            0.9,
            0.9,
        ];
        let rgb: Vec<[f32; 3]> = values
            .windows(3)
            .map(|w| [w[0], w[1], w[2]])
            .chain([[0.2; 3], [0.2; 3], [0.7, 0.2, 0.2]])
            .collect();
        let frame = Frame {
            rgb: rgb.clone(),
            ..Frame::blank(rgb.len() as u32, 1, [0.0; 3])
        };
        let expected: Vec<u8> = frame
            .rgb
            .iter()
            .flatten()
            .map(|&x| (linear_to_srgb(f64::from(x)) * 255.0 + 0.5) as u8)
            .collect();
        assert_eq!(srgb8(&frame), expected);
    }

    /// The PNG's rows are the image's rows, each followed by the legend's row.
    #[test]
    fn the_legend_strip_lies_right_of_the_image() {
        let mut frame = Frame::blank(3, 2, [0.0; 3]);
        frame.rgb[3] = [1.0; 3];
        frame.legend = Some(crate::render::theme::Legend {
            width: 2,
            height: 2,
            rgb: vec![[1.0, 0.0, 0.0], [0.0; 3], [0.0; 3], [0.0, 0.0, 1.0]],
        });
        assert_eq!(frame.png_width(), 5);
        let bytes = srgb8(&frame);
        let px: Vec<&[u8]> = bytes.chunks(3).collect();
        let (black, white) = ([0u8; 3], [255u8; 3]);
        let (red, blue) = ([255, 0, 0], [0, 0, 255]);
        let want: [&[u8]; 10] = [
            &black, &black, &black, &red, &black, &white, &black, &black, &black, &blue,
        ];
        assert_eq!(px, want);
    }

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
