//! Normal images: each pixel of a PNG that stores a normal becomes a surface point — one
//! [`SurfacePoint`] ([`ImageSurface::point`]), or several at a time as [`SurfaceLanes`] (what
//! `pointshade normalmap` shades: eight in f32 lanes for the `physical` preset,
//! [`ImageSurface::lanes`]; four in float64 lanes for `tp`, [`ImageSurface::tp_lanes`]), by the
//! same generic functions.
//!
//! This is the normal-map mode's counterpart of [`crate::surface::primary`]: where a mesh render finds a
//! surface point with a camera ray and a BVH, here the point is read off a pixel — no geometry,
//! no rays. How a colour
//! becomes a normal, where the pixel sits in space and where the viewer is depend on the preset:
//!
//! | | `tp` (the NPM3D TP4 report) | `physical` |
//! |---|---|---|
//! | normal | (v − min)/(max − min) on the integer levels v, one global min and max over all RGB values, used as is, in float64 | normalise(2c − 1) |
//! | background | max(r, g, b) ≤ 4/255: n = 0, no surface point | alpha = 0, or r = g = b = 0 |
//! | position | (row, column, 0), in pixels | image plane z = 0, centred, image height = 2 units, +x right, +y up |
//!
//! ω_o comes from a [`Viewer`]: a direction (orthographic) or a position (ω_o = (x_c − x)/‖x_c − x‖;
//! under `tp` in the material's [`UnitForm`]: as the report writes it for Cook-Torrance, by one
//! reciprocal for Lambert and Blinn-Phong).

use glam::{Vec2, Vec3};

use crate::lanes::{dot3, map3, normalize_or_zero, F32x8, LaneArray, Real, Scalar, LANES};
use crate::normal_map::image::NormalImage;
use crate::normal_map::image::TP_BACKGROUND_LEVEL;
use crate::normal_map::image::{foreground_mask, Sample, MASK_PIXELS};
use crate::normal_map::image::{Samples, UnitSample};
use crate::shading::convention::{unit_of_length, UnitForm};
use crate::surface::{SurfaceLanes, SurfacePoint};

/// The `tp` preset's scaling: n = (v − min)/(max − min) with one min and max over every RGB value
/// of the image, in float64 and in the units of the values it scales — an image's integer levels
/// ([`MinMaxScaling::of`]: numerator and denominator exact, one rounding), or [0, 1]
/// ([`MinMaxScaling::new`]). Only constructible with min < max, so the division is always defined.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MinMaxScaling {
    min: f64,
    max: f64,
    full_scale: f64,
}

impl MinMaxScaling {
    /// The scaling of values in [0, 1] spanning [`min`, `max`]; an error unless min < max, both
    /// finite (max − min = 0 would divide by zero: such an image is one flat colour and holds no
    /// normal information).
    pub fn new(min: f64, max: f64) -> Result<MinMaxScaling, String> {
        Self::of_levels(min, max, 1.0)
    }

    /// The scaling of levels in [0, `full_scale`] spanning [`min`, `max`] (see [`MinMaxScaling::new`]).
    pub fn of_levels(min: f64, max: f64, full_scale: f64) -> Result<MinMaxScaling, String> {
        if !(max > min && min.is_finite() && max.is_finite()) {
            return Err(format!(
                "every RGB value is {}: the tp preset's scaling (c − min)/(max − min) divides by zero",
                min / full_scale
            ));
        }
        // max − min > 0 is exact for levels, and ≥ one ulp of max otherwise: never 0.
        Ok(MinMaxScaling { min, max, full_scale })
    }

    /// The scaling of `image`'s RGB levels (see [`MinMaxScaling::new`]).
    pub fn of(image: &NormalImage) -> Result<MinMaxScaling, String> {
        let (min, max) = image.level_range();
        Self::of_levels(min, max, image.full_scale())
    }

    /// Smallest RGB value of the image, in its units.
    pub fn min(&self) -> f64 {
        self.min
    }

    /// Largest RGB value of the image, in its units.
    pub fn max(&self) -> f64 {
        self.max
    }

    /// Full scale of the units: 255 or 65535 for levels, 1 for values in [0, 1].
    pub fn full_scale(&self) -> f64 {
        self.full_scale
    }

