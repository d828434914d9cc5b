//! Running both renderers on a scene and comparing them (what `pointshade validate` does).
//!
//! For each sample count (pixel centres, then an N×N grid), the scene is exported per light,
//! rendered by Mitsuba through `validation/render.py` (the lights summed), and rendered by
//! pointshade twice: with Mitsuba's fixed-epsilon shadow offset (the like-for-like comparison)
//! and with pointshade's default error-bound offset and smooth shadow origins (to show what
//! those choices change). Where the render samples textures, the like-for-like comparison also
//! counts the rounding band ([`rounding`]).

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use crate::error::{InputError, InputResult};
use crate::film::compare::{compare, compare_checked, Comparison};
use crate::film::{Image, SamplerKind};
use crate::output::{encode, read_linear, write_all_or_nothing, Format};
use crate::render::request::{load_sampled, render_timed, sampled};
use crate::render::Rendered;
use crate::scene::shadows::ShadowOffset;
use crate::scene::Scene;
use crate::validation::mitsuba::{export, BsdfChoice, MitsubaExport};
use crate::validation::rounding;

/// Agreement every exact scene must reach at the like-for-like setting.
pub const REQUIRED_WITHIN: f64 = 0.999;
/// Largest mean relative error an exact scene may have.
pub const REQUIRED_MEAN_RELATIVE_ERROR: f64 = 1e-4;
/// Per-pixel relative tolerance.
pub const TOLERANCE: f32 = 1e-3;

/// Where Mitsuba is and how to call it.
#[derive(Clone, Debug)]
pub struct MitsubaRunner {
    /// The Python of the validation virtual environment.
    pub python: PathBuf,
    /// `validation/render.py`.
    pub script: PathBuf,
    /// How long one Mitsuba run may take before it is stopped and reported (none: as long as
    /// it takes, as `pointshade validate` lets it).
    pub timeout: Option<Duration>,
}

impl MitsubaRunner {
    /// The runner for the validation folder `dir` (`validation/` of the repository); an error
    /// says how to install Mitsuba when it is missing.
    pub fn in_dir(dir: &Path) -> InputResult<Self> {
        let python = dir.join(".venv/bin/python");
        let script = dir.join("render.py");
        if !python.is_file() {
            return Err(InputError::new(
                &python,
                format!("Mitsuba is not installed: run {}/install.sh", dir.display()),
            ));
        }
        if !script.is_file() {
            return Err(InputError::new(
                &script,
                "missing (the validation folder of the repository)",
            ));
        }
        Ok(Self {
            python,
            script,
            timeout: None,
        })
    }

    /// This runner, each Mitsuba run stopped with an error after `limit` (an interactive caller
    /// must not wait for ever on a Mitsuba that hangs).
    pub fn with_timeout(self, limit: Duration) -> Self {
        Self {
            timeout: Some(limit),
            ..self
        }
    }

    /// Renders `xml_files` and writes their sum to `out`; returns the variant and the seconds
    /// Mitsuba spent loading and rendering (Python start-up excluded).
    fn render(&self, xml_files: &[PathBuf], out: &Path) -> InputResult<MitsubaTiming> {
        let mut command = Command::new(&self.python);
        command.arg(&self.script).arg("--out").arg(out).args(xml_files);
        let output = output_within(command, self.timeout)
            .map_err(|e| InputError::new(&self.python, format!("cannot run: {e}")))?
            .ok_or_else(|| {
                let limit = self.timeout.unwrap_or_default().as_secs_f64();
                InputError::new(
                    &xml_files[0],
                    format!("Mitsuba did not finish within {limit} s: stopped"),
                )
            })?;
        let stdout = String::from_utf8_lossy(&output.stdout);
        if !output.status.success() {
            let stderr = String::from_utf8_lossy(&output.stderr);
            let last = stderr
                .lines()
                .rev()
                .find(|l| !l.trim().is_empty())
                .unwrap_or("no message");
            return Err(InputError::new(&xml_files[0], format!("Mitsuba failed: {last}")));
        }
        MitsubaTiming::parse(&stdout)
            .ok_or_else(|| InputError::new(&self.script, format!("unexpected output: {stdout}")))
    }
}

