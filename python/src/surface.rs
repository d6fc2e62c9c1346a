//! `schemes`, `build` and `Surface`: the registry's schemes built on a mesh as
//! `smoothlab metrics` builds them (in the mesh's local frame, timed), the surface in the
//! user's coordinates for patches, evaluation, exports and renders, the one in the frame for
//! the metrics — so that every figure is the command line's, bit for bit.

use std::path::PathBuf;
use std::sync::Arc;

use pyo3::exceptions::{PyIndexError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use rayon::prelude::*;
use smoothlab::surface::{LocalFrame, PatchGeometry};

use crate::convert;
use crate::detached::{self, OnInterrupt};
use crate::mesh::Mesh;
use crate::{to_py, warn_lines};

/// Every registered scheme, in the registry's order: a list of dicts with ``name``,
/// ``summary`` (with its paper), ``needs_closed_mesh``, ``sharp_edges`` (True if it keeps
/// sharp edges G0, else the reason it refuses them) and ``params`` (dicts of ``name``,
/// ``default``, ``help``) — what ``smoothlab schemes`` prints.
#[pyfunction]
pub(crate) fn schemes(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let list = PyList::empty(py);
    for spec in smoothlab::schemes::SCHEMES {
        let dict = PyDict::new(py);
        dict.set_item("name", spec.name)?;
        dict.set_item("summary", spec.summary)?;
        dict.set_item("needs_closed_mesh", spec.needs_closed_mesh)?;
        match spec.sharp_edges {
            smoothlab::schemes::SharpEdgeSupport::Builds => dict.set_item("sharp_edges", true)?,
            smoothlab::schemes::SharpEdgeSupport::Refuses(why) => {
                dict.set_item("sharp_edges", why)?
            }
        }
        let params = PyList::empty(py);
        for p in spec.params {
            let param = PyDict::new(py);
            param.set_item("name", p.name)?;
            param.set_item("default", p.default)?;
            param.set_item("help", p.help)?;
            params.append(param)?;
        }
        dict.set_item("params", params)?;
        list.append(dict)?;
    }
    Ok(list)
}

/// What a built surface keeps.
pub(crate) struct Built {
    /// The mesh it was built on.
    pub mesh: Arc<smoothlab::mesh::Mesh>,
    /// The surface in the user's coordinates.
    pub user: smoothlab::surface::Surface,
    /// The surface in the mesh's local frame (for the metrics).
    local: smoothlab::surface::Surface,
    frame: LocalFrame,
    construct_ms: f64,
    /// The patches of each mesh face.
    patches_of_face: Vec<Vec<u32>>,
}

/// Builds `scheme` on `mesh` with `name=value` pairs, as the command line does.
fn build_surface(
    mesh: Arc<smoothlab::mesh::Mesh>,
    scheme: &str,
    params: &[(String, String)],
) -> smoothlab::Result<Built> {
    let (local, frame, construct_ms) =
        smoothlab::schemes::build_timed_in_frame(scheme, &mesh, params)?;
    // As `schemes::build` maps it for exports and renders.
    let user = local.mapped(|q| frame.to_user(q));
    let mut patches_of_face = vec![Vec::new(); mesh.face_count()];
    for (k, p) in user.patches.iter().enumerate() {
        if let Some(list) = patches_of_face.get_mut(p.face as usize) {
            list.push(k as u32);
        }
    }
    Ok(Built {
        mesh,
        user,
        local,
        frame,
        construct_ms,
        patches_of_face,
    })
}

/// Builds ``scheme`` on ``mesh`` with its parameters as keyword arguments
/// (``build(mesh, "hb", normals="estimate")``; values are str, int, float or bool, given as
/// ``--param name=value`` would give them; unset ones take their defaults). The scheme's
/// warnings are issued as ``SmoothlabWarning``. An unknown scheme or parameter, a bad value or
/// a mesh the scheme refuses raises ``SmoothlabError`` (a ``ValueError``) with the command
/// line's message. The interpreter is released during the build.
#[pyfunction]
#[pyo3(signature = (mesh, scheme, **params))]
pub(crate) fn build(
    py: Python<'_>,
    mesh: &Bound<'_, Mesh>,
    scheme: String,
    params: Option<&Bound<'_, PyDict>>,
) -> PyResult<Surface> {
    let mut pairs = Vec::new();
    if let Some(params) = params {
        for (k, v) in params.iter() {
            let name: String = k.extract()?;
            pairs.push((name.clone(), convert::param_text(&name, &v)?));
        }
    }
    let mesh = Arc::clone(&mesh.get().mesh);
    let built = detached::run(py, OnInterrupt::Abandon, move |_| {
        build_surface(mesh, &scheme, &pairs)
    })?
    .map_err(to_py)?;
    warn_lines(py, &built.user.warnings)?;
    Ok(Surface {
        built: Arc::new(built),
    })
}

/// A surface built by a scheme: a list of patches, each a triangular Bézier patch (or a
/// blend of three, for Nielson and Fang–Mann) over a piece of one mesh face, in the mesh's
/// coordinates.
#[pyclass(module = "smoothlab", frozen)]
pub(crate) struct Surface {
    pub(crate) built: Arc<Built>,
}

/// The jets of `surface` at `(patch, u, v)` points: positions, normals and the four
/// curvatures (NaN where the parametrisation is singular), in parallel, in order.
fn evaluate_points(
    surface: &smoothlab::surface::Surface,
    points: &[(usize, f64, f64)],
) -> (Vec<f64>, Vec<f64>, [Vec<f64>; 4]) {
    let jets: Vec<([f64; 3], [f64; 3], [f64; 4])> = points
        .par_iter()
        .map(|&(patch, u, v)| {
            let jet = surface.patches[patch].jet(u, v);
            let c = jet.curvature();
            let curv = c.map_or([f64::NAN; 4], |c| [c.k1, c.k2, c.gaussian, c.mean]);
            (jet.p.to_array(), jet.normal().to_array(), curv)
        })
        .collect();
    let mut positions = Vec::with_capacity(3 * jets.len());
    let mut normals = Vec::with_capacity(3 * jets.len());
    let mut curvatures: [Vec<f64>; 4] = Default::default();
    for (p, n, c) in jets {
        positions.extend(p);
        normals.extend(n);
        for (list, x) in curvatures.iter_mut().zip(c) {
            list.push(x);
        }
    }
    (positions, normals, curvatures)
}

/// The `(u, v)` of parameter rows: (n, 2) as they are, (n, 3) barycentric `(1−u−v, u, v)`
/// (their sum must be 1 within 1e-12).
fn parameters(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<(f64, f64)>> {
    let obj = &obj
        .py()
        .import("numpy")?
        .call_method1("asarray", (obj, "float64"))?;
    let columns = match obj
        .getattr("shape")
        .ok()
        .and_then(|s| s.extract::<Vec<usize>>().ok())
    {
        Some(shape) if shape.len() == 2 => shape[1],
        _ => 2,
    };
    if columns != 2 && columns != 3 {
        return Err(PyValueError::new_err(format!(
            "{name} must have shape (n, 2) (u, v) or (n, 3) (1−u−v, u, v), got {columns} columns"
        )));
    }
    let values = convert::float_rows(obj, name, columns, "point")?;
    values
        .chunks_exact(columns)
        .enumerate()
        .map(|(k, row)| match row {
            [u, v] => Ok((*u, *v)),
            [w, u, v] if (w + u + v - 1.0).abs() <= 1e-12 => Ok((*u, *v)),
            [w, u, v] => Err(PyValueError::new_err(format!(
                "{name}: point {k} has barycentric weights ({w}, {u}, {v}) whose sum is {}, not 1",
                w + u + v
            ))),
            _ => unreachable!("rows have 2 or 3 columns"),
        })
        .collect()
}

/// The evaluation dict: ``position`` and ``normal`` (n, 3), ``k1``, ``k2``, ``K``, ``H`` (n,).
fn evaluation<'py>(
    py: Python<'py>,
    surface: &smoothlab::surface::Surface,
    points: Vec<(usize, f64, f64)>,
) -> PyResult<Bound<'py, PyDict>> {
    let n = points.len();
    let (positions, normals, [k1, k2, gaussian, mean]) =
        py.detach(|| evaluate_points(surface, &points));
    let dict = PyDict::new(py);
    dict.set_item("position", convert::array(py, positions, &[n, 3])?)?;
    dict.set_item("normal", convert::array(py, normals, &[n, 3])?)?;
    dict.set_item("k1", convert::array(py, k1, &[n])?)?;
    dict.set_item("k2", convert::array(py, k2, &[n])?)?;
    dict.set_item("K", convert::array(py, gaussian, &[n])?)?;
    dict.set_item("H", convert::array(py, mean, &[n])?)?;
    Ok(dict)
}

