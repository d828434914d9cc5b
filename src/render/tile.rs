//! One batch of samples through the pipeline: film positions → camera rays → BVH hits →
//! surface points (stage 1), then the shader on every point (stage 2), each stage timed.
//!
//! Batches are small (a tile's pixels, or the pixels of a tile still taking samples), so the
//! surface points of a batch stay in cache between the two stages.

use std::borrow::Borrow;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Instant;

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use crate::accel::packet::PACKET;
use crate::accel::shadow::{Occluder, SceneExtent};
use crate::accel::Bvh;
use crate::film::sampler::Sequence;
use crate::film::{sampler::pixel_offsets, PixelRect};
use crate::lanes::{lane_vec3, F32x8, LANES};
use crate::plan::{Aov, RenderPlan};
use crate::scene::camera::Camera;
use crate::scene::Scene;
use crate::shading::convention::ShadingConvention;
use crate::shading::shader::Shader;
use crate::surface::normal_texture::apply_normal_texture;
use crate::surface::primary::surface_points;
use crate::surface::SurfacePoint;

/// A sample to trace: the pixel slot it adds to, and its position on the film in pixels.
#[derive(Clone, Copy, Debug)]
pub struct SampleJob {
    /// Index into the batch's [`PixelSums`].
    pub slot: u32,
    /// Film position (x + offset, y + offset), in pixels.
    pub film: Vec2,
}

/// Per-pixel sums of sample values for one batch.
#[derive(Clone, Debug)]
pub struct PixelSums {
    /// Radiance.
    pub radiance: Vec<Vec3>,
    /// One buffer per requested per-sample AOV ([`Aov::per_sample`]), in the plan's order
    /// (the samples AOV is written from the counts and has none).
    pub aovs: Vec<Vec<Vec3>>,
    /// What the last sample of each slot hit: 0 = nothing, m + 1 = a surface of material m
    /// (the adaptive sampler compares neighbours' centre samples with it).
    pub surface: Vec<u32>,
}

impl PixelSums {
    /// Zeroed sums for `pixels` slots and `aovs` AOVs.
    pub fn new(pixels: usize, aovs: usize) -> Self {
        Self {
            radiance: vec![Vec3::ZERO; pixels],
            aovs: vec![vec![Vec3::ZERO; pixels]; aovs],
            surface: vec![0; pixels],
        }
    }

    /// Zeroes the sums and resizes them to `pixels` slots, keeping their allocations.
    pub fn reset(&mut self, pixels: usize) {
        for buffer in std::iter::once(&mut self.radiance).chain(&mut self.aovs) {
            buffer.clear();
            buffer.resize(pixels, Vec3::ZERO);
        }
        self.surface.clear();
        self.surface.resize(pixels, 0);
    }
}

/// Counters shared by every batch of a render.
#[derive(Default)]
pub struct Counters {
    /// Camera rays traced.
    pub primary_rays: AtomicU64,
    /// Shadow rays traced.
    pub shadow_rays: AtomicU64,
    /// Nanoseconds in stage 1, summed over threads.
    pub surface_ns: AtomicU64,
    /// Nanoseconds in stage 2, summed over threads.
    pub shading_ns: AtomicU64,
}

/// A surface point with what the AOVs need that shading does not.
struct Sample {
    slot: u32,
    /// Which camera-ray packet of the batch it came from: its shadow rays share packets too.
    packet: u32,
    point: SurfacePoint,
    depth: f32,
}

/// Side of the film's pixel blocks (4×4 = [`PACKET`] pixels): the camera rays of one block's
/// samples, consecutive in a batch, go through the tree as packets of up to [`PACKET`] — at one
/// sample per pixel a whole block, at 16 one pixel.
pub const BLOCK: u32 = 4;

/// The film's pixel block (the grid of [`BLOCK`]×[`BLOCK`] blocks from pixel (0, 0)) pixel
/// (x, y) lies in.
#[inline]
pub fn pixel_block(x: u32, y: u32) -> (u32, u32) {
    (x / BLOCK, y / BLOCK)
}

