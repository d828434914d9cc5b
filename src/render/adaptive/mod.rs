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
//!    A pixel that does not refine takes its centre sample corrected for the shading's curvature
//!    by its four neighbours' centres (`smooth_pixel_mean`, exact for quadratic shading).
//! 3. **Refinement**, by the sampler's own rule, to a tolerance of t times the pixel's scale:
//!    the largest of its centre value, a twentieth of its neighbourhood's level and display white
//!    (the radiance 8-bit output shows as white, 2^−exposure): below white the tolerance is
//!    absolute, as the error a viewer and RMSE see is.
//!    - `adaptive` (adaptive.rs): Owen-scrambled Sobol samples in rounds of 16, 64, 256, … until the
//!      pixel's estimate stops moving and the two halves of its samples agree.
//!    - `cells` (cells.rs): a centred 4×4 grid of cells (3×3 for a pixel active only
//!      through the dilation), split 2×2 where a cell's value still jumps against its
//!      neighbours', down to 32×32.
//!
//!    `cells` takes fewer samples for the same error where edges cross pixels at every angle (a
//!    curved glossy mesh); `adaptive` where edges run along the pixel grid and pixels take few
//!    samples (the Cornell box). The comparison: docs/sampling.md, "Sampling", and
//!    docs/performance-log.md.
//!
//! Each decision reads only the pixel's own samples and its neighbours' centre samples, which the
//! apron provides for crops: the image is independent of threads, tiles and crops.

use std::cell::RefCell;
use std::sync::atomic::{AtomicU64, Ordering};

use glam::{Vec2, Vec3};
use rayon::prelude::*;

// Each sampler's refinement in a file named as `--sampler` names it.
#[allow(clippy::module_inception)]
mod adaptive;
mod cells;
mod refine;

use crate::film::{FilmSettings, PixelRect, SamplerKind};
use crate::render::sample_cache::SampleCache;
use crate::render::tile::{
    assemble, block_order, par_tiles, place_tile, tiles, Context, PixelSums, SampleJob, SurfaceSample,
};
use cells::Scratch;
use refine::{ActivePixel, Settings, DARK_FLOOR};

/// Renders `region` adaptively; returns the per-pixel sums and sample counts (row-major).
pub fn render(ctx: &Context, region: PixelRect, on_tile: &(dyn Fn(u64) + Sync)) -> (PixelSums, Vec<u32>) {
    let centres = Centres::new(ctx, region);
    let mut caches: Vec<Option<SampleCache>> = tiles(region).iter().map(|_| None).collect();
    refine(ctx, &centres, ctx.scene.film.adaptive_threshold, &mut caches, on_tile)
}

/// The centre samples of a region and of the two-pixel apron around it: every threshold's
/// activation and refinement reads them, and a time budget's passes share them.
pub struct Centres {
    region: PixelRect,
    apron: PixelRect,
    sums: PixelSums,
}

impl Centres {
    /// One sample at the centre of every pixel of `region` and its apron.
    pub fn new(ctx: &Context, region: PixelRect) -> Self {
        // Bends are needed one pixel around the region (for the dilation), and each needs the
        // centres one pixel further out.
        let apron = grow(&ctx.scene.film, region, 2);
        Self {
            region,
            apron,
            sums: centre_pass(ctx, apron),
        }
    }

    /// Index of pixel (x, y) of the apron in `sums`.
    fn at(&self, x: u32, y: u32) -> usize {
        ((y - self.apron.y0) * self.apron.width() + (x - self.apron.x0)) as usize
    }
}

/// `r` grown by `by` pixels on every side, within the film.
fn grow(film: &FilmSettings, r: PixelRect, by: u32) -> PixelRect {
    PixelRect {
        x0: r.x0.saturating_sub(by),
        y0: r.y0.saturating_sub(by),
        x1: (r.x1 + by).min(film.width),
        y1: (r.y1 + by).min(film.height),
    }
}

