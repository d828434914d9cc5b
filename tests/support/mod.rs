//! Helpers shared by integration tests (each test crate uses some of them).

#![allow(dead_code)]

pub mod gltf_builder;

use std::path::{Path, PathBuf};
use std::process::Command;

/// `../shared/data/<sub>` if it exists; otherwise prints SKIPPED (the caller then returns).
pub fn shared_data(sub: &str) -> Option<PathBuf> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data").join(sub);
    if p.is_dir() {
        Some(p)
    } else {
        eprintln!(
            "SKIPPED: {} is missing; this test needs the shared test data",
            p.display()
        );
        None
    }
}

/// Renders `scene` with the CLI (`--quiet` and `extra`) into a temporary PNG; returns the
/// decoded image.
pub fn render_png(scene: &Path, extra: &[&str]) -> image::RgbImage {
    let out = std::env::temp_dir().join(format!(
        "pointshade-shared-{}-{}.png",
        std::process::id(),
        scene.file_stem().unwrap().to_string_lossy()
    ));
    let r = Command::new(env!("CARGO_BIN_EXE_pointshade"))
        .arg("render")
        .arg(scene)
        .arg("-o")
        .arg(&out)
        .arg("--quiet")
        .args(extra)
        .output()
        .unwrap();
    assert!(r.status.success(), "{scene:?}: {}", String::from_utf8_lossy(&r.stderr));
    let img = image::open(&out).unwrap().into_rgb8();
    let _ = std::fs::remove_file(out);
    img
}

/// Shipped scene `scenes/<name>` at `width`×`height` with `sampler` at `spp`.
pub fn shipped_scene(
    name: &str,
    (width, height): (u32, u32),
    sampler: pointshade::film::SamplerKind,
    spp: u32,
) -> pointshade::scene::Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(name);
    let mut s = pointshade::scene::load(&path).unwrap();
    s.film.width = width;
    s.film.height = height;
    s.film.sampler = sampler;
    s.film.spp = spp;
    s
}
