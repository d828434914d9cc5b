//! One render as every front end asks for it: a scene and the options that replace its settings.
//! [`RenderRequest::prepare`] loads the scene in the request's workers, applies the options and
//! makes the plan; [`PreparedRender::render`] renders it. The CLI writes the result to files, the
//! Python module returns it as arrays.

use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use super::options::{RenderOptions, Spelling};
use super::progress::Progress;
use super::progress::Silent;
use super::workers::Workers;
use super::{render_scene, render_scene_until, Rendered};
use crate::error::{InputError, InputResult};
use crate::film::SamplerKind;
use crate::plan::RenderPlan;
use crate::scene::shadows::ShadowOffset;
use crate::scene::{LoadOptions, Scene, SceneSource};

/// A scene to render and the options to render it with.
#[derive(Clone, Debug)]
pub struct RenderRequest {
    /// The scene.
    pub source: SceneSource,
    /// What replaces the scene's settings, and how the render runs.
    pub options: RenderOptions,
}

/// A scene loaded with its options applied and its plan made, ready to render.
pub struct PreparedRender {
    /// The scene, options applied.
    pub scene: Scene,
    /// The stages it needs.
    pub plan: RenderPlan,
    /// Where its parallel work runs (the `threads` option).
    pub workers: Workers,
    /// How long loading took (reading, parsing, building the meshes).
    pub load_time: Duration,
}

impl RenderRequest {
    /// Loads the scene and applies the options; errors name an option as `spelling` writes it.
    pub fn prepare(&self, spelling: Spelling) -> InputResult<PreparedRender> {
        let options = &self.options;
        if options.camera.is_some() && !self.source.is_gltf() {
            return Err(InputError::new(
                spelling.of("camera"),
                "chooses among a glTF file's cameras: only .gltf and .glb files have them",
            ));
        }
        let workers = Workers::new(options.threads).map_err(|e| InputError::new(spelling.of("threads"), e))?;
        let start = Instant::now();
        let load = LoadOptions { camera: options.camera };
        let mut scene = workers.install(|| self.source.load(load))?;
        options.apply(&mut scene, spelling)?;
        let plan = RenderPlan::new(&scene, &options.aovs);
        Ok(PreparedRender {
            scene,
            plan,
            workers,
            load_time: start.elapsed(),
        })
    }
}

impl PreparedRender {
    /// Renders the scene: BVH and samples. `progress` hears how far it has come; once `stop` is
    /// set no sample starts, and the render ends with the error [`super::INTERRUPTED`].
    pub fn render(&self, progress: &dyn Progress, stop: Option<&AtomicBool>) -> InputResult<Rendered> {
        self.workers
            .install(|| render_scene_until(&self.scene, &self.plan, progress, stop))
            .map_err(|e| InputError::new(&self.scene.source, e))
    }
}

/// The scene at `path` with its sampler and spp replaced (and checked) and no time budget: a
/// render of a given sample count whatever the machine, as the validation and the convergence
/// report measure them.
pub fn load_sampled(path: &Path, sampler: SamplerKind, spp: u32) -> InputResult<Scene> {
    sampled(crate::scene::load(path)?, sampler, spp)
}

/// [`load_sampled`] of a scene already loaded.
pub fn sampled(mut scene: Scene, sampler: SamplerKind, spp: u32) -> InputResult<Scene> {
    scene.film.sampler = sampler;
    scene.film.spp = spp;
    scene.film.time_budget = None;
    scene.film.validate().map_err(|e| InputError::new(&scene.source, e))?;
    Ok(scene)
}

/// `scene` rendered with shadow-ray offset `offset`, no AOVs and no progress; the render and
/// the time its plan, BVH and render took.
pub fn render_timed(scene: &Scene, offset: ShadowOffset) -> InputResult<(Rendered, Duration)> {
    let mut scene = scene.clone();
    scene.shadow_offset = offset;
    let start = Instant::now();
    let plan = RenderPlan::new(&scene, &[]);
    let rendered = render_scene(&scene, &plan, &Silent).map_err(|e| InputError::new(&scene.source, e))?;
    Ok((rendered, start.elapsed()))
}