/// Refines the region of `centres` at `threshold` (the film's, or a time budget's pass's);
/// returns the per-pixel sums and sample counts (row-major). `caches` holds one entry per tile
/// of the region: where there is a cache, samples are looked up by film position before they
/// are traced, and the ones traced are kept (see `sample_cache::SampleCache`).
pub fn refine(
    ctx: &Context,
    centres: &Centres,
    threshold: f32,
    caches: &mut [Option<SampleCache>],
    on_tile: &(dyn Fn(u64) + Sync),
) -> (PixelSums, Vec<u32>) {
    let film = &ctx.scene.film;
    let white = display_white(film);
    let (region, centre) = (centres.region, &centres.sums);
    let centre_at = |x: u32, y: u32| (centre.radiance[centres.at(x, y)], centre.surface[centres.at(x, y)]);
    let bent_area = grow(film, region, 1);
    // One decision per pixel, in parallel (an indexed collect keeps the row-major order).
    let bent: Vec<Neighbourhood> = (0..bent_area.width() * bent_area.height())
        .into_par_iter()
        .map(|i| {
            let (x, y) = (
                bent_area.x0 + i % bent_area.width(),
                bent_area.y0 + i / bent_area.width(),
            );
            neighbourhood(&centre_at, film, threshold, white, x, y)
        })
        .collect();
    let bent_at = |x: u32, y: u32| bent[((y - bent_area.y0) * bent_area.width() + (x - bent_area.x0)) as usize];
    let active_at = |x: u32, y: u32| {
        let (x0, x1) = (x.saturating_sub(1).max(bent_area.x0), (x + 2).min(bent_area.x1));
        let (y0, y1) = (y.saturating_sub(1).max(bent_area.y0), (y + 2).min(bent_area.y1));
        (y0..y1).any(|ny| (x0..x1).any(|nx| bent_at(nx, ny).bends))
    };
    let naovs = ctx.sampled_aovs;
    let settings = Settings {
        spp: film.spp,
        threshold,
        aovs: naovs,
        seed: film.seed,
        white,
    };
    let done = AtomicU64::new(0);
    let region_tiles = tiles(region);
    let parts: Vec<(PixelSums, Vec<u32>)> = par_tiles(&region_tiles)
        .zip(caches)
        .map(|(t, cache)| {
            let n = (t.width() * t.height()) as usize;
            let mut sums = PixelSums::new(n, naovs);
            let mut counts = vec![1u32; n];
            // Start from the centre samples; collect the pixels that refine, block by block
            // (neighbouring pixels' samples then share camera-ray packets).
            let mut active = Vec::new();
            for (x, y) in block_order(*t) {
                let slot = ((y - t.y0) * t.width() + (x - t.x0)) as usize;
                let a = centres.at(x, y);
                sums.radiance[slot] = centre.radiance[a];
                sums.surface[slot] = centre.surface[a];
                for k in 0..naovs {
                    sums.aovs[k][slot] = centre.aovs[k][a];
                }
                if film.spp == 1 {
                    // Pixel centres asked for: nothing refines, and nothing is corrected.
                } else if !active_at(x, y) {
                    let around = [(-1, 0), (1, 0), (0, -1), (0, 1)]
                        .map(|(dx, dy)| neighbour(film, x, y, dx, dy).map(|(nx, ny)| centres.at(nx, ny)));
                    sums.radiance[slot] = smooth_pixel_mean(&centre.radiance, a, around);
                    for k in 0..naovs {
                        sums.aovs[k][slot] = smooth_pixel_mean(&centre.aovs[k], a, around);
                    }
                } else {
                    let Neighbourhood { level, low, bends } = bent_at(x, y);
                    let c = centre.radiance[a];
                    let beside = [(-1, 0), (1, 0), (0, -1), (0, 1)]
                        .map(|(dx, dy)| neighbour(film, x, y, dx, dy).map(|(nx, ny)| centre_at(nx, ny).0));
                    active.push(ActivePixel {
                        x,
                        y,
                        slot: slot as u32,
                        centre: c,
                        beside,
                        scale: c.max_element().max(DARK_FLOOR * level).max(white),
                        level,
                        low,
                        bends,
                    });
                }
            }
            SCRATCH.with_borrow_mut(|(scratch, surfaces)| {
                let mut traced = |jobs: &[SampleJob], sums: &mut PixelSums| ctx.trace(jobs, sums, surfaces);
                let mut cached;
                let trace: &mut dyn FnMut(&[SampleJob], &mut PixelSums) = match cache {
                    Some(cache) => {
                        cached = |jobs: &[SampleJob], sums: &mut PixelSums| cache.trace(jobs, sums, &mut traced);
                        &mut cached
                    }
                    None => &mut traced,
                };
                if film.sampler == SamplerKind::Cells {
                    cells::refine(settings, &active, &mut sums, &mut counts, scratch, trace);
                } else {
                    adaptive::refine(settings, &active, &mut sums, &mut counts, trace);
                }
            });
            on_tile(done.fetch_add(1, Ordering::Relaxed) + 1);
            (sums, counts)
        })
        .collect();
    let (parts, count_parts): (Vec<_>, Vec<_>) = parts.into_iter().unzip();
    let sums = assemble(region, &region_tiles, parts, naovs);
    let mut counts = vec![0u32; (region.width() * region.height()) as usize];
    for (t, c) in region_tiles.iter().zip(count_parts) {
        place_tile(region, t, &c, &mut counts);
    }
    (sums, counts)
}

thread_local! {
    /// Each thread's refinement buffers (the cells', and the traced samples both samplers use),
    /// kept from tile to tile: `map_init` would make them anew for nearly every tile (each tile
    /// is its own job, see `par_tiles`), and they would grow again each time, in `realloc`.
    static SCRATCH: RefCell<(Scratch, Vec<SurfaceSample>)> = RefCell::default();
}

