//! BVH build time and primary/shadow ray throughput on the Stanford dragon, per build preset
//! (obvhs's four and pointshade's binned SAH, the default).
//!
//! `cargo bench --bench rays` prints a table (medians of 9 runs of 4 passes each, after one warm-up
//! pass; `--quick`: 1 run, two presets).
//! Rays are traced through the real pipeline pieces: the automatic camera, `Bvh::intersect`
//! for primary rays, and the shader's shadow-ray construction + `Bvh::any_hit`, in the order the
//! renderer traces them (16×16 tiles row by row, pixels in 4×4 blocks within a tile), one by one.
//! Two more tables compare, for the default tree, primary and shadow rays traced one by one and as
//! the renderer traces them: the samples of each 4×4 pixel block in packets of up to 16 rays
//! (`Bvh::intersect_packet`, `Bvh::any_hit_packet`, which walk the tree as one packet from 12
//! rays on), at 1, 4, 9 and 16 samples per pixel.

mod common;

use common::median;
use std::path::Path;
use std::time::Instant;

use glam::Vec3;
use rayon::prelude::*;

use pointshade::accel::packet::PACKET;
use pointshade::accel::shadow::ShadowRay;
use pointshade::accel::{Bvh, BvhPreset, Hit};
use pointshade::film::PixelRect;
use pointshade::light::LightKind;
use pointshade::render::tile::{block_order, pixel_block};
use pointshade::render::tiles;
use pointshade::scene::camera::Camera;
use pointshade::scene::framing::{default_lights, frame_bounds};
use pointshade::scene::mesh::TriangleMesh;
use pointshade::scene::obj::load_obj;

const SIZE: u32 = 512;
/// Passes over the ray set per timed run.
const PASSES: u32 = 4;

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
        &[BvhPreset::Fast, BvhPreset::DEFAULT]
    } else {
        &BvhPreset::ALL
    };
    let threads = rayon::current_num_threads();
    println!(
        "{what}: {} triangles, {SIZE}x{SIZE} primary rays (1 spp), one point light, tile order; medians of {runs} run(s) of {PASSES} passes",
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
    // Build every preset's tree and ray sets first, then time them round-robin: a slow spell of
    // the (shared) machine then slows every preset alike instead of one preset's whole row.
    let cases: Vec<Case> = presets
        .iter()
        .map(|&preset| Case::new(&mesh, &camera, light, preset, runs))
        .collect();
    for case in &cases {
        std::hint::black_box(case.primary(false) + case.shadow(false)); // warm-up
    }
    let mut seconds = vec![[(); 4].map(|_| Vec::new()); cases.len()];
    for _ in 0..runs {
        for (case, s) in cases.iter().zip(&mut seconds) {
            for (k, parallel) in [false, true].into_iter().enumerate() {
                s[k].push(time_passes(|| case.primary(parallel)));
                s[2 + k].push(time_passes(|| case.shadow(parallel)));
            }
        }
    }
    let packets = PixelPackets::new(&mesh, &cases, light, runs);
    for (case, s) in cases.iter().zip(seconds) {
        let [p1, pn, s1, sn] = s.map(median);
        let rate = |n: usize, seconds: f64| n as f64 / seconds / 1e6;
        println!(
            "{:<8} {:>10.1} {:>8} {:>16.2} {:>16.2} {:>16.2} {:>16.2}",
            case.preset.name(),
            case.build_ms,
            case.bvh.node_count(),
            rate(case.rays.len(), p1),
            rate(case.rays.len(), pn),
            rate(case.shadow_rays.len(), s1),
            rate(case.shadow_rays.len(), sn),
        );
    }
    if let Some(packets) = packets {
        packets.print(threads);
    }
}

/// Primary rays and the shadow rays of their hits, grouped as the renderer groups them (the
/// samples of a 4×4 pixel block, up to 16 rays at a time: at 1 sample per pixel a whole block, at
/// 16 one pixel): the same rays traced one by one and as packets (`Bvh::intersect_packet`,
/// `Bvh::any_hit_packet`, one call per group), timed alternately in one process, for 1 sample
/// per pixel (the top table's 512×512 image) and 4, 9 and 16 (n×n grids, 256×256 pixels).
struct PixelPackets {
    /// Per grid size n: image side, and the primary and the shadow rays' timings.
    rows: Vec<(u32, u32, [Timed; 2])>,
    runs: usize,
}

/// Pixels per side of the packet bench's multi-sample images (16 samples each: ~1M rays).
const PACKET_SIZE: u32 = 256;