/// Below this, a face-barycentric weight is taken as 0 when finding the patch of a point.
const INSIDE: f64 = -1e-12;

impl Surface {
    fn patch(&self, index: usize) -> PyResult<&smoothlab::surface::Patch> {
        self.built.user.patches.get(index).ok_or_else(|| {
            PyIndexError::new_err(format!(
                "patch {index} does not exist (the surface has {} patches)",
                self.built.user.patches.len()
            ))
        })
    }
}

#[pymethods]
impl Surface {
    /// The scheme's name.
    #[getter]
    fn scheme(&self) -> &str {
        &self.built.user.scheme
    }

    /// The scheme's parameters, defaults filled in (name → text).
    #[getter]
    fn params<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let dict = PyDict::new(py);
        for (k, v) in &self.built.user.params {
            dict.set_item(k, v)?;
        }
        Ok(dict)
    }

    /// The scheme's warning lines.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.built.user.warnings.clone()
    }

    /// Wall-clock time of the construction in milliseconds.
    #[getter]
    fn construct_ms(&self) -> f64 {
        self.built.construct_ms
    }

    /// The mesh it was built on.
    #[getter]
    fn mesh_face_count(&self) -> usize {
        self.built.mesh.face_count()
    }

    /// Number of patches.
    #[getter]
    fn patch_count(&self) -> usize {
        self.built.user.patches.len()
    }

    fn __len__(&self) -> usize {
        self.built.user.patches.len()
    }

    /// The mesh face (triangle) of every patch, (p,) int64; ``mesh.input_faces[faces]`` gives
    /// the input faces (polygons).
    #[getter]
    fn faces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let values = self
            .built
            .user
            .patches
            .iter()
            .map(|p| i64::from(p.face))
            .collect();
        convert::array(py, values, &[self.built.user.patches.len()])
    }

    /// The piece of its face every patch is (the scheme's numbering), (p,) int64.
    #[getter]
    fn pieces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let values = self
            .built
            .user
            .patches
            .iter()
            .map(|p| i64::from(p.piece))
            .collect();
        convert::array(py, values, &[self.built.user.patches.len()])
    }

    /// The degree of every patch (of its sub-surfaces, for a blend), (p,) int64.
    #[getter]
    fn degrees<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let values = self
            .built
            .user
            .patches
            .iter()
            .map(|p| match &p.geometry {
                PatchGeometry::Bezier(b) => b.degree() as i64,
                PatchGeometry::Blend(b) => b.degree() as i64,
            })
            .collect();
        convert::array(py, values, &[self.built.user.patches.len()])
    }

    /// ``"bezier"`` or ``"blend"`` for patch ``patch``.
    fn kind(&self, patch: usize) -> PyResult<&'static str> {
        Ok(match self.patch(patch)?.geometry {
            PatchGeometry::Bezier(_) => "bezier",
            PatchGeometry::Blend(_) => "blend",
        })
    }

    /// The face-barycentric coordinates of the corners of patch ``patch``'s domain, (3, 3).
    fn domain<'py>(&self, py: Python<'py>, patch: usize) -> PyResult<Bound<'py, PyAny>> {
        let values = self
            .patch(patch)?
            .domain
            .iter()
            .flat_map(|c| c.to_array())
            .collect();
        convert::array(py, values, &[3, 3])
    }

    /// The control points of patch ``patch`` in the export's order (multi-indices (i, j, k),
    /// i from d down to 0, then j from d−i down to 0): (N, 3) for a Bézier patch of degree d
    /// (N = (d+1)(d+2)/2), (3, N, 3) for a blend's three sub-surfaces.
    fn control_points<'py>(&self, py: Python<'py>, patch: usize) -> PyResult<Bound<'py, PyAny>> {
        let p = self.patch(patch)?;
        let values: Vec<f64> = p.control_points().flat_map(|q| q.to_array()).collect();
        let n = values.len() / 3;
        match p.geometry {
            PatchGeometry::Bezier(_) => convert::array(py, values, &[n, 3]),
            PatchGeometry::Blend(_) => convert::array(py, values, &[3, n / 3, 3]),
        }
    }

    /// Evaluates patches at many parameter points at once. ``patch`` is one patch index or
    /// an (n,) array of them; ``uv`` is (n, 2) ``(u, v)`` or (n, 3) barycentric
    /// ``(1−u−v, u, v)`` (the EXR's ``u, v`` channels and the export's point order use the
    /// same parameters). Returns a dict of ``position`` and unit ``normal`` (n, 3) and the
    /// principal curvatures ``k1 ≥ k2``, Gaussian ``K`` and mean ``H`` (n,) with respect to
    /// that normal (NaN where the parametrisation is singular).
    fn evaluate<'py>(
        &self,
        py: Python<'py>,
        patch: &Bound<'py, PyAny>,
        uv: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let uv = parameters(uv, "uv")?;
        let count = self.built.user.patches.len();
        let patches = match patch.extract::<i64>() {
            Ok(one) => {
                let one = usize::try_from(one)
                    .ok()
                    .filter(|&p| p < count)
                    .ok_or_else(|| {
                        PyIndexError::new_err(format!(
                            "patch {one} does not exist (the surface has {count} patches)"
                        ))
                    })?;
                vec![one; uv.len()]
            }
            Err(_) => convert::indices(patch, "patch", count)?,
        };
        if patches.len() != uv.len() {
            return Err(PyValueError::new_err(format!(
                "patch has {} indices but uv {} points",
                patches.len(),
                uv.len()
            )));
        }
        let points = patches
            .into_iter()
            .zip(uv)
            .map(|(p, (u, v))| (p, u, v))
            .collect();
        evaluation(py, &self.built.user, points)
    }

    /// Evaluates the surface over mesh face ``face`` (a triangle index) at face-barycentric
    /// points ``bary`` (n, 3), each in the patch of the face whose domain contains it. Returns
    /// the dict of :meth:`evaluate` plus ``patch`` (n,) and ``uv`` (n, 2).
    fn evaluate_face<'py>(
        &self,
        py: Python<'py>,
        face: usize,
        bary: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let list = self.built.patches_of_face.get(face).ok_or_else(|| {
            PyIndexError::new_err(format!(
                "face {face} does not exist (the mesh has {} faces)",
                self.built.patches_of_face.len()
            ))
        })?;
        let values = convert::float_rows(bary, "bary", 3, "point")?;
        let mut points = Vec::with_capacity(values.len() / 3);
        for (k, row) in values.chunks_exact(3).enumerate() {
            let b = glam::DVec3::from_slice(row);
            if (b.element_sum() - 1.0).abs() > 1e-12 || b.min_element() < INSIDE {
                return Err(PyValueError::new_err(format!(
                    "bary: point {k} ({}, {}, {}) is not a point of the face (weights ≥ 0, sum 1)",
                    row[0], row[1], row[2]
                )));
            }
            // The patch whose smallest weight of the point is largest: the one containing it.
            let best = list
                .iter()
                .filter_map(|&p| {
                    let uv = self.built.user.patches[p as usize].uv_of(b)?;
                    let least = (1.0 - uv.x - uv.y).min(uv.x).min(uv.y);
                    Some((p as usize, uv, least))
                })
                .max_by(|a, b| a.2.total_cmp(&b.2));
            match best {
                Some((p, uv, least)) if least >= INSIDE => points.push((p, uv.x, uv.y)),
                _ => {
                    return Err(PyValueError::new_err(format!(
                        "bary: point {k} lies in no patch of face {face}"
                    )));
                }
            }
        }
        let patches: Vec<i64> = points.iter().map(|p| p.0 as i64).collect();
        let uvs: Vec<f64> = points.iter().flat_map(|p| [p.1, p.2]).collect();
        let n = points.len();
        let dict = evaluation(py, &self.built.user, points)?;
        dict.set_item("patch", convert::array(py, patches, &[n])?)?;
        dict.set_item("uv", convert::array(py, uvs, &[n, 2])?)?;
        Ok(dict)
    }

    /// The metrics of the surface against its mesh: a dict with the keys of the metrics JSON
    /// (``smoothlab metrics --json``), the same figures bit for bit (``construct_ms`` is this
    /// build's time). The interpreter is released while it measures.
    fn metrics<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let built = Arc::clone(&self.built);
        let metrics = detached::run(py, OnInterrupt::Abandon, move |_| {
            let m = smoothlab::metrics::Metrics::measure_in_frame(
                &built.local,
                &built.frame,
                &built.mesh,
                built.construct_ms,
            );
            m.check_finite().map(|()| m)
        })?
        .map_err(to_py)?;
        convert::serialised(py, &metrics)
    }

    /// Writes the surface to ``path`` as ``smoothlab export`` does: ``format`` ``"json"``
    /// (the patch JSON), ``"bv"`` (BezierView) or ``"obj"`` (tessellated with ``tess``
    /// subdivisions per patch edge), by default told from the extension. The file is written
    /// whole or not at all.
    #[pyo3(signature = (path, format=None, *, tess=8))]
    fn export(
        &self,
        py: Python<'_>,
        path: PathBuf,
        format: Option<&str>,
        tess: usize,
    ) -> PyResult<()> {
        let format = match format {
            Some(name) => smoothlab::export::Format::parse(name),
            None => smoothlab::export::Format::from_path(&path),
        }
        .map_err(to_py)?;
        if !(1..=smoothlab::export::MAX_TESS).contains(&tess) {
            return Err(PyValueError::new_err(format!(
                "tess = {tess} must be in 1..={}",
                smoothlab::export::MAX_TESS
            )));
        }
        let built = Arc::clone(&self.built);
        detached::run(py, OnInterrupt::Join, move |_| {
            let input_face = |t: u32| built.mesh.input_face(t);
            smoothlab::export::write(&built.user, format, tess, &input_face, &path)
        })?
        .map_err(to_py)
    }

    fn __repr__(&self) -> String {
        format!(
            "<smoothlab.Surface: {} ({} patches on {} faces)>",
            self.built.user.scheme,
            self.built.user.patches.len(),
            self.built.mesh.face_count()
        )
    }
}
