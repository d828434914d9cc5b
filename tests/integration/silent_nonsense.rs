//! Input that used to be accepted in silence and rendered as something else than it says
//! (issue 42, class 5): each is now an error, or a warning that names the file, the element and
//! the value.

use crate::support;

use std::path::{Path, PathBuf};
use std::process::Output;

use serde_json::json;

use pointshade::scene;
use support::gltf_builder::{square, GltfBuilder};
use support::Scratch;

/// Renders `input` at 16×12 into `dir/out.png`: the output, and whether the PNG was written.
fn render(dir: &Path, input: &Path) -> (Output, bool) {
    let out = dir.join("out.png");
    let _ = std::fs::remove_file(&out);
    let args = [
        Path::new("render"),
        input,
        Path::new("-o"),
        &out,
        Path::new("--width"),
        Path::new("16"),
        Path::new("--height"),
        Path::new("12"),
    ];
    let output = support::pointshade(&args);
    (output, out.exists())
}

/// The one error line of a render of `input` that must fail as bad input does
/// ([`support::assert_input_error`]) and write nothing.
fn refused(dir: &Path, input: &Path) -> String {
    let (out, _) = render(dir, input);
    support::assert_input_error(&out, &[], &[&dir.join("out.png")])
}

/// The warning lines of a render of `input` that must succeed.
fn warnings(dir: &Path, input: &Path) -> Vec<String> {
    let (out, written) = render(dir, input);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success() && written, "{}: {stderr}", input.display());
    stderr
        .lines()
        .filter(|l| l.starts_with("warning:"))
        .map(str::to_string)
        .collect()
}

const TRIANGLE: &str = "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n";

fn scene_file(dir: &Path, name: &str, camera: &str, light: &str, material: &str) -> PathBuf {
    std::fs::write(dir.join("tri.obj"), TRIANGLE).unwrap();
    let text = format!(
        "[camera]\nposition = {camera}\nlook_at = [0.0, 0.0, 0.0]\nfov = 40.0\n\n\
         [[light]]\ntype = \"point\"\nposition = {light}\nintensity = 10.0\n\n\
         [material.m]\nalbedo = {material}\n\n\
         [[object]]\nmesh = \"tri.obj\"\nmaterial = \"m\"\n"
    );
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn vectors_with_more_than_three_elements_are_refused() {
    let dir = Scratch::new("long-vectors");
    let (camera, light, albedo) = ("[0.0, 0.0, 3.0]", "[0.0, 2.0, 2.0]", "[0.5, 0.5, 0.5]");
    // The three as they should be render.
    assert!(warnings(&dir, &scene_file(&dir, "fine", camera, light, albedo)).is_empty());
    for (bad, which) in [
        (
            scene_file(&dir, "junk", "[0.0, 2.2, 5.5, \"junk\"]", light, albedo),
            "line 2",
        ),
        (
            scene_file(&dir, "camera", "[0.0, 2.2, 5.5, 1.0]", light, albedo),
            "line 2",
        ),
        (
            scene_file(&dir, "light", camera, "[0.0, 2.0, 2.0, 1.0]", albedo),
            "line 8",
        ),
        (
            scene_file(&dir, "long", camera, light, "[0.5, 0.5, 0.5, 0.5, 0.5]"),
            "length 5",
        ),
        (scene_file(&dir, "short", camera, light, "[0.5, 0.5]"), "length 2"),
    ] {
        let e = refused(&dir, &bad);
        assert!(e.contains(&bad.display().to_string()) && e.contains(which), "{e}");
    }
}

#[test]
fn faces_that_repeat_a_vertex_are_named() {
    let dir = Scratch::new("repeated-vertices");
    let obj = dir.join("some.obj");
    std::fs::write(&obj, format!("{TRIANGLE}f 1 2\nf 3\nf 2 2 2\n")).unwrap();
    let w = warnings(&dir, &obj);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("some.obj") && w[0].contains("3 of its 4 triangles") && w[0].contains("line 5, `f 1 2`"),
        "{}",
        w[0]
    );
    let only = dir.join("only.obj");
    std::fs::write(&only, "v 0 0 0\nv 1 0 0\nf 1 2\nf 1 1 1\n").unwrap();
    let e = refused(&dir, &only);
    assert!(
        e.contains("only.obj") && e.contains("every triangle repeats a vertex"),
        "{e}"
    );
}

