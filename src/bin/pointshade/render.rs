//! `pointshade render`: scene → plan → BVH → render → PNG/EXR (+ AOVs), with a summary.

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::progress::Bar;
use crate::table::OptionFlags;
use pointshade::error::InputError;
use pointshade::film::Image;
use pointshade::output::exr::encode_exr;
use pointshade::output::{aov_path, encode, write_all_or_nothing, Format};
use pointshade::render::options::Spelling;
use pointshade::render::request::RenderRequest;
use pointshade::scene::SceneSource;

/// Arguments of `pointshade render`.
#[derive(clap::Args)]
pub struct RenderArgs {
    /// Scene file (.toml), mesh (.obj) or glTF file (.gltf, .glb).
    scene: PathBuf,
    /// Output image (.png or .exr); default: the scene's name with .png, in the current directory.
    #[arg(short, long)]
    output: Option<PathBuf>,
    #[command(flatten)]
    options: OptionFlags,
    /// Print the render plan: stages kept and skipped, and why.
    #[arg(long)]
    explain: bool,
    /// No progress bar and no summary.
    #[arg(long, short)]
    quiet: bool,
}

/// Runs `pointshade render`.
pub fn run(args: RenderArgs) -> Result<(), InputError> {
    let output = args.output.clone().unwrap_or_else(|| default_output(&args.scene));
    let format = Format::of_output(&output)?;
    let request = RenderRequest {
        source: SceneSource::File(args.scene.clone()),
        options: args.options.options()?,
    };
    if request.options.crop.is_some() && format != Format::Exr {
        return Err(InputError::new(
            "--crop",
            "crops are written as EXR (linear, with their position): use -o NAME.exr",
        ));
    }
    let prepared = request.prepare(Spelling::Flag)?;
    let scene = &prepared.scene;
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }
    let load_time = prepared.load_time;
    if args.explain {
        print!("{}", prepared.plan.explain(scene));
    }
    let bar = Bar::new(args.quiet);
    let rendered = prepared.render(&bar, None);
    bar.finish();
    let rendered = rendered?;

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
