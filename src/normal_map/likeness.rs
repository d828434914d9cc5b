//! Whether an image looks like a normal image, so that shading a colour photograph by mistake
//! says so instead of exiting 0 with a meaningless picture.
//!
//! A normal image stores n = 2c − 1 per pixel (tangent or view space, +z towards the viewer):
//! decoded, its foreground pixels are vectors of about unit length (8-bit rounding moves them by
//! under 1%) and face the viewer (blue ≥ 0.5). A photograph's colours decode to vectors of every
//! length and direction. The check looks at the foreground as both presets define it loosely
//! (alpha > 0 and some channel above 4/255) and counts the pixels that fail each test.

use rayon::prelude::*;

use crate::lanes::LaneInstructions;
use crate::normal_map::image::{foreground_mask, NormalImage, Sample, Samples, UnitSample, MASK_PIXELS};

/// Decoded lengths outside [1 − this, 1 + this] count as far from unit length.
pub const LENGTH_TOLERANCE: f32 = 0.2;
/// Shares of failing pixels above which the image does not look like a normal image.
pub const MAX_FAILING_SHARE: f64 = 0.5;

/// The counts behind the verdict.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NormalLikeness {
    /// Foreground pixels looked at.
    pub foreground: usize,
    /// Of those, pixels whose decoded vector's length is far from 1.
    pub off_unit: usize,
    /// Of those, pixels whose decoded vector faces away from the viewer (z < 0).
    pub facing_away: usize,
}

impl NormalLikeness {
    /// Counts `image`'s pixels, in blocks on every core (the counts are integers: the sum is
    /// the same in any order).
    pub fn of(image: &NormalImage) -> Self {
        match &image.samples {
            Samples::Eight(s) => count(s),
            Samples::Sixteen(s) => count(s),
            Samples::Float(s) => count(s),
        }
    }

    /// The counts of row `row` of `image` alone (the normal-map rows count their own while
    /// they are in cache, [`NormalMapStats::likeness`]); summed over the rows they are
    /// [`NormalLikeness::of`] the image. The same block code as [`NormalLikeness::of`]'s.
    ///
    /// [`NormalMapStats::likeness`]: crate::normal_map::NormalMapStats::likeness
    pub fn of_row(image: &NormalImage, row: u32) -> Self {
        let row = image.row_range(row);
        match &image.samples {
            Samples::Eight(s) => of_block(&s[row]),
            Samples::Sixteen(s) => of_block(&s[row]),
            Samples::Float(s) => of_block(&s[row]),
        }
    }

    fn share(&self, n: usize) -> f64 {
        n as f64 / self.foreground.max(1) as f64
    }

    /// The warning to print, or `None` when the image looks like a normal image (or has no
    /// foreground, which the renders already report as black).
    pub fn warning(&self) -> Option<String> {
        let (off, away) = (self.share(self.off_unit), self.share(self.facing_away));
        if self.foreground == 0 || (off <= MAX_FAILING_SHARE && away <= MAX_FAILING_SHARE) {
            return None;
        }
        Some(format!(
            "does not look like a normal image: {:.0}% of its {} foreground pixels decode (2c − 1) to vectors \
             far from unit length and {:.0}% face away from the viewer (blue < 0.5); shading it anyway",
            100.0 * off,
            self.foreground,
            100.0 * away
        ))
    }
}

impl std::ops::Add for NormalLikeness {
    type Output = NormalLikeness;
    fn add(self, b: NormalLikeness) -> NormalLikeness {
        NormalLikeness {
            foreground: self.foreground + b.foreground,
            off_unit: self.off_unit + b.off_unit,
            facing_away: self.facing_away + b.facing_away,
        }
    }
}

/// A pixel's verdicts, each 0 or 1: foreground, and of the foreground, off unit length and
/// facing away. Branch-free, so that the counting loop runs in vector instructions.
trait Verdicts: Sample {
    fn verdicts(p: [Self; 4]) -> [u32; 3];
}

/// `image`'s counts, as [`NormalLikeness::of`] returns them.
fn count<S: Verdicts>(samples: &[[S; 4]]) -> NormalLikeness {
    const BLOCK: usize = 8192;
    samples
        .par_chunks(BLOCK)
        .map(of_block)
        .reduce(NormalLikeness::default, |a, b| a + b)
}

/// The counts of `block`: [`count_block`] in the widest form this CPU runs.
fn of_block<S: Verdicts>(block: &[[S; 4]]) -> NormalLikeness {
    let [foreground, off_unit, facing_away] = match LaneInstructions::detect() {
        // SAFETY: `detect` found AVX2 on this CPU.
        #[cfg(target_arch = "x86_64")]
        LaneInstructions::Avx2 => unsafe { count_block_avx2(block) },
        // SAFETY: `detect` found AVX-512F (and so AVX2) on this CPU.
        #[cfg(target_arch = "x86_64")]
        LaneInstructions::Avx512 => unsafe { count_block_avx512(block) },
        _ => count_block(block),
    }
    .map(|n| n as usize);
    NormalLikeness {
        foreground,
        off_unit,
        facing_away,
    }
}

