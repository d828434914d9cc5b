//! Film: image size, sampling settings, and the pixel buffers samples are averaged into.
//!
//! Pixels use a box filter: a pixel's value is the plain mean of its own samples, which is what
//! Mitsuba's `box` rfilter computes, so references compare pixel for pixel; [`compare`] is that
//! comparison, the image metric every command uses.

pub mod compare;
pub mod memory;
pub mod sampler;

use std::mem::MaybeUninit;

use glam::Vec3;
use rayon::prelude::*;
pub use sampler::SamplerKind;

/// Largest image a render accepts (width × height), a guard against absurd sizes.
pub const MAX_PIXELS: u64 = 1 << 28;
/// Largest image side accepted, in pixels.
pub const MAX_SIDE: u32 = 65536;
/// Largest samples-per-pixel count accepted.
pub const MAX_SPP: u32 = 1 << 16;

/// Image and sampling settings.
#[derive(Clone, Debug, PartialEq)]
pub struct FilmSettings {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Samples per pixel.
    pub spp: u32,
    /// Where samples fall inside a pixel.
    pub sampler: SamplerKind,
    /// Seed of the scrambled/random samplers.
    pub seed: u64,
    /// Exposure in stops applied to 8-bit output (EXR stays linear and unscaled). The adaptive
    /// sampler's tolerances are absolute below the radiance it shows as white (2^−exposure).
    pub exposure: f32,
    /// Adaptive samplers: the relative contrast in a pixel's neighbourhood above which it takes
    /// more than its centre sample, and the tolerance, relative to the pixel's value or display
    /// white (whichever is larger), to which it is refined.
    pub adaptive_threshold: f32,
    /// The part of the film to render (`--crop`); `None` = all of it.
    pub crop: Option<PixelRect>,
    /// Seconds the BVH build and the render may take (`--time-budget`); `None` = no limit. The
    /// render then runs in passes, more samples per pixel or a finer adaptive threshold each,
    /// within `spp` and down to `adaptive_threshold`, while the next pass is predicted to end
    /// in time (see `render::budget`).
    pub time_budget: Option<f32>,
}

/// A rectangle of pixels [x0, x1) × [y0, y1), row 0 at the top.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PixelRect {
    /// First column.
    pub x0: u32,
    /// First row.
    pub y0: u32,
    /// One past the last column.
    pub x1: u32,
    /// One past the last row.
    pub y1: u32,
}

impl PixelRect {
    /// The whole `width` × `height` film.
    pub fn full(width: u32, height: u32) -> Self {
        Self {
            x0: 0,
            y0: 0,
            x1: width,
            y1: height,
        }
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.x1 - self.x0
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.y1 - self.y0
    }

    /// Parses `x0,y0,x1,y1`.
    pub fn parse(text: &str) -> Result<Self, String> {
        let v: Vec<u32> = text
            .split(',')
            .map(|t| t.trim().parse::<u32>())
            .collect::<Result<_, _>>()
            .map_err(|_| format!("expected x0,y0,x1,y1 (four whole numbers), got '{text}'"))?;
        match v[..] {
            [x0, y0, x1, y1] => Ok(Self { x0, y0, x1, y1 }),
            _ => Err(format!("expected x0,y0,x1,y1 (four whole numbers), got '{text}'")),
        }
    }
}

impl Default for FilmSettings {
    fn default() -> Self {
        Self {
            width: 640,
            height: 480,
            spp: 4,
            sampler: SamplerKind::Sobol,
            seed: 0,
            exposure: 0.0,
            adaptive_threshold: DEFAULT_ADAPTIVE_THRESHOLD,
            crop: None,
            time_budget: None,
        }
    }
}

/// Samples per pixel (the cap) and adaptive threshold (the finest) of a time budget that does not
/// set them: the budget decides. An adaptive sampler's cap is lower, as a single pass of its
/// rounds could otherwise spend 65,536 samples on a pixel that never settles.
pub fn time_budget_defaults(sampler: SamplerKind) -> (u32, f32) {
    let spp = if sampler.is_adaptive() { 1024 } else { MAX_SPP };
    (spp, 1.0 / 1024.0)
}

/// Largest time budget accepted, in seconds (a week): a guard against absurd values.
pub const MAX_TIME_BUDGET: f32 = 7.0 * 24.0 * 3600.0;

/// Default of [`FilmSettings::adaptive_threshold`].
pub const DEFAULT_ADAPTIVE_THRESHOLD: f32 = 0.01;

