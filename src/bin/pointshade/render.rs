//! `pointshade render`: scene → plan → BVH → render → PNG/EXR (+ AOVs), with a summary.

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::options::{comma_list, option_error, worker_pool};
use crate::progress::Progress;
use pointshade::error::InputError;
use pointshade::film::{Image, PixelRect};
use pointshade::output::exr::encode_exr;
use pointshade::output::{aov_path, encode, write_all_or_nothing, Format};
use pointshade::plan::{Aov, RenderPlan};
use pointshade::scene::framing::{Aim, View};
use pointshade::scene::overrides::Overrides;
use pointshade::{render, scene};

/// Arguments of `pointshade render`.
#[derive(clap::Args)]
pub struct RenderArgs {
    /// Scene file (.toml), mesh (.obj) or glTF file (.gltf, .glb).
    scene: PathBuf,
    /// Output image (.png or .exr); default: the scene's name with .png, in the current directory.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Samples per pixel.
    #[arg(long)]
    spp: Option<u32>,
    /// Sampler: grid (spp = N², sub-pixel centres), sobol (default), independent, adaptive
    /// (Sobol rounds where a pixel needs them, spp at most), cells (sub-pixel cells subdivided
    /// where a pixel needs them, spp at most).
    #[arg(long)]
    sampler: Option<String>,
    /// Adaptive sampler: relative tolerance of a pixel's refinement (default 0.01; smaller takes
    /// more samples).
    #[arg(long)]
    adaptive_threshold: Option<f32>,
    /// Seconds the BVH build and the render may take. sobol and independent add samples in
    /// passes (doubling, then smaller: sobol to totals of 2^k or 1.5·2^k only) while they fit,
    /// up to --spp if given (else 65536); adaptive and cells
    /// refine at thresholds halving from 0.04 down to --adaptive-threshold if given (else
    /// 1/1024), within --spp (else 1024). The scene's spp and threshold are then ignored. The
    /// image is bit for bit the render at the count or threshold reached, which the summary
    /// prints.
    #[arg(long, value_name = "SECONDS")]
    time_budget: Option<f32>,
    /// Render only pixels [x0, x1) × [y0, y1) of the frame, into an EXR crop that `pointshade
    /// merge` reassembles bit-identically (for splitting a frame over machines).
    #[arg(long, value_name = "x0,y0,x1,y1")]
    crop: Option<String>,
    /// Image width in pixels.
    #[arg(long)]
    width: Option<u32>,
    /// Image height in pixels.
    #[arg(long)]
    height: Option<u32>,
    /// Exposure in stops for PNG output.
    #[arg(long, allow_negative_numbers = true)]
    exposure: Option<f32>,
    /// Extra images written beside the output as EXR: normal,position,depth,albedo,samples.
    #[arg(long)]
    aov: Option<String>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// glTF files: render through camera N of the file (0-based) instead of the first one.
    #[arg(long, value_name = "N")]
    camera: Option<usize>,
    /// Shadow-ray origin offset: error-bound (default) or mitsuba (Mitsuba 3's fixed epsilon, for
    /// pixel-exact validation).
    #[arg(long)]
    shadow_offset: Option<String>,
    /// Where shadow rays start on smooth-shaded meshes: smooth (default: from the surface the
    /// vertex normals describe, so coarse meshes show no faceted shadow terminator) or flat (from
    /// the triangle itself). The mitsuba offset always starts on the triangle.
    #[arg(long, value_name = "smooth|flat")]
    shadow_terminator: Option<String>,
    /// Aim the automatic framing: degrees around the vertical from the front (+Z; 90 looks from
    /// +X), degrees above the horizontal, and the distance as a multiple of the one that fits the
    /// bounding box (default 1). Replaces the scene's camera; automatic lights follow it. The
    /// default framing is about 24.2,17.7.
    #[arg(long, value_name = "azimuth,elevation[,distance]", allow_hyphen_values = true)]
    view: Option<String>,
    /// Put the camera at this point (world coordinates, as a scene file writes them).
    #[arg(long, value_name = "x,y,z", allow_hyphen_values = true)]
    look_from: Option<String>,
    /// Aim the camera at this point (world coordinates).
    #[arg(long, value_name = "x,y,z", allow_hyphen_values = true)]
    look_at: Option<String>,
    /// Vertical field of view of the (perspective) camera, in degrees.
    #[arg(long, value_name = "DEGREES")]
    fov: Option<f32>,
    /// Seed of the samplers' random sequences (default: the scene's, else 0).
    #[arg(long)]
    seed: Option<u64>,
    /// Print the render plan: stages kept and skipped, and why.
    #[arg(long)]
    explain: bool,
    /// No progress bar and no summary.
    #[arg(long, short)]
    quiet: bool,
}