/// The verdicts of `block` summed, in vector instructions as wide as the caller is compiled for
/// (SSE2 in the portable build; [`count_block_avx2`], [`count_block_avx512`]). Runs of
/// [`MASK_PIXELS`] pixels none of which has a channel above the background level are skipped:
/// their verdicts are all 0 (foreground needs one), and most of a normal image's background is
/// such runs.
#[inline(always)]
fn count_block<S: Verdicts>(block: &[[S; 4]]) -> [u32; 3] {
    block.chunks(MASK_PIXELS).fold([0u32; 3], |sum, run| {
        if foreground_mask(run, S::tp_foreground) == 0 {
            return sum;
        }
        run.iter().fold(sum, |sum, &p| {
            let v = S::verdicts(p);
            [sum[0] + v[0], sum[1] + v[1], sum[2] + v[2]]
        })
    })
}

/// [`count_block`] compiled for AVX2.
///
/// # Safety
/// The CPU must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn count_block_avx2<S: Verdicts>(block: &[[S; 4]]) -> [u32; 3] {
    count_block(block)
}

/// [`count_block`] compiled for AVX-512F.
///
/// # Safety
/// The CPU must have AVX2 and AVX-512F.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,avx512f")]
unsafe fn count_block_avx512<S: Verdicts>(block: &[[S; 4]]) -> [u32; 3] {
    count_block(block)
}

/// Integer samples tested exactly on their levels v, with F = 2^bits − 1 the full scale: the
/// decoded n = (2v − F)/F, so |n| < 1 − 0.2 exactly when Σ(2v − F)² < (4F/5)², |n| > 1 + 0.2
/// when Σ(2v − F)² > (6F/5)² (F is a multiple of 5 for 8 and 16 bits), and n_z < 0 when
/// 2v < F. No conversion to float, no square root.
macro_rules! integer_verdicts {
    ($sample:ty, $wide:ty) => {
        impl Verdicts for $sample {
            #[inline(always)]
            fn verdicts(p: [$sample; 4]) -> [u32; 3] {
                const F: $wide = <$sample>::MAX as $wide;
                const _: () = assert!(F % 5 == 0 && LENGTH_TOLERANCE == 0.2);
                let foreground = (p[3] != 0) & Self::tp_foreground(p);
                let d = [0, 1, 2].map(|c| 2 * p[c] as $wide - F);
                let squared = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                let off = !((4 * F / 5) * (4 * F / 5)..=(6 * F / 5) * (6 * F / 5)).contains(&squared);
                let away = d[2] < 0;
                [foreground, foreground & off, foreground & away].map(u32::from)
            }
        }
    };
}
integer_verdicts!(u8, i32);
integer_verdicts!(u16, i64);

/// Float samples in [0, 1]: the same tests in f32 (|n|² against 0.8² and 1.2²).
impl Verdicts for UnitSample {
    #[inline(always)]
    fn verdicts(p: [UnitSample; 4]) -> [u32; 3] {
        let foreground = (p[3].0 > 0.0) & Self::tp_foreground(p);
        let n = [0, 1, 2].map(|c| 2.0 * p[c].0 - 1.0);
        let squared = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
        let (short, long) = (1.0 - LENGTH_TOLERANCE, 1.0 + LENGTH_TOLERANCE);
        let off = !(short * short..=long * long).contains(&squared);
        [foreground, foreground & off, foreground & (n[2] < 0.0)].map(u32::from)
    }
}

#[cfg(test)]
mod tests {
    use image::{DynamicImage, Rgb, RgbImage};

    use super::*;

    fn likeness(img: RgbImage) -> NormalLikeness {
        let mut png = Vec::new();
        DynamicImage::ImageRgb8(img)
            .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
            .unwrap();
        NormalLikeness::of(&NormalImage::decode("test.png".as_ref(), &png).unwrap())
    }

    /// 8-bit encoding of a unit vector.
    fn encode(n: [f32; 3]) -> Rgb<u8> {
        Rgb(n.map(|c| ((c * 0.5 + 0.5) * 255.0).round() as u8))
    }

    #[test]
    fn a_hemisphere_of_normals_looks_like_a_normal_image() {
        let img = RgbImage::from_fn(64, 64, |x, y| {
            let (u, v) = (x as f32 / 32.0 - 1.0, y as f32 / 32.0 - 1.0);
            let r2 = u * u + v * v;
            if r2 >= 1.0 {
                Rgb([0, 0, 0])
            } else {
                encode([u, -v, (1.0 - r2).sqrt()])
            }
        });
        let l = likeness(img);
        assert!(l.foreground > 3000, "{l:?}");
        assert_eq!((l.off_unit, l.facing_away), (0, 0), "{l:?}");
        assert_eq!(l.warning(), None);
    }

