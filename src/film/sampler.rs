//! Pixel samplers: where inside a pixel each of its `spp` samples falls.
//!
//! Every sampler is a pure function of (seed, pixel, sample index), so an image is identical for
//! any thread count or tiling.
//! - `grid`: a regular N×N sub-pixel grid at offsets (k + 0.5)/N; spp must be N². spp = 1 samples
//!   the pixel centre. Matches Mitsuba's `stratified` sampler with `jitter = false`.
//! - `sobol` (default): the first two dimensions of the Sobol sequence with Owen scrambling by
//!   hashing (Burley, "Practical Hash-based Owen Scrambling", JCGT 2020), a different
//!   scramble per pixel. Any spp works; power-of-two counts are stratified in every elementary
//!   interval, which makes the error fall faster than for random or jittered samples.
//! - `independent`: uniform random offsets from a hash (a reference for convergence studies).
//! - `adaptive`: the `sobol` points, taken as far as each pixel needs (see `render::adaptive`):
//!   `spp` is then the most a pixel may take.

use glam::Vec2;

/// Which sampler places the samples of a pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SamplerKind {
    /// Regular N×N grid of sub-pixel centres.
    Grid,
    /// Owen-scrambled Sobol (0,2)-sequence.
    Sobol,
    /// Independent uniform random offsets.
    Independent,
    /// Sobol points, as many as each pixel needs, up to spp (rounds of 16, 64, 256, …).
    Adaptive,
    /// Sub-pixel cells, subdivided where a pixel's value still jumps, up to spp.
    Cells,
}

/// Where a pixel's samples fall, sample by sample: what [`pixel_offsets`] draws from. The fixed
/// samplers use one each; the `adaptive` sampler's rounds draw the Sobol points.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sequence {
    /// Regular N×N grid of sub-pixel centres (all of a pixel's samples at once).
    Grid,
    /// Owen-scrambled Sobol (0,2)-sequence.
    Sobol,
    /// Independent uniform random offsets.
    Independent,
}

impl SamplerKind {
    /// Every sampler, in the order of [`SamplerKind::NAMES`].
    pub const ALL: [SamplerKind; 5] = [Self::Grid, Self::Sobol, Self::Independent, Self::Adaptive, Self::Cells];
    /// Their names.
    pub const NAMES: &'static [&'static str] = &["grid", "sobol", "independent", "adaptive", "cells"];

    /// Name as written in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::Grid => "grid",
            Self::Sobol => "sobol",
            Self::Independent => "independent",
            Self::Adaptive => "adaptive",
            Self::Cells => "cells",
        }
    }

    /// Parses a name; the error lists the valid ones.
    pub fn parse(name: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|k| k.name() == name)
            .ok_or_else(|| format!("unknown sampler '{name}' (expected grid, sobol, independent, adaptive or cells)"))
    }

    /// The sequence a fixed sampler draws every pixel's samples from; `None` for the adaptive
    /// ones, which decide per pixel where samples go (`render::adaptive`).
    pub fn fixed_sequence(self) -> Option<Sequence> {
        match self {
            Self::Grid => Some(Sequence::Grid),
            Self::Sobol => Some(Sequence::Sobol),
            Self::Independent => Some(Sequence::Independent),
            Self::Adaptive | Self::Cells => None,
        }
    }

    /// Whether the sampler decides each pixel's sample count (`adaptive`, `cells`): a centre pass,
    /// then refinement where the image needs it, with the film's spp as the cap.
    pub fn is_adaptive(self) -> bool {
        matches!(self, Self::Adaptive | Self::Cells)
    }

    /// Whether a render can add samples until a time budget is spent and still end with the
    /// image of a fixed setting: sobol and independent because a pixel's first n samples are the
    /// same whatever the count, the adaptive samplers because a finer threshold reuses the
    /// samples of a coarser one (`render::budget`). The grid moves every point when its
    /// side changes.
    pub fn takes_time_budget(self) -> bool {
        self != Self::Grid
    }

    /// Checks that `spp` suits this sampler (grid needs a perfect square).
    pub fn check_spp(self, spp: u32) -> Result<(), String> {
        if spp == 0 {
            return Err("spp must be at least 1".into());
        }
        if self == Self::Grid && grid_side(spp).is_none() {
            return Err(format!(
                "the grid sampler needs a square spp (1, 4, 9, 16, …), got {spp}"
            ));
        }
        Ok(())
    }
}

fn grid_side(spp: u32) -> Option<u32> {
    let n = (spp as f64).sqrt().round() as u32;
    (n * n == spp).then_some(n)
}

