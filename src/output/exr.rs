//! OpenEXR files: linear float32 RGB, written deterministically, and crops of a frame that know
//! where they belong.
//!
//! Every EXR pointshade writes goes through [`encode_exr`]: ZIP compression in blocks of 16 lines
//! written in increasing order, so the same pixels always give the same bytes (the image crate's
//! writer lets parallel compression decide the block order). A crop is written with the frame as
//! the EXR *display window* and the crop as its *data window* (OpenEXR's own way of saying "this
//! part of that image"); a full frame is the crop that covers it. `merge` reads crops, checks
//! that they tile one frame exactly, and assembles it: because every pixel is a pure function of
//! the scene and its coordinates, the result equals a single-machine render byte for byte.

use std::io::Cursor;
use std::path::Path;

use exr::prelude::*;
use glam::Vec3;

use crate::error::{InputError, InputResult};
use crate::film::{Image, PixelRect, MAX_PIXELS};

/// A crop read back: its pixels, where they go, and the frame's size.
#[derive(Clone, Debug, PartialEq)]
pub struct Crop {
    /// Pixels of the crop (its size).
    pub image: Image,
    /// Where it lies in the frame.
    pub region: PixelRect,
    /// The frame's width and height.
    pub frame: (u32, u32),
}

/// Encodes `image`, the pixels of `region` of a `frame`-sized film (the whole frame, or a crop).
pub fn encode_exr(image: &Image, region: PixelRect, frame: (u32, u32)) -> std::result::Result<Vec<u8>, String> {
    let (w, h) = (region.width() as usize, region.height() as usize);
    let channels = SpecificChannels::rgb(|p: exr::math::Vec2<usize>| {
        let v = image.pixels[p.y() * w + p.x()];
        (v.x, v.y, v.z)
    });
    let attributes = LayerAttributes {
        layer_position: exr::math::Vec2(region.x0 as i32, region.y0 as i32),
        ..Default::default()
    };
    let layer = Layer::new((w, h), attributes, Encoding::SMALL_LOSSLESS, channels);
    let mut exr_image = exr::image::Image::from_layer(layer);
    exr_image.attributes.display_window = IntegerBounds::new((0, 0), (frame.0 as usize, frame.1 as usize));
    let mut bytes = Cursor::new(Vec::new());
    exr_image.write().to_buffered(&mut bytes).map_err(|e| e.to_string())?;
    Ok(bytes.into_inner())
}

/// Checks an OpenEXR file's header before decoding: each layer's data window and the display
/// window must hold at most [`MAX_PIXELS`] pixels (as for PNG inputs). The exr crate allocates the
/// pixels, and `merge` the frame, from these sizes, and a corrupted header asked for 64 GB and
/// aborted the process. An unreadable header (or another format) passes: decoding then reports it.
pub fn check_exr_size(bytes: &[u8]) -> std::result::Result<(), String> {
    let Ok(meta) = exr::meta::MetaData::read_from_buffered(Cursor::new(bytes), false) else {
        return Ok(());
    };
    for header in &meta.headers {
        let display = header.shared_attributes.display_window.size;
        for (what, size) in [("data window", header.layer_size), ("display window", display)] {
            if size.width() as u64 * size.height() as u64 > MAX_PIXELS {
                return Err(format!(
                    "its {what} of {}×{} is too large (at most {MAX_PIXELS} pixels)",
                    size.width(),
                    size.height()
                ));
            }
        }
    }
    Ok(())
}

