//! A scene written as Mitsuba 3 XML files: what `pointshade export-mitsuba` and the Python
//! module's `Scene.export_mitsuba` write, prepared in memory so nothing is written on an error.

use std::path::{Path, PathBuf};

use crate::error::{InputError, InputResult};
use crate::film::SamplerKind;
use crate::scene::matching::Match;
use crate::scene::Scene;
use crate::validation::mitsuba::{export, BsdfChoice};

/// A file to write: its path and its bytes.
pub type OutputFile = (PathBuf, Vec<u8>);

/// How to export.
#[derive(Clone, Debug, Default)]
pub struct ExportOptions {
    /// Samples per pixel (default: the scene's).
    pub spp: Option<u32>,
    /// Sampler name (default: the scene's).
    pub sampler: Option<String>,
    /// A renderer to match (`mitsuba`: the grid sampler, as `render`'s `match` samples).
    pub matching: Option<String>,
    /// Also one file per light and the emission pass.
    pub per_light: bool,
    /// The pointshade BSDF plugin for every material.
    pub plugin_everywhere: bool,
}

/// The files of `scene` exported to `output` (the XML, meshes beside it named after it, and
/// with `per_light` the passes), and the lines to tell the user: material notes and what has no
/// Mitsuba equivalent. Errors name the option (`--spp`, `--sampler`) as `name` spells it.
pub fn export_files(
    mut scene: Scene,
    output: &Path,
    options: &ExportOptions,
    name: &dyn Fn(&str) -> String,
) -> InputResult<(Vec<OutputFile>, Vec<String>)> {
    let sampler = match &options.sampler {
        Some(s) => Some(SamplerKind::parse(s).map_err(|e| InputError::new(name("sampler"), e))?),
        None => None,
    };
    scene.film.sampler = sampler.unwrap_or(scene.film.sampler);
    if let Some(m) = &options.matching {
        let m = Match::parse(m).map_err(|e| InputError::new(name("match"), e))?;
        let keys = (name("sampler"), name("shadow_offset"));
        let problem = m.contradiction(sampler, None, (keys.0.as_str(), keys.1.as_str()));
        if let Some(problem) = problem {
            return Err(InputError::new(name("match"), problem));
        }
        m.apply(&mut scene);
    }
    if let Some(spp) = options.spp {
        scene.film.spp = spp;
    }
    // Mitsuba renders a sample count; a budget's count is only known once pointshade has run.
    if scene.film.time_budget.take().is_some() && options.spp.is_none() {
        return Err(InputError::new(
            name("spp"),
            "the scene renders to a time budget, which the Mitsuba export cannot: give the sample count",
        ));
    }
    scene.film.validate().map_err(|e| InputError::new(name("spp"), e))?;
    let choice = match options.plugin_everywhere {
        true => BsdfChoice::PluginEverywhere,
        false => BsdfChoice::NativeWhereExact,
    };
    // Mesh files (glTF meshes, OBJs of several materials) go beside the XML, named after it.
    let prefix = output.file_stem().map_or("scene".into(), |s| s.to_string_lossy());
    let e = export(&scene, scene.film.spp, choice, &prefix);
    let dir = output.parent().unwrap_or(Path::new("."));
    let mut files = vec![(output.to_path_buf(), e.scene.clone().into_bytes())];
    files.extend(e.meshes.iter().map(|(name, bytes)| (dir.join(name), bytes.clone())));
    if options.per_light {
        let stem = output.with_extension("");
        for (suffix, xml) in e.passes() {
            files.push((
                PathBuf::from(format!("{}.{suffix}.xml", stem.display())),
                xml.as_bytes().to_vec(),
            ));
        }
    }
    let mut lines: Vec<String> = e.material_notes.iter().map(|n| format!("material {n}")).collect();
    lines.extend(e.differences.iter().map(|d| format!("no Mitsuba equivalent: {d}")));
    Ok((files, lines))
}
