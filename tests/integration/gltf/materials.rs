//! glTF materials: base colour textures (upright, sRGB-decoded, sampled with their wrap
//! mode), KHR_texture_transform, a second coordinate set, metallic-roughness textures, emission
//! and single-sided backs, and textures decoded only for the materials rendered.

use std::path::Path;

use glam::{Quat, Vec3};
use serde_json::json;

use super::{camera_node, matte, ortho, quat, render_at};
use crate::support::gltf_builder::{square, write_png, GltfBuilder};
use crate::support::Scratch;
use pointshade::plan::RenderPlan;
use pointshade::scene;

/// f_r of glTF's BRDF at normal incidence (n = ω_i = ω_o) for a dielectric with roughness 1:
/// (1 − 0.04)·base/π + 0.04·D·V with D = 1/π and V = 1/4.
fn matte_at_normal_incidence(base: f32) -> f32 {
    let pi = std::f32::consts::PI;
    0.96 * base / pi + 0.04 / pi * 0.25
}

/// A square facing +z filling an orthographic view from +z, lit head-on by a directional light
/// of 1 lux, with `material`; `files` are written beside it.
fn lit_square(dir: &Path, name: &str, material: serde_json::Value, extra: serde_json::Value) -> std::path::PathBuf {
    let mut b = GltfBuilder::default();
    let mesh = square(&mut b, true, Some(0));
    let mut rest = json!({
        "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [
            {"mesh": 0},
            camera_node(0, [0.0, 0.0, 5.0], Quat::IDENTITY),
            {"extensions": {"KHR_lights_punctual": {"light": 0}}}
        ],
        "cameras": [ortho(1.0)],
        "meshes": [mesh],
        "materials": [material],
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "intensity": 1.0}]}}
    });
    for (k, v) in extra.as_object().unwrap() {
        rest[k] = v.clone();
    }
    b.write_gltf(dir, name, rest)
}

/// Writes `dir/quads.png`, 2×2: red, green / blue, grey — each channel at sRGB code 188 (linear
/// 0.50289); returns the code.
fn write_quads_png(dir: &Path) -> u8 {
    let code = 188u8;
    write_png(
        &dir.join("quads.png"),
        2,
        2,
        &[
            [code, 0, 0, 255],
            [0, code, 0, 255],
            [0, 0, code, 255],
            [code, code, code, 255],
        ],
    );
    code
}

