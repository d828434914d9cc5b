//! The shadow terminator: a coarse sphere with smooth vertex normals, on a ground plane, under a
//! grazing directional light. From the flat triangles (`shadow_terminator = "flat"`), points
//! whose shading normal faces the light are shadowed by the neighbouring facets in steps; from
//! the smooth surface of the normals (the default) every such point is lit as Lambert's law
//! says, while the shadow the sphere casts on the ground stays where the geometry puts it.

use crate::support::Scratch;

use glam::Vec3;
use pointshade::accel::Bvh;
use pointshade::film::Image;
use pointshade::plan::{Aov, RenderPlan};
use pointshade::render::render;
use pointshade::scene;
use pointshade::scene::procedural::{plane, uv_sphere};

const SIZE: u32 = 160;
/// Every scene's film: SIZE², one sample at each pixel's centre.
fn film() -> String {
    format!("[film]\nwidth = {SIZE}\nheight = {SIZE}\nspp = 1\nsampler = \"grid\"")
}

/// Where the light travels (towards −x, slightly down): a terminator across the sphere's front.
const LIGHT: Vec3 = Vec3::new(-1.0, -0.35, 0.1);
const ALBEDO: f32 = 0.8;
const COS_MIN: f32 = 0.02;
const IRRADIANCE: f32 = 3.0;
/// The sphere's centre; it has radius 1 (vertices on the sphere, the facets inside it).
const CENTRE: Vec3 = Vec3::new(0.0, 1.0, 0.0);
const CAMERA: Vec3 = Vec3::new(1.5, 3.0, 5.0);

/// A folder with the coarse sphere, the ground and (in `scene.toml`) the sphere on the ground
/// under [`LIGHT`] with `shadow_terminator = terminator`.
fn scene_dir(terminator: &str) -> Scratch {
    let dir = Scratch::new(&format!("terminator-{terminator}"));
    dir.write("sphere.obj", &uv_sphere(12, 8).to_obj("coarse sphere", None));
    dir.write("ground.obj", &plane(6.0, 1).to_obj("ground", None));
    let rest = format!(
        "[[light]]\ntype = \"directional\"\ndirection = {light}\nintensity = {IRRADIANCE}\n\
         [render]\nshadow_terminator = \"{terminator}\"\n\
         [[object]]\nmesh = \"sphere.obj\"\nmaterial = \"clay\"\ntransform = {{ translate = {centre} }}\n\
         [[object]]\nmesh = \"ground.obj\"\nmaterial = \"clay\"\n",
        light = toml_vec(LIGHT),
        centre = toml_vec(CENTRE),
    );
    let toml = clay_scene(CAMERA, Vec3::new(-0.8, 0.6, 0.0), 45.0, &rest);
    dir.write("scene.toml", &toml);
    dir
}

/// `v` as a TOML array.
fn toml_vec(v: Vec3) -> String {
    format!("[{}, {}, {}]", v.x, v.y, v.z)
}

/// A scene file: [`film`], a camera at `camera` looking at `look_at` with a vertical `fov`, the
/// two-sided (the default, written out) Lambert material `clay` of albedo [`ALBEDO`], then
/// `rest` (lights, settings and objects).
fn clay_scene(camera: Vec3, look_at: Vec3, fov: f32, rest: &str) -> String {
    format!(
        "{film}\n[camera]\nposition = {camera}\nlook_at = {look_at}\nfov = {fov:?}\n\
         [material.clay]\nmodel = \"lambert\"\nalbedo = [{ALBEDO}, {ALBEDO}, {ALBEDO}]\ntwo_sided = true\n{rest}",
        film = film(),
        camera = toml_vec(camera),
        look_at = toml_vec(look_at),
    )
}

/// The render of `dir`'s scene.toml: radiance, shading normals and positions, and whether the
/// plan smoothed the shadow origins.
fn render_dir(dir: &Scratch) -> (Image, Image, Image, bool) {
    let scene = scene::load(&dir.path("scene.toml")).expect("scene loads");
    let plan = RenderPlan::new(&scene, &[Aov::Normal, Aov::Position]);
    let bvh = Bvh::for_scene(&scene);
    let mut rendered = render(&scene, &plan, Some(&bvh), &|_| {}).unwrap();
    let position = rendered.aovs.pop().unwrap().1;
    let normal = rendered.aovs.pop().unwrap().1;
    (rendered.image, normal, position, plan.smooth_shadow_origins)
}

