//! The Python module `smoothlab._smoothlab`: meshes from numpy arrays or files, the schemes of
//! the registry, surfaces with their patches, evaluation, metrics and exports, and renders.
//! Everything is the root crate's own code, called as the command line calls it; this crate
//! converts values between Python and Rust and releases the interpreter while the work runs.

mod convert;
mod detached;
mod mesh;
mod render;
mod surface;

use pyo3::create_exception;
use pyo3::exceptions::{PyOSError, PyUserWarning, PyValueError};
use pyo3::prelude::*;

create_exception!(
    _smoothlab,
    SmoothlabError,
    PyValueError,
    "An input smoothlab refuses (a bad mesh, an unknown scheme or parameter, a bad scene key), \
     with the message the command line prints."
);
create_exception!(
    _smoothlab,
    SmoothlabWarning,
    PyUserWarning,
    "A warning line of smoothlab (a repair made while loading, a normal tilted by a scheme)."
);

/// The Python exception of a library error: `OSError` for a file that cannot be read or
/// written, [`SmoothlabError`] (a `ValueError`) for everything else; the message is the
/// error's own line, as the command line prints it after `error: `.
pub(crate) fn to_py(error: smoothlab::Error) -> PyErr {
    match error {
        smoothlab::Error::Io { .. } => PyOSError::new_err(error.to_string()),
        other => SmoothlabError::new_err(other.to_string()),
    }
}

/// Issues every line of `lines` as a Python warning of category [`SmoothlabWarning`].
pub(crate) fn warn_lines(py: Python<'_>, lines: &[String]) -> PyResult<()> {
    let category = py.get_type::<SmoothlabWarning>();
    for line in lines {
        let message = std::ffi::CString::new(line.replace('\0', " "))
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        PyErr::warn(py, category.as_any(), &message, 2)?;
    }
    Ok(())
}

/// The module.
#[pymodule]
fn _smoothlab(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("SmoothlabError", py.get_type::<SmoothlabError>())?;
    m.add("SmoothlabWarning", py.get_type::<SmoothlabWarning>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add(
        "EXR_CHANNELS",
        smoothlab::render::output::EXR_CHANNELS.to_vec(),
    )?;
    m.add(
        "EXR_ID_CHANNELS",
        smoothlab::render::output::EXR_ID_CHANNELS.to_vec(),
    )?;
    m.add(
        "METRICS_CONTRACT_KEYS",
        smoothlab::metrics::CONTRACT_KEYS.to_vec(),
    )?;
    m.add_class::<mesh::Mesh>()?;
    m.add_class::<surface::Surface>()?;
    m.add_class::<render::Render>()?;
    m.add_function(wrap_pyfunction!(mesh::load, m)?)?;
    m.add_function(wrap_pyfunction!(surface::schemes, m)?)?;
    m.add_function(wrap_pyfunction!(surface::build, m)?)?;
    m.add_function(wrap_pyfunction!(render::render, m)?)?;
    Ok(())
}