#[test]
fn base_colour_texture_is_upright_srgb_decoded_and_sampled_with_its_wrap_mode() {
    let dir = Scratch::new("gltf-texture");
    let code = write_quads_png(&dir);
    let material = matte(json!({"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}));
    let extra = json!({
        "images": [{"uri": "quads.png"}],
        "samplers": [{"wrapS": 33071, "wrapT": 33071}],
        "textures": [{"source": 0, "sampler": 0}]
    });
    let path = lit_square(&dir, "textured", material, extra);
    let scene = scene::load(&path).unwrap();
    assert_eq!(scene.textures.len(), 1);
    assert_eq!(
        scene.textures[0].texels[0],
        [code, 0, 0, 255],
        "texel (0, 0) is the PNG's top-left"
    );
    let plan = RenderPlan::new(&scene, &[]);
    assert!(plan.uvs && plan.textures && !plan.normal_textures);
    let explained = plan.explain(&scene);
    assert!(
        explained.contains("base colour: material 0") && explained.contains("1 image(s) decoded"),
        "{explained}"
    );
    let img = render_at(scene, 64, 64);
    let linear = 0.502_886_f32;
    let on = matte_at_normal_incidence(linear);
    let off = matte_at_normal_incidence(0.0);
    // Pixels with u, v < 1/4 (or > 3/4) see one texel only (clamp to edge, bilinear).
    let expect = [
        (4, 4, Vec3::new(on, off, off)),  // top-left: red
        (59, 4, Vec3::new(off, on, off)), // top-right: green
        (4, 59, Vec3::new(off, off, on)), // bottom-left: blue
        (59, 59, Vec3::new(on, on, on)),  // bottom-right: grey
    ];
    for (x, y, e) in expect {
        let v = img.get(x, y);
        assert!((v - e).abs().max_element() < 1e-5, "pixel ({x}, {y}): {v} vs {e}");
    }
}

#[test]
fn texture_transforms_move_the_texels_and_reach_the_normal_texture() {
    let dir = Scratch::new("gltf-texture-transform");
    write_quads_png(&dir);
    let transform = |t: serde_json::Value| json!({"KHR_texture_transform": t});
    let material = matte(json!({
        "pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "extensions": transform(json!({"offset": [0.5, 0.0]}))}},
        "normalTexture": {"index": 0, "extensions": transform(json!({"scale": [2.0, 2.0], "texCoord": 0}))}
    }));
    let extra = |material: serde_json::Value| {
        json!({
            "images": [{"uri": "quads.png"}],
            "samplers": [{"magFilter": 9728}],
            "textures": [{"source": 0, "sampler": 0}],
            "materials": [material],
            "extensionsUsed": ["KHR_lights_punctual", "KHR_texture_transform"]
        })
    };
    let path = lit_square(&dir, "transformed", json!({}), extra(material.clone()));
    let scene = scene::load(&path).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let textures = &scene.materials[0].textures;
    assert_eq!(
        textures.normal.unwrap().texture.transform.map(|t| t.m),
        Some([2.0, 0.0, 0.0, 0.0, 2.0, 0.0]),
        "the normal texture's transform, read from its JSON"
    );
    // Offset u by ½ (repeat): the top-left quarter of the square shows the top-right texel.
    let mut flat = scene.clone();
    flat.materials[0].textures.normal = None;
    let img = render_at(flat, 64, 64);
    let (on, off) = (matte_at_normal_incidence(0.502_886), matte_at_normal_incidence(0.0));
    for (x, y, e) in [(4, 4, Vec3::new(off, on, off)), (59, 4, Vec3::new(on, off, off))] {
        let v = img.get(x, y);
        assert!((v - e).abs().max_element() < 1e-5, "pixel ({x}, {y}): {v} vs {e}");
    }
    // A malformed transform is an error naming the slot.
    let mut bad = material;
    bad["normalTexture"]["extensions"] = transform(json!({"rotation": "quarter"}));
    let path = lit_square(&dir, "bad", json!({}), extra(bad));
    let e = scene::load(&path).unwrap_err().to_string();
    assert!(
        e.contains("KHR_texture_transform of its normal texture: rotation is not a number"),
        "{e}"
    );
}

#[test]
fn second_texture_coordinate_set_selects_the_texels() {
    let dir = Scratch::new("gltf-texcoord1");
    // The base colour texture is read through TEXCOORD_1, which is (0.75, 0.75) everywhere:
    // the bottom-right texel (white) on the whole square; through TEXCOORD_0 it would be mostly
    // black.
    write_png(
        &dir.join("base.png"),
        2,
        2,
        &[[0, 0, 0, 255], [0, 0, 0, 255], [0, 0, 0, 255], [255, 255, 255, 255]],
    );
    let mut b = GltfBuilder::default();
    let mut mesh = square(&mut b, true, Some(0));
    mesh["primitives"][0]["attributes"]["TEXCOORD_1"] = json!(b.floats("VEC2", &[0.75; 8]));
    let rest = json!({
        "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [
            {"mesh": 0},
            camera_node(0, [0.0, 0.0, 5.0], Quat::IDENTITY),
            {"extensions": {"KHR_lights_punctual": {"light": 0}}}
        ],
        "cameras": [ortho(1.0)],
        "meshes": [mesh],
        "materials": [matte(json!({"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": 1}}}))],
        "images": [{"uri": "base.png"}],
        "samplers": [{"wrapS": 33071, "wrapT": 33071}],
        "textures": [{"source": 0, "sampler": 0}],
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "intensity": 1.0}]}}
    });
    let path = b.write_gltf(&dir, "set1", rest);
    let scene = scene::load(&path).unwrap();
    assert!(RenderPlan::new(&scene, &[]).explain(&scene).contains("sets 0 and 1"));
    let img = render_at(scene, 16, 16);
    let white = matte_at_normal_incidence(1.0);
    for (x, y) in [(0, 0), (3, 12), (15, 15)] {
        assert!(
            (img.get(x, y) - Vec3::splat(white)).abs().max_element() < 1e-5,
            "{}",
            img.get(x, y)
        );
    }
}

#[test]
fn metallic_roughness_texture_reads_metalness_from_blue_and_roughness_from_green() {
    let dir = Scratch::new("gltf-metal-rough");
    // Left texel: G = 255, B = 0 → rough dielectric. Right texel: G = 128, B = 255 → metal with
    // roughness 128/255. Factors 1, base colour white.
    write_png(&dir.join("mr.png"), 2, 1, &[[0, 255, 0, 255], [0, 128, 255, 255]]);
    let material = json!({"pbrMetallicRoughness": {"metallicRoughnessTexture": {"index": 0}}});
    let extra = json!({
        "images": [{"uri": "mr.png"}],
        "samplers": [{"wrapS": 33071, "wrapT": 33071}],
        "textures": [{"source": 0, "sampler": 0}]
    });
    let img = render_at(scene::load(&lit_square(&dir, "mr", material, extra)).unwrap(), 16, 16);
    let rough_dielectric = matte_at_normal_incidence(1.0);
    // Metal at normal incidence: F = F0 = base = 1, no diffuse; f = D·V = 1/(π α²) · 1/4.
    let alpha = (128.0f32 / 255.0).powi(2);
    let metal = 1.0 / (std::f32::consts::PI * alpha * alpha) * 0.25;
    let (left, right) = (img.get(1, 8), img.get(14, 8));
    assert!(
        (left - Vec3::splat(rough_dielectric)).abs().max_element() < 1e-5,
        "{left}"
    );
    assert!(
        (right - Vec3::splat(metal)).abs().max_element() < 1e-4 * metal,
        "{right} vs {metal}"
    );
}

