//! PNG normal images: decoded as `pointshade normalmap n.png` decodes them, then (when small)
//! shaded with both presets and each model, so every decoding reaches the shader.
#![no_main]
use libfuzzer_sys::fuzz_target;
use pointshade::normal_map::image::NormalImage;
use pointshade::normal_map::scene_file::NormalMapScene;
use pointshade::normal_map::scene_file::Preset;
use pointshade::normal_map::{image_surface, plan, shade_image};
use pointshade::scene::file::ModelName;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let path = Path::new("fuzz.png");
    let Ok(image) = NormalImage::decode(path, data) else {
        return;
    };
    let _ = pointshade::normal_map::likeness::NormalLikeness::of(&image).warning();
    if image.width as u64 * image.height as u64 > 4096 {
        return;
    }
    for preset in [Preset::Tp, Preset::Physical] {
        for model in [ModelName::Lambert, ModelName::BlinnPhong, ModelName::CookTorrance] {
            let scene = NormalMapScene::from_preset(path, preset, model);
            let Ok(surface) = image_surface(&scene, &image) else {
                continue;
            };
            let _ = plan::plan(&scene, &image, "fuzz");
            let (shaded, _) = shade_image(&scene, &image, &surface);
            pointshade_fuzz::assert_finite(&shaded, "normal image");
        }
    }
});
