//! `pointshade validate`: render scenes with pointshade and Mitsuba 3, compare, report.

use std::path::PathBuf;

use crate::options::option_error;
use pointshade::error::InputError;
use pointshade::film::Image;
use pointshade::output::{read_linear, write_all_or_nothing};
use pointshade::validation::report::{html, markdown};
use pointshade::validation::run::{validate_scene, MitsubaRunner};
use pointshade::validation::staleness::{check_reference, ReferenceCheck};

/// Arguments of `pointshade validate`.
#[derive(clap::Args)]
pub struct ValidateArgs {
    /// Scene files (default: every scenes/validation/*.toml, and scenes/validation/shared/*.toml
    /// when ../shared/data is present).
    scenes: Vec<PathBuf>,
    /// Folder for the report (index.html, summary.md, images).
    #[arg(long)]
    report: PathBuf,
    /// Side of the sample grid of the second comparison (spp = N²); 1 = pixel centres only.
    #[arg(long, default_value_t = 4)]
    grid: u32,
    /// The repository's validation folder (its .venv holds Mitsuba; see install.sh).
    #[arg(long, default_value = "validation")]
    mitsuba_dir: PathBuf,
    /// Compare the fresh pixel-centre Mitsuba renders with the committed references in this
    /// folder (NAME.exr) and fail if one is stale: if it differs by more than another CPU's
    /// rounding explains (more than 0.5% of the pixels beyond 1e-3 relative error, or 0.1%
    /// beyond 1e-2; docs/reference-drift.md has the measurements), or is missing.
    #[arg(long)]
    check_references: Option<PathBuf>,
    /// Write the fresh pixel-centre Mitsuba renders as the references in this folder.
    #[arg(long)]
    update_references: Option<PathBuf>,
}

/// Runs `pointshade validate`; exits with an error if an exact scene disagrees or a committed
/// reference is stale.
pub fn run(args: ValidateArgs) -> Result<(), InputError> {
    if args.grid == 0 || args.grid > 16 {
        return Err(option_error("--grid", format!("must be in 1..=16, got {}", args.grid)));
    }
    let scenes = if args.scenes.is_empty() {
        default_scenes()?
    } else {
        args.scenes.clone()
    };
    let mitsuba = MitsubaRunner::in_dir(&args.mitsuba_dir)?;
    let mut results = Vec::new();
    let mut stale = Vec::new();
    for path in &scenes {
        let r = validate_scene(path, args.grid, &mitsuba, &args.report)?;
        let fresh = args.report.join(&r.name).join("mitsuba-spp1.exr");
        if let Some(dir) = &args.update_references {
            let bytes = std::fs::read(&fresh).map_err(|e| InputError::new(&fresh, e))?;
            write_all_or_nothing(&[(dir.join(format!("{}.exr", r.name)), bytes)])?;
        }
        if let Some(dir) = &args.check_references {
            let committed = dir.join(format!("{}.exr", r.name));
            match check_committed(&read_linear(&fresh)?, &committed) {
                ReferenceCheck::Identical => {}
                ReferenceCheck::HostRounding(drift) => eprintln!(
                    "{}: differs from the fresh render by host rounding only: {}",
                    committed.display(),
                    drift.summary()
                ),
                ReferenceCheck::Stale(reason) => stale.push(format!("{} ({reason})", committed.display())),
            }
        }
        let run = &r.runs[0];
        eprintln!(
            "{:<28} {:>9} within {:.0e}, mean rel. error {:.1e}{}",
            r.name,
            pointshade::validation::report::within(&run.ours[0].comparison),
            pointshade::validation::run::TOLERANCE,
            run.ours[0].comparison.mean_relative_error,
            if r.is_exact() {
                if r.passes() {
                    ""
                } else {
                    "  FAILS"
                }
            } else {
                "  (no exact Mitsuba equivalent)"
            }
        );
        results.push(r);
    }
    let index = args.report.join("index.html");
    write_all_or_nothing(&[
        (index.clone(), html(&results).into_bytes()),
        (args.report.join("summary.md"), markdown(&results).into_bytes()),
    ])?;
    eprintln!(
        "Mitsuba variant: {}",
        pointshade::validation::report::mitsuba_variants(&results)
    );
    eprintln!("report: {}", index.display());
    let failing: Vec<_> = results
        .iter()
        .filter(|r| !r.passes())
        .map(|r| r.name.as_str())
        .collect();
    if !failing.is_empty() {
        return Err(InputError::new(
            &index,
            format!("scenes disagree with Mitsuba: {}", failing.join(", ")),
        ));
    }
    if !stale.is_empty() {
        return Err(InputError::new(
            &args.report,
            format!("committed references are stale: {}", stale.join(", ")),
        ));
    }
    Ok(())
}

/// The verdict on the committed reference at `path` against `fresh`; a missing or unreadable
/// reference is stale.
fn check_committed(fresh: &Image, path: &std::path::Path) -> ReferenceCheck {
    match read_linear(path) {
        Ok(committed) => check_reference(fresh, &committed),
        Err(e) => ReferenceCheck::Stale(format!("cannot be read: {e}")),
    }
}

fn default_scenes() -> Result<Vec<PathBuf>, InputError> {
    let mut scenes = toml_files("scenes/validation")?;
    if std::path::Path::new("../shared/data").is_dir() {
        scenes.extend(toml_files("scenes/validation/shared")?);
    } else {
        eprintln!("SKIPPED: ../shared/data is missing, so scenes/validation/shared/*.toml are not validated");
    }
    Ok(scenes)
}

fn toml_files(dir: &str) -> Result<Vec<PathBuf>, InputError> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| InputError::new(dir, format!("cannot list: {e}")))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    Ok(files)
}