/// `command`'s output, or `None` if it ran longer than `limit` (it is then killed; no limit:
/// it runs to its end). Its standard output and error are read while it runs, so that a full
/// pipe cannot stall it.
fn output_within(mut command: Command, limit: Option<Duration>) -> std::io::Result<Option<Output>> {
    let mut child = command.stdout(Stdio::piped()).stderr(Stdio::piped()).spawn()?;
    fn drain(pipe: Option<impl Read + Send + 'static>) -> std::thread::JoinHandle<Vec<u8>> {
        std::thread::spawn(move || {
            let mut bytes = Vec::new();
            if let Some(mut pipe) = pipe {
                let _ = pipe.read_to_end(&mut bytes);
            }
            bytes
        })
    }
    let stdout = drain(child.stdout.take());
    let stderr = drain(child.stderr.take());
    let status = match limit {
        None => child.wait()?,
        Some(limit) => {
            let deadline = Instant::now() + limit;
            loop {
                if let Some(status) = child.try_wait()? {
                    break status;
                }
                if Instant::now() >= deadline {
                    let _ = child.kill();
                    let _ = child.wait();
                    return Ok(None);
                }
                std::thread::sleep(Duration::from_millis(10));
            }
        }
    };
    Ok(Some(Output {
        status,
        stdout: stdout.join().unwrap_or_default(),
        stderr: stderr.join().unwrap_or_default(),
    }))
}

/// An export's per-light scenes written to disk, ready for Mitsuba to render and sum.
#[derive(Clone, Debug)]
pub struct MitsubaJob {
    xmls: Vec<PathBuf>,
    size: (u32, u32),
}

impl MitsubaJob {
    /// Writes `exported`'s passes as `{stem}.light{k}.xml` (and `{stem}.emission.xml`) and the
    /// mesh and image files they reference beside them, for a film of `size`.
    pub fn write(exported: &MitsubaExport, stem: &Path, size: (u32, u32)) -> InputResult<Self> {
        Self::write_with(exported, stem, size, true)
    }

    /// [`Self::write`] for an export of the same scene with the same file prefix into the same
    /// folder as one already written (another sample count, other BSDFs): the mesh and image
    /// files already there are the same, so only the XML files and the files not written yet
    /// (a Mitsuba bitmap reads the OBJ itself where the plugin reads a PLY part) are written.
    pub fn write_reusing_files(exported: &MitsubaExport, stem: &Path, size: (u32, u32)) -> InputResult<Self> {
        Self::write_with(exported, stem, size, false)
    }

    fn write_with(exported: &MitsubaExport, stem: &Path, size: (u32, u32), all_files: bool) -> InputResult<Self> {
        let dir = stem.parent().unwrap_or(Path::new("."));
        let xmls: Vec<(PathBuf, Vec<u8>)> = exported
            .passes()
            .into_iter()
            .map(|(suffix, xml)| {
                (
                    PathBuf::from(format!("{}.{suffix}.xml", stem.display())),
                    xml.as_bytes().to_vec(),
                )
            })
            .collect();
        let xml_paths = xmls.iter().map(|(p, _)| p.clone()).collect();
        let files = exported
            .meshes
            .iter()
            .map(|(name, bytes)| (dir.join(name), bytes))
            .filter(|(path, _)| all_files || !path.is_file())
            .map(|(path, bytes)| (path, bytes.clone()));
        write_all_or_nothing(&xmls.into_iter().chain(files).collect::<Vec<_>>())?;
        Ok(Self { xmls: xml_paths, size })
    }
}

impl MitsubaRunner {
    /// Renders `job` (its lights summed) into `out`. A scene without lights is black in both
    /// renderers: the black image is written without running Mitsuba.
    pub fn render_job(&self, job: &MitsubaJob, out: &Path) -> InputResult<MitsubaTiming> {
        if job.xmls.is_empty() {
            write_image(out, &Image::new(job.size.0, job.size.1))?;
            return Ok(MitsubaTiming {
                variant: "none (no lights)".into(),
                load: Duration::ZERO,
                render: Duration::ZERO,
            });
        }
        self.render(&job.xmls, out)
    }
}

/// What `render.py` reports.
#[derive(Clone, Debug, PartialEq)]
pub struct MitsubaTiming {
    /// The Mitsuba variant used.
    pub variant: String,
    /// Scene loading (includes kernel compilation in llvm variants).
    pub load: Duration,
    /// Rendering.
    pub render: Duration,
}

