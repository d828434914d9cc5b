//! Every class of bad input gives a one-line error naming the file and the problem, exit code 2,
//! no panic, and no output file.

use crate::support;

use std::path::{Path, PathBuf};

use serde_json::json;
use support::gltf_builder::{square, GltfBuilder};
use support::Scratch;

/// A test's folder, holding `tri.obj` (one triangle) for scenes to name.
struct Case {
    dir: Scratch,
}

impl Case {
    fn new(name: &str) -> Self {
        let dir = Scratch::new(&format!("bad-{name}"));
        dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        Case { dir }
    }

    fn file(&self, name: &str, text: &str) -> PathBuf {
        self.dir.write(name, text)
    }

    /// Runs `render SCENE -o out.png EXTRA…` and checks the failure contract
    /// ([`support::assert_input_error`]); returns the error line.
    fn fails(&self, scene: &Path, extra: &[&str], expect_in_message: &[&str]) -> String {
        let out = self.dir.path("out.png");
        let result = support::command()
            .arg("render")
            .arg(scene)
            .arg("-o")
            .arg(&out)
            .args(extra)
            .output()
            .unwrap();
        support::assert_input_error(&result, expect_in_message, &[&out])
    }

    fn scene(&self, body: &str) -> PathBuf {
        self.file("scene.toml", body)
    }
}

const CAMERA: &str = "[camera]\nposition = [0.0, 0.0, 3.0]\nlook_at = [0.0, 0.0, 0.0]\nfov = 40.0\n";

