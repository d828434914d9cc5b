//! The image path (`shade_image_with`, every lane instruction set) gives, pixel for pixel, what
//! the single-pixel functions give, for the tp and physical presets.

use glam::Vec3;
use pointshade::normal_map::pixels::MinMaxScaling;
use pointshade::normal_map::scene_file::{ModelName, NormalMapScene, Preset};
use pointshade::normal_map::shade_min_max_pixel;

use super::shared_normal_map;
use crate::support::Scratch;

/// Shades `image` through `shade_image_with` for every lane instruction set and compares each
/// pixel with one point at a time: `shade_min_max_pixel` for the tp preset (float64, rounded to f32 as
/// the image path stores it), the scalar shader on `ImageSurface::point` for the physical one
/// (one- and two-sided). Equal as numbers; the image check's counts are the image's.
fn assert_image_path_is_the_single_pixel_function(image: &pointshade::normal_map::image::NormalImage) {
    use pointshade::lanes::LaneInstructions;
    use pointshade::normal_map::likeness::NormalLikeness;
    use pointshade::normal_map::{image_surface, shade_image_with, shader, MinMaxPrecision};
    let scaling = MinMaxScaling::of(image).unwrap();
    // Every instruction set this CPU runs (the register lanes' own tests say which are
    // skipped here).
    let all = [
        LaneInstructions::Portable,
        #[cfg(target_arch = "x86_64")]
        LaneInstructions::Avx2,
        #[cfg(target_arch = "x86_64")]
        LaneInstructions::Avx512,
    ];
    let sets: Vec<_> = all.into_iter().filter(|&s| s <= LaneInstructions::detect()).collect();
    for brdf in ModelName::ALL {
        for (preset, two_sided) in [(Preset::Tp, true), (Preset::Physical, false), (Preset::Physical, true)] {
            let mut scene = NormalMapScene::from_preset(&image.source, preset, brdf);
            scene.material.two_sided = two_sided;
            let surface = image_surface(&scene, image).unwrap();
            let one = shader(&scene, preset.convention());
            for &set in &sets {
                let (shaded, stats) = shade_image_with(&scene, image, &surface, set, MinMaxPrecision::Float64);
                // The rows' own counts of the image check are the whole image's.
                assert_eq!(stats.likeness, NormalLikeness::of(image), "{preset:?} {set:?}");
                for row in 0..image.height {
                    for col in 0..image.width {
                        let index = (row * image.width + col) as usize;
                        let (rgb, alpha) = image.pixel(index);
                        let expected = match preset {
                            Preset::Tp => shade_min_max_pixel(&scene, scaling, image.levels(index), row, col).as_vec3(),
                            Preset::Physical => surface
                                .point(col, row, rgb, alpha)
                                .map_or(Vec3::ZERO, |sp| one.shade(&sp, &mut 0)),
                        };
                        assert_eq!(
                            expected,
                            shaded.get(col, row),
                            "{} {brdf:?} {preset:?} two-sided {two_sided} {set:?} ({col}, {row})",
                            image.source.display()
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn single_pixel_function_is_the_image_path() {
    use pointshade::normal_map::image::NormalImage;
    // Synthetic images first (always run): 8- and 16-bit, with background runs, isolated
    // foreground pixels and rows whose foreground count is not a multiple of eight, so every
    // branch of the row code (whole blocks, partial blocks, runs of eight neighbours, padded
    // last groups) is taken.
    let dir = Scratch::new("normalmap-image-path");
    let value = |x: u32, y: u32, c: u32| ((x * 37 + y * 101 + c * 53) ^ (x * y)) % 256;
    // Holes every few pixels left of x = 15, a background run over x ∈ [21, 29) and row 2,
    // runs of eight or more neighbours elsewhere.
    let foreground =
        |x: u32, y: u32| !((x < 15 && (x * 7 + y * 3).is_multiple_of(4)) || y == 2 || (21..29).contains(&x));
    let rgb8 = image::RgbImage::from_fn(43, 9, |x, y| {
        image::Rgb(if foreground(x, y) {
            [0, 1, 2].map(|c| value(x, y, c) as u8)
        } else {
            [4, 2, 0]
        })
    });
    let rgba16 = image::ImageBuffer::<image::Rgba<u16>, _>::from_fn(37, 7, |x, y| {
        image::Rgba(if foreground(x, y) {
            [0, 1, 2, 3].map(|c| (value(x, y, c) * 257 + x) as u16)
        } else {
            [1000, 0, 1028, 65535]
        })
    });
    let (a, b) = (dir.path("rgb8.png"), dir.path("rgba16.png"));
    rgb8.save(&a).unwrap();
    rgba16.save(&b).unwrap();
    for path in [a, b] {
        assert_image_path_is_the_single_pixel_function(&NormalImage::load(&path).unwrap());
    }
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn single_pixel_function_is_the_image_path_on_the_assignments_image() {
    use pointshade::normal_map::image::NormalImage;
    let input = shared_normal_map("nmap2.png");
    assert_image_path_is_the_single_pixel_function(&NormalImage::load(&input).unwrap());
}