    /// Whether a pixel of values `v` is background: max(v) ≤ 4/255 of full scale (4 and 1028
    /// exactly for levels).
    #[inline(always)]
    pub fn is_background(&self, v: [f64; 3]) -> bool {
        v[0].max(v[1]).max(v[2]) <= 4.0 * self.full_scale / 255.0
    }

    /// The normal of foreground values `v`: (v − min)/(max − min), in any [`Real`].
    #[inline(always)]
    pub fn normal<R: Real>(&self, v: [R; 3]) -> [R; 3] {
        let (min, range) = (R::lit(self.min), R::lit(self.max - self.min));
        map3(v, |c| (c - min) / range)
    }
}

/// What the `tp` lane path decodes with: the scaling, the normal component of every 8-bit
/// level in precision `T` — (v − min)/(max − min) computed once per level, so a pixel's normal
/// is three table reads with the same bits as three divisions — and whether ω_o is formed.
#[derive(Clone, Debug)]
pub struct MinMaxDecoding<T> {
    /// The image's scaling.
    pub scaling: MinMaxScaling,
    /// [`MinMaxScaling::normal`] of each 8-bit level (unused for other samples).
    eight_bit: [T; 256],
    /// How the points get their ω_o from the offset to the viewer, or `None`: then `to_viewer`
    /// is the zero vector, which is the same L_o where the material does not read it, and saves
    /// a square root and the divisions a pixel (the material's
    /// [`clamped_to_viewer_form`](crate::shading::shader::clamped_to_viewer_form)).
    pub to_viewer: Option<UnitForm>,
}

impl<T: Scalar> MinMaxDecoding<T> {
    /// The table of `scaling`, for points that get their ω_o in `to_viewer`'s form, or none.
    pub fn new(scaling: MinMaxScaling, to_viewer: Option<UnitForm>) -> Self {
        let eight_bit = std::array::from_fn(|v| scaling.normal([T::lit(v as f64); 3])[0]);
        MinMaxDecoding {
            scaling,
            eight_bit,
            to_viewer,
        }
    }
}

/// How a pixel's colour becomes a normal, and which pixels are background.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NormalDecoding {
    /// `tp`: the min-max-scaled colour as is; background (n = 0) at max(r, g, b) ≤ 4/255.
    MinMax(MinMaxScaling),
    /// `physical`: n = normalise(2c − 1); background where alpha = 0 or r = g = b = 0.
    Signed,
}

impl NormalDecoding {
    /// The normal stored in colour `rgb` with opacity `alpha`, or `None` for background.
    ///
    /// `MinMax`: max − min > 0 is guaranteed by [`MinMaxScaling::new`]; the colour in [0, 1] is
    /// taken to the scaling's units and decoded in float64, then rounded to f32 (the `tp` image
    /// path shades in float64 from the levels themselves: [`ImageSurface::tp_lanes`]). `Signed`:
    /// 2c − 1 can only be the zero vector for c = (½, ½, ½), which no 8- or 16-bit value encodes
    /// exactly; if it does occur the pixel has no direction and is background too (never a NaN
    /// from 0/0).
    #[inline(always)]
    pub fn normal(self, rgb: [f32; 3], alpha: f32) -> Option<Vec3> {
        let (background, n) = match self {
            NormalDecoding::MinMax(s) => {
                let v = rgb.map(|c| c as f64 * s.full_scale);
                let background = rgb[0].max(rgb[1]).max(rgb[2]) <= TP_BACKGROUND_LEVEL;
                (background, Vec3::from(s.normal(v).map(|c| c as f32)))
            }
            NormalDecoding::Signed => (alpha == 0.0 || rgb == [0.0; 3], Vec3::from(Self::signed(rgb))),
        };
        (!background && n != Vec3::ZERO).then_some(n)
    }

    /// The `physical` normal of the foreground colour `rgb` (each channel in [0, 1]), in any
    /// [`Real`] (one pixel in f32, eight in [`F32x8`] lanes): normalise(2c − 1), zero where
    /// 2c − 1 is.
    #[inline(always)]
    pub fn signed<R: Real>(rgb: [R; 3]) -> [R; 3] {
        normalize_or_zero(map3(rgb, |c| c * R::lit(2.0) - R::one()))
    }
}

