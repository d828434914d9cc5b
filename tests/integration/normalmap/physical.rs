//! The physical preset: closed-form radiance with the background masked, and the bake → shade
//! round trip against a mesh render.

use std::path::Path;

use glam::Vec3;

use super::{ok, s};
use crate::support::Scratch;

#[test]
fn physical_preset_matches_closed_form_radiance_and_masks_background() {
    use std::f32::consts::PI;
    let dir = Scratch::new("normalmap-physical");
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
    let dir = Scratch::new("normalmap-bake");
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
