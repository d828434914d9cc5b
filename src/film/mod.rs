//! Film: image size, sampling settings, and the pixel buffers samples are averaged into.
//!
//! Pixels use a box filter: a pixel's value is the plain mean of its own samples, which is what
//! Mitsuba's `box` rfilter computes, so references compare pixel for pixel.

pub mod sampler;

use glam::Vec3;
pub use sampler::SamplerKind;

/// Largest image a render accepts (width × height), a guard against absurd sizes.
pub const MAX_PIXELS: u64 = 1 << 28;
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
    /// Exposure in stops applied to 8-bit output (EXR stays linear and unscaled).
    pub exposure: f32,
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
        }
    }
}

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
        if pixels > MAX_PIXELS || self.width > 65536 || self.height > 65536 {
            return Err(format!(
                "image size {}×{} is too large (at most 65536 per side and {} pixels)",
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
        Ok(())
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

impl Image {
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
