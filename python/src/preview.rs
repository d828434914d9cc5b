//! `_native.Preview`: a scene held for renders after material and light edits
//! (`pointshade::render::preview::Preview`), for `pointshade.Preview`.

use std::path::PathBuf;
use std::sync::Mutex;
use std::time::Duration;

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
    load_time: Duration,
}

impl Preview {
    fn held(&self) -> std::sync::MutexGuard<'_, Held> {
        // A panic cannot leave the preview half-edited: every edit checks first, then assigns.
        self.held.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
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
            load_time,
        })
    }

    /// Renders the scene as edited: the dict `render` returns (`load_seconds` and
    /// `bvh_seconds` are the preview's, made once).
    fn render<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let mut held = self.held();
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
    fn material_names(&self) -> Vec<String> {
        let held = self.held();
        held.preview.scene().materials.iter().map(|m| m.name.clone()).collect()
    }

    /// Replaces material `name` by the one a `[material.NAME]` section of keys `text` describes.
    fn set_material(&self, name: &str, text: &str) -> PyResult<()> {
        let mut held = self.held();
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
    fn set_camera(&self, text: &str) -> PyResult<()> {
        let mut held = self.held();
        let origin = held.preview.scene().origin;
        let camera = camera_from_toml(text, origin).map_err(|e| call_error("set_camera", e))?;
        held.preview.set_camera(camera).map_err(|e| call_error("set_camera", e))
    }

    /// Replaces every light by those `[[light]]` sections of keys `texts` describe.
    fn set_lights(&self, texts: Vec<String>) -> PyResult<()> {
        let mut held = self.held();
        let origin = held.preview.scene().origin;
        let lights = (texts.iter().enumerate())
            .map(|(k, text)| {
                light_from_toml(text, origin).map_err(|e| call_error("set_lights", format!("light {}: {e}", k + 1)))
            })
            .collect::<PyResult<Vec<_>>>()?;
        held.preview.set_lights(lights).map_err(|e| call_error("set_lights", e))
    }
}
