//! glTF loading and rendering, on small files the tests write themselves: the scene graph
//! (node hierarchies, flat normals, cameras, KHR_lights_punctual spot cones, accessors, GLB, map
//! coordinates) and materials (textures: orientation, sRGB decoding, samplers, transforms,
//! coordinate sets; metal and roughness, emission, sidedness, and what the plan decodes).
//! The glTF pieces both use are here.

mod materials;
mod scene_graph;

use crate::support;

use glam::Quat;
use serde_json::json;

use pointshade::film::{Image, SamplerKind};
use pointshade::scene::Scene;

/// Renders `scene` at `width`×`height` with one grid sample per pixel centre.
fn render_at(mut scene: Scene, width: u32, height: u32) -> Image {
    scene.film.width = width;
    scene.film.height = height;
    scene.film.spp = 1;
    scene.film.sampler = SamplerKind::Grid;
    support::render(&scene, &[]).image
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
