//! glTF loading and rendering, on small files the tests write themselves: node hierarchies,
//! flat normals, cameras, KHR_lights_punctual spot cones, textures (orientation, sRGB decoding,
//! samplers, coordinate sets), emission, sidedness, and what the plan decodes.

use crate::support;

use std::f32::consts::{FRAC_PI_2, FRAC_PI_4};
use std::path::Path;

use glam::{Quat, Vec3};
use serde_json::json;

use pointshade::accel::Bvh;
use pointshade::film::{Image, SamplerKind};
use pointshade::light::{Falloff, LightKind};
use pointshade::plan::RenderPlan;
use pointshade::render::render;
use pointshade::scene::{self, LoadOptions, Scene};
use support::gltf_builder::{square, temp_dir, write_png, GltfBuilder};

/// Renders `scene` at `size` with one grid sample per pixel centre.
fn render_at(mut scene: Scene, width: u32, height: u32) -> Image {
    scene.film.width = width;
    scene.film.height = height;
    scene.film.spp = 1;
    scene.film.sampler = SamplerKind::Grid;
    let plan = RenderPlan::new(&scene, &[]);
    let bvh = Bvh::for_scene(&scene);
    render(&scene, &plan, Some(&bvh), &|_| {}).unwrap().image
}

fn quat(q: Quat) -> [f32; 4] {
    q.normalize().to_array()
}

/// Node placing a camera at `position` looking down −Z (no rotation) or as `rotation` turns it.
fn camera_node(camera: usize, position: [f32; 3], rotation: Quat) -> serde_json::Value {
    json!({"camera": camera, "translation": position, "rotation": quat(rotation)})
}

const ORTHO_1: &str =
    r#"{"type": "orthographic", "orthographic": {"xmag": 1.0, "ymag": 1.0, "znear": 0.0, "zfar": 100.0}}"#;

fn ortho(mag: f32) -> serde_json::Value {
    let mut c: serde_json::Value = serde_json::from_str(ORTHO_1).unwrap();
    c["orthographic"]["xmag"] = json!(mag);
    c["orthographic"]["ymag"] = json!(mag);
    c
}