/// [`render_dir`] of the sphere on the ground with `shadow_terminator = terminator`.
fn render_with(terminator: &str) -> (Image, Image, Image, bool) {
    render_dir(&scene_dir(terminator))
}

/// Lambert under the directional light at cos θ_i.
fn lambert(cos: f32) -> f32 {
    ALBEDO / std::f32::consts::PI * IRRADIANCE * cos
}

/// Counts over the sphere's pixels whose shading normal faces the light by cos θ_i > [`COS_MIN`]:
/// (pixels, those black, those off Lambert's value by more than 1e-3 relative).
fn facing_the_light(image: &Image, normal: &Image, position: &Image) -> (u32, u32, u32) {
    let to_light = -LIGHT.normalize();
    let (mut facing, mut black, mut off) = (0, 0, 0);
    for y in 0..SIZE {
        for x in 0..SIZE {
            let (p, n) = (position.get(x, y), normal.get(x, y));
            let cos = n.dot(to_light);
            // Near the silhouette a facet seen from the front can have shading normals that
            // face away from the viewer: black whatever the shadows (n·ω_o ≤ 0), left out.
            let seen = n.dot((CAMERA - p).normalize()) > 0.05;
            if p.y < 0.01 || !seen || cos <= COS_MIN {
                continue;
            }
            facing += 1;
            let v = image.get(x, y).x;
            black += u32::from(v == 0.0);
            off += u32::from((v - lambert(cos)).abs() > 1e-3 * lambert(cos));
        }
    }
    (facing, black, off)
}

/// Over the pixels `pick` keeps (given position and normal, it returns the normal to shade
/// with), those whose normal faces the point light at `light` by cos θ_i > [`COS_MIN`], and of
/// them those off Lambert's value under that light by more than 1e-3 relative: (facing, wrong).
/// The background (no normal) is left out.
fn lambert_under_point_light(
    image: &Image,
    normal: &Image,
    position: &Image,
    light: Vec3,
    pick: impl Fn(Vec3, Vec3) -> Option<Vec3>,
) -> (u32, u32) {
    let (mut facing, mut wrong) = (0, 0);
    for y in 0..SIZE {
        for x in 0..SIZE {
            let (p, n) = (position.get(x, y), normal.get(x, y));
            let Some(n) = pick(p, n).filter(|&n| n != Vec3::ZERO) else {
                continue;
            };
            let d = light - p;
            let cos = n.dot(d.normalize());
            if cos <= COS_MIN {
                continue;
            }
            facing += 1;
            let e = lambert(cos) / d.length_squared();
            wrong += u32::from((image.get(x, y).x - e).abs() > 1e-3 * e);
        }
    }
    (facing, wrong)
}

#[test]
fn smooth_origins_light_every_point_that_faces_the_light() {
    let (flat, flat_n, flat_p, flat_smoothed) = render_with("flat");
    let (smooth, smooth_n, smooth_p, smoothed) = render_with("smooth");
    assert!(smoothed && !flat_smoothed, "the plan follows shadow_terminator");
    let (facing, flat_black, _) = facing_the_light(&flat, &flat_n, &flat_p);
    let (smooth_facing, black, off) = facing_the_light(&smooth, &smooth_n, &smooth_p);
    // The README quotes these (`cargo test --release --test integration shadow_terminator -- --nocapture`).
    eprintln!("{facing} pixels face the light; black from flat origins {flat_black}, from smooth ones {black}");
    // From the flat facets, the sphere shadows itself in steps along the terminator…
    assert!(facing > 1500, "{facing} pixels face the light");
    assert!(
        flat_black > 50,
        "flat origins: {flat_black} of {facing} facing pixels black"
    );
    // …and from the smooth surface, every point that faces the light gets Lambert's value.
    assert_eq!((black, off), (0, 0), "smooth origins: of {smooth_facing} facing pixels");
}

