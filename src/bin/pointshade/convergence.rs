//! `pointshade convergence`: error against run time, as a CSV and a log-log plot.

use std::path::PathBuf;

use crate::options::{comma_list, option_error};
use pointshade::error::InputError;
use pointshade::film::SamplerKind;
use pointshade::output::read_linear;
use pointshade::reports::convergence::{check, own_reference, run, write_outputs, ErrorMetric, Reference, Sweep};
use pointshade::scene::shadows::ShadowOffset;
use pointshade::validation::run::MitsubaRunner;

/// Arguments of `pointshade convergence`.
#[derive(clap::Args)]
pub struct ConvergenceArgs {
    /// Scene file (.toml) or mesh.
    scene: PathBuf,
    /// Reference image (linear EXR of the same size); default: a pointshade 32×32-grid render.
    #[arg(long)]
    reference: Option<PathBuf>,
    /// Sample counts (comma-separated; the grid sampler uses the square ones).
    #[arg(long, default_value = "1,4,16,64")]
    spp: String,
    /// pointshade samplers (comma-separated): sobol, adaptive, cells, grid, independent.
    #[arg(long, default_value = "sobol,adaptive")]
    sampler: String,
    /// Thresholds of the adaptive samplers, adaptive and cells (comma-separated; default: the
    /// scene's, 0.01 unless it sets one). With several, each adaptive sampler runs each at the
    /// largest --spp (its cap) instead of running each sample count: its error against time is
    /// traced by the threshold.
    #[arg(long)]
    adaptive_threshold: Option<String>,
    /// Time budgets in seconds (comma-separated), for BVH build and render: every sampler but
    /// the grid then also runs once per budget, drawn as a dashed line of its own (the
    /// adaptive ones down to the smallest --adaptive-threshold, if given), and each budget's
    /// point is the run of median time among the repeats (its count, threshold and error with it).
    #[arg(long, value_name = "SECONDS,…")]
    time_budget: Option<String>,
    /// Repeats per point; the median time is kept.
    #[arg(long, default_value_t = 3)]
    repeats: u32,
    /// Also run Mitsuba 3 (llvm variant; grid and independent samplers) in the same run.
    #[arg(long)]
    mitsuba: bool,
    /// The repository's validation folder (Mitsuba's virtual environment).
    #[arg(long, default_value = "validation")]
    mitsuba_dir: PathBuf,
    /// Shadow-ray offset of pointshade's renders (default: mitsuba with --mitsuba, else error-bound).
    #[arg(long)]
    shadow_offset: Option<String>,
    /// The plot's error: rmse, rel-mse (relative MSE) or outside (the share of pixels off by
    /// more than 1e-3). The CSV has all three.
    #[arg(long, default_value = "rmse", value_name = "rmse|rel-mse|outside")]
    metric: String,
    /// Output folder: convergence.csv, convergence.svg, convergence.png, reference.png.
    #[arg(long)]
    out: PathBuf,
}

/// Runs `pointshade convergence`.
pub fn run_command(args: ConvergenceArgs) -> Result<(), InputError> {
    let metric = ErrorMetric::parse(&args.metric).map_err(|e| option_error("--metric", e))?;
    let spp = comma_list("--spp", &args.spp, "sample counts like 1,4,16,64", |s| {
        s.parse::<u32>()
            .ok()
            .filter(|&n| (1..=pointshade::film::MAX_SPP).contains(&n))
    })?;
    // The range is the film's to check (with the scene named), as for a threshold in the scene.
    let adaptive_thresholds = match &args.adaptive_threshold {
        Some(text) => comma_list("--adaptive-threshold", text, "thresholds like 0.02,0.01,0.005", |s| {
            s.parse::<f32>().ok()
        })?,
        None => Vec::new(),
    };
    // The range is the film's to check, as for the thresholds.
    let time_budgets = match &args.time_budget {
        Some(text) => comma_list("--time-budget", text, "seconds like 0.1,0.2,0.5", |s| {
            s.parse::<f32>().ok()
        })?,
        None => Vec::new(),
    };
    let samplers = args
        .sampler
        .split(',')
        .map(|s| SamplerKind::parse(s.trim()))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| option_error("--sampler", e))?;
    if args.repeats == 0 || args.repeats > 100 {
        return Err(option_error(
            "--repeats",
            format!("must be in 1..=100, got {}", args.repeats),
        ));
    }
    let shadow_offset = match &args.shadow_offset {
        Some(name) => ShadowOffset::parse(name).map_err(|e| option_error("--shadow-offset", e))?,
        None if args.mitsuba => ShadowOffset::Mitsuba,
        None => ShadowOffset::ErrorBound,
    };
    let mitsuba = if args.mitsuba {
        Some(MitsubaRunner::in_dir(&args.mitsuba_dir)?)
    } else {
        None
    };
    let sweep = Sweep {
        scene: args.scene.clone(),
        spp,
        samplers,
        repeats: args.repeats,
        shadow_offset,
        adaptive_thresholds,
        time_budgets,
        mitsuba,
        out: args.out.clone(),
    };
    let given = match &args.reference {
        Some(path) => Some(Reference {
            image: read_linear(path)?,
            description: path.display().to_string(),
        }),
        None => None,
    };
    // Bad input fails here, before the output folder exists.
    check(&sweep, given.as_ref())?;
    std::fs::create_dir_all(&args.out).map_err(|e| InputError::new(&args.out, format!("cannot create: {e}")))?;
    let reference = match given {
        Some(reference) => reference,
        None => {
            eprintln!("no --reference: rendering a pointshade 32×32-grid reference (the plot says so)");
            own_reference(&sweep)?
        }
    };
    eprintln!(
        "{:<11} {:<12} {:>5} {:>9} {:>7} {:>9} {:>10} {:>12} {:>10}",
        "renderer", "sampler", "spp", "threshold", "budget", "mean spp", "seconds", "RMSE", "within"
    );
    let points = run(&sweep, &reference, &mut |p| {
        let text = |v: Option<f32>| v.map(|t| t.to_string()).unwrap_or_default();
        eprintln!(
            "{:<11} {:<12} {:>5} {:>9} {:>7} {:>9.2} {:>10.4} {:>12.4e} {:>9.3}%",
            p.renderer,
            p.sampler,
            p.spp,
            text(p.threshold),
            text(p.time_budget),
            p.mean_spp,
            p.seconds,
            p.rmse,
            100.0 * p.within
        )
    })?;
    let name = args
        .scene
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    if let Some(note) = write_outputs(&args.out, &name, &points, &reference, metric)? {
        eprintln!("warning: {note}");
    }
    eprintln!("wrote {}/convergence.{{csv,svg,png}}", args.out.display());
    Ok(())
}
