//! The `cells` sampler's refinement of an active pixel, by subdividing it: a centred 4×4 grid of cells first, then each
//! cell whose value still jumps against a neighbour's is split into 2×2 cells, each sampled at
//! its centre, down to 32×32 cells (the film's spp caps the samples). The pixel's value is the
//! area-weighted mean of its leaf cells.
//!
//! A pixel that refines only because the centre values bend at a neighbour (the activation's
//! one-pixel dilation), not at itself, starts with a 3×3 grid (then 6×6, 12×12, 24×24): its
//! neighbours' centres lie on a straight line through its own in every direction, so an edge
//! inside it is unlikely and nearly all such pixels stop at the first grid, which then costs
//! fewer samples for the same RMSE. A 2×2 first grid saves more at coarse thresholds but loses
//! at fine ones, its midpoint rule being less accurate on curved shading (docs/sampling.md,
//! "Adaptive sampling"; docs/performance-log.md).
//!
//! Why cells rather than more points spread over the whole pixel: the error left in an active
//! pixel is nearly all where an edge (silhouette, shadow boundary) crosses it. A grid of side g
//! estimates the covered area to within about one cell along the edge, and only those ~2g cells
//! need the next level, so the samples go to the edge alone; a smooth region's cells agree and stop.
//!
//! A cell at grid side g is split when `range · g^−1.5 > tolerance`, with `range` the largest
//! jump from its value to its four neighbours' (the neighbour cell at the same level, or the
//! sampled cell that covers it; at the first level, across the pixel's border, the neighbouring
//! pixel's centre sample) and to its parent's sample, which sits at its corner (a feature the
//! parent saw and all four children missed lies between them). The g^−1.5 is the error an edge
//! leaves in a pixel: ~2g cells along it, each off by up to a cell's area (g^−2) times the jump,
//! with signs that mostly cancel (√(2g)). Jumps, not second differences: a steep smooth gradient
//! splits too, but the second-difference rule, though it takes fewer samples at equal error, is
//! no faster (the samples it saves are the cheap ones; docs/performance-log.md).
//!
//! Every position is a cell centre, fixed by the pixel and the decisions: no seed, and the image
//! does not depend on threads, tiles or crops. The price of a regular grid: an edge that runs
//! along the pixel grid puts the same error in every cell it crosses (no cancelling), and a
//! sliver thinner than a cell can pass between the centres. On the Cornell box, whose edges all
//! run so, the Sobol rounds of `adaptive` do better at low sample counts (README).

use glam::{Vec2, Vec3};

use super::refine::{ActivePixel, Settings};
use crate::render::tile::{PixelSums, SampleJob};

/// Side of the first grid (16 cells, one packet of rays) when the film allows 16 samples.
const FIRST_SIDE: u32 = 4;
/// Side of the first grid of a pixel that refines only for its neighbours' sake.
const FIRST_SIDE_DILATED: u32 = 3;
/// Levels of the hierarchy: 4×4, 8×8, 16×16, 32×32 cells.
const LEVELS: usize = 4;

/// One pixel's cells, level by level: `start[l]` indexes the first of the level's g² cells in
/// the tile's arena (`None` until a cell at that level is sampled).
#[derive(Clone, Copy)]
struct Cells {
    start: [Option<u32>; LEVELS],
    taken: u32,
    /// Side of this pixel's first grid.
    first: u32,
}

/// A tile's cells and work lists; reused between tiles by one thread.
#[derive(Default)]
pub struct Scratch {
    /// Each cell's sample, and whether it has one, in the order `Cells::start` indexes.
    radiance: Vec<Vec3>,
    sampled: Vec<bool>,
    /// Per AOV, each cell's sample (same indices as `radiance`).
    aovs: Vec<Vec<Vec3>>,
    pixels: Vec<Cells>,
    /// Cells to sample at the current level: (pixel, cx, cy), pixel by pixel.
    queue: Vec<(u32, u16, u16)>,
    next: Vec<(u32, u16, u16)>,
    jobs: Vec<SampleJob>,
    /// A level's cells of one pixel with their split scores.
    candidates: Vec<(f32, u16, u16)>,
}