/// The pixel block a film position lies in.
#[inline]
fn block_of(film: Vec2) -> (u32, u32) {
    // Film positions are non-negative: `as` truncates them to their pixel.
    pixel_block(film.x as u32, film.y as u32)
}

/// The pixels of `rect` block by block (the film's blocks that meet it, row by row; each block's
/// pixels row by row), so that batches list the samples of a block together.
pub fn block_order(rect: PixelRect) -> impl Iterator<Item = (u32, u32)> {
    let first = |lo: u32| lo / BLOCK * BLOCK;
    (first(rect.y0)..rect.y1).step_by(BLOCK as usize).flat_map(move |by| {
        (first(rect.x0)..rect.x1).step_by(BLOCK as usize).flat_map(move |bx| {
            let xs = bx.max(rect.x0)..(bx + BLOCK).min(rect.x1);
            (by.max(rect.y0)..(by + BLOCK).min(rect.y1)).flat_map(move |y| xs.clone().map(move |x| (x, y)))
        })
    })
}

/// Everything a batch needs, built once per render.
pub struct Context<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// Its plan.
    pub plan: &'a RenderPlan,
    camera: Camera,
    bvh: Option<&'a Bvh>,
    shader: Shader<'a, Bvh>,
    size: Vec2,
    /// The depth AOV was asked for (the only reader of a sample's distance from the camera).
    depth_aov: bool,
    /// The adaptive sampler reads what each centre sample hit.
    record_surface: bool,
    /// How many of the plan's AOVs are per-sample means: the AOV buffers of [`PixelSums`].
    pub sampled_aovs: usize,
    /// Counters and stage times.
    pub counters: Counters,
    /// Set by the caller to end the render early.
    stop: Option<&'a AtomicBool>,
}

impl<'a> Context<'a> {
    /// The context of a render of `scene` (whole film geometry; the region only selects pixels).
    /// `stop`, when given, ends the render early: see [`Context::trace`].
    pub fn new(
        scene: &'a Scene,
        plan: &'a RenderPlan,
        bvh: Option<&'a Bvh>,
        stop: Option<&'a AtomicBool>,
    ) -> Result<Self, String> {
        let film = &scene.film;
        Ok(Self {
            scene,
            plan,
            camera: Camera::new(scene.camera, film.width, film.height)?,
            bvh,
            shader: Shader {
                materials: &scene.materials,
                lights: &scene.lights,
                occluder: if plan.shadows { bvh } else { None },
                extent: bvh.map_or(SceneExtent::UNIT, |b| SceneExtent::new(b.scene_unit(), b.bounds())),
                convention: ShadingConvention::Physical,
                textures: plan.textures.then_some(scene.textures.as_slice()),
                emission: plan.emission,
                shadow_offset: scene.shadow_offset,
            },
            size: Vec2::new(film.width as f32, film.height as f32),
            depth_aov: plan.aovs.contains(&Aov::Depth),
            record_surface: film.sampler.is_adaptive(),
            sampled_aovs: plan.aovs.iter().filter(|a| a.per_sample()).count(),
            counters: Counters::default(),
            stop,
        })
    }

