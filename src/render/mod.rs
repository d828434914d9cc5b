//! The render driver: runs the planned stages over image tiles in parallel.
//!
//! The region (the whole film, or a `--crop`) is cut into 16×16 tiles; each tile's samples go
//! through [`tile::Context::trace`] (surface points, then shading, both timed) and are averaged
//! with a box filter. With the `adaptive` and `cells` samplers, `render/adaptive.rs` decides per
//! pixel how many samples it takes. Every pixel is a pure function of the scene and its
//! coordinates (and, for adaptive sampling, of its neighbours' centre samples), so the image
//! depends neither on the thread count nor on the tiling, and crops merge bit-identically into
//! the full frame. With a time budget, `render/budget.rs` renders in passes until the budget;
//! the image is that of the sample count or threshold reached.

mod adaptive;
mod budget;
pub mod preview;
mod retained;
pub use budget::threshold_ladder;
pub mod options;
pub mod progress;
pub mod request;
mod sample_cache;
pub mod tile;
pub(crate) mod workers;
pub use workers::{check_thread_count, Workers, MAX_THREADS_PER_CPU};

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use glam::Vec3;
use rayon::prelude::*;

use crate::accel::Bvh;
use crate::film::sampler::Sequence;
use crate::film::{overflow_error, Image, PixelRect};
use crate::plan::{Aov, RenderPlan};
use crate::scene::Scene;
use progress::{Advance, Progress, ProgressUnit};
use tile::{assemble, par_tiles, tile_samples, Context, PixelSums};
pub use tile::{tiles, TILE};