impl MitsubaTiming {
    /// Parses `{"variant": "…", "load_s": …, "render_s": …}` (the last line of `stdout`).
    fn parse(stdout: &str) -> Option<Self> {
        let line = stdout.lines().rev().find(|l| l.trim_start().starts_with('{'))?;
        let field = |name: &str| -> Option<&str> {
            let start = line.find(&format!("\"{name}\":"))? + name.len() + 3;
            let rest = line[start..].trim_start();
            let end = rest.find([',', '}']).unwrap_or(rest.len());
            Some(rest[..end].trim().trim_matches('"'))
        };
        let seconds = |name| field(name)?.parse::<f64>().ok().filter(|s| s.is_finite() && *s >= 0.0);
        Some(Self {
            variant: field("variant")?.to_string(),
            load: Duration::from_secs_f64(seconds("load_s")?),
            render: Duration::from_secs_f64(seconds("render_s")?),
        })
    }
}

/// pointshade's side of one comparison.
#[derive(Clone, Debug)]
pub struct OurRun {
    /// The shadow offset used.
    pub offset: ShadowOffset,
    /// Agreement with Mitsuba.
    pub comparison: Comparison,
    /// Plan + BVH + render time.
    pub time: Duration,
}

/// Both renderers at one sample count.
#[derive(Clone, Debug)]
pub struct SppRun {
    /// Samples per pixel (a square: grid sampler).
    pub spp: u32,
    /// Mitsuba's timing.
    pub mitsuba: MitsubaTiming,
    /// pointshade with Mitsuba's offset, then with its own.
    pub ours: Vec<OurRun>,
    /// Image files written for the report, relative to the report folder: ours (Mitsuba offset),
    /// Mitsuba, heat map (Mitsuba offset), heat map (default offset).
    pub images: [String; 4],
}

/// Everything validated about one scene.
#[derive(Clone, Debug)]
pub struct SceneValidation {
    /// Scene name (file stem).
    pub name: String,
    /// The scene file.
    pub source: PathBuf,
    /// Features Mitsuba cannot express (empty = the comparison must agree).
    pub differences: Vec<String>,
    /// How each material was mapped.
    pub material_notes: Vec<String>,
    /// One run per sample count.
    pub runs: Vec<SppRun>,
    /// Where some material maps to a native Mitsuba BSDF: Mitsuba with pointshade's plugin for
    /// every material against Mitsuba with its own BSDFs, at pixel centres (checks the plugin).
    pub plugin_check: Option<Comparison>,
}

impl SceneValidation {
    /// True when the scene has an exact Mitsuba equivalent.
    pub fn is_exact(&self) -> bool {
        self.differences.is_empty()
    }

    /// True when every like-for-like run of an exact scene meets the thresholds (always true for
    /// scenes without an exact equivalent: their differences are expected), and the plugin
    /// agrees with Mitsuba's own BSDFs where that was checked.
    pub fn passes(&self) -> bool {
        let plugin_ok = self.plugin_check.as_ref().is_none_or(meets_thresholds);
        plugin_ok && (!self.is_exact() || self.runs.iter().all(|r| meets_thresholds(&r.ours[0].comparison)))
    }
}

/// Whether a comparison meets [`REQUIRED_WITHIN`] (counting the rounding band where it was
/// measured: [`rounding`]) and [`REQUIRED_MEAN_RELATIVE_ERROR`].
pub fn meets_thresholds(c: &Comparison) -> bool {
    c.within_rounding_band.unwrap_or(c.within_tolerance) >= REQUIRED_WITHIN
        && c.mean_relative_error <= REQUIRED_MEAN_RELATIVE_ERROR
}

/// [`rounding::within_band`] of `c`, pointshade's render of `scene` against `reference` with
/// Mitsuba's shadow offset: `scene` rendered again with its texture coordinates one ulp up and
/// one ulp down. `None` when the render samples no texture.
pub fn rounding_band(scene: &Scene, reference: &Image, c: &Comparison) -> InputResult<Option<f64>> {
    let mut nudged = Vec::new();
    for up in [true, false] {
        let Some(s) = rounding::nudged_texture_coordinates(scene, up) else {
            return Ok(None);
        };
        let image = render_timed(&s, ShadowOffset::Mitsuba)?.0.image;
        nudged.push(compare(&image, reference, c.tolerance, 0));
    }
    Ok(Some(rounding::within_band(c, &nudged)))
}

