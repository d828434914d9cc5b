//! The glTF scene graph: node hierarchies and their transforms (flat normals where a mesh has
//! none, normals under mirroring), cameras framing the square, a spot light's cone, GLB files,
//! non-triangle primitives, sparse accessors, and files in map coordinates.

use std::f32::consts::{FRAC_PI_2, FRAC_PI_4};

use glam::{Quat, Vec3};
use serde_json::json;

use super::{camera_node, matte, ortho, quat, render_at};
use crate::support::gltf_builder::{square, GltfBuilder};
use crate::support::Scratch;
use pointshade::film::Image;
use pointshade::light::{Falloff, LightKind};
use pointshade::scene::{self, LoadOptions};

#[test]
fn node_hierarchy_places_a_known_vertex_and_missing_normals_are_flat() {
    let dir = Scratch::new("gltf-hierarchy");
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
}

#[test]
fn non_uniform_and_mirroring_transforms_keep_normals_right() {
    let dir = Scratch::new("gltf-mirror");
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
    let dir = Scratch::new("gltf-cameras");
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
}

#[test]
fn spot_cone_lights_one_half_of_the_square_and_not_the_other() {
    let dir = Scratch::new("gltf-spot");
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
}

#[test]
fn glb_and_an_embedded_data_uri_load_like_gltf_and_non_triangle_primitives_are_skipped_with_one_warning() {
    let dir = Scratch::new("gltf-glb");
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
    let embedded = dir.join("embedded.gltf");
    let uri = format!("data:application/octet-stream;base64,{}", base64(&b.bin));
    std::fs::write(&embedded, b.document(rest.clone(), Some(&uri)).to_string()).unwrap();
    let gltf = b.write_gltf(&dir, "square", rest);
    let (a, c) = (scene::load(&glb).unwrap(), scene::load(&gltf).unwrap());
    assert_eq!(a.mesh, c.mesh);
    assert_eq!(scene::load(&embedded).unwrap().mesh, c.mesh);
    assert_eq!(a.mesh.triangle_count(), 2);
    assert_eq!(a.warnings.len(), 1, "{:?}", a.warnings);
    assert!(a.warnings[0].contains("1 LINES, 2 POINTS"), "{}", a.warnings[0]);
    // No camera, no light: automatic framing and the default lights; no material: glTF's default.
    assert_eq!(a.lights.len(), 2);
    assert_eq!(a.materials[0].model_name(), "gltf-pbr");
    assert!(!a.materials[0].two_sided);
}

/// `bytes` in padded base64 (RFC 4648), written here independently of the loader's decoder.
fn base64(bytes: &[u8]) -> String {
    const DIGITS: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for group in bytes.chunks(3) {
        let n = group
            .iter()
            .enumerate()
            .fold(0u32, |n, (i, &b)| n | u32::from(b) << (16 - 8 * i));
        for i in 0..4 {
            let digit = DIGITS[(n >> (18 - 6 * i) & 63) as usize] as char;
            out.push(if i <= group.len() { digit } else { '=' });
        }
    }
    out
}

#[test]
fn sparse_accessors_substitute_their_elements() {
    let dir = Scratch::new("gltf-sparse");
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
}

/// A glTF in map coordinates — the offset in a node's translation, a UTM easting and northing
/// whose f32 step is 0.5 m — keeps its geometry, camera and light exact: node transforms are
/// read in f64 from the JSON and the scene is taken relative to the square's centre
/// (`Scene::origin`). As a GLB too (the JSON is then the first chunk).
#[test]
fn a_gltf_in_map_coordinates_keeps_its_precision() {
    let dir = Scratch::new("gltf-map-coordinates");
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
}
