//! `pointshade compare`: per-pixel metrics between two linear images, and a heat map.

use std::path::PathBuf;

use crate::options::{comma_list, option_error};
use pointshade::error::InputError;
use pointshade::film::compare::{bin_labels, compare_checked, error_by_group, group_table, Side};
use pointshade::film::Image;
use pointshade::output::{encode, read_linear, write_all_or_nothing, Format};
use pointshade::validation::staleness::{check_reference, ReferenceCheck};

/// Arguments of `pointshade compare`.
#[derive(clap::Args)]
pub struct CompareArgs {
    /// Our image (EXR).
    ours: PathBuf,
    /// The reference image (EXR).
    reference: PathBuf,
    /// Relative tolerance per pixel (relative to max(|ref|, 1e-4 · max ref)).
    #[arg(long, default_value_t = 1e-3)]
    tol: f32,
    /// Write a heat map of the per-pixel relative error (PNG).
    #[arg(long)]
    heatmap: Option<PathBuf>,
    /// Number of worst pixels to list.
    #[arg(long, default_value_t = 10)]
    worst: usize,
    /// Also split the squared error by the value of this image's first channel (EXR of the same
    /// size with a few distinct values, such as `render --aov samples`): where the error sits.
    #[arg(long)]
    group_by: Option<PathBuf>,
    /// With --group-by: group its values into intervals starting at these increasing edges
    /// (comma-separated; a value joins the largest edge at or below it), e.g. 1,16,17,64,256
    /// for the adaptive sampler's counts.
    #[arg(long, requires = "group_by")]
    group_edges: Option<String>,
    /// Take OURS as a fresh Mitsuba render and REFERENCE as the committed reference of the same
    /// export (`validate --check-references` does this for every scene): print whether they
    /// differ by another CPU's rounding only, or the reference is stale (exit code 2). What
    /// counts as stale: docs/reference-drift.md.
    #[arg(long, conflicts_with_all = ["heatmap", "group_by"])]
    reference_check: bool,
    /// Count NaN and infinite pixels as mismatches (never within tolerance, left out of the
    /// averages) instead of refusing the images.
    #[arg(long)]
    count_non_finite: bool,
}

/// Runs `pointshade compare`; prints the metrics on stdout.
pub fn run(args: CompareArgs) -> Result<(), InputError> {
    if !(args.tol >= 0.0 && args.tol.is_finite()) {
        return Err(option_error(
            "--tol",
            format!("must be a finite number ≥ 0, got {}", args.tol),
        ));
    }
    let ours = read_linear(&args.ours)?;
    if args.reference_check {
        return match check_reference(&ours, &read_linear(&args.reference)?) {
            ReferenceCheck::Identical => {
                println!("identical");
                Ok(())
            }
            ReferenceCheck::HostRounding(drift) => {
                println!("host rounding: {}", drift.summary());
                Ok(())
            }
            ReferenceCheck::Stale(reason) => Err(InputError::new(&args.reference, format!("stale: {reason}"))),
        };
    }
    let same_size = |path: &PathBuf| -> Result<Image, InputError> {
        let image = read_linear(path)?;
        if (ours.width, ours.height) != (image.width, image.height) {
            return Err(InputError::new(
                path,
                format!(
                    "size {}×{} differs from {}×{} of {}",
                    image.width,
                    image.height,
                    ours.width,
                    ours.height,
                    args.ours.display()
                ),
            ));
        }
        Ok(image)
    };
    let reference = same_size(&args.reference)?;
    let edges = match &args.group_edges {
        Some(text) => {
            let expected = "increasing finite numbers like 1,16,17,64";
            let edges = comma_list("--group-edges", text, expected, |s| {
                s.parse::<f32>().ok().filter(|e| e.is_finite())
            })?;
            if !edges.windows(2).all(|w| w[0] < w[1]) {
                return Err(option_error(
                    "--group-edges",
                    format!("expected {expected}, got '{text}'"),
                ));
            }
            edges
        }
        None => Vec::new(),
    };
    let groups = match &args.group_by {
        Some(path) => {
            let labels = bin_labels(&same_size(path)?, &edges);
            Some(error_by_group(&ours, &reference, &labels).map_err(|e| InputError::new(path, e))?)
        }
        None => None,
    };
    let c = compare_checked(&ours, &reference, args.tol, args.worst, args.count_non_finite).map_err(
        |(side, problem)| match side {
            Side::Ours => InputError::new(&args.ours, problem),
            Side::Reference => InputError::new(&args.reference, problem),
        },
    )?;
    if let Some(path) = &args.heatmap {
        let bytes = encode(&c.heat_map(ours.width, ours.height), Format::of(path)?, 0.0)
            .map_err(|e| InputError::new(path, e))?;
        write_all_or_nothing(&[(path.clone(), bytes)])?;
    }
    print!("{}", c.summary());
    if let Some(groups) = groups {
        print!("{}", group_table(&groups));
    }
    Ok(())
}
