//! Normal images: a PNG (RGB or RGBA, 8 or 16 bits) decoded into its samples as stored, with
//! the checks every input gets (size, channels, a one-line error naming the file). How a pixel
//! becomes a surface point is [`crate::normal_map::pixels`].

use std::borrow::Cow;
use std::io::Cursor;
use std::path::{Path, PathBuf};

use image::{DynamicImage, ImageFormat, ImageReader};
use rayon::prelude::*;

use crate::error::{InputError, InputResult};
use crate::film::MAX_PIXELS;
use crate::lanes::{map3, F32x8, LANES};

/// The 8-bit signature every PNG file starts with.
const PNG_SIGNATURE: &[u8] = b"\x89PNG\r\n\x1a\n";

/// `tp` background: pixels whose largest RGB value is at most 4/255 of full scale (the data's
/// README: the assignment treats them as background, n = 0). In normal.png that is the black
/// surround (values 0–3), 65.5% of the pixels.
pub const TP_BACKGROUND_LEVEL: f32 = 4.0 / 255.0;

/// A decoded normal image: its RGBA samples as stored in the file (alpha at full scale where the
/// file has none). Kept as integers — 4 bytes a pixel for 8-bit images — and converted to
/// [0, 1] per pixel by [`Sample::unit`], which is cheaper than reading four floats a pixel.
/// The samples are owned (a decoded file) or borrowed for `'a` (a caller's array, read where
/// it lies).
#[derive(Clone, Debug, PartialEq)]
pub struct NormalImage<'a> {
    /// The file it was read from (for messages).
    pub source: PathBuf,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major RGBA samples.
    pub samples: Samples<'a>,
    /// Whether the file has an alpha channel.
    pub has_alpha: bool,
}

/// Row-major RGBA samples at the file's bit depth, owned or borrowed for `'a`.
#[derive(Clone, Debug, PartialEq)]
pub enum Samples<'a> {
    /// 8 bits per channel.
    Eight(Cow<'a, [[u8; 4]]>),
    /// 16 bits per channel.
    Sixteen(Cow<'a, [[u16; 4]]>),
    /// Floats in [0, 1], as a PNG's samples divided by full scale (arrays from the Python module).
    Float(Cow<'a, [[UnitSample; 4]]>),
}

impl Samples<'_> {
    /// The same samples, borrowed: a view of owned ones for as long as they live.
    pub fn borrowed(&self) -> Samples<'_> {
        match self {
            Samples::Eight(s) => Samples::Eight(Cow::Borrowed(s)),
            Samples::Sixteen(s) => Samples::Sixteen(Cow::Borrowed(s)),
            Samples::Float(s) => Samples::Float(Cow::Borrowed(s)),
        }
    }
}

/// A float sample in [0, 1]: what v/(2^bits − 1) is for an integer sample. Ordered (never NaN:
/// [`NormalImage::from_samples`] refuses NaN and values outside [0, 1]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UnitSample(pub f32);

impl Eq for UnitSample {}

impl PartialOrd for UnitSample {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for UnitSample {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

/// An integer sample of a PNG channel.
pub trait Sample: Copy + Send + Sync + Ord {
    /// Zero.
    const ZERO: Self;
    /// The largest value whose [`Sample::unit`] is ≤ [`TP_BACKGROUND_LEVEL`] (4/255 of full
    /// scale), so the tp background test can run on the integers.
    const TP_BACKGROUND_MAX: Self;
    /// Full scale, 2^bits − 1.
    const FULL_SCALE: f64;
    /// The value in [0, 1]: v / (2^bits − 1), correctly rounded.
    fn unit(self) -> f32;
    /// The integer level v itself, exactly.
    fn level(self) -> f64;

    /// The colours of the pixels at `cols` of `samples`, each channel in [0, 1] as
    /// [`Sample::unit`] gives it, one lane per pixel.
    #[inline(always)]
    fn unit_lanes(samples: &[[Self; 4]], cols: [u32; LANES]) -> [F32x8; 3] {
        map3([0, 1, 2], |c| F32x8::from_fn(|i| samples[cols[i] as usize][c].unit()))
    }

    /// Whether RGBA sample `p` is foreground for the `tp` preset: max(r, g, b) above
    /// [`Sample::TP_BACKGROUND_MAX`].
    #[inline(always)]
    fn tp_foreground(p: [Self; 4]) -> bool {
        (p[0] > Self::TP_BACKGROUND_MAX) | (p[1] > Self::TP_BACKGROUND_MAX) | (p[2] > Self::TP_BACKGROUND_MAX)
    }

