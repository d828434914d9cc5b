//! Never a panic on a malformed glTF: a small glTF that uses most of what the loader reads (a
//! textured, normal-mapped, emissive, cut-out material with a texture transform, a camera,
//! point and spot lights, a node hierarchy) is mutated many times — a value replaced by one of
//! a list of troublesome ones (out-of-range indices, NaN-like overflows, wrong types, zero,
//! negative and huge numbers) or a key removed, and one in five with its binary buffer or an
//! image corrupted — and each mutant is loaded and, when it loads,
//! rendered at 8×8. Either is fine; a panic, or a non-finite pixel, is not. Deterministic: the seed is fixed, so a
//! failure names a mutant that reproduces (`POINTSHADE_MUTATION_SEED=n` explores others). (A wider run of the same idea over the shared assets
//! found the out-of-range POSITION accessor that `tests/integration/bad_input.rs` now checks.)

use crate::support;

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

use serde_json::{json, Value};

use pointshade::scene;
use support::gltf_builder::{square, write_png, GltfBuilder};
use support::Scratch;

/// The document's JSON besides buffers and accessors; the builder holds the binary data.
fn document() -> (GltfBuilder, Value) {
    let mut b = GltfBuilder::default();
    let mesh = square(&mut b, true, Some(0));
    let texture = |index: usize| json!({"index": index});
    let mut base = texture(0);
    base["extensions"] = json!({"KHR_texture_transform": {"offset": [0.1, 0.0], "rotation": 0.3, "scale": [2.0, 1.0]}});
    let material = json!({
        "pbrMetallicRoughness": {
            "baseColorFactor": [1.0, 0.8, 0.6, 1.0],
            "baseColorTexture": base,
            "metallicFactor": 0.5,
            "roughnessFactor": 0.4,
            "metallicRoughnessTexture": texture(1)
        },
        "normalTexture": {"index": 1, "scale": 0.8},
        "emissiveTexture": texture(0),
        "emissiveFactor": [0.2, 0.1, 0.0],
        "alphaMode": "MASK",
        "alphaCutoff": 0.3,
        "doubleSided": true,
        "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 2.0}}
    });
    let rest = json!({
        "scenes": [{"nodes": [0, 2]}],
        "nodes": [
            {"mesh": 0, "children": [1], "rotation": [0.0, 0.0, 0.0, 1.0]},
            {"camera": 0, "translation": [0.0, 0.0, 4.0]},
            {"children": [3, 4], "scale": [1.0, 1.0, 1.0]},
            {"translation": [1.0, 1.0, 2.0], "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"translation": [-1.0, 0.0, 2.0], "extensions": {"KHR_lights_punctual": {"light": 1}}}
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.01, "aspectRatio": 1.0}}],
        "meshes": [mesh],
        "materials": [material],
        "images": [{"uri": "a.png"}, {"uri": "b.png"}],
        "samplers": [{"magFilter": 9729, "wrapS": 33648, "wrapT": 10497}],
        "textures": [{"source": 0, "sampler": 0}, {"source": 1}],
        "extensionsUsed": ["KHR_lights_punctual", "KHR_texture_transform", "KHR_materials_emissive_strength"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "point", "intensity": 20.0, "range": 10.0},
            {"type": "spot", "intensity": 30.0, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}}
        ]}}
    });
    (b, rest)
}

/// Values that have broken loaders: indices just past the end and far past it, overflowing
/// and negative numbers, zero, wrong types, enums out of their set.
fn troublesome() -> Vec<Value> {
    vec![
        json!(null),
        json!(-1),
        json!(0),
        json!(7),
        json!(2147483648u64),
        json!(4294967295u64),
        json!(1e39),
        json!(-1e39),
        json!(1.5),
        json!("x"),
        json!([]),
        json!({}),
        json!([0.0, 0.0, 0.0, 0.0]),
        json!([1e30, 1e30, 1e30]),
        json!(5126),
        json!("BLEND"),
        json!({"index": 9, "texCoord": 7}),
    ]
}

/// Every path (keys and array positions) in `v`.
fn paths(v: &Value, prefix: &mut Vec<PathStep>, out: &mut Vec<Vec<PathStep>>) {
    let mut visit = |step: PathStep, child: &Value| {
        prefix.push(step);
        out.push(prefix.clone());
        paths(child, prefix, out);
        prefix.pop();
    };
    match v {
        Value::Object(map) => map.iter().for_each(|(k, c)| visit(PathStep::Key(k.clone()), c)),
        Value::Array(items) => items.iter().enumerate().for_each(|(i, c)| visit(PathStep::Index(i), c)),
        _ => {}
    }
}

#[derive(Clone, Debug)]
enum PathStep {
    Key(String),
    Index(usize),
}

/// The value at `path`.
fn lookup<'v>(doc: &'v Value, path: &[PathStep]) -> &'v Value {
    path.iter().fold(doc, |v, step| match step {
        PathStep::Key(k) => &v[k.as_str()],
        PathStep::Index(i) => &v[*i],
    })
}

/// Replaces the value at `path` (or removes it, for object keys when `remove`).
fn mutate(doc: &mut Value, path: &[PathStep], replacement: Value, remove: bool) {
    let (last, parent_path) = path.split_last().unwrap();
    let mut parent = doc;
    for step in parent_path {
        parent = match step {
            PathStep::Key(k) => &mut parent[k.as_str()],
            PathStep::Index(i) => &mut parent[*i],
        };
    }
    match (last, parent) {
        (PathStep::Key(k), Value::Object(map)) if remove => {
            map.remove(k);
        }
        (PathStep::Key(k), p) => p[k.as_str()] = replacement,
        (PathStep::Index(i), p) => p[*i] = replacement,
    }
}

