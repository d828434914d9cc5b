//! The Khronos glTF sample assets of ../shared/data/gltf: every one renders, and the properties
//! checked by eye are asserted (cameras, lights, textures used, normal-map orientation, the
//! metal/roughness grid). Without ../shared/data these tests are ignored ("needs ../shared/data").

use crate::support;

use std::path::{Path, PathBuf};

use glam::Vec3;
use pointshade::light::{Falloff, LightKind};
use pointshade::material::BrdfModel;
use pointshade::plan::RenderPlan;
use pointshade::scene::{self, LoadOptions};

fn gltf_dir() -> PathBuf {
    support::shared_data("gltf")
}

/// Every asset, as CI renders them.
const ASSETS: [&str; 11] = [
    "Box/glTF-Binary/Box.glb",
    "Box/glTF/Box.gltf",
    "BoxTextured/glTF-Binary/BoxTextured.glb",
    "Duck/glTF-Binary/Duck.glb",
    "Avocado/glTF/Avocado.gltf",
    "DamagedHelmet/glTF-Binary/DamagedHelmet.glb",
    "MetalRoughSpheresNoTextures/glTF-Binary/MetalRoughSpheresNoTextures.glb",
    "NormalTangentTest/glTF-Binary/NormalTangentTest.glb",
    "Suzanne/glTF/Suzanne.gltf",
    "LightsPunctualLamp/glTF/LightsPunctualLamp.gltf",
    "Cameras/glTF/Cameras.gltf",
];

/// Renders `scene` with the CLI at one sample per pixel.
fn render(scene: &Path, extra: &[&str]) -> image::RgbImage {
    let mut args = vec!["--spp", "1"];
    args.extend_from_slice(extra);
    support::render_png(scene, &args)
}

