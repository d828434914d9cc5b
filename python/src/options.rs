//! Python keywords → the library's render options: each value converted to an
//! [`OptionValue`] of the kind its row of `RENDER_OPTIONS` takes (a `TypeError` naming the
//! keyword when it is not of that kind), then read and checked by the library
//! ([`RenderOptions::set`]: a `pointshade.InputError`, a `ValueError`, naming the keyword).

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

use pointshade::render::options::{render_option, OptionValue, RenderOptions, Spelling, Values, RENDER_OPTIONS};

use crate::py_err;

/// A Python int as a whole number; one beyond i128 keeps its digits as text, which the
/// library refuses with the range it takes.
fn whole(value: &Bound<'_, PyAny>) -> PyResult<OptionValue> {
    Ok(match value.extract::<i128>() {
        Ok(n) => OptionValue::Whole(n),
        Err(_) => OptionValue::Text(value.str()?.to_string()),
    })
}

fn is_int(value: &Bound<'_, PyAny>) -> bool {
    value.is_instance_of::<PyInt>() && !value.is_instance_of::<PyBool>()
}

/// The items of a list or tuple.
fn sequence<'py>(v: &Bound<'py, PyAny>) -> Option<Vec<Bound<'py, PyAny>>> {
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        v.try_iter().ok()?.collect::<PyResult<Vec<_>>>().ok()
    } else {
        None
    }
}

/// `value` as the option `name` takes it, or a `TypeError` saying what it takes.
fn convert(name: &str, takes: Values, value: &Bound<'_, PyAny>) -> PyResult<OptionValue> {
    let type_name = value.get_type().name().map_or_else(|_| "?".into(), |n| n.to_string());
    let wrong = |expected: &str| {
        let shown = value.repr().map_or_else(|_| "?".into(), |r| r.to_string());
        PyTypeError::new_err(format!("{name}: expected {expected}, got {type_name} {shown}"))
    };
    let number = |v: &Bound<'_, PyAny>| -> Option<PyResult<OptionValue>> {
        if is_int(v) {
            Some(whole(v))
        } else if v.is_instance_of::<PyFloat>() {
            Some(v.extract::<f64>().map(OptionValue::Number))
        } else {
            None
        }
    };
    match takes {
        Values::Whole { .. } if is_int(value) => whole(value),
        Values::Whole { .. } => Err(wrong("an int")),
        Values::Number { .. } => number(value).unwrap_or_else(|| Err(wrong("a number"))),
        Values::Name(_) if value.is_instance_of::<PyString>() => Ok(OptionValue::Text(value.extract()?)),
        Values::Name(_) => Err(wrong("a str")),
        Values::Names(_) if value.is_instance_of::<PyString>() => Ok(OptionValue::Text(value.extract()?)),
        Values::Names(_) => {
            let items = sequence(value).ok_or_else(|| wrong("a str or a list of str"))?;
            items
                .iter()
                .map(|i| match i.is_instance_of::<PyString>() {
                    true => Ok(OptionValue::Text(i.extract()?)),
                    false => Err(wrong("a str or a list of str")),
                })
                .collect::<PyResult<_>>()
                .map(OptionValue::List)
        }
        Values::Numbers { whole: is_whole, .. } => {
            let expected = match is_whole {
                true => "a sequence of ints",
                false => "a sequence of numbers",
            };
            let items = sequence(value).ok_or_else(|| wrong(expected))?;
            items
                .iter()
                .map(|i| match number(i) {
                    Some(Ok(OptionValue::Number(_))) if is_whole => Err(wrong(expected)),
                    Some(v) => v,
                    None => Err(wrong(expected)),
                })
                .collect::<PyResult<_>>()
                .map(OptionValue::List)
        }
    }
}

/// The render options of the keywords in `options` (`None` values left out); an unknown
/// keyword is a `TypeError`, as Python reports one.
pub fn render_options(function: &str, options: Option<&Bound<'_, PyDict>>) -> PyResult<RenderOptions> {
    let mut out = RenderOptions::default();
    let Some(options) = options else {
        return Ok(out);
    };
    for (key, value) in options.iter() {
        let name: String = key.extract()?;
        let option = render_option(&name)
            .ok_or_else(|| PyTypeError::new_err(format!("{function}() got an unexpected keyword argument '{name}'")))?;
        if value.is_none() {
            continue;
        }
        let value = convert(&name, option.values, &value)?;
        out.set(&name, &value, Spelling::Keyword).map_err(py_err)?;
    }
    Ok(out)
}

/// `(name, placeholder, help)` of every render option, in the table's order (for the docstring
/// of `pointshade.render` and a test that the stub lists every keyword).
#[pyfunction]
pub fn render_option_table() -> Vec<(&'static str, &'static str, &'static str)> {
    RENDER_OPTIONS.iter().map(|o| (o.name, o.placeholder, o.help)).collect()
}