#[test]
fn smooth_origins_keep_the_shadow_the_sphere_casts() {
    let (image, _, position, _) = render_with("smooth");
    let to_light = -LIGHT.normalize();
    let (mut shadowed, mut lit) = (0, 0);
    for y in 0..SIZE {
        for x in 0..SIZE {
            let p = position.get(x, y);
            if p.y.abs() > 1e-3 || image.get(x, y) == Vec3::ZERO && p == Vec3::ZERO {
                continue; // not the ground (or background)
            }
            // Distance from the sphere's centre to the ray from the ground point to the light.
            let to_centre = CENTRE - p;
            let along = to_centre.dot(to_light);
            let miss = (to_centre - along * to_light).length();
            let v = image.get(x, y).x;
            // The facets lie between radius cos(π/12)·cos(π/16) ≈ 0.947 and 1.
            if along > 0.0 && miss < 0.9 {
                assert_eq!(v, 0.0, "ground at {p} is in the sphere's shadow");
                shadowed += 1;
            } else if along <= 0.0 || miss > 1.05 {
                let e = lambert(to_light.y);
                assert!((v - e).abs() <= 1e-4 * e, "ground at {p}: {v} against {e}");
                lit += 1;
            }
        }
    }
    assert!(shadowed > 500 && lit > 3000, "shadowed {shadowed}, lit {lit}");
}

/// Inside the same sphere (two-sided, scaled ×3), lit by a point light inside it: the inside is
/// concave, seen from behind the normals, and whatever the smoothing does there, every point
/// that faces the light is lit with Lambert's value.
#[test]
fn points_seen_from_inside_a_smooth_mesh_are_lit_as_lambert_says() {
    let dir = scene_dir("inside");
    let light = Vec3::new(0.5, 0.8, 0.6);
    let rest = format!(
        "[[light]]\ntype = \"point\"\nposition = {}\nintensity = {IRRADIANCE}\n\
         [[object]]\nmesh = \"sphere.obj\"\nmaterial = \"clay\"\ntransform = {{ scale = 3.0 }}\n",
        toml_vec(light)
    );
    let toml = clay_scene(Vec3::ZERO, Vec3::new(0.3, -0.2, -1.0), 90.0, &rest);
    std::fs::write(dir.join("scene.toml"), toml).unwrap();
    let (image, normal, position, smoothed) = render_dir(&dir);
    assert!(smoothed);
    // The normal image holds the mesh's normals (outwards); the material turns them to the
    // viewer at the centre.
    let (facing, wrong) = lambert_under_point_light(&image, &normal, &position, light, |p, n| {
        Some(if n.dot(-p) < 0.0 { -n } else { n })
    });
    assert!(facing > 10_000, "{facing} pixels face the light");
    assert_eq!(wrong, 0, "of {facing} pixels facing the light");
}

/// A point light hanging just under a ceiling, closer to it than the sphere's lifts: the
/// shadow rays leave from the lifted origins but must still end at the light. (Kept parallel to
/// the light's direction from the hit, they ended a lift's height above the light, behind the
/// ceiling, and the sphere's top went black.)
#[test]
fn lifted_shadow_rays_end_at_a_light_just_under_a_ceiling() {
    let dir = scene_dir("ceiling");
    let light = Vec3::new(0.3, 2.29, 0.0);
    let camera = Vec3::new(2.6, 2.25, 2.6);
    let rest = format!(
        "[[light]]\ntype = \"point\"\nposition = {}\nintensity = {IRRADIANCE}\n\
         [[object]]\nmesh = \"sphere.obj\"\nmaterial = \"clay\"\ntransform = {{ translate = [0.0, 1.0, 0.0] }}\n\
         [[object]]\nmesh = \"ground.obj\"\nmaterial = \"clay\"\ntransform = {{ translate = [0.0, 2.3, 0.0] }}\n",
        toml_vec(light)
    );
    let toml = clay_scene(camera, Vec3::new(0.0, 1.6, 0.0), 50.0, &rest);
    std::fs::write(dir.join("scene.toml"), toml).unwrap();
    let (image, normal, position, smoothed) = render_dir(&dir);
    assert!(smoothed);
    // The sphere's points seen from the front (the ceiling is at y = 2.3).
    let (facing, wrong) = lambert_under_point_light(&image, &normal, &position, light, |p, n| {
        (p.y < 2.2 && n.dot((camera - p).normalize()) > 0.05).then_some(n)
    });
    assert!(facing > 800, "{facing} pixels face the light");
    assert_eq!(wrong, 0, "of {facing} pixels facing the light");
}
