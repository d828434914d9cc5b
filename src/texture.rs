//! Textures: decoded images and how materials look them up (wrap modes, bilinear filtering,
//! sRGB decoding).
//!
//! An image is decoded once per scene into 8-bit RGBA texels (16-bit sources are rounded to 8
//! bits), whatever its colour space: the colour space belongs to the use, not to the image (glTF
//! base colour and emissive textures are sRGB, the others linear), so [`TextureRef::sample`] takes
//! it as an argument and decodes sRGB texels through a 256-entry table *before* filtering, as
//! GPUs do for sRGB formats.
//!
//! Texture coordinates follow glTF: (0, 0) is the top-left corner of the image (the first texel
//! row), u grows to the right and v downwards; texel (i, j) has its centre at
//! ((i + ½)/W, (j + ½)/H). There are no mipmaps: minified textures alias unless several samples
//! per pixel average them.

use std::sync::OnceLock;

use glam::{Vec2, Vec4};

/// For a palette PNG, that every pixel's index names an entry of its palette, or what it holds
/// that does not (other PNGs pass; so does one the caller's decoder will refuse anyway). The
/// decoders turn an index past the palette's end into black without a word.
pub fn check_palette_indices(bytes: &[u8]) -> Result<(), String> {
    let decoder = |bytes| {
        let mut d = png::Decoder::new(std::io::Cursor::new(bytes));
        d.set_transformations(png::Transformations::IDENTITY);
        d.read_info().ok()
    };
    let Some(mut reader) = decoder(bytes) else {
        return Ok(());
    };
    let info = reader.info();
    if info.color_type != png::ColorType::Indexed {
        return Ok(());
    }
    let entries = info.palette.as_ref().map_or(0, |p| p.len() / 3);
    let (bits, width) = (info.bit_depth as usize, info.width as usize);
    let Some(mut buffer) = reader.output_buffer_size().map(|n| vec![0; n]) else {
        return Ok(());
    };
    let Ok(frame) = reader.next_frame(&mut buffer) else {
        return Ok(());
    };
    // Indices of 1, 2, 4 or 8 bits, packed from the high bits of each byte.
    let per_byte = 8 / bits;
    let mask = (1u32 << bits) - 1;
    let largest = buffer
        .chunks_exact(frame.line_size)
        .take(frame.height as usize)
        .flat_map(|row| {
            (0..width).map(move |x| {
                let shift = 8 - bits * (x % per_byte + 1);
                (u32::from(row[x / per_byte]) >> shift) & mask
            })
        })
        .max()
        .unwrap_or(0);
    if (largest as usize) < entries {
        Ok(())
    } else {
        Err(format!(
            "palette index {largest} used by a pixel, but the palette has {entries} entries"
        ))
    }
}

/// A decoded image: `width × height` RGBA texels, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureImage {
    /// What it was decoded from, for messages and `--explain`.
    pub label: String,
    /// Width in texels (≥ 1).
    pub width: u32,
    /// Height in texels (≥ 1).
    pub height: u32,
    /// Texels, row by row from the top.
    pub texels: Vec<[u8; 4]>,
}

/// How coordinates outside [0, 1] map into the image, per axis (glTF sampler wrapS/wrapT).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wrap {
    /// Tile: the image repeats (glTF's default).
    Repeat,
    /// Tile with every other copy mirrored.
    MirroredRepeat,
    /// Coordinates are clamped to the edge texels.
    ClampToEdge,
}

impl Wrap {
    /// Texel index `i` wrapped into `0..n` (n ≥ 1).
    #[inline(always)]
    fn apply(self, i: i64, n: i64) -> usize {
        let wrapped = match self {
            Wrap::Repeat => i.rem_euclid(n),
            Wrap::ClampToEdge => i.clamp(0, n - 1),
            Wrap::MirroredRepeat => {
                let m = i.rem_euclid(2 * n);
                if m < n {
                    m
                } else {
                    2 * n - 1 - m
                }
            }
        };
        wrapped as usize
    }
}

