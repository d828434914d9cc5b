//! The `pointshade` command line: one module per subcommand.
//!
//! Every subcommand returns `Result<(), InputError>`; [`main`] prints an error as one line
//! (`error: FILE: problem`) and exits with code 2.

mod bake;
mod compare;
mod convergence;
mod export_mitsuba;
mod merge;
mod normalmap;
mod options;
mod progress;
mod render;
mod stability;
mod validate;

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
    /// Shade a normal image (PNG) or a [normal_map] scene file: presets tp (the NPM3D TP4 report) and physical.
    Normalmap(normalmap::NormalMapArgs),
    /// Write a mesh scene's camera-space normals as an RGBA PNG normal image (the assignment's format).
    Bake(bake::BakeArgs),
    /// Write a scene as Mitsuba 3 XML (meshes referenced, not copied).
    ExportMitsuba(export_mitsuba::ExportArgs),
    /// Compare two linear images (EXR) pixel by pixel: error metrics, worst pixels, heat map.
    Compare(compare::CompareArgs),
    /// Error against run time at increasing sample counts (optionally with Mitsuba 3): CSV and plot.
    Convergence(convergence::ConvergenceArgs),
    /// Reassemble `render --crop` EXR crops into one frame, bit-identical to a single render.
    Merge(merge::MergeArgs),
    /// Render scenes with pointshade and Mitsuba 3, compare pixel by pixel, write an HTML report.
    Validate(validate::ValidateArgs),
    /// Check numerical stability on stiff and extreme inputs (f32 vs f64, watertight rays,
    /// shadows at extreme scales, extreme lights); exit code 1 if any case fails.
    Stability(stability::StabilityArgs),
}

/// Parses the command line, runs the subcommand, and maps errors to exit code 2.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(args) => render::run(args).map(|()| ExitCode::SUCCESS),
        Command::Normalmap(args) => normalmap::run(args).map(|()| ExitCode::SUCCESS),
        Command::Bake(args) => bake::run(args).map(|()| ExitCode::SUCCESS),
        Command::ExportMitsuba(args) => export_mitsuba::run(args).map(|()| ExitCode::SUCCESS),
        Command::Compare(args) => compare::run(args).map(|()| ExitCode::SUCCESS),
        Command::Convergence(args) => convergence::run_command(args).map(|()| ExitCode::SUCCESS),
        Command::Merge(args) => merge::run(args).map(|()| ExitCode::SUCCESS),
        Command::Validate(args) => validate::run(args).map(|()| ExitCode::SUCCESS),
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