/// Where the pixels of a normal image sit in space.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixelPositions {
    /// `tp`: pixel (row r, column c) is x = (r, c, 0), in pixels.
    RowColumn,
    /// `physical`: the image plane z = 0, centred on the origin, the image's height 2 units (so
    /// a pixel is 2/H wide), +x to the right, +y up; a pixel's position is its centre.
    ImagePlane,
}

/// Where the viewer is, which gives ω_o.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Viewer {
    /// Orthographic: ω_o is this unit vector everywhere.
    Direction(Vec3),
    /// A viewer at this position: ω_o = (x_c − x)/‖x_c − x‖, or 0 at x = x_c (documented: a
    /// viewer at the point sees n·ω_o = 0).
    Position(Vec3),
}

impl Viewer {
    /// The orthographic view of the `physical` preset: looking down −z, so ω_o = +z.
    pub const ALONG_Z: Viewer = Viewer::Direction(Vec3::Z);

    /// ω_o at `x`.
    #[inline(always)]
    pub fn to_viewer(self, x: Vec3) -> Vec3 {
        Vec3::from(self.to_viewer_from(x.to_array()))
    }

    /// ω_o at `x`, in any [`Real`].
    #[inline(always)]
    pub fn to_viewer_from<R: Real>(self, x: [R; 3]) -> [R; 3] {
        match self {
            Viewer::Direction(d) => map3(d.to_array(), R::of),
            Viewer::Position(c) => {
                let c = map3(c.to_array(), R::of);
                normalize_or_zero([c[0] - x[0], c[1] - x[1], c[2] - x[2]])
            }
        }
    }
}

/// Turns pixels of one image into surface points: decoding, positions and viewer together.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageSurface {
    /// Colour → normal.
    pub decoding: NormalDecoding,
    /// Pixel → position.
    pub positions: PixelPositions,
    /// Position → ω_o.
    pub viewer: Viewer,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Index of the material every point gets.
    pub material: u32,
}

impl ImageSurface {
    /// Position of pixel (`col`, `row`).
    #[inline(always)]
    pub fn position(&self, col: u32, row: u32) -> Vec3 {
        Vec3::from(self.position_of(col as f32, row as f32))
    }

    /// Position of the pixels at columns `col` of rows `row` (whole numbers), in any [`Real`].
    #[inline(always)]
    pub fn position_of<R: Real>(&self, col: R, row: R) -> [R; 3] {
        match self.positions {
            PixelPositions::RowColumn => [row, col, R::zero()],
            PixelPositions::ImagePlane => {
                let size = R::of(2.0 / self.height as f32);
                [
                    (col + R::lit(0.5) - R::of(0.5 * self.width as f32)) * size,
                    (R::of(0.5 * self.height as f32) - row - R::lit(0.5)) * size,
                    R::zero(),
                ]
            }
        }
    }

    /// The surface point of pixel (`col`, `row`) with colour `rgb` and opacity `alpha` (1 for
    /// images without alpha), or `None` for background. The geometric normal is the image
    /// plane's, +z, facing the camera that took the image.
    #[inline(always)]
    pub fn point(&self, col: u32, row: u32, rgb: [f32; 3], alpha: f32) -> Option<SurfacePoint> {
        let shading_normal = self.decoding.normal(rgb, alpha)?;
        let position = self.position(col, row);
        Some(SurfacePoint {
            position,
            shadow_lift: 0.0,
            geometric_normal: Vec3::Z,
            shading_normal,
            uv: Vec2::ZERO,
            uv1: Vec2::ZERO,
            material: self.material,
            to_viewer: self.viewer.to_viewer(position),
        })
    }

