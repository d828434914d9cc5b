//! `pointshade export-mitsuba`: a scene as Mitsuba 3 XML.

use std::path::PathBuf;

use crate::cli::options::option_error;
use crate::error::InputError;
use crate::film::SamplerKind;
use crate::output::write_all_or_nothing;
use crate::scene;
use crate::validation::mitsuba::{export, BsdfChoice};

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
    let mut scene = scene::load(&args.scene)?;
    if let Some(name) = &args.sampler {
        scene.film.sampler = SamplerKind::parse(name).map_err(|e| option_error("--sampler", e))?;
    }
    if let Some(spp) = args.spp {
        scene.film.spp = spp;
    }
    // Mitsuba renders a sample count; a budget's count is only known once pointshade has run.
    if scene.film.time_budget.take().is_some() && args.spp.is_none() {
        return Err(option_error(
            "--spp",
            "the scene renders to a time budget, which the Mitsuba export cannot: give the sample count with --spp",
        ));
    }
    scene.film.validate().map_err(|e| option_error("--spp", e))?;
    let choice = if args.plugin_everywhere {
        BsdfChoice::PluginEverywhere
    } else {
        BsdfChoice::NativeWhereExact
    };
    // Mesh files (glTF meshes, OBJs of several materials) go beside the XML, named after it.
    let prefix = args.output.file_stem().map_or("scene".into(), |s| s.to_string_lossy());
    let e = export(&scene, scene.film.spp, choice, &prefix);
    let dir = args.output.parent().unwrap_or(std::path::Path::new("."));
    let mut files = vec![(args.output.clone(), e.scene.clone().into_bytes())];
    files.extend(e.meshes.iter().map(|(name, bytes)| (dir.join(name), bytes.clone())));
    if args.per_light {
        let stem = args.output.with_extension("");
        for (suffix, xml) in e.passes() {
            files.push((
                PathBuf::from(format!("{}.{suffix}.xml", stem.display())),
                xml.as_bytes().to_vec(),
            ));
        }
    }
    write_all_or_nothing(&files)?;
    for note in &e.material_notes {
        eprintln!("material {note}");
    }
    for d in &e.differences {
        eprintln!("no Mitsuba equivalent: {d}");
    }
    Ok(())
}
