//! `pointshade merge`: reassemble `render --crop` EXR crops into the full frame.

use std::path::PathBuf;

use pointshade::error::InputError;
use pointshade::output::exr::{check_tiling, merge, read_crop, read_crop_placement};
use pointshade::output::{encode, write_all_or_nothing, Format};

/// Arguments of `pointshade merge`.
#[derive(clap::Args)]
pub struct MergeArgs {
    /// Crop EXRs written by `pointshade render --crop` (any order); together they must cover the
    /// frame exactly once.
    #[arg(required = true)]
    crops: Vec<PathBuf>,
    /// The frame (.exr: bit-identical to a single render; .png: sRGB with --exposure).
    #[arg(short, long)]
    output: PathBuf,
    /// Exposure in stops for PNG output.
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.0)]
    exposure: f32,
}

/// Runs `pointshade merge`.
pub fn run(args: MergeArgs) -> Result<(), InputError> {
    let format = Format::of_output(&args.output)?;
    if !(args.exposure.is_finite() && args.exposure.abs() <= 64.0) {
        return Err(crate::options::option_error(
            "--exposure",
            format!("must be in [-64, 64], got {}", args.exposure),
        ));
    }
    // Headers first: a set of crops that does not tile one frame is refused before gigabytes of
    // pixels are decoded.
    let placements = args
        .crops
        .iter()
        .map(|p| read_crop_placement(p).map(|(region, frame)| (p.clone(), region, frame)))
        .collect::<Result<Vec<_>, InputError>>()?;
    check_tiling(&placements)?;
    let crops = args
        .crops
        .iter()
        .map(|p| Ok((p.clone(), read_crop(p)?)))
        .collect::<Result<Vec<_>, InputError>>()?;
    let frame = merge(&crops)?;
    let bytes = encode(&frame, format, args.exposure).map_err(|e| InputError::new(&args.output, e))?;
    write_all_or_nothing(&[(args.output.clone(), bytes)])
}
