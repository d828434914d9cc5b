//! Helpers shared by the integration test modules (each uses some of them): running the binary
//! and checking its refusals (`cli`), scratch folders (`scratch`), glTF files (`gltf_builder`),
//! rendering a scene in-process, the shipped scenes and the shared test data.

#![allow(dead_code)]

pub mod cli;
pub mod gltf_builder;
pub mod scratch;

pub use cli::{assert_input_error, assert_one_line_error, command, pointshade};
pub use scratch::Scratch;

use std::path::{Path, PathBuf};

use pointshade::plan::{Aov, RenderPlan};
use pointshade::render::{render_scene, Rendered};
use pointshade::scene::Scene;

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
    let stem = scene.file_stem().unwrap().to_string_lossy();
    let dir = Scratch::new(&format!("render-png-{stem}"));
    let out = dir.path("out.png");
    let r = command()
        .arg("render")
        .arg(scene)
        .arg("-o")
        .arg(&out)
        .arg("--quiet")
        .args(extra)
        .output()
        .unwrap();
    assert!(r.status.success(), "{scene:?}: {}", String::from_utf8_lossy(&r.stderr));
    image::open(&out).unwrap().into_rgb8()
}

/// Shipped scene `scenes/<name>` at `width`×`height` with `sampler` at `spp`.
pub fn shipped_scene(
    name: &str,
    (width, height): (u32, u32),
    sampler: pointshade::film::SamplerKind,
    spp: u32,
) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(name);
    let mut s = pointshade::scene::load(&path).unwrap();
    s.film.width = width;
    s.film.height = height;
    s.film.sampler = sampler;
    s.film.spp = spp;
    s
}

/// Plans `scene` with `aovs` and renders it in-process, as `pointshade render` does (the BVH
/// the plan asks for, no progress output); panics if the render fails.
#[track_caller]
pub fn render(scene: &Scene, aovs: &[Aov]) -> Rendered {
    try_render(scene, aovs).unwrap_or_else(|e| panic!("the render failed: {e}"))
}

/// [`render`], returning the error: for tests to which a refused render is a fine outcome.
pub fn try_render(scene: &Scene, aovs: &[Aov]) -> Result<Rendered, String> {
    render_scene(scene, &RenderPlan::new(scene, aovs), &|_| {})
}
