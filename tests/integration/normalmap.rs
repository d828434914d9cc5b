//! The normal-map mode end to end: `pointshade normalmap` (tp and physical presets, scene files),
//! `pointshade bake`, the tp preset's degenerate pixels, and bad input.
//!
//! The tp images are checked against an independent float64 evaluation of the report's formulas
//! written here (it does not call the shader or the BRDF module). Tests that need
//! ../shared/data are ignored without it ("needs ../shared/data").

use crate::support;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use glam::{DVec3, Vec3};
use pointshade::light::{Falloff, Light, LightKind};
use pointshade::normal_map::pixels::{MinMaxScaling, Viewer};
use pointshade::normal_map::scene_file::{ModelName, NormalMapScene, Preset};
use pointshade::normal_map::shade_min_max_pixel;

const BRDFS: [&str; 3] = ["lambert", "blinn-phong", "cook-torrance"];

fn shared_normal_map(name: &str) -> PathBuf {
    support::shared_data("normalmaps").join(name)
}

/// A scratch directory, removed on drop.
struct Dir(PathBuf);

impl Dir {
    fn new(name: &str) -> Self {
        let d = std::env::temp_dir().join(format!("pointshade-nm-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        Dir(d)
    }
    fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }
    fn write(&self, name: &str, text: &str) -> PathBuf {
        let p = self.path(name);
        std::fs::write(&p, text).unwrap();
        p
    }
}

impl Drop for Dir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn pointshade(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pointshade"))
        .args(args)
        .output()
        .unwrap()
}

fn ok(args: &[&str]) -> Output {
    let out = pointshade(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// `pointshade normalmap INPUT --preset PRESET --brdf BRDF -o OUT --quiet EXTRA…`, which must succeed.
fn shade(input: &Path, preset: &str, brdf: &str, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "normalmap",
        s(input),
        "--preset",
        preset,
        "--brdf",
        brdf,
        "-o",
        s(out),
        "--quiet",
    ];
    args.extend_from_slice(extra);
    ok(&args)
}

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
    let dir = Dir::new("tp");
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

/// Shades `image` through `shade_image_with` for every lane instruction set and compares each
/// pixel with one point at a time: `shade_min_max_pixel` for the tp preset (float64, rounded to f32 as
/// the image path stores it), the scalar shader on `ImageSurface::point` for the physical one
/// (one- and two-sided). Equal as numbers.
fn assert_image_path_is_the_single_pixel_function(image: &pointshade::normal_map::image::NormalImage) {
    use pointshade::lanes::LaneInstructions;
    use pointshade::normal_map::{image_surface, shade_image_with, shader, MinMaxPrecision};
    let scaling = MinMaxScaling::of(image).unwrap();
    let mut sets = vec![LaneInstructions::Portable, LaneInstructions::detect()];
    sets.dedup();
    for brdf in ModelName::ALL {
        for (preset, two_sided) in [(Preset::Tp, true), (Preset::Physical, false), (Preset::Physical, true)] {
            let mut scene = NormalMapScene::from_preset(&image.source, preset, brdf);
            scene.material.two_sided = two_sided;
            let surface = image_surface(&scene, image).unwrap();
            let one = shader(&scene, preset.convention());
            for &set in &sets {
                let (shaded, _) = shade_image_with(&scene, image, &surface, set, MinMaxPrecision::Float64);
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
    let dir = Dir::new("image-path");
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
    assert_eq!(ct, lambert, "the specular lobe is 0 where the denominator is 0");
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
    let dir = Dir::new("degenerate");
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

// ---------------------------------------------------------------------------------------------
// The physical preset.

#[test]
fn physical_preset_matches_closed_form_radiance_and_masks_background() {
    use std::f32::consts::PI;
    let dir = Dir::new("physical");
    // 8×4 image: all (128, 128, 255) except an alpha-0 pixel and an RGB-0 pixel.
    let img = image::RgbaImage::from_fn(8, 4, |x, y| match (x, y) {
        (1, 1) => image::Rgba([128, 128, 255, 0]),
        (2, 1) => image::Rgba([0, 0, 0, 255]),
        _ => image::Rgba([128, 128, 255, 255]),
    });
    let input = dir.path("flat.png");
    img.save(&input).unwrap();
    let n = Vec3::new(2.0 * 128.0 / 255.0 - 1.0, 2.0 * 128.0 / 255.0 - 1.0, 1.0).normalize();
    let albedo = Vec3::new(0.4, 0.7, 0.4);
    // A point light 2 units in front of the image plane's origin, inverse-square falloff.
    let scene = dir.write(
        "flat.toml",
        "[normal_map]\nimage = \"flat.png\"\nbrdf = \"lambert\"\n\
         [[light]]\ntype = \"point\"\nposition = [0.0, 0.0, 2.0]\nintensity = 8.0\n",
    );
    let out = dir.path("flat.exr");
    ok(&["normalmap", s(&scene), "-o", s(&out), "--quiet"]);
    let l = image::open(&out).unwrap().into_rgb32f();
    for y in 0..4u32 {
        for x in 0..8u32 {
            let got = Vec3::from(l.get_pixel(x, y).0);
            if (x, y) == (1, 1) || (x, y) == (2, 1) {
                assert_eq!(got, Vec3::ZERO, "background ({x}, {y})");
                continue;
            }
            // README: image height = 2 units, centred, +x right, +y up; pixel centres.
            let p = Vec3::new((x as f32 + 0.5 - 4.0) * 0.5, (2.0 - y as f32 - 0.5) * 0.5, 0.0);
            let to_light = Vec3::new(0.0, 0.0, 2.0) - p;
            let e = 8.0 / to_light.length_squared();
            let expect = albedo / PI * e * n.dot(to_light.normalize()).max(0.0);
            assert!(
                (got - expect).abs().max_element() <= 1e-5 * expect.max_element(),
                "({x}, {y}): {got} vs {expect}"
            );
        }
    }
}

/// The bake → shade round trip: a mesh scene rendered without shadows equals the scene's baked
/// normals shaded with the physical preset, to the 8-bit quantisation of the normals.
#[test]
fn baked_normals_shaded_physically_equal_the_mesh_render() {
    let dir = Dir::new("bake");
    let torus = Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/torus.obj");
    for (model, extra, tolerance) in [
        ("lambert", "", 0.01f32),
        ("cook-torrance", "roughness = 0.4\n", 0.03),
        ("blinn-phong", "shininess = 8.0\nks = 0.3\n", 0.03),
    ] {
        let material = format!("[material.m]\nmodel = \"{model}\"\nalbedo = [0.7, 0.5, 0.3]\n{extra}");
        let light = "[[light]]\ntype = \"directional\"\ndirection = [0.4, -0.5, -0.8]\nintensity = 2.0\n";
        let mesh_scene = dir.write(
            "mesh.toml",
            &format!(
                "[film]\nwidth = 96\nheight = 72\nspp = 1\nsampler = \"grid\"\n\
                 [camera]\ntype = \"orthographic\"\nposition = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\nscale = 1.0\n\
                 [render]\nshadows = false\n{light}{material}\
                 [[object]]\nmesh = \"{}\"\nmaterial = \"m\"\ntransform = {{ rotate = [60.0, 20.0, 0.0] }}\n",
                s(&torus)
            ),
        );
        let render = dir.path("render.exr");
        ok(&["render", s(&mesh_scene), "-o", s(&render), "--quiet"]);
        let baked = dir.path("normals.png");
        ok(&["bake", s(&mesh_scene), "-o", s(&baked), "--quiet"]);
        let nm_scene = dir.write(
            "nm.toml",
            &format!(
                "[normal_map]\nimage = \"normals.png\"\npreset = \"physical\"\nmaterial = \"m\"\n{light}{material}"
            ),
        );
        let shaded = dir.path("shaded.exr");
        ok(&["normalmap", s(&nm_scene), "-o", s(&shaded), "--quiet"]);

        let normals = image::open(&baked).unwrap().into_rgba8();
        let (a, b) = (
            image::open(&render).unwrap().into_rgb32f(),
            image::open(&shaded).unwrap().into_rgb32f(),
        );
        assert_eq!(a.dimensions(), b.dimensions());
        let peak = a.pixels().flat_map(|p| p.0).fold(0.0f32, f32::max);
        let (mut hits, mut worst, mut sum) = (0, 0.0f32, 0.0f32);
        for ((pa, pb), pn) in a.pixels().zip(b.pixels()).zip(normals.pixels()) {
            let d = (Vec3::from(pa.0) - Vec3::from(pb.0)).abs().max_element();
            if pn[3] == 0 {
                assert_eq!(
                    pa.0, [0.0; 3],
                    "{model}: background of the bake is background of the render"
                );
                assert_eq!(pb.0, [0.0; 3]);
                continue;
            }
            hits += 1;
            worst = worst.max(d);
            sum += d;
        }
        assert!(hits > 1000, "{model}: the torus covers the image ({hits} px)");
        assert!(
            worst <= tolerance * peak,
            "{model}: worst difference {worst} > {tolerance} of the peak {peak}"
        );
        assert!(
            sum / (hits as f32) <= 0.2 * tolerance * peak,
            "{model}: mean difference too large"
        );
        eprintln!(
            "{model}: worst {:.2e}, mean {:.2e} of peak {peak}",
            worst / peak,
            sum / hits as f32 / peak
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Scene files, the plan, determinism.

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn scene_file_gives_the_same_image_as_the_command_line() {
    let input = shared_normal_map("nmap2.png");
    let dir = Dir::new("scenefile");
    let scene = dir.write(
        "tp.toml",
        &format!(
            "[normal_map]\nimage = \"{}\"\npreset = \"tp\"\nbrdf = \"cook-torrance\"\n",
            s(&input)
        ),
    );
    let (a, b) = (dir.path("a.png"), dir.path("b.png"));
    ok(&["normalmap", s(&scene), "-o", s(&a), "--quiet"]);
    shade(&input, "tp", "cook-torrance", &b, &[]);
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    // --brdf on the command line replaces the file's brdf.
    let c = dir.path("c.png");
    ok(&["normalmap", s(&scene), "--brdf", "lambert", "-o", s(&c), "--quiet"]);
    assert_ne!(std::fs::read(&a).unwrap(), std::fs::read(&c).unwrap());
}

#[test]
fn plan_shows_no_bvh_and_no_rays() {
    let dir = Dir::new("plan");
    let input = dir.path("n.png");
    image::RgbImage::from_pixel(4, 4, image::Rgb([100, 150, 250]))
        .save(&input)
        .unwrap();
    let out = dir.path("o.png");
    for preset in ["tp", "physical"] {
        let o = ok(&[
            "normalmap",
            s(&input),
            "--preset",
            preset,
            "--brdf",
            "blinn-phong",
            "-o",
            s(&out),
            "--explain",
        ]);
        let text = String::from_utf8_lossy(&o.stdout);
        assert!(text.contains("[skip] bvh + primary rays"), "{text}");
        assert!(text.contains("[skip] shadow rays"), "{text}");
        assert!(text.contains("rays: 0 primary, at most 0 shadow"), "{text}");
        assert!(
            text.contains(if preset == "tp" { "clamped:" } else { "physical:" }),
            "{text}"
        );
        let summary = String::from_utf8_lossy(&o.stderr);
        assert!(summary.contains("16 surface points, 0 rays"), "{summary}");
    }
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn image_does_not_depend_on_the_thread_count() {
    let input = shared_normal_map("normal.png");
    let dir = Dir::new("threads");
    let (a, b) = (dir.path("a.png"), dir.path("b.exr"));
    let (c, d) = (dir.path("c.png"), dir.path("d.exr"));
    for (png, exr, threads) in [(&a, &b, "1"), (&c, &d, "3")] {
        for out in [png, exr] {
            shade(&input, "tp", "cook-torrance", out, &["--threads", threads]);
        }
    }
    assert_eq!(std::fs::read(a).unwrap(), std::fs::read(c).unwrap());
    assert_eq!(std::fs::read(b).unwrap(), std::fs::read(d).unwrap());
}

// ---------------------------------------------------------------------------------------------
// Bad input: one error line, exit code 2, no output file.

fn fails(dir: &Dir, args: &[&str], expect: &[&str]) {
    let out = dir.path("out.png");
    let mut all: Vec<&str> = args.to_vec();
    all.extend(["-o", s(&out)]);
    let r = pointshade(&all);
    let stderr = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(2), "{args:?}: {stderr}");
    let errors: Vec<_> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(errors.len(), 1, "one error line: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    for e in expect {
        assert!(errors[0].contains(e), "'{}' should mention '{e}'", errors[0]);
    }
    assert!(!out.exists(), "no output after an error");
    let leftovers = std::fs::read_dir(&dir.0)
        .unwrap()
        .filter(|e| e.as_ref().unwrap().file_name().to_string_lossy().ends_with(".tmp"))
        .count();
    assert_eq!(leftovers, 0, "no temporary files");
}

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
    let dir = Dir::new("bad");
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
fn bad_options_and_scene_files_are_refused_with_one_line() {
    let dir = Dir::new("badopts");
    let input = dir.path("n.png");
    image::RgbImage::from_pixel(4, 4, image::Rgb([100, 150, 250]))
        .save(&input)
        .unwrap();
    let i = s(&input);
    fails(&dir, &["normalmap", i], &["--brdf", "required"]);
    fails(&dir, &["normalmap", i, "--brdf", "phong"], &["--brdf", "phong"]);
    fails(
        &dir,
        &["normalmap", i, "--brdf", "lambert", "--preset", "exact"],
        &["--preset", "exact"],
    );
    fails(
        &dir,
        &["normalmap", i, "--brdf", "lambert", "--preset", "tp", "--exposure", "1"],
        &["--exposure"],
    );
    fails(
        &dir,
        &["normalmap", i, "--brdf", "lambert", "--exposure", "nan"],
        &["--exposure"],
    );
    let scene = dir.write(
        "s.toml",
        "[normal_map]\nimage = \"n.png\"\nbrdf = \"lambert\"\nwidht = 3\n",
    );
    fails(&dir, &["normalmap", s(&scene)], &["s.toml", "line 4", "widht"]);
    let scene = dir.write("p.toml", "[normal_map]\nimage = \"n.png\"\nbrdf = \"lambert\"\n");
    fails(&dir, &["normalmap", s(&scene), "--preset", "tp"], &["--preset"]);
    let missing = dir.write("m.toml", "[normal_map]\nimage = \"absent.png\"\nbrdf = \"lambert\"\n");
    fails(&dir, &["normalmap", s(&missing)], &["absent.png"]);
    let nan = dir.write(
        "nan.toml",
        "[normal_map]\nimage = \"n.png\"\nbrdf = \"lambert\"\n[[light]]\ntype = \"point\"\nposition = [0.0, nan, 1.0]\n",
    );
    fails(&dir, &["normalmap", s(&nan)], &["nan.toml", "line 4", "position"]);
    // `render` refuses a normal-map scene and says which command shades it.
    fails(
        &dir,
        &["render", s(&scene)],
        &["p.toml", "line 1", "pointshade normalmap"],
    );
    // bake writes PNG only, and needs a mesh scene.
    let r = pointshade(&["bake", s(&scene), "-o", s(&dir.path("n.exr"))]);
    assert_eq!(r.status.code(), Some(2));
    fails(&dir, &["bake", s(&scene)], &["p.toml", "normalmap"]);
}

#[test]
fn sixteen_bit_images_shade_like_their_eight_bit_originals() {
    let dir = Dir::new("sixteen");
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
    let dir = Dir::new("not-normals");
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
    let dir = Dir::new("assignment-normals");
    for name in ["normal.png", "nmap2.png", "nmap3.png"] {
        let o = shade(&shared_normal_map(name), "tp", "lambert", &dir.path("out.png"), &[]);
        assert!(
            !String::from_utf8_lossy(&o.stderr).contains("warning"),
            "{name}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
}