/// Validates one scene at pixel centres and on a `grid`×`grid` grid, writing the files of the
/// report under `report_dir/<name>/`.
pub fn validate_scene(
    path: &Path,
    grid: u32,
    mitsuba: &MitsubaRunner,
    report_dir: &Path,
) -> InputResult<SceneValidation> {
    let name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".into());
    let dir = report_dir.join(&name);
    std::fs::create_dir_all(&dir).map_err(|e| InputError::new(&dir, format!("cannot create: {e}")))?;
    let mut counts = vec![1];
    if grid > 1 {
        counts.push(grid * grid);
    }
    let mut result = SceneValidation {
        name: name.clone(),
        source: path.to_path_buf(),
        differences: Vec::new(),
        material_notes: Vec::new(),
        runs: Vec::new(),
        plugin_check: None,
    };
    for (k, spp) in counts.into_iter().enumerate() {
        let scene = load_sampled(path, SamplerKind::Grid, spp)?;
        // The meshes and images are the same at every sample count: written once.
        let stem = dir.join(format!("mitsuba-spp{spp}"));
        let (exported, reference, timing) = mitsuba_reference(&scene, mitsuba, &stem, k > 0)?;
        result.differences = exported.differences.clone();
        result.material_notes = exported.material_notes.clone();
        write_all_or_nothing(&[(
            dir.join(format!("mitsuba-spp{spp}.xml")),
            exported.scene.clone().into_bytes(),
        )])?;
        if spp == 1 && exported.material_notes.iter().any(|n| n.contains("exact)")) && !exported.per_light.is_empty() {
            result.plugin_check = Some(plugin_against_native(&scene, &dir, mitsuba, &reference)?);
        }
        let mut ours = Vec::new();
        let mut heat = Vec::new();
        for offset in [ShadowOffset::Mitsuba, ShadowOffset::ErrorBound] {
            let (Rendered { image, .. }, time) = render_timed(&scene, offset)?;
            let mut comparison = compare(&image, &reference, TOLERANCE, 8);
            if offset == ShadowOffset::Mitsuba {
                comparison.within_rounding_band = rounding_band(&scene, &reference, &comparison)?;
            }
            let stem = format!("ours-spp{spp}-{}", offset.name());
            write_image(&dir.join(format!("{stem}.exr")), &image)?;
            write_image(&dir.join(format!("{stem}.png")), &image)?;
            let heat_name = format!("heat-spp{spp}-{}.png", offset.name());
            write_image(&dir.join(&heat_name), &comparison.heat_map(image.width, image.height))?;
            heat.push(heat_name);
            ours.push(OurRun {
                offset,
                comparison,
                time,
            });
        }
        write_image(&dir.join(format!("mitsuba-spp{spp}.png")), &reference)?;
        result.runs.push(SppRun {
            spp,
            mitsuba: timing,
            ours,
            images: [
                format!("{name}/ours-spp{spp}-mitsuba.png"),
                format!("{name}/mitsuba-spp{spp}.png"),
                format!("{name}/{}", heat[0]),
                format!("{name}/{}", heat[1]),
            ],
        });
    }
    Ok(result)
}

/// Mitsuba's render of `scene` at its film's sample count (its lights summed), read back from
/// `{stem}.exr`, and the export it rendered; the export's files are written beside `stem`
/// (`reuse`: the mesh and image files of an earlier export of the same scene are there).
fn mitsuba_reference(
    scene: &Scene,
    mitsuba: &MitsubaRunner,
    stem: &Path,
    reuse: bool,
) -> InputResult<(MitsubaExport, Image, MitsubaTiming)> {
    let exported = export(scene, scene.film.spp, BsdfChoice::NativeWhereExact, "mitsuba");
    let size = (scene.film.width, scene.film.height);
    let job = match reuse {
        true => MitsubaJob::write_reusing_files(&exported, stem, size)?,
        false => MitsubaJob::write(&exported, stem, size)?,
    };
    let reference_path = PathBuf::from(format!("{}.exr", stem.display()));
    let timing = mitsuba.render_job(&job, &reference_path)?;
    Ok((exported, read_linear(&reference_path)?, timing))
}