impl Scratch {
    /// Arena index of cell (cx, cy) at `level` of pixel `k`, if that level has cells.
    fn index(&self, k: usize, level: usize, cx: u32, cy: u32) -> Option<usize> {
        let start = self.pixels[k].start[level]?;
        Some((start + cy * (self.pixels[k].first << level) + cx) as usize)
    }

    /// The sample of cell (cx, cy) at `level` of pixel `k`, or of the sampled cell that covers
    /// it (every first-level cell is sampled).
    fn value(&self, k: usize, level: usize, cx: u32, cy: u32) -> Vec3 {
        for l in (0..=level).rev() {
            let shift = level - l;
            match self.index(k, l, cx >> shift, cy >> shift) {
                Some(i) if self.sampled[i] => return self.radiance[i],
                _ => {}
            }
        }
        Vec3::ZERO
    }

    /// Whether cell (cx, cy) at `level` of pixel `k` was split (its children were sampled).
    fn split(&self, k: usize, level: usize, cx: u32, cy: u32) -> bool {
        level + 1 < LEVELS
            && self
                .index(k, level + 1, 2 * cx, 2 * cy)
                .is_some_and(|i| self.sampled[i])
    }

    /// The area-weighted mean of `values` (the radiance arena or an AOV's) over the leaf cells
    /// of pixel `k`: the pixel's estimate.
    fn leaf_mean(&self, k: usize, values: &[Vec3]) -> Vec3 {
        let mut sum = Vec3::ZERO;
        // Levels are made in order: the first without cells has none deeper.
        for (level, start) in self.pixels[k].start.iter().map_while(|s| *s).enumerate() {
            let g = self.pixels[k].first << level;
            let area = 1.0 / (g * g) as f32;
            for cy in 0..g {
                for cx in 0..g {
                    let i = (start + cy * g + cx) as usize;
                    if self.sampled[i] && !self.split(k, level, cx, cy) {
                        sum += values[i] * area;
                    }
                }
            }
        }
        sum
    }

    /// The largest jump (largest channel) from cell (cx, cy) at `level` of pixel `k` to its four
    /// neighbours — at the first level, across the pixel's border, to the neighbouring pixel's
    /// centre — and to the sample of the cell it was split from.
    fn jump(&self, k: usize, p: &ActivePixel, level: usize, cx: u32, cy: u32) -> f32 {
        let g = (self.pixels[k].first << level) as i32;
        let v = self.value(k, level, cx, cy);
        let mut jump = 0.0f32;
        for (side, (dx, dy)) in [(-1, 0), (1, 0), (0, -1), (0, 1)].into_iter().enumerate() {
            let (nx, ny) = (cx as i32 + dx, cy as i32 + dy);
            let neighbour = if nx >= 0 && ny >= 0 && nx < g && ny < g {
                Some(self.value(k, level, nx as u32, ny as u32))
            } else if level == 0 {
                p.beside[side]
            } else {
                None
            };
            if let Some(n) = neighbour {
                jump = jump.max((v - n).abs().max_element());
            }
        }
        // The parent's sample lies at this cell's corner: a feature it saw that all four
        // children missed lies between them.
        if level > 0 {
            jump = jump.max((v - self.value(k, level - 1, cx / 2, cy / 2)).abs().max_element());
        }
        jump
    }