    /// The tree camera and shadow rays are traced in (none without geometry).
    pub(super) fn bvh(&self) -> Option<&'a Bvh> {
        self.bvh
    }

    /// Whether the caller asked the render to stop.
    pub fn stopped(&self) -> bool {
        self.stop.is_some_and(|s| s.load(Ordering::Relaxed))
    }

    /// Traces and shades `jobs`, adding each sample's radiance and AOV values to its slot of
    /// `sums`. Misses add nothing (black). `scratch` is reused between batches. Once the caller
    /// asked to stop, nothing is traced: the remaining batches cost nothing, and the driver
    /// discards the image.
    pub fn trace(&self, jobs: &[SampleJob], sums: &mut PixelSums, scratch: &mut Vec<SurfaceSample>) {
        if self.stopped() {
            return;
        }
        let t0 = Instant::now();
        self.surface_samples(jobs, scratch);
        let t1 = Instant::now();
        let rays = self.shade_samples(&self.shader, scratch, sums);
        let t2 = Instant::now();
        let c = &self.counters;
        c.surface_ns.fetch_add((t1 - t0).as_nanos() as u64, Ordering::Relaxed);
        c.shading_ns.fetch_add((t2 - t1).as_nanos() as u64, Ordering::Relaxed);
        c.shadow_rays.fetch_add(rays, Ordering::Relaxed);
    }

    /// Stage 1: the surface point of every job's camera ray that hits, in job order, into
    /// `scratch` (cleared first). Counts the camera rays.
    pub(super) fn surface_samples(&self, jobs: &[SampleJob], scratch: &mut Vec<SurfaceSample>) {
        let scene = self.scene;
        let plan = self.plan;
        scratch.clear();
        let (true, Some(bvh)) = (plan.trace_rays, self.bvh) else {
            return;
        };
        // Consecutive samples of one pixel block go through the tree as packets: one walk
        // for up to PACKET nearly parallel rays (exactly the hits of one walk per ray).
        let mut rays = [(Vec3::ZERO, Vec3::ZERO, 0.0); PACKET];
        let mut hits = [None; PACKET];
        let options = plan.point_options();
        let blocks = jobs.chunk_by(|a, b| block_of(a.film) == block_of(b.film));
        for (packet, group) in blocks.flat_map(|block| block.chunks(PACKET)).enumerate() {
            let n = group.len();
            // The camera rays eight at a time, each lane the single ray to the bit.
            for (first, jobs) in (0..n).step_by(LANES).zip(group.chunks(LANES)) {
                let film = |i: usize| jobs[i.min(jobs.len() - 1)].film / self.size;
                let r = self
                    .camera
                    .rays(F32x8::from_fn(|i| film(i).x), F32x8::from_fn(|i| film(i).y));
                for (i, ray) in rays[first..first + jobs.len()].iter_mut().enumerate() {
                    *ray = (lane_vec3(&r.origin, i), lane_vec3(&r.direction, i), r.t_max.0[i]);
                }
            }
            bvh.intersect_packet(&rays[..n], &mut hits[..n]);
            surface_points(
                &scene.mesh,
                &hits[..n],
                |k| rays[k].1,
                options,
                |k, hit, mut point| {
                    let (job, origin) = (&group[k], rays[k].0);
                    if plan.normal_textures {
                        apply_normal_texture(&mut point, &scene.mesh, hit, &scene.materials, &scene.textures);
                    }
                    // Decided once per render: no square root per hit unless the AOV is written.
                    let depth = if self.depth_aov {
                        hit.t + (origin - scene.camera.position).length()
                    } else {
                        0.0
                    };
                    scratch.push(SurfaceSample(Sample {
                        slot: job.slot,
                        packet: packet as u32,
                        point,
                        depth,
                    }));
                },
            );
        }
        self.counters
            .primary_rays
            .fetch_add(jobs.len() as u64, Ordering::Relaxed);
    }

    /// Stage 2: shades `samples` with `shader` (this context's, or one with another occluder)
    /// and adds their radiance and AOV values to their slots of `sums`, each slot's samples in
    /// order. Returns the shadow rays the shader asked for.
    pub(super) fn shade_samples<O: Occluder>(
        &self,
        shader: &Shader<O>,
        samples: &[SurfaceSample],
        sums: &mut PixelSums,
    ) -> u64 {
        let mut rays = 0u64;
        // The points of a camera-ray packet are shaded together: their shadow rays towards each
        // light are nearly parallel and go through the tree as one packet (each point's value
        // is the same, bit for bit, and each slot adds its samples in the same order).
        let mut radiance = [Vec3::ZERO; PACKET];
        for group in samples.chunk_by(SurfaceSample::same_packet) {
            shader.shade_batch(group, &mut radiance[..group.len()], &mut rays);
            for (SurfaceSample(s), radiance) in group.iter().zip(&radiance) {
                sums.radiance[s.slot as usize] += *radiance;
            }
        }
        if self.record_surface {
            for SurfaceSample(s) in samples {
                sums.surface[s.slot as usize] = s.point.material + 1;
            }
        }
        for (k, aov) in self.plan.aovs.iter().filter(|a| a.per_sample()).enumerate() {
            for SurfaceSample(s) in samples {
                sums.aovs[k][s.slot as usize] += aov_value(*aov, self.scene, s);
            }
        }
        rays
    }

    /// This context's shader with another occluder (same scene, plan and materials).
    pub(super) fn shader_with<'o, O: Occluder>(&self, occluder: Option<&'o O>) -> Shader<'o, O>
    where
        'a: 'o,
    {
        let s = &self.shader;
        Shader {
            materials: s.materials,
            lights: s.lights,
            occluder: occluder.filter(|_| s.occluder.is_some()),
            extent: s.extent,
            convention: s.convention,
            textures: s.textures,
            emission: s.emission,
            shadow_offset: s.shadow_offset,
        }
    }
}

