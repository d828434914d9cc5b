//! Renders of the large models in ../shared/data: bare meshes and scene files that use them.
//! Without ../shared/data these tests are ignored ("needs ../shared/data"); CI always has it.

use crate::support;

use std::path::{Path, PathBuf};

use support::render_png as render;

fn shared() -> PathBuf {
    support::shared_data("meshes")
}

/// Share of pixels that are not black.
fn coverage(img: &image::RgbImage) -> f64 {
    img.pixels().filter(|p| p.0 != [0, 0, 0]).count() as f64 / (img.width() * img.height()) as f64
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn bare_bunny_and_dragon_render_framed_and_lit() {
    let dir = shared();
    for name in ["stanford-bunny.obj", "stanford-dragon.obj"] {
        let img = render(&dir.join(name), &["--width", "160", "--height", "120", "--spp", "1"]);
        assert_eq!(img.dimensions(), (160, 120));
        let c = coverage(&img);
        // Framed: the model fills a good part of the picture but is not cut off at the borders.
        assert!((0.15..0.8).contains(&c), "{name}: coverage {c}");
        let border_lit = (0..160).any(|x| img.get_pixel(x, 0).0 != [0, 0, 0] || img.get_pixel(x, 119).0 != [0, 0, 0]);
        assert!(!border_lit, "{name}: the model touches the top or bottom border");
    }
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn scene_files_using_shared_meshes_render() {
    shared();
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/shared");
    for name in ["dragon-copper.toml", "bunny-blinn-phong.toml"] {
        let img = render(&scenes.join(name), &["--width", "128", "--height", "128", "--spp", "1"]);
        let c = coverage(&img);
        assert!(c > 0.3, "{name}: coverage {c}");
    }
}
