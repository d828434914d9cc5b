//! Output: images to files. PNG is 8-bit sRGB with exposure and clamping; EXR is linear float32
//! RGB, untouched. All files of a render are encoded in memory first, written to temporary
//! files beside their targets and renamed only when every one of them is written, so a failure
//! never leaves partial output behind. The normal-map mode's formats (min-max 8-bit renders,
//! RGBA normal images) are in [`crate::normal_map::formats`].

pub mod atomic;
pub mod exr;

pub use atomic::{refuse_overwriting_inputs, write_all_or_nothing};

use std::io::Cursor;
use std::path::{Path, PathBuf};

use image::{ImageFormat, RgbImage};

use crate::error::{InputError, InputResult};
use crate::film::Image;
use crate::plan::Aov;

/// Output formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// 8-bit sRGB PNG.
    Png,
    /// Linear float32 OpenEXR.
    Exr,
}

impl Format {
    /// The format a path's extension asks for.
    pub fn of(path: &Path) -> InputResult<Format> {
        match crate::scene::extension(path).as_deref() {
            Some("png") => Ok(Format::Png),
            Some("exr") => Ok(Format::Exr),
            _ => Err(InputError::new(path, "unsupported output type (expected .png or .exr)")),
        }
    }

    /// [`Self::of`] an output file that is about to be made, also checking that its folder
    /// exists: asked before any work, so that a long render does not fail at the very end.
    pub fn of_output(path: &Path) -> InputResult<Format> {
        let format = Self::of(path)?;
        let folder = path
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        if !folder.is_dir() {
            return Err(InputError::new(
                path,
                format!("the folder {} does not exist", folder.display()),
            ));
        }
        Ok(format)
    }
}

/// The sRGB transfer function (IEC 61966-2-1) of a linear value in [0, 1].
pub fn srgb_encode(linear: f32) -> f32 {
    if linear <= 0.003_130_8 {
        12.92 * linear
    } else {
        1.055 * linear.powf(1.0 / 2.4) - 0.055
    }
}

/// Linear radiance → 8-bit sRGB: scale by 2^exposure, clamp to [0, 1] (NaN → 0), encode, round.
pub fn to_srgb8(linear: f32, exposure_scale: f32) -> u8 {
    let v = (linear * exposure_scale).clamp(0.0, 1.0);
    let v = if v.is_nan() { 0.0 } else { v };
    (srgb_encode(v) * 255.0).round() as u8
}

/// The 8-bit sRGB bytes of `image` as a PNG of it holds them: three a pixel, after scaling by
/// 2^`exposure` ([`to_srgb8`]).
pub fn srgb8_pixels(image: &Image, exposure: f32) -> Vec<u8> {
    let scale = exposure.exp2();
    image
        .pixels
        .iter()
        .flat_map(|p| p.to_array().map(|c| to_srgb8(c, scale)))
        .collect()
}

/// An 8-bit RGB PNG of `rgb` (three bytes a pixel, rows top to bottom), as every PNG render
/// is written.
pub fn encode_png8(width: u32, height: u32, rgb: Vec<u8>) -> Result<Vec<u8>, String> {
    let img = RgbImage::from_raw(width, height, rgb).ok_or("the pixels do not fill the image")?;
    let mut bytes = Cursor::new(Vec::new());
    img.write_to(&mut bytes, ImageFormat::Png).map_err(|e| e.to_string())?;
    Ok(bytes.into_inner())
}

/// Encodes `image` in `format`.
pub fn encode(image: &Image, format: Format, exposure: f32) -> Result<Vec<u8>, String> {
    match format {
        Format::Png => encode_png8(image.width, image.height, srgb8_pixels(image, exposure)),
        Format::Exr => {
            let full = crate::film::PixelRect::full(image.width, image.height);
            exr::encode_exr(image, full, (image.width, image.height))
        }
    }
}

/// Reads a linear RGB image (EXR, or any format the image crate decodes, taken as is) for
/// comparisons. Alpha is dropped. Errors name the file.
pub fn read_linear(path: &Path) -> InputResult<Image> {
    let bytes = crate::input_files::read(path).map_err(|e| InputError::new(path, e))?;
    // An EXR's header is checked before the image crate decodes (other formats pass: their
    // header is not one).
    exr::check_exr_size(&bytes).map_err(|e| InputError::new(path, e))?;
    exr::check_full_frame(&bytes).map_err(|e| InputError::new(path, e))?;
    let decoded =
        image::load_from_memory(&bytes).map_err(|e| InputError::new(path, format!("not a readable image: {e}")))?;
    let rgb = decoded.into_rgb32f();
    let (width, height) = rgb.dimensions();
    let pixels = rgb.pixels().map(|p| glam::Vec3::from(p.0)).collect();
    Ok(Image { width, height, pixels })
}

/// Where an AOV of a render written to `out` goes: `out` with `.<aov>.exr` instead of its extension.
pub fn aov_path(out: &Path, aov: Aov) -> PathBuf {
    let stem = out
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    out.with_file_name(format!("{stem}.{}.exr", aov.name()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn srgb_encoding_hits_known_values() {
        assert_eq!(to_srgb8(0.0, 1.0), 0);
        assert_eq!(to_srgb8(1.0, 1.0), 255);
        assert_eq!(to_srgb8(0.5, 1.0), 188); // 0.7354 · 255
        assert_eq!(to_srgb8(0.25, 2.0), 188); // one stop of exposure
        assert_eq!(to_srgb8(7.0, 1.0), 255);
        assert_eq!(to_srgb8(-1.0, 1.0), 0);
        assert_eq!(to_srgb8(f32::NAN, 1.0), 0);
    }

    #[test]
    fn exr_round_trips_linear_values_exactly() {
        let mut img = Image::new(3, 2);
        img.pixels[4] = Vec3::new(0.125, 7.5, 1e-6);
        let bytes = encode(&img, Format::Exr, 3.0).unwrap();
        let back = image::load_from_memory(&bytes).unwrap().into_rgb32f();
        assert_eq!(back.dimensions(), (3, 2));
        assert_eq!(back.get_pixel(1, 1).0, [0.125, 7.5, 1e-6]);
    }

    #[test]
    fn aov_files_sit_beside_the_image() {
        assert_eq!(
            aov_path(Path::new("out/dragon.png"), Aov::Depth),
            PathBuf::from("out/dragon.depth.exr")
        );
    }
}