/// How texels are interpolated when the texture is magnified (glTF sampler magFilter).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Filter {
    /// The nearest texel.
    Nearest,
    /// Bilinear interpolation of the four nearest texels (glTF's usual choice).
    Bilinear,
}

/// Which transfer function a texture's RGB channels are stored with (alpha is always linear).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColorSpace {
    /// sRGB-encoded colour (glTF base colour and emissive textures).
    Srgb,
    /// Linear data (metallic-roughness, normal and occlusion textures).
    Linear,
}

/// `KHR_texture_transform`: texture coordinates mapped by an affine transform before the lookup,
/// uv' = T·R·S·uv with S = diag(scale), R the rotation by `rotation` radians (counter-clockwise
/// in uv space: [cos, sin; −sin, cos]) and T the translation by `offset`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvTransform {
    /// Rows of the 2×3 matrix: u' = `m[0]·u + m[1]·v + m[2]`, v' = `m[3]·u + m[4]·v + m[5]`.
    pub m: [f32; 6],
}

impl UvTransform {
    /// The extension's transform from its offset, rotation (radians) and scale.
    pub fn new(offset: [f32; 2], rotation: f32, scale: [f32; 2]) -> Self {
        let (sin, cos) = rotation.sin_cos();
        Self {
            m: [
                cos * scale[0],
                sin * scale[1],
                offset[0],
                -sin * scale[0],
                cos * scale[1],
                offset[1],
            ],
        }
    }

    /// `uv` mapped.
    #[inline]
    pub fn apply(&self, uv: Vec2) -> Vec2 {
        let m = &self.m;
        Vec2::new(m[0] * uv.x + m[1] * uv.y + m[2], m[3] * uv.x + m[4] * uv.y + m[5])
    }
}

/// A material's use of an image: which image, which texture-coordinate set, and the sampler.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureRef {
    /// Index into the scene's decoded images (`Scene::textures`).
    pub image: u32,
    /// Texture-coordinate set: 0 (`TEXCOORD_0`) or 1 (`TEXCOORD_1`).
    pub tex_coord: u8,
    /// Wrapping along u.
    pub wrap_u: Wrap,
    /// Wrapping along v.
    pub wrap_v: Wrap,
    /// Magnification filter.
    pub filter: Filter,
    /// `KHR_texture_transform`, applied to the coordinates first.
    pub transform: Option<UvTransform>,
}

/// sRGB → linear for every 8-bit code (IEC 61966-2-1):
/// c ≤ 0.04045: c/12.92, otherwise ((c + 0.055)/1.055)^2.4, with c = code/255.
pub fn srgb_decode_table() -> &'static [f32; 256] {
    static TABLE: OnceLock<[f32; 256]> = OnceLock::new();
    TABLE.get_or_init(|| {
        std::array::from_fn(|code| {
            let c = code as f32 / 255.0;
            if c <= 0.04045 {
                c / 12.92
            } else {
                ((c + 0.055) / 1.055).powf(2.4)
            }
        })
    })
}

impl TextureRef {
    /// Image `image` read through glTF's default sampler: coordinate set 0, repeating on both
    /// axes, bilinear, no transform.
    pub fn gltf_default(image: u32) -> Self {
        Self {
            image,
            tex_coord: 0,
            wrap_u: Wrap::Repeat,
            wrap_v: Wrap::Repeat,
            filter: Filter::Bilinear,
            transform: None,
        }
    }

