//! Rendering to a time budget: passes that add samples to every pixel.
//!
//! Pass 1 takes every pixel's sample 0; each later pass doubles the samples taken, up to the
//! film's spp, if it is expected to end within the budget. If it is not, the pass takes half as
//! many, or a quarter, down to one sample per pixel, whichever is the largest expected to fit;
//! if none fits, the render ends. Counts are powers of two, so every shrunk pass has the count
//! of an earlier one, whose measured time is its prediction; a doubling pass is predicted as
//! twice the last one (per sample, later passes cost the same or less: more of a pixel block's
//! rays share a packet). The first pass always runs, so there is always an image.
//!
//! Each pixel adds its samples in index order, and a progressive sampler's first n samples are
//! the same whatever the count (`SamplerKind::is_progressive`). So the image is, bit for bit,
//! the fixed render at the count reached (`--spp n`): the budget decides only the count. The
//! count depends on the machine; the image for a given count does not.

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use rayon::prelude::*;

use super::tile::{Context, PixelSums};
use super::{tile_samples, tiles};
use crate::film::PixelRect;

/// One finished pass: samples per pixel and wall time.
pub(super) type Pass = (u32, Duration);

/// The sample count of the next pass, with `taken` samples per pixel taken by the `passes` so
/// far (the first one included) and `remaining` before the deadline: the largest power of two
/// up to `taken` and to `spp − taken` whose predicted time is below `remaining`, or `None`.
/// A count is predicted from the latest pass with the largest count not above it, scaled.
pub(super) fn next_pass(taken: u32, spp: u32, passes: &[Pass], remaining: Duration) -> Option<u32> {
    let most = taken.min(spp.saturating_sub(taken));
    if most == 0 {
        return None;
    }
    let mut count = 1 << most.ilog2();
    loop {
        // The first pass took one sample, so a pass with a count not above `count` exists;
        // among equal counts `max_by_key` gives the last, the latest pass.
        let &(c, time) = passes.iter().filter(|p| p.0 <= count).max_by_key(|p| p.0)?;
        if time.mul_f64(count as f64 / c as f64) < remaining {
            return Some(count);
        }
        if count == 1 {
            return None;
        }
        count /= 2;
    }
}

/// Renders `region` in passes until the film's spp or `deadline`; returns the per-pixel sums
/// and the samples each pixel took (the same for all).
pub(super) fn render(
    ctx: &Context,
    region: PixelRect,
    deadline: Instant,
    on_tile: &(dyn Fn(u64) + Sync),
) -> (PixelSums, u32) {
    let spp = ctx.scene.film.spp;
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
        // One tile per job, as `par_tiles`: an idle thread steals any tile not yet started.
        tiles.par_iter().zip(&mut parts).with_max_len(1).for_each(|(t, sums)| {
            tile_samples(ctx, *t, taken, count, sums);
            on_tile(done.fetch_add(1, Ordering::Relaxed) + 1);
        });
        let now = Instant::now();
        taken += count;
        passes.push((count, now - start));
        match next_pass(taken, spp, &passes, deadline.saturating_duration_since(now)) {
            Some(next) => count = next,
            None => break,
        }
    }
    (super::assemble(region, &tiles, parts, naovs), taken)
}

#[cfg(test)]
mod tests {
    use super::*;

    const MS: Duration = Duration::from_millis(1);

    /// The counts of the passes a render with `spp` takes when a pass of n samples takes
    /// `cost(n)` and the budget is `budget`.
    fn passes(spp: u32, budget: Duration, cost: impl Fn(u32) -> Duration) -> Vec<u32> {
        let mut passes = vec![(1, cost(1))];
        let mut elapsed = cost(1);
        let mut taken = 1;
        while let Some(count) = next_pass(taken, spp, &passes, budget.saturating_sub(elapsed)) {
            passes.push((count, cost(count)));
            elapsed += cost(count);
            taken += count;
        }
        passes.iter().map(|p| p.0).collect()
    }

    #[test]
    fn passes_double_the_samples_up_to_the_cap() {
        let counts = passes(12, Duration::from_secs(3600), |n| n * MS);
        assert_eq!(counts, [1, 1, 2, 4, 4]);
        assert_eq!(counts.iter().sum::<u32>(), 12);
    }

    #[test]
    fn the_last_passes_shrink_to_what_fits_the_budget() {
        // 1 ms per sample per pixel, 100 ms: 1 + 1 + 2 + 4 + 8 + 16 + 32 = 64 ms; 64 more do not
        // fit in the 36 left, 32 do not (32 < 36 does: 96 ms), then 2 (98), then 1 (99).
        assert_eq!(passes(4096, 100 * MS, |n| n * MS), [1, 1, 2, 4, 8, 16, 32, 32, 2, 1]);
        // Past the deadline nothing more starts, however fast the passes were.
        assert_eq!(next_pass(1, 64, &[(1, Duration::ZERO)], Duration::ZERO), None);
    }

    #[test]
    fn a_pass_is_predicted_from_the_latest_pass_of_its_count_or_below() {
        let history = [(1, 9 * MS), (1, 3 * MS), (2, 5 * MS), (4, 10 * MS)];
        // Doubling to 8 (taken 8): twice the last pass, 20 ms.
        assert_eq!(next_pass(8, 64, &history, 21 * MS), Some(8));
        // 20 ms left: 8 does not fit; 4 is predicted by the pass of 4 (10 ms).
        assert_eq!(next_pass(8, 64, &history, 20 * MS), Some(4));
        assert_eq!(next_pass(8, 64, &history, 10 * MS), Some(2));
        // A count of 1 is predicted by the latest pass of one (3 ms), not the first (9 ms).
        assert_eq!(next_pass(8, 64, &history, 4 * MS), Some(1));
        assert_eq!(next_pass(8, 64, &history, 3 * MS), None);
        // The cap: 4 more to 12, predicted by the pass of 4.
        assert_eq!(next_pass(8, 12, &history, 11 * MS), Some(4));
        assert_eq!(next_pass(12, 12, &history, Duration::MAX), None);
    }
}
