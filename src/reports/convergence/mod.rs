//! Error against run time: renders a scene at increasing sample counts or time budgets with
//! pointshade (and, optionally, Mitsuba 3 at sample counts in the same run), times each render
//! (median of repeats, scene load included), measures its error against a reference, and writes
//! a CSV and a log-log plot.
//!
//! Time is what a user waits for: scene loading (files parsed again each repeat), BVH build and
//! rendering for pointshade; scene loading (with kernel compilation) and rendering for Mitsuba,
//! as its Python side measures them — Python's own start-up is left out.

pub mod plot;
pub mod point;

pub use plot::ErrorMetric;
pub use point::Point;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use crate::error::{InputError, InputResult};
use crate::film::compare::compare;
use crate::film::{time_budget_defaults, FilmSettings, Image, SamplerKind};
use crate::output::{encode, write_all_or_nothing, Format};
use crate::render::request::{load_sampled, render_timed};
use crate::scene::shadows::ShadowOffset;
use crate::scene::Scene;
use crate::validation::mitsuba::{export, BsdfChoice};
use crate::validation::run::{MitsubaJob, MitsubaRunner};

/// Relative tolerance of the "within" column.
pub const TOLERANCE: f32 = 1e-3;

/// What the sweep runs.
#[derive(Clone, Debug)]
pub struct Sweep {
    /// The scene file.
    pub scene: PathBuf,
    /// Sample counts.
    pub spp: Vec<u32>,
    /// pointshade samplers.
    pub samplers: Vec<SamplerKind>,
    /// Repeats per point (the median is kept).
    pub repeats: u32,
    /// Shadow-ray offset of pointshade's renders (`mitsuba` when comparing with Mitsuba).
    pub shadow_offset: ShadowOffset,
    /// The adaptive sampler's thresholds (empty: the scene's). With more than one, the adaptive
    /// sampler is swept over them at the largest sample count (its cap) instead of over the
    /// sample counts: the threshold is what trades its error for time; the cap only bounds it.
    pub adaptive_thresholds: Vec<f32>,
    /// Time budgets in seconds (empty: none). Given some, every sampler but the grid also runs
    /// once per budget (a line of its own on the plot), with the caps of a budget
    /// ([`time_budget_defaults`]); the adaptive samplers' finest threshold is then the smallest
    /// of `adaptive_thresholds`, if any.
    pub time_budgets: Vec<f32>,
    /// Run Mitsuba's grid and independent samplers too.
    pub mitsuba: Option<MitsubaRunner>,
    /// Folder for the outputs (and Mitsuba's scene files).
    pub out: PathBuf,
}

/// The reference image and what it is.
pub struct Reference {
    /// The image.
    pub image: Image,
    /// A description for the plot and the CSV.
    pub description: String,
}

fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    s[s.len() / 2]
}

/// One pointshade render of the sweep: sampler, sample count (the cap, for the adaptive
/// samplers and time budgets), the adaptive threshold if not the scene's, and the time budget.
type OurRun = (SamplerKind, u32, Option<f32>, Option<f32>);

fn load(sweep: &Sweep, (sampler, spp, threshold, budget): OurRun) -> InputResult<Scene> {
    let mut scene = load_sampled(&sweep.scene, sampler, spp)?;
    if let Some(t) = threshold {
        scene.film.adaptive_threshold = t;
    }
    scene.film.time_budget = budget;
    scene.film.validate().map_err(|e| InputError::new(&sweep.scene, e))?;
    Ok(scene)
}

