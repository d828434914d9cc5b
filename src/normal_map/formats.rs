//! The NPM3D TP4 assignment's two image formats.
//!
//! - Its renders (the `tp` preset's PNG): L_o over all pixels and all three channels is min-max
//!   normalised to [0, 1] with one global min and max, multiplied by 255 and truncated (not
//!   rounded) to 8 bits, written as RGB.
//! - Its normal images (what `pointshade bake` writes): RGBA, rgb = (n·0.5 + 0.5)·255 for a unit
//!   camera-space normal n (x right, y up, z towards the viewer), rounded to the nearest level;
//!   background pixels black with alpha 0.

use std::io::Cursor;

use glam::Vec3;
use image::{ImageFormat, RgbaImage};

use crate::film::Image;

/// The range the min-max normalisation of a render used.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Range {
    /// Smallest L_o value over all pixels and channels.
    pub min: f32,
    /// Largest L_o value over all pixels and channels.
    pub max: f32,
}

impl Range {
    /// What to tell the user when the range is empty (every pixel shades to one value), so
    /// that the min-max output is all 0.
    pub fn warning(&self) -> Option<String> {
        (!(self.max > self.min)).then(|| format!("every pixel shades to {}: the min-max output is all 0", self.min))
    }
}

/// The report's 8-bit output of `image`: ⌊(L − min)/(max − min) · 255⌋ per channel, with one
/// global min and max. Computed in f64 so the only rounding is the truncation itself.
///
/// A uniform image (max = min, e.g. every pixel background) has no range to normalise by: every
/// value is written as 0 (documented in README.md; the caller warns).
pub fn min_max_8bit(image: &Image) -> (Vec<u8>, Range) {
    let (min, max) = image
        .pixels
        .iter()
        .flat_map(|p| p.to_array())
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
    let range = Range { min, max };
    if !(max > min) {
        return (vec![0; image.pixels.len() * 3], range);
    }
    let (lo, span) = (min as f64, max as f64 - min as f64);
    let bytes = image
        .pixels
        .iter()
        .flat_map(|p| p.to_array())
        .map(|v| (((v as f64 - lo) / span) * 255.0).clamp(0.0, 255.0) as u8)
        .collect();
    (bytes, range)
}

/// [`min_max_8bit`] encoded as an RGB PNG.
pub fn encode_min_max_png(image: &Image) -> Result<(Vec<u8>, Range), String> {
    let (raw, range) = min_max_8bit(image);
    Ok((crate::output::encode_png8(image.width, image.height, raw)?, range))
}

/// A unit normal's 8-bit colour: round((n·0.5 + 0.5)·255) per component (clamped, so a
/// component a rounding error past ±1 stays in range).
#[inline]
pub fn normal_to_rgb8(n: Vec3) -> [u8; 3] {
    n.to_array()
        .map(|c| ((c * 0.5 + 0.5) * 255.0).round().clamp(0.0, 255.0) as u8)
}

/// A normal image as RGBA PNG bytes: `normals` row-major, `None` for background (black, alpha 0).
pub fn encode_normal_png(width: u32, height: u32, normals: &[Option<Vec3>]) -> Result<Vec<u8>, String> {
    let raw = normals
        .iter()
        .flat_map(|n| match n {
            Some(n) => {
                let [r, g, b] = normal_to_rgb8(*n);
                [r, g, b, 255]
            }
            None => [0; 4],
        })
        .collect();
    let img = RgbaImage::from_raw(width, height, raw).ok_or("normal buffer does not match the image size")?;
    let mut bytes = Cursor::new(Vec::new());
    img.write_to(&mut bytes, ImageFormat::Png).map_err(|e| e.to_string())?;
    Ok(bytes.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn min_max_output_truncates_with_one_global_range() {
        let mut img = Image::new(2, 1);
        img.pixels[0] = Vec3::new(1.0, 2.0, 3.0);
        img.pixels[1] = Vec3::new(5.0, 1.0 + 4.0 * (100.9 / 255.0), 1.0);
        let (raw, range) = min_max_8bit(&img);
        assert_eq!((range.min, range.max), (1.0, 5.0));
        // (2 − 1)/4·255 = 63.75 → 63; (3 − 1)/4·255 = 127.5 → 127; 100.9 → 100 (truncated).
        assert_eq!(raw, vec![0, 63, 127, 255, 100, 0]);
    }

    #[test]
    fn uniform_render_is_written_as_zeros() {
        let mut img = Image::new(3, 1);
        img.pixels.fill(Vec3::splat(0.25));
        let (raw, range) = min_max_8bit(&img);
        assert_eq!(raw, vec![0; 9]);
        assert_eq!(range.min, range.max);
    }

    #[test]
    fn normal_colours_round_trip_within_half_a_level() {
        let n = Vec3::new(0.3, -0.5, 0.8).normalize();
        let c = normal_to_rgb8(n);
        for k in 0..3 {
            let back = c[k] as f32 / 255.0 * 2.0 - 1.0;
            assert!((back - n[k]).abs() <= 1.0 / 255.0 + 1e-6, "{k}: {back} vs {}", n[k]);
        }
        assert_eq!(normal_to_rgb8(Vec3::Z), [128, 128, 255]);
        assert_eq!(normal_to_rgb8(Vec3::new(-1.0000001, 0.0, 0.0))[0], 0);
    }

    #[test]
    fn background_is_transparent_black() {
        let bytes = encode_normal_png(2, 1, &[Some(Vec3::Z), None]).unwrap();
        let img = image::load_from_memory(&bytes).unwrap().into_rgba8();
        assert_eq!(img.get_pixel(0, 0).0, [128, 128, 255, 255]);
        assert_eq!(img.get_pixel(1, 0).0, [0, 0, 0, 0]);
    }
}