    /// Whether RGBA sample `p` is foreground for the `physical` preset: alpha ≠ 0 and RGB ≠ 0.
    #[inline(always)]
    fn signed_foreground(p: [Self; 4]) -> bool {
        (p[3] != Self::ZERO) & ((p[0] != Self::ZERO) | (p[1] != Self::ZERO) | (p[2] != Self::ZERO))
    }
}

/// Pixels per [`foreground_mask`]: the bits of one `u32`.
pub const MASK_PIXELS: usize = 32;

/// Bit i set where `foreground(block[i])`, for a block of at most [`MASK_PIXELS`] pixels.
///
/// One word per block lets a scan decide an all-background or all-foreground block with one
/// comparison. Written as an OR of shifted flags, which the compiler turns into vector
/// compares and an OR reduction.
#[inline(always)]
pub fn foreground_mask<S: Copy>(block: &[S], foreground: impl Fn(S) -> bool) -> u32 {
    debug_assert!(block.len() <= MASK_PIXELS);
    block
        .iter()
        .enumerate()
        .fold(0, |mask, (i, &p)| mask | (foreground(p) as u32) << i)
}

/// v / 255 for every 8-bit value, computed once (at compile time) by exact division.
const UNIT8: [f32; 256] = {
    let mut t = [0.0f32; 256];
    let mut v = 0;
    while v < 256 {
        t[v] = v as f32 / 255.0;
        v += 1;
    }
    t
};

impl Sample for u8 {
    const ZERO: u8 = 0;
    const TP_BACKGROUND_MAX: u8 = 4;
    const FULL_SCALE: f64 = 255.0;
    #[inline(always)]
    fn unit(self) -> f32 {
        UNIT8[self as usize]
    }
    #[inline(always)]
    fn level(self) -> f64 {
        self as f64
    }

    /// Each pixel read as one word, its channels shifted out and divided by 255 in lanes: the
    /// same correctly rounded v/255 as `UNIT8`, without 24 table lookups.
    #[inline(always)]
    fn unit_lanes(samples: &[[u8; 4]], cols: [u32; LANES]) -> [F32x8; 3] {
        let mut words = [0u32; LANES];
        for (word, &col) in words.iter_mut().zip(&cols) {
            *word = u32::from_le_bytes(samples[col as usize]);
        }
        map3([0, 8, 16], |shift| {
            F32x8::from_fn(|i| ((words[i] >> shift) & 0xff) as i32 as f32) / F32x8::splat(255.0)
        })
    }

    /// The pixel as one little-endian u32 (r in the low byte); a byte b is > 4 exactly when bit
    /// 7 of ((b & 0x7f) + 0x7b) | b is set, and no byte carries into the next (0x7f + 0x7b <
    /// 0x100). Word operations that the compiler vectorises across pixels, where the three
    /// byte compares of the default are left one pixel at a time.
    #[inline(always)]
    fn tp_foreground(p: [u8; 4]) -> bool {
        let rgb = u32::from_le_bytes(p) & 0x00ff_ffff;
        (((rgb & 0x007f_7f7f) + 0x007b_7b7b) | rgb) & 0x0080_8080 != 0
    }

    #[inline(always)]
    fn signed_foreground(p: [u8; 4]) -> bool {
        let w = u32::from_le_bytes(p);
        (w >> 24 != 0) & (w & 0x00ff_ffff != 0)
    }
}

impl Sample for UnitSample {
    const ZERO: UnitSample = UnitSample(0.0);
    const TP_BACKGROUND_MAX: UnitSample = UnitSample(TP_BACKGROUND_LEVEL);
    const FULL_SCALE: f64 = 1.0;
    #[inline(always)]
    fn unit(self) -> f32 {
        self.0
    }
    #[inline(always)]
    fn level(self) -> f64 {
        self.0 as f64
    }
}

impl Sample for u16 {
    const ZERO: u16 = 0;
    const TP_BACKGROUND_MAX: u16 = 4 * 257;
    const FULL_SCALE: f64 = 65535.0;
    #[inline(always)]
    fn unit(self) -> f32 {
        self as f32 / 65535.0
    }
    #[inline(always)]
    fn level(self) -> f64 {
        self as f64
    }
}

/// Colour in [0, 1] and alpha in [0, 1] of an RGBA sample.
#[inline(always)]
fn unit_rgba<S: Sample>(p: [S; 4]) -> ([f32; 3], f32) {
    ([p[0].unit(), p[1].unit(), p[2].unit()], p[3].unit())
}

impl<'a> NormalImage<'a> {
    /// Reads and decodes the PNG at `path`.
    pub fn load(path: &Path) -> InputResult<NormalImage<'static>> {
        let bytes = crate::input_files::read(path).map_err(|e| InputError::new(path, e))?;
        Self::decode(path, &bytes)
    }

