//! Whether an image looks like a normal image, so that shading a colour photograph by mistake
//! says so instead of exiting 0 with a meaningless picture.
//!
//! A normal image stores n = 2c − 1 per pixel (tangent or view space, +z towards the viewer):
//! decoded, its foreground pixels are vectors of about unit length (8-bit rounding moves them by
//! under 1%) and face the viewer (blue ≥ 0.5). A photograph's colours decode to vectors of every
//! length and direction. The check looks at the foreground as both presets define it loosely
//! (alpha > 0 and some channel above 4/255) and counts the pixels that fail each test.

use rayon::prelude::*;

use crate::normal_map::image::NormalImage;

/// Decoded lengths outside [1 − this, 1 + this] count as far from unit length.
pub const LENGTH_TOLERANCE: f32 = 0.2;
/// Shares of failing pixels above which the image does not look like a normal image.
pub const MAX_FAILING_SHARE: f64 = 0.5;

/// The counts behind the verdict.
#[derive(Clone, Copy, Debug, PartialEq)]
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
        const BLOCK: usize = 8192;
        let none = NormalLikeness {
            foreground: 0,
            off_unit: 0,
            facing_away: 0,
        };
        let blocks = image.pixel_count().div_ceil(BLOCK);
        (0..blocks)
            .into_par_iter()
            .map(|b| {
                let mut counts = none;
                for i in b * BLOCK..((b + 1) * BLOCK).min(image.pixel_count()) {
                    counts.count(image.pixel(i));
                }
                counts
            })
            .reduce(
                || none,
                |a, b| NormalLikeness {
                    foreground: a.foreground + b.foreground,
                    off_unit: a.off_unit + b.off_unit,
                    facing_away: a.facing_away + b.facing_away,
                },
            )
    }

    /// Counts one pixel of colour `rgb` and `alpha`.
    #[inline(always)]
    fn count(&mut self, (rgb, alpha): ([f32; 3], f32)) {
        if !(alpha > 0.0 && rgb.iter().any(|&c| c > 4.0 / 255.0)) {
            return;
        }
        let n = rgb.map(|c| 2.0 * c - 1.0);
        let length = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        self.foreground += 1;
        self.off_unit += usize::from((length - 1.0).abs() > LENGTH_TOLERANCE);
        self.facing_away += usize::from(n[2] < 0.0);
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

    #[test]
    fn a_black_image_has_no_foreground_and_no_warning() {
        let l = likeness(RgbImage::new(8, 8));
        assert_eq!(l.foreground, 0);
        assert_eq!(l.warning(), None);
    }
}
