//! Adaptive sampling: one sample where the image is smooth, many where a pixel's estimate still
//! changes (silhouettes, shadow edges, highlights).
//!
//! 1. **Centre pass.** Every pixel of the region, and a two-pixel apron around it, takes one
//!    sample at its centre (the midpoint rule: exact for linear shading across the pixel).
//! 2. **Activation.** The centre values *bend* at a pixel if, for a line through it (horizontal,
//!    vertical, either diagonal), |2c − a − b|/2 > t·level, with `level` the largest channel in
//!    its 3×3 neighbourhood and t the film's `adaptive_threshold`. Linear gradients do not bend,
//!    so smooth shading stays at one sample; edges and peaks do. The values also bend where the
//!    centre sample of a neighbour hit another material, or nothing (a silhouette between two
//!    black areas shows no contrast). A pixel refines if the values bend at it or at a
//!    neighbour: an edge that crosses a pixel between sample centres bends the values beside it.
//! 3. **Refinement.** An active pixel takes Sobol samples 0..16, then up to 64, 256, … (the
//!    film's spp at most), and stops once its mean moves by at most t times its own value between
//!    two rounds (or t times a twentieth of its neighbourhood's level, for dark pixels). Its value
//!    is the mean of those stratified samples (the centre sample is not mixed in). The first
//!    round is 16 samples, not 4: an edge or highlight that covers a small part of a pixel is
//!    missed by 4 samples as often as by the centre, which then agree and stop the pixel with
//!    its feature unseen (on the glossy dragon that left RMSE at 1e-3 whatever the spp).
//!
//! Each decision reads only the pixel's own samples and its neighbours' centre samples, which the
//! apron provides for crops: the image is independent of threads, tiles and crops.

use std::sync::atomic::{AtomicU64, Ordering};

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::tile::{Context, PixelSums, SampleJob};
use super::{assemble, tiles};
use crate::film::{sampler::pixel_offsets, PixelRect, SamplerKind};

/// Samples of an active pixel's first refinement round (a 4×4-stratified Sobol net); each later
/// round takes 4× as many.
const FIRST_ROUND: u32 = 16;
/// Floor of a pixel's scale in the convergence test, as a share of its neighbourhood's level.
const DARK_FLOOR: f32 = 0.05;

/// Renders `region` adaptively; returns the per-pixel sums and sample counts (row-major).
pub fn render(ctx: &Context, region: PixelRect, on_tile: &(dyn Fn(u64) + Sync)) -> (PixelSums, Vec<u32>) {
    let film = &ctx.scene.film;
    let grow = |r: PixelRect, by: u32| PixelRect {
        x0: r.x0.saturating_sub(by),
        y0: r.y0.saturating_sub(by),
        x1: (r.x1 + by).min(film.width),
        y1: (r.y1 + by).min(film.height),
    };
    // Bends are needed one pixel around the region (for the dilation), and each needs the
    // centres one pixel further out.
    let apron = grow(region, 2);
    let centre = centre_pass(ctx, apron);
    let at = |x: u32, y: u32| ((y - apron.y0) * apron.width() + (x - apron.x0)) as usize;
    let centre_at = |x: u32, y: u32| (centre.radiance[at(x, y)], centre.surface[at(x, y)]);
    let bent_area = grow(region, 1);
    // One decision per pixel, in parallel (an indexed collect keeps the row-major order).
    let bent: Vec<(bool, f32)> = (0..bent_area.width() * bent_area.height())
        .into_par_iter()
        .map(|i| {
            let (x, y) = (
                bent_area.x0 + i % bent_area.width(),
                bent_area.y0 + i / bent_area.width(),
            );
            neighbourhood(&centre_at, film.width, film.height, x, y, film.adaptive_threshold)
        })
        .collect();
    let bent_at = |x: u32, y: u32| bent[((y - bent_area.y0) * bent_area.width() + (x - bent_area.x0)) as usize];
    let active_at = |x: u32, y: u32| {
        let (x0, x1) = (x.saturating_sub(1).max(bent_area.x0), (x + 2).min(bent_area.x1));
        let (y0, y1) = (y.saturating_sub(1).max(bent_area.y0), (y + 2).min(bent_area.y1));
        (y0..y1).any(|ny| (x0..x1).any(|nx| bent_at(nx, ny).0))
    };
    let naovs = ctx.plan.aovs.len();
    let threshold = film.adaptive_threshold;
    let done = AtomicU64::new(0);
    let region_tiles = tiles(region);
    let parts: Vec<(PixelSums, Vec<u32>)> = region_tiles
        .par_iter()
        .map(|t| {
            let n = (t.width() * t.height()) as usize;
            let mut sums = PixelSums::new(n, naovs);
            let mut counts = vec![1u32; n];
            // Start from the centre samples; collect the pixels that refine.
            let mut active = Vec::new();
            for y in t.y0..t.y1 {
                for x in t.x0..t.x1 {
                    let slot = ((y - t.y0) * t.width() + (x - t.x0)) as usize;
                    let a = ((y - apron.y0) * apron.width() + (x - apron.x0)) as usize;
                    sums.radiance[slot] = centre.radiance[a];
                    sums.surface[slot] = centre.surface[a];
                    for k in 0..naovs {
                        sums.aovs[k][slot] = centre.aovs[k][a];
                    }
                    let level = bent_at(x, y).1;
                    if film.spp > 1 && active_at(x, y) {
                        active.push(Refining {
                            x,
                            y,
                            slot: slot as u32,
                            taken: 0,
                            level,
                            previous: centre.radiance[a],
                            previous_max: centre.radiance[a].max_element(),
                        });
                    }
                }
            }
            refine(ctx, &mut active, &mut sums, &mut counts, threshold);
            on_tile(done.fetch_add(1, Ordering::Relaxed) + 1);
            (sums, counts)
        })
        .collect();
    let (parts, count_parts): (Vec<_>, Vec<_>) = parts.into_iter().unzip();
    let sums = assemble(region, &region_tiles, parts, naovs);
    let mut counts = vec![0u32; (region.width() * region.height()) as usize];
    for (t, c) in region_tiles.iter().zip(count_parts) {
        for (i, v) in c.into_iter().enumerate() {
            let (x, y) = (t.x0 + i as u32 % t.width(), t.y0 + i as u32 / t.width());
            counts[((y - region.y0) * region.width() + (x - region.x0)) as usize] = v;
        }
    }
    (sums, counts)
}

