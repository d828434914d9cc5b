//! BVH build time and primary/shadow ray throughput on the Stanford dragon, per obvhs preset.
//!
//! `cargo bench --bench rays` prints a table (medians of 9 runs after one warm-up run; `--quick`:
//! 1 run, two presets).
//! Rays are traced through the real pipeline pieces: the automatic camera, `Bvh::intersect`
//! for primary rays, and the shader's shadow-ray construction + `Bvh::any_hit`.

mod common;

use common::median;
use std::path::Path;
use std::time::{Duration, Instant};

use glam::Vec3;
use rayon::prelude::*;

use pointshade::accel::{Bvh, BvhPreset};
use pointshade::scene::framing::{default_lights, frame_bounds};
use pointshade::scene::mesh::TriangleMesh;
use pointshade::scene::obj::load_obj;
use pointshade::shading::light::LightKind;
use pointshade::shading::shadow::ShadowRay;
use pointshade::surface::camera::Camera;

const SIZE: u32 = 512;

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let dragon = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/meshes/stanford-dragon.obj");
    let (mesh, what) = if dragon.is_file() {
        (load_obj(&dragon).expect("dragon loads").mesh, "stanford-dragon.obj")
    } else {
        eprintln!(
            "WARNING: {} missing: benchmarking a procedural torus instead",
            dragon.display()
        );
        (torus(), "procedural torus")
    };
    let (lo, hi) = mesh.bounds().unwrap();
    let spec = frame_bounds(lo, hi);
    let camera = Camera::new(spec, SIZE, SIZE).unwrap();
    let light = match default_lights(lo, hi, &spec)[0].kind {
        LightKind::Point { position } => position,
        _ => unreachable!(),
    };
    let runs = if quick { 1 } else { 9 };
    let presets: &[BvhPreset] = if quick {
        &[BvhPreset::Fast, BvhPreset::Medium]
    } else {
        &BvhPreset::ALL
    };
    let threads = rayon::current_num_threads();
    println!(
        "{what}: {} triangles, {SIZE}x{SIZE} primary rays (1 spp), one point light; medians of {runs} run(s)",
        mesh.triangle_count()
    );
    println!(
        "{:<8} {:>10} {:>8} {:>16} {:>16} {:>16} {:>16}",
        "preset",
        "build ms",
        "nodes",
        "primary Mray/s 1t",
        format!("primary Mray/s {threads}t"),
        "shadow Mray/s 1t",
        format!("shadow Mray/s {threads}t")
    );
    for &preset in presets {
        let mut build = Vec::new();
        let mut bvh = None;
        for _ in 0..runs {
            let b = Bvh::build(&mesh, preset);
            build.push(b.build_time.as_secs_f64() * 1e3);
            bvh = Some(b);
        }
        let bvh = bvh.unwrap();
        let rays: Vec<(Vec3, Vec3, f32)> = (0..SIZE * SIZE)
            .map(|i| {
                let r = camera.ray(
                    ((i % SIZE) as f32 + 0.5) / SIZE as f32,
                    ((i / SIZE) as f32 + 0.5) / SIZE as f32,
                );
                (r.origin, r.direction, r.t_max)
            })
            .collect();
        let hits: Vec<(Vec3, Vec3)> = rays
            .iter()
            .filter_map(|&(o, d, t)| {
                bvh.intersect(o, d, t).map(|h| {
                    let [p0, p1, p2] = mesh.triangle_positions(h.triangle as usize);
                    let p = (1.0 - h.b1 - h.b2) * p0 + h.b1 * p1 + h.b2 * p2;
                    (p, (p1 - p0).cross(p2 - p0).normalize_or_zero())
                })
            })
            .collect();
        let shadow: Vec<ShadowRay> = hits
            .iter()
            .map(|&(p, n)| {
                let to = light - p;
                ShadowRay::towards_light(p, n, to.normalize(), to.length(), bvh.scene_unit())
            })
            .collect();
        let rate = |n: usize, d: Duration| n as f64 / d.as_secs_f64() / 1e6;
        let time = |f: &dyn Fn() -> usize| {
            // One untimed run first: the clock ramps up and caches fill.
            std::hint::black_box(f());
            median(
                (0..runs)
                    .map(|_| {
                        let t = Instant::now();
                        std::hint::black_box(f());
                        t.elapsed().as_secs_f64()
                    })
                    .collect(),
            )
        };
        let primary_1t = time(&|| {
            rays.iter()
                .filter(|&&(o, d, t)| bvh.intersect(o, d, t).is_some())
                .count()
        });
        let primary_nt = time(&|| {
            rays.par_iter()
                .filter(|&&(o, d, t)| bvh.intersect(o, d, t).is_some())
                .count()
        });
        let shadow_1t = time(&|| {
            shadow
                .iter()
                .filter(|r| bvh.any_hit(r.origin, r.direction, r.t_max))
                .count()
        });
        let shadow_nt = time(&|| {
            shadow
                .par_iter()
                .filter(|r| bvh.any_hit(r.origin, r.direction, r.t_max))
                .count()
        });
        let d = Duration::from_secs_f64;
        println!(
            "{:<8} {:>10.1} {:>8} {:>16.2} {:>16.2} {:>16.2} {:>16.2}",
            preset.name(),
            median(build),
            bvh.node_count(),
            rate(rays.len(), d(primary_1t)),
            rate(rays.len(), d(primary_nt)),
            rate(shadow.len(), d(shadow_1t)),
            rate(shadow.len(), d(shadow_nt)),
        );
    }
}

fn torus() -> TriangleMesh {
    let g = pointshade::scene::procedural::torus(1.0, 0.35, 400, 125);
    let normals = g.normals.expect("the torus has analytic normals");
    TriangleMesh {
        material_of_triangle: vec![0; g.triangles.len()],
        positions: g.positions,
        normals,
        triangles: g.triangles,
        ..Default::default()
    }
}
