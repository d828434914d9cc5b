//! `pointshade export-mitsuba`: a scene as Mitsuba 3 XML.

use std::path::PathBuf;

use pointshade::error::InputError;
use pointshade::output::write_all_or_nothing;
use pointshade::scene;
use pointshade::validation::export::{export_files, ExportOptions};

/// Arguments of `pointshade export-mitsuba`.
#[derive(clap::Args)]
pub struct ExportArgs {
    /// Scene file (.toml) or mesh (.obj).
    scene: PathBuf,
    /// Output XML file. Meshes Mitsuba cannot read (glTF, OBJs of several materials) are
    /// written beside it as OUTPUT-STEM.object{i}.mat{m}.ply.
    #[arg(short, long)]
    output: PathBuf,
    /// Samples per pixel (default: the scene's).
    #[arg(long)]
    spp: Option<u32>,
    /// Sampler (default: the scene's): grid → Mitsuba's stratified without jitter, independent.
    #[arg(long)]
    sampler: Option<String>,
    /// Export the scene as `render --match RENDERER` renders it (mitsuba: the grid sampler), so
    /// that the two images compare pixel by pixel.
    #[arg(long = "match", value_name = "RENDERER")]
    matching: Option<String>,
    /// Also write one file per light (OUTPUT with .lightK.xml) and, if some material emits, the
    /// emission pass (.emission.xml): their renders sum to a deterministic reference.
    #[arg(long)]
    per_light: bool,
    /// Use the pointshade BSDF plugin for every material, even where Mitsuba has an exact BSDF.
    #[arg(long)]
    plugin_everywhere: bool,
}

/// Runs `pointshade export-mitsuba`.
pub fn run(args: ExportArgs) -> Result<(), InputError> {
    let scene = scene::load(&args.scene)?;
    let options = ExportOptions {
        spp: args.spp,
        sampler: args.sampler,
        matching: args.matching,
        per_light: args.per_light,
        plugin_everywhere: args.plugin_everywhere,
    };
    let (files, lines) = export_files(scene, &args.output, &options, &|key| format!("--{key}"))?;
    write_all_or_nothing(&files)?;
    for line in lines {
        eprintln!("{line}");
    }
    Ok(())
}