/// Counters and per-stage times of one render.
#[derive(Clone, Debug, Default)]
pub struct RenderStats {
    /// Camera rays traced (= samples taken).
    pub primary_rays: u64,
    /// Shadow rays traced.
    pub shadow_rays: u64,
    /// Shadow rays whose verdict a preview's re-shading took from its last render instead of
    /// tracing them ([`preview::Preview`]); zero for every other render.
    pub shadow_rays_reused: u64,
    /// Time summed over threads spent making surface points (camera rays and BVH traversal).
    pub surface_time: Duration,
    /// Time summed over threads spent shading (BRDFs, lights, shadow rays).
    pub shading_time: Duration,
    /// Of `shading_time`, the time spent tracing shadow rays, where it was measured apart (a
    /// preview's renders, [`preview::Preview`]; the others do not pay for two more clock
    /// readings per packet and light).
    pub shadow_time: Option<Duration>,
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
pub fn render_scene(scene: &Scene, plan: &RenderPlan, progress: &dyn Progress) -> Result<Rendered, String> {
    render_scene_until(scene, plan, progress, None)
}

/// Refuses a film whose peak memory is more than the process can have
/// ([`crate::film::memory::check_fits`]), before the BVH is built or a pixel rendered.
fn check_film_memory(region: PixelRect, plan: &RenderPlan) -> Result<(), String> {
    let samples_aov = plan.aovs.contains(&Aov::Samples);
    let others = plan.aovs.len() - usize::from(samples_aov);
    crate::film::memory::check_fits(region.width(), region.height(), others, samples_aov, plan.adaptive)
}

/// The message of a render that `stop` ended.
pub const INTERRUPTED: &str = "interrupted";

/// [`render_scene`], which ends early with the error [`INTERRUPTED`] once `stop` is set: no
/// sample starts after that (each batch looks at it), so a render ends within one batch of
/// samples per thread (the Python module's KeyboardInterrupt).
#[inline(never)] // a stage boundary that benches/instructions.sh counts
pub fn render_scene_until(
    scene: &Scene,
    plan: &RenderPlan,
    progress: &dyn Progress,
    stop: Option<&AtomicBool>,
) -> Result<Rendered, String> {
    let start = Instant::now();
    check_film_memory(scene.film.region(), plan)?;
    // The plan's cut-out stage and `Bvh::for_scene`'s mask look at the same materials.
    let bvh = plan.trace_rays.then(|| Bvh::for_scene(scene));
    debug_assert!(bvh.as_ref().is_none_or(|b| b.has_alpha_mask() == plan.cutouts));
    let mut rendered = render_from(start, scene, plan, bvh.as_ref(), progress, stop)?;
    rendered.stats.bvh_time = bvh.map_or(Duration::ZERO, |b| b.build_time);
    Ok(rendered)
}

/// Renders `scene` following `plan`. `bvh` must be present when `plan.trace_rays` is set.
/// `progress` hears of each finished tile. A film's time budget counts from this call.
pub fn render(
    scene: &Scene,
    plan: &RenderPlan,
    bvh: Option<&Bvh>,
    progress: &dyn Progress,
) -> Result<Rendered, String> {
    render_from(Instant::now(), scene, plan, bvh, progress, None)
}

/// [`render`], with a time budget counted from `budget_start`.
fn render_from(
    budget_start: Instant,
    scene: &Scene,
    plan: &RenderPlan,
    bvh: Option<&Bvh>,
    progress: &dyn Progress,
    stop: Option<&AtomicBool>,
) -> Result<Rendered, String> {
    let start = Instant::now();
    let film = &scene.film;
    let region = film.region();
    check_film_memory(region, plan)?;
    let ctx = Context::new(scene, plan, bvh, stop)?;
    let deadline = film.time_budget.map(|b| budget_start + Duration::from_secs_f32(b));
    let tile_count = tiles(region).len() as u64;
    // With a time budget tiles are rendered in passes, so the budget's share spent is the measure.
    let on_tile = |done: u64| {
        progress.advance(match film.time_budget {
            Some(budget) => {
                let total = (budget as f64 * 1e3) as u64;
                let spent = budget_start.elapsed().as_millis() as u64;
                Advance {
                    done: spent.min(total),
                    total,
                    unit: ProgressUnit::BudgetMilliseconds,
                }
            }
            None => Advance {
                done: done.min(tile_count),
                total: tile_count,
                unit: ProgressUnit::Tiles,
            },
        })
    };
    let on_tile = &on_tile;
    let (sums, counts, spp, threshold) = match (film.sampler.fixed_sequence(), deadline) {
        (None, Some(deadline)) => {
            let (sums, counts, threshold) = budget::render_adaptive(&ctx, region, deadline, on_tile);
            (sums, Some(counts), film.spp, Some(threshold))
        }
        (None, None) => {
            let (sums, counts) = adaptive::render(&ctx, region, on_tile);
            (sums, Some(counts), film.spp, Some(film.adaptive_threshold))
        }
        (Some(sequence), Some(deadline)) => {
            let (sums, spp) = budget::render(&ctx, sequence, region, deadline, on_tile);
            (sums, None, spp, None)
        }
        (Some(sequence), None) => (fixed(&ctx, sequence, region, on_tile), None, film.spp, None),
    };
    let sampled = Sampled {
        sums,
        counts,
        spp,
        threshold,
    };
    finish(&ctx, start, region, sampled)
}

/// What a sampler took: per-pixel sums, per-pixel sample counts (adaptive), and the sample
/// count and threshold reached.
struct Sampled {
    sums: PixelSums,
    counts: Option<Vec<u32>>,
    spp: u32,
    threshold: Option<f32>,
}

/// The image, AOVs and statistics of a render of `region` that took `sampled`, started at
/// `start`; the error [`INTERRUPTED`] if the caller stopped it, an overflow error if a pixel is
/// not finite.
fn finish(ctx: &Context, start: Instant, region: PixelRect, sampled: Sampled) -> Result<Rendered, String> {
    let Sampled {
        sums,
        counts,
        spp,
        threshold,
    } = sampled;
    let plan = ctx.plan;
    if ctx.stopped() {
        return Err(INTERRUPTED.into());
    }
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
        shadow_rays_reused: 0,
        shadow_time: None,
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

/// Fixed sampling: every pixel takes the film's spp samples from `sequence`.
fn fixed(ctx: &Context, sequence: Sequence, region: PixelRect, on_tile: &(dyn Fn(u64) + Sync)) -> PixelSums {
    let tiles = tiles(region);
    let done = AtomicU64::new(0);
    let naovs = ctx.sampled_aovs;
    let parts: Vec<PixelSums> = par_tiles(&tiles)
        .map(|t| {
            let mut sums = PixelSums::new((t.width() * t.height()) as usize, naovs);
            tile_samples(ctx, sequence, *t, 0, ctx.scene.film.spp, &mut sums);
            on_tile(done.fetch_add(1, Ordering::Relaxed) + 1);
            sums
        })
        .collect();
    assemble(region, &tiles, parts, naovs)
}