/// SplitMix64: a fixed, dependency-free sequence.
struct Rng(u64);

impl Rng {
    fn below(&mut self, n: usize) -> usize {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) % n as u64) as usize
    }
}

/// Loads `path` and, if it loads, renders it at 8×8 with one sample per pixel (and panics on a
/// non-finite pixel); returns whether it loaded.
fn load_and_render(path: &Path) -> bool {
    let Ok(mut scene) = scene::load(path) else {
        return false;
    };
    scene.film.width = 8;
    scene.film.height = 8;
    scene.film.spp = 1;
    scene.film.time_budget = None;
    if let Ok(rendered) = support::try_render(&scene, &[]) {
        // NaN never reaches a pixel, whatever finite data the loader let through.
        assert!(
            rendered.image.pixels.iter().all(|p| p.is_finite()),
            "a non-finite pixel"
        );
    }
    true
}

const CASES: usize = 1000;

#[test]
fn mutated_gltf_files_load_or_fail_without_panicking() {
    let dir = Scratch::new("mutations");
    write_png(
        &dir.join("a.png"),
        2,
        2,
        &[[255, 0, 0, 128], [0, 255, 0, 255], [0, 0, 255, 0], [9, 9, 9, 255]],
    );
    write_png(&dir.join("b.png"), 1, 1, &[[128, 128, 255, 255]]);
    let (b, rest) = document();
    let original = b.document(rest.clone(), Some("m.bin"));
    b.write_gltf(&dir, "m", rest);
    // The unmutated file loads and renders: the mutants start from a working document.
    let path = dir.join("m.gltf");
    scene::load(&path).expect("the unmutated document loads");
    let files: Vec<_> = ["m.bin", "a.png", "b.png"]
        .iter()
        .map(|f| (dir.join(f), std::fs::read(dir.join(f)).unwrap()))
        .collect();
    let values = troublesome();
    // POINTSHADE_MUTATION_SEED=n explores other mutants (CI uses the fixed default).
    let seed = std::env::var("POINTSHADE_MUTATION_SEED").map_or(7, |s| s.parse().expect("a u64 seed"));
    let mut rng = Rng(seed);
    let (mut failures, mut loaded) = (Vec::new(), 0);
    for case in 0..CASES {
        let mut doc = original.clone();
        let mut applied = Vec::new();
        for _ in 0..1 + usize::from(rng.below(4) == 0) {
            let mut all = Vec::new();
            paths(&doc, &mut Vec::new(), &mut all);
            let path = &all[rng.below(all.len())];
            // Numbers mostly get other numbers, so that many mutants still load and render.
            let current = lookup(&doc, path);
            let value = match (current.as_u64(), current.as_f64()) {
                (Some(n), _) if rng.below(4) > 0 => {
                    let near = [0, 1, n + 1, n + 1000, 1 << 31, u64::from(u32::MAX)];
                    json!(near[rng.below(near.len())])
                }
                (None, Some(x)) if rng.below(4) > 0 => {
                    let near = [0.0, -1.0, -x, x * 1e3, 1e30, -1e30, 0.5, 1e-30];
                    json!(near[rng.below(near.len())])
                }
                _ => values[rng.below(values.len())].clone(),
            };
            let remove = rng.below(5) == 0 && matches!(path.last(), Some(PathStep::Key(_)));
            applied.push(format!(
                "{path:?} {}",
                if remove { "removed".into() } else { value.to_string() }
            ));
            mutate(&mut doc, path, value, remove);
        }
        std::fs::write(&path, serde_json::to_vec(&doc).unwrap()).unwrap();
        // One case in five also gets a corrupted binary buffer or image: bytes overwritten
        // (vertex data becomes NaN, infinite or huge; indices run past the end) or cut short.
        let (file, original_bytes) = &files[rng.below(files.len())];
        let corrupt = rng.below(5) == 0;
        if corrupt {
            let mut bytes = original_bytes.clone();
            if rng.below(2) == 0 {
                bytes.truncate(rng.below(bytes.len()));
            } else {
                for _ in 0..1 + rng.below(16) {
                    let at = rng.below(bytes.len());
                    bytes[at] = rng.below(256) as u8;
                }
            }
            applied.push(format!("{} corrupted", file.display()));
            std::fs::write(file, bytes).unwrap();
        }
        match catch_unwind(AssertUnwindSafe(|| load_and_render(&path))) {
            Ok(ok) => loaded += usize::from(ok),
            Err(_) => failures.push(format!("case {case}: {}", applied.join("; "))),
        }
        if corrupt {
            std::fs::write(file, original_bytes).unwrap();
        }
    }
    drop(dir);
    assert!(failures.is_empty(), "panics:\n{}", failures.join("\n"));
    // Both outcomes are exercised: mutants that still load (and are rendered) and ones refused.
    eprintln!("{loaded} of {CASES} mutants loaded and rendered, the rest were refused");
    assert!(
        (CASES / 10..=CASES * 9 / 10).contains(&loaded),
        "{loaded} of {CASES} loaded"
    );
}