impl FilmSettings {
    /// Range checks, with messages naming the key.
    pub fn validate(&self) -> Result<(), String> {
        if self.width == 0 || self.height == 0 {
            return Err(format!(
                "image size must be at least 1×1, got {}×{}",
                self.width, self.height
            ));
        }
        let pixels = self.width as u64 * self.height as u64;
        if pixels > MAX_PIXELS || self.width > MAX_SIDE || self.height > MAX_SIDE {
            return Err(format!(
                "image size {}×{} is too large (at most {MAX_SIDE} per side and {} pixels)",
                self.width, self.height, MAX_PIXELS
            ));
        }
        if self.spp > MAX_SPP {
            return Err(format!("spp {} is too large (at most {MAX_SPP})", self.spp));
        }
        self.sampler.check_spp(self.spp)?;
        if !self.exposure.is_finite() || self.exposure.abs() > 64.0 {
            return Err(format!(
                "exposure must be a finite number of stops in [-64, 64], got {}",
                self.exposure
            ));
        }
        if !(self.adaptive_threshold > 0.0 && self.adaptive_threshold < 1.0) {
            return Err(format!(
                "adaptive_threshold must be in (0, 1), got {}",
                self.adaptive_threshold
            ));
        }
        if let Some(c) = self.crop {
            if !(c.x0 < c.x1 && c.y0 < c.y1 && c.x1 <= self.width && c.y1 <= self.height) {
                return Err(format!(
                    "crop {},{},{},{} is not a non-empty rectangle inside the {}×{} image",
                    c.x0, c.y0, c.x1, c.y1, self.width, self.height
                ));
            }
        }
        if let Some(budget) = self.time_budget {
            self.check_time_budget(budget)?;
        }
        Ok(())
    }

    /// A time budget needs a positive, finite number of seconds, a sampler that can add samples
    /// (not the grid, whose points all move when the count changes), and the whole film: crops
    /// of one frame must take the same samples to merge, and budgets would give each its own.
    fn check_time_budget(&self, budget: f32) -> Result<(), String> {
        if !(budget > 0.0 && budget <= MAX_TIME_BUDGET) {
            return Err(format!(
                "time_budget must be a number of seconds in (0, {MAX_TIME_BUDGET}], got {budget}"
            ));
        }
        if !self.sampler.takes_time_budget() {
            return Err(format!(
                "a time budget needs a sampler that can add samples (sobol, independent, adaptive or cells), not {}",
                self.sampler.name()
            ));
        }
        if self.crop.is_some() {
            return Err(
                "a time budget cannot render a crop: the crops of a frame must take the same samples to merge".into(),
            );
        }
        Ok(())
    }

    /// The rectangle that is rendered: the crop, or the whole film.
    pub fn region(&self) -> PixelRect {
        self.crop.unwrap_or(PixelRect::full(self.width, self.height))
    }

    /// Number of pixels.
    pub fn pixel_count(&self) -> usize {
        self.width as usize * self.height as usize
    }
}

/// A linear RGB image, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major pixels.
    pub pixels: Vec<Vec3>,
}

/// Whether every channel of `pixels` is finite: no channel's bits without the sign reach
/// infinity's (all exponent bits set is infinity or NaN). One branch-free reduction of integer
/// compares, which the compiler runs in vector instructions (SSE2 has signed compares but no
/// integer max; the magnitudes are below 2^31, so the signed compare is exact).
#[inline(always)]
pub fn all_finite(pixels: &[Vec3]) -> bool {
    // The channels as one run of words: a reduction over a stride of three floats is left
    // scalar.
    let bits: &[u32] = bytemuck::cast_slice(pixels);
    let infinity = f32::INFINITY.to_bits() as i32;
    !bits
        .iter()
        .fold(false, |any, &b| any | ((b & 0x7fff_ffff) as i32 >= infinity))
}

impl Image {
    /// The first pixel, row-major, with a non-finite channel: its column, row and value. A
    /// renderer returns an error instead of such an image ([`overflow_error`]).
    pub fn first_non_finite(&self) -> Option<(u32, u32, Vec3)> {
        // Blocks on every core, each tested without a branch per value (the compiler packs the
        // test into vector instructions); the pixel itself is then found in the first bad block.
        const BLOCK: usize = 4096;
        let block = self.pixels.par_chunks(BLOCK).position_first(|b| !all_finite(b))?;
        let i = block * BLOCK
            + self.pixels[block * BLOCK..]
                .iter()
                .position(|p| !all_finite(std::slice::from_ref(p)))?;
        Some((i as u32 % self.width, i as u32 / self.width, self.pixels[i]))
    }

    /// An image made row by row in parallel: `row(state, y, pixels)` writes row `y`, whose pixels
    /// start black, and returns what it counted; `init` makes each worker's scratch `state` (as
    /// rayon's `map_init`). The rows' counts are summed (in a tree, in any order: `R`'s sum
    /// must not depend on it), so that no two workers update one counter per row.
    ///
    /// Unlike [`Image::new`] followed by a parallel pass, no thread zeroes the whole buffer first:
    /// each row is cleared by the worker that is about to write it, in its cache, so the
    /// memory is written once, in parallel.
    pub fn par_from_rows<T, R: Send + Default + std::ops::Add<Output = R>>(
        width: u32,
        height: u32,
        init: impl Fn() -> T + Sync + Send,
        row: impl Fn(&mut T, u32, &mut [Vec3]) -> R + Sync + Send,
    ) -> (Image, R) {
        let (w, n) = (width as usize, width as usize * height as usize);
        let mut pixels: Vec<Vec3> = Vec::with_capacity(n);
        let sum = pixels.spare_capacity_mut()[..n]
            .par_chunks_mut(w.max(1))
            .enumerate()
            .map_init(init, |state, (y, chunk)| {
                // SAFETY (both): the bytes of `chunk` are set to zero, which is `Vec3::ZERO`
                // (three 0.0 floats), so every element is initialised; `MaybeUninit<Vec3>` has
                // the layout of `Vec3`.
                unsafe { chunk.as_mut_ptr().write_bytes(0, chunk.len()) };
                let chunk = unsafe { &mut *(chunk as *mut [MaybeUninit<Vec3>] as *mut [Vec3]) };
                row(state, y as u32, chunk)
            })
            .reduce(R::default, |a, b| a + b);
        // SAFETY: the chunks above cover the first `n` elements, and each was initialised (a
        // panic in `row` propagates before this line, leaving the vector empty).
        unsafe { pixels.set_len(n) };
        (Image { width, height, pixels }, sum)
    }

