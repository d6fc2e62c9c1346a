//! `render` and `Render`: a surface ray-traced as `smoothlab render` traces it. The keyword
//! arguments become scene keys (the README's scene contract), validated by the library's
//! [`smoothlab::SceneFile::job`] into the same render job; the frame is the command line's bit
//! for bit, its EXR channels come from the EXR writer's own planes, and `save` writes through
//! the command line's output path.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::Ordering;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyIterator, PyTuple};
use smoothlab::render::Frame;
use smoothlab::render::RenderStats;
use smoothlab::render::output::{
    self, EXR_CHANNELS, EXR_ID_CHANNELS, ExrCompression, OutputMeta, OutputOptions,
};
use smoothlab::render::{Camera, Projection};

use crate::convert;
use crate::detached::{self, OnInterrupt};
use crate::surface::Surface;
use crate::{SmoothlabError, to_py};

/// Scene sections a render of a built surface takes (the mesh, scheme and load keys belong
/// to the surface, which is given).
const SECTIONS: [&str; 8] = [
    "camera",
    "render",
    "bvh",
    "zebra",
    "highlight",
    "isophote",
    "curvature",
    "shaded",
];

/// `[render]` keys that are not about one image (animations) or that have keyword arguments
/// of their own (`output`, `exr`, `exr_compression`).
const NOT_RENDER_KEYS: [&str; 7] = [
    "output",
    "exr",
    "exr_compression",
    "turntable",
    "turntable_axis",
    "sweep",
    "mode",
];

/// The sub-table `name` of `table`, created if missing.
fn section<'t>(table: &'t mut toml::Table, name: &str) -> PyResult<&'t mut toml::Table> {
    table
        .entry(name)
        .or_insert_with(|| toml::Value::Table(toml::Table::new()))
        .as_table_mut()
        .ok_or_else(|| SmoothlabError::new_err(format!("scene key '{name}' must be a table")))
}

/// The scene of a render's keyword arguments, as TOML text for [`smoothlab::SceneFile::parse`].
#[allow(clippy::too_many_arguments)]
fn scene_text(
    mode: &str,
    size: Option<(u32, u32)>,
    camera: Option<&Bound<'_, PyDict>>,
    spp: Option<u32>,
    overlay: Option<&str>,
    seed: Option<u64>,
    exr: bool,
    exr_compression: Option<&str>,
    scene: Option<&Bound<'_, PyDict>>,
    mode_params: Option<&Bound<'_, PyDict>>,
) -> PyResult<String> {
    let mut table = match scene {
        Some(s) => convert::toml_table(s, "")?,
        None => toml::Table::new(),
    };
    if let Some(key) = table.keys().find(|k| !SECTIONS.contains(&k.as_str())) {
        return Err(SmoothlabError::new_err(format!(
            "scene key '{key}' does not apply to a render of a built surface (sections: {})",
            SECTIONS.join(", ")
        )));
    }
    if let Some(key) = section(&mut table, "render")?
        .keys()
        .find(|k| NOT_RENDER_KEYS.contains(&k.as_str()))
    {
        return Err(SmoothlabError::new_err(format!(
            "scene key 'render.{key}' is not for scene=: give mode=, output=, exr= or \
             exr_compression= to render(); animations are the command line's"
        )));
    }
    let render = section(&mut table, "render")?;
    render.insert("mode".into(), toml::Value::String(mode.into()));
    if let Some((w, h)) = size {
        render.insert(
            "size".into(),
            toml::Value::Array(vec![i64::from(w).into(), i64::from(h).into()]),
        );
    }
    if let Some(spp) = spp {
        render.insert("spp".into(), i64::from(spp).into());
    }
    if let Some(o) = overlay {
        render.insert("overlay".into(), o.into());
    }
    if let Some(seed) = seed {
        let seed = i64::try_from(seed)
            .map_err(|_| SmoothlabError::new_err(format!("seed {seed} is above 2^63 − 1")))?;
        render.insert("seed".into(), seed.into());
    }
    render.insert("exr".into(), exr.into());
    if let Some(c) = exr_compression {
        render.insert("exr_compression".into(), c.into());
    }
    if let Some(camera) = camera {
        let given = convert::toml_table(camera, "camera")?;
        section(&mut table, "camera")?.extend(given);
    }
    if let Some(params) = mode_params.filter(|p| !p.is_empty()) {
        let given = convert::toml_table(params, mode)?;
        if !SECTIONS[3..].contains(&mode) {
            return Err(SmoothlabError::new_err(format!(
                "mode '{mode}' takes no parameters, got {}",
                given.keys().cloned().collect::<Vec<_>>().join(", ")
            )));
        }
        section(&mut table, mode)?.extend(given);
    }
    toml::to_string(&table)
        .map_err(|e| PyValueError::new_err(format!("cannot write the scene: {e}")))
}

