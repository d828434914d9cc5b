//! Whole-pipeline render time (surface points + shading) per scene, medians of several runs.
//!
//! `cargo bench --bench render` prints one row per scene: the BVH is built once, then the scene
//! is rendered through `pointshade::render::render` with its real plan, at 512×512 and 1 spp
//! (`--quick`: 1 run instead of 5). The surface and shading columns are summed over threads, as
//! the CLI reports them. Scenes from ../shared/data are skipped with a warning when it is absent.

mod common;

use common::median;
use std::path::{Path, PathBuf};
use std::time::Instant;

use pointshade::accel::Bvh;
use pointshade::plan::RenderPlan;
use pointshade::render::render;
use pointshade::scene;

const SIZE: u32 = 512;

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let runs = if quick { 1 } else { 5 };
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let shared = root.join("../shared/data");
    let scenes: Vec<PathBuf> = vec![
        shared.join("meshes/stanford-dragon.obj"),
        root.join("scenes/cook-torrance.toml"),
        shared.join("gltf/DamagedHelmet/glTF-Binary/DamagedHelmet.glb"),
        shared.join("gltf/MetalRoughSpheresNoTextures/glTF-Binary/MetalRoughSpheresNoTextures.glb"),
    ];
    println!(
        "{SIZE}x{SIZE}, 1 spp, {} thread(s); medians of {runs} run(s)",
        rayon::current_num_threads()
    );
    println!(
        "{:<34} {:>9} {:>11} {:>11} {:>9} {:>12}",
        "scene", "triangles", "surface ms", "shading ms", "wall ms", "Msamples/s"
    );
    for path in scenes {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let mut scene = match scene::load(&path) {
            Ok(s) => s,
            Err(e) => {
                eprintln!("WARNING: skipping {name}: {e}");
                continue;
            }
        };
        scene.film.width = SIZE;
        scene.film.height = SIZE;
        scene.film.spp = 1;
        let plan = RenderPlan::new(&scene, &[]);
        let bvh = Bvh::for_scene(&scene);
        let (mut surface, mut shading, mut wall) = (Vec::new(), Vec::new(), Vec::new());
        for _ in 0..runs {
            let t = Instant::now();
            let r = render(&scene, &plan, Some(&bvh), &pointshade::render::progress::Silent).expect("renders");
            wall.push(t.elapsed().as_secs_f64() * 1e3);
            surface.push(r.stats.surface_time.as_secs_f64() * 1e3);
            shading.push(r.stats.shading_time.as_secs_f64() * 1e3);
            std::hint::black_box(r.image);
        }
        let wall = median(wall);
        println!(
            "{:<34} {:>9} {:>11.1} {:>11.1} {:>9.1} {:>12.2}",
            name,
            scene.mesh.triangle_count(),
            median(surface),
            median(shading),
            wall,
            (SIZE * SIZE) as f64 / wall / 1e3
        );
    }
}