/// The mean over a pixel that does not refine, from its centre sample `values[a]` and its four
/// neighbours' (`around`: left, right, up, down, where they lie on the film). The centre alone is
/// the midpoint rule, which errs by (h²/24)·(f_xx + f_yy) over a pixel of side h; along each axis
/// with both neighbours, the second difference of the three centres estimates h²·f'' and its
/// 24th is added. The result is a blur with positive weights (20/24 for the centre, 1/24 per
/// neighbour): it cannot overshoot its samples, and NaN-free samples give a NaN-free mean.
/// Exact for quadratic shading; a pixel whose neighbourhood bends or changes surface refines
/// instead (`neighbourhood`), so the samples used here lie on one smooth surface. It lowers the
/// one-sample pixels' error without a sample more (README, "Where the error sits";
/// docs/performance-log.md).
fn smooth_pixel_mean(values: &[Vec3], a: usize, around: [Option<usize>; 4]) -> Vec3 {
    let c = values[a];
    let mut v = c;
    for (n0, n1) in [(around[0], around[1]), (around[2], around[3])] {
        if let (Some(n0), Some(n1)) = (n0, n1) {
            v += (values[n0] + values[n1] - 2.0 * c) / 24.0;
        }
    }
    v
}

/// One sample at the centre of every pixel of `rect`.
fn centre_pass(ctx: &Context, rect: PixelRect) -> PixelSums {
    let naovs = ctx.sampled_aovs;
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
/// and the neighbourhood's level.
fn neighbourhood(
    centre: &impl Fn(u32, u32) -> (Vec3, u32),
    film: &FilmSettings,
    threshold: f32,
    white: f32,
    x: u32,
    y: u32,
) -> Neighbourhood {
    let (c, surface) = centre(x, y);
    let at = |dx: i32, dy: i32| neighbour(film, x, y, dx, dy).map(|(nx, ny)| centre(nx, ny));
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
        bends: other_surface || bend > threshold * level.max(white),
        level,
        low,
    }
}

/// Pixel (x + dx, y + dy), if it lies on the film.
fn neighbour(film: &FilmSettings, x: u32, y: u32, dx: i32, dy: i32) -> Option<(u32, u32)> {
    let (nx, ny) = (x.checked_add_signed(dx)?, y.checked_add_signed(dy)?);
    (nx < film.width && ny < film.height).then_some((nx, ny))
}

/// The radiance shown as white on 8-bit output (2^−exposure): below it the adaptive tolerances are
/// absolute, as the error a viewer (and RMSE) sees is. A dim scene exposed up for viewing gets
/// proportionally tighter tolerances.
fn display_white(film: &FilmSettings) -> f32 {
    (-film.exposure).exp2()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Quadratic shading f(x, y) and its exact mean over the pixel [x, x+1] × [y, y+1].
    fn quadratic(x: f32, y: f32) -> f32 {
        0.3 + 0.1 * x - 0.05 * y + 0.02 * x * x - 0.03 * y * y + 0.01 * x * y
    }
    fn exact_mean(x: f32, y: f32) -> f32 {
        // ∫₀¹ (x+s)² ds = x² + x + 1/3; the cross term's mean is (x + ½)(y + ½).
        0.3 + 0.1 * (x + 0.5) - 0.05 * (y + 0.5) + 0.02 * (x * x + x + 1.0 / 3.0) - 0.03 * (y * y + y + 1.0 / 3.0)
            + 0.01 * (x + 0.5) * (y + 0.5)
    }

    /// The centre samples of pixels (x, y) with x, y in 0..3, row-major, as values.
    fn centres() -> Vec<Vec3> {
        (0..9)
            .map(|i| Vec3::splat(quadratic((i % 3) as f32 + 0.5, (i / 3) as f32 + 0.5)))
            .collect()
    }

    #[test]
    fn a_smooth_pixels_mean_is_exact_for_quadratic_shading() {
        let values = centres();
        let around = [Some(3), Some(5), Some(1), Some(7)];
        let mean = smooth_pixel_mean(&values, 4, around).x;
        let exact = exact_mean(1.0, 1.0);
        assert!((mean - exact).abs() < 1e-6, "{mean} against {exact}");
        let centre_error = (values[4].x - exact).abs();
        assert!(centre_error > 1e-4, "the centre alone errs: {centre_error}");
    }

    #[test]
    fn at_the_films_border_only_axes_with_both_neighbours_are_corrected() {
        let values = centres();
        // Pixel (0, 1) has no left neighbour: x keeps the midpoint rule, y is corrected.
        let mean = smooth_pixel_mean(&values, 3, [None, Some(4), Some(0), Some(6)]).x;
        let x_error = 0.02 / 12.0; // the midpoint rule's error on 0.02·x²
        assert!((mean - (exact_mean(0.0, 1.0) - x_error)).abs() < 1e-6, "{mean}");
        // Without neighbours, the centre.
        assert_eq!(smooth_pixel_mean(&values, 3, [None; 4]), values[3]);
    }
}
