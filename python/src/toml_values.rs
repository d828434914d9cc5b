//! Python values ↔ TOML values, for the `Scene` builder: it keeps a scene as the dict a scene
//! file parses to, and the library reads the TOML text of that dict, so a scene built in Python
//! goes through exactly the checks (and messages) a scene file does.

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// A dict of str keys as a TOML table. An error names the key path of the value at fault
/// (`light[0].intensity`) after `context` (the call that gave it): a `ValueError` for a value
/// no scene file can hold (NaN, infinity), a `TypeError` for a type it cannot.
pub fn table_of(dict: &Bound<'_, PyDict>, context: &str) -> PyResult<toml::Table> {
    table(dict, "").map_err(|u| u.into_py_err(context))
}

/// Why a value cannot be written, and where.
struct Unwritable {
    path: String,
    problem: String,
    /// The value's type is wrong (else the value itself).
    wrong_type: bool,
}

impl Unwritable {
    fn into_py_err(self, context: &str) -> PyErr {
        let message = [context, &self.path, &self.problem]
            .into_iter()
            .filter(|s| !s.is_empty())
            .collect::<Vec<_>>()
            .join(": ");
        match self.wrong_type {
            true => PyTypeError::new_err(message),
            false => PyValueError::new_err(message),
        }
    }
}

fn table(dict: &Bound<'_, PyDict>, path: &str) -> Result<toml::Table, Unwritable> {
    let mut table = toml::Table::new();
    for (key, value) in dict.iter() {
        let Ok(key) = key.extract::<String>() else {
            return Err(Unwritable {
                path: path.to_string(),
                problem: format!("keys are strings, got {key}"),
                wrong_type: true,
            });
        };
        if value.is_none() {
            continue; // an unset key
        }
        let child = match path.is_empty() {
            true => key.clone(),
            false => format!("{path}.{key}"),
        };
        table.insert(key, value_of(&value, &child)?);
    }
    Ok(table)
}

/// A Python value as a TOML value: bool, int, finite float, str, list or tuple, dict, or
/// anything with `tolist()` (numpy arrays and scalars).
fn value_of(value: &Bound<'_, PyAny>, path: &str) -> Result<toml::Value, Unwritable> {
    let fail = |problem: String, wrong_type: bool| Unwritable {
        path: path.to_string(),
        problem,
        wrong_type,
    };
    let python = |e: PyErr| fail(e.to_string(), true);
    if value.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(value.extract().map_err(python)?));
    }
    if value.is_instance_of::<PyInt>() {
        let i: i64 = value
            .extract()
            .map_err(|_| fail(format!("{value} does not fit a 64-bit integer"), false))?;
        return Ok(toml::Value::Integer(i));
    }
    if value.is_instance_of::<PyFloat>() {
        let v: f64 = value.extract().map_err(python)?;
        if !v.is_finite() {
            return Err(fail(format!("{v} is not a finite number"), false));
        }
        return Ok(toml::Value::Float(v));
    }
    if value.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(value.extract().map_err(python)?));
    }
    if let Ok(dict) = value.cast::<PyDict>() {
        return Ok(toml::Value::Table(table(dict, path)?));
    }
    if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        let mut items = Vec::new();
        for (i, item) in value.try_iter().map_err(python)?.enumerate() {
            items.push(value_of(&item.map_err(python)?, &format!("{path}[{i}]"))?);
        }
        return Ok(toml::Value::Array(items));
    }
    if value.hasattr("tolist").unwrap_or(false) {
        return value_of(&value.call_method0("tolist").map_err(python)?, path);
    }
    let type_name = value.get_type().name().map_or_else(|_| "?".into(), |n| n.to_string());
    Err(fail(format!("cannot write a {type_name} in a scene file"), true))
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
