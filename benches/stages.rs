//! Where a render's time goes, stage by stage, and what a preview costs after an edit.
//!
//! `cargo bench --bench stages [-- --quick] [-- --csv PATH]` renders each scene at 512×512, one
//! Sobol sample per pixel, through [`pointshade::render::preview::Preview`] (the only renderer
//! path that times shadow rays apart from the rest of shading), and prints one table per stage —
//! load, BVH build, primary visibility, shadow rays, shading — with rays per second per core,
//! then the preview's table: from scratch, and re-shaded after a material edit and after a light
//! moved (issue 45's goal 5: ≤ 60 and ≤ 20 ms for the dragon on two cores). Medians of 9 rounds
//! (`--quick`: 2); in each round every scene runs once (round-robin, so a slow spell of a shared
//! machine slows every scene alike). `--csv PATH` writes every figure with the CPU's name.
//! The dragon (`scenes/shared/dragon-copper.toml`) needs ../shared/data; without it the table
//! says SKIPPED on its row.

mod common;

use common::median;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use glam::Vec3;

use pointshade::film::sampler::SamplerKind;
use pointshade::light::LightKind;
use pointshade::material::BrdfModel;
use pointshade::plan::RenderPlan;
use pointshade::render::preview::Preview;
use pointshade::render::{progress::Silent, render_scene};
use pointshade::scene::{self, Scene};

const SIZE: u32 = 512;

/// One round's figures for one scene.
#[derive(Default)]
struct Round {
    load: f64,
    build: f64,
    triangles: u64,
    primary_rays: u64,
    primary: f64,
    shadow_rays: u64,
    shadows: f64,
    shading: f64,
    from_scratch: f64,
    first_render: f64,
    render_scene: f64,
    reshade_material: f64,
    reshade_light: f64,
    light_rays_traced: u64,
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let quick = args.iter().any(|a| a == "--quick");
    let csv = args
        .iter()
        .position(|a| a == "--csv")
        .map(|i| PathBuf::from(args.get(i + 1).expect("--csv takes a path")));
    let rounds = if quick { 2 } else { 9 };
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let scenes = [
        ("dragon-copper", root.join("scenes/shared/dragon-copper.toml")),
        ("cornell-box", root.join("scenes/cornell-box.toml")),
        ("cook-torrance", root.join("scenes/cook-torrance.toml")),
    ];
    let threads = rayon::current_num_threads();
    let cpu = cpu_name();
    let width = vector_width();
    println!("{cpu} ({width}), {threads} thread(s); {SIZE}x{SIZE}, 1 spp (sobol); medians of {rounds} round(s)");
    let mut results: Vec<(&str, Result<Vec<Round>, String>)> =
        scenes.iter().map(|(name, _)| (*name, Ok(Vec::new()))).collect();
    for _ in 0..rounds {
        for ((_, path), (_, result)) in scenes.iter().zip(&mut results) {
            let Ok(list) = result else { continue };
            match round(path) {
                Ok(r) => list.push(r),
                Err(e) => *result = Err(e),
            }
        }
    }
    let mut table = String::new();
    let mut rows = Vec::new();
    let stage = |table: &mut String, title: &str, head: [&str; 3]| {
        let _ = writeln!(table, "\n{title}");
        let _ = writeln!(table, "{:<16} {:>12} {:>14} {:>22}", "scene", head[0], head[1], head[2]);
    };
    // Per stage: its title, column heads, what it counts and how long it took (median).
    type Count = fn(&Round) -> u64;
    type Millis = fn(&Round) -> f64;
    let stages: [(&str, [&str; 3], Count, Millis); 5] = [
        ("load", ["triangles", "ms", "Mtriangles/s"], |r| r.triangles, |r| r.load),
        (
            "build (BVH)",
            ["triangles", "ms", "Mtriangles/s"],
            |r| r.triangles,
            |r| r.build,
        ),
        (
            "primary visibility",
            ["rays", "ms (threads)", "Mrays/s per core"],
            |r| r.primary_rays,
            |r| r.primary,
        ),
        (
            "shadow rays",
            ["rays", "ms (threads)", "Mrays/s per core"],
            |r| r.shadow_rays,
            |r| r.shadows,
        ),
        (
            "shading (without shadow rays)",
            ["samples", "ms (threads)", "Msamples/s per core"],
            |r| r.primary_rays,
            |r| r.shading,
        ),
    ];
    for (title, head, count, millis) in stages {
        stage(&mut table, title, head);
        for (name, result) in &results {
            match result {
                Ok(r) if !r.is_empty() => {
                    let (count, m) = (count(&r[0]) as f64, med(r, millis));
                    let rate = count / (m * 1e3);
                    let _ = writeln!(table, "{name:<16} {count:>12} {m:>14.2} {rate:>22.2}");
                    rows.push(format!("{title},{name},{},{count},{m:.4},{rate:.4}", head[2]));
                }
                Ok(_) => {}
                Err(e) => {
                    let _ = writeln!(table, "{name:<16} SKIPPED: {e}");
                }
            }
        }
    }
    let _ = writeln!(
        table,
        "\npreview, wall ms on {threads} thread(s): from scratch = BVH build + trace + shade (render_scene: the same \
         without keeping anything); trace + shade = the BVH already built (a new view); re-shade = after the edit"
    );
    let _ = writeln!(
        table,
        "{:<16} {:>13} {:>13} {:>14} {:>18} {:>15} {:>11}",
        "scene", "from scratch", "render_scene", "trace + shade", "re-shade material", "re-shade light", "light rays"
    );
    for (name, result) in &results {
        let Ok(r) = result else {
            let _ = writeln!(table, "{name:<16} SKIPPED");
            continue;
        };
        if r.is_empty() {
            continue;
        }
        let (scratch, whole) = (med(r, |r| r.from_scratch), med(r, |r| r.render_scene));
        let first = med(r, |r| r.first_render);
        let (material, light) = (med(r, |r| r.reshade_material), med(r, |r| r.reshade_light));
        let goals = if *name == "dragon-copper" {
            format!(
                "  goals ≤ 60 / ≤ 20 ms: from scratch {}, trace + shade {}; re-shade {}",
                if scratch <= 60.0 { "met" } else { "NOT met" },
                if first <= 60.0 { "met" } else { "NOT met" },
                if material <= 20.0 { "met" } else { "NOT met" }
            )
        } else {
            String::new()
        };
        let _ = writeln!(
            table,
            "{name:<16} {scratch:>13.2} {whole:>13.2} {first:>14.2} {material:>18.2} {light:>15.2} {:>11}{goals}",
            r[0].light_rays_traced
        );
        for (what, v) in [
            ("from scratch", scratch),
            ("render_scene", whole),
            ("trace + shade", first),
            ("re-shade after a material edit", material),
            ("re-shade after a light moved", light),
        ] {
            rows.push(format!("preview,{name},wall ms {what},1,{v:.4},"));
        }
    }
    print!("{table}");
    if let Some(path) = csv {
        let mut out = String::from("cpu,vector,threads,stage,scene,measure,count,ms,rate\n");
        for row in rows {
            let _ = writeln!(out, "\"{cpu}\",{width},{threads},{row}");
        }
        std::fs::write(&path, out).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        println!("\nwrote {}", path.display());
    }
}

