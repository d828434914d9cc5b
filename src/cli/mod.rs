//! The `pointshade` command line: one module per subcommand.
//!
//! Every subcommand returns `Result<(), InputError>`; [`main`] prints an error as one line
//! (`error: FILE: problem`) and exits with code 2.

mod progress;
mod render;

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
    /// Render a scene (.toml), a bare mesh (.obj) or a glTF file (.gltf, .glb) to PNG (8-bit sRGB)
    /// or EXR (linear float32).
    Render(render::RenderArgs),
}

/// Parses the command line, runs the subcommand, and maps errors to exit code 2.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(args) => render::run(args),
    };
    finish(result)
}

fn finish(result: Result<(), InputError>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
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
