//! The render driver: runs the planned stages over image tiles in parallel.
//!
//! Each 16×16 tile runs the pipeline in two passes, each timed: *surface points* (sample
//! positions → camera rays → BVH hits → [`SurfacePoint`]s) and *shading* (the shader on every
//! point, accumulated into the tile's pixels with a box filter). Every pixel is a pure function of
//! the scene and its coordinates, so the image does not depend on the thread count.

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use crate::accel::{Bvh, BvhPreset};
use crate::film::{sampler::pixel_offsets, Image};
use crate::plan::{Aov, RenderPlan};
use crate::scene::Scene;
use crate::shading::shader::Shader;
use crate::surface::camera::Camera;
use crate::surface::normal_texture::apply_normal_texture;
use crate::surface::primary::surface_point;
use crate::surface::SurfacePoint;

const TILE: u32 = 16;

/// Counters and per-stage times of one render.
#[derive(Clone, Debug, Default)]
pub struct RenderStats {
    /// Camera rays traced.
    pub primary_rays: u64,
    /// Shadow rays traced.
    pub shadow_rays: u64,
    /// Time summed over threads spent making surface points (camera rays and BVH traversal).
    pub surface_time: Duration,
    /// Time summed over threads spent shading (BRDFs, lights, shadow rays).
    pub shading_time: Duration,
    /// Wall-clock time of the whole render stage.
    pub wall_time: Duration,
    /// Time spent building the BVH (zero when the plan needs none).
    pub bvh_time: Duration,
}

/// The result of a render: the image, the requested AOVs and the statistics.
pub struct Rendered {
    /// Linear radiance.
    pub image: Image,
    /// AOV images, in the order of `RenderPlan::aovs`.
    pub aovs: Vec<(Aov, Image)>,
    /// Counters and times.
    pub stats: RenderStats,
}

/// A surface point with what the AOVs need that shading does not.
struct Sample {
    pixel: u32,
    point: SurfacePoint,
    depth: f32,
}

/// The pipeline after loading: builds the BVH the plan asks for (default preset) and renders.
pub fn render_scene(scene: &Scene, plan: &RenderPlan, on_tile: &(dyn Fn(u64) + Sync)) -> Result<Rendered, String> {
    let bvh = plan.trace_rays.then(|| Bvh::build(&scene.mesh, BvhPreset::DEFAULT));
    let mut rendered = render(scene, plan, bvh.as_ref(), on_tile)?;
    rendered.stats.bvh_time = bvh.map_or(Duration::ZERO, |b| b.build_time);
    Ok(rendered)
}