    #[test]
    fn a_photograph_like_image_is_reported_with_its_shares() {
        // Browns and greys: short vectors (grey decodes to ~0) facing away (blue < 0.5).
        let img = RgbImage::from_fn(32, 32, |x, y| Rgb([120 + (x * 3) as u8, 90 + (y * 2) as u8, 60]));
        let l = likeness(img);
        assert_eq!((l.foreground, l.facing_away), (1024, 1024), "{l:?}");
        let w = l.warning().expect("warns");
        assert!(
            w.contains("of its 1024 foreground pixels") && w.contains("100% face away"),
            "{w}"
        );
    }

    /// The verdicts by definition, in f64: decode n = 2v/F − 1 and test its length and z.
    fn by_definition(levels: [u32; 3], full_scale: f64) -> [u32; 3] {
        let n = levels.map(|v| 2.0 * v as f64 / full_scale - 1.0);
        let length = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        let foreground = levels.iter().any(|&v| v as f64 / full_scale > 4.0 / 255.0);
        let off = (length - 1.0).abs() > LENGTH_TOLERANCE as f64;
        [foreground, foreground & off, foreground & (n[2] < 0.0)].map(u32::from)
    }

    #[test]
    fn integer_verdicts_are_the_definitions() {
        // 8 bits: every green and blue level, a fifth of the red ones; 16 bits: a grid through
        // both length bounds.
        for r in (0..=255u8).step_by(5) {
            for g in 0..=255u8 {
                for b in 0..=255u8 {
                    let want = by_definition([r, g, b].map(u32::from), 255.0);
                    assert_eq!(u8::verdicts([r, g, b, 255]), want, "{r} {g} {b}");
                }
                assert_eq!(u8::verdicts([r, g, 200, 0]), [0; 3], "no alpha, no foreground");
            }
        }
        for r in (0..=65535u16).step_by(1021) {
            for g in (0..=65535u16).step_by(257) {
                for b in [0, 1028, 1029, 32767, 32768, 40000, 65535] {
                    let want = by_definition([r, g, b].map(u32::from), 65535.0);
                    assert_eq!(u16::verdicts([r, g, b, 65535]), want, "{r} {g} {b}");
                }
            }
        }
        // Floats: the same verdicts as the 8-bit levels they stand for.
        for v in [
            [0, 0, 5],
            [128, 128, 255],
            [255, 255, 255],
            [10, 20, 30],
            [127, 128, 60],
        ] {
            let unit = [v[0], v[1], v[2], 255].map(|l| UnitSample(l as f32 / 255.0));
            assert_eq!(UnitSample::verdicts(unit), by_definition(v, 255.0), "{v:?}");
        }
    }

    /// The skipped runs change no count: every pixel's verdicts summed one by one, on spans of
    /// background (some with a channel at the background level, some transparent) between
    /// foreground spans of every length, and blocks that end inside a run.
    #[test]
    fn skipping_background_runs_counts_every_foreground_pixel() {
        let mut state = 12345u32;
        let mut next = move || {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            state >> 8
        };
        let mut pixels = Vec::new();
        while pixels.len() < 20_000 {
            let (span, foreground) = (next() as usize % 90, next() % 3 == 0);
            for _ in 0..span {
                let v = next().to_le_bytes();
                let p = match foreground {
                    true => [v[0], v[1], v[2], if next() % 8 == 0 { 0 } else { 255 }],
                    false => [v[0] % 5, v[1] % 5, v[2] % 5, 255],
                };
                pixels.push(p);
            }
        }
        for len in [0, 1, 31, 33, 4095, pixels.len()] {
            let block = &pixels[..len];
            let one_by_one = block.iter().fold([0u32; 3], |sum, &p| {
                let v = u8::verdicts(p);
                [sum[0] + v[0], sum[1] + v[1], sum[2] + v[2]]
            });
            assert_eq!(count_block(block), one_by_one, "{len} pixels");
            // The same block through the widest code this CPU runs, and through each compiled
            // form it can run (on an AVX-512 machine `of_block` no longer reaches the AVX2 one).
            let widest = of_block(block);
            assert_eq!(
                [widest.foreground, widest.off_unit, widest.facing_away].map(|n| n as u32),
                one_by_one,
                "{len} pixels, {:?}",
                LaneInstructions::detect()
            );
            #[cfg(target_arch = "x86_64")]
            {
                let detected = LaneInstructions::detect();
                if detected >= LaneInstructions::Avx2 {
                    // SAFETY: `detect` found AVX2.
                    assert_eq!(unsafe { count_block_avx2(block) }, one_by_one, "{len} pixels, AVX2");
                }
                if detected >= LaneInstructions::Avx512 {
                    // SAFETY: `detect` found AVX-512F and AVX2.
                    assert_eq!(
                        unsafe { count_block_avx512(block) },
                        one_by_one,
                        "{len} pixels, AVX-512"
                    );
                }
            }
        }
        assert!(count_block(&pixels)[0] > 1000, "the test has foreground");
    }

    #[test]
    fn a_black_image_has_no_foreground_and_no_warning() {
        let l = likeness(RgbImage::new(8, 8));
        assert_eq!(l.foreground, 0);
        assert_eq!(l.warning(), None);
    }
}
