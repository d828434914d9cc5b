//! Cut-outs (glTF `alphaMode` MASK) on a file the test writes: a square whose left half is cut
//! out by its base colour texture's alpha, in front of a larger opaque square, under a tilted
//! directional light. Camera rays see the back square through the cut-out half, shadow rays pass
//! through it too, and the opaque half still hides and shadows; packets answer as single rays, and
//! a bake of camera-space normals sees through the cut-out too.

use crate::support;

use glam::{Quat, Vec3};
use serde_json::json;

use pointshade::accel::{Bvh, BvhPreset};
use pointshade::film::{Image, SamplerKind};
use pointshade::normal_map::bake::bake_normals;
use pointshade::plan::RenderPlan;
use pointshade::scene::{self, Scene};
use support::gltf_builder::{write_png, GltfBuilder};
use support::Scratch;

/// A square of half-size `s` in the plane z = `z`, facing +z, uv (0, 0) at its top-left corner.
fn square_mesh(b: &mut GltfBuilder, s: f32, z: f32, material: usize) -> serde_json::Value {
    let positions = [-s, s, z, s, s, z, s, -s, z, -s, -s, z];
    let uvs = [0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0];
    let attributes = json!({
        "POSITION": b.floats("VEC3", &positions),
        "NORMAL": b.floats("VEC3", &[0.0, 0.0, 1.0].repeat(4)),
        "TEXCOORD_0": b.floats("VEC2", &uvs)
    });
    json!({"primitives": [{"attributes": attributes, "indices": b.indices(&[0, 3, 2, 0, 2, 1]), "material": material}]})
}

/// The scene: the front square (x, y ∈ [−1, 1], z = 0) with `alpha_mode`, the back square
/// (half-size 3, z = −1, green), an orthographic camera from +z spanning x ∈ [−2, 2], and a
/// directional light travelling along (0.5, 0, −1): a shadow falls 0.5 to the right of its caster.
fn scene(alpha_mode: &str) -> Scene {
    let dir = Scratch::new(&format!("cutouts-{alpha_mode}"));
    // 2×1 texels: red with alpha 0 on the left, red with alpha 255 on the right.
    write_png(&dir.join("alpha.png"), 2, 1, &[[255, 0, 0, 0], [255, 0, 0, 255]]);
    let mut b = GltfBuilder::default();
    let front = square_mesh(&mut b, 1.0, 0.0, 0);
    let back = square_mesh(&mut b, 3.0, -1.0, 1);
    let matte =
        |base: serde_json::Value| json!({"metallicFactor": 0.0, "roughnessFactor": 1.0, "baseColorFactor": base});
    let mut front_material =
        json!({"pbrMetallicRoughness": matte(json!([1.0, 1.0, 1.0, 1.0])), "alphaMode": alpha_mode});
    front_material["pbrMetallicRoughness"]["baseColorTexture"] = json!({"index": 0});
    let light_rotation = Quat::from_rotation_y(-0.5f32.atan()).to_array();
    let rest = json!({
        "scenes": [{"nodes": [0, 1, 2, 3]}],
        "nodes": [
            {"mesh": 0},
            {"mesh": 1},
            {"camera": 0, "translation": [0.0, 0.0, 5.0]},
            {"rotation": light_rotation, "extensions": {"KHR_lights_punctual": {"light": 0}}}
        ],
        "cameras": [{"type": "orthographic", "orthographic": {"xmag": 2.0, "ymag": 2.0, "znear": 0.0, "zfar": 100.0}}],
        "meshes": [front, back],
        "materials": [front_material, {"pbrMetallicRoughness": matte(json!([0.0, 0.8, 0.0, 1.0]))}],
        "images": [{"uri": "alpha.png"}],
        // Nearest texels, clamped: the cut is exactly at u = 1/2.
        "samplers": [{"magFilter": 9728, "wrapS": 33071, "wrapT": 33071}],
        "textures": [{"source": 0, "sampler": 0}],
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "intensity": 1.0}]}}
    });
    let path = b.write_gltf(&dir, "cutouts", rest);
    let mut scene = scene::load(&path).unwrap();
    scene.film.width = 64;
    scene.film.height = 64;
    scene.film.spp = 1;
    scene.film.sampler = SamplerKind::Grid;
    scene
}

fn render(scene: &Scene) -> Image {
    support::render(scene, &[]).image
}

/// The pixel whose centre looks at x (y = 0): x = −2 + 4·(px + ½)/64.
fn at(img: &Image, x: f32) -> Vec3 {
    let px = ((x + 2.0) / 4.0 * 64.0 - 0.5).round() as u32;
    img.get(px, 32)
}

