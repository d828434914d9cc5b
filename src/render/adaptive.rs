//! Adaptive sampling: one sample where the image is smooth, many where a pixel's estimate still
//! changes (silhouettes, shadow edges, highlights).
//!
//! 1. **Centre pass.** Every pixel of the region, and a two-pixel apron around it, takes one
//!    sample at its centre (the midpoint rule: exact for linear shading across the pixel).
//! 2. **Activation.** The centre values *bend* at a pixel if, for a line through it (horizontal,
//!    vertical, either diagonal), |2c − a − b|/2 > t·max(level, w), with `level` the largest
//!    channel in its 3×3 neighbourhood, w display white (2^−exposure, see the scale in step 3)
//!    and t the film's `adaptive_threshold`. Linear gradients do not bend,
//!    so smooth shading stays at one sample; edges and peaks do. The values also bend where the
//!    centre sample of a neighbour hit another material, or nothing (a silhouette between two
//!    black areas shows no contrast). A pixel refines if the values bend at it or at a
//!    neighbour: an edge that crosses a pixel between sample centres bends the values beside it.
//! 3. **Refinement.** An active pixel takes Sobol samples 0..16, then up to 64, 256, … (the
//!    film's spp at most). It stops once two error estimates are within t times its scale: how
//!    far its mean moved in the round, and how far the means of the first and the second half of
//!    its samples lie apart (each half is a stratified net of its own). The scale is the largest
//!    of its value, a twentieth of its neighbourhood's level and display white (the radiance
//!    8-bit output shows as white, 2^−exposure): below white the tolerance is absolute, as the
//!    error a viewer and RMSE see is. Its value is the mean of those samples (the centre sample is not
//!    mixed in). The first round is 16 samples, and is not trusted alone where
//!    - its samples all repeat the centre value while a neighbour is brighter by more than the
//!      tolerance (sixteen samples in shadow can miss a lit sliver the neighbours show), or
//!    - the neighbourhood's centres span more than 30 tolerances (where sixteen samples agree
//!      with the centre by chance too often).
//!
//!    On the glossy dragon these rules reach the 8×8 grid's error with 9 samples per pixel on
//!    average instead of 20 (README, "Error against run time").
//!
//! Each decision reads only the pixel's own samples and its neighbours' centre samples, which the
//! apron provides for crops: the image is independent of threads, tiles and crops.

use std::sync::atomic::{AtomicU64, Ordering};

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::tile::{block_order, Context, PixelSums, SampleJob};
use super::{assemble, par_tiles, tiles};
use crate::film::{sampler::pixel_offsets, FilmSettings, PixelRect, SamplerKind};

