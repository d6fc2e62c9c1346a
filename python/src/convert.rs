//! Values between Python and Rust: numpy arrays checked for shape, type, contiguity and
//! finiteness with errors naming the argument; JSON values (the library's serialised results)
//! as Python objects; Python values as TOML values (scene keys) and as parameter text.

use numpy::{
    PyArray1, PyArray2, PyArrayDescrMethods, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// `obj` as a numpy array: an `ndarray` as it is, anything else through `numpy.asarray` with
/// `dtype` (so that nested lists are accepted).
fn as_array<'py>(
    obj: &Bound<'py, PyAny>,
    dtype: Option<&str>,
) -> PyResult<Bound<'py, PyUntypedArray>> {
    if let Ok(array) = obj.cast::<PyUntypedArray>() {
        return Ok(array.clone());
    }
    let numpy = obj.py().import("numpy")?;
    let converted = match dtype {
        Some(d) => numpy.call_method1("asarray", (obj, d))?,
        None => numpy.call_method1("asarray", (obj,))?,
    };
    Ok(converted.cast_into::<PyUntypedArray>()?)
}

/// A shape as Python writes it: `(12, 2)`, `(36,)`.
fn shape_text(shape: &[usize]) -> String {
    match shape {
        [one] => format!("({one},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// Checks that `array` (argument `name`) is C-contiguous and two-dimensional with `columns`
/// columns (any when None); returns the number of rows.
fn check_2d(
    array: &Bound<'_, PyUntypedArray>,
    name: &str,
    columns: Option<usize>,
) -> PyResult<usize> {
    let shape = array.shape();
    let want = columns.map_or("(n, k)".to_string(), |c| format!("(n, {c})"));
    if shape.len() != 2 || columns.is_some_and(|c| shape[1] != c) {
        return Err(PyValueError::new_err(format!(
            "{name} must have shape {want}, got shape {}",
            shape_text(shape)
        )));
    }
    if !array.is_c_contiguous() {
        return Err(PyValueError::new_err(format!(
            "{name} must be C-contiguous (a strided view such as a[:, ::2] or a.T is not): \
             pass numpy.ascontiguousarray({name})"
        )));
    }
    Ok(shape[0])
}

/// An (n, 3) float64 array (argument `name`) of finite values as points; `what` names a row
/// in errors (`vertex`).
pub(crate) fn points(obj: &Bound<'_, PyAny>, name: &str, what: &str) -> PyResult<Vec<glam::DVec3>> {
    let values = float_rows(obj, name, 3, what)?;
    Ok(values
        .chunks_exact(3)
        .map(|c| glam::DVec3::new(c[0], c[1], c[2]))
        .collect())
}

/// An (n, `columns`) float64 array (argument `name`) of finite values, row after row; `what`
/// names a row in errors.
pub(crate) fn float_rows(
    obj: &Bound<'_, PyAny>,
    name: &str,
    columns: usize,
    what: &str,
) -> PyResult<Vec<f64>> {
    let array = as_array(obj, Some("float64"))?;
    check_2d(&array, name, Some(columns))?;
    let dtype = array.dtype();
    if dtype.kind() != b'f' || dtype.itemsize() != 8 {
        return Err(PyTypeError::new_err(format!(
            "{name} must be a float64 array, got dtype {}: pass {name}.astype(numpy.float64)",
            dtype.str()?
        )));
    }
    let typed = array.cast::<PyArray2<f64>>()?;
    let values = typed.readonly().as_slice()?.to_vec();
    if let Some(k) = values.iter().position(|x| !x.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "{name}: {what} {} has a non-finite value (column {}: {})",
            k / columns,
            k % columns,
            values[k]
        )));
    }
    Ok(values)
}