impl Sweep {
    /// The sample counts `sampler` takes (the grid: the square ones).
    fn counts(&self, sampler: SamplerKind) -> impl Iterator<Item = u32> + '_ {
        self.spp
            .iter()
            .copied()
            .filter(move |&spp| sampler.check_spp(spp).is_ok())
    }

    /// pointshade's renders: each sampler at each sample count it takes (the grid: the square
    /// ones), except the adaptive samplers given several thresholds, which take each threshold
    /// at the largest count; then, given time budgets, every sampler but the grid takes each
    /// budget as well, so that one plot shows what a budget costs against the count or
    /// threshold it reaches.
    fn ours(&self) -> Vec<OurRun> {
        let mut renders = Vec::new();
        for &sampler in &self.samplers {
            let counts = self.counts(sampler);
            let thresholds = self.adaptive_thresholds.as_slice();
            if sampler.is_adaptive() && thresholds.len() > 1 {
                let cap = counts.max().unwrap_or(1);
                renders.extend(thresholds.iter().map(|&t| (sampler, cap, Some(t), None)));
            } else if sampler.is_adaptive() {
                renders.extend(counts.map(|spp| (sampler, spp, thresholds.first().copied(), None)));
            } else {
                renders.extend(counts.map(|spp| (sampler, spp, None, None)));
            }
            if sampler.takes_time_budget() {
                let (cap, finest) = time_budget_defaults(sampler);
                let finest = thresholds.iter().copied().reduce(f32::min).unwrap_or(finest);
                let finest = sampler.is_adaptive().then_some(finest);
                renders.extend(self.time_budgets.iter().map(|&b| (sampler, cap, finest, Some(b))));
            }
        }
        renders
    }
}

/// Checks what can fail before anything is rendered or written: every sampler takes some of
/// the sample counts, the scene loads, its film is valid for every render of the sweep (sampler,
/// count and threshold), and `reference` has its size.
pub fn check(sweep: &Sweep, reference: Option<&Reference>) -> InputResult<()> {
    if !sweep.time_budgets.is_empty() && !sweep.samplers.iter().any(|s| s.takes_time_budget()) {
        return Err(InputError::new(
            "--time-budget",
            "the grid cannot add samples to a budget: add another sampler to --sampler",
        ));
    }
    for &sampler in &sweep.samplers {
        if sweep.counts(sampler).next().is_none() {
            let why = sampler.check_spp(sweep.spp[0]).unwrap_err();
            return Err(InputError::new(
                "--spp",
                format!("no count for the {} sampler: {why}", sampler.name()),
            ));
        }
    }
    let renders = sweep.ours();
    let (sampler, spp, ..) = renders[0];
    let film = load(sweep, (sampler, spp, None, None))?.film;
    for (sampler, spp, threshold, time_budget) in renders {
        let film = FilmSettings {
            sampler,
            spp,
            adaptive_threshold: threshold.unwrap_or(film.adaptive_threshold),
            time_budget,
            ..film.clone()
        };
        film.validate().map_err(|e| InputError::new(&sweep.scene, e))?;
    }
    match reference {
        Some(r) if (r.image.width, r.image.height) != (film.width, film.height) => {
            Err(size_mismatch(r, film.width, film.height))
        }
        _ => Ok(()),
    }
}

fn size_mismatch(reference: &Reference, width: u32, height: u32) -> InputError {
    InputError::new(
        "--reference",
        format!(
            "is {}×{}, the scene renders {width}×{height}",
            reference.image.width, reference.image.height
        ),
    )
}

/// One timed pointshade render.
struct OurRender {
    image: Image,
    /// Samples per pixel: the film's, or the count the time budget reached.
    spp: u32,
    /// Samples per pixel taken, on average.
    mean_spp: f64,
    /// The threshold the adaptive sampler used (adaptive renders only).
    threshold: Option<f32>,
    /// Load + plan + BVH + render.
    time: Duration,
}

/// One pointshade render: load + plan + BVH + render, timed.
fn render_once(sweep: &Sweep, run: OurRun) -> InputResult<OurRender> {
    let start = Instant::now();
    let scene = load(sweep, run)?;
    let (rendered, _) = render_timed(&scene, sweep.shadow_offset)?;
    let time = start.elapsed();
    let pixels = (rendered.image.width * rendered.image.height) as f64;
    Ok(OurRender {
        image: rendered.image,
        spp: rendered.spp,
        mean_spp: rendered.stats.primary_rays as f64 / pixels,
        threshold: rendered.adaptive_threshold,
        time,
    })
}

