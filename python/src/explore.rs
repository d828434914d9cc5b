//! `_native.ExploreServer`: `pointshade explore`'s server in a thread of this process
//! (`pointshade::explore`), for `pointshade.explore`.

use std::path::PathBuf;
use std::sync::Mutex;

use pyo3::prelude::*;

use pointshade::explore::server::Server;
use pointshade::explore::Explorer;

use crate::workers::detached;
use crate::{py_err, value_error};

/// The explorer's server, running until `stop`.
#[pyclass(module = "pointshade._native")]
pub struct ExploreServer {
    server: Mutex<Option<Server>>,
    url: String,
}

#[pymethods]
impl ExploreServer {
    /// Opens `path` (a normal image, a scene file, a bare mesh or a glTF file; none: the
    /// assignment's setting on a baked normal image) and serves it on 127.0.0.1:`port` (0: a
    /// free port); its Mitsuba comparison uses the validation folder `mitsuba_dir` (default:
    /// `validation` of the working folder).
    #[new]
    #[pyo3(signature = (path=None, port=0, mitsuba_dir=None))]
    fn new(py: Python<'_>, path: Option<PathBuf>, port: u32, mitsuba_dir: Option<PathBuf>) -> PyResult<Self> {
        let port =
            u16::try_from(port).map_err(|_| value_error("port", format!("must be in [0, 65535], got {port}")))?;
        let mut explorer = detached(py, || Explorer::open(path.as_deref()))?.map_err(py_err)?;
        if let Some(dir) = mitsuba_dir {
            explorer.set_mitsuba_dir(dir);
        }
        let server = Server::start(explorer, port).map_err(|e| value_error("port", e))?;
        let url = server.url();
        Ok(Self {
            server: Mutex::new(Some(server)),
            url,
        })
    }

    /// The page's address.
    #[getter]
    fn url(&self) -> String {
        self.url.clone()
    }

    /// Whether it still serves.
    #[getter]
    fn running(&self) -> bool {
        self.server.lock().map(|s| s.is_some()).unwrap_or(false)
    }

    /// Stops the server (requests being answered finish first); stopping twice does nothing.
    fn stop(&self, py: Python<'_>) {
        let server = self.server.lock().ok().and_then(|mut s| s.take());
        if let Some(server) = server {
            py.detach(|| server.stop());
        }
    }
}