#[test]
fn malformed_obj_files() {
    let c = Case::new("obj");
    let out_of_range = c.file("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
    c.fails(&out_of_range, &[], &["range.obj"]);
    let garbage = c.file("garbage.obj", "v 0 0 zero\nf 1 2 3\n");
    c.fails(&garbage, &[], &["garbage.obj", "malformed OBJ"]);
    let nan = c.file("nan.obj", "v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    c.fails(&nan, &[], &["nan.obj", "not finite"]);
    let empty = c.file("empty.obj", "# nothing\n");
    c.fails(&empty, &[], &["empty.obj", "no faces"]);
    let binary = c.dir.join("binary.obj");
    std::fs::write(&binary, [0u8, 159, 146, 150, 255, 0, 1, 2]).unwrap();
    c.fails(&binary, &[], &["binary.obj"]);
}

#[test]
fn toml_syntax_unknown_keys_and_wrong_types_give_line_and_column() {
    let c = Case::new("toml");
    let syntax = c.scene("[film\nwidth = 3\n");
    c.fails(&syntax, &[], &["scene.toml", "line 1"]);
    let unknown = c.scene(&format!("{CAMERA}\n[film]\nwidth = 64\nwidht = 64\n"));
    c.fails(&unknown, &[], &["scene.toml", "line 8", "widht"]);
    let wrong_type = c.scene(&format!("{CAMERA}[film]\nwidth = \"big\"\n"));
    c.fails(&wrong_type, &[], &["scene.toml", "line 6"]);
    let unknown_model = c.scene("[material.m]\nmodel = \"phong\"\n");
    c.fails(&unknown_model, &[], &["line 2", "phong"]);
    let unknown_term = c.scene("[material.m]\nmodel = \"cook-torrance\"\ng = \"smith\"\n");
    c.fails(&unknown_term, &[], &["line 3", "smith"]);
    let terminator = c.scene("[render]\nshadow_terminator = \"soft\"\n");
    c.fails(&terminator, &[], &["scene.toml", "line 2", "soft", "smooth or flat"]);
}

#[test]
fn unknown_material_name() {
    let c = Case::new("material");
    let s = c.scene(&format!(
        "{CAMERA}[material.red]\nalbedo = [0.8, 0.1, 0.1]\n[[object]]\nmesh = \"tri.obj\"\nmaterial = \"blue\"\n"
    ));
    c.fails(&s, &[], &["scene.toml", "line 9", "unknown material 'blue'", "red"]);
}

#[test]
fn missing_files() {
    let c = Case::new("missing");
    c.fails(&c.dir.join("nope.toml"), &[], &["nope.toml"]);
    c.fails(&c.dir.join("nope.obj"), &[], &["nope.obj", "not found"]);
    let s = c.scene(&format!("{CAMERA}[[object]]\nmesh = \"absent.obj\"\n"));
    c.fails(&s, &[], &["absent.obj", "not found"]);
}

#[test]
fn nan_and_negative_parameters() {
    let c = Case::new("params");
    let nan_roughness = c.scene(&format!(
        "{CAMERA}[material.m]\nmodel = \"cook-torrance\"\nroughness = nan\n[[object]]\nmesh = \"tri.obj\"\nmaterial = \"m\"\n"
    ));
    c.fails(&nan_roughness, &[], &["scene.toml", "roughness"]);
    let negative_light = c.scene(&format!(
        "{CAMERA}[[light]]\ntype = \"point\"\nposition = [0.0, 1.0, 1.0]\nintensity = -5.0\n"
    ));
    c.fails(&negative_light, &[], &["scene.toml", "line 5", "intensity"]);
    let nan_position = c.scene(&format!(
        "{CAMERA}[[light]]\ntype = \"point\"\nposition = [0.0, nan, 1.0]\n"
    ));
    c.fails(&nan_position, &[], &["position"]);
    let bad_fov = c.scene("[camera]\nposition = [0.0, 0.0, 3.0]\nlook_at = [0.0, 0.0, 0.0]\nfov = 190.0\n");
    c.fails(&bad_fov, &[], &["fov"]);
    let zero_scale = c.scene(&format!(
        "{CAMERA}[[object]]\nmesh = \"tri.obj\"\ntransform = {{ scale = 0.0 }}\n"
    ));
    c.fails(&zero_scale, &[], &["scale"]);
    // Finite parameters whose product overflows f32: an error, never an image with ∞ in it.
    let overflow = c.scene(&format!(
        "{CAMERA}[[light]]\ntype = \"directional\"\ndirection = [0.0, 0.0, -1.0]\nintensity = 3e38\n[material.m]\nalbedo = [1e30, 1.0, 1.0]\n[[object]]\nmesh = \"tri.obj\"\nmaterial = \"m\"\n"
    ));
    c.fails(&overflow, &[], &["scene.toml", "radiance overflowed at pixel"]);
}

#[test]
fn absurd_sizes_and_bad_options() {
    let c = Case::new("sizes");
    let huge = c.scene(&format!("{CAMERA}[film]\nwidth = 1000000\nheight = 1000000\n"));
    c.fails(&huge, &[], &["scene.toml", "too large"]);
    let tri = c.dir.join("tri.obj");
    c.fails(&tri, &["--width", "0"], &["--width", "from 1 to 65536"]);
    c.fails(
        &tri,
        &["--width", "65536", "--height", "65536"],
        &["image size", "too large"],
    );
    c.fails(&tri, &["--spp", "10000000"], &["spp"]);
    c.fails(&tri, &["--sampler", "grid", "--spp", "8"], &["square"]);
    c.fails(&tri, &["--sampler", "halton"], &["--sampler", "halton"]);
    c.fails(&tri, &["--aov", "normals"], &["--aov"]);
    c.fails(&tri, &["--shadow-terminator", "soft"], &["--shadow-terminator", "soft"]);
    c.fails(&tri, &["--time-budget", "nan"], &["--time-budget", "got 'nan'"]);
    c.fails(&tri, &["--time-budget", "0"], &["--time-budget", "(0, 604800]"]);
    c.fails(
        &tri,
        &["--time-budget", "1", "--sampler", "grid"],
        &["time budget", "grid"],
    );
    let budget_in_file = c.scene(&format!("{CAMERA}[film]\ntime_budget = -2.0\n"));
    c.fails(&budget_in_file, &[], &["scene.toml", "time_budget"]);
    let out = c.dir.join("out.png");
    let r = support::pointshade(&[
        "render",
        tri.to_str().unwrap(),
        "-o",
        c.dir.join("out.jpg").to_str().unwrap(),
    ]);
    assert_eq!(r.status.code(), Some(2));
    assert!(!out.exists());
}

#[test]
fn an_output_folder_that_does_not_exist_fails_before_anything_is_rendered() {
    let c = Case::new("folder");
    let tri = c.dir.join("tri.obj");
    let out = c.dir.join("missing").join("out.png");
    // merge's crop does not even exist: the folder is checked before any input is read.
    for (command, input) in [("render", tri), ("merge", c.dir.join("crop.exr"))] {
        let r = support::pointshade(&[command.as_ref(), input.as_os_str(), "-o".as_ref(), out.as_os_str()]);
        support::assert_one_line_error(&r, &["out.png", "does not exist"], &[&out]);
    }
    assert!(!c.dir.join("missing").exists());
}

/// A valid single-square glTF document (builder and the JSON besides buffers and accessors).
fn gltf_square() -> (GltfBuilder, serde_json::Value) {
    let mut b = GltfBuilder::default();
    let mesh = square(&mut b, true, None);
    let rest = json!({"scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}], "meshes": [mesh]});
    (b, rest)
}

#[test]
fn malformed_gltf_and_glb_files() {
    let c = Case::new("gltf");
    let (b, rest) = gltf_square();
    let glb = b.glb(rest.clone());

    let truncated = c.dir.join("truncated.glb");
    std::fs::write(&truncated, &glb[..glb.len() / 2]).unwrap();
    c.fails(&truncated, &[], &["truncated.glb", "truncated binary glTF"]);
    let mut chunk_cut = glb.clone();
    chunk_cut.truncate(glb.len() - 8);
    let cut_length = chunk_cut.len() as u32;
    chunk_cut[8..12].copy_from_slice(&cut_length.to_le_bytes());
    let chunk = c.dir.join("chunk.glb");
    std::fs::write(&chunk, &chunk_cut).unwrap();
    c.fails(&chunk, &[], &["chunk.glb", "truncated binary glTF"]);
    let tiny = c.dir.join("tiny.glb");
    std::fs::write(&tiny, b"glTF").unwrap();
    c.fails(&tiny, &[], &["tiny.glb", "truncated"]);

    let mut wrong = glb.clone();
    wrong[..4].copy_from_slice(b"glTX");
    let magic = c.dir.join("magic.glb");
    std::fs::write(&magic, &wrong).unwrap();
    c.fails(&magic, &[], &["magic.glb", "not a binary glTF", "glTX"]);

    let json = c.file("syntax.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [");
    c.fails(&json, &[], &["syntax.gltf", "invalid glTF JSON"]);
    let bad_index = c.file(
        "index.gltf",
        r#"{"asset": {"version": "2.0"}, "scenes": [{"nodes": [3]}], "nodes": []}"#,
    );
    c.fails(&bad_index, &[], &["index.gltf", "invalid glTF"]);
    // An out-of-range POSITION accessor: the gltf crate's own validation indexes with it
    // unchecked and panicked (found by mutating shared assets).
    let position = c.file(
        "position.gltf",
        r#"{"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 5}}]}]}"#,
    );
    c.fails(
        &position,
        &[],
        &["position.gltf", "POSITION", "accessor 5 does not exist"],
    );
    let cycle = c.file(
        "cycle.gltf",
        r#"{"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"children": [1]}, {"children": [0]}]}"#,
    );
    c.fails(&cycle, &[], &["cycle.gltf", "reached twice"]);
    let overflow = c.file(
        "overflow.gltf",
        r#"{"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"scale": [1e39, 1, 1]}]}"#,
    );
    c.fails(&overflow, &[], &["overflow.gltf", "node 0", "not finite"]);
    let empty = c.file("empty.gltf", r#"{"asset": {"version": "2.0"}}"#);
    c.fails(&empty, &[], &["empty.gltf", "no triangles"]);
}

#[test]
fn gltf_data_out_of_range_or_not_finite() {
    let c = Case::new("gltf-range");
    // An accessor reading past the end of its buffer view; a view past its buffer; an index
    // beyond the vertices; an absurd element count; NaN positions.
    let (b, rest) = gltf_square();
    let doc = b.document(rest, Some("square.bin"));
    std::fs::write(c.dir.join("square.bin"), &b.bin).unwrap();
    let write = |name: &str, edit: &dyn Fn(&mut serde_json::Value)| {
        let mut d = doc.clone();
        edit(&mut d);
        let p = c.dir.join(name);
        std::fs::write(&p, serde_json::to_string(&d).unwrap()).unwrap();
        p
    };
    let past_view = write("accessor.gltf", &|d| d["accessors"][0]["count"] = json!(40));
    c.fails(&past_view, &[], &["accessor.gltf", "accessor 0", "past the end"]);
    let huge = write("huge.gltf", &|d| d["accessors"][0]["count"] = json!(4_000_000_000u64));
    c.fails(&huge, &[], &["huge.gltf", "accessor 0"]);
    let past_buffer = write("view.gltf", &|d| d["bufferViews"][0]["byteLength"] = json!(100_000));
    c.fails(&past_buffer, &[], &["view.gltf", "lies outside buffer 0"]);
    let short_buffer = write("buffer.gltf", &|d| d["buffers"][0]["byteLength"] = json!(100_000));
    c.fails(&short_buffer, &[], &["buffer.gltf", "fewer than its byteLength"]);
    let wrong_type = write("type.gltf", &|d| d["accessors"][0]["type"] = json!("VEC2"));
    c.fails(&wrong_type, &[], &["type.gltf", "POSITION"]);
    // glTF keeps baseColorFactor in [0, 1]; 1e30 made a metal's diffuse weight 1 − F hugely
    // negative and the pixel −∞ (found by tests/integration/gltf_mutations.rs with another seed).
    let base = write("base.gltf", &|d| {
        d["materials"] = json!([{"pbrMetallicRoughness": {"baseColorFactor": [1e30, 1.0, 1.0, 1.0]}}]);
        d["meshes"][0]["primitives"][0]["material"] = json!(0);
    });
    c.fails(&base, &[], &["base.gltf", "base colour factor must be in [0, 1]"]);

    // Index 7 of 4 vertices.
    let mut b2 = GltfBuilder::default();
    let p = b2.floats("VEC3", &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0]);
    let i = b2.indices(&[0, 1, 7]);
    let mesh = json!({"primitives": [{"attributes": {"POSITION": p}, "indices": i}]});
    let path = b2.write_gltf(
        &c.dir,
        "indices",
        json!({"scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}], "meshes": [mesh]}),
    );
    c.fails(&path, &[], &["indices.gltf", "index 7 is out of range"]);

    let mut b3 = GltfBuilder::default();
    let p = b3.floats("VEC3", &[0.0, 0.0, 0.0, f32::NAN, 0.0, 0.0, 0.0, 1.0, 0.0]);
    let mesh = json!({"primitives": [{"attributes": {"POSITION": p}}]});
    let path = b3.write_gltf(
        &c.dir,
        "nan",
        json!({"scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}], "meshes": [mesh]}),
    );
    c.fails(&path, &[], &["nan.gltf", "not finite"]);
}

#[test]
fn gltf_missing_files_unsupported_extensions_and_bad_camera_choice() {
    let c = Case::new("gltf-files");
    let (b, rest) = gltf_square();
    let path = b.write_gltf(&c.dir, "square", rest.clone());
    std::fs::remove_file(c.dir.join("square.bin")).unwrap();
    c.fails(&path, &[], &["square.gltf", "buffer 0", "square.bin"]);

    let (b, mut rest) = gltf_square();
    rest["materials"] = json!([{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]);
    rest["meshes"][0]["primitives"][0]["material"] = json!(0);
    rest["textures"] = json!([{"source": 0}]);
    rest["images"] = json!([{"uri": "missing.png"}]);
    let path = b.write_gltf(&c.dir, "texture", rest.clone());
    c.fails(&path, &[], &["texture.gltf", "missing.png"]);
    c.file("garbage.png", "not a png");
    rest["images"] = json!([{"uri": "garbage.png"}]);
    let path = b.write_gltf(&c.dir, "garbage", rest);
    c.fails(&path, &[], &["garbage.gltf", "garbage.png", "cannot decode"]);

    let (b, mut rest) = gltf_square();
    rest["extensionsUsed"] = json!([
        "KHR_draco_mesh_compression",
        "KHR_materials_transmission",
        "KHR_texture_transform",
        "KHR_lights_punctual"
    ]);
    rest["extensionsRequired"] = json!([
        "KHR_draco_mesh_compression",
        "KHR_lights_punctual",
        "KHR_materials_transmission",
        "KHR_texture_transform"
    ]);
    let path = b.write_gltf(&c.dir, "draco", rest);
    let e = c.fails(
        &path,
        &[],
        &["draco.gltf", "KHR_draco_mesh_compression, KHR_materials_transmission"],
    );
    assert!(
        !e.contains("KHR_lights_punctual") && !e.contains("KHR_texture_transform"),
        "{e}"
    );

    let (b, rest) = gltf_square();
    let path = b.write_gltf(&c.dir, "nocamera", rest);
    c.fails(&path, &["--camera", "0"], &["--camera", "no camera"]);
    c.fails(
        &c.dir.join("tri.obj"),
        &["--camera", "0"],
        &["--camera", "only .gltf and .glb files"],
    );
    let toml = c.scene("[[object]]\nmesh = \"missing.glb\"\n");
    c.fails(&toml, &[], &["missing.glb", "not found"]);
}
