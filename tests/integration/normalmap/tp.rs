//! The tp preset: its images against an independent float64 evaluation of the report's formulas
//! (tp-assignment.md) written here, and its degenerate pixels (background, zero normals, zero
//! denominators, light or viewer on the point) through the public single-pixel function.

use std::path::Path;

use glam::{DVec3, Vec3};
use pointshade::light::{Falloff, Light, LightKind};
use pointshade::normal_map::pixels::{MinMaxScaling, Viewer};
use pointshade::normal_map::scene_file::{ModelName, NormalMapScene, Preset};
use pointshade::normal_map::shade_min_max_pixel;

use super::{shade, shared_normal_map, BRDFS};
use crate::support::Scratch;

// ---------------------------------------------------------------------------------------------
// The independent float64 evaluation of the report's formulas (tp-assignment.md).

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn unit(a: [f64; 3]) -> [f64; 3] {
    let l = dot(a, a).sqrt();
    [a[0] / l, a[1] / l, a[2] / l]
}
fn clamp01(v: f64) -> f64 {
    v.clamp(0.0, 1.0)
}

/// The report's L_o at pixel (row, col) with normal `n` (already min-max scaled), in f64, written
/// as a numpy implementation writes it: directions divided by their length, dot products summed
/// x, y, z. Where n·ω_i or n·ω_o is 0 in exact arithmetic the Cook-Torrance guard is
/// discontinuous (at 0 f_s = 0, just above it G/(4 n·ω_i n·ω_o) → 1/(4 (…)k)), so the side the
/// rounding lands on decides the pixel: the tp preset must land where float64 numpy does.
fn report_radiance(brdf: &str, n: [f64; 3], row: f64, col: f64) -> [f64; 3] {
    use std::f64::consts::PI;
    let (light, li, camera) = ([0.0, 1.0, 1.0], 0.5 * 1.0, [1.0, 300.0, 1.0]);
    let albedo = [0.4, 0.7, 0.4];
    let x = [row, col, 0.0];
    let wi = unit(sub(x, light)); // from the light towards the point, as the report writes it
    let wo = unit(sub(camera, x));
    let n_wi = clamp01(dot(n, wi));
    let mut f = albedo.map(|a| 1.0 * a / PI);
    match brdf {
        "lambert" => {}
        "blinn-phong" => {
            let wh = unit([wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]]);
            let fs = 1.0 * clamp01(dot(n, wh)).powf(1.0);
            f = f.map(|v| v + fs);
        }
        "cook-torrance" => {
            let wh = unit([wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]]);
            let (n_wh, n_wo, wi_wh) = (clamp01(dot(n, wh)), clamp01(dot(n, wo)), clamp01(dot(wi, wh)));
            let alpha: f64 = 0.7;
            let a2 = alpha * alpha;
            let d = a2 / (PI * (1.0 + (a2 - 1.0) * n_wh * n_wh).powi(2));
            let k = alpha * (2.0 / PI).sqrt();
            let g = n_wi / (n_wi * (1.0 - k) + k) * (n_wo / (n_wo * (1.0 - k) + k));
            let mut denominator = 4.0 * n_wi * n_wo;
            if denominator == 0.0 {
                denominator = 1.0;
            }
            let f0 = [0.98, 0.82, 0.76]; // metallic: F0 is the specular colour
            for c in 0..3 {
                let fresnel = f0[c] + (1.0 - f0[c]) * (1.0 - wi_wh.max(0.0)).powi(5);
                f[c] += d * fresnel * g / denominator;
            }
        }
        _ => unreachable!(),
    }
    f.map(|v| li * v * n_wi)
}