fn med(rounds: &[Round], f: impl Fn(&Round) -> f64) -> f64 {
    median(rounds.iter().map(f).collect())
}

/// One round on the scene at `path`: load, preview from scratch, the two edits, and the
/// whole-render path for comparison.
fn round(path: &Path) -> Result<Round, String> {
    let t = Instant::now();
    let mut scene: Scene = scene::load(path).map_err(|e| e.to_string())?;
    let load = ms(t.elapsed());
    scene.film.width = SIZE;
    scene.film.height = SIZE;
    scene.film.spp = 1;
    scene.film.sampler = SamplerKind::Sobol;
    let triangles = scene.mesh.triangle_count() as u64;

    let t = Instant::now();
    let whole = render_scene(&scene, &RenderPlan::new(&scene, &[]), &Silent)?;
    let render_scene_ms = ms(t.elapsed());
    std::hint::black_box(whole.image);

    let t = Instant::now();
    let mut preview = Preview::new(scene, &[])?;
    let t_first = Instant::now();
    let first = preview.render()?;
    let (from_scratch, first_render) = (ms(t.elapsed()), ms(t_first.elapsed()));
    let s = &first.stats;
    let shadows = ms(s.shadow_time.unwrap_or_default());

    // A material edit: every material's roughness or exponent nudged, its colour changed.
    let mut materials = preview.scene().materials.clone();
    for m in &mut materials {
        m.albedo = m.albedo.map(|c| c * 0.9);
        match &mut m.model {
            BrdfModel::CookTorrance(ct) => ct.alpha = (ct.alpha * 1.1).min(1.0),
            BrdfModel::BlinnPhong(bp) => bp.shininess *= 1.1,
            _ => {}
        }
    }
    let t = Instant::now();
    preview.set_materials(materials)?;
    let reshaded = preview.render()?;
    let reshade_material = ms(t.elapsed());
    assert_eq!(
        reshaded.stats.primary_rays + reshaded.stats.shadow_rays,
        0,
        "nothing traced"
    );

    // A light edit: the first positional light moved by 1% of the scene's size.
    let mut lights = preview.scene().lights.clone();
    let (lo, hi) = preview.scene().mesh.bounds().unwrap_or_default();
    if let Some(LightKind::Point { position } | LightKind::Spot { position, .. }) =
        lights.first_mut().map(|l| &mut l.kind)
    {
        *position += Vec3::splat(0.01 * (hi - lo).length());
    }
    let t = Instant::now();
    preview.set_lights(lights)?;
    let moved = preview.render()?;
    let reshade_light = ms(t.elapsed());

    Ok(Round {
        load,
        build: ms(preview.bvh_time()),
        triangles,
        primary_rays: s.primary_rays,
        primary: ms(s.surface_time),
        shadow_rays: s.shadow_rays,
        shadows,
        shading: ms(s.shading_time) - shadows,
        from_scratch,
        first_render,
        render_scene: render_scene_ms,
        reshade_material,
        reshade_light,
        light_rays_traced: moved.stats.shadow_rays,
    })
}

/// The CPU's model name with its family and model numbers (/proc/cpuinfo), which tell
/// machines of one marketing name apart ("AMD EPYC" covers Zen 1 to Zen 5).
fn cpu_name() -> String {
    let info = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    let field = |key: &str| {
        info.lines()
            .find(|l| l.split(':').next().is_some_and(|k| k.trim() == key))
            .and_then(|l| l.split(':').nth(1))
            .map(|v| v.trim().to_string())
    };
    match (field("model name"), field("cpu family"), field("model")) {
        (Some(name), Some(family), Some(model)) => format!("{name} (family {family}, model {model})"),
        (Some(name), ..) => name,
        _ => "unknown CPU".into(),
    }
}

/// The widest vector instructions the CPU has that pointshade can use.
fn vector_width() -> &'static str {
    #[cfg(target_arch = "x86_64")]
    {
        if is_x86_feature_detected!("avx512f") {
            return "AVX-512";
        }
        if is_x86_feature_detected!("avx2") {
            return "AVX2";
        }
    }
    "no AVX2"
}