/// Reads a crop written by [`encode_exr`] (or any RGB(A) EXR: a full frame is a crop of itself).
pub fn read_crop(path: &Path) -> InputResult<Crop> {
    let bytes = std::fs::read(path).map_err(|e| InputError::new(path, format!("cannot read: {e}")))?;
    check_exr_size(&bytes).map_err(|e| InputError::new(path, e))?;
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .rgb_channels(
            |size, _| (size.width(), vec![Vec3::ZERO; size.width() * size.height()]),
            |(w, px): &mut (usize, Vec<Vec3>), p, (r, g, b): (f32, f32, f32)| {
                px[p.y() * *w + p.x()] = Vec3::new(r, g, b)
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_buffered(Cursor::new(bytes))
        .map_err(|e| InputError::new(path, format!("not a readable RGB OpenEXR file: {e}")))?;
    let layer = &image.layer_data;
    let (x0, y0) = (layer.attributes.layer_position.x(), layer.attributes.layer_position.y());
    let display = image.attributes.display_window;
    if display.position.x() != 0 || display.position.y() != 0 || x0 < 0 || y0 < 0 {
        return Err(InputError::new(
            path,
            "its display window does not start at (0, 0) or its data lies outside it",
        ));
    }
    let (width, height) = (layer.size.width() as u32, layer.size.height() as u32);
    let region = PixelRect {
        x0: x0 as u32,
        y0: y0 as u32,
        x1: x0 as u32 + width,
        y1: y0 as u32 + height,
    };
    let frame = (display.size.width() as u32, display.size.height() as u32);
    if region.x1 > frame.0 || region.y1 > frame.1 {
        return Err(InputError::new(path, "its data window lies outside its display window"));
    }
    let pixels = layer.channel_data.pixels.1.clone();
    Ok(Crop {
        image: Image { width, height, pixels },
        region,
        frame,
    })
}

/// Assembles `crops` into their frame: they must share one frame size and cover it exactly once.
/// Errors name the crop at fault.
pub fn merge(crops: &[(std::path::PathBuf, Crop)]) -> InputResult<Image> {
    let (first_path, first) = crops
        .first()
        .ok_or_else(|| InputError::new("merge", "no crops given"))?;
    let (w, h) = first.frame;
    let mut covered = vec![false; w as usize * h as usize];
    let mut frame = Image::new(w, h);
    for (path, crop) in crops {
        if crop.frame != first.frame {
            return Err(InputError::new(
                path,
                format!(
                    "frame {}×{} differs from {}×{} of {}",
                    crop.frame.0,
                    crop.frame.1,
                    w,
                    h,
                    first_path.display()
                ),
            ));
        }
        let r = crop.region;
        for y in r.y0..r.y1 {
            for x in r.x0..r.x1 {
                let at = (y * w + x) as usize;
                if covered[at] {
                    return Err(InputError::new(
                        path,
                        format!("overlaps another crop at pixel ({x}, {y})"),
                    ));
                }
                covered[at] = true;
                frame.pixels[at] = crop.image.pixels[((y - r.y0) * r.width() + (x - r.x0)) as usize];
            }
        }
    }
    if let Some(missing) = covered.iter().position(|c| !c) {
        let (x, y) = (missing as u32 % w, missing as u32 / w);
        return Err(InputError::new(
            first_path,
            format!("the crops leave pixel ({x}, {y}) of the {w}×{h} frame uncovered"),
        ));
    }
    Ok(frame)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crop_round_trips_with_its_position_and_frame() {
        let region = PixelRect {
            x0: 3,
            y0: 2,
            x1: 6,
            y1: 4,
        };
        let image = Image {
            width: 3,
            height: 2,
            pixels: (0..6).map(|i| Vec3::splat(i as f32 * 0.25)).collect(),
        };
        let dir = std::env::temp_dir().join(format!("pointshade-crop-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("c.exr");
        std::fs::write(&path, encode_exr(&image, region, (10, 7)).unwrap()).unwrap();
        let back = read_crop(&path).unwrap();
        assert_eq!(
            back,
            Crop {
                image,
                region,
                frame: (10, 7)
            }
        );
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn same_pixels_give_the_same_bytes() {
        let image = Image {
            width: 300,
            height: 200,
            pixels: (0..60000).map(|i| Vec3::splat((i % 977) as f32)).collect(),
        };
        let full = PixelRect::full(300, 200);
        let a = encode_exr(&image, full, (300, 200)).unwrap();
        assert!((0..5).all(|_| encode_exr(&image, full, (300, 200)).unwrap() == a));
    }

    #[test]
    fn merge_checks_coverage_and_overlap() {
        let crop = |x0, x1| Crop {
            image: Image {
                width: x1 - x0,
                height: 1,
                pixels: vec![Vec3::splat(x0 as f32); (x1 - x0) as usize],
            },
            region: PixelRect { x0, y0: 0, x1, y1: 1 },
            frame: (4, 1),
        };
        let p = |s: &str| std::path::PathBuf::from(s);
        let whole = merge(&[(p("a"), crop(0, 2)), (p("b"), crop(2, 4))]).unwrap();
        assert_eq!(
            whole.pixels,
            vec![Vec3::ZERO, Vec3::ZERO, Vec3::splat(2.0), Vec3::splat(2.0)]
        );
        assert!(merge(&[(p("a"), crop(0, 3)), (p("b"), crop(2, 4))])
            .unwrap_err()
            .to_string()
            .contains("overlaps"));
        assert!(merge(&[(p("a"), crop(0, 2))])
            .unwrap_err()
            .to_string()
            .contains("uncovered"));
    }
}
