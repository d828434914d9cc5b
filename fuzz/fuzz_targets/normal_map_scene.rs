//! Normal-map scene files: parsed, validated and planned as `pointshade normalmap s.toml` does,
//! with a 3×2 normal image `n.png` beside it, then shaded.
#![no_main]
use libfuzzer_sys::fuzz_target;
use pointshade::normal_map::image::NormalImage;
use pointshade::normal_map::scene_file::NormalMapScene;
use pointshade::normal_map::{image_surface, plan, shade_image};
use std::sync::Once;

static IMAGE: Once = Once::new();

fuzz_target!(|data: &[u8]| {
    IMAGE.call_once(|| {
        pointshade_fuzz::put("n.png", &pointshade_fuzz_png());
    });
    let path = pointshade_fuzz::put("s.toml", data);
    let Ok(scene) = NormalMapScene::load(&path, None) else {
        return;
    };
    let Ok(image) = NormalImage::load(&scene.image) else {
        return;
    };
    if image.width as u64 * image.height as u64 > 4096 {
        return;
    }
    let Ok(surface) = image_surface(&scene, &image) else {
        return;
    };
    let _ = plan::plan(&scene, &image, "fuzz");
    let (shaded, _) = shade_image(&scene, &image, &surface);
    let _ = shaded.first_non_finite(); // overflow is an error the CLI reports, not a finding
});

/// A 3×2 RGBA normal image: up, tilted, and background.
fn pointshade_fuzz_png() -> Vec<u8> {
    let texels: [[u8; 4]; 6] = [
        [128, 128, 255, 255],
        [200, 128, 200, 255],
        [128, 60, 220, 255],
        [0, 0, 0, 0],
        [90, 170, 230, 255],
        [128, 128, 255, 255],
    ];
    let mut bytes = Vec::new();
    let encoder = image::codecs::png::PngEncoder::new(&mut bytes);
    image::ImageEncoder::write_image(encoder, texels.as_flattened(), 3, 2, image::ExtendedColorType::Rgba8)
        .expect("a PNG");
    bytes
}