/// A traced sample waiting for shading (opaque: only [`Context`] reads it).
pub struct SurfaceSample(Sample);

impl SurfaceSample {
    /// Whether two samples came from the same camera-ray packet (they are shaded together).
    pub(super) fn same_packet(a: &Self, b: &Self) -> bool {
        a.0.packet == b.0.packet
    }

    /// The same sample, its packet number moved by `by` (to keep packets apart when batches
    /// are joined).
    pub(super) fn packet_moved(mut self, by: u32) -> Self {
        self.0.packet += by;
        self
    }

    /// One past the packet number of the last of `samples` (0 for none).
    pub(super) fn packets(samples: &[Self]) -> u32 {
        samples.last().map_or(0, |s| s.0.packet + 1)
    }
}

impl Borrow<SurfacePoint> for SurfaceSample {
    fn borrow(&self) -> &SurfacePoint {
        &self.0.point
    }
}

fn aov_value(aov: Aov, scene: &Scene, s: &Sample) -> Vec3 {
    match aov {
        Aov::Normal => s.point.shading_normal,
        // World space, as the scene's files give positions (`Scene::origin` added back in f64):
        // far from the origin an f32 coordinate of the AOV has the f32 step there.
        Aov::Position => (s.point.position.as_dvec3() + scene.origin).as_vec3(),
        Aov::Depth => Vec3::splat(s.depth),
        Aov::Albedo => {
            let m = &scene.materials[s.point.material as usize];
            Vec3::from(m.albedo) * m.kd
        }
        // Not per sample: the driver writes it from the counts (the loop above skips it).
        Aov::Samples => Vec3::ZERO,
    }
}

/// Side of the square tiles the region is cut into.
pub const TILE: u32 = 16;

/// `region` cut into tiles of at most [`TILE`]×[`TILE`] pixels, row by row.
pub fn tiles(region: PixelRect) -> Vec<PixelRect> {
    let mut out = Vec::new();
    for y0 in (region.y0..region.y1).step_by(TILE as usize) {
        for x0 in (region.x0..region.x1).step_by(TILE as usize) {
            out.push(PixelRect {
                x0,
                y0,
                x1: (x0 + TILE).min(region.x1),
                y1: (y0 + TILE).min(region.y1),
            });
        }
    }
    out
}

/// The tiles as parallel jobs of one tile each. Left to itself, rayon cuts a slice into about
/// two runs per thread, and a run is not split once a thread has started it: in an adaptive
/// render the thread whose run holds the most refined pixels finishes long after the other,
/// which sits idle (docs/performance-log.md). One tile per job lets an idle thread steal any
/// tile not yet started; tiles take milliseconds, so the extra jobs cost nothing measurable. A
/// zip with another indexed iterator keeps the one tile per job (rayon's zip takes the smaller
/// maximum).
pub(super) fn par_tiles(tiles: &[PixelRect]) -> impl IndexedParallelIterator<Item = &PixelRect> {
    tiles.par_iter().with_max_len(1)
}