fn lit(p: &image::Rgb<u8>) -> bool {
    p.0 != [0, 0, 0]
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn every_asset_renders_and_auto_framed_ones_are_whole_in_the_picture() {
    let dir = gltf_dir();
    for asset in ASSETS {
        let path = dir.join(asset);
        let img = render(&path, &["--width", "96", "--height", "72"]);
        let covered = img.pixels().filter(|p| lit(p)).count() as f64 / (96.0 * 72.0);
        assert!(covered > 0.02, "{asset}: only {covered:.3} of the picture is lit");
        let scene = scene::load(&path).unwrap();
        if scene.notes.iter().any(|n| n.contains("framed automatically")) {
            // Framed on the bounding box: nothing lit on the top and bottom rows.
            let touches = (0..96).any(|x| lit(img.get_pixel(x, 0)) || lit(img.get_pixel(x, 71)));
            assert!(!touches, "{asset}: the model touches the top or bottom border");
        }
    }
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn damaged_helmet_scene_file_of_the_gallery_renders() {
    gltf_dir();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/shared/damaged-helmet.toml");
    let img = render(&scene, &["--width", "64", "--height", "64"]);
    let covered = img.pixels().filter(|p| lit(p)).count() as f64 / (64.0 * 64.0);
    assert!(covered > 0.2, "coverage {covered}");
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn duck_and_cameras_use_their_own_cameras() {
    let dir = gltf_dir();
    let duck = scene::load(&dir.join("Duck/glTF-Binary/Duck.glb")).unwrap();
    assert!(
        duck.notes.iter().any(|n| n.contains("the file's camera 0")),
        "{:?}",
        duck.notes
    );
    assert_eq!((duck.film.width, duck.film.height), (720, 480), "aspect ratio 1.5");
    // The camera node is a child of the root scaled by 0.01: it stands at 0.01 × its offset.
    assert!((duck.camera.position - Vec3::new(4.00113, 4.63264, -4.31078)).length() < 1e-4);

    // Cameras.gltf: a unit square tilted 45° back about x, both cameras at (0.5, 0.5, 3).
    // Perspective (yfov 0.7): bottom edge (y 0, z 0) at row 240 + 240·(0.5/3)/tan(0.35);
    // top edge (y = z = 0.707 back) at row 240 − 240·(0.207/3.707)/tan(0.35).
    let cameras = dir.join("Cameras/glTF/Cameras.gltf");
    let t = 0.35f32.tan();
    let bottom = 240.0 + 240.0 * (0.5 / 3.0) / t;
    let top = 240.0 - 240.0 * ((0.5f32.sqrt() - 0.5) / (3.0 + 0.5f32.sqrt())) / t;
    let img = render(&cameras, &[]);
    assert_eq!(img.dimensions(), (480, 480));
    let rows: Vec<u32> = (0..480).filter(|&y| lit(img.get_pixel(240, y))).collect();
    assert!(
        (rows[0] as f32 - top).abs() <= 1.5,
        "top edge at row {} vs {top}",
        rows[0]
    );
    assert!(
        (*rows.last().unwrap() as f32 - bottom).abs() <= 1.5,
        "bottom edge at row {} vs {bottom}",
        rows.last().unwrap()
    );
    // Orthographic (xmag = ymag = 1): x ∈ [0, 1] → columns 120..360, y ∈ [0, 0.707] → rows
    // 360 down to 240 − 0.207·240.
    let img = render(&cameras, &["--camera", "1"]);
    let cols: Vec<u32> = (0..480).filter(|&x| lit(img.get_pixel(x, 300))).collect();
    assert_eq!((cols[0], *cols.last().unwrap()), (120, 359));
    let rows: Vec<u32> = (0..480).filter(|&y| lit(img.get_pixel(240, y))).collect();
    let top = 240.0 - (0.5f32.sqrt() - 0.5) * 240.0;
    assert!(
        (rows[0] as f32 - top).abs() <= 1.0 && *rows.last().unwrap() == 359,
        "{:?}",
        (rows[0], top)
    );
    let err = scene::load_with(&cameras, LoadOptions { camera: Some(2) }).unwrap_err();
    assert!(err.to_string().contains("--camera"), "{err}");
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn lamp_has_its_five_point_lights_where_its_nodes_put_them() {
    let dir = gltf_dir();
    let lamp = scene::load(&dir.join("LightsPunctualLamp/glTF/LightsPunctualLamp.gltf")).unwrap();
    // (node translation, colour × intensity) from the file, in node order.
    let expected = [
        (
            [0.046_223_55, 0.907_797_3, 0.006_696_63],
            [1.0, 0.631_875, 0.239_099_76],
            15.0,
        ),
        ([0.175_456_2, -0.764_219_9, -0.005_704_08], [1.0, 1.0, 1.0], 1.5),
        (
            [0.137_618_2, 2.066_983_7, -1.178_986_4],
            [0.212_230_8, 0.590_619, 0.558_340_5],
            80.0,
        ),
        (
            [0.044_289, 0.254_364_4, -1.209_032_4],
            [0.212_230_8, 0.590_619, 0.558_340_5],
            80.0,
        ),
        (
            [0.292_021, 1.032_399_9, 1.558_916],
            [1.0, 0.627_836_5, 0.501_240_4],
            180.0,
        ),
    ];
    assert_eq!(lamp.lights.len(), 5);
    for (light, (position, color, intensity)) in lamp.lights.iter().zip(expected) {
        match light.kind {
            LightKind::Point { position: p } => assert!((p - Vec3::from(position)).length() < 1e-5, "{p}"),
            other => panic!("{other:?}"),
        }
        assert!((light.power - Vec3::from(color) * intensity).length() < 1e-4 * intensity);
        assert_eq!(light.falloff, Falloff::InverseSquare);
    }
    assert!(lamp.warnings.iter().any(|w| w.contains("KHR_materials_transmission")));
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn damaged_helmet_decodes_four_textures_and_maps_normals() {
    let dir = gltf_dir();
    let helmet = scene::load(&dir.join("DamagedHelmet/glTF-Binary/DamagedHelmet.glb")).unwrap();
    let plan = RenderPlan::new(&helmet, &[]);
    assert!(plan.textures && plan.normal_textures && plan.emission && plan.uvs);
    // Base colour, metallic-roughness, normal, emissive; not occlusion.
    assert_eq!(helmet.textures.len(), 4);
    assert!(helmet.textures.iter().all(|t| (t.width, t.height) == (2048, 2048)));
    assert!(helmet.notes.iter().any(|n| n.contains("occlusion textures not used")));
    assert!(helmet.notes.iter().any(|n| n.contains("MikkTSpace tangents generated")));
    let tangents = helmet.mesh.tangents.as_ref().unwrap();
    let with_tangent = tangents.iter().filter(|t| t.w != 0.0).count();
    assert!(with_tangent as f64 > 0.99 * tangents.len() as f64);
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn normal_mapped_cells_are_lit_like_their_geometry_twins() {
    let dir = gltf_dir();
    // A front orthographic view of NormalTangentTest, 0.005 units per pixel, lit from the
    // upper left. Each row has two pairs of cells: real hemisphere geometry, then a flat quad
    // whose normal texture encodes the same hemisphere (each row with UVs rotated differently).
    // A flipped green channel or a wrong tangent frame lights the mapped dome from another side.
    let scene_dir = support::Scratch::new("ntt");
    let toml = scene_dir.write(
        "ntt.toml",
        &format!(
            "[film]\nwidth = 444\nheight = 430\n\
             [camera]\ntype = \"orthographic\"\nposition = [0.0, -0.125, 5.0]\nlook_at = [0.0, -0.125, 0.0]\nscale = 1.075\n\
             [[light]]\ntype = \"directional\"\ndirection = [0.5, -0.6, -1.0]\nintensity = 3.0\n\
             [[object]]\nmesh = \"{}\"\n",
            dir.join("NormalTangentTest/glTF-Binary/NormalTangentTest.glb").display()
        ),
    );
    let img = render(&toml, &[]);
    drop(scene_dir);
    // Mean brightness of the four quadrants (UL, UR, LL, LR) of the dome of the 60-pixel cell
    // whose top-left pixel is (x0, y0).
    let quadrants = |x0: u32, y0: u32| -> [f64; 4] {
        let mut q = [0.0; 4];
        for y in 0..44 {
            for x in 0..44 {
                let p = img.get_pixel(x0 + 8 + x, y0 + 8 + y).0;
                q[(y / 22 * 2 + x / 22) as usize] += p.iter().map(|&c| c as f64).sum::<f64>();
            }
        }
        q.map(|v| v / (22.0 * 22.0))
    };
    for y0 in [0, 80, 160, 240, 320] {
        for (geometry_x, mapped_x) in [(0, 64), (160, 224)] {
            let (g, m) = (quadrants(geometry_x, y0), quadrants(mapped_x, y0));
            // Lit from the upper left: UL brightest, then UR and LL, LR darkest — on both.
            for q in [g, m] {
                assert!(
                    q[0] > q[1] && q[0] > q[2] && q[1] > q[3] && q[2] > q[3],
                    "cell at ({mapped_x}, {y0}): {q:?}"
                );
            }
            // The lit quadrants agree within 10% (LR differs: only real geometry casts a shadow).
            for k in 0..3 {
                assert!(
                    (g[k] - m[k]).abs() < 0.1 * g[k],
                    "row {y0}, quadrant {k}: geometry {g:?} vs mapped {m:?}"
                );
            }
        }
    }
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn metal_rough_spheres_vary_roughness_along_x_and_metalness_along_y() {
    let dir = gltf_dir();
    let s = scene::load(&dir.join("MetalRoughSpheresNoTextures/glTF-Binary/MetalRoughSpheresNoTextures.glb")).unwrap();
    // Every sphere instance (98 of them share one mesh) carries its own material: in the front
    // grid (z ≈ 0), roughness = column/6 and metalness = row/6, rows and columns 1 mm apart.
    let mut checked = 0;
    for (t, &m) in s.mesh.material_of_triangle.iter().enumerate() {
        let BrdfModel::GltfPbr(p) = s.materials[m as usize].model else {
            continue;
        };
        if s.materials[m as usize].name == "glTF default" || t % 97 != 0 {
            continue; // the text labels; and a sample of the triangles is enough
        }
        let centre = s.mesh.triangle_positions(t).iter().copied().sum::<Vec3>() / 3.0 * 1000.0;
        if centre.z.abs() > 0.5 {
            continue; // the gold grid behind
        }
        let (column, row) = (centre.x.round(), centre.y.round());
        assert!(
            (p.roughness - column / 6.0).abs() < 1e-3,
            "{centre}: roughness {}",
            p.roughness
        );
        assert!(
            (p.metallic - row / 6.0).abs() < 1e-3,
            "{centre}: metallic {}",
            p.metallic
        );
        checked += 1;
    }
    assert!(checked > 1000, "{checked}");
}
