//! `pointshade explore`: the interactive explorer's server (`pointshade::explore`), its address
//! printed, until Ctrl-C.

use std::io::Write;
use std::path::PathBuf;

use crate::options::option_error;
use pointshade::error::InputError;
use pointshade::explore::server::Server;
use pointshade::explore::{Explorer, Mode};

/// Arguments of `pointshade explore`.
#[derive(clap::Args)]
pub struct ExploreArgs {
    /// A PNG normal image, a scene file (.toml), a bare mesh (.obj) or a glTF file; without one,
    /// the assignment's setting on a normal image baked from the shipped scenes/lambert.toml.
    input: Option<PathBuf>,
    /// Port on 127.0.0.1 (default: a free one).
    #[arg(long, default_value_t = 0)]
    port: u16,
    /// Open the page in the system's browser.
    #[arg(long)]
    open: bool,
    /// The validation folder whose Mitsuba 3 (installed by its install.sh) the page's
    /// "Compare with Mitsuba" button runs.
    #[arg(long, default_value = pointshade::explore::DEFAULT_MITSUBA_DIR)]
    mitsuba_dir: PathBuf,
}

/// Runs `pointshade explore`.
pub fn run(args: ExploreArgs) -> Result<(), InputError> {
    let mut explorer = Explorer::open(args.input.as_deref())?;
    explorer.set_mitsuba_dir(args.mitsuba_dir);
    let what = match explorer.mode() {
        Mode::NormalImage => "normal image",
        Mode::Scene => "scene",
    };
    let name = explorer.name().to_string();
    let server = Server::start(explorer, args.port).map_err(|e| option_error("--port", e))?;
    let url = server.url();
    let mut out = std::io::stdout().lock();
    // The address first, on a line of its own: scripts and tests read it.
    let _ = writeln!(out, "{url}");
    let _ = writeln!(out, "pointshade explore: {name} ({what}); Ctrl-C stops it");
    let _ = out.flush();
    drop(out);
    if args.open {
        open_browser(&url);
    }
    server.wait();
    Ok(())
}

/// Asks the desktop to open `url`; says so when it cannot (the page is still served).
fn open_browser(url: &str) {
    let opener = match std::env::consts::OS {
        "macos" => "open",
        "windows" => "explorer",
        _ => "xdg-open",
    };
    if let Err(e) = std::process::Command::new(opener).arg(url).spawn() {
        eprintln!("warning: could not open a browser ({opener}: {e}); open {url} yourself");
    }
}