    /// The texture at `uv`, RGBA in [0, 1]; RGB decoded to linear when `space` is sRGB.
    /// Non-finite coordinates read the texel at (0, 0) so NaN never leaves a texture lookup.
    #[inline]
    pub fn sample(&self, images: &[TextureImage], uv: Vec2, space: ColorSpace) -> Vec4 {
        let image = &images[self.image as usize];
        let uv = self.transform.map_or(uv, |t| t.apply(uv));
        let (w, h) = (image.width as i64, image.height as i64);
        // Continuous texel coordinates (texel centres at integer + ½), kept within ±1e9 so that
        // the fractional part below is finite (u·W can overflow to infinity).
        let texel_coordinate = |c: f32, n: i64| {
            let c = if c.is_finite() { c } else { 0.0 };
            (c * n as f32 - 0.5).clamp(-1e9, 1e9)
        };
        let (x, y) = (texel_coordinate(uv.x, w), texel_coordinate(uv.y, h));
        let texel = |i: i64, j: i64| -> Vec4 {
            let t = image.texels[self.wrap_v.apply(j, h) * w as usize + self.wrap_u.apply(i, w)];
            decode(t, space)
        };
        match self.filter {
            Filter::Nearest => texel((x + 0.5).floor() as i64, (y + 0.5).floor() as i64), // = ⌊u·W⌋, ⌊v·H⌋
            Filter::Bilinear => {
                let (x0, y0) = (x.floor(), y.floor());
                // Weights in [0, 1): the fractional parts. Huge coordinates lose the fraction
                // (f32 spacing > 1 texel) but stay finite.
                let (fx, fy) = (x - x0, y - y0);
                let (i, j) = (x0 as i64, y0 as i64);
                let top = texel(i, j).lerp(texel(i + 1, j), fx);
                let bottom = texel(i, j + 1).lerp(texel(i + 1, j + 1), fx);
                top.lerp(bottom, fy)
            }
        }
    }
}

