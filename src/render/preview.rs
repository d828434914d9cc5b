//! A scene held for repeated renders while its materials and lights are edited — what an
//! interactive front end does between two frames (an explorer's sliders, a notebook's loop).
//!
//! The first render traces the view and keeps its surface points and shadow verdicts
//! (`render/retained.rs`); after an edit that leaves them valid, the next render shades the kept
//! points again and traces only the shadow rays that changed. Each image is the one
//! [`super::render_scene`] gives for the edited scene, byte for byte. What would change the
//! surface points themselves (a material's normal texture or cut-out, the stages the plan keeps)
//! makes the next render trace the view again.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use super::retained::{RayCounts, RetainedFrame};
use super::tile::Context;
use super::{check_film_memory, finish, Rendered, Sampled, INTERRUPTED};
use crate::accel::alpha::AlphaMask;
use crate::accel::Bvh;
use crate::light::Light;
use crate::material::{Cutout, Material, NormalTexture};
use crate::plan::{Aov, RenderPlan};
use crate::scene::camera::{Camera, CameraSpec};
use crate::scene::Scene;
use crate::surface::primary::{surface_point, PointOptions};
use crate::surface::SurfacePoint;
use crate::texture::TextureRef;

/// A scene, its BVH and the surface points of its last render (see the module's comment).
pub struct Preview {
    scene: Scene,
    aovs: Vec<Aov>,
    plan: RenderPlan,
    bvh: Option<Bvh>,
    /// The last render's frame at each sample count rendered (the film's, and the coarser
    /// passes of a progressive preview: [`Preview::render_pass`]), oldest first.
    frames: Vec<KeptFrame>,
}

/// A render's surface points and shadow verdicts, kept for the next render at its sample count.
struct KeptFrame {
    spp: u32,
    key: SurfaceKey,
    frame: RetainedFrame,
}

/// The most frames kept at once (the film's and two coarser passes): a progressive preview
/// steps through a few sample counts, and each kept frame costs memory.
const MAX_KEPT_FRAMES: usize = 3;

/// What the surface points of a frame depend on that an edit of materials or lights can change
/// (the mesh, the film and the AOVs never change in a preview, and a camera edit drops the frame):
/// the plan's stages that make them, and what the surface stage and the tree read of each
/// material.
#[derive(Clone, Debug, PartialEq)]
struct SurfaceKey {
    points: PointOptions,
    normal_textures: bool,
    cutouts: bool,
    materials: Vec<MaterialSurface>,
}

/// What the surface stage (the normal texture) and the tree (the cut-out) read of a material.
#[derive(Clone, Copy, Debug, PartialEq)]
struct MaterialSurface {
    normal: Option<NormalTexture>,
    cutout: Option<(Cutout, Option<TextureRef>)>,
}

impl SurfaceKey {
    fn of(scene: &Scene, plan: &RenderPlan) -> Self {
        Self {
            points: plan.point_options(),
            normal_textures: plan.normal_textures,
            cutouts: plan.cutouts,
            materials: (scene.materials.iter())
                .map(|m| MaterialSurface {
                    normal: m.textures.normal,
                    cutout: m.cutout(),
                })
                .collect(),
        }
    }
}

/// Refuses a preview whose kept frame under `lights` lights ([`RetainedFrame::bytes_at_most`])
/// would need more memory than the process can have, before anything is traced: a preview that
/// is accepted does not abort on a failed allocation later.
fn check_frame_memory(scene: &Scene, lights: usize) -> Result<(), String> {
    check_frames_memory(scene, scene.film.spp, lights)
}

/// [`check_frame_memory`] for frames of `spp` samples per pixel in all.
fn check_frames_memory(scene: &Scene, spp: u32, lights: usize) -> Result<(), String> {
    let film = &scene.film;
    let region = film.region();
    let samples = region.width() as u64 * region.height() as u64 * spp as u64;
    let need = RetainedFrame::bytes_at_most(samples, lights);
    match crate::film::memory::available_bytes() {
        Some((available, source)) if need > available => Err(format!(
            "a preview of a {}×{} film at {} spp keeps up to {:.2} GB of surface points and shadow \
             verdicts, more than the {:.2} GB {source}: make the film smaller or take fewer samples",
            region.width(),
            region.height(),
            spp,
            need as f64 / 1e9,
            available as f64 / 1e9
        )),
        _ => Ok(()),
    }
}

