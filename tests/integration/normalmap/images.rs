//! What images `pointshade normalmap` takes: bad images are refused with one line, 16-bit
//! images shade like their 8-bit originals, and an image that is not a normal image shades with
//! a warning while real normal images shade without one.

use std::path::Path;

use super::{fails, ok, s, shade, shared_normal_map};
use crate::support::Scratch;

/// CRC-32 (ISO-HDLC), for hand-made PNG chunks.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= b as u32;
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// A PNG whose header claims `width`×`height` RGB pixels, followed by an empty image stream.
fn png_with_header(width: u32, height: u32) -> Vec<u8> {
    let chunk = |kind: &[u8], data: &[u8]| {
        let mut c = (data.len() as u32).to_be_bytes().to_vec();
        let mut body = kind.to_vec();
        body.extend_from_slice(data);
        c.extend_from_slice(&body);
        c.extend_from_slice(&crc32(&body).to_be_bytes());
        c
    };
    let mut ihdr = width.to_be_bytes().to_vec();
    ihdr.extend_from_slice(&height.to_be_bytes());
    ihdr.extend_from_slice(&[8, 2, 0, 0, 0]);
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    png.extend(chunk(b"IHDR", &ihdr));
    png.extend(chunk(b"IDAT", &[0x78, 0x9c, 0x03, 0x00, 0x00, 0x00, 0x00, 0x01]));
    png.extend(chunk(b"IEND", &[]));
    png
}

#[test]
fn bad_images_are_refused_with_one_line() {
    let dir = Scratch::new("normalmap-bad");
    let tp = ["--preset", "tp", "--brdf", "lambert"];
    let with = |file: &Path, extra: &[&str]| {
        let mut v = vec!["normalmap", s(file)];
        v.extend_from_slice(extra);
        v.into_iter().map(String::from).collect::<Vec<_>>()
    };
    let run = |file: &Path, expect: &[&str]| {
        for preset in ["tp", "physical"] {
            let args = with(file, &["--preset", preset, "--brdf", "lambert"]);
            fails(&dir, &args.iter().map(String::as_str).collect::<Vec<_>>(), expect);
        }
    };
    let text = dir.write("text.png", "this is not an image\n");
    run(&text, &["text.png", "not a PNG"]);
    let jpeg = dir.path("photo.png");
    std::fs::write(&jpeg, b"\xff\xd8\xff\xe0\x00\x10JFIF\x00").unwrap();
    run(&jpeg, &["photo.png", "not a PNG"]);
    let grey = dir.path("grey.png");
    image::GrayImage::from_pixel(8, 8, image::Luma([90]))
        .save(&grey)
        .unwrap();
    run(&grey, &["grey.png", "greyscale"]);
    let grey16 = dir.path("grey16.png");
    image::ImageBuffer::<image::Luma<u16>, _>::from_pixel(8, 8, image::Luma([900]))
        .save(&grey16)
        .unwrap();
    run(&grey16, &["grey16.png", "greyscale"]);
    let empty = dir.path("empty.png");
    std::fs::write(&empty, png_with_header(0, 5)).unwrap();
    run(&empty, &["empty.png"]);
    let huge = dir.path("huge.png");
    std::fs::write(&huge, png_with_header(200_000, 200_000)).unwrap();
    run(&huge, &["huge.png"]);
    let truncated = dir.path("truncated.png");
    std::fs::write(&truncated, &png_with_header(64, 64)[..30]).unwrap();
    run(&truncated, &["truncated.png"]);
    run(&dir.path("missing.png"), &["missing.png", "file not found"]);
    // min = max: the tp scaling would divide by zero (the physical preset shades such an image).
    let flat = dir.path("flat.png");
    image::RgbImage::from_pixel(8, 8, image::Rgb([77, 77, 77]))
        .save(&flat)
        .unwrap();
    let args = with(&flat, &tp);
    fails(
        &dir,
        &args.iter().map(String::as_str).collect::<Vec<_>>(),
        &["flat.png", "divides by zero"],
    );
    let out = dir.path("flat-physical.png");
    shade(&flat, "physical", "lambert", &out, &[]);
}

#[test]
fn sixteen_bit_images_shade_like_their_eight_bit_originals() {
    let dir = Scratch::new("normalmap-sixteen");
    let img8 = image::RgbaImage::from_fn(24, 16, |x, y| {
        image::Rgba([(x * 10) as u8, (y * 15) as u8, 200 + (x % 5) as u8, 255])
    });
    let img16 = image::ImageBuffer::<image::Rgba<u16>, _>::from_fn(24, 16, |x, y| {
        let p = img8.get_pixel(x, y).0;
        image::Rgba(p.map(|v| v as u16 * 257))
    });
    let (p8, p16) = (dir.path("a8.png"), dir.path("a16.png"));
    img8.save(&p8).unwrap();
    img16.save(&p16).unwrap();
    for preset in ["tp", "physical"] {
        let (o8, o16) = (dir.path("o8.exr"), dir.path("o16.exr"));
        shade(&p8, preset, "cook-torrance", &o8, &[]);
        shade(&p16, preset, "cook-torrance", &o16, &[]);
        assert_eq!(
            image::open(&o8).unwrap().into_rgb32f(),
            image::open(&o16).unwrap().into_rgb32f(),
            "{preset}: v/255 and 257v/65535 are the same value"
        );
    }
}

/// A colour photograph given as a normal image still shades (exit 0) under both presets, with a
/// warning that names the share of its pixels that fail; the assignment's own normal images, and
/// a normal image baked from a shipped scene, shade without one.
#[test]
fn an_image_that_is_not_a_normal_image_is_shaded_with_a_warning() {
    let dir = Scratch::new("normalmap-not-normals");
    let photo = dir.path("photo.png");
    image::RgbImage::from_fn(48, 32, |x, y| {
        image::Rgb([150 + (x * 2) as u8, 100 + (y * 3) as u8, 40 + (x ^ y) as u8])
    })
    .save(&photo)
    .unwrap();
    for preset in ["tp", "physical"] {
        let o = shade(&photo, preset, "cook-torrance", &dir.path("out.png"), &[]);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(
            stderr.contains("photo.png: does not look like a normal image")
                && stderr.contains("% face away from the viewer"),
            "{preset}: {stderr}"
        );
    }
    let baked = dir.path("baked.png");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/lambert.toml");
    ok(&[
        "bake",
        s(&scene),
        "-o",
        s(&baked),
        "--width",
        "64",
        "--height",
        "64",
        "--quiet",
    ]);
    let o = shade(&baked, "physical", "lambert", &dir.path("baked-out.png"), &[]);
    assert!(
        !String::from_utf8_lossy(&o.stderr).contains("warning"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn the_assignments_normal_images_shade_without_a_warning() {
    let dir = Scratch::new("normalmap-assignment-normals");
    for name in ["normal.png", "nmap2.png", "nmap3.png"] {
        let o = shade(&shared_normal_map(name), "tp", "lambert", &dir.path("out.png"), &[]);
        assert!(
            !String::from_utf8_lossy(&o.stderr).contains("warning"),
            "{name}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
}
