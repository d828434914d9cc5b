//! What the fuzz targets share: a scratch folder for the files a loader reads (loaders take
//! paths, and an MTL, a glTF buffer or a scene's mesh is found beside its file), and the tiny
//! render every accepted input goes through, so that what a loader accepts the BVH builder and
//! the renderer survive too.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use pointshade::plan::{Aov, RenderPlan};
use pointshade::render::options::{RenderOptions, Spelling};
use pointshade::scene::Scene;

/// This process's scratch folder (in memory where /dev/shm exists), made once.
pub fn scratch() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let base = if Path::new("/dev/shm").is_dir() {
            PathBuf::from("/dev/shm")
        } else {
            std::env::temp_dir()
        };
        let dir = base.join(format!("pointshade-fuzz-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("a scratch folder");
        dir
    })
}

/// Writes `bytes` to `name` in the scratch folder; returns its path.
pub fn put(name: &str, bytes: &[u8]) -> PathBuf {
    let path = scratch().join(name);
    std::fs::write(&path, bytes).expect("a scratch file");
    path
}

/// Splits `data` at the first `sep` line: (before, after). Lets one input hold two files.
pub fn split<'a>(data: &'a [u8], sep: &[u8]) -> (&'a [u8], &'a [u8]) {
    match data.windows(sep.len()).position(|w| w == sep) {
        Some(at) => (&data[..at], &data[at + sep.len()..]),
        None => (data, &[]),
    }
}

/// Renders `scene` at 4×3 pixels, one sample, with every AOV: an error is fine (a film the
/// scene cannot have), a panic or a non-finite pixel is a finding.
pub fn tiny_render(mut scene: Scene) {
    let options = RenderOptions {
        width: Some(4),
        height: Some(3),
        spp: Some(1),
        ..RenderOptions::default()
    };
    if options.apply(&mut scene, Spelling::Keyword).is_err() {
        return;
    }
    scene.film.time_budget = None;
    let plan = RenderPlan::new(&scene, &Aov::ALL);
    if let Ok(rendered) = pointshade::render::render_scene(&scene, &plan, &pointshade::render::progress::Silent) {
        assert_finite(&rendered.image, "image");
        for (aov, image) in &rendered.aovs {
            assert_finite(image, aov.name());
        }
    }
}

/// Panics (a finding) if `image` has a NaN or infinite pixel.
pub fn assert_finite(image: &pointshade::film::Image, what: &str) {
    if let Some((x, y, v)) = image.first_non_finite() {
        panic!("{what}: pixel ({x}, {y}) is {v}");
    }
}