/// Ray-traces ``surface`` exactly as ``smoothlab render`` does and returns a :class:`Render`
/// (unpacks as ``rgb, channels``).
///
/// ``mode`` is one of zebra, highlight, isophote, curvature, normals, patches, diffuse,
/// shaded; ``size`` is ``(width, height)`` (default 640×480); ``camera`` a dict of the scene's
/// ``[camera]`` keys (``eye``, ``target``, ``up``, ``fov``, ``ortho``; default: automatic
/// framing); ``spp`` samples per pixel (default 4); ``overlay`` none, faces, patches or both;
/// further keyword arguments are the keys of the mode's section (``stripes=16``,
/// ``quantity="gaussian"``, …). ``scene`` takes any other scene sections as dicts
/// (``{"bvh": {"flatness": 0.01}, "render": {"background": [1, 1, 1]}}``). Every value is
/// checked as in a scene file; a bad one raises ``SmoothlabError`` naming the key.
///
/// With ``output``, the PNG and (unless ``exr=False``) the EXR are written to
/// ``output.png``/``output.exr`` once the render is complete. The interpreter is released
/// while rendering; Ctrl-C (``KeyboardInterrupt``) stops the render between tiles and writes
/// nothing.
#[pyfunction]
#[pyo3(signature = (surface, mode="zebra", size=None, camera=None, *, spp=None, overlay=None, seed=None, scene=None, output=None, exr=true, exr_compression=None, **mode_params))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn render(
    py: Python<'_>,
    surface: &Bound<'_, Surface>,
    mode: &str,
    size: Option<(u32, u32)>,
    camera: Option<&Bound<'_, PyDict>>,
    spp: Option<u32>,
    overlay: Option<&str>,
    seed: Option<u64>,
    scene: Option<&Bound<'_, PyDict>>,
    output: Option<PathBuf>,
    exr: bool,
    exr_compression: Option<&str>,
    mode_params: Option<&Bound<'_, PyDict>>,
) -> PyResult<Render> {
    let text = scene_text(
        mode,
        size,
        camera,
        spp,
        overlay,
        seed,
        exr,
        exr_compression,
        scene,
        mode_params,
    )?;
    let scene = smoothlab::SceneFile::parse(&text).map_err(to_py)?;
    let mut job = scene.job().map_err(to_py)?;
    let exr = scene.exr_compression().map_err(to_py)?;
    job.settings.progress = false;
    smoothlab::render::check_frame_memory(
        job.settings.width,
        job.settings.height,
        output::output_bytes_per_pixel(exr.is_some()),
    )
    .map_err(to_py)?;
    let files = output
        .as_deref()
        .map(output::prepare_outputs)
        .transpose()
        .map_err(to_py)?;
    let built = Arc::clone(&surface.get().built);
    // The back of an open surface shows: tinted in the quality modes, as the command does.
    if !built.mesh.is_closed() {
        job.settings.mode = job.settings.mode.with_back_faces_tinted();
    }
    let rendered = detached::run(py, OnInterrupt::Join, move |cancel| {
        let tracer = job.tracer(&built.user)?;
        let Some((frame, stats)) =
            job.render_with(&tracer, &built.mesh, &|| cancel.load(Ordering::SeqCst))?
        else {
            return Ok(None);
        };
        let camera = job.camera_of(&built.user)?;
        if let Some(files) = &files
            && !cancel.load(Ordering::SeqCst)
        {
            write(&frame, files, exr, camera)?;
        }
        Ok::<_, smoothlab::Error>(Some((frame, stats, camera)))
    })?
    .map_err(to_py)?;
    let (frame, stats, camera) = rendered.ok_or_else(|| {
        pyo3::exceptions::PyKeyboardInterrupt::new_err("the render was cancelled")
    })?;
    Ok(Render {
        frame,
        stats,
        camera,
        exr,
    })
}

/// Writes `frame` to `files` as the `render` command writes them.
fn write(
    frame: &Frame,
    files: &[PathBuf; 2],
    exr: Option<ExrCompression>,
    camera: Camera,
) -> smoothlab::Result<()> {
    let options = OutputOptions {
        exr,
        meta: OutputMeta {
            command: None,
            camera: Some(camera),
        },
    };
    output::write_outputs_with(frame, files, &options)
}

/// A rendered image: linear RGB, the EXR's channels, the camera and the render statistics.
#[pyclass(module = "smoothlab", frozen)]
pub(crate) struct Render {
    frame: Frame,
    stats: RenderStats,
    camera: Camera,
    exr: Option<ExrCompression>,
}

