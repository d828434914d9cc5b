//! End-to-end renders through the whole pipeline (scene file → plan → BVH → surface points →
//! shader → film), with pixel values checked against closed-form radiance.

use crate::support::Scratch;

use std::path::Path;

use glam::Vec3;
use pointshade::accel::Bvh;
use pointshade::film::Image;
use pointshade::plan::RenderPlan;
use pointshade::render::render;
use pointshade::scene;

const SIZE: u32 = 128;

/// A ground quad at y = 0 (±3), an occluder quad at y = 1 over x ∈ [0.4, 0.8], z ∈ [−0.2, 0.2],
/// a point light 2 above the origin, an orthographic camera looking down on x, z ∈ [−1, 1] —
/// everything moved by `offset`.
fn scene_dir(name: &str, offset: f32) -> Scratch {
    let dir = Scratch::new(&format!("e2e-{name}"));
    let quad = |y: f32, x0: f32, x1: f32, z0: f32, z1: f32| {
        format!("v {x0} {y} {z0}\nv {x0} {y} {z1}\nv {x1} {y} {z1}\nv {x1} {y} {z0}\nf 1 2 3\nf 1 3 4\n")
    };
    std::fs::write(dir.join("ground.obj"), quad(0.0, -3.0, 3.0, -3.0, 3.0)).unwrap();
    std::fs::write(dir.join("occluder.obj"), quad(1.0, 0.4, 0.8, -0.2, 0.2)).unwrap();
    let o = offset;
    let toml = format!(
        r#"
[film]
width = {SIZE}
height = {SIZE}
spp = 1
sampler = "grid"
[camera]
type = "orthographic"
position = [{o}, {y}, {o}]
look_at = [{o}, {o}, {o}]
up = [0.0, 0.0, -1.0]
scale = 1.0
[[light]]
type = "point"
position = [{o}, {ly}, {o}]
intensity = 4.0
[material.paint]
albedo = [0.5, 0.25, 1.0]
two_sided = false
[[object]]
mesh = "ground.obj"
material = "paint"
transform = {{ translate = [{o}, {o}, {o}] }}
[[object]]
mesh = "occluder.obj"
material = "paint"
transform = {{ translate = [{o}, {o}, {o}] }}
"#,
        y = o + 5.0,
        ly = o + 2.0,
    );
    std::fs::write(dir.join("scene.toml"), toml).unwrap();
    dir
}

fn render_scene(dir: &Path) -> Image {
    let scene = scene::load(&dir.join("scene.toml")).expect("scene loads");
    let plan = RenderPlan::new(&scene, &[]);
    assert!(plan.shadows && !plan.specular);
    let bvh = Bvh::for_scene(&scene);
    render(&scene, &plan, Some(&bvh), &|_| {}).unwrap().image
}

/// World (x, z) of a pixel centre (camera looks down −Y with up −Z: image right = +X, down = +Z).
fn pixel_xz(i: u32, j: u32) -> (f32, f32) {
    (
        2.0 * (i as f32 + 0.5) / SIZE as f32 - 1.0,
        2.0 * (j as f32 + 0.5) / SIZE as f32 - 1.0,
    )
}

/// Lambert radiance at height y under the light (at height 2 above the origin, I = 4).
fn lambert(x: f32, y: f32, z: f32) -> Vec3 {
    let h = 2.0 - y;
    let d2 = x * x + z * z + h * h;
    let cos = h / d2.sqrt();
    Vec3::new(0.5, 0.25, 1.0) / std::f32::consts::PI * 4.0 / d2 * cos
}

