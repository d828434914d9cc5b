//! The `pointshade` command line: one module per subcommand.
//!
//! Every subcommand returns `Result<(), InputError>`; [`main`] prints an error as one line
//! (`error: FILE: problem`) and exits with code 2.

mod bake;
mod compare;
mod convergence;
mod explore;
mod export_mitsuba;
mod merge;
mod normalmap;
mod options;
mod progress;
mod render;
mod stability;
mod table;
mod validate;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

use pointshade::error::InputError;

#[derive(Parser)]
#[command(name = "pointshade", version, about = "Shade surface points with analytic BRDFs")]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Read no file outside DIR (links and `..` resolved): scene files, meshes, MTL files,
    /// textures, glTF buffers and images, normal images, EXR inputs. For input from others,
    /// such as a glTF file rendered on a server.
    #[arg(long, global = true, value_name = "DIR")]
    confine: Option<std::path::PathBuf>,
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
    /// Explore BRDFs in the browser: a local server for one page, with sliders, plots, a lit
    /// sphere and the live render of a normal image or a scene.
    Explore(explore::ExploreArgs),
    /// Check numerical stability on stiff and extreme inputs (f32 vs f64, watertight rays,
    /// shadows at extreme scales, extreme lights); exit code 1 if any case fails.
    Stability(stability::StabilityArgs),
}

/// Parses the command line, runs the subcommand, and maps errors to exit code 2.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    remove_temporaries_on_signals();
    // Every file read is recorded, so that no command writes over one of its inputs.
    pointshade::input_files::record_reads();
    let confinement = match pointshade::input_files::Confinement::to_optional(cli.confine.as_deref()) {
        Ok(c) => c,
        Err(e) => {
            let dir = cli.confine.unwrap_or_default();
            return finish(Err(options::option_error(
                "--confine",
                format!("{}: {e}", dir.display()),
            )));
        }
    };
    let result = confinement.run(|| match cli.command {
        Command::Render(args) => render::run(args).map(|()| ExitCode::SUCCESS),
        Command::Normalmap(args) => normalmap::run(args).map(|()| ExitCode::SUCCESS),
        Command::Bake(args) => bake::run(args).map(|()| ExitCode::SUCCESS),
        Command::ExportMitsuba(args) => export_mitsuba::run(args).map(|()| ExitCode::SUCCESS),
        Command::Compare(args) => compare::run(args).map(|()| ExitCode::SUCCESS),
        Command::Convergence(args) => convergence::run_command(args).map(|()| ExitCode::SUCCESS),
        Command::Merge(args) => merge::run(args).map(|()| ExitCode::SUCCESS),
        Command::Validate(args) => validate::run(args).map(|()| ExitCode::SUCCESS),
        Command::Explore(args) => explore::run(args).map(|()| ExitCode::SUCCESS),
        Command::Stability(args) => stability::run(args),
    });
    finish(result)
}

/// On SIGINT or SIGTERM, removes the temporary files of writes in progress (a large EXR takes a
/// while) before the process exits with 128 + the signal's number, as a shell reports it.
///
/// The two signals are blocked in this thread before any other starts, so every thread inherits
/// the mask, and one thread of its own waits for them with `sigwait`: the cleanup then runs as
/// ordinary code, not in a signal handler. (Child processes start with an empty mask: the
/// standard library resets it.)
fn remove_temporaries_on_signals() {
    // SAFETY: sigemptyset/sigaddset initialise `set`; pthread_sigmask and sigwait only read it.
    let set = unsafe {
        let mut set: libc::sigset_t = std::mem::zeroed();
        libc::sigemptyset(&mut set);
        libc::sigaddset(&mut set, libc::SIGINT);
        libc::sigaddset(&mut set, libc::SIGTERM);
        libc::pthread_sigmask(libc::SIG_BLOCK, &set, std::ptr::null_mut());
        set
    };
    std::thread::spawn(move || {
        let mut signal = 0;
        // SAFETY: `set` is an initialised signal set, `signal` a valid place for the result.
        if unsafe { libc::sigwait(&set, &mut signal) } == 0 {
            pointshade::output::atomic::remove_pending();
            std::process::exit(128 + signal);
        }
    });
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