impl Render {
    fn shape(&self) -> [usize; 2] {
        [self.frame.height as usize, self.frame.width as usize]
    }
}

#[pymethods]
impl Render {
    /// Width in pixels.
    #[getter]
    fn width(&self) -> u32 {
        self.frame.width
    }

    /// Height in pixels.
    #[getter]
    fn height(&self) -> u32 {
        self.frame.height
    }

    /// Linear RGB, (height, width, 3) float32, rows top to bottom (the EXR's R, G, B).
    #[getter]
    fn rgb<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let values = self.frame.rgb.iter().flatten().copied().collect();
        let [h, w] = self.shape();
        convert::array(py, values, &[h, w, 3])
    }

    /// The PNG's pixels: 8-bit sRGB, (height, width + legend width, 3) uint8 — the image
    /// with the mode's legend strip right of it (curvature mode), as the PNG holds them.
    #[getter]
    fn srgb8<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let h = self.frame.height as usize;
        let w = self.frame.png_width() as usize;
        convert::array(py, output::srgb8(&self.frame), &[h, w, 3])
    }

    /// The EXR's channels by name, each (height, width): ``R, G, B, Z, N.X, N.Y, N.Z, P.X,
    /// P.Y, P.Z, u, v, patch_id, face_id, K, H`` as float32 (misses: ``Z = u = v = patch_id =
    /// face_id = −1``, the others 0) and ``id.patch``, ``id.face`` as uint32 (misses 2^32 − 1).
    #[getter]
    fn channels<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let [h, w] = self.shape();
        let dict = PyDict::new(py);
        let planes = py.detach(|| output::exr_planes(&self.frame));
        for (name, plane) in EXR_CHANNELS.iter().zip(planes) {
            dict.set_item(*name, convert::array(py, plane, &[h, w])?)?;
        }
        for (name, plane) in EXR_ID_CHANNELS
            .iter()
            .zip(output::exr_id_planes(&self.frame))
        {
            dict.set_item(*name, convert::array(py, plane, &[h, w])?)?;
        }
        Ok(dict)
    }

    /// The render statistics (the keys of ``smoothlab render --stats``).
    #[getter]
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        convert::serialised(py, &self.stats)
    }

    /// The camera: ``eye``, ``target``, ``up`` and ``fov_deg`` (perspective) or
    /// ``ortho_height`` (orthographic).
    #[getter]
    fn camera<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let c = &self.camera;
        let dict = PyDict::new(py);
        dict.set_item("eye", c.eye.to_array())?;
        dict.set_item("target", c.target.to_array())?;
        dict.set_item("up", c.up().to_array())?;
        match c.projection {
            Projection::Perspective { fov_deg } => dict.set_item("fov_deg", fov_deg)?,
            Projection::Orthographic { height } => dict.set_item("ortho_height", height)?,
        }
        Ok(dict)
    }

    /// Writes ``NAME.png`` and (unless ``exr=False``, or the render was made with
    /// ``exr=False``) ``NAME.exr`` as ``smoothlab render -o NAME`` writes them (a name ending
    /// in .png or .exr counts without it; a missing folder is created); each file is written
    /// whole or not at all. Returns the paths written.
    #[pyo3(signature = (name, *, exr=None, exr_compression=None))]
    fn save(
        &self,
        py: Python<'_>,
        name: PathBuf,
        exr: Option<bool>,
        exr_compression: Option<&str>,
    ) -> PyResult<Vec<PathBuf>> {
        let compression = match exr_compression {
            Some(c) => Some(ExrCompression::by_name(c).map_err(to_py)?),
            None => self.exr,
        };
        let exr = match exr {
            Some(false) => None,
            Some(true) => Some(compression.unwrap_or_default()),
            None => compression,
        };
        let files = output::prepare_outputs(&name).map_err(to_py)?;
        let frame = self.frame.clone();
        let camera = self.camera;
        let written = files.clone();
        detached::run(py, OnInterrupt::Join, move |_| {
            write(&frame, &files, exr, camera)
        })?
        .map_err(to_py)?;
        Ok(written[..1 + usize::from(exr.is_some())].to_vec())
    }

    /// ``rgb, channels = render(...)``.
    fn __iter__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyIterator>> {
        let pair = PyTuple::new(py, [self.rgb(py)?, self.channels(py)?.into_any()])?;
        PyIterator::from_object(pair.as_any())
    }

    fn __repr__(&self) -> String {
        format!(
            "<smoothlab.Render: {}x{}, {} hits>",
            self.frame.width, self.frame.height, self.stats.hits
        )
    }
}