    /// An image of `width` × `height` row-major RGBA `samples` (alpha at full scale when the
    /// source has none), from `source`: the size checks [`NormalImage::decode`] makes.
    pub fn from_samples(
        source: &Path,
        width: u32,
        height: u32,
        samples: Samples<'a>,
        has_alpha: bool,
    ) -> InputResult<NormalImage<'a>> {
        let err = |problem: String| InputError::new(source, problem);
        if width == 0 || height == 0 {
            return Err(err(format!("the image is empty ({width}×{height})")));
        }
        if width as u64 * height as u64 > MAX_PIXELS {
            return Err(err(format!(
                "{width}×{height} is too large (at most {MAX_PIXELS} pixels)"
            )));
        }
        let len = match &samples {
            Samples::Eight(s) => s.len(),
            Samples::Sixteen(s) => s.len(),
            Samples::Float(s) => {
                let outside = s.iter().flatten().position(|v| !(0.0..=1.0).contains(&v.0));
                if let Some(i) = outside {
                    let (pixel, channel) = (i / 4, i % 4);
                    let (row, col) = (pixel / width as usize, pixel % width as usize);
                    return Err(err(format!(
                        "the sample at row {row}, column {col}, channel {channel} is {}: float samples are a PNG's values divided by full scale, in [0, 1] (for unit normals n, pass (n + 1) / 2)",
                        s[pixel][channel].0
                    )));
                }
                s.len()
            }
        };
        assert_eq!(len as u64, width as u64 * height as u64, "one sample per pixel");
        Ok(NormalImage {
            source: source.to_path_buf(),
            width,
            height,
            samples,
            has_alpha,
        })
    }

