//! The threads a call's parallel work runs on. Every call that may run parallel work, the
//! library's or its own, runs it on a [`Workers`]: rayon's global pool in the process that
//! first used it, and in a process forked from that one (Python's `multiprocessing` on Linux)
//! a pool of its own, since the forked process inherits the global pool without its threads.

use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use pointshade::render::options::RenderOptions;
use pointshade::render::Workers;

use crate::options::render_options;

/// The workers of a `threads=` keyword (checked as `render`'s is).
pub fn workers(threads: Option<&Bound<'_, PyAny>>) -> PyResult<Workers> {
    let options = match threads {
        Some(t) => {
            let dict = PyDict::new(t.py());
            dict.set_item("threads", t)?;
            render_options("threads", Some(&dict))?
        }
        None => RenderOptions::default(),
    };
    Workers::new(options.threads).map_err(|e| crate::value_error("threads", e))
}

/// `work` run without the GIL on the workers of a call without `threads=`.
pub fn detached<T: Send>(py: Python<'_>, work: impl FnOnce() -> T + Send) -> PyResult<T> {
    let workers = Workers::new(None).map_err(PyRuntimeError::new_err)?;
    Ok(py.detach(|| workers.install(work)))
}
