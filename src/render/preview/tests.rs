//! A preview's renders are the whole renders of the edited scene, byte for byte, and re-shading
//! traces only what an edit changed.

use std::path::Path;

use glam::Vec3;

use super::Preview;
use crate::light::LightKind;
use crate::material::{BrdfModel, CookTorrance};
use crate::plan::{Aov, RenderPlan};
use crate::render::{progress::Silent, render_scene, Rendered};
use crate::scene::{self, Scene};

/// A shipped scene at a small film with several samples per pixel.
fn scene(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(name);
    let mut scene = scene::load(&path).expect("a shipped scene loads");
    scene.film.width = 48;
    scene.film.height = 40;
    scene.film.spp = 4;
    scene
}

const AOVS: [Aov; 2] = [Aov::Normal, Aov::Depth];

/// The image and AOVs as bits.
fn bits(r: &Rendered) -> Vec<Vec<[u32; 3]>> {
    let image = |pixels: &[Vec3]| pixels.iter().map(|p| p.to_array().map(f32::to_bits)).collect();
    std::iter::once(image(&r.image.pixels))
        .chain(r.aovs.iter().map(|(_, a)| image(&a.pixels)))
        .collect()
}

/// `render_scene` of the preview's scene as it is now.
fn whole_render(preview: &Preview) -> Rendered {
    let scene = preview.scene();
    render_scene(scene, &RenderPlan::new(scene, &AOVS), &Silent).expect("renders")
}

/// Every material turned into a rough Cook-Torrance conductor-like lobe, its sides swapped.
fn edited_materials(scene: &Scene) -> Vec<crate::material::Material> {
    let mut materials = scene.materials.clone();
    for (k, m) in materials.iter_mut().enumerate() {
        m.model = BrdfModel::CookTorrance(CookTorrance {
            alpha: 0.05 + 0.1 * k as f32,
            ..CookTorrance::default()
        });
        m.albedo = [0.3, 0.5 + 0.02 * k as f32, 0.7];
        m.two_sided = !m.two_sided;
    }
    materials
}

#[test]
fn material_edits_reshade_the_kept_points_into_the_whole_render_of_the_edited_scene() {
    let mut preview = Preview::new(scene("cornell-box.toml"), &AOVS).unwrap();
    let first = preview.render().unwrap();
    assert_eq!(bits(&first), bits(&whole_render(&preview)));
    assert_eq!(first.stats.primary_rays, 48 * 40 * 4);
    assert!(first.stats.shadow_rays > 0 && first.stats.shadow_rays_reused == 0);

    // A BRDF parameter alone: every shadow ray is asked again and none traced.
    let mut materials = preview.scene().materials.clone();
    materials[0].albedo = [0.9, 0.1, 0.1];
    preview.set_materials(materials).unwrap();
    let second = preview.render().unwrap();
    assert_eq!(bits(&second), bits(&whole_render(&preview)));
    assert_eq!(second.stats.primary_rays, 0, "nothing retraced");
    assert_eq!(second.stats.shadow_rays, 0);
    assert_eq!(second.stats.shadow_rays_reused, first.stats.shadow_rays);

    // New models and sides: points seen from behind now shade, and their rays are traced.
    preview.set_materials(edited_materials(preview.scene())).unwrap();
    let third = preview.render().unwrap();
    assert_eq!(bits(&third), bits(&whole_render(&preview)));
    assert_eq!(third.stats.primary_rays, 0);
    assert!(third.stats.shadow_rays_reused > 0);
}

#[test]
fn light_edits_trace_only_the_rays_that_changed() {
    let mut preview = Preview::new(scene("mixed-lights.toml"), &AOVS).unwrap();
    let first = preview.render().unwrap();
    assert_eq!(bits(&first), bits(&whole_render(&preview)));

    // Colour and intensity: the rays are the same.
    let mut lights = preview.scene().lights.clone();
    for l in &mut lights {
        l.power *= Vec3::new(0.5, 1.0, 2.0);
    }
    preview.set_lights(lights.clone()).unwrap();
    let brighter = preview.render().unwrap();
    assert_eq!(bits(&brighter), bits(&whole_render(&preview)));
    assert_eq!((brighter.stats.primary_rays, brighter.stats.shadow_rays), (0, 0));

    // The point light moves: its rays are traced again, the other two lights' are reused.
    let LightKind::Point { position } = &mut lights[0].kind else {
        panic!("the scene's first light is a point light")
    };
    *position += Vec3::new(0.5, 0.25, 0.0);
    preview.set_lights(lights).unwrap();
    let moved = preview.render().unwrap();
    assert_eq!(bits(&moved), bits(&whole_render(&preview)));
    assert_eq!(moved.stats.primary_rays, 0);
    assert!(moved.stats.shadow_rays > 0 && moved.stats.shadow_rays_reused > 0);
    assert!(moved.stats.shadow_rays < moved.stats.shadow_rays_reused);

    // Again, unchanged: the verdicts kept are the last shading's.
    let again = preview.render().unwrap();
    assert_eq!(bits(&again), bits(&moved));
    assert_eq!(again.stats.shadow_rays, 0);
}