#[test]
fn emission_is_added_and_single_sided_backs_stay_dark() {
    let dir = Scratch::new("gltf-emission");
    // The light comes from behind (travels +z): the front receives nothing, so the front shows
    // exactly the emitted radiance.
    let mut b = GltfBuilder::default();
    let mesh = square(&mut b, true, Some(0));
    let make = |b: &GltfBuilder, name: &str, double_sided: bool| {
        let rest = json!({
            "scenes": [{"nodes": [0, 1, 2]}],
            "nodes": [
                {"mesh": 0},
                camera_node(0, [0.0, 0.0, -5.0], Quat::from_rotation_y(std::f32::consts::PI)),
                {"rotation": quat(Quat::from_rotation_y(std::f32::consts::PI)),
                 "extensions": {"KHR_lights_punctual": {"light": 0}}}
            ],
            "cameras": [ortho(1.0)],
            "meshes": [mesh.clone()],
            "materials": [matte(json!({"emissiveFactor": [1.0, 0.5, 0.0], "doubleSided": double_sided}))],
            "extensionsUsed": ["KHR_lights_punctual"],
            "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "intensity": 1.0}]}}
        });
        b.write_gltf(&dir, name, rest)
    };
    // Seen from behind (the camera is at −z): single-sided → nothing at all, not even emission.
    let one = scene::load(&make(&b, "one-sided", false)).unwrap();
    assert!(RenderPlan::new(&one, &[]).emission);
    let img = render_at(one, 8, 8);
    assert_eq!(img.get(4, 4), Vec3::ZERO);
    // Double-sided: the back is lit by the light behind it and glows.
    let two = scene::load(&make(&b, "two-sided", true)).unwrap();
    let img = render_at(two, 8, 8);
    let lit = matte_at_normal_incidence(1.0);
    let e = Vec3::new(1.0, 0.5, 0.0) + Vec3::splat(lit);
    assert!(
        (img.get(4, 4) - e).abs().max_element() < 1e-5,
        "{} vs {e}",
        img.get(4, 4)
    );
    // KHR_materials_emissive_strength scales the factor past 1.
    let mut strong = matte(json!({"emissiveFactor": [1.0, 0.5, 0.0]}));
    strong["extensions"] = json!({"KHR_materials_emissive_strength": {"emissiveStrength": 4.0}});
    let rest = json!({
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, camera_node(0, [0.0, 0.0, 5.0], Quat::IDENTITY)],
        "cameras": [ortho(1.0)],
        "meshes": [mesh],
        "materials": [strong],
        "extensionsUsed": ["KHR_materials_emissive_strength"],
        "extensionsRequired": ["KHR_materials_emissive_strength"]
    });
    let scene = scene::load(&b.write_gltf(&dir, "strong", rest)).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let lights = scene.lights.len();
    let img = render_at(scene, 8, 8);
    // The default lights (the file has none) add reflected light: compare what the emission adds.
    let glow = img.get(4, 4);
    assert!(
        lights > 0 && (glow.x - glow.z - 4.0).abs() < 1e-4 && (glow.y - glow.z - 2.0).abs() < 1e-4,
        "{glow}"
    );
}

#[test]
fn textures_are_decoded_only_for_rendered_materials() {
    let dir = Scratch::new("gltf-unused");
    // The texture file does not exist; the glTF alone cannot load…
    let material = matte(json!({"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}));
    let extra = json!({"images": [{"uri": "absent.png"}], "textures": [{"source": 0}]});
    let path = lit_square(&dir, "absent", material, extra);
    let err = scene::load(&path).unwrap_err().to_string();
    assert!(err.contains("absent.png"), "{err}");
    // …but in a scene file that gives the object its own material, the texture is never read.
    let toml = dir.join("scene.toml");
    std::fs::write(
        &toml,
        "[camera]\nposition = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\nfov = 40.0\n\
         [material.grey]\nalbedo = [0.5, 0.5, 0.5]\n\
         [[object]]\nmesh = \"absent.gltf\"\nmaterial = \"grey\"\n",
    )
    .unwrap();
    let scene = scene::load(&toml).unwrap();
    assert!(scene.textures.is_empty());
    let plan = RenderPlan::new(&scene, &[]);
    assert!(!plan.textures && !plan.uvs);
    assert!(plan.explain(&scene).contains("[skip] material textures"));
    assert!(
        scene
            .notes
            .iter()
            .any(|n| n.contains("1 camera(s) and 1 light(s) are not used")),
        "{:?}",
        scene.notes
    );
}