/// One like-for-like comparison: pointshade and Mitsuba at pixel centres with Mitsuba's
/// shadow offset (what [`validate_scene`] does first; what the explorer's Mitsuba button shows).
#[derive(Clone, Debug)]
pub struct PixelCentreComparison {
    /// pointshade's render.
    pub ours: Image,
    /// Mitsuba's.
    pub reference: Image,
    /// Their agreement (NaN and infinite pixels counted as mismatches).
    pub comparison: Comparison,
    /// Mitsuba's variant and times.
    pub mitsuba: MitsubaTiming,
    /// What Mitsuba cannot express of the scene (empty: the two should agree).
    pub differences: Vec<String>,
}

/// [`PixelCentreComparison`] of `scene` (its film at one sample per pixel on the grid sampler),
/// Mitsuba's files written into the folder `dir`.
pub fn compare_at_pixel_centres(
    scene: &Scene,
    mitsuba: &MitsubaRunner,
    dir: &Path,
) -> InputResult<PixelCentreComparison> {
    let scene = sampled(scene.clone(), SamplerKind::Grid, 1)?;
    let (exported, reference, timing) = mitsuba_reference(&scene, mitsuba, &dir.join("mitsuba"), false)?;
    let ours = render_timed(&scene, ShadowOffset::Mitsuba)?.0.image;
    let mut comparison = compare_checked(&ours, &reference, TOLERANCE, 8, true)
        .map_err(|(_, e)| InputError::new(&scene.source, format!("against Mitsuba: {e}")))?;
    comparison.within_rounding_band = rounding_band(&scene, &reference, &comparison)?;
    Ok(PixelCentreComparison {
        ours,
        reference,
        comparison,
        mitsuba: timing,
        differences: exported.differences,
    })
}

/// Renders `scene` in Mitsuba with the plugin for every material and compares with `native`.
fn plugin_against_native(
    scene: &Scene,
    dir: &Path,
    mitsuba: &MitsubaRunner,
    native: &Image,
) -> InputResult<Comparison> {
    let exported = export(scene, 1, BsdfChoice::PluginEverywhere, "mitsuba");
    let size = (scene.film.width, scene.film.height);
    // Called after the pixel-centre export of the same scene: its meshes and images are there.
    let job = MitsubaJob::write_reusing_files(&exported, &dir.join("plugin-spp1"), size)?;
    let out = dir.join("plugin-spp1.exr");
    mitsuba.render_job(&job, &out)?;
    Ok(compare(&read_linear(&out)?, native, TOLERANCE, 3))
}

fn write_image(path: &Path, image: &Image) -> InputResult<()> {
    let bytes = encode(image, Format::of(path)?, 0.0).map_err(|e| InputError::new(path, e))?;
    write_all_or_nothing(&[(path.to_path_buf(), bytes)])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_mitsuba_that_hangs_is_stopped_at_the_runners_time_limit() {
        use std::os::unix::fs::PermissionsExt;
        let dir = std::env::temp_dir().join(format!("pointshade-hanging-mitsuba-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let python = dir.join("python");
        std::fs::write(&python, "#!/bin/sh\necho started\nsleep 30\n").unwrap();
        std::fs::set_permissions(&python, std::fs::Permissions::from_mode(0o755)).unwrap();
        let runner = MitsubaRunner {
            python,
            script: dir.join("render.py"),
            timeout: None,
        }
        .with_timeout(Duration::from_millis(300));
        let start = Instant::now();
        let e = runner
            .render(&[dir.join("scene.xml")], &dir.join("out.exr"))
            .unwrap_err();
        assert!(e.to_string().contains("Mitsuba did not finish within 0.3 s"), "{e}");
        assert!(start.elapsed() < Duration::from_secs(20), "stopped, not waited for");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn timing_line_is_parsed() {
        let t = MitsubaTiming::parse("noise\n{\"variant\": \"llvm_ad_rgb\", \"load_s\": 0.25, \"render_s\": 1.5}\n")
            .unwrap();
        assert_eq!(t.variant, "llvm_ad_rgb");
        assert_eq!(
            (t.load, t.render),
            (Duration::from_millis(250), Duration::from_millis(1500))
        );
        assert!(MitsubaTiming::parse("{\"variant\": \"x\", \"load_s\": nan, \"render_s\": 1}").is_none());
        assert!(MitsubaTiming::parse("Traceback …").is_none());
    }
}