/// The report's 8-bit image of an RGB(A) PNG: global min-max of the RGB values used as the
/// normal (background max ≤ 4 → n = 0), positions (row, col, 0), global min-max of L_o, ×255,
/// truncated. Also returns how many foreground pixels sit on the Cook-Torrance knife edge:
/// |n·ω_o| or |n·ω_i| below 1e-15, 0 in exact arithmetic as far as float64 shows.
fn report_image(input: &Path, brdf: &str) -> (u32, u32, Vec<u8>, usize) {
    let rgb = image::open(input).unwrap().into_rgb8();
    let (w, h) = rgb.dimensions();
    let values = rgb.as_raw();
    let (lo, hi) = (
        *values.iter().min().unwrap() as f64,
        *values.iter().max().unwrap() as f64,
    );
    let mut lo_out = f64::INFINITY;
    let mut hi_out = f64::NEG_INFINITY;
    let mut radiance = Vec::with_capacity(values.len());
    let mut knife_edges = 0;
    for (i, p) in rgb.pixels().enumerate() {
        let background = p.0.iter().all(|&v| v <= 4);
        let n = if background {
            [0.0; 3]
        } else {
            p.0.map(|v| (v as f64 - lo) / (hi - lo))
        };
        let (row, col) = ((i as u32 / w) as f64, (i as u32 % w) as f64);
        let on_edge = |to: [f64; 3]| dot(n, unit(to)).abs() < 1e-15;
        if !background
            && (on_edge(sub([1.0, 300.0, 1.0], [row, col, 0.0])) || on_edge(sub([row, col, 0.0], [0.0, 1.0, 1.0])))
        {
            knife_edges += 1;
        }
        let l = report_radiance(brdf, n, row, col);
        for v in l {
            assert!(v.is_finite());
            lo_out = lo_out.min(v);
            hi_out = hi_out.max(v);
            radiance.push(v);
        }
    }
    let level = |v: f64| ((v - lo_out) / (hi_out - lo_out) * 255.0).clamp(0.0, 255.0) as u8;
    (w, h, radiance.into_iter().map(level).collect(), knife_edges)
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn tp_images_match_an_independent_float64_evaluation_to_one_level() {
    let dir = Scratch::new("normalmap-tp");
    for name in ["normal.png", "nmap2.png", "nmap3.png"] {
        let input = shared_normal_map(name);
        for brdf in BRDFS {
            let out = dir.path(&format!("{name}-{brdf}.png"));
            shade(&input, "tp", brdf, &out, &[]);
            let ours = image::open(&out).unwrap();
            assert_eq!(
                ours.color(),
                image::ColorType::Rgb8,
                "the report's output is an RGB PNG"
            );
            let ours = ours.into_rgb8();
            let (w, h, reference, knife_edges) = report_image(&input, brdf);
            assert_eq!(ours.dimensions(), (w, h));
            let mut off_by_one = 0usize;
            let mut distinct = std::collections::BTreeSet::new();
            // Every value, no exception: within one level (the output's min-max normalisation
            // runs on the f32 image, which can move a value across a level boundary).
            for (k, (&a, &r)) in ours.as_raw().iter().zip(&reference).enumerate() {
                assert!(
                    (a as i32 - r as i32).abs() <= 1,
                    "{name} {brdf}: pixel ({}, {}) channel {}: pointshade {a}, reference {r}",
                    k / 3 % w as usize,
                    k / 3 / w as usize,
                    k % 3,
                );
                off_by_one += (a != r) as usize;
                distinct.insert(a);
            }
            // The comparison is not vacuous: the images use the whole range.
            assert!(
                distinct.contains(&255) && distinct.len() > 100,
                "{name} {brdf}: {} levels",
                distinct.len()
            );
            eprintln!(
                "{name} {brdf}: {off_by_one} of {} values differ from the f64 reference by one level; \
                 {knife_edges} pixels on the knife edge (|n·ω| < 1e-15)",
                reference.len()
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Degenerate tp pixels, through the public single-pixel function (the very code of the image path).

fn tp_scene(brdf: ModelName) -> NormalMapScene {
    NormalMapScene::from_preset(Path::new("unused.png"), Preset::Tp, brdf)
}

fn all_finite(v: DVec3) -> bool {
    v.is_finite() && v.min_element() >= 0.0
}

#[test]
fn tp_background_and_zero_normals_shade_to_zero() {
    let full = MinMaxScaling::new(0.0, 1.0).unwrap();
    let from_tenth = MinMaxScaling::new(0.1, 0.9).unwrap();
    for brdf in ModelName::ALL {
        let scene = tp_scene(brdf);
        // Background: max(rgb) ≤ 4/255 → n = 0, no surface point.
        assert_eq!(
            shade_min_max_pixel(&scene, full, [4.0 / 255.0, 0.0, 1.0 / 255.0], 100, 200),
            DVec3::ZERO
        );
        // A pixel at the image's minimum is not background but scales to n = 0: every dot
        // product is 0, the Cook-Torrance denominator is guarded, L_o = 0.
        assert_eq!(
            shade_min_max_pixel(&scene, from_tenth, [0.1; 3], 100, 200),
            DVec3::ZERO,
            "{brdf:?}"
        );
        // A lit pixel is not 0 (the test above is not vacuous).
        assert!(shade_min_max_pixel(&scene, full, [0.9, 0.6, 0.4], 100, 200).max_element() > 0.0);
    }
}

#[test]
fn tp_zero_cook_torrance_denominator_leaves_the_diffuse_part() {
    use std::f64::consts::PI;
    let full = MinMaxScaling::new(0.0, 1.0).unwrap();
    // n = (1, 0, 0) at (row 100, col 50): n·ω_i = 100/‖(100, 49, −1)‖ > 0, but ω_o points to the
    // camera [1, 300, 1] with a negative first component, so n·ω_o is clamped to 0 and
    // 4(n·ω_i)(n·ω_o) = 0.
    let ct = shade_min_max_pixel(&tp_scene(ModelName::CookTorrance), full, [1.0, 0.0, 0.0], 100, 50);
    let lambert = shade_min_max_pixel(&tp_scene(ModelName::Lambert), full, [1.0, 0.0, 0.0], 100, 50);
    assert!(all_finite(ct));
    // Lambert forms ω_i by a reciprocal, Cook-Torrance by quotients (`UnitForm`): the diffuse
    // parts agree to a few ulps; a specular lobe would add far more.
    let ulps = (ct - lambert).abs().max_element() / (f64::EPSILON * lambert.max_element());
    assert!(
        ulps <= 4.0,
        "the specular lobe is 0 where the denominator is 0: {ct} vs {lambert}"
    );
    let cos = 100.0 / (100.0f64 * 100.0 + 49.0 * 49.0 + 1.0).sqrt();
    for (c, albedo) in [0.4, 0.7, 0.4].into_iter().enumerate() {
        let expect = 0.5 * albedo / PI * cos;
        assert!((ct[c] - expect).abs() < 1e-6 * expect, "{c}: {} vs {expect}", ct[c]);
    }
    // n·ω_i = 0 as well (n = (0, 0, 1): ω_i has z = −1/‖·‖ < 0): L_o = 0.
    let dark = shade_min_max_pixel(&tp_scene(ModelName::CookTorrance), full, [0.0, 0.0, 1.0], 100, 50);
    assert_eq!(dark, DVec3::ZERO);
}

#[test]
fn tp_light_and_viewer_on_one_ray_leave_the_diffuse_part() {
    let full = MinMaxScaling::new(0.0, 1.0).unwrap();
    let on_the_light = |brdf| {
        let mut scene = tp_scene(brdf);
        // The viewer at the light: ω_o = (x_s − x)/‖·‖ = −ω_i, ω_i + ω_o = 0, no half vector.
        scene.viewer = Viewer::Position(Vec3::new(0.0, 1.0, 1.0));
        shade_min_max_pixel(&scene, full, [0.8, 0.7, 0.1], 40, 30)
    };
    let lambert = on_the_light(ModelName::Lambert);
    assert!(lambert.min_element() > 0.0);
    for brdf in [ModelName::BlinnPhong, ModelName::CookTorrance] {
        let v = on_the_light(brdf);
        assert!(all_finite(v), "{brdf:?}: {v}");
        assert_eq!(v, lambert, "{brdf:?}: documented value is the diffuse part alone");
    }
}

#[test]
fn tp_light_or_viewer_at_the_point_stay_finite() {
    let full = MinMaxScaling::new(0.0, 1.0).unwrap();
    for brdf in ModelName::ALL {
        let mut scene = tp_scene(brdf);
        scene.lights = vec![Light {
            kind: LightKind::Point {
                position: Vec3::new(5.0, 7.0, 0.0),
            },
            power: Vec3::splat(0.5),
            falloff: Falloff::None,
        }];
        // The light at the point: no direction, documented to add nothing.
        assert_eq!(shade_min_max_pixel(&scene, full, [0.5, 0.6, 0.7], 5, 7), DVec3::ZERO);
        // The viewer at the point: ω_o = 0, n·ω_o = 0; finite.
        let mut scene = tp_scene(brdf);
        scene.viewer = Viewer::Position(Vec3::new(5.0, 7.0, 0.0));
        assert!(all_finite(shade_min_max_pixel(&scene, full, [0.5, 0.6, 0.7], 5, 7)));
    }
}

#[test]
fn tp_degenerate_pixels_in_an_image_never_produce_nan() {
    // Background, n = 0 at the minimum, normals along each axis, on a grid that includes the
    // light's row/column: the EXR (raw L_o) has no NaN and background pixels are exactly 0.
    let dir = Scratch::new("normalmap-degenerate");
    let img = image::RgbImage::from_fn(16, 16, |x, y| {
        image::Rgb(match (x + y * 16) % 6 {
            0 => [0, 0, 0],
            1 => [3, 4, 2],
            2 => [10, 10, 10], // dim grey: a short normal, not background
            3 => [255, 10, 10],
            4 => [10, 255, 10],
            _ => [10, 10, 255],
        })
    });
    let input = dir.path("degenerate.png");
    img.save(&input).unwrap();
    for brdf in BRDFS {
        let out = dir.path(&format!("{brdf}.exr"));
        shade(&input, "tp", brdf, &out, &[]);
        let l = image::open(&out).unwrap().into_rgb32f();
        for (i, p) in l.pixels().enumerate() {
            assert!(
                p.0.iter().all(|v| v.is_finite() && *v >= 0.0),
                "{brdf} pixel {i}: {:?}",
                p.0
            );
            if i % 6 < 2 {
                assert_eq!(p.0, [0.0; 3], "{brdf}: background pixel {i}");
            }
        }
    }
}
