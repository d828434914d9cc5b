//! Scenes at extreme scales (issue 42, class 7): one scaled far up renders as at scale 1, and one
//! that reaches beyond what f32 distances can hold is refused at load, naming what lies too far.

use std::f32::consts::FRAC_PI_4;
use std::path::{Path, PathBuf};

use glam::{Quat, Vec3};
use pointshade::scene;
use serde_json::json;

use crate::support::gltf_builder::{square, GltfBuilder};
use crate::support::{self, Scratch};

/// A pyramid on a ground square, every coordinate multiplied by `scale`.
fn pyramid(dir: &Path, scale: f64) -> PathBuf {
    let apex = [(0.0, 0.8, 0.0)];
    let base = [(-1.0, 0.0, -1.0), (1.0, 0.0, -1.0), (1.0, 0.0, 1.0), (-1.0, 0.0, 1.0)];
    let ground = [
        (-3.0, -0.01, -3.0),
        (3.0, -0.01, -3.0),
        (3.0, -0.01, 3.0),
        (-3.0, -0.01, 3.0),
    ];
    let mut obj = String::new();
    for (x, y, z) in base.iter().chain(&apex).chain(&ground) {
        obj += &format!("v {:e} {:e} {:e}\n", x * scale, y * scale, z * scale);
    }
    obj += "f 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\nf 6 9 8 7\n";
    let path = dir.join(format!("pyramid-{scale:e}.obj"));
    std::fs::write(&path, obj).unwrap();
    path
}

/// Renders `mesh` framed automatically at 64×48 into an EXR; returns its linear RGB values.
fn render(mesh: &Path) -> Vec<f32> {
    let out = mesh.with_extension("exr");
    let r = support::command()
        .args(["render".as_ref(), mesh.as_os_str(), "-o".as_ref(), out.as_os_str()])
        .args(["--width", "64", "--height", "48", "--quiet"])
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let img = image::open(&out).unwrap().into_rgb32f();
    img.into_raw()
}

#[test]
fn a_scene_scaled_by_1e12_renders_as_at_scale_1() {
    // Above about 1e10 the cross products of the triangles' edges overflowed in f32: the
    // geometric normals came out zero and the image black or speckled.
    let dir = Scratch::new("far-scale");
    let near = render(&pyramid(&dir, 1.0));
    let far = render(&pyramid(&dir, 1e12));
    assert!(near.iter().any(|&v| v > 0.05), "the pyramid is lit");
    for (i, (a, b)) in near.iter().zip(&far).enumerate() {
        assert!(
            (a - b).abs() <= 1e-4 * a.abs().max(1e-3),
            "value {i}: {a} at scale 1, {b} at 1e12"
        );
    }
}

#[test]
fn normals_survive_transforms_whose_determinant_overflows() {
    // A scale of 1e17 has a determinant of 1e51: the inverse transpose is not finite in f32, and
    // the flat normals' cross products (edges of 2e17) overflow. Both keep their direction.
    let dir = Scratch::new("far-normals");
    for with_normals in [true, false] {
        let mut b = GltfBuilder::default();
        let mesh = square(&mut b, with_normals, None);
        let q = Quat::from_rotation_x(FRAC_PI_4);
        let rest = json!({
            "scenes": [{"nodes": [0]}],
            "nodes": [{
                "scale": [1e17, 1e17, 1e17],
                "rotation": q.to_array(),
                "mesh": 0
            }],
            "meshes": [mesh]
        });
        let path = b.write_gltf(&dir, "scaled", rest);
        let scene = scene::load(&path).unwrap();
        let expected = Vec3::new(0.0, -FRAC_PI_4.sin(), FRAC_PI_4.cos());
        for (i, n) in scene.mesh.normals.iter().enumerate() {
            assert!(
                (*n - expected).length() < 1e-5,
                "normals given: {with_normals}, normal {i}: {n}"
            );
        }
    }
}

/// Runs `args`, which must fail as bad input does ([`support::assert_input_error`]): one error
/// line containing each of `expect`, and no output written to `out`.
fn refused(args: &[PathBuf], out: &Path, expect: &[&str]) {
    support::assert_input_error(&support::pointshade(args), expect, &[out]);
}

#[test]
fn geometry_cameras_and_lights_beyond_1e18_are_refused() {
    let dir = Scratch::new("far-refused");
    let out = dir.join("out.png");
    let render = |input: &Path, extra: &[&str]| -> Vec<PathBuf> {
        let mut args = vec![PathBuf::from("render"), input.into(), "-o".into(), out.clone()];
        args.extend(extra.iter().map(PathBuf::from));
        args
    };

    // A vertex whose coordinate is finite in f32 but whose squared distances are not.
    let obj = dir.join("huge.obj");
    std::fs::write(&obj, "v 0 0 0\nv 3e38 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    refused(
        &render(&obj, &[]),
        &out,
        &["huge.obj", "vertex 1", "3.000e38", "beyond 1e18"],
    );

    // A glTF node's matrix that carries a unit square out to 1e38.
    let mut b = GltfBuilder::default();
    let mesh = square(&mut b, true, None);
    let m = [
        1e38, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
    ];
    let rest = json!({"scenes": [{"nodes": [0]}], "nodes": [{"matrix": m, "mesh": 0}], "meshes": [mesh]});
    let gltf = b.write_gltf(&dir, "stretched", rest);
    refused(
        &render(&gltf, &[]),
        &out,
        &["stretched.gltf", "vertex 0", "beyond 1e18"],
    );

    // A camera placed from the command line, beyond the limit and beyond f32.
    let fine = dir.join("fine.obj");
    std::fs::write(&fine, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    for far in ["1e30,0,0", "1e39,0,0"] {
        refused(
            &render(&fine, &["--look-from", far]),
            &out,
            &["--look-from", "camera's position"],
        );
    }

    // A light in a scene file.
    let toml = dir.join("far-light.toml");
    std::fs::write(
        &toml,
        "[camera]\nposition = [0.0, 0.0, 3.0]\nlook_at = [0.0, 0.0, 0.0]\nfov = 40.0\n\
         [[light]]\ntype = \"point\"\nposition = [0.0, 0.0, 1e30]\nintensity = 1.0\n\
         [[object]]\nmesh = \"fine.obj\"\n",
    )
    .unwrap();
    refused(&render(&toml, &[]), &out, &["far-light.toml", "light 1", "1.000e30"]);
}
