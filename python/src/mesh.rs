//! `Mesh` and `load`: a mesh from numpy arrays (or a trimesh object) or from a file, through
//! the library's one loading pipeline, with its load report as Python data and its warning
//! lines as Python warnings.

use std::path::PathBuf;
use std::sync::Arc;

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use smoothlab::mesh::{LoadOptions, LoadReport};

use crate::convert;
use crate::detached::{self, OnInterrupt};
use crate::{SmoothlabError, to_py, warn_lines};

/// The load options of the keyword arguments, checked as the command line checks its flags.
fn load_options(
    weld_tolerance: Option<f64>,
    crease_angle: Option<f64>,
    strict: bool,
) -> PyResult<LoadOptions> {
    let mut options = LoadOptions {
        strict,
        ..LoadOptions::default()
    };
    if let Some(t) = weld_tolerance {
        options.weld_tolerance = smoothlab::mesh::check_weld_tolerance(t)
            .map_err(|e| SmoothlabError::new_err(format!("weld_tolerance: {e}")))?;
    }
    if let Some(a) = crease_angle {
        options.crease_angle = Some(
            smoothlab::mesh::check_crease_angle(a)
                .map_err(|e| SmoothlabError::new_err(format!("crease_angle: {e}")))?,
        );
    }
    Ok(options)
}

/// A validated, consistently oriented, manifold triangle mesh.
///
/// ``Mesh(vertices, faces)`` takes a float64 array of shape (n, 3) and either an integer array
/// of shape (m, 3) (triangles; (m, k) for k-gons) or a list of polygons (sequences of vertex
/// indices, any number of corners: planar convex ones are split into triangles). A
/// ``trimesh.Trimesh`` may be passed alone. Loading welds, checks and orients the mesh as the
/// command line does; what it changed is in ``report`` and each warning line is issued as a
/// ``SmoothlabWarning``. Bad input raises ``SmoothlabError`` (a ``ValueError``) naming the
/// vertex or face, ``ValueError``/``TypeError`` for a badly shaped or typed array.
#[pyclass(module = "smoothlab", frozen)]
pub(crate) struct Mesh {
    pub(crate) mesh: Arc<smoothlab::mesh::Mesh>,
    report: LoadReport,
}

impl Mesh {
    fn finish(
        py: Python<'_>,
        (mesh, report): (smoothlab::mesh::Mesh, LoadReport),
    ) -> PyResult<Mesh> {
        warn_lines(py, &report.warnings)?;
        Ok(Mesh {
            mesh: Arc::new(mesh),
            report,
        })
    }
}

#[pymethods]
impl Mesh {
    #[new]
    #[pyo3(signature = (vertices, faces=None, *, weld_tolerance=None, crease_angle=None, strict=false))]
    fn new(
        py: Python<'_>,
        vertices: &Bound<'_, PyAny>,
        faces: Option<&Bound<'_, PyAny>>,
        weld_tolerance: Option<f64>,
        crease_angle: Option<f64>,
        strict: bool,
    ) -> PyResult<Mesh> {
        let options = load_options(weld_tolerance, crease_angle, strict)?;
        let (vertices, faces) = match faces {
            Some(f) => (vertices.clone(), f.clone()),
            None if vertices.hasattr("vertices")? && vertices.hasattr("faces")? => {
                // A trimesh.Trimesh (or anything with vertices and faces arrays).
                (vertices.getattr("vertices")?, vertices.getattr("faces")?)
            }
            None => {
                return Err(PyTypeError::new_err(
                    "Mesh(vertices, faces): faces missing (only a trimesh.Trimesh may be \
                     passed alone)",
                ));
            }
        };
        let positions = convert::points(&vertices, "vertices", "vertex")?;
        let faces = convert::faces(&faces, "faces")?;
        let loaded = detached::run(py, OnInterrupt::Abandon, move |_| {
            if faces.all_triangles() {
                let triangles = faces
                    .corners
                    .chunks_exact(3)
                    .map(|c| [c[0], c[1], c[2]])
                    .collect();
                smoothlab::mesh::Mesh::from_triangles_with(positions, triangles, &options)
            } else {
                smoothlab::mesh::Mesh::from_polygons_with(
                    positions,
                    faces.corners,
                    faces.arities,
                    &options,
                )
            }
        })?
        .map_err(to_py)?;
        Mesh::finish(py, loaded)
    }

