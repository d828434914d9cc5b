//! Rendering to a time budget: passes that add samples to every pixel (sobol, independent) or
//! refine at a finer threshold (adaptive, cells) while the next pass is predicted to end in time.
//! The first pass always runs, so there is always an image.
//!
//! **Samples.** Pass 1 takes every pixel's sample 0; each later pass doubles the samples taken,
//! up to the film's spp, or else takes the largest power of two that is predicted to fit
//! ([`next_pass`]); if none fits, the render ends. A shrunk pass has the count of an earlier
//! one, whose time predicts it; a doubling pass is predicted as twice the last one (per sample,
//! later passes cost the same or less: more of a pixel block's rays share a packet).
//!
//! Each pixel adds its samples in index order, and a progressive sampler's first n samples are
//! the same whatever the count (`SamplerKind::takes_time_budget`), so the image is, bit for bit,
//! the fixed render at the count reached (`--spp n`). The machine decides only the count.
//!
//! **Thresholds.** An adaptive render is a whole render at each threshold of a ladder halving
//! down to the film's (`render_adaptive`). A sample is a pure function of its film position and
//! a finer threshold revisits nearly every position a coarser one took, so each tile keeps its
//! samples by position ([`SampleCache`]) and traces only new ones. The image is bit for bit the
//! render at the threshold reached.

use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use rayon::prelude::*;

use super::adaptive::{self, Centres};
use super::sample_cache::SampleCache;
use super::tile::{par_tiles, tile_samples, tiles, Context, PixelSums};
use crate::film::sampler::Sequence;
use crate::film::PixelRect;

/// One finished pass: samples per pixel and wall time.
pub(super) type Pass = (u32, Duration);

/// The sample count of the next pass, with `taken` samples per pixel taken by the `passes` so
/// far (the first one included) and `remaining` before the deadline: the largest power of two
/// up to `taken` and to `spp − taken` whose predicted time is below `remaining`, or `None`.
/// A count is predicted from the latest pass with the largest count not above it, scaled.
///
/// With `sobol`, the totals stay at 2^k or 3·2^(k−1): from 2^k a pass of 2^k or 2^(k−1), from
/// 3·2^(k−1) only one of 2^(k−1), back to a power of two. Owen-scrambled Sobol points are
/// balanced in blocks of powers of two, and a total whose last block is small is worse than
/// the power of two below it (docs/sampling.md, "Time budgets").
pub(super) fn next_pass(taken: u32, spp: u32, passes: &[Pass], remaining: Duration, sobol: bool) -> Option<u32> {
    let mut most = taken.min(spp.saturating_sub(taken));
    let mut least = 1;
    if sobol {
        let last_block = taken & taken.wrapping_neg();
        most = most.min(last_block);
        least = if taken.is_power_of_two() {
            (taken / 2).max(1)
        } else {
            last_block
        };
    }
    if most == 0 {
        return None;
    }
    let mut count = 1 << most.ilog2();
    while count >= least {
        // The first pass took one sample, so a pass with a count not above `count` exists;
        // among equal counts `max_by_key` gives the last, the latest pass.
        let &(c, time) = passes.iter().filter(|p| p.0 <= count).max_by_key(|p| p.0)?;
        if time.mul_f64(count as f64 / c as f64) < remaining {
            return Some(count);
        }
        count /= 2;
    }
    None
}

/// Renders `region` in passes until the film's spp or `deadline`; returns the per-pixel sums
/// and the samples each pixel took (the same for all).
pub(super) fn render(
    ctx: &Context,
    sequence: Sequence,
    region: PixelRect,
    deadline: Instant,
    on_tile: &(dyn Fn(u64) + Sync),
) -> (PixelSums, u32) {
    let spp = ctx.scene.film.spp;
    let sobol = sequence == Sequence::Sobol;
    let naovs = ctx.sampled_aovs;
    let tiles = tiles(region);
    let mut parts: Vec<PixelSums> = tiles
        .iter()
        .map(|t| PixelSums::new((t.width() * t.height()) as usize, naovs))
        .collect();
    let done = AtomicU64::new(0);
    let mut passes: Vec<Pass> = Vec::new();
    let (mut taken, mut count) = (0, 1);
    loop {
        let start = Instant::now();
        par_tiles(&tiles).zip(&mut parts).for_each(|(t, sums)| {
            tile_samples(ctx, sequence, *t, taken, count, sums);
            on_tile(done.fetch_add(1, Ordering::Relaxed) + 1);
        });
        let now = Instant::now();
        taken += count;
        passes.push((count, now - start));
        match next_pass(taken, spp, &passes, deadline.saturating_duration_since(now), sobol) {
            Some(next) => count = next,
            None => break,
        }
    }
    (super::assemble(region, &tiles, parts, naovs), taken)
}