/// A dielectric, fully rough, white material (F0 = 0.04).
fn matte(extra: serde_json::Value) -> serde_json::Value {
    let mut m = json!({"pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 1.0}});
    for (k, v) in extra.as_object().unwrap() {
        if k == "pbrMetallicRoughness" {
            for (k2, v2) in v.as_object().unwrap() {
                m["pbrMetallicRoughness"][k2] = v2.clone();
            }
        } else {
            m[k] = v.clone();
        }
    }
    m
}

/// f_r of glTF's BRDF at normal incidence (n = ω_i = ω_o) for a dielectric with roughness 1:
/// (1 − 0.04)·base/π + 0.04·D·V with D = 1/π and V = 1/4.
fn matte_at_normal_incidence(base: f32) -> f32 {
    let pi = std::f32::consts::PI;
    0.96 * base / pi + 0.04 / pi * 0.25
}

#[test]
fn node_hierarchy_places_a_known_vertex_and_missing_normals_are_flat() {
    let dir = temp_dir("hierarchy");
    let mut b = GltfBuilder::default();
    // A "roof": two triangles sharing the edge (0,0,0)–(0,0,1), folded at 90°, no normals.
    let positions = [0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0, -1.0, 0.0, -1.0, -1.0, 0.0];
    let p = b.floats("VEC3", &positions);
    let i = b.indices(&[0, 1, 2, 0, 3, 1]);
    let rest = json!({
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [
            {"translation": [10.0, 0.0, 0.0], "scale": [2.0, 2.0, 2.0], "children": [1]},
            {"rotation": quat(Quat::from_rotation_z(FRAC_PI_2)), "mesh": 0}
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": p}, "indices": i}]}]
    });
    let path = b.write_gltf(&dir, "roof", rest);
    let scene = scene::load(&path).unwrap();
    let mesh = &scene.mesh;
    // Vertex (1, −1, 0): rotated 90° about z → (1, 1, 0), scaled by 2 → (2, 2, 0), moved → (12, 2, 0).
    assert!(
        mesh.positions
            .iter()
            .any(|p| (*p - Vec3::new(12.0, 2.0, 0.0)).length() < 1e-5),
        "{:?}",
        mesh.positions
    );
    // Flat: the shared edge's vertices are duplicated and each triangle's vertices carry its own
    // face normal (a smoothed normal would be the average of the two).
    assert_eq!((mesh.triangle_count(), mesh.positions.len()), (2, 6));
    for t in &mesh.triangles {
        let [a, b2, c] = t.map(|i| mesh.positions[i as usize]);
        let face = (b2 - a).cross(c - a).normalize();
        for &v in t {
            assert!((mesh.normals[v as usize] - face).length() < 1e-6);
        }
    }
    let n0 = mesh.normals[mesh.triangles[0][0] as usize];
    let n1 = mesh.normals[mesh.triangles[1][0] as usize];
    assert!(n0.dot(n1).abs() < 1e-6, "the two faces are perpendicular: {n0} {n1}");
    assert!(
        scene.notes.iter().any(|n| n.contains("flat normals")),
        "{:?}",
        scene.notes
    );
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn non_uniform_and_mirroring_transforms_keep_normals_right() {
    let dir = temp_dir("mirror");
    let mut b = GltfBuilder::default();
    let mesh = square(&mut b, true, None);
    // Square tilted 45° about x, then squashed in y and mirrored in x.
    let rest = json!({
        "scenes": [{"nodes": [0]}],
        "nodes": [
            {"scale": [-1.0, 0.5, 1.0], "children": [1]},
            {"rotation": quat(Quat::from_rotation_x(FRAC_PI_4)), "mesh": 0}
        ],
        "meshes": [mesh]
    });
    let path = b.write_gltf(&dir, "mirror", rest);
    let scene = scene::load(&path).unwrap();
    let m = &scene.mesh;
    for t in &m.triangles {
        let [a, b2, c] = t.map(|i| m.positions[i as usize]);
        let geometric = (b2 - a).cross(c - a).normalize();
        // Inverse transpose: the normal stays perpendicular to the transformed surface…
        let n = m.normals[t[0] as usize];
        assert!((n - geometric).length() < 1e-5, "shading {n} vs geometric {geometric}");
    }
    // …and is (0, sin 45°·2, cos 45°) normalised: squashing y by ½ doubles the normal's y.
    let expected = Vec3::new(0.0, -FRAC_PI_4.sin() * 2.0, FRAC_PI_4.cos()).normalize();
    assert!((m.normals[0] - expected).length() < 1e-5, "{}", m.normals[0]);
    assert!(scene.notes.iter().any(|n| n.contains("no default scene")));
    let _ = std::fs::remove_dir_all(dir);
}

/// Rows and columns of `img` whose centre pixel is not black.
fn lit_span(img: &Image, horizontal: bool) -> (u32, u32) {
    let (n, mid) = if horizontal {
        (img.width, img.height / 2)
    } else {
        (img.height, img.width / 2)
    };
    let lit: Vec<u32> = (0..n)
        .filter(|&k| {
            let p = if horizontal { img.get(k, mid) } else { img.get(mid, k) };
            p.max_element() > 0.0
        })
        .collect();
    (*lit.first().unwrap(), *lit.last().unwrap())
}

#[test]
fn camera_yfov_aspect_ratio_and_orthographic_magnification_frame_the_square() {
    let dir = temp_dir("cameras");
    let mut b = GltfBuilder::default();
    let mesh = square(&mut b, true, Some(0));
    // Camera 0: 2 units in front, yfov 90° → the view is 4 units tall there; the square (2
    // tall) covers the middle half of the rows, and with aspect 2 a quarter of the columns.
    // Camera 1: orthographic, xmag = ymag = 2 → the middle half both ways.
    let rest = json!({
        "scenes": [{"nodes": [0, 1, 2, 3]}],
        "nodes": [
            {"mesh": 0},
            camera_node(0, [0.0, 0.0, 2.0], Quat::IDENTITY),
            camera_node(1, [0.0, 0.0, 2.0], Quat::IDENTITY),
            {"translation": [0.0, 0.0, 5.0], "extensions": {"KHR_lights_punctual": {"light": 0}}}
        ],
        "cameras": [
            {"type": "perspective", "perspective": {"yfov": FRAC_PI_2, "aspectRatio": 2.0, "znear": 0.1}},
            ortho(2.0)
        ],
        "meshes": [mesh],
        "materials": [matte(json!({}))],
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "intensity": 1.0}]}}
    });
    let path = b.write_gltf(&dir, "cameras", rest);
    let perspective = scene::load(&path).unwrap();
    assert_eq!(
        (perspective.film.width, perspective.film.height),
        (960, 480),
        "aspect ratio 2 sets the width"
    );
    let img = render_at(perspective, 320, 160);
    // Rows: the square spans y ∈ [−1, 1] of [−2, 2] → rows 40..119 of 160.
    assert_eq!(lit_span(&img, false), (40, 119));
    // Columns: x ∈ [−1, 1] of [−4, 4] → columns 120..199 of 320.
    assert_eq!(lit_span(&img, true), (120, 199));

    let ortho = scene::load_with(&path, LoadOptions { camera: Some(1) }).unwrap();
    assert_eq!((ortho.film.width, ortho.film.height), (480, 480));
    let img = render_at(ortho, 160, 160);
    assert_eq!(lit_span(&img, false), (40, 119));
    assert_eq!(lit_span(&img, true), (40, 119));
    let err = scene::load_with(&path, LoadOptions { camera: Some(2) }).unwrap_err();
    assert!(err.to_string().contains("0 to 1"), "{err}");
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn spot_cone_lights_one_half_of_the_square_and_not_the_other() {
    let dir = temp_dir("spot");
    let mut b = GltfBuilder::default();
    let mesh = square(&mut b, true, Some(0));
    // The square lies in the ground plane (facing +y); the spot hangs 1 above its centre and
    // points 45° down towards +x with a 45° outer cone: the straight-down direction is exactly
    // on the cone, so ground points with x < 0 are outside it and those with x > 0 (near z = 0)
    // inside. The camera looks straight down, image right = +x.
    let down_right = Vec3::new(1.0, -1.0, 0.0).normalize();
    let rest = json!({
        "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [
            {"mesh": 0, "rotation": quat(Quat::from_rotation_x(-FRAC_PI_2))},
            camera_node(0, [0.0, 5.0, 0.0], Quat::from_rotation_x(-FRAC_PI_2)),
            {"translation": [0.0, 1.0, 0.0], "rotation": quat(Quat::from_rotation_arc(Vec3::NEG_Z, down_right)),
             "extensions": {"KHR_lights_punctual": {"light": 0}}}
        ],
        "cameras": [ortho(1.0)],
        "meshes": [mesh],
        "materials": [matte(json!({}))],
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "spot", "intensity": 2.0, "range": 10.0,
            "spot": {"innerConeAngle": FRAC_PI_4 - 0.01, "outerConeAngle": FRAC_PI_4}}]}}
    });
    let path = b.write_gltf(&dir, "spot", rest);
    let scene = scene::load(&path).unwrap();
    assert_eq!(scene.lights.len(), 1);
    match scene.lights[0].kind {
        LightKind::Spot { direction, .. } => assert!((direction - down_right).length() < 1e-5, "{direction}"),
        other => panic!("{other:?}"),
    }
    assert_eq!(scene.lights[0].falloff, Falloff::InverseSquareWithin { range: 10.0 });
    let img = render_at(scene, 100, 100);
    let world = |k: u32| (k as f32 + 0.5) / 50.0 - 1.0; // pixel centre → x (columns) or z (rows)
    let (mut lit, mut dark) = (0, 0);
    for row in 0..100 {
        for col in 0..100 {
            let (x, z) = (world(col), world(row));
            let v = img.get(col, row);
            if x < -0.02 {
                assert_eq!(v, Vec3::ZERO, "x = {x}, z = {z}: outside the cone");
                dark += 1;
            } else if x > 0.1 && z.abs() < 0.2 {
                assert!(v.min_element() > 0.0, "x = {x}, z = {z}: inside the cone");
                lit += 1;
            }
        }
    }
    assert!(lit > 300 && dark > 4500, "lit {lit}, dark {dark}");
    // Far along z on the right the angle exceeds the cone again (x = 0.11, z = 0.91).
    assert_eq!(img.get(55, 95), Vec3::ZERO);
    let _ = std::fs::remove_dir_all(dir);
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
    let dir = temp_dir("texture");
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
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn texture_transforms_move_the_texels_and_reach_the_normal_texture() {
    let dir = temp_dir("texture-transform");
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
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn second_texture_coordinate_set_selects_the_texels() {
    let dir = temp_dir("texcoord1");
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
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn metallic_roughness_texture_reads_metalness_from_blue_and_roughness_from_green() {
    let dir = temp_dir("metal-rough");
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
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn emission_is_added_and_single_sided_backs_stay_dark() {
    let dir = temp_dir("emission");
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
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn textures_are_decoded_only_for_rendered_materials() {
    let dir = temp_dir("unused");
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
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn glb_renders_like_gltf_and_non_triangle_primitives_are_skipped_with_one_warning() {
    let dir = temp_dir("glb");
    let mut b = GltfBuilder::default();
    let mut mesh = square(&mut b, true, None);
    let points = json!({"attributes": {"POSITION": 0}, "mode": 0});
    let lines = json!({"attributes": {"POSITION": 0}, "mode": 1});
    mesh["primitives"]
        .as_array_mut()
        .unwrap()
        .extend([points.clone(), points, lines]);
    let rest = json!({"scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}], "meshes": [mesh]});
    let glb = dir.join("square.glb");
    std::fs::write(&glb, b.glb(rest.clone())).unwrap();
    let gltf = b.write_gltf(&dir, "square", rest);
    let (a, c) = (scene::load(&glb).unwrap(), scene::load(&gltf).unwrap());
    assert_eq!(a.mesh, c.mesh);
    assert_eq!(a.mesh.triangle_count(), 2);
    assert_eq!(a.warnings.len(), 1, "{:?}", a.warnings);
    assert!(a.warnings[0].contains("1 LINES, 2 POINTS"), "{}", a.warnings[0]);
    // No camera, no light: automatic framing and the default lights; no material: glTF's default.
    assert_eq!(a.lights.len(), 2);
    assert_eq!(a.materials[0].model_name(), "gltf-pbr");
    assert!(!a.materials[0].two_sided);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn sparse_accessors_substitute_their_elements() {
    let dir = temp_dir("sparse");
    let mut b = GltfBuilder::default();
    // Base: four vertices at the origin except vertex 0; sparse values move vertices 1 and 3.
    let base = b.floats("VEC3", &[5.0, 5.0, 5.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0]);
    let index_view = b.view(&[1u32, 3].iter().flat_map(|v| v.to_le_bytes()).collect::<Vec<u8>>());
    let value_view = b.view(
        &[1.0f32, 0.0, 0.0, 2.0, 2.0, 0.0]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect::<Vec<u8>>(),
    );
    b.accessors[base]["sparse"] = json!({
        "count": 2,
        "indices": {"bufferView": index_view, "componentType": 5125},
        "values": {"bufferView": value_view}
    });
    let i = b.indices(&[0, 1, 2, 1, 3, 2]);
    let mesh = json!({"primitives": [{"attributes": {"POSITION": base}, "indices": i}]});
    let path = b.write_gltf(
        &dir,
        "sparse",
        json!({"scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}], "meshes": [mesh]}),
    );
    let scene = scene::load(&path).unwrap();
    let expect = [
        Vec3::new(5.0, 5.0, 5.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(2.0, 2.0, 0.0),
    ];
    // Flat normals unshare the vertices: corner k of triangle t is vertex 3t + k.
    for (corner, &v) in [0usize, 1, 2, 1, 3, 2].iter().enumerate() {
        assert_eq!(scene.mesh.positions[corner], expect[v], "corner {corner}");
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// A glTF in map coordinates — the offset in a node's translation, a UTM easting and northing
/// whose f32 step is 0.5 m — keeps its geometry, camera and light exact: node transforms are
/// read in f64 from the JSON and the scene is taken relative to the square's centre
/// (`Scene::origin`). As a GLB too (the JSON is then the first chunk).
#[test]
fn a_gltf_in_map_coordinates_keeps_its_precision() {
    let dir = temp_dir("map-coordinates");
    let mut b = GltfBuilder::default();
    let mesh = square(&mut b, true, None);
    let (e, n) = (650000.3, 6860000.7);
    let rest = json!({
        "scenes": [{"nodes": [0]}],
        "nodes": [
            {"translation": [e, 0.0, n], "children": [1, 2, 3]},
            {"mesh": 0},
            {"translation": [0.0, 0.0, 4.0], "camera": 0},
            {"translation": [0.25, 0.5, 3.0], "extensions": {"KHR_lights_punctual": {"light": 0}}}
        ],
        "meshes": [mesh],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 1.0, "znear": 0.1}}],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 10.0}]}},
        "extensionsUsed": ["KHR_lights_punctual"]
    });
    let gltf = b.write_gltf(&dir, "far", rest.clone());
    let glb = dir.join("far.glb");
    std::fs::write(&glb, b.glb(rest)).unwrap();
    for path in [gltf, glb] {
        let scene = scene::load(&path).unwrap();
        assert_eq!(scene.origin, glam::DVec3::new(e, 0.0, n), "{path:?}");
        let corners = [
            Vec3::new(-1.0, 1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
        ];
        for c in corners {
            assert!(scene.mesh.positions.contains(&c), "{:?}", scene.mesh.positions);
        }
        assert_eq!(scene.camera.position, Vec3::new(0.0, 0.0, 4.0));
        let LightKind::Point { position } = scene.lights[0].kind else {
            panic!("a point light")
        };
        assert_eq!(position, Vec3::new(0.25, 0.5, 3.0));
    }
    let _ = std::fs::remove_dir_all(dir);
}