fn gltf_with_camera(dir: &Path, name: &str, camera: serde_json::Value, version: &str) -> PathBuf {
    let mut b = GltfBuilder::default();
    let mesh = square(&mut b, true, None);
    let rest = json!({
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0.0, 0.0, 3.0]}],
        "cameras": [camera],
        "meshes": [mesh],
    });
    let path = b.write_gltf(dir, name, rest);
    let text = std::fs::read_to_string(&path).unwrap();
    std::fs::write(&path, text.replace("\"2.0\"", &format!("\"{version}\""))).unwrap();
    path
}

#[test]
fn gltf_aspect_ratios_beyond_a_hundred_to_one_are_not_used_and_other_major_versions_are_refused() {
    let dir = Scratch::new("gltf-nonsense");
    let perspective = |aspect: f64| json!({"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.01, "aspectRatio": aspect}});
    let ortho =
        json!({"type": "orthographic", "orthographic": {"xmag": 1e18, "ymag": 1.0, "znear": 0.01, "zfar": 100.0}});
    for (name, camera, value) in [
        ("wide", perspective(1e9), "1e9"),
        ("narrow", perspective(1e-9), "1e-9"),
        ("ortho", ortho, "1e18"),
    ] {
        let path = gltf_with_camera(&dir, name, camera, "2.0");
        let s = scene::load(&path).unwrap();
        assert_eq!((s.film.width, s.film.height), (640, 480), "{name}");
        assert_eq!(s.warnings.len(), 1, "{:?}", s.warnings);
        let w = &s.warnings[0];
        assert!(
            w.contains(&format!("{name}.gltf")) && w.contains("camera 0") && w.contains(value),
            "{w}"
        );
    }
    // Within the limit the camera still sets the width.
    let s = scene::load(&gltf_with_camera(&dir, "fine", perspective(2.0), "2.0")).unwrap();
    assert_eq!((s.film.width, s.warnings.len()), (960, 0));

    for (version, what) in [
        ("3.0", "asset.version is \"3.0\""),
        ("2", "asset.version is \"2\""),
        ("two", "\"two\""),
    ] {
        let path = gltf_with_camera(&dir, "version", perspective(1.0), version);
        let e = refused(&dir, &path);
        assert!(e.contains("version.gltf") && e.contains(what), "{e}");
    }
    assert!(scene::load(&gltf_with_camera(&dir, "minor", perspective(1.0), "2.1")).is_ok());
}

/// A 4×2 palette PNG of `entries` colours whose pixels use the indices `0..8`.
fn palette_png(path: &Path, entries: usize) {
    let file = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    let mut encoder = png::Encoder::new(file, 4, 2);
    encoder.set_color(png::ColorType::Indexed);
    encoder.set_depth(png::BitDepth::Eight);
    let palette: Vec<u8> = (0..entries).flat_map(|k| [128, 128, 200 + k as u8]).collect();
    encoder.set_palette(palette);
    let mut writer = encoder.write_header().unwrap();
    writer.write_image_data(&[0, 1, 2, 3, 4, 5, 6, 7]).unwrap();
}

#[test]
fn palette_indices_past_the_palette_are_refused() {
    let dir = Scratch::new("palette");
    // As a normal image.
    palette_png(&dir.join("full.png"), 8);
    palette_png(&dir.join("short.png"), 5);
    let normalmap = |name: &str| {
        let out = dir.join(format!("{name}-shaded.png"));
        let output = support::pointshade(&[
            Path::new("normalmap"),
            &dir.join(name),
            Path::new("--brdf"),
            Path::new("lambert"),
            Path::new("-o"),
            &out,
        ]);
        (output, out.exists())
    };
    let (ok, written) = normalmap("full.png");
    assert!(
        ok.status.success() && written,
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    let (bad, written) = normalmap("short.png");
    let stderr = String::from_utf8_lossy(&bad.stderr);
    assert_eq!(bad.status.code(), Some(2), "{stderr}");
    assert!(!written);
    assert!(
        stderr.contains("short.png") && stderr.contains("palette index 7") && stderr.contains("5 entries"),
        "{stderr}"
    );
    // As a texture.
    std::fs::write(
        dir.join("textured.obj"),
        "mtllib t.mtl\nv -1 -1 0\nv 1 -1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl t\nf 1/1 2/2 3/3\n",
    )
    .unwrap();
    std::fs::write(dir.join("t.mtl"), "newmtl t\nKd 1 1 1\nmap_Kd short.png\n").unwrap();
    let e = refused(&dir, &dir.join("textured.obj"));
    assert!(e.contains("short.png") && e.contains("palette index 7"), "{e}");
}