/// One sample at the centre of every pixel of `rect`.
fn centre_pass(ctx: &Context, rect: PixelRect) -> PixelSums {
    let naovs = ctx.plan.aovs.len();
    let rect_tiles = tiles(rect);
    let parts: Vec<PixelSums> = rect_tiles
        .par_iter()
        .map(|t| {
            let mut sums = PixelSums::new((t.width() * t.height()) as usize, naovs);
            let jobs: Vec<SampleJob> = (t.y0..t.y1)
                .flat_map(|y| (t.x0..t.x1).map(move |x| (x, y)))
                .map(|(x, y)| SampleJob {
                    slot: (y - t.y0) * t.width() + (x - t.x0),
                    film: Vec2::new(x as f32 + 0.5, y as f32 + 0.5),
                })
                .collect();
            ctx.trace(&jobs, &mut sums, &mut Vec::new());
            sums
        })
        .collect();
    assemble(rect, &rect_tiles, parts, naovs)
}

/// Whether the centre values bend at (x, y) by more than `threshold` of the neighbourhood's
/// level, or a neighbour's centre hit another surface; and that level (largest channel in the
/// 3×3 neighbourhood inside the film).
fn neighbourhood(
    centre: &impl Fn(u32, u32) -> (Vec3, u32),
    width: u32,
    height: u32,
    x: u32,
    y: u32,
    threshold: f32,
) -> (bool, f32) {
    let (c, surface) = centre(x, y);
    let at = |dx: i32, dy: i32| -> Option<(Vec3, u32)> {
        let (nx, ny) = (x as i64 + dx as i64, y as i64 + dy as i64);
        (nx >= 0 && ny >= 0 && nx < width as i64 && ny < height as i64).then(|| centre(nx as u32, ny as u32))
    };
    let mut level = c.max_element();
    let mut bend = 0.0f32;
    let mut other_surface = false;
    for (dx, dy) in [(1, 0), (0, 1), (1, 1), (1, -1)] {
        let (a, b) = (at(dx, dy), at(-dx, -dy));
        for (v, s) in [a, b].into_iter().flatten() {
            level = level.max(v.max_element());
            other_surface |= s != surface;
        }
        match (a, b) {
            (Some((a, _)), Some((b, _))) => bend = bend.max(((2.0 * c - a - b) * 0.5).abs().max_element()),
            // At the film's border only one neighbour exists: a step to it counts as a bend.
            (Some((a, _)), None) | (None, Some((a, _))) => bend = bend.max((c - a).abs().max_element()),
            (None, None) => {}
        }
    }
    (other_surface || (level > 0.0 && bend > threshold * level), level)
}

/// A pixel still taking samples.
struct Refining {
    x: u32,
    y: u32,
    slot: u32,
    /// Sobol samples taken so far.
    taken: u32,
    /// The neighbourhood's level (absolute scale of the convergence test).
    level: f32,
    /// The estimate before the last round.
    previous: Vec3,
    /// Its largest channel.
    previous_max: f32,
}

/// Rounds of 16, 64, 256, … samples for the `active` pixels of a tile until each converges or
/// reaches the film's spp; their sums replace the centre sample.
fn refine(ctx: &Context, active: &mut Vec<Refining>, sums: &mut PixelSums, counts: &mut [u32], threshold: f32) {
    let film = &ctx.scene.film;
    let naovs = ctx.plan.aovs.len();
    for p in active.iter() {
        sums.radiance[p.slot as usize] = Vec3::ZERO;
        for k in 0..naovs {
            sums.aovs[k][p.slot as usize] = Vec3::ZERO;
        }
    }
    let mut target = FIRST_ROUND.min(film.spp);
    let mut offsets = Vec::new();
    let mut jobs = Vec::new();
    let mut scratch = Vec::new();
    while !active.is_empty() {
        jobs.clear();
        for p in active.iter() {
            offsets.resize((target - p.taken) as usize, Vec2::ZERO);
            pixel_offsets(SamplerKind::Adaptive, film.seed, p.x, p.y, p.taken, &mut offsets);
            let corner = Vec2::new(p.x as f32, p.y as f32);
            jobs.extend(offsets.iter().map(|&o| SampleJob {
                slot: p.slot,
                film: corner + o,
            }));
        }
        ctx.trace(&jobs, sums, &mut scratch);
        active.retain_mut(|p| {
            p.taken = target;
            counts[p.slot as usize] = target;
            let mean = sums.radiance[p.slot as usize] / target as f32;
            let change = (mean - p.previous).abs().max_element();
            p.previous = mean;
            // Relative to the pixel's own value; a dark pixel beside bright ones is judged
            // against a twentieth of its neighbourhood's level instead of chasing noise.
            let scale = mean.max_element().max(p.previous_max).max(DARK_FLOOR * p.level);
            p.previous_max = mean.max_element();
            let converged = change <= threshold * scale;
            !(converged || target == film.spp)
        });
        target = (target * 4).min(film.spp);
    }
}