    /// Decodes PNG bytes. RGB and RGBA at 8 or 16 bits are accepted (palette images arrive as
    /// RGB(A)); greyscale is refused — one channel cannot hold a direction — as is anything that
    /// is not a PNG, an empty image or one larger than a render may be.
    pub fn decode(source: &Path, bytes: &[u8]) -> InputResult<NormalImage<'static>> {
        let err = |problem: String| InputError::new(source, problem);
        if !bytes.starts_with(PNG_SIGNATURE) {
            return Err(err("not a PNG file (a normal image must be an RGB or RGBA PNG)".into()));
        }
        let mut reader = ImageReader::with_format(Cursor::new(bytes), ImageFormat::Png);
        let mut limits = image::Limits::default();
        limits.max_image_width = Some(65536);
        limits.max_image_height = Some(65536);
        reader.limits(limits);
        let img = reader.decode().map_err(|e| err(format!("cannot decode PNG: {e}")))?;
        crate::texture::check_palette_indices(bytes).map_err(err)?;
        let (width, height) = (img.width(), img.height());
        let image = |samples, has_alpha| NormalImage::from_samples(source, width, height, samples, has_alpha);
        match img {
            DynamicImage::ImageRgb8(b) => image(
                Samples::Eight(b.pixels().map(|p| [p[0], p[1], p[2], u8::MAX]).collect()),
                false,
            ),
            DynamicImage::ImageRgba8(b) => image(Samples::Eight(b.pixels().map(|p| p.0).collect()), true),
            DynamicImage::ImageRgb16(b) => image(
                Samples::Sixteen(b.pixels().map(|p| [p[0], p[1], p[2], u16::MAX]).collect()),
                false,
            ),
            DynamicImage::ImageRgba16(b) => image(Samples::Sixteen(b.pixels().map(|p| p.0).collect()), true),
            DynamicImage::ImageLuma8(_)
            | DynamicImage::ImageLumaA8(_)
            | DynamicImage::ImageLuma16(_)
            | DynamicImage::ImageLumaA16(_) => Err(err(
                "greyscale PNG: a normal image needs three colour channels (RGB or RGBA)".into(),
            )),
            other => Err(err(format!("unsupported PNG colour type {:?}", other.color()))),
        }
    }

    /// The indices of row `row`'s samples.
    #[inline(always)]
    pub fn row_range(&self, row: u32) -> std::ops::Range<usize> {
        let w = self.width as usize;
        row as usize * w..(row as usize + 1) * w
    }

    /// Number of pixels.
    pub fn pixel_count(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// Bits per channel in the file (8 or 16).
    pub fn bit_depth(&self) -> u8 {
        match self.samples {
            Samples::Eight(_) => 8,
            Samples::Sixteen(_) => 16,
            Samples::Float(_) => 32,
        }
    }

    /// Colour and alpha of pixel `index` (row-major), each in [0, 1].
    #[inline(always)]
    pub fn pixel(&self, index: usize) -> ([f32; 3], f32) {
        match &self.samples {
            Samples::Eight(s) => unit_rgba(s[index]),
            Samples::Sixteen(s) => unit_rgba(s[index]),
            Samples::Float(s) => unit_rgba(s[index]),
        }
    }

    /// The integer RGB levels of pixel `index` (row-major), exactly.
    pub fn levels(&self, index: usize) -> [f64; 3] {
        match &self.samples {
            Samples::Eight(s) => map3([0, 1, 2], |c| s[index][c].level()),
            Samples::Sixteen(s) => map3([0, 1, 2], |c| s[index][c].level()),
            Samples::Float(s) => map3([0, 1, 2], |c| s[index][c].level()),
        }
    }

    /// Full scale of a level: 255 or 65535.
    pub fn full_scale(&self) -> f64 {
        match self.samples {
            Samples::Eight(_) => u8::FULL_SCALE,
            Samples::Sixteen(_) => u16::FULL_SCALE,
            Samples::Float(_) => UnitSample::FULL_SCALE,
        }
    }

    /// Smallest and largest RGB level over every pixel (a parallel, vectorised scan).
    pub fn level_range(&self) -> (f64, f64) {
        fn range<S: Sample>(s: &[[S; 4]]) -> Option<(f64, f64)> {
            let first = s.first()?[0];
            let (lo, hi) = s
                .par_chunks(4096)
                .map(|chunk| {
                    // Element-wise min/max over blocks of 16 pixels (64 samples, alpha included
                    // and left out at the end): fixed-size loops the compiler packs into vector
                    // min/max instructions.
                    const BLOCK: usize = 16;
                    let (mut lo, mut hi) = ([first; 4 * BLOCK], [first; 4 * BLOCK]);
                    let blocks = chunk.chunks_exact(BLOCK);
                    let rest = blocks.remainder();
                    for block in blocks {
                        for (k, &v) in block.as_flattened().iter().enumerate() {
                            lo[k] = lo[k].min(v);
                            hi[k] = hi[k].max(v);
                        }
                    }
                    for (k, &v) in rest.as_flattened().iter().enumerate() {
                        lo[k] = lo[k].min(v);
                        hi[k] = hi[k].max(v);
                    }
                    let rgb = |k: &usize| k % 4 != 3;
                    let lo = (0..4 * BLOCK).filter(rgb).map(|k| lo[k]).min().unwrap_or(first);
                    let hi = (0..4 * BLOCK).filter(rgb).map(|k| hi[k]).max().unwrap_or(first);
                    (lo, hi)
                })
                .reduce(|| (first, first), |a, b| (a.0.min(b.0), a.1.max(b.1)));
            Some((lo.level(), hi.level()))
        }
        match &self.samples {
            Samples::Eight(s) => range(s),
            Samples::Sixteen(s) => range(s),
            Samples::Float(s) => range(s),
        }
        .unwrap_or((0.0, 0.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Float samples read as the integers divided by full scale; NaN and values outside [0, 1]
    /// are an error naming the sample.
    #[test]
    fn float_samples_are_units_and_checked() {
        let source = Path::new("normals");
        let unit = |v: [f32; 4]| v.map(UnitSample);
        let image = NormalImage::from_samples(
            source,
            2,
            1,
            Samples::Float(vec![unit([0.2, 0.4, 1.0, 1.0]); 2].into()),
            false,
        );
        let image = image.unwrap();
        assert_eq!(image.pixel(1), ([0.2, 0.4, 1.0], 1.0));
        assert_eq!(image.levels(0), [0.2f32 as f64, 0.4f32 as f64, 1.0]);
        assert_eq!(image.full_scale(), 1.0);
        for bad in [f32::NAN, -0.1, 1.5] {
            let samples = Samples::Float(vec![unit([0.2, 0.4, 1.0, 1.0]), unit([0.5, bad, 0.5, 1.0])].into());
            let e = NormalImage::from_samples(source, 2, 1, samples, false).unwrap_err();
            let expected = format!("normals: the sample at row 0, column 1, channel 1 is {bad}:");
            assert!(e.to_string().starts_with(&expected), "{e}");
        }
    }

    fn png(img: DynamicImage) -> Vec<u8> {
        let mut bytes = Cursor::new(Vec::new());
        img.write_to(&mut bytes, ImageFormat::Png).unwrap();
        bytes.into_inner()
    }

    #[test]
    fn eight_and_sixteen_bit_images_decode_to_the_same_values() {
        let rgba8 = image::RgbaImage::from_fn(3, 2, |x, y| image::Rgba([x as u8 * 100, y as u8 * 200, 255, 128]));
        let rgba16 = image::ImageBuffer::<image::Rgba<u16>, _>::from_fn(3, 2, |x, y| {
            image::Rgba([x as u16 * 100 * 257, y as u16 * 200 * 257, 65535, 128 * 257])
        });
        let a = NormalImage::decode(Path::new("a.png"), &png(rgba8.into())).unwrap();
        let b = NormalImage::decode(Path::new("b.png"), &png(rgba16.into())).unwrap();
        assert_eq!((a.bit_depth(), b.bit_depth()), (8, 16));
        for i in 0..6 {
            assert_eq!(a.pixel(i), b.pixel(i), "v/255 = 257v/65535");
        }
        assert_eq!(a.pixel(5), ([200.0 / 255.0, 200.0 / 255.0, 1.0], 128.0 / 255.0));
        assert!(a.has_alpha);
        let rgb = NormalImage::decode(Path::new("c.png"), &png(image::RgbImage::new(2, 2).into())).unwrap();
        assert_eq!((rgb.has_alpha, rgb.pixel(3).1), (false, 1.0));
    }

    #[test]
    fn eight_bit_table_is_exact_division() {
        for v in 0..=255u8 {
            assert_eq!(v.unit(), v as f32 / 255.0);
        }
        assert_eq!(4u8.unit(), TP_BACKGROUND_LEVEL);
        assert_eq!(1028u16.unit(), TP_BACKGROUND_LEVEL, "4/255 of full scale at 16 bits");
    }

    #[test]
    fn eight_bit_lanes_convert_as_the_table() {
        let samples: Vec<[u8; 4]> = (0..=255u8).map(|v| [v, v.wrapping_mul(7), 255 - v, v / 3]).collect();
        for start in (0..256 - LANES as u32).step_by(5) {
            let cols = std::array::from_fn(|i| start + (i as u32 * 3) % (256 - start));
            let lanes = u8::unit_lanes(&samples, cols);
            for (i, &col) in cols.iter().enumerate() {
                for (c, lane) in lanes.iter().enumerate() {
                    let v = samples[col as usize][c];
                    assert_eq!(lane.0[i].to_bits(), v.unit().to_bits(), "value {v}");
                }
            }
        }
    }

    #[test]
    fn eight_bit_word_tests_agree_with_the_channel_tests() {
        // Every RGB triple, with alpha 0, a middle value and full: the word forms of the u8
        // foreground tests against the per-channel defaults (run on u16, the same rules).
        for rgb in 0..1u32 << 24 {
            for alpha in [0u8, 77, 255] {
                let p = (rgb | (alpha as u32) << 24).to_le_bytes();
                let wide = p.map(|v| v as u16 * 257);
                assert_eq!(u8::tp_foreground(p), u16::tp_foreground(wide), "{p:?}");
                assert_eq!(u8::signed_foreground(p), u16::signed_foreground(wide), "{p:?}");
            }
        }
    }

    #[test]
    fn integer_background_tests_agree_with_the_float_rule() {
        for v in 0..=255u8 {
            assert_eq!(v <= u8::TP_BACKGROUND_MAX, v.unit() <= TP_BACKGROUND_LEVEL, "{v}");
            assert_eq!(v == u8::ZERO, v.unit() == 0.0);
        }
        for v in 0..=u16::MAX {
            assert_eq!(v <= u16::TP_BACKGROUND_MAX, v.unit() <= TP_BACKGROUND_LEVEL, "{v}");
            assert_eq!(v == u16::ZERO, v.unit() == 0.0);
        }
    }

    #[test]
    fn greyscale_and_non_png_inputs_are_refused() {
        let grey = image::GrayImage::from_pixel(4, 4, image::Luma([9]));
        let e = NormalImage::decode(Path::new("g.png"), &png(grey.into())).unwrap_err();
        assert!(e.problem.contains("greyscale"), "{e}");
        let e = NormalImage::decode(Path::new("j.png"), b"\xff\xd8\xff\xe0 JFIF").unwrap_err();
        assert!(e.problem.contains("not a PNG"), "{e}");
        let mut truncated = png(image::RgbImage::new(8, 8).into());
        truncated.truncate(40);
        let e = NormalImage::decode(Path::new("t.png"), &truncated).unwrap_err();
        assert!(e.problem.contains("cannot decode PNG"), "{e}");
    }
}