#[test]
fn pixels_match_closed_form_radiance_and_shadows_are_black() {
    let dir = scene_dir("origin", 0.0);
    let img = render_scene(&dir);
    let (mut lit, mut shadowed, mut top) = (0, 0, 0);
    for j in 0..SIZE {
        for i in 0..SIZE {
            let (x, z) = pixel_xz(i, j);
            let v = img.get(i, j);
            let on_occluder = (0.4..0.8).contains(&x) && (-0.2..0.2).contains(&z);
            let in_shadow = (0.8..1.6).contains(&x) && (-0.4..0.4).contains(&z);
            let margin = 0.02; // more than a pixel from any edge
            let near_edge = |a: f32, lo: f32, hi: f32| (a - lo).abs() < margin || (a - hi).abs() < margin;
            if near_edge(x, 0.4, 0.8) || near_edge(z, -0.2, 0.2) || near_edge(x, 0.8, 1.6) || near_edge(z, -0.4, 0.4) {
                continue;
            }
            if on_occluder {
                let e = lambert(x, 1.0, z);
                assert!(
                    (v - e).abs().max_element() <= 1e-4 * e.max_element(),
                    "occluder top at ({x},{z}): {v} vs {e}"
                );
                top += 1;
            } else if in_shadow {
                assert_eq!(v, Vec3::ZERO, "shadowed ground at ({x},{z})");
                shadowed += 1;
            } else {
                let e = lambert(x, 0.0, z);
                assert!(
                    (v - e).abs().max_element() <= 1e-4 * e.max_element(),
                    "ground at ({x},{z}): {v} vs {e}"
                );
                lit += 1;
            }
        }
    }
    assert!(
        lit > 8000 && shadowed > 120 && top > 120,
        "lit {lit}, shadowed {shadowed}, top {top}"
    );
}

#[test]
fn scene_moved_to_1e5_keeps_its_shadows_and_shading() {
    let (a, b) = (scene_dir("near", 0.0), scene_dir("far", 1e5));
    let (near, far) = (render_scene(&a), render_scene(&b));
    let mut within = 0;
    for (p, q) in near.pixels.iter().zip(&far.pixels) {
        let tol = 0.05 * p.max_element().max(1e-3);
        if (*p - *q).abs().max_element() <= tol {
            within += 1;
        }
    }
    let share = within as f64 / near.pixels.len() as f64;
    assert!(share >= 0.99, "only {:.2}% of pixels within 5%", share * 100.0);
    // The middle of the shadow stays black and the occluder's top stays lit (no acne).
    let (si, sj) = ((0.95f32 + 1.0) / 2.0 * SIZE as f32, SIZE as f32 / 2.0);
    assert_eq!(far.get(si as u32, sj as u32), Vec3::ZERO);
    let (ti, tj) = ((0.6f32 + 1.0) / 2.0 * SIZE as f32, SIZE as f32 / 2.0);
    assert!(far.get(ti as u32, tj as u32).min_element() > 0.0);
}

#[test]
fn image_is_identical_for_any_thread_count() {
    let dir = scene_dir("threads", 0.0);
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| render_scene(&dir));
    let three = rayon::ThreadPoolBuilder::new()
        .num_threads(3)
        .build()
        .unwrap()
        .install(|| render_scene(&dir));
    assert_eq!(one, three);
}

/// A render whose stop flag is set ends with `INTERRUPTED`; never set, the same call renders the
/// whole image.
#[test]
fn a_stopped_render_ends_without_an_image() {
    use pointshade::render::{render_scene_until, INTERRUPTED};
    use std::sync::atomic::AtomicBool;
    let mut scene = scene::load(Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/cornell-box.toml"
    )))
    .unwrap();
    (scene.film.width, scene.film.height, scene.film.spp) = (64, 48, 64);
    let plan = RenderPlan::new(&scene, &[]);
    let stopped = render_scene_until(&scene, &plan, &|_| {}, Some(&AtomicBool::new(true)));
    assert_eq!(stopped.err().as_deref(), Some(INTERRUPTED));
    let go_on = AtomicBool::new(false);
    let rendered = render_scene_until(&scene, &plan, &|_| {}, Some(&go_on)).unwrap();
    assert_eq!(rendered.stats.primary_rays, 64 * 48 * 64);
}