#[test]
fn bad_edits_are_refused_and_change_nothing() {
    let mut preview = Preview::new(scene("cornell-box.toml"), &[]).unwrap();
    let before = preview.render().unwrap();
    let mut materials = preview.scene().materials.clone();
    materials[1].model = BrdfModel::CookTorrance(CookTorrance {
        alpha: f32::NAN,
        ..CookTorrance::default()
    });
    let e = preview.set_materials(materials).unwrap_err();
    assert!(e.contains("roughness must be in [0, 1], got NaN"), "{e}");
    let mut short = preview.scene().materials.clone();
    short.pop();
    let e = preview.set_materials(short).unwrap_err();
    assert!(e.contains("material(s), got"), "{e}");
    let mut lights = preview.scene().lights.clone();
    lights[0].power = Vec3::new(1.0, f32::NAN, 1.0);
    let e = preview.set_lights(lights.clone()).unwrap_err();
    assert!(e.starts_with("light 1: power"), "{e}");
    lights[0].power = Vec3::ONE;
    lights[0].kind = LightKind::Point {
        position: Vec3::splat(1e30),
    };
    assert!(
        preview.set_lights(lights).is_err(),
        "a light beyond the f32 range is refused"
    );
    let after = preview.render().unwrap();
    assert_eq!(bits(&after), bits(&before));
    assert_eq!(after.stats.shadow_rays, 0, "the kept frame survives refused edits");
}

#[test]
fn samplers_whose_samples_follow_the_shading_are_refused() {
    let mut s = scene("cornell-box.toml");
    s.film.sampler = crate::film::sampler::SamplerKind::Adaptive;
    let e = Preview::new(s, &[]).err().expect("refused");
    assert!(e.contains("fixed number of samples per pixel"), "{e}");
}

#[test]
fn a_frame_too_large_to_keep_is_refused_before_anything_is_traced() {
    let mut s = scene("cornell-box.toml");
    (s.film.width, s.film.height, s.film.spp) = (4096, 4096, 4096);
    // 6.9e10 samples of about 100 bytes: far beyond any machine this runs on.
    let e = Preview::new(s, &[]).err().expect("refused");
    assert!(e.contains("keeps up to") && e.contains("GB of surface points"), "{e}");

    let mut s = scene("cornell-box.toml");
    (s.film.width, s.film.height, s.film.spp) = (256, 256, 16);
    let mut preview = Preview::new(s, &[]).unwrap();
    // 10⁶ samples under 20,000 lights: more than a terabyte of verdicts.
    let lights = vec![preview.scene().lights[0]; 20_000];
    let e = preview.set_lights(lights).unwrap_err();
    assert!(e.contains("keeps up to"), "{e}");
    assert_eq!(preview.scene().lights.len(), 1, "nothing changed");
}

#[test]
fn a_new_view_is_traced_with_the_same_tree_and_a_bad_one_refused() {
    let mut preview = Preview::new(scene("mixed-lights.toml"), &AOVS).unwrap();
    preview.render().unwrap();
    let mut camera = preview.scene().camera;
    camera.position += Vec3::new(1.0, -0.5, 0.25);
    preview.set_camera(camera).unwrap();
    let moved = preview.render().unwrap();
    assert_eq!(bits(&moved), bits(&whole_render(&preview)));
    assert_eq!(moved.stats.primary_rays, 48 * 40 * 4, "the new view is traced");
    assert_eq!(moved.stats.shadow_rays_reused, 0);

    let mut bad = camera;
    bad.look_at = bad.position;
    assert!(preview.set_camera(bad).is_err(), "a camera looking at its own position");
    bad.position = Vec3::splat(1e30);
    assert!(preview.set_camera(bad).is_err(), "a camera beyond the f32 range");
    assert_eq!(preview.scene().camera, camera, "nothing changed");
    assert_eq!(preview.render().unwrap().stats.primary_rays, 0);
}

#[test]
fn progressive_passes_are_whole_renders_at_their_sample_counts_and_each_is_reshaded() {
    let mut preview = Preview::new(scene("cornell-box.toml"), &AOVS).unwrap();
    let at = |preview: &Preview, spp: u32| {
        let mut s = preview.scene().clone();
        s.film.spp = spp;
        render_scene(&s, &RenderPlan::new(&s, &AOVS), &Silent).expect("renders")
    };
    let coarse = preview.render_pass(1, None).unwrap();
    assert_eq!(bits(&coarse), bits(&at(&preview, 1)));
    assert_eq!(coarse.stats.primary_rays, 48 * 40);
    let full = preview.render().unwrap();
    assert_eq!(bits(&full), bits(&whole_render(&preview)));
    assert_eq!(
        full.stats.primary_rays,
        48 * 40 * 4,
        "the film's pass traces its own samples"
    );
    assert_eq!(preview.scene().film.spp, 4, "the film is left as it was");

    // A material edit: both passes re-shade their kept points.
    let mut materials = preview.scene().materials.clone();
    materials[0].albedo = [0.2, 0.8, 0.4];
    preview.set_materials(materials).unwrap();
    for spp in [1, 4] {
        let pass = preview.render_pass(spp, None).unwrap();
        assert_eq!(bits(&pass), bits(&at(&preview, spp)), "{spp} spp");
        assert_eq!((pass.stats.primary_rays, pass.stats.shadow_rays), (0, 0), "{spp} spp");
    }

    let e = preview.render_pass(16, None).err().expect("refused");
    assert!(e.contains("at most the film's 4 samples per pixel"), "{e}");
    let e = preview.render_pass(0, None).err().expect("refused");
    assert!(e.contains("spp"), "{e}");
}