/// The integers of an integer array of any width and sign, as i128 (no value is lost).
fn integers(array: &Bound<'_, PyUntypedArray>, name: &str) -> PyResult<Vec<i128>> {
    let dtype = array.dtype();
    match dtype.kind() {
        b'i' => {
            let wide = array.call_method1("astype", ("int64",))?;
            let typed = wide.cast::<numpy::PyArrayDyn<i64>>()?;
            Ok(typed
                .readonly()
                .as_slice()?
                .iter()
                .map(|&x| i128::from(x))
                .collect())
        }
        b'u' => {
            let wide = array.call_method1("astype", ("uint64",))?;
            let typed = wide.cast::<numpy::PyArrayDyn<u64>>()?;
            Ok(typed
                .readonly()
                .as_slice()?
                .iter()
                .map(|&x| i128::from(x))
                .collect())
        }
        _ => Err(PyTypeError::new_err(format!(
            "{name} must be an integer array, got dtype {}",
            dtype.str()?
        ))),
    }
}

/// Vertex index `value` of corner `corner` of face `face` as u32, or an error naming them
/// (an index beyond the vertices is the mesh loader's to report).
fn vertex_index(value: i128, name: &str, face: usize, corner: usize) -> PyResult<u32> {
    u32::try_from(value).map_err(|_| {
        PyValueError::new_err(format!(
            "{name}: face {face} corner {corner} refers to vertex {value}, which is not a \
             vertex index (0 ≤ index < 2^32)"
        ))
    })
}

/// The faces of a mesh: corners (concatenated) and the number of corners of each face.
pub(crate) struct Faces {
    /// Vertex indices, face after face.
    pub corners: Vec<u32>,
    /// Corners per face.
    pub arities: Vec<u32>,
}

impl Faces {
    /// True if every face is a triangle.
    pub fn all_triangles(&self) -> bool {
        self.arities.iter().all(|&a| a == 3)
    }
}

/// Faces from an (m, k) integer array (k ≥ 3 corners each) or from a list of polygons (each
/// a sequence of vertex indices, any number of corners).
pub(crate) fn faces(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Faces> {
    let is_array = obj.cast::<PyUntypedArray>().is_ok();
    if !is_array && (obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>()) {
        // A list of polygons whose lengths may differ.
        let mut corners = Vec::new();
        let mut arities = Vec::new();
        for (face, polygon) in obj.try_iter()?.enumerate() {
            let polygon = polygon?;
            let items: Vec<Bound<'_, PyAny>> = polygon
                .try_iter()
                .map_err(|_| {
                    PyTypeError::new_err(format!(
                        "{name}: face {face} is not a sequence of vertex indices"
                    ))
                })?
                .collect::<PyResult<_>>()?;
            for (corner, item) in items.iter().enumerate() {
                let value: i128 = if item.is_instance_of::<PyBool>() {
                    return Err(PyTypeError::new_err(format!(
                        "{name}: face {face} corner {corner} is a bool, not a vertex index"
                    )));
                } else {
                    item.call_method0("__index__")
                        .and_then(|i| i.extract::<i128>())
                        .map_err(|_| {
                            PyTypeError::new_err(format!(
                                "{name}: face {face} corner {corner} is not an integer"
                            ))
                        })?
                };
                corners.push(vertex_index(value, name, face, corner)?);
            }
            arities.push(items.len() as u32);
        }
        return Ok(Faces { corners, arities });
    }
    let array = as_array(obj, None)?;
    let rows = check_2d(&array, name, None)?;
    let columns = array.shape()[1];
    let values = integers(&array, name)?;
    let mut corners = Vec::with_capacity(values.len());
    for (k, &value) in values.iter().enumerate() {
        corners.push(vertex_index(
            value,
            name,
            k / columns.max(1),
            k % columns.max(1),
        )?);
    }
    Ok(Faces {
        corners,
        arities: vec![columns as u32; rows],
    })
}

/// A one-dimensional array of patch indices (argument `name`), each below `count`.
pub(crate) fn indices(obj: &Bound<'_, PyAny>, name: &str, count: usize) -> PyResult<Vec<usize>> {
    let array = as_array(obj, None)?;
    if array.ndim() != 1 {
        return Err(PyValueError::new_err(format!(
            "{name} must be one index or a one-dimensional array of indices, got shape {}",
            shape_text(array.shape())
        )));
    }
    integers(&array, name)?
        .into_iter()
        .enumerate()
        .map(|(k, i)| {
            usize::try_from(i)
                .ok()
                .filter(|&i| i < count)
                .ok_or_else(|| {
                    pyo3::exceptions::PyIndexError::new_err(format!(
                        "{name}[{k}] = {i} is not a patch index (the surface has {count} patches)"
                    ))
                })
        })
        .collect()
}

/// A numpy array of shape `shape` holding `values` (row-major).
pub(crate) fn array<'py, T: numpy::Element + Copy>(
    py: Python<'py>,
    values: Vec<T>,
    shape: &[usize],
) -> PyResult<Bound<'py, PyAny>> {
    let flat = PyArray1::from_vec(py, values);
    Ok(flat.reshape(shape.to_vec())?.into_any())
}