    /// Queues (in `next`) the children of the cells of pixel `k` just sampled at `level`
    /// (`cells`) that split, within the film's spp.
    fn split_cells(&mut self, settings: Settings, p: &ActivePixel, k: usize, level: usize, cells: &[(u32, u16, u16)]) {
        let tolerance = settings.threshold * p.scale;
        let weight = ((self.pixels[k].first << level) as f32).powf(-1.5);
        self.candidates.clear();
        let mut blind = true;
        for &(_, cx, cy) in cells {
            let (cx, cy) = (u32::from(cx), u32::from(cy));
            let v = self.value(k, level, cx, cy);
            blind &= (v - p.centre).abs().max_element() <= 1e-6 * v.max_element();
            let score = self.jump(k, p, level, cx, cy) * weight;
            self.candidates.push((score, cx as u16, cy as u16));
        }
        // A first grid that only repeats the centre beside a brighter neighbourhood may have
        // missed a sliver of light between its points: split all of it.
        let suspect = level == 0 && blind && p.level - p.centre.max_element() > tolerance;
        if !suspect {
            self.candidates.retain(|&(score, _, _)| score > tolerance);
        }
        let budget = (settings.spp.saturating_sub(self.pixels[k].taken) / 4) as usize;
        if self.candidates.len() > budget {
            self.candidates.sort_by(|a, b| b.0.total_cmp(&a.0));
            self.candidates.truncate(budget);
        }
        for &(_, cx, cy) in &self.candidates {
            for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                self.next.push((k as u32, 2 * cx + dx, 2 * cy + dy));
            }
        }
    }
}