/// Fills `out` with the sub-pixel offsets in [0, 1)² of samples `first`, `first + 1`, … of pixel
/// (x, y). The grid sampler places all of a pixel's samples at once (`first` = 0, `out` = spp).
pub fn pixel_offsets(sequence: Sequence, seed: u64, x: u32, y: u32, first: u32, out: &mut [Vec2]) {
    let spp = out.len() as u32;
    match sequence {
        Sequence::Grid => {
            debug_assert_eq!(first, 0, "the grid is placed whole");
            let n = grid_side(spp).expect("spp checked by SamplerKind::check_spp");
            let inv = 1.0 / n as f32;
            for (i, o) in out.iter_mut().enumerate() {
                let (k, l) = (i as u32 % n, i as u32 / n);
                *o = Vec2::new((k as f32 + 0.5) * inv, (l as f32 + 0.5) * inv);
            }
        }
        Sequence::Sobol => {
            let pixel_seed = hash3(seed, x, y);
            let (seed_index, seed_x, seed_y) = (
                pixel_seed as u32,
                (pixel_seed >> 32) as u32,
                mix32(pixel_seed as u32 ^ 0x9e37_79b9),
            );
            for (i, o) in (first..).zip(out.iter_mut()) {
                let index = nested_uniform_scramble(i, seed_index);
                // Dimension 0 is reverse(index); its scramble reverse(LK(reverse(reverse(index))))
                // is reverse(LK(index)): two bit reversals saved. Dimension 1 likewise uses the
                // bit-reversed direction tables, so reverse(sobol2(index)) comes for free.
                let sx = laine_karras_permutation(index, seed_x).reverse_bits();
                let sy = laine_karras_permutation(reversed_sobol_second_dimension(index), seed_y).reverse_bits();
                *o = Vec2::new(unit_float(sx), unit_float(sy));
            }
        }
        Sequence::Independent => {
            let pixel_seed = hash3(seed, x, y);
            for (i, o) in (first..).zip(out.iter_mut()) {
                let h = splitmix64(pixel_seed ^ (i as u64).wrapping_mul(0xd6e8_feb8_6659_fd93));
                *o = Vec2::new(unit_float(h as u32), unit_float((h >> 32) as u32));
            }
        }
    }
}

/// Direction numbers of the second Sobol dimension: v_0 = 2^31, v_{k+1} = v_k ⊕ (v_k >> 1).
const fn sobol_directions() -> [u32; 32] {
    let mut v = [0u32; 32];
    v[0] = 1 << 31;
    let mut k = 1;
    while k < 32 {
        v[k] = v[k - 1] ^ (v[k - 1] >> 1);
        k += 1;
    }
    v
}

/// The second dimension for every value of each byte of the index: entry [b][x] is the XOR of
/// the direction numbers of the bits set in x, shifted to byte b.
const SOBOL_BYTE_TABLES: [[u32; 256]; 4] = {
    let v = sobol_directions();
    let mut t = [[0u32; 256]; 4];
    let mut b = 0;
    while b < 4 {
        let mut x = 0;
        while x < 256 {
            let mut r = 0;
            let mut bit = 0;
            while bit < 8 {
                if x & (1 << bit) != 0 {
                    r ^= v[8 * b + bit];
                }
                bit += 1;
            }
            t[b][x] = r;
            x += 1;
        }
        b += 1;
    }
    t
};

/// The second Sobol dimension of `index`: the XOR of v_k over its set bits k, four table
/// lookups (the scrambled indices use all 32 bits, where a bit loop would take 32 steps).
#[cfg(test)]
fn sobol_second_dimension(index: u32) -> u32 {
    let t = &SOBOL_BYTE_TABLES;
    t[0][(index & 0xff) as usize]
        ^ t[1][((index >> 8) & 0xff) as usize]
        ^ t[2][((index >> 16) & 0xff) as usize]
        ^ t[3][(index >> 24) as usize]
}

/// The same tables with every entry bit-reversed (reversal distributes over XOR).
const REVERSED_SOBOL_BYTE_TABLES: [[u32; 256]; 4] = {
    let mut t = SOBOL_BYTE_TABLES;
    let mut b = 0;
    while b < 4 {
        let mut x = 0;
        while x < 256 {
            t[b][x] = t[b][x].reverse_bits();
            x += 1;
        }
        b += 1;
    }
    t
};

/// reverse(sobol_second_dimension(index)), by the reversed tables.
fn reversed_sobol_second_dimension(index: u32) -> u32 {
    let t = &REVERSED_SOBOL_BYTE_TABLES;
    t[0][(index & 0xff) as usize]
        ^ t[1][((index >> 8) & 0xff) as usize]
        ^ t[2][((index >> 16) & 0xff) as usize]
        ^ t[3][(index >> 24) as usize]
}

