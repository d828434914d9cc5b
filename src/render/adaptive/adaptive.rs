//! The `adaptive` sampler's refinement: an active pixel takes Owen-scrambled Sobol samples in
//! rounds of 16, 64, 256, … (the film's spp at most) and stops once two error estimates are
//! within t times its scale: how far its mean moved in the round, and how far the means of the
//! first and the second half of its samples lie apart (each half is a stratified net of its own).
//! The scale is the largest of its value, a twentieth of its neighbourhood's level and display
//! white. Its value is the mean of those samples (the centre sample is not mixed in). The first
//! round is 16 samples, and is not trusted alone where
//! - its samples all repeat the centre value while a neighbour is brighter by more than the
//!   tolerance (sixteen samples in shadow can miss a lit sliver the neighbours show), or
//! - the neighbourhood's centres span more than 30 tolerances (where sixteen samples agree with
//!   the centre by chance too often).
//!
//! Random points make no assumption about where edges run: a Sobol net of 16 points puts one
//! point in each 1/16-wide column and row of the pixel, so an edge along either axis is resolved
//! to 1/16 of a pixel by the first round (the `cells` sampler needs three levels for that).

use glam::{Vec2, Vec3};

use super::refine::{ActivePixel, Settings, DARK_FLOOR};
use crate::film::sampler::pixel_offsets;
use crate::film::sampler::Sequence;
use crate::render::tile::{PixelSums, SampleJob};

/// Samples of an active pixel's first refinement round (a 4×4-stratified Sobol net); each later
/// round takes 4× as many.
const FIRST_ROUND: u32 = 16;
/// Neighbourhood contrast, in tolerances, above which a first round alone never converges.
const HIGH_CONTRAST: f32 = 30.0;

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

/// Refines `pixels` (the active pixels of one tile) in rounds of 16, 64, 256, … samples until
/// each converges or reaches the film's spp; their sums replace the centre sample in `sums`, and
/// `counts` gets their sample counts. `trace` adds each job's sample to its slot (a context's
/// `trace` in a render).
pub fn refine(
    settings: Settings,
    pixels: &[ActivePixel],
    sums: &mut PixelSums,
    counts: &mut [u32],
    trace: &mut dyn FnMut(&[SampleJob], &mut PixelSums),
) {
    let mut active: Vec<Refining> = pixels
        .iter()
        .map(|p| Refining {
            x: p.x,
            y: p.y,
            slot: p.slot,
            taken: 0,
            level: p.level,
            low: p.low,
            previous: p.centre,
            previous_max: p.centre.max_element(),
        })
        .collect();
    let Settings {
        spp,
        threshold,
        aovs: naovs,
        seed,
        white,
    } = settings;
    for p in active.iter() {
        sums.radiance[p.slot as usize] = Vec3::ZERO;
        for k in 0..naovs {
            sums.aovs[k][p.slot as usize] = Vec3::ZERO;
        }
    }
    let mut target = FIRST_ROUND.min(spp);
    let mut offsets = Vec::new();
    let mut jobs = Vec::new();
    // Two slots per active pixel: the round's samples in the first and in the second half of
    // the pixel's samples so far.
    let mut halves = PixelSums::new(0, naovs);
    while !active.is_empty() {
        jobs.clear();
        let half = target / 2;
        for (k, p) in active.iter().enumerate() {
            offsets.resize((target - p.taken) as usize, Vec2::ZERO);
            pixel_offsets(Sequence::Sobol, seed, p.x, p.y, p.taken, &mut offsets);
            let corner = Vec2::new(p.x as f32, p.y as f32);
            jobs.extend(offsets.iter().zip(p.taken..).map(|(&o, i)| SampleJob {
                slot: 2 * k as u32 + u32::from(i >= half),
                film: corner + o,
            }));
        }
        halves.reset(2 * active.len());
        trace(&jobs, &mut halves);
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
            !(converged || target == spp)
        });
        target = (target * 4).min(spp);
    }
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

    /// Refines one pixel at (0, 0) of an analytic image `f` (film position → value), whose
    /// neighbourhood has the given level and low; returns its estimate and sample count.
    fn refine_pixel(spp: u32, threshold: f32, level: f32, low: f32, f: impl Fn(Vec2) -> f32) -> (f32, u32) {
        let pixel = ActivePixel {
            x: 0,
            y: 0,
            slot: 0,
            centre: Vec3::splat(f(Vec2::splat(0.5))),
            beside: [None; 4],
            scale: 1.0,
            level,
            low,
            bends: true,
        };
        let (mut sums, mut counts) = (PixelSums::new(1, 0), [0u32]);
        let mut trace = |jobs: &[SampleJob], sums: &mut PixelSums| {
            for job in jobs {
                sums.radiance[job.slot as usize] += Vec3::splat(f(job.film));
            }
        };
        let settings = Settings {
            spp,
            threshold,
            aovs: 0,
            seed: 7,
            white: 1.0,
        };
        refine(settings, &[pixel], &mut sums, &mut counts, &mut trace);
        (sums.radiance[0].x / counts[0] as f32, counts[0])
    }

    /// Light on one side of a slanted line through the pixel: 0.575 of it is lit.
    fn edge(p: Vec2) -> f32 {
        f32::from(p.x + 0.37 * p.y > 0.61)
    }

    #[test]
    fn a_flat_pixel_stops_after_the_first_round_and_an_edge_refines_toward_its_coverage() {
        let (value, taken) = refine_pixel(256, 0.01, 0.3, 0.3, |_| 0.3);
        assert_eq!(taken, FIRST_ROUND);
        assert!((value - 0.3).abs() < 1e-6, "{value}");
        let (value, taken) = refine_pixel(4096, 0.002, 1.0, 0.0, edge);
        assert!(taken > 4 * FIRST_ROUND, "{taken}");
        assert!((value - 0.575).abs() < 0.01, "{value} after {taken} samples");
        // The film's spp caps the rounds (the last one is cut to fit).
        assert_eq!(refine_pixel(100, 1e-6, 1.0, 0.0, edge).1, 100);
    }

    #[test]
    fn untrusted_first_rounds_take_a_second_round() {
        // A dark pixel whose samples all repeat its centre, beside lit neighbours (level 0.1 is
        // above the tolerance 0.004 but within 30 tolerances, so only blindness counts)…
        assert_eq!(refine_pixel(256, 0.004, 0.1, 0.0, |_| 0.0).1, 4 * FIRST_ROUND);
        // …and beside neighbours as dark.
        assert_eq!(refine_pixel(256, 0.004, 0.002, 0.0, |_| 0.0).1, FIRST_ROUND);
        // A neighbourhood spanning more than 30 tolerances, whatever the samples say.
        assert_eq!(refine_pixel(256, 0.004, 0.5, 0.0, |_| 0.5).1, 4 * FIRST_ROUND);
        assert_eq!(refine_pixel(256, 0.004, 0.5, 0.45, |_| 0.5).1, FIRST_ROUND);
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