    /// Appends the columns of row `row`'s foreground pixels (those [`ImageSurface::point`] makes
    /// a surface point of, bar the one colour noted at [`ImageSurface::lanes`]) to `out`. The
    /// background rules of [`NormalDecoding::normal`] are tested on the integer samples (the same
    /// decision for every value: see the tests), so background pixels cost no conversion.
    #[inline(always)]
    pub fn foreground_columns(&self, image: &NormalImage, row: u32, out: &mut Vec<u32>) {
        #[inline(always)]
        fn push<S: Sample>(samples: &[[S; 4]], out: &mut Vec<u32>, foreground: impl Fn([S; 4]) -> bool) {
            // Blocks of 32 pixels: their mask is computed without branches (in vector
            // instructions), blocks all background or all foreground are decided at once, and
            // the others compacted without a branch per pixel. A per-pixel `if` here
            // mispredicts along every silhouette and cost more than the shading.
            for (k, block) in samples.chunks(MASK_PIXELS).enumerate() {
                let mask = foreground_mask(block, &foreground);
                let base = (k * MASK_PIXELS) as u32;
                if mask == u32::MAX >> (MASK_PIXELS - block.len()) {
                    out.extend(base..base + block.len() as u32);
                } else if mask != 0 {
                    let (mut columns, mut n) = ([0u32; MASK_PIXELS], 0);
                    for (i, column) in (base..base + block.len() as u32).enumerate() {
                        columns[n] = column;
                        n += (mask >> i) as usize & 1;
                    }
                    out.extend_from_slice(&columns[..n]);
                }
            }
        }
        #[inline(always)]
        fn rows<S: Sample>(s: &ImageSurface, samples: &[[S; 4]], out: &mut Vec<u32>) {
            match s.decoding {
                NormalDecoding::MinMax(_) => push(samples, out, S::tp_foreground),
                NormalDecoding::Signed => push(samples, out, S::signed_foreground),
            }
        }
        match &image.samples {
            Samples::Eight(s) => rows(self, &s[image.row_range(row)], out),
            Samples::Sixteen(s) => rows(self, &s[image.row_range(row)], out),
            Samples::Float(s) => rows(self, &s[image.row_range(row)], out),
        }
    }

    /// The `physical` surface points of the pixels at columns `cols` of row `row`, in lanes: the
    /// decoding, position and ω_o of [`ImageSurface::point`], computed by the same generic
    /// functions eight pixels per operation. The columns must be foreground
    /// ([`ImageSurface::foreground_columns`]); the one foreground colour `point` still rejects — a
    /// 2c − 1 = 0, which no 8- or 16-bit value encodes — would give a zero normal here.
    #[inline(always)]
    pub fn lanes(&self, image: &NormalImage, row: u32, cols: [u32; LANES]) -> SurfaceLanes {
        debug_assert_eq!(self.decoding, NormalDecoding::Signed, "tp pixels go through tp_lanes");
        let rgb = match &image.samples {
            Samples::Eight(s) => u8::unit_lanes(&s[image.row_range(row)], cols),
            Samples::Sixteen(s) => u16::unit_lanes(&s[image.row_range(row)], cols),
            Samples::Float(s) => UnitSample::unit_lanes(&s[image.row_range(row)], cols),
        };
        // Columns are below 2^16 (images are at most 65536 wide): exact through i32, which
        // converts in one instruction where u32 → f32 takes several.
        let col = F32x8::from_fn(|i| cols[i] as i32 as f32);
        let position = self.position_of(col, F32x8::splat(row as f32));
        SurfaceLanes {
            position,
            shading_normal: NormalDecoding::signed(rgb),
            to_viewer: self.viewer.to_viewer_from(position),
            material: self.material,
        }
    }