/// A serialisable library value as a Python object: its JSON text (the contract's, keys in
/// the order the command line writes them; numbers in the shortest form that reads back
/// exactly) read by Python's `json.loads`.
pub(crate) fn serialised<'py>(
    py: Python<'py>,
    value: &impl serde::Serialize,
) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value)
        .map_err(|e| PyValueError::new_err(format!("cannot serialise a result: {e}")))?;
    py.import("json")?.call_method1("loads", (text,))
}

/// A Python value as a TOML value of scene key `key`: bool, int, float, str, sequences of
/// them and dicts (tables).
pub(crate) fn toml_value(obj: &Bound<'_, PyAny>, key: &str) -> PyResult<toml::Value> {
    if obj.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(obj.extract()?));
    }
    if obj.is_instance_of::<PyInt>() {
        return Ok(toml::Value::Integer(obj.extract().map_err(|_| {
            PyValueError::new_err(format!("{key}: the integer {obj} is out of range"))
        })?));
    }
    if obj.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(obj.extract()?));
    }
    if obj.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(obj.extract()?));
    }
    if let Ok(dict) = obj.cast::<PyDict>() {
        return Ok(toml::Value::Table(toml_table(dict, key)?));
    }
    // numpy scalars and arrays, tuples and lists.
    if obj.hasattr("tolist")? {
        return toml_value(&obj.call_method0("tolist")?, key);
    }
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        let items = obj
            .try_iter()?
            .enumerate()
            .map(|(i, item)| toml_value(&item?, &format!("{key}[{i}]")))
            .collect::<PyResult<Vec<_>>>()?;
        return Ok(toml::Value::Array(items));
    }
    Err(PyTypeError::new_err(format!(
        "{key}: a {} is not a scene value (bool, int, float, str, a sequence or a dict of them)",
        obj.get_type().name()?
    )))
}

/// A Python dict as a TOML table; `prefix` names the section in errors.
pub(crate) fn toml_table(dict: &Bound<'_, PyDict>, prefix: &str) -> PyResult<toml::Table> {
    let mut table = toml::Table::new();
    for (k, v) in dict.iter() {
        let key: String = k
            .extract()
            .map_err(|_| PyTypeError::new_err(format!("{prefix}: keys must be strings")))?;
        if v.is_none() {
            continue;
        }
        let name = if prefix.is_empty() {
            key.clone()
        } else {
            format!("{prefix}.{key}")
        };
        table.insert(key, toml_value(&v, &name)?);
    }
    Ok(table)
}

/// A scheme parameter's value as the text `--param name=value` would give: a str as it is,
/// a bool as `true`/`false`, a number as Python writes it (`repr`, which reads back exactly).
pub(crate) fn param_text(name: &str, obj: &Bound<'_, PyAny>) -> PyResult<String> {
    if obj.is_instance_of::<PyBool>() {
        return Ok(if obj.extract::<bool>()? {
            "true"
        } else {
            "false"
        }
        .into());
    }
    if obj.is_instance_of::<PyString>() {
        return obj.extract();
    }
    if obj.is_instance_of::<PyInt>() {
        return Ok(obj.extract::<i128>()?.to_string());
    }
    if obj.is_instance_of::<PyFloat>() {
        // The repr of a plain float (a numpy float64 is a float whose repr names its type).
        let x: f64 = obj.extract()?;
        return Ok(PyFloat::new(obj.py(), x).repr()?.to_string());
    }
    if obj.hasattr("item")? {
        // A numpy scalar.
        return param_text(name, &obj.call_method0("item")?);
    }
    Err(PyTypeError::new_err(format!(
        "parameter {name}: a {} is not a parameter value (str, int, float or bool)",
        obj.get_type().name()?
    )))
}