    /// A black image.
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            pixels: vec![Vec3::ZERO; width as usize * height as usize],
        }
    }

    /// The pixel at column `x`, row `y`.
    pub fn get(&self, x: u32, y: u32) -> Vec3 {
        self.pixels[y as usize * self.width as usize + x as usize]
    }
}

/// The error for radiance past f32's range at pixel (`x`, `y`): every guard in the shading path
/// keeps NaN out, but a product of finite values near 3.4e38 (a light's intensity, an albedo)
/// can still overflow, and an image with ∞ in it is no answer.
pub fn overflow_error(x: u32, y: u32, p: Vec3) -> String {
    format!(
        "radiance overflowed at pixel ({x}, {y}): [{:.3e}, {:.3e}, {:.3e}] (light intensities or material parameters too large for 32-bit floats)",
        p.x, p.y, p.z
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_non_finite_pixel_is_found_by_column_and_row() {
        let mut image = Image::new(4, 3);
        assert_eq!(image.first_non_finite(), None);
        image.pixels[2 * 4 + 1] = Vec3::new(1.0, f32::NEG_INFINITY, 0.0);
        image.pixels[2 * 4 + 3] = Vec3::splat(f32::NAN);
        let (x, y, p) = image.first_non_finite().unwrap();
        assert_eq!((x, y), (1, 2));
        assert!(overflow_error(x, y, p).starts_with("radiance overflowed at pixel (1, 2): [1.000e0, -inf, 0.000e0]"));
    }

    #[test]
    fn all_finite_is_every_channels_is_finite() {
        let finite = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            f32::MAX,
            -f32::MAX,
            f32::MIN_POSITIVE,
            1e-45,
            -1e-45,
        ];
        let not = [
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            -f32::NAN,
            f32::from_bits(0xff80_0001),
        ];
        for &v in &finite {
            assert!(all_finite(&[Vec3::ONE, Vec3::new(1.0, v, 2.0)]), "{v}");
        }
        for &v in &not {
            for c in 0..3 {
                let mut p = Vec3::ONE;
                p[c] = v;
                assert!(!all_finite(&[Vec3::ZERO, p, Vec3::ONE]), "{v} in channel {c}");
            }
        }
        assert!(all_finite(&[]));
    }

    #[test]
    fn the_first_non_finite_pixel_is_found_across_blocks() {
        // 1000 × 50 pixels: a dozen blocks of 4096; bad pixels in the third block and later.
        let mut image = Image::new(1000, 50);
        image.pixels[48_000] = Vec3::new(0.0, 0.0, f32::INFINITY);
        assert_eq!(image.first_non_finite().map(|(x, y, _)| (x, y)), Some((0, 48)));
        image.pixels[9_001] = Vec3::new(f32::NAN, 1.0, 1.0);
        image.pixels[9_002] = Vec3::splat(f32::NAN);
        assert_eq!(image.first_non_finite().map(|(x, y, _)| (x, y)), Some((1, 9)));
    }

    #[test]
    fn rows_made_in_parallel_start_black_and_keep_what_was_written() {
        // Fill the allocator with non-zero memory first, so a missed clear would show.
        drop(vec![Vec3::splat(7.0); 64 * 64]);
        let (image, rows) = Image::par_from_rows(
            13,
            9,
            || 0u32,
            |calls, y, pixels| {
                *calls += 1;
                assert_eq!(pixels.len(), 13);
                assert!(pixels.iter().all(|p| *p == Vec3::ZERO), "row {y} starts black");
                pixels[y as usize] = Vec3::new(y as f32, 1.0, *calls as f32);
                1u32
            },
        );
        assert_eq!(rows, 9, "every row's count is summed once");
        assert_eq!((image.width, image.height, image.pixels.len()), (13, 9, 117));
        for y in 0..9 {
            for x in 0..13 {
                let p = image.get(x, y);
                if x == y {
                    assert_eq!((p.x, p.y), (y as f32, 1.0));
                } else {
                    assert_eq!(p, Vec3::ZERO, "({x}, {y})");
                }
            }
        }
        let (empty, rows) = Image::par_from_rows(0, 0, || (), |_, _, _| -> u32 { panic!("no rows") });
        assert!(empty.pixels.is_empty() && rows == 0);
    }
}