/// A pointshade reference when none is given: 32×32 grid samples per pixel.
pub fn own_reference(sweep: &Sweep) -> InputResult<Reference> {
    let ours = render_once(sweep, (SamplerKind::Grid, 1024, None, None))?;
    Ok(Reference {
        image: ours.image,
        description: format!(
            "pointshade 32×32 grid ({:.1} s), no external reference given",
            ours.time.as_secs_f64()
        ),
    })
}

/// A point without its times yet: what `image` (taking `mean_spp` samples per pixel) scores
/// against the reference.
fn point(
    renderer: &'static str,
    (sampler, spp, threshold, time_budget): (&str, u32, Option<f32>, Option<f32>),
    mean_spp: f64,
    image: &Image,
    reference: &Reference,
) -> InputResult<Point> {
    if (image.width, image.height) != (reference.image.width, reference.image.height) {
        return Err(size_mismatch(reference, image.width, image.height));
    }
    let c = compare(image, &reference.image, TOLERANCE, 0);
    Ok(Point {
        renderer,
        sampler: sampler.to_string(),
        spp,
        threshold,
        time_budget,
        mean_spp,
        seconds: 0.0,
        all_seconds: Vec::new(),
        rmse: c.rmse,
        rel_mse: c.rel_mse,
        within: c.within_tolerance,
    })
}

/// One configuration of the sweep.
enum Config<'a> {
    Ours(OurRun),
    Mitsuba(SamplerKind, u32, &'a MitsubaRunner, MitsubaJob, PathBuf),
}

impl Config<'_> {
    /// Renders once; returns the seconds, and the scored point on the first repeat, or on every
    /// repeat for a time budget (whose sample count, and so error, varies from run to run).
    fn measure(&self, sweep: &Sweep, reference: &Reference, first: bool) -> InputResult<(f64, Option<Point>)> {
        match self {
            &Config::Ours(run) => {
                let ours = render_once(sweep, run)?;
                let (sampler, _, _, budget) = run;
                let what = (sampler.name(), ours.spp, ours.threshold, budget);
                let point = (first || budget.is_some())
                    .then(|| point("pointshade", what, ours.mean_spp, &ours.image, reference))
                    .transpose()?;
                Ok((ours.time.as_secs_f64(), point))
            }
            Config::Mitsuba(sampler, spp, mitsuba, job, out) => {
                let t = mitsuba.render_job(job, out)?;
                let point = if first {
                    let image = crate::output::read_linear(out)?;
                    Some(point(
                        "mitsuba",
                        (sampler.name(), *spp, None, None),
                        *spp as f64,
                        &image,
                        reference,
                    )?)
                } else {
                    None
                };
                Ok(((t.load + t.render).as_secs_f64(), point))
            }
        }
    }
}

