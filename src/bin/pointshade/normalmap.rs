//! `pointshade normalmap`: a normal image (or a `[normal_map]` scene file) → plan → surface
//! points → shader → PNG/EXR, with a summary.

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::options::{option_error, workers};
use pointshade::error::InputError;
use pointshade::normal_map;
use pointshade::normal_map::formats::encode_min_max_png;
use pointshade::normal_map::image::NormalImage;
use pointshade::normal_map::scene_file::{ModelName, NormalMapScene, Preset};
use pointshade::output::{encode, write_all_or_nothing, Format};
use pointshade::scene::extension;

/// Arguments of `pointshade normalmap`.
#[derive(clap::Args)]
pub struct NormalMapArgs {
    /// A normal image (RGB or RGBA PNG, 8 or 16 bits), or a .toml scene file with a [normal_map]
    /// section.
    input: PathBuf,
    /// BRDF of the preset's material: lambert, blinn-phong or cook-torrance (required for an
    /// image; for a scene file it replaces the file's `brdf`).
    #[arg(long)]
    brdf: Option<String>,
    /// tp (the NPM3D TP4 report's images, exactly) or physical (default); images only: a scene
    /// file sets its preset in [normal_map].
    #[arg(long)]
    preset: Option<String>,
    /// Output image (.png or .exr); default: the input's name with the preset and BRDF, .png.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Exposure in stops for physical PNG output.
    #[arg(long, allow_negative_numbers = true)]
    exposure: Option<f32>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Print the plan: stages kept and skipped, and why.
    #[arg(long)]
    explain: bool,
    /// No summary.
    #[arg(long, short)]
    quiet: bool,
}

/// Runs `pointshade normalmap`.
pub fn run(args: NormalMapArgs) -> Result<(), InputError> {
    let t_load = Instant::now();
    let brdf = match &args.brdf {
        Some(b) => Some(b.parse::<ModelName>().map_err(|e| option_error("--brdf", e))?),
        None => None,
    };
    let is_scene = extension(&args.input).as_deref() == Some("toml");
    let mut scene = if is_scene {
        if args.preset.is_some() {
            return Err(option_error(
                "--preset",
                "applies to an image; a scene file sets preset in its [normal_map] section",
            ));
        }
        NormalMapScene::load(&args.input, brdf)?
    } else {
        let preset = match &args.preset {
            Some(p) => p.parse::<Preset>().map_err(|e| option_error("--preset", e))?,
            None => Preset::default(),
        };
        let brdf = brdf.ok_or_else(|| {
            option_error(
                "--brdf",
                "is required for an image: lambert, blinn-phong or cook-torrance",
            )
        })?;
        NormalMapScene::from_preset(&args.input, preset, brdf)
    };
    if let Some(e) = args.exposure {
        if scene.preset == Preset::Tp {
            return Err(option_error(
                "--exposure",
                "does not apply to the tp preset (its PNG is min-max normalised)",
            ));
        }
        if !(e.is_finite() && e.abs() <= 64.0) {
            return Err(option_error(
                "--exposure",
                format!("must be finite stops in [-64, 64], got {e}"),
            ));
        }
        scene.exposure = e;
    }
    let output = args
        .output
        .clone()
        .unwrap_or_else(|| default_output(&args.input, &scene, is_scene));
    let format = Format::of_output(&output)?;
    let pool = workers(args.threads)?;
    let image = NormalImage::load(&scene.image)?;
    let load_time = t_load.elapsed();
    let description = match (scene.preset, format) {
        (Preset::Tp, Format::Png) => {
            "RGB PNG: L_o min-max normalised over all pixels and channels, ×255 truncated".into()
        }
        (Preset::Physical, Format::Png) => format!("sRGB PNG, exposure {} stops", scene.exposure),
        (_, Format::Exr) => "linear float32 EXR of L_o".into(),
    };
    let shaded = pool.install(|| normal_map::shade(&scene, &image, &description));
    let shaded = shaded?;
    for warning in &shaded.warnings {
        eprintln!("warning: {warning}");
    }
    if args.explain {
        print!("{}", shaded.plan.explain(&scene, &image));
    }
    let stats = shaded.stats;

    let t_out = Instant::now();
    let bytes = match (scene.preset, format) {
        (Preset::Tp, Format::Png) => {
            let (bytes, range) = encode_min_max_png(&shaded.radiance).map_err(|e| InputError::new(&output, e))?;
            if let Some(warning) = range.warning() {
                eprintln!("warning: {}: {warning}", scene.image.display());
            }
            bytes
        }
        _ => encode(&shaded.radiance, format, scene.exposure).map_err(|e| InputError::new(&output, e))?,
    };
    write_all_or_nothing(&[(output.clone(), bytes)])?;
    let output_time = t_out.elapsed();

    if !args.quiet {
        eprintln!(
            "shaded {}x{} normal image ({} preset, {}): {} surface points, 0 rays in {:.3} s → {}",
            image.width,
            image.height,
            scene.preset.name(),
            scene.material.model_name(),
            stats.surface_points,
            (load_time + stats.wall_time + output_time).as_secs_f64(),
            output.display()
        );
        eprintln!(
            "  stages: load + decode {:.4} s, shade {:.4} s (foreground scan and image check {:.4} s + surface points and shading {:.4} s, summed over threads), output {:.4} s",
            load_time.as_secs_f64(),
            stats.wall_time.as_secs_f64(),
            stats.surface_time.as_secs_f64(),
            stats.shading_time.as_secs_f64(),
            output_time.as_secs_f64()
        );
    }
    Ok(())
}

fn default_output(input: &Path, scene: &NormalMapScene, is_scene: bool) -> PathBuf {
    let stem = input
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "normalmap".into());
    if is_scene {
        PathBuf::from(format!("{stem}.png"))
    } else {
        PathBuf::from(format!(
            "{stem}-{}-{}.png",
            scene.preset.name(),
            scene.material.model_name()
        ))
    }
}