impl Preview {
    /// Holds `scene` for renders with the AOVs `aovs`, and builds its BVH (when it has
    /// geometry). The film must take a fixed number of samples per pixel (the `grid`, `sobol` or
    /// `independent` sampler, no time budget): an adaptive sampler's samples depend on the
    /// shading they follow, so there would be nothing to keep.
    pub fn new(scene: Scene, aovs: &[Aov]) -> Result<Self, String> {
        let film = &scene.film;
        if film.sampler.fixed_sequence().is_none() || film.time_budget.is_some() {
            // No file name: the caller's error names the scene (as render errors do).
            return Err(format!(
                "a preview renders a fixed number of samples per pixel; the film's {} sampler{} does not",
                film.sampler.name(),
                if film.time_budget.is_some() {
                    " with a time budget"
                } else {
                    ""
                }
            ));
        }
        let plan = RenderPlan::new(&scene, aovs);
        check_film_memory(film.region(), &plan)?;
        check_frame_memory(&scene, scene.lights.len())?;
        let bvh = plan.trace_rays.then(|| Bvh::for_scene(&scene));
        Ok(Self {
            scene,
            aovs: aovs.to_vec(),
            plan,
            bvh,
            frames: Vec::new(),
        })
    }

    /// The scene as edited so far.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The surface point one camera ray through the centre of pixel (`x`, `y`) of the film
    /// meets (its interpolated shading normal, before any normal texture, not yet turned to the
    /// viewer), or
    /// `None` for background and pixels outside the film: what an explorer shows of a clicked
    /// pixel. (A pixel's samples may meet other points near an edge.)
    pub fn surface_at(&self, x: u32, y: u32) -> Option<SurfacePoint> {
        let (w, h) = (self.scene.film.width, self.scene.film.height);
        if x >= w || y >= h {
            return None;
        }
        let camera = Camera::new(self.scene.camera, w, h).ok()?;
        let ray = camera.ray((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
        let hit = self.bvh.as_ref()?.intersect(ray.origin, ray.direction, ray.t_max)?;
        Some(surface_point(
            &self.scene.mesh,
            &hit,
            ray.direction,
            self.plan.point_options(),
        ))
    }

    /// Time the BVH took to build (zero without geometry).
    pub fn bvh_time(&self) -> Duration {
        self.bvh.as_ref().map_or(Duration::ZERO, |b| b.build_time)
    }

    /// Replaces the scene's materials (as many as it has: the mesh refers to them by index).
    /// Each is checked as a scene file's would be, and its textures must be the scene's; on an
    /// error nothing changes.
    pub fn set_materials(&mut self, materials: Vec<Material>) -> Result<(), String> {
        let count = self.scene.materials.len();
        if materials.len() != count {
            return Err(format!("the scene has {count} material(s), got {}", materials.len()));
        }
        let images = self.scene.textures.len();
        for m in &materials {
            m.validate().map_err(|e| format!("material '{}': {e}", m.name))?;
            let mut textures = m.textures;
            let outside = textures.refs_mut().map(|r| r.image).find(|&i| i as usize >= images);
            if let Some(image) = outside {
                return Err(format!(
                    "material '{}': texture {image} is not one of the scene's {images} image(s)",
                    m.name
                ));
            }
        }
        let cutouts_before: Vec<_> = self.scene.materials.iter().map(Material::cutout).collect();
        self.scene.materials = materials;
        // New cut-outs: the tree's mask follows (the kept frame, found with the old ones, no
        // longer matches its key and is traced again).
        if self.scene.materials.iter().map(Material::cutout).ne(cutouts_before) {
            if let Some(bvh) = &mut self.bvh {
                bvh.replace_alpha_mask(AlphaMask::new(
                    &self.scene.mesh,
                    &self.scene.materials,
                    &self.scene.textures,
                ));
            }
        }
        self.plan = RenderPlan::new(&self.scene, &self.aovs);
        Ok(())
    }

    /// Replaces the scene's lights. Each is checked ([`Light::validate`], and positions within
    /// the range the scene's coordinates allow); on an error nothing changes.
    pub fn set_lights(&mut self, lights: Vec<Light>) -> Result<(), String> {
        for (k, light) in lights.iter().enumerate() {
            light.validate().map_err(|e| format!("light {}: {e}", k + 1))?;
        }
        check_frame_memory(&self.scene, lights.len())?;
        let before = std::mem::replace(&mut self.scene.lights, lights);
        let default_before = std::mem::replace(&mut self.scene.default_lights, false);
        if let Err(e) = crate::scene::extent::check_lights(&self.scene) {
            self.scene.lights = before;
            self.scene.default_lights = default_before;
            return Err(e);
        }
        self.plan = RenderPlan::new(&self.scene, &self.aovs);
        Ok(())
    }

    /// Replaces the camera (a new view: the next render traces it, keeping the BVH). Checked as
    /// a scene file's camera is, and its position and target must lie within the range the
    /// scene's coordinates allow; on an error nothing changes.
    pub fn set_camera(&mut self, camera: CameraSpec) -> Result<(), String> {
        Camera::new(camera, self.scene.film.width, self.scene.film.height)?;
        let before = std::mem::replace(&mut self.scene.camera, camera);
        if let Err(e) = crate::scene::extent::check_camera(&self.scene) {
            self.scene.camera = before;
            return Err(e);
        }
        self.frames.clear();
        Ok(())
    }

    /// Renders the scene as edited: shades the last render's surface points again where they
    /// are still valid (the statistics then count no camera rays, and shadow rays only where
    /// they changed: [`super::RenderStats::shadow_rays_reused`]), else traces the view.
    pub fn render(&mut self) -> Result<Rendered, String> {
        self.render_until(None)
    }

    /// [`Self::render`], ended early with the error [`INTERRUPTED`] once `stop` is set (an
    /// edit that makes the image in flight moot). The kept frame is then dropped.
    pub fn render_until(&mut self, stop: Option<&AtomicBool>) -> Result<Rendered, String> {
        self.render_pass(self.scene.film.spp, stop)
    }

    /// [`Self::render_until`] at `spp` samples per pixel instead of the film's: one pass of a
    /// progressive preview, which shows a coarse image at once and the film's when nothing has
    /// changed since. The image is the one [`super::render_scene`] gives for the scene with its
    /// film at `spp`; each sample count keeps its own frame, so the next edit re-shades every
    /// pass. `spp` must be at most the film's and one the film's sampler takes.
    pub fn render_pass(&mut self, spp: u32, stop: Option<&AtomicBool>) -> Result<Rendered, String> {
        let film_spp = self.scene.film.spp;
        if spp > film_spp {
            return Err(format!(
                "a preview pass takes at most the film's {film_spp} samples per pixel, got {spp}"
            ));
        }
        let mut film = self.scene.film.clone();
        film.spp = spp;
        film.validate()?;
        let kept_spp: u32 = self.frames.iter().filter(|f| f.spp != spp).map(|f| f.spp).sum();
        check_frames_memory(&self.scene, kept_spp.saturating_add(spp), self.scene.lights.len())?;
        self.scene.film.spp = spp;
        let rendered = self.render_at_film_spp(stop);
        self.scene.film.spp = film_spp;
        rendered
    }

    fn render_at_film_spp(&mut self, stop: Option<&AtomicBool>) -> Result<Rendered, String> {
        let start = Instant::now();
        let spp = self.scene.film.spp;
        let key = SurfaceKey::of(&self.scene, &self.plan);
        let region = self.scene.film.region();
        let ctx = Context::new(&self.scene, &self.plan, self.bvh.as_ref(), stop)?;
        let counts = RayCounts::default();
        let kept = self
            .frames
            .iter()
            .position(|f| f.spp == spp)
            .map(|k| self.frames.remove(k));
        let (frame, sums) = match kept {
            Some(mut kept) if kept.key == key => {
                let sums = kept.frame.shade(&ctx, &counts);
                (kept.frame, sums)
            }
            _ => {
                let sequence = self
                    .scene
                    .film
                    .sampler
                    .fixed_sequence()
                    .expect("checked by Preview::new");
                RetainedFrame::trace(&ctx, sequence, region, &counts)
            }
        };
        if ctx.stopped() {
            return Err(INTERRUPTED.into());
        }
        if self.frames.len() == MAX_KEPT_FRAMES {
            self.frames.remove(0);
        }
        self.frames.push(KeptFrame { spp, key, frame });
        let sampled = Sampled {
            sums,
            counts: None,
            spp,
            threshold: None,
        };
        let mut rendered = finish(&ctx, start, region, sampled)?;
        let (asked, traced) = (
            counts.asked.load(Ordering::Relaxed),
            counts.traced.load(Ordering::Relaxed),
        );
        rendered.stats.shadow_rays = traced;
        rendered.stats.shadow_rays_reused = asked - traced;
        rendered.stats.shadow_time = Some(Duration::from_nanos(counts.trace_ns.load(Ordering::Relaxed)));
        Ok(rendered)
    }
}

#[cfg(test)]
mod tests;