/// Runs the sweep; `progress` receives one line per finished point.
///
/// The repeats go round-robin over every configuration (each renderer, sampler and sample
/// count once, then again): a slow spell of a shared machine then slows every configuration
/// alike instead of all the repeats of one renderer's (sweeps that ran the renderers one after
/// the other put the same two points at ratios far apart; docs/performance-log.md).
pub fn run(sweep: &Sweep, reference: &Reference, progress: &mut dyn FnMut(&Point)) -> InputResult<Vec<Point>> {
    let mut configs: Vec<Config> = sweep.ours().into_iter().map(Config::Ours).collect();
    if let Some(mitsuba) = &sweep.mitsuba {
        let mut files_written = false;
        for sampler in [SamplerKind::Grid, SamplerKind::Independent] {
            for spp in sweep.counts(sampler) {
                let scene = load(sweep, (sampler, spp, None, None))?;
                let exported = export(&scene, spp, BsdfChoice::NativeWhereExact, "mitsuba");
                let stem = sweep.out.join(format!("mitsuba-{}-{spp}", sampler.name()));
                let size = (scene.film.width, scene.film.height);
                // Every export of the sweep references the same meshes and images: written once.
                let job = if files_written {
                    MitsubaJob::write_reusing_files(&exported, &stem, size)?
                } else {
                    MitsubaJob::write(&exported, &stem, size)?
                };
                files_written = true;
                configs.push(Config::Mitsuba(sampler, spp, mitsuba, job, stem.with_extension("exr")));
            }
        }
    }
    let repeats = sweep.repeats.max(1);
    let mut runs: Vec<Vec<(f64, Option<Point>)>> = configs.iter().map(|_| Vec::new()).collect();
    let mut points = Vec::new();
    for repeat in 0..repeats {
        for (config, runs) in configs.iter().zip(&mut runs) {
            runs.push(config.measure(sweep, reference, repeat == 0)?);
            if repeat + 1 == repeats {
                let point = summary(std::mem::take(runs));
                progress(&point);
                points.push(point);
            }
        }
    }
    Ok(points)
}

/// One configuration's point from its runs (seconds, and the point if that run was scored):
/// the median time of all runs, with the scored run of the median time among the scored ones
/// (the only one, unless every run was scored). The first run is always scored.
fn summary(runs: Vec<(f64, Option<Point>)>) -> Point {
    let all_seconds: Vec<f64> = runs.iter().map(|r| r.0).collect();
    let mut scored: Vec<(f64, Point)> = runs.into_iter().filter_map(|(t, p)| Some((t, p?))).collect();
    scored.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (_, point) = scored.swap_remove(scored.len() / 2);
    Point {
        seconds: median(&all_seconds),
        all_seconds,
        ..point
    }
}

/// The points as CSV, with the reference described in a leading comment line.
pub fn csv(points: &[Point], reference: &Reference) -> String {
    let mut s = format!("# reference: {}\n", reference.description);
    s.push_str(
        "renderer,sampler,spp,threshold,mean_spp,seconds_median,seconds_all,rmse,rel_mse,within_1e-3,time_budget\n",
    );
    for p in points {
        let all = p
            .all_seconds
            .iter()
            .map(|t| format!("{t:.4}"))
            .collect::<Vec<_>>()
            .join(" ");
        let threshold = p.threshold.map(|t| t.to_string()).unwrap_or_default();
        let budget = p.time_budget.map(|t| t.to_string()).unwrap_or_default();
        let _ = writeln!(
            s,
            "{},{},{},{threshold},{:.3},{:.4},{},{:.6e},{:.6e},{:.6},{budget}",
            p.renderer, p.sampler, p.spp, p.mean_spp, p.seconds, all, p.rmse, p.rel_mse, p.within
        );
    }
    s
}