    /// Vertex positions after loading (unused vertices dropped, near ones welded), (n, 3) float64.
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let values = self
            .mesh
            .positions()
            .iter()
            .flat_map(|p| p.to_array())
            .collect();
        convert::array(py, values, &[self.mesh.vertex_count(), 3])
    }

    /// Triangles as counter-clockwise vertex triples (consistently oriented), (m, 3) int64.
    #[getter]
    fn faces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let values = self
            .mesh
            .faces()
            .iter()
            .flat_map(|f| f.map(i64::from))
            .collect();
        convert::array(py, values, &[self.mesh.face_count(), 3])
    }

    /// The input face (polygon) every triangle was cut from, (m,) int64.
    #[getter]
    fn input_faces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let values = self
            .mesh
            .face_origins()
            .iter()
            .map(|&f| i64::from(f))
            .collect();
        convert::array(py, values, &[self.mesh.face_count()])
    }

    /// Number of vertices.
    #[getter]
    fn vertex_count(&self) -> usize {
        self.mesh.vertex_count()
    }

    /// Number of triangles.
    #[getter]
    fn face_count(&self) -> usize {
        self.mesh.face_count()
    }

    /// Number of undirected edges.
    #[getter]
    fn edge_count(&self) -> usize {
        self.mesh.edge_count()
    }

    /// True if the mesh has no boundary edge.
    #[getter]
    fn is_closed(&self) -> bool {
        self.mesh.is_closed()
    }

    /// Euler characteristic V − E + F.
    #[getter]
    fn euler_characteristic(&self) -> i64 {
        self.mesh.euler_characteristic()
    }

    /// What loading did: ``welded``, ``welded_near``, ``weld_max_distance``,
    /// ``reoriented_faces``, ``sharp_edges``, ``repairs`` (each with ``kind``, ``count``,
    /// ``first``, ``detail``, as in the metrics JSON) and ``warnings`` (lines).
    #[getter]
    fn report<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let r = &self.report;
        let dict = PyDict::new(py);
        dict.set_item("welded", r.welded)?;
        dict.set_item("welded_near", r.welded_near)?;
        dict.set_item("weld_max_distance", r.weld_max_distance)?;
        dict.set_item("reoriented_faces", r.reoriented_faces)?;
        dict.set_item("sharp_edges", r.sharp_edges)?;
        dict.set_item("repairs", convert::serialised(py, &r.repairs)?)?;
        dict.set_item("warnings", PyList::new(py, &r.warnings)?)?;
        Ok(dict)
    }

    fn __repr__(&self) -> String {
        format!(
            "<smoothlab.Mesh: {} vertices, {} faces, {}>",
            self.mesh.vertex_count(),
            self.mesh.face_count(),
            if self.mesh.is_closed() {
                "closed"
            } else {
                "open"
            }
        )
    }
}

/// Loads a mesh file (OBJ, PLY, OFF or STL by its extension, case ignored) as
/// ``smoothlab metrics|render|export`` load it; warning lines are issued as
/// ``SmoothlabWarning``. A missing file raises ``OSError``, a bad one ``SmoothlabError``.
#[pyfunction]
#[pyo3(signature = (path, *, weld_tolerance=None, crease_angle=None, strict=false))]
pub(crate) fn load(
    py: Python<'_>,
    path: PathBuf,
    weld_tolerance: Option<f64>,
    crease_angle: Option<f64>,
    strict: bool,
) -> PyResult<Mesh> {
    let options = load_options(weld_tolerance, crease_angle, strict)?;
    let loaded = detached::run(py, OnInterrupt::Abandon, move |_| {
        smoothlab::mesh::Mesh::load_with(&path, &options)
    })?
    .map_err(to_py)?;
    Mesh::finish(py, loaded)
}