    /// The `tp` surface points of the pixels at columns `cols` (foreground; one per lane) of row
    /// `row`, in the lanes of `V` (float64 lanes for the preset; f32 lanes for comparison):
    /// [`ImageSurface::tp_point`] of each. 8-bit levels take their normal from `decoding`'s table
    /// (the same quotients), other samples divide.
    #[inline(always)]
    pub fn tp_lanes<V: LaneArray>(
        &self,
        decoding: &MinMaxDecoding<V::Scalar>,
        image: &NormalImage,
        row: u32,
        cols: &[u32],
    ) -> SurfaceLanes<V> {
        #[inline(always)]
        fn levels<S: Sample, V: LaneArray>(samples: &[[S; 4]], cols: &[u32]) -> [V; 3] {
            map3([0, 1, 2], |c| {
                V::from_fn(|i| V::Scalar::lit(samples[cols[i] as usize][c].level()))
            })
        }
        let scaling = &decoding.scaling;
        let normal = match &image.samples {
            Samples::Eight(s) => {
                // A function per channel, not a closure over the channels: the compiler does
                // not always inline a closure, and an outlined one costs more than the lookups.
                #[inline(always)]
                fn channel<V: LaneArray>(table: &[V::Scalar; 256], s: &[[u8; 4]], cols: &[u32], c: usize) -> V {
                    V::from_fn(|i| table[s[cols[i] as usize][c] as usize])
                }
                let (s, n) = (&s[image.row_range(row)], &decoding.eight_bit);
                [channel(n, s, cols, 0), channel(n, s, cols, 1), channel(n, s, cols, 2)]
            }
            Samples::Sixteen(s) => scaling.normal(levels::<_, V>(&s[image.row_range(row)], cols)),
            Samples::Float(s) => scaling.normal(levels::<_, V>(&s[image.row_range(row)], cols)),
        };
        let col = V::from_fn(|i| V::Scalar::lit(cols[i] as f64));
        self.tp_point_with_normal(normal, col, V::lit(row as f64), decoding.to_viewer)
    }

    /// The `tp` surface point of a foreground pixel at (`col`, `row`) with values `v` in
    /// `scaling`'s units, in any [`Real`] (float64 for the preset): n = (v − min)/(max − min),
    /// x = (row, col, 0), and ω_o = (x_c − x)/‖x_c − x‖ in `form` — as the report writes it
    /// ([`UnitForm::Quotients`]: in float64, n·ω_o is then the numpy implementation's to the bit)
    /// or by one reciprocal.
    #[inline(always)]
    pub fn tp_point<R: Real>(
        &self,
        scaling: &MinMaxScaling,
        v: [R; 3],
        col: R,
        row: R,
        form: UnitForm,
    ) -> SurfaceLanes<R> {
        self.tp_point_with_normal(scaling.normal(v), col, row, Some(form))
    }