impl PixelPackets {
    fn new(mesh: &TriangleMesh, cases: &[Case], light: Vec3, runs: usize) -> Option<Self> {
        let case = cases.iter().find(|c| c.preset == BvhPreset::DEFAULT)?;
        let bvh = &case.bvh;
        let (lo, hi) = mesh.bounds()?;
        let mut rows = Vec::new();
        for grid in [1u32, 2, 3, 4] {
            let size = if grid == 1 { SIZE } else { PACKET_SIZE };
            let camera = Camera::new(frame_bounds(lo, hi), size, size).ok()?;
            let groups = grid_rays(&camera, size, grid);
            let pixels: Vec<&[Segment]> = groups.iter().map(Vec::as_slice).collect();
            let shadow: Vec<Vec<Segment>> = pixels
                .iter()
                .map(|pixel| {
                    let hits = pixel.iter().filter_map(|&(o, d, t)| bvh.intersect(o, d, t));
                    hits.map(|h| {
                        let r = shadow_ray(mesh, bvh, &h, light);
                        (r.origin, r.direction, r.t_max)
                    })
                    .collect()
                })
                .collect();
            let shadow: Vec<&[Segment]> = shadow.iter().map(Vec::as_slice).collect();
            let primary_seconds = alternate(runs, |packets, parallel| {
                per_group(&pixels, parallel, |rays| count_hits(bvh, rays, packets))
            });
            let shadow_seconds = alternate(runs, |packets, parallel| {
                per_group(&shadow, parallel, |rays| count_blocked(bvh, rays, packets))
            });
            let count = |groups: &[&[Segment]]| groups.iter().map(|g| g.len()).sum();
            rows.push((
                grid,
                size,
                [(count(&pixels), primary_seconds), (count(&shadow), shadow_seconds)],
            ));
        }
        Some(Self { rows, runs })
    }

    fn print(&self, threads: usize) {
        for (k, what) in ["primary rays", "shadow rays of their hits"].into_iter().enumerate() {
            println!(
                "\nn x n samples per pixel in groups of up to {PACKET} rays, preset {}, {what} (M/s); medians of {} run(s)",
                BvhPreset::DEFAULT.name(),
                self.runs
            );
            println!(
                "{:<22} {:>14} {:>14} {:>14} {:>14}",
                "samples per pixel",
                "single 1t",
                "packet 1t",
                format!("single {threads}t"),
                format!("packet {threads}t")
            );
            for &(grid, size, kinds) in &self.rows {
                let (rays, seconds) = kinds[k];
                let [s1, p1, sn, pn] = seconds.map(|s| rays as f64 / s / 1e6);
                let label = format!("{} ({size}x{size})", grid * grid);
                println!("{label:<22} {s1:>14.2} {p1:>14.2} {sn:>14.2} {pn:>14.2}");
            }
        }
    }
}

/// A ray count and its seconds per pass [one by one 1t, packets 1t, one by one all threads,
/// packets all threads].
type Timed = (usize, [f64; 4]);

/// A ray as the packet calls take it: origin, unit direction, t_max.
type Segment = (Vec3, Vec3, f32);

/// Median seconds of `work(packets, parallel)` over `runs` runs, as [one by one 1t, packets 1t,
/// one by one all threads, packets all threads]. Each run times A B B A: whichever runs first
/// after the other thread count is slower (by ~15% here, even for identical code), so each gets
/// one early and one late slot and the run's value is their mean.
fn alternate(runs: usize, work: impl Fn(bool, bool) -> usize) -> [f64; 4] {
    std::hint::black_box(work(true, false)); // warm-up
    let mut all = [(); 4].map(|_| Vec::new());
    for _ in 0..runs {
        for parallel in [false, true] {
            let mut seconds = [0.0; 2];
            for packets in [false, true, true, false] {
                let t = Instant::now();
                std::hint::black_box(work(packets, parallel));
                seconds[packets as usize] += t.elapsed().as_secs_f64() / 2.0;
            }
            for (packets, s) in seconds.into_iter().enumerate() {
                all[2 * parallel as usize + packets].push(s);
            }
        }
    }
    all.map(median)
}

/// `grid`² rays per pixel on a grid inside it, in the renderer's order and groups: tiles row by
/// row, each tile's pixels block by block, each block's rays in chunks of up to [`PACKET`].
fn grid_rays(camera: &Camera, size: u32, grid: u32) -> Vec<Vec<Segment>> {
    let (side, g) = (size as f32, grid as f32);
    let ray = |x: u32, y: u32, k: u32| {
        let (jx, jy) = (((k % grid) as f32 + 0.5) / g, ((k / grid) as f32 + 0.5) / g);
        let r = camera.ray((x as f32 + jx) / side, (y as f32 + jy) / side);
        (r.origin, r.direction, r.t_max)
    };
    let mut groups = Vec::new();
    for tile in tiles(PixelRect::full(size, size)) {
        let pixels: Vec<(u32, u32)> = block_order(tile).collect();
        for block in pixels.chunk_by(|a, b| pixel_block(a.0, a.1) == pixel_block(b.0, b.1)) {
            let rays: Vec<Segment> = block
                .iter()
                .flat_map(|&(x, y)| (0..grid * grid).map(move |k| ray(x, y, k)))
                .collect();
            groups.extend(rays.chunks(PACKET).map(<[Segment]>::to_vec));
        }
    }
    groups
}

/// The sum of `f` over `groups` (one group per pixel), on one thread or all.
fn per_group(groups: &[&[Segment]], parallel: bool, f: impl Fn(&[Segment]) -> usize + Sync) -> usize {
    if parallel {
        groups.par_iter().map(|g| f(g)).sum()
    } else {
        groups.iter().map(|g| f(g)).sum()
    }
}