/// Writes `convergence.csv` (every metric), `convergence.svg` and `convergence.png` (`metric`
/// against time) into `out`, and the reference as `reference.png` for a look. Returns a note
/// about the PNG's text when no system font was found.
pub fn write_outputs(
    out: &Path,
    scene_name: &str,
    points: &[Point],
    reference: &Reference,
    metric: ErrorMetric,
) -> InputResult<Option<String>> {
    let title = format!("{scene_name}: {} against time", metric.label());
    let svg = plot::svg(&title, &reference.description, points, metric)
        .map_err(|e| InputError::new(out.join("convergence.svg"), e))?;
    let (png, note) = plot::png(&title, &reference.description, points, metric)
        .map_err(|e| InputError::new(out.join("convergence.png"), e))?;
    let reference_png =
        encode(&reference.image, Format::Png, 0.0).map_err(|e| InputError::new(out.join("reference.png"), e))?;
    write_all_or_nothing(&[
        (out.join("convergence.csv"), csv(points, reference).into_bytes()),
        (out.join("convergence.svg"), svg.into_bytes()),
        (out.join("convergence.png"), png),
        (out.join("reference.png"), reference_png),
    ])?;
    Ok(note)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sweep(thresholds: &[f32]) -> Sweep {
        Sweep {
            scene: PathBuf::from("scene.toml"),
            spp: vec![1, 2, 4],
            samplers: vec![SamplerKind::Grid, SamplerKind::Adaptive],
            repeats: 1,
            shadow_offset: ShadowOffset::ErrorBound,
            adaptive_thresholds: thresholds.to_vec(),
            time_budgets: Vec::new(),
            mitsuba: None,
            out: PathBuf::from("out"),
        }
    }

    #[test]
    fn the_adaptive_sampler_is_swept_over_its_thresholds_only_when_given_several() {
        use SamplerKind::{Adaptive, Grid};
        // The grid takes the square counts; the adaptive sampler each count, at the scene's
        // threshold or the one given.
        let grid = [(Grid, 1, None, None), (Grid, 4, None, None)];
        let by_count = |t| [(Adaptive, 1, t, None), (Adaptive, 2, t, None), (Adaptive, 4, t, None)];
        assert_eq!(sweep(&[]).ours(), [&grid[..], &by_count(None)].concat());
        assert_eq!(sweep(&[0.01]).ours(), [&grid[..], &by_count(Some(0.01))].concat());
        // Several thresholds: each once, at the largest count.
        let by_threshold = [(Adaptive, 4, Some(0.02), None), (Adaptive, 4, Some(0.01), None)];
        assert_eq!(sweep(&[0.02, 0.01]).ours(), [&grid[..], &by_threshold].concat());
    }

    #[test]
    fn time_budgets_add_a_run_per_budget_to_every_sampler_but_the_grid() {
        use SamplerKind::{Adaptive, Grid, Independent, Sobol};
        let mut s = sweep(&[0.02, 0.005, 0.01]);
        s.samplers = vec![Sobol, Grid, Independent, Adaptive];
        s.time_budgets = vec![0.1, 0.3];
        let by_count = |k| [(k, 1, None, None), (k, 2, None, None), (k, 4, None, None)];
        let budgets = |k, finest| {
            let cap = time_budget_defaults(k).0;
            [(k, cap, finest, Some(0.1)), (k, cap, finest, Some(0.3))]
        };
        let grid = [(Grid, 1, None, None), (Grid, 4, None, None)];
        // Each sampler's own sweep first; the adaptive one's budgets refine down to the
        // smallest threshold given.
        let by_threshold = [0.02, 0.005, 0.01].map(|t| (Adaptive, 4, Some(t), None));
        assert_eq!(
            s.ours(),
            [
                &by_count(Sobol)[..],
                &budgets(Sobol, None),
                &grid,
                &by_count(Independent),
                &budgets(Independent, None),
                &by_threshold,
                &budgets(Adaptive, Some(0.005)),
            ]
            .concat()
        );
    }

    fn scored(rmse: f64) -> Option<Point> {
        Some(Point {
            renderer: "pointshade",
            sampler: "sobol".into(),
            spp: 1,
            threshold: None,
            time_budget: None,
            mean_spp: 1.0,
            seconds: 0.0,
            all_seconds: Vec::new(),
            rmse,
            rel_mse: 0.0,
            within: 0.0,
        })
    }

    #[test]
    fn a_point_is_its_scored_run_of_median_time() {
        // Scored once (the first run): that run's error, the median of all times.
        let p = summary(vec![(3.0, scored(0.5)), (1.0, None), (2.0, None)]);
        assert_eq!((p.rmse, p.seconds, p.all_seconds), (0.5, 2.0, vec![3.0, 1.0, 2.0]));
        // Scored every run (time budgets): the error of the run of median time.
        let p = summary(vec![(3.0, scored(0.1)), (1.0, scored(0.3)), (2.0, scored(0.2))]);
        assert_eq!((p.rmse, p.seconds), (0.2, 2.0));
    }
}