    /// [`ImageSurface::tp_point`] of a pixel whose normal `n` is decoded; ω_o formed in
    /// `to_viewer`'s form, or the zero vector where it is `None`
    /// ([`MinMaxDecoding::to_viewer`]).
    #[inline(always)]
    fn tp_point_with_normal<R: Real>(&self, n: [R; 3], col: R, row: R, to_viewer: Option<UnitForm>) -> SurfaceLanes<R> {
        let position = self.position_of(col, row);
        let to_viewer = match (self.viewer, to_viewer) {
            (_, None) => [R::zero(); 3],
            (Viewer::Direction(d), _) => map3(d.to_array(), R::of),
            (Viewer::Position(c), Some(form)) => {
                let c = map3(c.to_array(), R::of);
                let offset = [c[0] - position[0], c[1] - position[1], c[2] - position[2]];
                unit_of_length(offset, dot3(offset, offset).sqrt(), form).0
            }
        };
        SurfaceLanes {
            position,
            shading_normal: n,
            to_viewer,
            material: self.material,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tp_scaling_is_global_and_refuses_constant_images() {
        let img = NormalImage {
            source: "x.png".into(),
            width: 2,
            height: 1,
            samples: Samples::Eight(vec![[51, 102, 153, 255], [76, 204, 127, 255]].into()),
            has_alpha: false,
        };
        let s = MinMaxScaling::of(&img).unwrap();
        assert_eq!((s.min(), s.max(), s.full_scale()), (51.0, 204.0, 255.0), "levels");
        // (v − min)/(max − min) on the levels: one division of exact integers.
        assert_eq!(s.normal([51.0, 127.5, 204.0]), [0.0, 0.5, 1.0]);
        assert_eq!(s.normal([102.0f64; 3])[0], (102.0 - 51.0) / 153.0);
        let n = NormalDecoding::MinMax(s).normal([0.2, 0.5, 0.8], 1.0).unwrap();
        assert!((n - Vec3::new(0.0, 0.5, 1.0)).abs().max_element() < 1e-6);
        let flat = NormalImage {
            samples: Samples::Sixteen(vec![[300; 4]; 2].into()),
            ..img
        };
        assert!(MinMaxScaling::of(&flat).unwrap_err().contains("divides by zero"));
        assert!(MinMaxScaling::new(0.3, 0.3).is_err());
        // Many pixels (whole blocks and a remainder), the extremes in different channels and
        // blocks, alpha outside the RGB range: alpha must not count.
        let many = NormalImage {
            width: 37,
            height: 3,
            samples: Samples::Eight(
                (0..111u32)
                    .map(|i| match i {
                        40 => [90, 12, 90, 0],
                        77 => [90, 90, 201, 255],
                        _ => [90, 60 + (i % 7) as u8, 100, if i % 2 == 0 { 0 } else { 255 }],
                    })
                    .collect(),
            ),
            has_alpha: true,
            source: "m.png".into(),
        };
        assert_eq!(many.level_range(), (12.0, 201.0));
        assert!(MinMaxScaling::new(0.0, f64::NAN).is_err());
    }

    #[test]
    fn tp_background_of_levels_is_the_integer_rule() {
        // The f64 test on levels decides as the integer test the row scan runs, at both depths.
        let eight = MinMaxScaling::of_levels(0.0, 255.0, 255.0).unwrap();
        for v in 0..=255u8 {
            assert_eq!(
                eight.is_background([v as f64, 0.0, 0.0]),
                !u8::tp_foreground([v, 0, 0, 255]),
                "{v}"
            );
        }
        let sixteen = MinMaxScaling::of_levels(0.0, 65535.0, 65535.0).unwrap();
        for v in 0..=65535u16 {
            assert_eq!(
                sixteen.is_background([0.0, v as f64, 0.0]),
                !u16::tp_foreground([0, v, 0, 65535]),
                "{v}"
            );
        }
    }

    #[test]
    fn tp_background_is_the_near_black_surround() {
        let d = NormalDecoding::MinMax(MinMaxScaling::new(0.0, 1.0).unwrap());
        assert_eq!(d.normal([4.0 / 255.0, 3.0 / 255.0, 0.0], 1.0), None);
        assert!(d.normal([5.0 / 255.0, 0.0, 0.0], 1.0).is_some());
    }

    #[test]
    fn signed_decoding_normalises_and_masks_background() {
        let d = NormalDecoding::Signed;
        let n = d.normal([1.0, 0.5, 1.0], 1.0).unwrap();
        assert!((n - Vec3::new(1.0, 0.0, 1.0).normalize()).length() < 1e-6);
        assert_eq!(d.normal([0.0; 3], 1.0), None, "RGB exactly 0");
        assert_eq!(d.normal([0.5, 0.5, 1.0], 0.0), None, "alpha 0");
        assert_eq!(d.normal([0.5; 3], 1.0), None, "2c − 1 = 0 has no direction");
    }

    #[test]
    fn positions_follow_each_preset() {
        let s = ImageSurface {
            decoding: NormalDecoding::Signed,
            positions: PixelPositions::RowColumn,
            viewer: Viewer::Position(Vec3::new(1.0, 300.0, 1.0)),
            width: 4,
            height: 2,
            material: 0,
        };
        assert_eq!(s.position(3, 1), Vec3::new(1.0, 3.0, 0.0));
        let p = ImageSurface {
            positions: PixelPositions::ImagePlane,
            ..s
        };
        // Height 2 units: pixels 1 unit wide; the image spans x ∈ [−2, 2], y ∈ [−1, 1].
        assert_eq!(p.position(0, 0), Vec3::new(-1.5, 0.5, 0.0));
        assert_eq!(p.position(3, 1), Vec3::new(1.5, -0.5, 0.0));
        let sp = s.point(3, 1, [1.0, 0.5, 1.0], 1.0).unwrap();
        let wo = (Vec3::new(1.0, 300.0, 1.0) - Vec3::new(1.0, 3.0, 0.0)).normalize();
        assert!((sp.to_viewer - wo).length() < 1e-7);
        assert_eq!(Viewer::Position(Vec3::ONE).to_viewer(Vec3::ONE), Vec3::ZERO);
    }
}