/// Laine–Karras style hash that permutes bits only towards higher positions (Burley 2020, eq. 4
/// with its improved constants), so applied to bit-reversed values it is a nested uniform scramble.
fn laine_karras_permutation(mut x: u32, seed: u32) -> u32 {
    x = x.wrapping_add(seed);
    x ^= x.wrapping_mul(0x6c50_b47c);
    x ^= x.wrapping_mul(0xb82f_1e52);
    x ^= x.wrapping_mul(0xc7af_e638);
    x ^= x.wrapping_mul(0x8d22_f6e6);
    x
}

fn nested_uniform_scramble(x: u32, seed: u32) -> u32 {
    laine_karras_permutation(x.reverse_bits(), seed).reverse_bits()
}

/// Top 24 bits as a float in [0, 1) (never 1.0).
fn unit_float(x: u32) -> f32 {
    (x >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

fn splitmix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

fn mix32(x: u32) -> u32 {
    splitmix64(x as u64) as u32
}

fn hash3(seed: u64, x: u32, y: u32) -> u64 {
    splitmix64(splitmix64(seed ^ ((x as u64) << 32 | y as u64)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn offsets(sequence: Sequence, spp: usize, x: u32, y: u32) -> Vec<Vec2> {
        let mut v = vec![Vec2::ZERO; spp];
        pixel_offsets(sequence, 7, x, y, 0, &mut v);
        v
    }

    #[test]
    fn names_are_the_variants_names() {
        let names: Vec<&str> = SamplerKind::ALL.iter().map(|k| k.name()).collect();
        assert_eq!(names, SamplerKind::NAMES);
    }

    #[test]
    fn second_dimension_tables_match_the_direction_numbers() {
        let v = sobol_directions();
        for index in [0u32, 1, 2, 3, 255, 256, 0x1234_5678, u32::MAX] {
            let by_bits = (0..32).filter(|k| index & (1 << k) != 0).fold(0, |r, k| r ^ v[k]);
            assert_eq!(sobol_second_dimension(index), by_bits, "{index:#x}");
        }
        // The first points of the (unscrambled) sequence: 0, 1/2, 3/4, 1/4.
        assert_eq!([0, 1, 2, 3].map(sobol_second_dimension), [0, 1 << 31, 3 << 30, 1 << 30]);
        for index in [7u32, 0xdead_beef] {
            assert_eq!(
                reversed_sobol_second_dimension(index),
                sobol_second_dimension(index).reverse_bits()
            );
        }
    }

    #[test]
    fn grid_places_sub_pixel_centres() {
        assert_eq!(offsets(Sequence::Grid, 1, 3, 4), vec![Vec2::splat(0.5)]);
        let g = offsets(Sequence::Grid, 4, 0, 0);
        assert_eq!(
            g,
            vec![
                Vec2::new(0.25, 0.25),
                Vec2::new(0.75, 0.25),
                Vec2::new(0.25, 0.75),
                Vec2::new(0.75, 0.75)
            ]
        );
        assert!(SamplerKind::Grid.check_spp(8).is_err());
        assert!(SamplerKind::Grid.check_spp(9).is_ok());
    }

    #[test]
    fn sobol_is_stratified_in_every_elementary_interval_for_power_of_two_counts() {
        // 16 points: each of the 16 boxes of every shape 1×16, 2×8, 4×4, 8×2, 16×1 holds exactly one.
        let pts = offsets(Sequence::Sobol, 16, 11, 5);
        for log_x in 0..=4 {
            let (nx, ny) = (1usize << log_x, 16usize >> log_x);
            let mut seen = vec![0; 16];
            for p in &pts {
                let (i, j) = ((p.x * nx as f32) as usize, (p.y * ny as f32) as usize);
                seen[j * nx + i] += 1;
            }
            assert!(seen.iter().all(|&c| c == 1), "{nx}×{ny} boxes: {seen:?}");
        }
    }

    #[test]
    fn samples_are_in_the_unit_square_deterministic_and_differ_between_pixels() {
        for kind in [Sequence::Sobol, Sequence::Independent] {
            let a = offsets(kind, 64, 1, 2);
            assert!(a.iter().all(|p| (0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y)));
            assert_eq!(a, offsets(kind, 64, 1, 2));
            assert_ne!(a, offsets(kind, 64, 2, 1));
        }
    }

    #[test]
    fn sobol_mean_converges_faster_than_independent() {
        // Integrate f(x, y) = x·y (exact 1/4) over many pixels; compare mean squared errors.
        let mse = |kind| {
            (0..256u32)
                .map(|px| {
                    let pts = offsets(kind, 64, px, 0);
                    let est = pts.iter().map(|p| p.x * p.y).sum::<f32>() / 64.0;
                    ((est - 0.25) as f64).powi(2)
                })
                .sum::<f64>()
        };
        assert!(mse(Sequence::Sobol) * 10.0 < mse(Sequence::Independent));
    }
}
