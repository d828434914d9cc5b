//! `pointshade compare`: per-pixel metrics between two linear images, and a heat map.

use std::path::PathBuf;

use crate::cli::option_error;
use crate::error::InputError;
use crate::output::{encode, read_linear, write_all_or_nothing, Format};
use crate::validation::compare::compare;

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
    let reference = read_linear(&args.reference)?;
    if (ours.width, ours.height) != (reference.width, reference.height) {
        return Err(InputError::new(
            &args.reference,
            format!(
                "size {}×{} differs from {}×{} of {}",
                reference.width,
                reference.height,
                ours.width,
                ours.height,
                args.ours.display()
            ),
        ));
    }
    let c = compare(&ours, &reference, args.tol, args.worst);
    if let Some(path) = &args.heatmap {
        let bytes = encode(&c.heat_map(ours.width, ours.height), Format::of(path)?, 0.0)
            .map_err(|e| InputError::new(path, e))?;
        write_all_or_nothing(&[(path.clone(), bytes)])?;
    }
    print!("{}", c.summary());
    Ok(())
}
