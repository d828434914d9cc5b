//! Python values ↔ TOML values, for the `Scene` builder: it keeps a scene as the dict a scene
//! file parses to, and the library reads the TOML text of that dict, so a scene built in Python
//! goes through exactly the checks (and messages) a scene file does.

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// A dict of str keys as a TOML table.
pub fn table_of(dict: &Bound<'_, PyDict>) -> PyResult<toml::Table> {
    let mut table = toml::Table::new();
    for (key, value) in dict.iter() {
        let key: String = key
            .extract()
            .map_err(|_| PyTypeError::new_err(format!("TOML keys are strings, got {key}")))?;
        if value.is_none() {
            continue; // an unset key
        }
        let v = value_of(&value).map_err(|e| PyTypeError::new_err(format!("{key}: {e}")))?;
        table.insert(key, v);
    }
    Ok(table)
}

/// A Python value as a TOML value: bool, int, finite float, str, list or tuple, dict, or
/// anything with `tolist()` (numpy arrays and scalars).
fn value_of(value: &Bound<'_, PyAny>) -> PyResult<toml::Value> {
    if value.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(value.extract()?));
    }
    if value.is_instance_of::<PyInt>() {
        return Ok(toml::Value::Integer(value.extract()?));
    }
    if value.is_instance_of::<PyFloat>() {
        let v: f64 = value.extract()?;
        if !v.is_finite() {
            return Err(PyValueError::new_err(format!("{v} is not a finite number")));
        }
        return Ok(toml::Value::Float(v));
    }
    if value.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(value.extract()?));
    }
    if let Ok(dict) = value.cast::<PyDict>() {
        return Ok(toml::Value::Table(table_of(dict)?));
    }
    if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        let items: PyResult<Vec<toml::Value>> = value.try_iter()?.map(|item| value_of(&item?)).collect();
        return Ok(toml::Value::Array(items?));
    }
    if value.hasattr("tolist")? {
        return value_of(&value.call_method0("tolist")?);
    }
    Err(PyTypeError::new_err(format!(
        "cannot write a {} in a scene file",
        value.get_type().name()?
    )))
}

/// A TOML value as a Python value (datetimes as their text).
pub fn py_of<'py>(py: Python<'py>, value: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match value {
        toml::Value::String(s) => PyString::new(py, s).into_any(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        toml::Value::Float(f) => PyFloat::new(py, *f).into_any(),
        toml::Value::Boolean(b) => PyBool::new(py, *b).to_owned().into_any(),
        toml::Value::Datetime(d) => PyString::new(py, &d.to_string()).into_any(),
        toml::Value::Array(items) => {
            let list = PyList::empty(py);
            for item in items {
                list.append(py_of(py, item)?)?;
            }
            list.into_any()
        }
        toml::Value::Table(table) => {
            let dict = PyDict::new(py);
            for (k, v) in table {
                dict.set_item(k, py_of(py, v)?)?;
            }
            dict.into_any()
        }
    })
}
