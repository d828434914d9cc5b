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

/// Where the pixels of an EXR lie: its data window in its display window, read from the header
/// alone (the first layer).
fn placement(header: &exr::meta::header::Header) -> std::result::Result<(PixelRect, (u32, u32)), String> {
    let display = header.shared_attributes.display_window;
    let (x0, y0) = (
        header.own_attributes.layer_position.x(),
        header.own_attributes.layer_position.y(),
    );
    if display.position.x() != 0 || display.position.y() != 0 || x0 < 0 || y0 < 0 {
        return Err("its display window does not start at (0, 0) or its data lies outside it".into());
    }
    let (width, height) = (header.layer_size.width() as u32, header.layer_size.height() as u32);
    let region = PixelRect {
        x0: x0 as u32,
        y0: y0 as u32,
        x1: x0 as u32 + width,
        y1: y0 as u32 + height,
    };
    let frame = (display.size.width() as u32, display.size.height() as u32);
    if region.x1 > frame.0 || region.y1 > frame.1 {
        return Err("its data window lies outside its display window".into());
    }
    Ok((region, frame))
}

/// Refuses an EXR crop where a full frame is expected (`compare`, `validate`): the image crate
/// would pad it to its frame with zeros, and a comparison would count the padding as error or,
/// worse, as agreement. Other formats and unreadable headers pass (decoding reports those).
pub fn check_full_frame(bytes: &[u8]) -> std::result::Result<(), String> {
    let Ok(meta) = exr::meta::MetaData::read_from_buffered(Cursor::new(bytes), false) else {
        return Ok(());
    };
    let Some(header) = meta.headers.first() else {
        return Ok(());
    };
    let (region, frame) = placement(header)?;
    if region != PixelRect::full(frame.0, frame.1) {
        return Err(format!(
            "is a crop (columns {}..{}, rows {}..{} of a {}×{} frame), not a whole image: \
             `pointshade merge` its crops first",
            region.x0, region.x1, region.y0, region.y1, frame.0, frame.1
        ));
    }
    Ok(())
}

/// The header of a crop: where its pixels go and the frame's size, without decoding them.
pub fn read_crop_placement(path: &Path) -> InputResult<(PixelRect, (u32, u32))> {
    crate::input_files::check(path).map_err(|e| InputError::new(path, e))?;
    let meta = exr::meta::MetaData::read_from_file(path, false)
        .map_err(|e| InputError::new(path, format!("not a readable OpenEXR file: {e}")))?;
    let header = meta
        .headers
        .first()
        .ok_or_else(|| InputError::new(path, "an OpenEXR file without a layer"))?;
    let size = header.layer_size;
    if size.width() as u64 * size.height() as u64 > MAX_PIXELS {
        return Err(InputError::new(
            path,
            format!("its data window of {}×{} is too large", size.width(), size.height()),
        ));
    }
    placement(header).map_err(|e| InputError::new(path, e))
}

/// Reads a crop written by [`encode_exr`] (or any RGB(A) EXR: a full frame is a crop of itself).
/// A NaN or infinite pixel is an error naming it: `render` never writes one.
pub fn read_crop(path: &Path) -> InputResult<Crop> {
    let bytes = crate::input_files::read(path).map_err(|e| InputError::new(path, e))?;
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
        .from_buffered(Cursor::new(bytes.as_slice()))
        .map_err(|e| InputError::new(path, format!("not a readable RGB OpenEXR file: {e}")))?;
    let meta = exr::meta::MetaData::read_from_buffered(Cursor::new(bytes.as_slice()), false)
        .map_err(|e| InputError::new(path, format!("not a readable OpenEXR file: {e}")))?;
    let (region, frame) = placement(&meta.headers[0]).map_err(|e| InputError::new(path, e))?;
    let layer = &image.layer_data;
    let (width, height) = (layer.size.width() as u32, layer.size.height() as u32);
    let image = Image {
        width,
        height,
        pixels: layer.channel_data.pixels.1.clone(),
    };
    if let Some((x, y, value)) = image.first_non_finite() {
        return Err(InputError::new(
            path,
            format!(
                "pixel ({}, {}) of the frame is not finite: {value}",
                region.x0 + x,
                region.y0 + y
            ),
        ));
    }
    Ok(Crop { image, region, frame })
}

/// Checks, from their headers alone, that `placements` (path, region, frame) share one frame
/// and cover it exactly once, before any pixel is decoded or the frame allocated. Errors name
/// the crop at fault.
pub fn check_tiling(placements: &[(std::path::PathBuf, PixelRect, (u32, u32))]) -> InputResult<()> {
    let (first_path, _, frame) = placements
        .first()
        .ok_or_else(|| InputError::new("merge", "no crops given"))?;
    let (w, h) = *frame;
    for (i, (path, region, other)) in placements.iter().enumerate() {
        if other != frame {
            return Err(InputError::new(
                path,
                format!(
                    "frame {}×{} differs from {w}×{h} of {}",
                    other.0,
                    other.1,
                    first_path.display()
                ),
            ));
        }
        for (earlier, r) in placements[..i].iter().map(|(p, r, _)| (p, r)) {
            let (x0, y0) = (region.x0.max(r.x0), region.y0.max(r.y0));
            if x0 < region.x1.min(r.x1) && y0 < region.y1.min(r.y1) {
                return Err(InputError::new(
                    path,
                    format!("overlaps {} at pixel ({x0}, {y0})", earlier.display()),
                ));
            }
        }
    }
    // Disjoint rectangles inside the frame cover it exactly when their areas add up to it.
    let covered: u64 = placements
        .iter()
        .map(|(_, r, _)| r.width() as u64 * r.height() as u64)
        .sum();
    if covered != w as u64 * h as u64 {
        let missing = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .find(|&(x, y)| {
                !placements
                    .iter()
                    .any(|(_, r, _)| (r.x0..r.x1).contains(&x) && (r.y0..r.y1).contains(&y))
            })
            .unwrap_or((0, 0));
        return Err(InputError::new(
            first_path,
            format!(
                "the crops leave pixel ({}, {}) of the {w}×{h} frame uncovered",
                missing.0, missing.1
            ),
        ));
    }
    Ok(())
}

/// Assembles `crops` into their frame: they must share one frame size and cover it exactly once
/// ([`check_tiling`]). Errors name the crop at fault.
pub fn merge(crops: &[(std::path::PathBuf, Crop)]) -> InputResult<Image> {
    let placements: Vec<_> = crops.iter().map(|(p, c)| (p.clone(), c.region, c.frame)).collect();
    check_tiling(&placements)?;
    let (w, h) = crops[0].1.frame;
    let mut frame = Image::new(w, h);
    for (_, crop) in crops {
        let r = crop.region;
        for y in r.y0..r.y1 {
            let row = ((y - r.y0) * r.width()) as usize;
            let at = (y * w + r.x0) as usize;
            frame.pixels[at..at + r.width() as usize]
                .copy_from_slice(&crop.image.pixels[row..row + r.width() as usize]);
        }
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