/// Samples of an active pixel's first refinement round (a 4×4-stratified Sobol net); each later
/// round takes 4× as many.
const FIRST_ROUND: u32 = 16;
/// Floor of a pixel's scale in the convergence test, as a share of its neighbourhood's level.
const DARK_FLOOR: f32 = 0.05;
/// Neighbourhood contrast, in tolerances, above which a first round alone never converges.
const HIGH_CONTRAST: f32 = 30.0;

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
    let bent: Vec<Neighbourhood> = (0..bent_area.width() * bent_area.height())
        .into_par_iter()
        .map(|i| {
            let (x, y) = (
                bent_area.x0 + i % bent_area.width(),
                bent_area.y0 + i / bent_area.width(),
            );
            neighbourhood(&centre_at, film, x, y)
        })
        .collect();
    let bent_at = |x: u32, y: u32| bent[((y - bent_area.y0) * bent_area.width() + (x - bent_area.x0)) as usize];
    let active_at = |x: u32, y: u32| {
        let (x0, x1) = (x.saturating_sub(1).max(bent_area.x0), (x + 2).min(bent_area.x1));
        let (y0, y1) = (y.saturating_sub(1).max(bent_area.y0), (y + 2).min(bent_area.y1));
        (y0..y1).any(|ny| (x0..x1).any(|nx| bent_at(nx, ny).bends))
    };
    let naovs = ctx.plan.aovs.len();
    let done = AtomicU64::new(0);
    let region_tiles = tiles(region);
    let parts: Vec<(PixelSums, Vec<u32>)> = par_tiles(&region_tiles)
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
                    let Neighbourhood { level, low, .. } = bent_at(x, y);
                    if film.spp > 1 && active_at(x, y) {
                        active.push(Refining {
                            x,
                            y,
                            slot: slot as u32,
                            taken: 0,
                            level,
                            low,
                            previous: centre.radiance[a],
                            previous_max: centre.radiance[a].max_element(),
                        });
                    }
                }
            }
            refine(ctx, &mut active, &mut sums, &mut counts);
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
    let parts: Vec<PixelSums> = par_tiles(&rect_tiles)
        .map(|t| {
            let mut sums = PixelSums::new((t.width() * t.height()) as usize, naovs);
            let jobs: Vec<SampleJob> = block_order(*t)
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

/// What the centre samples around a pixel say about it.
#[derive(Clone, Copy)]
struct Neighbourhood {
    /// The centre values bend at the pixel, or a neighbour's centre hit another surface.
    bends: bool,
    /// Largest channel of the centre values in the 3×3 neighbourhood (inside the film).
    level: f32,
    /// Smallest of the centre values' largest channels in that neighbourhood.
    low: f32,
}

/// Whether the centre values bend at (x, y) by more than `threshold` of the neighbourhood's
/// level (or of display white, if that is brighter), or a neighbour's centre hit another surface;
/// and the neighbourhood's range.
fn neighbourhood(centre: &impl Fn(u32, u32) -> (Vec3, u32), film: &FilmSettings, x: u32, y: u32) -> Neighbourhood {
    let (width, height) = (film.width, film.height);
    let (c, surface) = centre(x, y);
    let at = |dx: i32, dy: i32| -> Option<(Vec3, u32)> {
        let (nx, ny) = (x as i64 + dx as i64, y as i64 + dy as i64);
        (nx >= 0 && ny >= 0 && nx < width as i64 && ny < height as i64).then(|| centre(nx as u32, ny as u32))
    };
    let (mut level, mut low) = (c.max_element(), c.max_element());
    let mut bend = 0.0f32;
    let mut other_surface = false;
    for (dx, dy) in [(1, 0), (0, 1), (1, 1), (1, -1)] {
        let (a, b) = (at(dx, dy), at(-dx, -dy));
        for (v, s) in [a, b].into_iter().flatten() {
            level = level.max(v.max_element());
            low = low.min(v.max_element());
            other_surface |= s != surface;
        }
        match (a, b) {
            (Some((a, _)), Some((b, _))) => bend = bend.max(((2.0 * c - a - b) * 0.5).abs().max_element()),
            // At the film's border only one neighbour exists: a step to it counts as a bend.
            (Some((a, _)), None) | (None, Some((a, _))) => bend = bend.max((c - a).abs().max_element()),
            (None, None) => {}
        }
    }
    Neighbourhood {
        bends: other_surface || bend > film.adaptive_threshold * level.max(display_white(film)),
        level,
        low,
    }
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
    /// The neighbourhood's darkest centre value (with `level`, its contrast).
    low: f32,
    /// The estimate before the last round.
    previous: Vec3,
    /// Its largest channel.
    previous_max: f32,
}

/// Rounds of 16, 64, 256, … samples for the `active` pixels of a tile until each converges or
/// reaches the film's spp; their sums replace the centre sample.
fn refine(ctx: &Context, active: &mut Vec<Refining>, sums: &mut PixelSums, counts: &mut [u32]) {
    let film = &ctx.scene.film;
    let (threshold, white) = (film.adaptive_threshold, display_white(film));
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
    // Two slots per active pixel: the round's samples in the first and in the second half of
    // the pixel's samples so far.
    let mut halves = PixelSums::new(0, naovs);
    while !active.is_empty() {
        jobs.clear();
        let half = target / 2;
        for (k, p) in active.iter().enumerate() {
            offsets.resize((target - p.taken) as usize, Vec2::ZERO);
            pixel_offsets(SamplerKind::Adaptive, film.seed, p.x, p.y, p.taken, &mut offsets);
            let corner = Vec2::new(p.x as f32, p.y as f32);
            jobs.extend(offsets.iter().zip(p.taken..).map(|(&o, i)| SampleJob {
                slot: 2 * k as u32 + u32::from(i >= half),
                film: corner + o,
            }));
        }
        halves.reset(2 * active.len());
        ctx.trace(&jobs, &mut halves, &mut scratch);
        let mut k = 0;
        active.retain_mut(|p| {
            let slot = p.slot as usize;
            let (first, second) = (halves.radiance[2 * k], halves.radiance[2 * k + 1]);
            for (aov, round) in sums.aovs.iter_mut().zip(&halves.aovs) {
                aov[slot] += round[2 * k] + round[2 * k + 1];
            }
            k += 1;
            // Samples [0, half) of the pixel: all it had before this round, and `first`.
            let first_half = sums.radiance[slot] + first;
            sums.radiance[slot] += first + second;
            let is_first_round = p.taken == 0;
            p.taken = target;
            counts[slot] = target;
            let mean = sums.radiance[slot] / target as f32;
            let verdict = Verdict {
                change: (mean - p.previous).abs().max_element(),
                halves_differ: ((first_half - second) / half as f32).abs().max_element(),
                mean: mean.max_element(),
            };
            let scale = verdict.mean.max(p.previous_max).max(DARK_FLOOR * p.level).max(white);
            p.previous = mean;
            p.previous_max = verdict.mean;
            let converged = verdict.converged(threshold * scale)
                && !(is_first_round && verdict.first_round_suspect(p, threshold * scale));
            !(converged || target == film.spp)
        });
        target = (target * 4).min(film.spp);
    }
}

/// The radiance shown as white on 8-bit output (2^−exposure): below it the adaptive tolerances are
/// absolute, as the error a viewer (and RMSE) sees is. A dim scene exposed up for viewing gets
/// proportionally tighter tolerances.
fn display_white(film: &FilmSettings) -> f32 {
    (-film.exposure).exp2()
}

/// What a round of samples says about a pixel's estimate.
struct Verdict {
    /// How far the mean moved in this round (largest channel).
    change: f32,
    /// How far the means of the pixel's first and second halves of samples lie apart (two
    /// stratified estimates of the same integral; largest channel).
    halves_differ: f32,
    /// The mean's largest channel.
    mean: f32,
}

impl Verdict {
    /// Both error estimates are within `tolerance`.
    fn converged(&self, tolerance: f32) -> bool {
        self.change.max(self.halves_differ) <= tolerance
    }

    /// A first round that cannot be trusted: its samples all agree with the centre (they may all
    /// have missed a sliver of light or shadow that the neighbours show), or the neighbourhood
    /// spans a large contrast, where 16 samples too often agree by chance.
    fn first_round_suspect(&self, p: &Refining, tolerance: f32) -> bool {
        let blind = self.change.max(self.halves_differ) <= 1e-6 * self.mean;
        (blind && p.level - self.mean > tolerance) || p.level - p.low > HIGH_CONTRAST * tolerance
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pixel(level: f32, low: f32) -> Refining {
        Refining {
            x: 0,
            y: 0,
            slot: 0,
            taken: 0,
            level,
            low,
            previous: Vec3::ZERO,
            previous_max: 0.0,
        }
    }

    #[test]
    fn a_pixel_converges_only_when_both_error_estimates_are_within_tolerance() {
        let v = |change, halves_differ| Verdict {
            change,
            halves_differ,
            mean: 0.5,
        };
        assert!(v(0.001, 0.002).converged(0.002));
        // The mean did not move, but the two halves of its samples disagree.
        assert!(!v(0.0, 0.01).converged(0.002));
        assert!(!v(0.01, 0.0).converged(0.002));
    }

    #[test]
    fn a_first_round_that_only_repeats_the_centre_is_not_trusted_beside_brighter_neighbours() {
        // Sixteen samples in shadow, like the centre, beside lit neighbours: a lit sliver may
        // have slipped between them.
        let blind = Verdict {
            change: 0.0,
            halves_differ: 0.0,
            mean: 0.0,
        };
        assert!(blind.first_round_suspect(&pixel(0.15, 0.0), 0.004));
        // The same samples where the neighbourhood is as dark are trusted.
        assert!(!blind.first_round_suspect(&pixel(0.002, 0.0), 0.004));
        // Samples that moved the estimate were not blind; a modest contrast is then fine…
        let seen = Verdict {
            change: 0.001,
            halves_differ: 0.001,
            mean: 0.1,
        };
        assert!(!seen.first_round_suspect(&pixel(0.15, 0.05), 0.004));
        // …but not a neighbourhood spanning more than HIGH_CONTRAST tolerances.
        assert!(seen.first_round_suspect(&pixel(1.5, 0.05), 0.004));
    }
}
