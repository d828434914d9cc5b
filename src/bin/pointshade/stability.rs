//! `pointshade stability`: runs the numerical-stability suite and prints its table.
//!
//! Exit codes: 0 when every case passes, 1 when any fails, 2 for a bad option.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use crate::options::option_error;
use pointshade::error::InputError;
use pointshade::output::write_all_or_nothing;
use pointshade::reports::stability::{self, table, Options};

/// Arguments of `pointshade stability`.
#[derive(clap::Args)]
pub struct StabilityArgs {
    /// Random BRDF samples (each evaluated in f32 and f64) and rays fired from inside closed
    /// meshes: this many of each.
    #[arg(long, default_value_t = 10_000_000)]
    cases: u64,
    /// Seed of every random choice.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Also write every case to this CSV file.
    #[arg(long)]
    csv: Option<PathBuf>,
}

/// Runs the suite; `Ok(ExitCode::FAILURE)` when a case failed.
pub fn run(args: StabilityArgs) -> Result<ExitCode, InputError> {
    if !(1000..=10_000_000_000).contains(&args.cases) {
        return Err(option_error(
            "--cases",
            format!("must be between 1000 and 1e10, got {}", args.cases),
        ));
    }
    if let Some(csv) = &args.csv {
        if !csv.extension().is_some_and(|e| e.eq_ignore_ascii_case("csv")) {
            return Err(option_error(
                "--csv",
                format!("{}: expected a .csv file name", csv.display()),
            ));
        }
    }
    let start = Instant::now();
    let shared = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/meshes");
    let options = Options {
        cases: args.cases,
        seed: args.seed,
        shared_meshes: Some(shared),
    };
    let report = stability::run(&options);
    if let Some(csv) = &args.csv {
        write_all_or_nothing(&[(csv.clone(), table::csv(&report).into_bytes())])?;
    }
    print!("{}", table::case_table(&report));
    println!();
    for note in &report.notes {
        if note.starts_with("SKIPPED") {
            eprintln!("{note}");
        } else {
            println!("{note}");
        }
    }
    println!(
        "seed {}, --cases {}, {:.1} s",
        args.seed,
        args.cases,
        start.elapsed().as_secs_f64()
    );
    println!();
    print!("{}", table::summary_table(&report));
    println!("{}", table::summary_line(&report));
    Ok(if report.failures() == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}
