//! Helpers shared by integration tests (each test crate uses some of them).

#![allow(dead_code)]

pub mod gltf_builder;

use std::path::{Path, PathBuf};
use std::process::Command;

/// `../shared/data/<sub>`. Tests that call it carry
/// `#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]` (build.rs sets the cfg), so
/// they run only where the data is; a folder missing from the data then fails the test.
pub fn shared_data(sub: &str) -> PathBuf {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data").join(sub);
    assert!(p.is_dir(), "{} is missing from the shared test data", p.display());
    p
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
