//! The `pointshade` command line: one module per subcommand.
//!
//! Every subcommand returns `Result<(), InputError>`; [`main`] prints an error as one line
//! (`error: FILE: problem`) and exits with code 2.

mod progress;
mod render;
mod stability;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

use crate::error::InputError;

#[derive(Parser)]
#[command(name = "pointshade", version, about = "Shade surface points with analytic BRDFs")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene (.toml) or a bare mesh (.obj) to PNG (8-bit sRGB) or EXR (linear float32).
    Render(render::RenderArgs),
    /// Check numerical stability on stiff and extreme inputs (f32 vs f64, watertight rays,
    /// shadows at extreme scales, extreme lights); exit code 1 if any case fails.
    Stability(stability::StabilityArgs),
}

/// Parses the command line, runs the subcommand, and maps errors to exit code 2.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(args) => render::run(args).map(|()| ExitCode::SUCCESS),
        Command::Stability(args) => stability::run(args),
    };
    finish(result)
}

fn finish(result: Result<ExitCode, InputError>) -> ExitCode {
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

/// An error about a command-line option rather than a file.
pub(crate) fn option_error(option: &str, problem: impl std::fmt::Display) -> InputError {
    InputError::new(option, problem)
}