/// The coarsest threshold an adaptive render to a time budget starts from (or the film's, if
/// coarser). Its pass always runs, so it sets what the smallest budget costs (its samples
/// against a fine threshold's: docs/performance-log.md).
pub const COARSEST_THRESHOLD: f32 = 0.04;

/// The thresholds of an adaptive render's passes, coarse to fine, ending at `finest`: `finest`
/// times the powers of two from the largest not above `COARSEST_THRESHOLD` down to one.
pub fn threshold_ladder(finest: f32) -> Vec<f32> {
    let mut ladder = vec![finest];
    while ladder[0] * 2.0 <= COARSEST_THRESHOLD {
        ladder.insert(0, ladder[0] * 2.0);
    }
    ladder
}

/// Samples the passes of one adaptive render keep, at most: a bound of about 500 MB on the
/// tables (their index and arrays grow by doubling; more with AOVs; the bytes per sample:
/// docs/performance-log.md). Past it, samples are traced without being kept: the image is the
/// same, the passes slower.
const MAX_KEPT_SAMPLES: usize = 1 << 23;

/// The predicted time of the next adaptive pass, a rung finer than the last of `passes` (their
/// wall times). The first pass traces every sample it needs; later ones mostly reuse them and
/// trace only what the finer threshold adds. So: the second as long as the first, the third
/// 1.5× the second, then the last scaled by its growth over the one before, within 1× to 3×
/// (the ratios passes take: docs/performance-log.md).
fn next_adaptive_pass(passes: &[Duration]) -> Duration {
    match passes {
        [] => Duration::ZERO,
        [first] => *first,
        [_, second] => second.mul_f64(1.5),
        [.., previous, last] => last.mul_f64((last.as_secs_f64() / previous.as_secs_f64()).clamp(1.0, 3.0)),
    }
}

/// How much an adaptive render's time grows from one rung of the ladder to the next finer one,
/// as predicted. Typical, not a bound: it varies by scene, and on some speeds up at fine
/// thresholds (docs/sampling.md, "Time budgets"; docs/performance-log.md).
const RUNG_GROWTH: f64 = 1.5;

/// What a pass straight to a finer rung costs over the render at that threshold alone: it also
/// fills the tiles' sample tables (docs/performance-log.md).
const JUMP_OVERHEAD: f64 = 1.1;

/// How many rungs down the ladder the pass after the first (which took `first`) goes: 1, rung
/// by rung, or k > 1, straight to a threshold k rungs finer; `None` when not even the next rung
/// is predicted to end within `remaining`. Rung by rung, the next pass is predicted by
/// [`next_adaptive_pass`] and each after it by [`RUNG_GROWTH`]; a jump of k rungs as a render at
/// that threshold from scratch plus its tables, `first` × 1.5^k × [`JUMP_OVERHEAD`], since it
/// reuses nothing of the rungs skipped and little of the first. It jumps when that reaches
/// finer, or reaches the film's threshold (two rungs or more away) sooner: rung by rung, each
/// pass repeats the decisions of the one before, so the jump costs less in all
/// (docs/performance-log.md).
fn rungs_after_first(first: Duration, remaining: Duration, rungs_left: usize) -> Option<usize> {
    let mut step = next_adaptive_pass(&[first]);
    let mut by_steps = 0;
    let mut spent = Duration::ZERO;
    while by_steps < rungs_left && spent + step < remaining {
        spent += step;
        step = step.mul_f64(RUNG_GROWTH);
        by_steps += 1;
    }
    // In f64 seconds: a ladder down to a tiny threshold has over a hundred rungs, and 1.5^k
    // times the first pass would overflow a `Duration` (f64 holds 1.5^1750).
    let by_jump = (1..=rungs_left)
        .rev()
        .find(|&k| first.as_secs_f64() * RUNG_GROWTH.powi(k as i32) * JUMP_OVERHEAD < remaining.as_secs_f64())
        .unwrap_or(0);
    // A tie short of the film's threshold goes rung by rung: each pass re-predicts from the
    // last one measured, and passes that reuse samples often end sooner than predicted.
    if by_jump > by_steps || (by_jump == rungs_left && by_jump >= 2) {
        Some(by_jump)
    } else {
        (by_steps > 0).then_some(1)
    }
}