/// Hits among one group's `rays`: one packet call, or one call per ray — the very code
/// `intersect_packet` falls back to below MIN_PACKET rays (calling `intersect` from here
/// instead ran ~15% slower or faster depending on where the compiler put it, for identical
/// work).
fn count_hits(bvh: &Bvh, rays: &[Segment], packets: bool) -> usize {
    count(rays, packets, |r, h| bvh.intersect_packet(r, h), Option::is_some)
}

/// Blocked segments among one group's shadow rays, as [`count_hits`] does for hits.
fn count_blocked(bvh: &Bvh, rays: &[Segment], packets: bool) -> usize {
    count(rays, packets, |r, b| bvh.any_hit_packet(r, b), |&b| b)
}

/// `trace(rays, answers)` as one call or one call per ray; the answers that are `counted`.
fn count<T: Copy + Default>(
    rays: &[Segment],
    packets: bool,
    trace: impl Fn(&[Segment], &mut [T]),
    counted: impl Fn(&T) -> bool,
) -> usize {
    let mut answers = [T::default(); PACKET];
    if packets {
        trace(rays, &mut answers[..rays.len()]);
    } else {
        for (ray, answer) in rays.chunks(1).zip(answers.chunks_mut(1)) {
            trace(ray, answer);
        }
    }
    answers[..rays.len()].iter().filter(|a| counted(a)).count()
}

/// The shadow ray from the point `hit` found towards a point light at `light`, offset as the
/// renderer offsets it.
fn shadow_ray(mesh: &TriangleMesh, bvh: &Bvh, hit: &Hit, light: Vec3) -> ShadowRay {
    let [p0, p1, p2] = mesh.triangle_positions(hit.triangle as usize);
    let p = (1.0 - hit.b1 - hit.b2) * p0 + hit.b1 * p1 + hit.b2 * p2;
    let n = (p1 - p0).cross(p2 - p0).normalize_or_zero();
    let to = light - p;
    ShadowRay::towards_light(p, n, to.normalize(), to.length(), bvh.scene_unit())
}

/// Seconds per pass of `f`, timed over [`PASSES`] passes (one pass on two threads is ~15 ms,
/// short enough for one scheduler hiccup to move a median).
fn time_passes(f: impl Fn() -> usize) -> f64 {
    let t = Instant::now();
    for _ in 0..PASSES {
        std::hint::black_box(f());
    }
    t.elapsed().as_secs_f64() / PASSES as f64
}

/// One preset's tree with the primary rays (the renderer's order) and the shadow rays of their hits.
struct Case {
    preset: BvhPreset,
    bvh: Bvh,
    build_ms: f64,
    rays: Vec<(Vec3, Vec3, f32)>,
    shadow_rays: Vec<ShadowRay>,
}

impl Case {
    fn new(mesh: &TriangleMesh, camera: &Camera, light: Vec3, preset: BvhPreset, runs: usize) -> Self {
        let builds: Vec<Bvh> = (0..runs).map(|_| Bvh::build(mesh, preset)).collect();
        let build_ms = median(builds.iter().map(|b| b.build_time.as_secs_f64() * 1e3).collect());
        let bvh = builds.into_iter().next_back().unwrap();
        // The renderer's order: tiles row by row, each tile's pixels block by block.
        let rays: Vec<(Vec3, Vec3, f32)> = tiles(PixelRect::full(SIZE, SIZE))
            .into_iter()
            .flat_map(block_order)
            .map(|(x, y)| {
                let r = camera.ray((x as f32 + 0.5) / SIZE as f32, (y as f32 + 0.5) / SIZE as f32);
                (r.origin, r.direction, r.t_max)
            })
            .collect();
        let shadow_rays = rays
            .iter()
            .filter_map(|&(o, d, t)| bvh.intersect(o, d, t).map(|h| shadow_ray(mesh, &bvh, &h, light)))
            .collect();
        Self {
            preset,
            bvh,
            build_ms,
            rays,
            shadow_rays,
        }
    }

    /// Primary rays that hit something.
    fn primary(&self, parallel: bool) -> usize {
        let hits = |&(o, d, t): &(Vec3, Vec3, f32)| self.bvh.intersect(o, d, t).is_some();
        if parallel {
            self.rays.par_iter().filter(|r| hits(r)).count()
        } else {
            self.rays.iter().filter(|r| hits(r)).count()
        }
    }

    /// Shadow rays that are blocked.
    fn shadow(&self, parallel: bool) -> usize {
        let blocked = |r: &ShadowRay| self.bvh.any_hit(r.origin, r.direction, r.t_max);
        if parallel {
            self.shadow_rays.par_iter().filter(|r| blocked(r)).count()
        } else {
            self.shadow_rays.iter().filter(|r| blocked(r)).count()
        }
    }
}

fn torus() -> TriangleMesh {
    pointshade::scene::procedural::torus(1.0, 0.35, 400, 125).into_triangle_mesh()
}