#[test]
fn camera_and_shadow_rays_pass_through_the_cut_out_half_only() {
    let scene = scene("MASK");
    let plan = RenderPlan::new(&scene, &[]);
    assert!(plan.cutouts, "{}", plan.explain(&scene));
    assert!(plan.explain(&scene).contains("alpha < alphaCutoff: material 0"));
    let img = render(&scene);
    let back_lit = at(&img, -1.5); // the back square beside the front one, unshadowed
    assert!(back_lit.y > 0.05 && back_lit.x < 0.1 * back_lit.y, "{back_lit}");
    // Through the cut-out half: the back square, lit, although the cut half lies between it and
    // the light (its shadow ray crosses z = 0 at x = −0.75).
    assert_eq!(at(&img, -0.25), back_lit, "seen and lit through the cut-out");
    // The opaque half: the front square's red.
    let front = at(&img, 0.5);
    assert!(front.x > 0.05 && front.y < 0.1 * front.x, "{front}");
    // Beside the front square, in the shadow of its opaque half: black (direct light only).
    assert_eq!(at(&img, 1.25), Vec3::ZERO, "shadowed by the opaque half");
    assert_eq!(at(&img, 1.75), back_lit, "beyond the shadow");

    // The same file as OPAQUE: the front square's left half hides the back one.
    let opaque = render(&scene_with_mode("OPAQUE"));
    let hidden = at(&opaque, -0.25);
    assert!(hidden.x > 0.05 && hidden.y < 0.1 * hidden.x, "{hidden}");
}

fn scene_with_mode(mode: &str) -> Scene {
    let scene = scene(mode);
    assert!(!RenderPlan::new(&scene, &[]).cutouts);
    scene
}

#[test]
fn packets_and_single_rays_agree_on_cut_out_hits() {
    let scene = scene("MASK");
    let bvh = Bvh::for_scene(&scene);
    assert!(bvh.has_alpha_mask());
    // 16 rays fanning from one origin (so that they travel as one packet: origins together,
    // direction signs alike) across both halves of the front square.
    let origin = Vec3::new(-3.0, 0.1, 5.0);
    let rays: Vec<(Vec3, Vec3, f32)> = (0..16)
        .map(|k| {
            let target = Vec3::new(-0.95 + 0.125 * k as f32, 0.0, 0.0);
            (origin, (target - origin).normalize(), 100.0)
        })
        .collect();
    let mut hits = vec![None; 16];
    bvh.intersect_packet(&rays, &mut hits);
    let mut cut = 0;
    for (k, (&(o, d, t), packet)) in rays.iter().zip(&hits).enumerate() {
        let single = bvh.intersect(o, d, t);
        assert_eq!(*packet, single, "ray {k}");
        let z = (o + d * single.unwrap().t).z;
        // The left half (x < 0) is cut out: those rays go on to the back square at z = −1.
        let expected = if k < 8 { -1.0 } else { 0.0 };
        assert!((z - expected).abs() < 1e-4, "ray {k} stops at z = {z}");
        cut += usize::from(z < -0.5);
    }
    assert_eq!(cut, 8);
    // 16 shadow segments from one point above the squares down to just short of the back one:
    // blocked only where they cross the front square's opaque half (0 < x < 1 at z = 0).
    let from = Vec3::new(-3.0, 0.1, 3.0);
    let segments: Vec<(Vec3, Vec3, f32)> = (0..16)
        .map(|k| {
            let to = Vec3::new(-0.45 + 0.125 * k as f32, 0.05, -0.999);
            ((from), (to - from).normalize(), (to - from).length())
        })
        .collect();
    let mut occluded = vec![false; 16];
    bvh.any_hit_packet(&segments, &mut occluded);
    let (mut through_cut, mut blocked) = (0, 0);
    for (k, (&(o, d, t), &packet)) in segments.iter().zip(&occluded).enumerate() {
        assert_eq!(packet, bvh.any_hit(o, d, t), "segment {k}");
        let crossing = o + d * (o.z / -d.z);
        assert_eq!(
            packet,
            crossing.x > 0.0 && crossing.x < 1.0,
            "segment {k} crosses z = 0 at {crossing}"
        );
        through_cut += usize::from(crossing.x > -1.0 && crossing.x < 0.0);
        blocked += usize::from(packet);
    }
    assert!(
        through_cut >= 4 && blocked >= 4,
        "{through_cut} through the cut-out, {blocked} blocked"
    );
}

#[test]
fn a_bake_sees_through_cut_outs() {
    // The front square alone: through its cut-out half a camera ray then hits nothing.
    let mut scene = scene("MASK");
    let front: Vec<usize> = (0..scene.mesh.triangle_count())
        .filter(|&t| scene.mesh.material_of_triangle[t] == 0)
        .collect();
    scene.mesh.triangles = front.iter().map(|&t| scene.mesh.triangles[t]).collect();
    scene.mesh.material_of_triangle = vec![0; front.len()];
    let baked = bake_normals(&scene, &Bvh::for_scene(&scene)).unwrap();
    let normal_at = |x: f32| baked.normals[32 * 64 + ((x + 2.0) / 4.0 * 64.0 - 0.5).round() as usize];
    assert_eq!(normal_at(-0.5), None, "the cut-out half");
    assert_eq!(normal_at(0.5), Some(Vec3::Z), "the opaque half, facing the camera");
    assert_eq!(normal_at(1.5), None, "beside the square");
    // Without the mask the whole square is there.
    let opaque = bake_normals(&scene, &Bvh::build(&scene.mesh, BvhPreset::DEFAULT)).unwrap();
    assert_eq!(opaque.hits(), 2 * baked.hits());
}