/// Renders `region` adaptively to `deadline`: a full adaptive render at the ladder's coarsest
/// threshold (down to the film's), which always runs; then one pass straight to a finer
/// threshold if [`rungs_after_first`] predicts it reaches further; then rung by rung while
/// [`next_adaptive_pass`] predicts the next pass to end in time. Returns the sums and counts of
/// the finest pass that ran, and its threshold: bit for bit the render with that
/// `adaptive_threshold`.
pub(super) fn render_adaptive(
    ctx: &Context,
    region: PixelRect,
    deadline: Instant,
    on_tile: &(dyn Fn(u64) + Sync),
) -> (PixelSums, Vec<u32>, f32) {
    let room = AtomicUsize::new(MAX_KEPT_SAMPLES);
    let mut caches: Vec<Option<SampleCache>> = tiles(region).iter().map(|_| Some(SampleCache::new(&room))).collect();
    let centres = Centres::new(ctx, region);
    let ladder = threshold_ladder(ctx.scene.film.adaptive_threshold);
    let mut passes = Vec::new();
    let mut rung = 0;
    loop {
        let start = Instant::now();
        let pass = adaptive::refine(ctx, &centres, ladder[rung], &mut caches, on_tile);
        passes.push(start.elapsed());
        let remaining = deadline.saturating_duration_since(Instant::now());
        let rungs_left = ladder.len() - 1 - rung;
        // A jump only from the first pass: 1.5× per rung is typical, not a bound, and a chain of
        // jumps would compound the error where the growth speeds up (docs/sampling.md, "Time budgets").
        let next = if rung == 0 {
            rungs_after_first(passes[0], remaining, rungs_left)
        } else {
            (rungs_left > 0 && next_adaptive_pass(&passes) < remaining).then_some(1)
        };
        match next {
            Some(rungs) => {
                rung += rungs;
                // A pass straight to a finer rung traces nearly all it needs, as a first pass
                // does: the passes after it are predicted from it alone.
                if rungs > 1 {
                    passes.clear();
                }
            }
            None => {
                let (sums, counts) = pass;
                return (sums, counts, ladder[rung]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MS: Duration = Duration::from_millis(1);

    /// The counts of the passes a render with `spp` takes when a pass of n samples takes
    /// `cost(n)` and the budget is `budget`.
    fn passes(spp: u32, budget: Duration, sobol: bool, cost: impl Fn(u32) -> Duration) -> Vec<u32> {
        let mut passes = vec![(1, cost(1))];
        let mut elapsed = cost(1);
        let mut taken = 1;
        while let Some(count) = next_pass(taken, spp, &passes, budget.saturating_sub(elapsed), sobol) {
            passes.push((count, cost(count)));
            elapsed += cost(count);
            taken += count;
        }
        passes.iter().map(|p| p.0).collect()
    }

    #[test]
    fn the_threshold_ladder_halves_from_the_coarsest_down_to_the_finest() {
        assert_eq!(threshold_ladder(0.01), [0.04, 0.02, 0.01]);
        assert_eq!(threshold_ladder(0.0075), [0.03, 0.015, 0.0075]);
        assert_eq!(threshold_ladder(0.05), [0.05]);
        let finest = 1.0 / 1024.0;
        assert_eq!(
            threshold_ladder(finest),
            [32.0, 16.0, 8.0, 4.0, 2.0, 1.0].map(|k| k * finest)
        );
    }

    #[test]
    fn an_adaptive_pass_is_predicted_from_the_growth_of_the_last_two() {
        // The second as long as the first, the third 1.5× the second.
        assert_eq!(next_adaptive_pass(&[100 * MS]), 100 * MS);
        assert_eq!(next_adaptive_pass(&[100 * MS, 60 * MS]), 90 * MS);
        // Then the growth of the last two, within 1× and 3×.
        assert_eq!(
            next_adaptive_pass(&[100 * MS, 50 * MS, 75 * MS]),
            Duration::from_micros(112_500)
        );
        assert_eq!(next_adaptive_pass(&[100 * MS, 80 * MS, 60 * MS]), 60 * MS);
        assert_eq!(next_adaptive_pass(&[100 * MS, 10 * MS, 60 * MS]), 180 * MS);
    }

    #[test]
    fn after_the_first_pass_a_render_jumps_when_that_reaches_a_finer_rung() {
        // Rung by rung the passes are predicted 100, 150, 225, 337.5 ms (cumulative 100, 250,
        // 475, 812.5); straight to k rungs finer, 165, 247.5, 371.25, 556.875 ms for k = 1 … 4.
        let first = 100 * MS;
        assert_eq!(rungs_after_first(first, 99 * MS, 5), None);
        assert_eq!(rungs_after_first(first, 101 * MS, 5), Some(1));
        // 249 ms: two rungs straight (247.5) against one rung by rung (100 + 150 > 249).
        assert_eq!(rungs_after_first(first, 249 * MS, 5), Some(2));
        // 260 ms: two either way (100 + 150; 247.5), so rung by rung, which reuses more.
        assert_eq!(rungs_after_first(first, 260 * MS, 5), Some(1));
        assert_eq!(rungs_after_first(first, 600 * MS, 5), Some(4));
        // Never past the film's threshold.
        assert_eq!(rungs_after_first(first, 10_000 * MS, 5), Some(5));
        assert_eq!(rungs_after_first(first, 10_000 * MS, 0), None);
        // A ladder down to the smallest f32 (about 150 rungs) predicts without overflowing:
        // 100 ms × 1.5^11 × 1.1 < 10 s < 100 ms × 1.5^12 × 1.1.
        let rungs = threshold_ladder(f32::from_bits(1)).len() - 1;
        assert!(rungs > 140);
        assert_eq!(rungs_after_first(first, 10_000 * MS, rungs), Some(11));
    }

    #[test]
    fn passes_double_the_samples_up_to_the_cap() {
        for sobol in [false, true] {
            let counts = passes(12, Duration::from_secs(3600), sobol, |n| n * MS);
            assert_eq!(counts, [1, 1, 2, 4, 4]);
            assert_eq!(counts.iter().sum::<u32>(), 12);
        }
    }

    #[test]
    fn the_last_passes_shrink_to_what_fits_the_budget() {
        // 1 ms per sample per pixel, 100 ms: 1 + 1 + 2 + 4 + 8 + 16 + 32 = 64 ms; 64 more do not
        // fit in the 36 left, 32 do not (32 < 36 does: 96 ms), then 2 (98), then 1 (99).
        assert_eq!(
            passes(4096, 100 * MS, false, |n| n * MS),
            [1, 1, 2, 4, 8, 16, 32, 32, 2, 1]
        );
        // Past the deadline nothing more starts, however fast the passes were.
        assert_eq!(next_pass(1, 64, &[(1, Duration::ZERO)], Duration::ZERO, false), None);
    }

    #[test]
    fn sobol_totals_stay_at_powers_of_two_or_one_and_a_half_times_one() {
        // As above, but the 2 and the 1 would end on small blocks: 96 = 3 · 32 it is.
        assert_eq!(passes(4096, 100 * MS, true, |n| n * MS), [1, 1, 2, 4, 8, 16, 32, 32]);
        // 80 ms: 64 taken, 16 ms left; a pass of 16 would fit but end on 80 = 5 · 16.
        assert_eq!(passes(4096, 80 * MS, true, |n| n * MS), [1, 1, 2, 4, 8, 16, 32]);
        let history = [(1, MS), (1, MS), (2, 2 * MS), (4, 4 * MS), (8, 8 * MS), (16, 16 * MS)];
        // From 48 = 3 · 16: only 16 more, back to 64, and never 32 (80).
        assert_eq!(next_pass(48, 4096, &history, Duration::MAX, true), Some(16));
        assert_eq!(next_pass(48, 4096, &history, 16 * MS, true), None);
        // The cap: 100 from 64 takes 32 (96), not 36.
        assert_eq!(next_pass(64, 100, &history, Duration::MAX, true), Some(32));
        assert_eq!(next_pass(96, 100, &history, Duration::MAX, true), None);
    }

    #[test]
    fn a_pass_is_predicted_from_the_latest_pass_of_its_count_or_below() {
        let history = [(1, 9 * MS), (1, 3 * MS), (2, 5 * MS), (4, 10 * MS)];
        // Doubling to 8 (taken 8): twice the last pass, 20 ms.
        assert_eq!(next_pass(8, 64, &history, 21 * MS, false), Some(8));
        // 20 ms left: 8 does not fit; 4 is predicted by the pass of 4 (10 ms).
        assert_eq!(next_pass(8, 64, &history, 20 * MS, false), Some(4));
        assert_eq!(next_pass(8, 64, &history, 10 * MS, false), Some(2));
        // A count of 1 is predicted by the latest pass of one (3 ms), not the first (9 ms).
        assert_eq!(next_pass(8, 64, &history, 4 * MS, false), Some(1));
        assert_eq!(next_pass(8, 64, &history, 3 * MS, false), None);
        // The cap: 4 more to 12, predicted by the pass of 4.
        assert_eq!(next_pass(8, 12, &history, 11 * MS, false), Some(4));
        assert_eq!(next_pass(12, 12, &history, Duration::MAX, false), None);
    }
}