#[inline(always)]
fn decode(t: [u8; 4], space: ColorSpace) -> Vec4 {
    let alpha = t[3] as f32 / 255.0;
    match space {
        ColorSpace::Linear => Vec4::new(t[0] as f32, t[1] as f32, t[2] as f32, t[3] as f32) / 255.0,
        ColorSpace::Srgb => {
            let table = srgb_decode_table();
            Vec4::new(table[t[0] as usize], table[t[1] as usize], table[t[2] as usize], alpha)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2×2 image: red, green / blue, white — with alpha 255.
    fn image() -> Vec<TextureImage> {
        vec![TextureImage {
            label: "test".into(),
            width: 2,
            height: 2,
            texels: vec![
                [255, 0, 0, 255],
                [0, 255, 0, 255],
                [0, 0, 255, 255],
                [255, 255, 255, 255],
            ],
        }]
    }

    fn reference(wrap: Wrap, filter: Filter) -> TextureRef {
        TextureRef {
            image: 0,
            tex_coord: 0,
            wrap_u: wrap,
            wrap_v: wrap,
            filter,
            transform: None,
        }
    }

    #[test]
    fn srgb_decode_of_known_codes() {
        let t = srgb_decode_table();
        assert_eq!(t[0], 0.0);
        assert_eq!(t[255], 1.0);
        // 10/255 = 0.0392 is on the linear segment; 188/255 = 0.7373 → 0.5029 (0.50289…).
        assert!((t[10] - 10.0 / 255.0 / 12.92).abs() < 1e-8);
        assert!((t[188] - 0.502_886).abs() < 1e-5, "{}", t[188]);
        // The decode inverts the output module's encoder at every code.
        for (code, &lin) in t.iter().enumerate() {
            let back = (crate::output::srgb_encode(lin) * 255.0).round() as usize;
            assert_eq!(back, code);
        }
    }

    #[test]
    fn texel_centres_return_the_texel_and_uv_origin_is_the_top_left() {
        let images = image();
        let r = reference(Wrap::ClampToEdge, Filter::Bilinear);
        let at = |u: f32, v: f32| r.sample(&images, Vec2::new(u, v), ColorSpace::Linear);
        assert_eq!(at(0.25, 0.25), Vec4::new(1.0, 0.0, 0.0, 1.0), "top-left texel is red");
        assert_eq!(at(0.75, 0.25), Vec4::new(0.0, 1.0, 0.0, 1.0));
        assert_eq!(at(0.25, 0.75), Vec4::new(0.0, 0.0, 1.0, 1.0));
        // Half way between red and green.
        let mid = at(0.5, 0.25);
        assert!(
            (mid - Vec4::new(0.5, 0.5, 0.0, 1.0)).abs().max_element() < 1e-6,
            "{mid}"
        );
    }

    #[test]
    fn bilinear_filters_linear_values_after_srgb_decoding() {
        let images = vec![TextureImage {
            label: "grey".into(),
            width: 2,
            height: 1,
            texels: vec![[0, 0, 0, 0], [188, 188, 188, 255]],
        }];
        let r = reference(Wrap::ClampToEdge, Filter::Bilinear);
        let v = r.sample(&images, Vec2::new(0.5, 0.5), ColorSpace::Srgb);
        assert!((v.x - 0.502_886 / 2.0).abs() < 1e-5, "{v}");
        assert!((v.w - 0.5).abs() < 1e-6, "alpha is linear: {v}");
    }

    #[test]
    fn uv_transforms_follow_the_extension_matrix() {
        // Rotation by a quarter turn maps (1, 0) to (cos, −sin) = (0, −1), then scale and offset.
        let t = UvTransform::new([0.5, 0.25], std::f32::consts::FRAC_PI_2, [1.0, 1.0]);
        let p = t.apply(Vec2::new(1.0, 0.0));
        assert!((p - Vec2::new(0.5, -0.75)).abs().max_element() < 1e-6, "{p}");
        let s = UvTransform::new([0.0, 0.0], 0.0, [2.0, 3.0]).apply(Vec2::new(0.25, 0.5));
        assert_eq!(s, Vec2::new(0.5, 1.5));
        // A lookup goes through it: offset u by ½ turns the left (red) texel into the right one.
        let images = image();
        let mut r = reference(Wrap::Repeat, Filter::Nearest);
        r.transform = Some(UvTransform::new([0.5, 0.0], 0.0, [1.0, 1.0]));
        let v = r.sample(&images, Vec2::new(0.25, 0.25), ColorSpace::Linear);
        assert_eq!(v, Vec4::new(0.0, 1.0, 0.0, 1.0), "green, the texel right of red");
    }

    #[test]
    fn wrap_modes() {
        let images = image();
        let sample =
            |wrap, u: f32| reference(wrap, Filter::Nearest).sample(&images, Vec2::new(u, 0.25), ColorSpace::Linear);
        let (red, green) = (Vec4::new(1.0, 0.0, 0.0, 1.0), Vec4::new(0.0, 1.0, 0.0, 1.0));
        // u = 1.25 is texel 2: repeat → 0 (red), mirrored → 1 (green), clamp → 1 (green).
        assert_eq!(sample(Wrap::Repeat, 1.25), red);
        assert_eq!(sample(Wrap::MirroredRepeat, 1.25), green);
        assert_eq!(sample(Wrap::ClampToEdge, 1.25), green);
        // u = −0.25 is texel −1: repeat → 1, mirrored → 0, clamp → 0.
        assert_eq!(sample(Wrap::Repeat, -0.25), green);
        assert_eq!(sample(Wrap::MirroredRepeat, -0.25), red);
        assert_eq!(sample(Wrap::ClampToEdge, -0.25), red);
        // u = 7.75 is texel 15: repeat → 1; mirrored: 15 mod 4 = 3 → 0.
        assert_eq!(sample(Wrap::Repeat, 7.75), green);
        assert_eq!(sample(Wrap::MirroredRepeat, 7.75), red);
    }

    #[test]
    fn non_finite_and_huge_coordinates_stay_finite() {
        let images = image();
        for wrap in [Wrap::Repeat, Wrap::MirroredRepeat, Wrap::ClampToEdge] {
            let r = reference(wrap, Filter::Bilinear);
            for uv in [
                Vec2::new(f32::NAN, 0.3),
                Vec2::new(f32::INFINITY, f32::NEG_INFINITY),
                Vec2::new(3e38, -3e38),
                Vec2::new(1e7 + 0.3, 0.5),
            ] {
                let v = r.sample(&images, uv, ColorSpace::Srgb);
                assert!(
                    v.is_finite() && v.min_element() >= 0.0 && v.max_element() <= 1.0,
                    "{uv}: {v}"
                );
            }
        }
    }
}