/// Refines `active` (pixels of one tile) and writes each one's sums (its value times its sample
/// count) and sample count into `sums` and `counts`. `trace` adds each job's sample to its slot
/// (a context's `trace` in a render, an analytic image in the tests).
pub fn refine(
    settings: Settings,
    active: &[ActivePixel],
    sums: &mut PixelSums,
    counts: &mut [u32],
    scratch: &mut Scratch,
    trace: &mut dyn FnMut(&[SampleJob], &mut PixelSums),
) {
    let s = scratch;
    // A bending pixel's first grid: the largest side up to FIRST_SIDE whose square the film's
    // spp allows.
    let first = (1..=FIRST_SIDE).rev().find(|n| n * n <= settings.spp).unwrap_or(1);
    s.radiance.clear();
    s.sampled.clear();
    s.aovs.resize_with(settings.aovs, Vec::new);
    s.aovs.iter_mut().for_each(Vec::clear);
    s.pixels.clear();
    s.queue.clear();
    for (k, p) in active.iter().enumerate() {
        let first = if p.bends { first } else { first.min(FIRST_SIDE_DILATED) };
        s.pixels.push(Cells {
            start: [None; LEVELS],
            taken: 0,
            first,
        });
        let k = k as u32;
        s.queue
            .extend((0..first * first).map(|i| (k, (i % first) as u16, (i / first) as u16)));
    }
    let mut samples = PixelSums::new(0, settings.aovs);
    for level in 0..LEVELS {
        if s.queue.is_empty() {
            break;
        }
        // Sample the queued cells at their centres.
        s.jobs.clear();
        for (i, &(k, cx, cy)) in s.queue.iter().enumerate() {
            let p = &active[k as usize];
            let g = s.pixels[k as usize].first << level;
            let cell = Vec2::new(f32::from(cx) + 0.5, f32::from(cy) + 0.5) / g as f32;
            s.jobs.push(SampleJob {
                slot: i as u32,
                film: Vec2::new(p.x as f32, p.y as f32) + cell,
            });
        }
        samples.reset(s.jobs.len());
        trace(&s.jobs, &mut samples);
        for (i, &(k, cx, cy)) in s.queue.iter().enumerate() {
            let cells = &mut s.pixels[k as usize];
            let g = cells.first << level;
            let start = *cells.start[level].get_or_insert_with(|| {
                let start = s.radiance.len() as u32;
                s.radiance.resize(s.radiance.len() + (g * g) as usize, Vec3::ZERO);
                s.sampled.resize(s.radiance.len(), false);
                for aov in &mut s.aovs {
                    aov.resize(s.radiance.len(), Vec3::ZERO);
                }
                start
            });
            cells.taken += 1;
            let at = (start + u32::from(cy) * g + u32::from(cx)) as usize;
            s.radiance[at] = samples.radiance[i];
            s.sampled[at] = true;
            for (aov, sample) in s.aovs.iter_mut().zip(&samples.aovs) {
                aov[at] = sample[i];
            }
        }
        if level + 1 == LEVELS {
            break;
        }
        s.next.clear();
        let mut queue = std::mem::take(&mut s.queue);
        for cells in queue.chunk_by(|a, b| a.0 == b.0) {
            let k = cells[0].0 as usize;
            s.split_cells(settings, &active[k], k, level, cells);
        }
        queue.clear();
        s.queue = std::mem::replace(&mut s.next, queue);
    }
    for (k, p) in active.iter().enumerate() {
        let (slot, taken) = (p.slot as usize, s.pixels[k].taken);
        counts[slot] = taken;
        sums.radiance[slot] = s.leaf_mean(k, &s.radiance) * taken as f32;
        for (a, aov) in s.aovs.iter().enumerate() {
            sums.aovs[a][slot] = s.leaf_mean(k, aov) * taken as f32;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Refines one pixel at (0, 0) of an analytic image `f` (film position → value), whose own
    /// centre values bend; returns its estimate and sample count.
    fn refine_pixel(spp: u32, threshold: f32, beside: [Option<Vec3>; 4], f: impl Fn(Vec2) -> f32) -> (f32, u32) {
        refine_pixel_bending(true, spp, threshold, beside, f)
    }

    /// [`refine_pixel`] of a pixel whose centre values bend (`bends`) or that refines only
    /// because a neighbour's do.
    fn refine_pixel_bending(
        bends: bool,
        spp: u32,
        threshold: f32,
        beside: [Option<Vec3>; 4],
        f: impl Fn(Vec2) -> f32,
    ) -> (f32, u32) {
        let centre = Vec3::splat(f(Vec2::splat(0.5)));
        let level = beside.iter().flatten().fold(centre.x, |m, v| m.max(v.x));
        let pixel = ActivePixel {
            x: 0,
            y: 0,
            slot: 0,
            centre,
            beside,
            scale: 1.0,
            level,
            low: 0.0,
            bends,
        };
        let (mut sums, mut counts) = (PixelSums::new(1, 1), [0u32]);
        let mut trace = |jobs: &[SampleJob], sums: &mut PixelSums| {
            for job in jobs {
                sums.radiance[job.slot as usize] += Vec3::splat(f(job.film));
                sums.aovs[0][job.slot as usize] += Vec3::splat(2.0 * f(job.film));
            }
        };
        let settings = Settings {
            spp,
            threshold,
            aovs: 1,
            seed: 0,
            white: 1.0,
        };
        refine(
            settings,
            &[pixel],
            &mut sums,
            &mut counts,
            &mut Scratch::default(),
            &mut trace,
        );
        let n = counts[0] as f32;
        assert_eq!(
            sums.aovs[0][0] / n,
            2.0 * sums.radiance[0] / n,
            "AOVs are weighted like radiance"
        );
        (sums.radiance[0].x / n, counts[0])
    }

    /// The share of the unit pixel where `f` is 1, by a 2048×2048 grid.
    fn coverage(f: impl Fn(Vec2) -> f32) -> f32 {
        let n = 2048;
        let hits = (0..n * n)
            .filter(|i| f(Vec2::new((i % n) as f32 + 0.5, (i / n) as f32 + 0.5) / n as f32) > 0.5)
            .count();
        hits as f32 / (n * n) as f32
    }

    /// Light on one side of a slanted line through the pixel.
    fn edge(p: Vec2) -> f32 {
        f32::from(p.x + 0.37 * p.y > 0.61)
    }

    #[test]
    fn a_pixel_whose_cells_agree_stops_at_the_first_grid() {
        let (value, taken) = refine_pixel(256, 0.01, [Some(Vec3::splat(0.3)); 4], |_| 0.3);
        assert_eq!((value, taken), (0.3, 16));
        // A gentle ramp: neighbouring cells differ by 0.1/4, a score of 0.025·4^−1.5 ≈ 0.003.
        let (value, taken) = refine_pixel(256, 0.01, [None; 4], |p| 0.1 * p.x);
        assert_eq!(taken, 16);
        assert!(
            (value - 0.05).abs() < 1e-6,
            "the midpoint rule is exact on a ramp: {value}"
        );
        // A steep one (0.5 across the pixel) scores 0.016 and splits once: at the next level
        // the steps halve and the weight falls by 2^1.5.
        assert_eq!(refine_pixel(256, 0.01, [None; 4], |p| 0.5 * p.x).1, 16 + 64);
    }

    #[test]
    fn an_edge_is_followed_to_finer_cells_and_its_coverage_converges() {
        let exact = coverage(edge);
        let (first_grid, _) = refine_pixel(16, 0.01, [None; 4], edge);
        let (value, taken) = refine_pixel(1024, 0.001, [None; 4], edge);
        let (err_first, err) = ((first_grid - exact).abs(), (value - exact).abs());
        // Only the cells along the line split: far fewer samples than a full 32×32 grid.
        assert!(taken > 16 && taken < 400, "{taken} samples");
        assert!(
            err < 0.003 && err < err_first / 4.0,
            "error {err} (first grid alone {err_first})"
        );
    }

    #[test]
    fn the_films_spp_caps_a_pixels_samples() {
        for spp in [4, 9, 20, 64] {
            let (_, taken) = refine_pixel(spp, 1e-4, [None; 4], edge);
            assert!(taken <= spp, "{taken} samples at spp {spp}");
        }
        // Below 16 samples the first grid is the largest square that fits, and nothing splits.
        assert_eq!(refine_pixel(9, 1e-4, [None; 4], edge).1, 9);
        assert_eq!(refine_pixel(6, 1e-4, [None; 4], edge).1, 4);
    }

    #[test]
    fn a_jump_to_the_neighbouring_pixel_splits_the_cells_beside_it() {
        // An edge just inside the pixel's left border, between the border and the first grid's
        // points: only the left neighbour's centre (dark) shows it.
        let sliver = |p: Vec2| f32::from(p.x > 0.1);
        let bright = Some(Vec3::ONE);
        let (_, blind) = refine_pixel(256, 0.01, [bright, bright, bright, bright], sliver);
        let (value, taken) = refine_pixel(256, 0.01, [Some(Vec3::ZERO), bright, bright, bright], sliver);
        assert_eq!(blind, 16);
        assert!(taken > 16, "the left column splits");
        assert!(
            (value - 0.9).abs() < (1.0f32 - 0.9).abs(),
            "closer than the first grid: {value}"
        );
    }

    #[test]
    fn a_first_grid_that_repeats_a_dark_centre_beside_lit_neighbours_splits_whole() {
        // A lit strip between the first grid's points (at 1/8, 3/8, …) but on the second's (3/16).
        let strip = |p: Vec2| f32::from((0.17..0.2).contains(&p.x));
        let lit = Some(Vec3::ONE);
        let (value, taken) = refine_pixel(256, 0.01, [lit, None, None, None], strip);
        assert!(taken >= 16 + 64, "{taken} samples");
        assert!(value > 0.0, "the strip is seen: {value} {taken}");
        // Beside dark neighbours the same grid is trusted.
        let dark = Some(Vec3::ZERO);
        assert_eq!(refine_pixel(256, 0.01, [dark, None, None, None], strip), (0.0, 16));
    }

    #[test]
    fn a_pixel_active_only_for_its_neighbours_takes_a_first_look_of_3x3() {
        // Smooth: nine samples, and the midpoint rule's value on a ramp.
        let (value, taken) = refine_pixel_bending(false, 256, 0.01, [None; 4], |p| 0.1 * p.x);
        assert_eq!(taken, 9);
        assert!((value - 0.05).abs() < 1e-6, "{value}");
        // An edge in it is still followed to finer cells, and converges as from the 4×4 grid.
        let exact = coverage(edge);
        let (value, taken) = refine_pixel_bending(false, 1024, 0.001, [None; 4], edge);
        assert!(taken > 9 && taken < 400, "{taken} samples");
        assert!((value - exact).abs() < 0.003, "{value} against {exact}");
        // Below nine samples the film's cap decides, as for any pixel.
        assert_eq!(refine_pixel_bending(false, 4, 1e-4, [None; 4], edge).1, 4);
    }
}