/// Runs `pointshade render`.
pub fn run(args: RenderArgs) -> Result<(), InputError> {
    let t_load = Instant::now();
    let output = args.output.clone().unwrap_or_else(|| default_output(&args.scene));
    let format = Format::of_output(&output)?;
    let aovs = match &args.aov {
        Some(list) => Aov::parse_list(list).map_err(|e| option_error("--aov", e))?,
        None => Vec::new(),
    };
    let pool = worker_pool(args.threads)?;
    let point = |option: &str, text: &Option<String>| -> Result<Option<glam::DVec3>, InputError> {
        text.as_ref()
            .map(|t| {
                let v = comma_list(option, t, "x,y,z", |s| s.parse::<f64>().ok().filter(|v| v.is_finite()))?;
                match v[..] {
                    [x, y, z] => Ok(glam::DVec3::new(x, y, z)),
                    _ => Err(option_error(option, format!("expected x,y,z, got '{t}'"))),
                }
            })
            .transpose()
    };
    let crop = args.crop.as_deref().map(PixelRect::parse).transpose();
    let crop = crop.map_err(|e| option_error("--crop", e))?;
    if crop.is_some() && format != Format::Exr {
        return Err(option_error(
            "--crop",
            "crops are written as EXR (linear, with their position): use -o NAME.exr",
        ));
    }
    let overrides = Overrides {
        width: args.width,
        height: args.height,
        spp: args.spp,
        sampler: args.sampler.clone(),
        adaptive_threshold: args.adaptive_threshold,
        time_budget: args.time_budget,
        seed: args.seed,
        crop,
        exposure: args.exposure,
        shadow_offset: args.shadow_offset.clone(),
        shadow_terminator: args.shadow_terminator.clone(),
        aim: Aim {
            view: args
                .view
                .as_deref()
                .map(View::parse)
                .transpose()
                .map_err(|e| option_error("--view", e))?,
            look_from: point("--look-from", &args.look_from)?,
            look_at: point("--look-at", &args.look_at)?,
            fov: args.fov,
        },
    };
    let mut scene = pool.install(|| scene::load_with(&args.scene, scene::LoadOptions { camera: args.camera }))?;
    overrides.apply(&mut scene, &|key| format!("--{}", key.replace('_', "-")))?;
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }
    let load_time = t_load.elapsed();

    let plan = RenderPlan::new(&scene, &aovs);
    if args.explain {
        print!("{}", plan.explain(&scene));
    }

    let rendered = pool.install(|| {
        let progress = Progress::new(&scene, args.quiet);
        let rendered = render::render_scene(&scene, &plan, &|n| progress.tick(n));
        progress.finish();
        rendered
    });
    let rendered = rendered.map_err(|e| InputError::new(&args.scene, e))?;

    let t_out = Instant::now();
    let frame = (scene.film.width, scene.film.height);
    let encode_as = |img: &Image, format: Format, path: &Path| match scene.film.crop {
        Some(region) => encode_exr(img, region, frame).map_err(|e| InputError::new(path, e)),
        None => encode(img, format, scene.film.exposure).map_err(|e| InputError::new(path, e)),
    };
    let mut files = vec![(output.clone(), encode_as(&rendered.image, format, &output)?)];
    for (aov, img) in &rendered.aovs {
        let path = aov_path(&output, *aov);
        files.push((path.clone(), encode_as(img, Format::Exr, &path)?));
    }
    write_all_or_nothing(&files)?;
    let output_time = t_out.elapsed();

    if !args.quiet {
        let s = &rendered.stats;
        let bvh_time = s.bvh_time;
        let r = rendered.region;
        let spp = match &rendered.sample_counts {
            Some(c) => format!(
                "{:.2} spp on average (adaptive, threshold {}{}, at most {})",
                s.primary_rays as f64 / c.len() as f64,
                rendered.adaptive_threshold.unwrap_or(scene.film.adaptive_threshold),
                match scene.film.time_budget {
                    Some(budget) => format!(" reached in a time budget of {budget} s"),
                    None => String::new(),
                },
                scene.film.spp
            ),
            None => match scene.film.time_budget {
                Some(budget) => format!(
                    "{} spp (reached in a time budget of {budget} s, at most {})",
                    rendered.spp, scene.film.spp
                ),
                None => format!("{} spp", rendered.spp),
            },
        };
        let what = match scene.film.crop {
            Some(_) => format!(
                "{}x{} crop at ({}, {}) of {}x{}",
                r.width(),
                r.height(),
                r.x0,
                r.y0,
                frame.0,
                frame.1
            ),
            None => format!("{}x{}", frame.0, frame.1),
        };
        eprintln!(
            "rendered {what}, {spp}, {} triangles, {} primary + {} shadow rays in {:.2} s → {}",
            scene.mesh.triangle_count(),
            s.primary_rays,
            s.shadow_rays,
            (load_time + bvh_time + s.wall_time + output_time).as_secs_f64(),
            output.display()
        );
        eprintln!(
            "  stages: load {:.3} s, bvh {:.3} s, render {:.3} s (surface points {:.3} s + shading {:.3} s, summed over threads), output {:.3} s",
            load_time.as_secs_f64(),
            bvh_time.as_secs_f64(),
            s.wall_time.as_secs_f64(),
            s.surface_time.as_secs_f64(),
            s.shading_time.as_secs_f64(),
            output_time.as_secs_f64()
        );
    }
    Ok(())
}

fn default_output(scene: &Path) -> PathBuf {
    let stem = scene
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "render".into());
    PathBuf::from(format!("{stem}.png"))
}