/// Copies per-tile sums into one region-sized buffer (row-major).
pub(super) fn assemble(region: PixelRect, tiles: &[PixelRect], parts: Vec<PixelSums>, aovs: usize) -> PixelSums {
    let mut all = PixelSums::new((region.width() * region.height()) as usize, aovs);
    for (t, part) in tiles.iter().zip(parts) {
        place_tile(region, t, &part.radiance, &mut all.radiance);
        place_tile(region, t, &part.surface, &mut all.surface);
        for (tile_aov, aov) in part.aovs.iter().zip(&mut all.aovs) {
            place_tile(region, t, tile_aov, aov);
        }
    }
    all
}

/// Copies the row-major values of `tile` into the row-major values of `region`, row by row.
pub(super) fn place_tile<T: Copy>(region: PixelRect, tile: &PixelRect, values: &[T], into: &mut [T]) {
    let width = tile.width() as usize;
    for (row, y) in values.chunks_exact(width).zip(tile.y0..tile.y1) {
        let at = ((y - region.y0) * region.width() + (tile.x0 - region.x0)) as usize;
        into[at..at + width].copy_from_slice(row);
    }
}

/// Most samples traced in one call of [`Context::trace`]: bounds the job list (12 bytes a job)
/// when a pixel takes thousands of samples. Flushes fall between pixels, so each pixel still adds
/// its samples in order.
const JOBS_PER_TRACE: usize = 4096;

/// Traces samples `first` to `first + count − 1` of every pixel of tile `t` from the film's
/// sampler (pixel by pixel, 4×4 blocks in order) and adds them to `sums`.
pub(super) fn tile_samples(
    ctx: &Context,
    sequence: Sequence,
    t: PixelRect,
    first: u32,
    count: u32,
    sums: &mut PixelSums,
) {
    let mut scratch = Vec::new();
    tile_jobs(ctx, sequence, t, first, count, &mut |jobs| {
        ctx.trace(jobs, sums, &mut scratch)
    });
}

/// The sample jobs of [`tile_samples`], handed to `trace` in runs of up to about
/// [`JOBS_PER_TRACE`] (whole pixels), in order. Stops early once the caller asked the render
/// to stop.
pub(super) fn tile_jobs(
    ctx: &Context,
    sequence: Sequence,
    t: PixelRect,
    first: u32,
    count: u32,
    trace: &mut dyn FnMut(&[SampleJob]),
) {
    let film = &ctx.scene.film;
    let mut offsets = vec![Vec2::ZERO; count as usize];
    let mut jobs = Vec::with_capacity(((t.width() * t.height() * count) as usize).min(2 * JOBS_PER_TRACE));
    for (x, y) in block_order(t) {
        if ctx.stopped() {
            return; // not even the sample positions: they cost as much as tracing at high spp
        }
        pixel_offsets(sequence, film.seed, x, y, first, &mut offsets);
        let slot = (y - t.y0) * t.width() + (x - t.x0);
        let corner = Vec2::new(x as f32, y as f32);
        jobs.extend(offsets.iter().map(|&o| SampleJob { slot, film: corner + o }));
        if jobs.len() >= JOBS_PER_TRACE {
            trace(&jobs);
            jobs.clear();
        }
    }
    if !jobs.is_empty() {
        trace(&jobs);
    }
}

#[cfg(test)]
mod tests {
    use super::{block_order, pixel_block};
    use crate::film::PixelRect;

    #[test]
    fn block_order_lists_each_pixel_once_with_the_pixels_of_a_block_together() {
        // A rect whose edges cut the film's blocks on every side.
        let rect = PixelRect {
            x0: 5,
            y0: 3,
            x1: 22,
            y1: 14,
        };
        let pixels: Vec<(u32, u32)> = block_order(rect).collect();
        let mut sorted = pixels.clone();
        sorted.sort_by_key(|&(x, y)| (y, x));
        let expected: Vec<(u32, u32)> = (3..14).flat_map(|y| (5..22).map(move |x| (x, y))).collect();
        assert_eq!(sorted, expected);
        let runs = pixels
            .chunk_by(|a, b| pixel_block(a.0, a.1) == pixel_block(b.0, b.1))
            .count();
        // Blocks meeting the rect: columns 1..=5, rows 0..=3.
        assert_eq!(runs, 5 * 4, "each block's pixels form one run");
    }
}
