//! `_native.Preview`: a scene held for renders after material and light edits
//! (`pointshade::render::preview::Preview`), for `pointshade.Preview`.

use std::path::PathBuf;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Mutex, MutexGuard, TryLockError};
use std::time::{Duration, Instant};

use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use pointshade::error::InputError as LibError;
use pointshade::render::options::Spelling;
use pointshade::render::preview::Preview as ScenePreview;
use pointshade::render::Workers;
use pointshade::scene::file::{camera_from_toml, light_from_toml, material_from_toml, MaterialDefaults};

use crate::interrupt::run_interruptible;
use crate::{py_err, render_request, rendered_dict, InputError};

/// The held scene and the workers its renders run on.
struct Held {
    preview: ScenePreview,
    workers: Workers,
}

/// A scene held for renders after material and light edits.
#[pyclass(module = "pointshade._native")]
pub struct Preview {
    held: Mutex<Held>,
    /// The process whose thread took `held` last (its creator's before that).
    holder: AtomicU32,
    load_time: Duration,
}

/// How long another process's id may stay the holder's while `held` is taken before it is a
/// fork's leftover: a thread of this process stores its id just after it takes the lock.
const FOREIGN_HOLDER_GRACE: Duration = Duration::from_millis(100);

impl Preview {
    /// The held scene, once no other call on this preview uses it.
    ///
    /// The wait is without the GIL: a render holds the lock while it takes the GIL every
    /// 50 ms (to see Ctrl-C), so a second thread waiting with the GIL would wait for ever, and the
    /// render with it. In a process forked while a thread of its parent held the lock, no thread
    /// will release it; that is an error, not a wait.
    fn held(&self, py: Python<'_>) -> PyResult<MutexGuard<'_, Held>> {
        let process = std::process::id();
        let mut foreign_since = None;
        loop {
            let guard = match self.held.try_lock() {
                Ok(guard) => Some(guard),
                // A panic cannot leave the preview half-edited: every edit checks first, then
                // assigns.
                Err(TryLockError::Poisoned(poisoned)) => Some(poisoned.into_inner()),
                Err(TryLockError::WouldBlock) => None,
            };
            if let Some(guard) = guard {
                self.holder.store(process, Ordering::Relaxed);
                return Ok(guard);
            }
            if self.holder.load(Ordering::Relaxed) == process {
                // Taken here and released later: wait for that, then take it with the GIL.
                py.detach(|| drop(self.held.lock()));
            } else if foreign_since.get_or_insert_with(Instant::now).elapsed() < FOREIGN_HOLDER_GRACE {
                py.detach(|| std::thread::sleep(Duration::from_millis(1)));
            } else {
                return Err(PyRuntimeError::new_err(
                    "this Preview was in use by another thread when the process was forked, and that \
                     call did not come along: make a new Preview in this process",
                ));
            }
        }
    }
}

/// A `pointshade.InputError` about the call `call`.
fn call_error(call: &str, problem: impl std::fmt::Display) -> PyErr {
    InputError::new_err(format!("{call}: {problem}"))
}

#[pymethods]
impl Preview {
    /// Loads the scene as `render` does (the same arguments and options) and builds its BVH.
    #[new]
    #[pyo3(signature = (path, *, text=None, dir=None, meshes=None, confine=None, options=None))]
    fn new(
        py: Python<'_>,
        path: PathBuf,
        text: Option<String>,
        dir: Option<PathBuf>,
        meshes: Option<Bound<'_, PyDict>>,
        confine: Option<PathBuf>,
        options: Option<Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let (confinement, request) = render_request("Preview", path, text, dir, meshes, confine, options)?;
        let held = py.detach(|| -> Result<(Held, Duration), LibError> {
            let prepared = confinement.run(|| request.prepare(Spelling::Keyword))?;
            let load_time = prepared.load_time;
            let source = prepared.scene.source.clone();
            let aovs = prepared.plan.aovs.clone();
            let workers = prepared.workers;
            let preview = workers
                .install(|| ScenePreview::new(prepared.scene, &aovs))
                .map_err(|e| LibError::new(&source, e))?;
            Ok((Held { preview, workers }, load_time))
        });
        let (held, load_time) = held.map_err(py_err)?;
        Ok(Self {
            held: Mutex::new(held),
            holder: AtomicU32::new(std::process::id()),
            load_time,
        })
    }

    /// Renders the scene as edited: the dict `render` returns (`load_seconds` and
    /// `bvh_seconds` are the preview's, made once).
    fn render<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let mut held = self.held(py)?;
        let held = &mut *held;
        // A preview made before a fork (`multiprocessing` on Linux) holds its parent's workers.
        held.workers.move_to_this_process().map_err(PyRuntimeError::new_err)?;
        let rendered = run_interruptible(py, None, |stop, _| {
            let (preview, workers) = (&mut held.preview, &held.workers);
            workers.install(|| preview.render_until(Some(stop)))
        })?;
        let mut rendered = rendered.map_err(|e| py_err(LibError::new(&held.preview.scene().source, e)))?;
        // The BVH was built with the preview, once: every render's stats name that build.
        rendered.stats.bvh_time = held.preview.bvh_time();
        rendered_dict(py, rendered, held.preview.scene(), self.load_time)
    }

    /// The scene's material names, in the order its meshes refer to them.
    fn material_names(&self, py: Python<'_>) -> PyResult<Vec<String>> {
        let held = self.held(py)?;
        Ok(held.preview.scene().materials.iter().map(|m| m.name.clone()).collect())
    }

    /// Replaces material `name` by the one a `[material.NAME]` section of keys `text` describes.
    fn set_material(&self, py: Python<'_>, name: &str, text: &str) -> PyResult<()> {
        let mut held = self.held(py)?;
        let materials = &held.preview.scene().materials;
        let Some(index) = materials.iter().position(|m| m.name == name) else {
            let names: Vec<_> = materials.iter().map(|m| format!("'{}'", m.name)).collect();
            return Err(call_error(
                "set_material",
                format!("the scene has no material '{name}' (it has {})", names.join(", ")),
            ));
        };
        let material =
            material_from_toml(name, text, &MaterialDefaults::SCENE).map_err(|e| call_error("set_material", e))?;
        let mut materials = materials.clone();
        materials[index] = material;
        held.preview
            .set_materials(materials)
            .map_err(|e| call_error("set_material", e))
    }

    /// Replaces the camera by the one a `[camera]` section of keys `text` describes.
    fn set_camera(&self, py: Python<'_>, text: &str) -> PyResult<()> {
        let mut held = self.held(py)?;
        let origin = held.preview.scene().origin;
        let camera = camera_from_toml(text, origin).map_err(|e| call_error("set_camera", e))?;
        held.preview.set_camera(camera).map_err(|e| call_error("set_camera", e))
    }

    /// Replaces every light by those `[[light]]` sections of keys `texts` describe.
    fn set_lights(&self, py: Python<'_>, texts: Vec<String>) -> PyResult<()> {
        let mut held = self.held(py)?;
        let origin = held.preview.scene().origin;
        let lights = (texts.iter().enumerate())
            .map(|(k, text)| {
                light_from_toml(text, origin).map_err(|e| call_error("set_lights", format!("light {}: {e}", k + 1)))
            })
            .collect::<PyResult<Vec<_>>>()?;
        held.preview.set_lights(lights).map_err(|e| call_error("set_lights", e))
    }
}
