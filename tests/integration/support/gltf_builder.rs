//! Writes small glTF files for tests: binary data goes into one buffer, the test writes the rest
//! of the JSON itself (meshes, nodes, materials …) with `serde_json::json!`.

#![allow(dead_code)]

use std::path::{Path, PathBuf};

use serde_json::{json, Value};

/// Accessors over one binary buffer.
#[derive(Default)]
pub struct GltfBuilder {
    pub bin: Vec<u8>,
    pub views: Vec<Value>,
    pub accessors: Vec<Value>,
}

impl GltfBuilder {
    /// A buffer view over `bytes` (4-byte aligned); returns its index.
    pub fn view(&mut self, bytes: &[u8]) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        self.views
            .push(json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len()}));
        self.bin.extend_from_slice(bytes);
        self.views.len() - 1
    }

    /// A float accessor of `type_` ("VEC2", "VEC3", "VEC4") over `data`; returns its index.
    pub fn floats(&mut self, type_: &str, data: &[f32]) -> usize {
        let n = match type_ {
            "SCALAR" => 1,
            "VEC2" => 2,
            "VEC3" => 3,
            "VEC4" => 4,
            _ => panic!("type {type_}"),
        };
        let bytes: Vec<u8> = data.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes);
        let mut accessor = json!({"bufferView": view, "componentType": 5126, "count": data.len() / n, "type": type_});
        if type_ == "VEC3" {
            let (mut lo, mut hi) = ([f32::MAX; 3], [f32::MIN; 3]);
            for c in data.chunks(3) {
                for k in 0..3 {
                    lo[k] = lo[k].min(c[k]);
                    hi[k] = hi[k].max(c[k]);
                }
            }
            accessor["min"] = json!(lo);
            accessor["max"] = json!(hi);
        }
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    /// An unsigned-int index accessor; returns its index.
    pub fn indices(&mut self, data: &[u32]) -> usize {
        let bytes: Vec<u8> = data.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes);
        self.accessors
            .push(json!({"bufferView": view, "componentType": 5125, "count": data.len(), "type": "SCALAR"}));
        self.accessors.len() - 1
    }

    /// The whole document: `rest` (meshes, nodes, scenes …) plus asset, buffers, views and
    /// accessors; the buffer is `uri` if given (the caller writes the .bin), else the GLB chunk.
    pub fn document(&self, rest: Value, uri: Option<&str>) -> Value {
        let mut doc = rest;
        doc["asset"] = json!({"version": "2.0"});
        let mut buffer = json!({"byteLength": self.bin.len()});
        if let Some(uri) = uri {
            buffer["uri"] = json!(uri);
        }
        doc["buffers"] = json!([buffer]);
        doc["bufferViews"] = json!(self.views);
        doc["accessors"] = json!(self.accessors);
        doc
    }

    /// Writes `dir/name.gltf` + `dir/name.bin`; returns the .gltf path.
    pub fn write_gltf(&self, dir: &Path, name: &str, rest: Value) -> PathBuf {
        let bin = format!("{name}.bin");
        std::fs::write(dir.join(&bin), &self.bin).unwrap();
        let path = dir.join(format!("{name}.gltf"));
        std::fs::write(
            &path,
            serde_json::to_string_pretty(&self.document(rest, Some(&bin))).unwrap(),
        )
        .unwrap();
        path
    }

    /// The GLB bytes of the document with the buffer embedded.
    pub fn glb(&self, rest: Value) -> Vec<u8> {
        let mut json = serde_json::to_vec(&self.document(rest, None)).unwrap();
        while !json.len().is_multiple_of(4) {
            json.push(b' ');
        }
        let mut bin = self.bin.clone();
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        let total = 12 + 8 + json.len() + 8 + bin.len();
        let mut out = Vec::new();
        out.extend_from_slice(b"glTF");
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&(total as u32).to_le_bytes());
        out.extend_from_slice(&(json.len() as u32).to_le_bytes());
        out.extend_from_slice(b"JSON");
        out.extend_from_slice(&json);
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&bin);
        out
    }
}

/// A square [−1, 1]² in the z = 0 plane facing +z, uv (0, 0) at the top-left (−1, 1) corner and
/// (1, 1) at the bottom-right: mesh JSON for `material` (or none), optionally with normals.
pub fn square(b: &mut GltfBuilder, with_normals: bool, material: Option<usize>) -> Value {
    let positions = [-1.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0, -1.0, 0.0, -1.0, -1.0, 0.0];
    let uvs = [0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0];
    let mut attributes = json!({"POSITION": b.floats("VEC3", &positions), "TEXCOORD_0": b.floats("VEC2", &uvs)});
    if with_normals {
        attributes["NORMAL"] = json!(b.floats("VEC3", &[0.0, 0.0, 1.0].repeat(4)));
    }
    let mut primitive = json!({"attributes": attributes, "indices": b.indices(&[0, 3, 2, 0, 2, 1])});
    if let Some(m) = material {
        primitive["material"] = json!(m);
    }
    json!({"primitives": [primitive]})
}

/// Writes a `w×h` RGBA PNG.
pub fn write_png(path: &Path, w: u32, h: u32, texels: &[[u8; 4]]) {
    let raw: Vec<u8> = texels.iter().flatten().copied().collect();
    image::RgbaImage::from_raw(w, h, raw).unwrap().save(path).unwrap();
}
