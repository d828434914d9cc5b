//! The render driver: runs the planned stages over image tiles in parallel.
//!
//! The region (the whole film, or a `--crop`) is cut into 16×16 tiles; each tile's samples go
//! through [`tile::Context::trace`] (surface points, then shading, both timed) and are averaged
//! with a box filter. With the `adaptive` and `cells` samplers, `render/adaptive.rs` decides per
//! pixel how many samples it takes. Every pixel is a pure function of the scene and its
//! coordinates (and, for adaptive sampling, of its neighbours' centre samples), so the image
//! depends neither on the thread count nor on the tiling, and crops merge bit-identically into
//! the full frame. With a time budget, `render/progressive.rs` renders in passes until the budget;
//! the image is that of the sample count or threshold reached.

mod adaptive;
mod progressive;
pub use progressive::threshold_ladder;
mod rounds;
mod subdivision;
pub mod tile;

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use crate::accel::Bvh;
use crate::film::{overflow_error, sampler::pixel_offsets, Image, PixelRect};
use crate::plan::{Aov, RenderPlan};
use crate::scene::Scene;
use tile::{block_order, Context, PixelSums, SampleJob};

/// Side of the square tiles the region is cut into.
pub const TILE: u32 = 16;

/// Counters and per-stage times of one render.
#[derive(Clone, Debug, Default)]
pub struct RenderStats {
    /// Camera rays traced (= samples taken).
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

/// The result of a render: the image of the region, the requested AOVs and the statistics.
pub struct Rendered {
    /// Linear radiance of `region` (its size; row 0 = the region's top row).
    pub image: Image,
    /// AOV images, in the order of `RenderPlan::aovs`.
    pub aovs: Vec<(Aov, Image)>,
    /// The part of the film rendered.
    pub region: PixelRect,
    /// Samples each pixel of the region took (adaptive sampling), row-major; `None` = `spp` each.
    pub sample_counts: Option<Vec<u32>>,
    /// Samples per pixel: the film's, or the count a time budget reached; for the adaptive
    /// samplers, the most a pixel may take.
    pub spp: u32,
    /// The adaptive samplers' threshold: the film's, or the finest a time budget reached.
    pub adaptive_threshold: Option<f32>,
    /// Counters and times.
    pub stats: RenderStats,
}

/// The pipeline after loading: builds the BVH the plan asks for (default preset) and renders.
/// A film's time budget counts from here: BVH build and render.
#[inline(never)] // a stage boundary that benches/instructions.sh counts
pub fn render_scene(scene: &Scene, plan: &RenderPlan, on_tile: &(dyn Fn(u64) + Sync)) -> Result<Rendered, String> {
    let start = Instant::now();
    // The plan's cut-out stage and `Bvh::for_scene`'s mask look at the same materials.
    let bvh = plan.trace_rays.then(|| Bvh::for_scene(scene));
    debug_assert!(bvh.as_ref().is_none_or(|b| b.has_alpha_mask() == plan.cutouts));
    let mut rendered = render_from(start, scene, plan, bvh.as_ref(), on_tile)?;
    rendered.stats.bvh_time = bvh.map_or(Duration::ZERO, |b| b.build_time);
    Ok(rendered)
}

/// Renders `scene` following `plan`. `bvh` must be present when `plan.trace_rays` is set.
/// `on_tile` is called after each finished tile with the number of tiles (for progress bars).
/// A film's time budget counts from this call.
pub fn render(
    scene: &Scene,
    plan: &RenderPlan,
    bvh: Option<&Bvh>,
    on_tile: &(dyn Fn(u64) + Sync),
) -> Result<Rendered, String> {
    render_from(Instant::now(), scene, plan, bvh, on_tile)
}

/// [`render`], with a time budget counted from `budget_start`.
fn render_from(
    budget_start: Instant,
    scene: &Scene,
    plan: &RenderPlan,
    bvh: Option<&Bvh>,
    on_tile: &(dyn Fn(u64) + Sync),
) -> Result<Rendered, String> {
    let start = Instant::now();
    let ctx = Context::new(scene, plan, bvh)?;
    let film = &scene.film;
    let region = film.region();
    let deadline = film.time_budget.map(|b| budget_start + Duration::from_secs_f32(b));
    let adaptive = film.sampler.is_adaptive();
    let (sums, counts, spp, threshold) = match deadline {
        Some(deadline) if adaptive => {
            let (sums, counts, threshold) = progressive::render_adaptive(&ctx, region, deadline, on_tile);
            (sums, Some(counts), film.spp, Some(threshold))
        }
        None if adaptive => {
            let (sums, counts) = adaptive::render(&ctx, region, on_tile);
            (sums, Some(counts), film.spp, Some(film.adaptive_threshold))
        }
        Some(deadline) => {
            let (sums, spp) = progressive::render(&ctx, region, deadline, on_tile);
            (sums, None, spp, None)
        }
        None => (fixed(&ctx, region, on_tile), None, film.spp, None),
    };
    let count = |i: usize| counts.as_ref().map_or(spp, |c| c[i]) as f32;
    let average = |sums: &[Vec3]| Image {
        width: region.width(),
        height: region.height(),
        pixels: sums.iter().enumerate().map(|(i, &v)| v / count(i)).collect(),
    };
    let image = average(&sums.radiance);
    if let Some((x, y, p)) = image.first_non_finite() {
        return Err(overflow_error(region.x0 + x, region.y0 + y, p));
    }
    let sample_counts = || Image {
        pixels: (0..image.pixels.len()).map(|i| Vec3::splat(count(i))).collect(),
        ..image
    };
    // The per-sample AOVs' buffers, in the plan's order; the samples AOV is the counts.
    let mut buffers = sums.aovs.iter();
    let aovs = plan
        .aovs
        .iter()
        .map(|&a| {
            let buffer = a.per_sample().then(|| buffers.next()).flatten();
            (a, buffer.map_or_else(sample_counts, |s| average(s)))
        })
        .collect();
    let c = &ctx.counters;
    let stats = RenderStats {
        primary_rays: c.primary_rays.load(Ordering::Relaxed),
        shadow_rays: c.shadow_rays.load(Ordering::Relaxed),
        surface_time: Duration::from_nanos(c.surface_ns.load(Ordering::Relaxed)),
        shading_time: Duration::from_nanos(c.shading_ns.load(Ordering::Relaxed)),
        wall_time: start.elapsed(),
        bvh_time: Duration::ZERO,
    };
    Ok(Rendered {
        image,
        aovs,
        region,
        sample_counts: counts,
        spp,
        adaptive_threshold: threshold,
        stats,
    })
}

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
/// two runs per thread, and a run is not split once a thread has started it: on the dragon the
/// thread whose run held the most refined pixels finished 77 ms after the other, which sat idle
/// (docs/performance-log.md). One tile per job lets an idle thread steal any tile not
/// yet started; tiles take milliseconds, so the extra jobs cost nothing measurable. A zip with
/// another indexed iterator keeps the one tile per job (rayon's zip takes the smaller maximum).
fn par_tiles(tiles: &[PixelRect]) -> impl IndexedParallelIterator<Item = &PixelRect> {
    tiles.par_iter().with_max_len(1)
}

/// Copies per-tile sums into one region-sized buffer (row-major).
fn assemble(region: PixelRect, tiles: &[PixelRect], parts: Vec<PixelSums>, aovs: usize) -> PixelSums {
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
fn place_tile<T: Copy>(region: PixelRect, tile: &PixelRect, values: &[T], into: &mut [T]) {
    let width = tile.width() as usize;
    for (row, y) in values.chunks_exact(width).zip(tile.y0..tile.y1) {
        let at = ((y - region.y0) * region.width() + (tile.x0 - region.x0)) as usize;
        into[at..at + width].copy_from_slice(row);
    }
}

/// Fixed sampling: every pixel takes the film's spp samples from its sampler.
fn fixed(ctx: &Context, region: PixelRect, on_tile: &(dyn Fn(u64) + Sync)) -> PixelSums {
    let tiles = tiles(region);
    let done = AtomicU64::new(0);
    let naovs = ctx.sampled_aovs;
    let parts: Vec<PixelSums> = par_tiles(&tiles)
        .map(|t| {
            let mut sums = PixelSums::new((t.width() * t.height()) as usize, naovs);
            tile_samples(ctx, *t, 0, ctx.scene.film.spp, &mut sums);
            on_tile(done.fetch_add(1, Ordering::Relaxed) + 1);
            sums
        })
        .collect();
    assemble(region, &tiles, parts, naovs)
}

/// Most samples traced in one call of [`Context::trace`]: bounds the job list (12 bytes a job)
/// when a pixel takes thousands of samples. Flushes fall between pixels, so each pixel still adds
/// its samples in order.
const JOBS_PER_TRACE: usize = 4096;

/// Traces samples `first` to `first + count − 1` of every pixel of tile `t` from the film's
/// sampler (pixel by pixel, 4×4 blocks in order) and adds them to `sums`.
fn tile_samples(ctx: &Context, t: PixelRect, first: u32, count: u32, sums: &mut PixelSums) {
    let film = &ctx.scene.film;
    let mut offsets = vec![Vec2::ZERO; count as usize];
    let mut jobs = Vec::with_capacity(((t.width() * t.height() * count) as usize).min(2 * JOBS_PER_TRACE));
    let mut scratch = Vec::new();
    for (x, y) in block_order(t) {
        pixel_offsets(film.sampler, film.seed, x, y, first, &mut offsets);
        let slot = (y - t.y0) * t.width() + (x - t.x0);
        let corner = Vec2::new(x as f32, y as f32);
        jobs.extend(offsets.iter().map(|&o| SampleJob { slot, film: corner + o }));
        if jobs.len() >= JOBS_PER_TRACE {
            ctx.trace(&jobs, sums, &mut scratch);
            jobs.clear();
        }
    }
    if !jobs.is_empty() {
        ctx.trace(&jobs, sums, &mut scratch);
    }
}