/// Renders `scene` following `plan`. `bvh` must be present when `plan.trace_rays` is set.
/// `on_tile` is called after each finished tile with the number of tiles (for progress bars).
pub fn render(
    scene: &Scene,
    plan: &RenderPlan,
    bvh: Option<&Bvh>,
    on_tile: &(dyn Fn(u64) + Sync),
) -> Result<Rendered, String> {
    let start = Instant::now();
    let film = &scene.film;
    let camera = Camera::new(scene.camera, film.width, film.height)?;
    let (w, h) = (film.width, film.height);
    let tiles_x = w.div_ceil(TILE);
    let tiles: Vec<(u32, u32)> = (0..h.div_ceil(TILE))
        .flat_map(|ty| (0..tiles_x).map(move |tx| (tx, ty)))
        .collect();

    let shadow_rays = AtomicU64::new(0);
    let surface_ns = AtomicU64::new(0);
    let shading_ns = AtomicU64::new(0);
    let done = AtomicU64::new(0);
    let shader = Shader {
        materials: &scene.materials,
        lights: &scene.lights,
        occluder: if plan.shadows { bvh } else { None },
        scene_unit: bvh.map_or(1.0, Bvh::scene_unit),
        convention: plan.convention,
        textures: plan.textures.then_some(scene.textures.as_slice()),
        emission: plan.emission,
        shadow_offset: scene.shadow_offset,
    };

    let tile_results: Vec<TileResult> = tiles
        .par_iter()
        .map(|&(tx, ty)| {
            let x0 = tx * TILE;
            let y0 = ty * TILE;
            let (tw, th) = (TILE.min(w - x0), TILE.min(h - y0));
            let mut result = TileResult::new(tw * th, plan.aovs.len());
            let mut offsets = vec![Vec2::ZERO; film.spp as usize];
            let mut samples = Vec::new();

            // Stage: surface points.
            let t0 = Instant::now();
            if plan.trace_rays {
                let bvh = bvh.expect("plan.trace_rays implies a BVH");
                for py in 0..th {
                    for px in 0..tw {
                        let (x, y) = (x0 + px, y0 + py);
                        pixel_offsets(film.sampler, film.seed, x, y, &mut offsets);
                        for o in &offsets {
                            let ray = camera.ray((x as f32 + o.x) / w as f32, (y as f32 + o.y) / h as f32);
                            if let Some(hit) = bvh.intersect(ray.origin, ray.direction, ray.t_max) {
                                let mut point = surface_point(&scene.mesh, &hit, ray.direction, plan.uvs);
                                if plan.normal_textures {
                                    apply_normal_texture(
                                        &mut point,
                                        &scene.mesh,
                                        &hit,
                                        &scene.materials,
                                        &scene.textures,
                                    );
                                }
                                let depth = hit.t + (ray.origin - scene.camera.position).length();
                                samples.push(Sample {
                                    pixel: py * tw + px,
                                    point,
                                    depth,
                                });
                            }
                        }
                    }
                }
            }
            let t1 = Instant::now();

            // Stage: shading.
            let mut rays = 0u64;
            for s in &samples {
                result.radiance[s.pixel as usize] += shader.shade(&s.point, &mut rays);
            }
            for (k, aov) in plan.aovs.iter().enumerate() {
                for s in &samples {
                    result.aovs[k][s.pixel as usize] += aov_value(*aov, scene, s);
                }
            }
            let t2 = Instant::now();

            surface_ns.fetch_add((t1 - t0).as_nanos() as u64, Ordering::Relaxed);
            shading_ns.fetch_add((t2 - t1).as_nanos() as u64, Ordering::Relaxed);
            shadow_rays.fetch_add(rays, Ordering::Relaxed);
            on_tile(done.fetch_add(1, Ordering::Relaxed) + 1);
            result
        })
        .collect();

    // Film: box filter = mean of the pixel's samples (misses count as black).
    let inv_spp = 1.0 / film.spp as f32;
    let mut image = Image::new(w, h);
    let mut aovs: Vec<(Aov, Image)> = plan.aovs.iter().map(|&a| (a, Image::new(w, h))).collect();
    for (&(tx, ty), r) in tiles.iter().zip(&tile_results) {
        let (x0, y0) = (tx * TILE, ty * TILE);
        let tw = TILE.min(w - x0);
        for (i, &v) in r.radiance.iter().enumerate() {
            let (x, y) = (x0 + i as u32 % tw, y0 + i as u32 / tw);
            let idx = (y * w + x) as usize;
            image.pixels[idx] = v * inv_spp;
            for (k, (_, img)) in aovs.iter_mut().enumerate() {
                img.pixels[idx] = r.aovs[k][i] * inv_spp;
            }
        }
    }
    let stats = RenderStats {
        primary_rays: plan.primary_rays,
        shadow_rays: shadow_rays.into_inner(),
        surface_time: Duration::from_nanos(surface_ns.into_inner()),
        shading_time: Duration::from_nanos(shading_ns.into_inner()),
        wall_time: start.elapsed(),
        bvh_time: Duration::ZERO,
    };
    Ok(Rendered { image, aovs, stats })
}

struct TileResult {
    radiance: Vec<Vec3>,
    aovs: Vec<Vec<Vec3>>,
}

impl TileResult {
    fn new(pixels: u32, aovs: usize) -> Self {
        Self {
            radiance: vec![Vec3::ZERO; pixels as usize],
            aovs: vec![vec![Vec3::ZERO; pixels as usize]; aovs],
        }
    }
}

fn aov_value(aov: Aov, scene: &Scene, s: &Sample) -> Vec3 {
    match aov {
        Aov::Normal => s.point.shading_normal,
        Aov::Position => s.point.position,
        Aov::Depth => Vec3::splat(s.depth),
        Aov::Albedo => {
            let m = &scene.materials[s.point.material as usize];
            Vec3::from(m.albedo) * m.kd
        }
    }
}
