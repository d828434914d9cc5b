//! `pointshade convergence`: the CSV lists every point with a falling error, and the plots exist;
//! bad input fails before anything is rendered or written.

use crate::support::{self, Scratch};

use std::path::{Path, PathBuf};

/// A fresh folder for one test, and in it `small.toml`: the Lambert scene at `width`×`height`.
fn small_scene(test: &str, width: u32, height: u32) -> (Scratch, PathBuf) {
    let d = Scratch::new(&format!("convergence-{test}"));
    let lambert = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/lambert.toml")).unwrap();
    let meshes = Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes");
    let small = lambert
        .replace("width = 512", &format!("width = {width}"))
        .replace("height = 384", &format!("height = {height}"))
        .replace("../meshes", meshes.to_str().unwrap());
    let scene = d.write("small.toml", &small);
    (d, scene)
}

/// One test's sweep: its folder, the small scene in it, a reference and the output folder.
/// Dropping it removes the folder.
struct SweepFolder {
    /// Held for its drop.
    _dir: Scratch,
    scene: PathBuf,
    reference: PathBuf,
    out: PathBuf,
}

impl SweepFolder {
    /// A fresh folder for `test` with the Lambert scene at `width`×`height` and its reference.
    fn new(test: &str, width: u32, height: u32) -> Self {
        let (dir, scene) = small_scene(test, width, height);
        let reference = reference(&dir, &scene);
        Self {
            out: dir.path("out"),
            _dir: dir,
            scene,
            reference,
        }
    }

    /// Runs `pointshade convergence` with `options`.
    fn run(&self, options: &[&str]) -> std::process::Output {
        support::command()
            .args(["convergence", self.scene.to_str().unwrap(), "--reference"])
            .arg(&self.reference)
            .args(options)
            .arg("--out")
            .arg(&self.out)
            .output()
            .unwrap()
    }

    /// Runs a sweep that must succeed; returns its CSV's pointshade rows.
    fn rows(&self, options: &[&str]) -> Table {
        let r = self.run(options);
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        let csv = std::fs::read_to_string(self.out.join("convergence.csv")).unwrap();
        let split = |l: &str| l.split(',').map(str::to_string).collect::<Vec<_>>();
        let header = split(csv.lines().find(|l| l.starts_with("renderer,")).unwrap());
        let rows = csv
            .lines()
            .filter(|l| l.starts_with("pointshade,"))
            .map(split)
            .collect();
        Table { csv, header, rows }
    }

    /// Runs a sweep that must fail (`why`) before writing anything: the failure contract
    /// ([`support::assert_one_line_error`]) with the one line naming each of `says`, and no
    /// output folder.
    fn fails_before_writing(&self, options: &[&str], why: &str, says: &[&str]) {
        let r = self.run(options);
        assert!(!r.status.success(), "{why} must fail");
        support::assert_one_line_error(&r, says, &[&self.out]);
    }
}

/// The pointshade rows of a `convergence.csv`, read by the column names of its header.
struct Table {
    csv: String,
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl Table {
    /// The field `name` of each row of `sampler`'s (every row: `None`).
    fn column(&self, sampler: Option<&str>, name: &str) -> Vec<&str> {
        let at = |name: &str| {
            self.header
                .iter()
                .position(|c| c == name)
                .unwrap_or_else(|| panic!("no column {name}"))
        };
        let (s, k) = (at("sampler"), at(name));
        let rows = self.rows.iter().filter(|r| sampler.is_none_or(|want| r[s] == want));
        rows.map(|r| r[k].as_str()).collect()
    }

    /// The same, as numbers.
    fn numbers(&self, sampler: Option<&str>, name: &str) -> Vec<f64> {
        self.column(sampler, name).iter().map(|v| v.parse().unwrap()).collect()
    }
}

/// Renders `scene` with a 16×16 grid into `d/ref.exr`.
fn reference(d: &Path, scene: &Path) -> PathBuf {
    let reference = d.join("ref.exr");
    let r = support::pointshade(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        reference.to_str().unwrap(),
        "--sampler",
        "grid",
        "--spp",
        "256",
        "--quiet",
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    reference
}

#[test]
fn a_reference_of_another_size_fails_before_anything_is_written() {
    let mut sweep = SweepFolder::new("size", 48, 36);
    let other = SweepFolder::new("size-ref", 40, 30);
    sweep.reference = other.reference.clone();
    let why = "a 40×30 reference for a 48×36 scene";
    sweep.fails_before_writing(&["--spp", "1"], why, &["--reference", "40×30", "48×36"]);
}

#[test]
fn convergence_writes_csv_and_plots_with_falling_error() {
    let sweep = SweepFolder::new("sweep", 96, 72);
    let options = ["--spp", "1,4,16", "--sampler", "sobol,adaptive,grid", "--repeats", "2"];
    let table = sweep.rows(&options);
    // sobol and adaptive at 1, 4, 16; grid at the squares 1, 4, 16.
    assert_eq!(table.rows.len(), 9, "{}", table.csv);
    for sampler in ["sobol", "grid"] {
        let rmse = table.numbers(Some(sampler), "rmse");
        assert!(
            rmse.windows(2).all(|w| w[1] < w[0]),
            "{sampler}: error must fall with samples: {rmse:?}"
        );
    }
    for times in table.column(None, "seconds_all") {
        let times: Vec<f64> = times.split(' ').map(|t| t.parse().unwrap()).collect();
        assert_eq!(times.len(), 2, "two repeats timed");
    }
    for f in ["convergence.svg", "convergence.png", "reference.png"] {
        assert!(std::fs::metadata(sweep.out.join(f)).unwrap().len() > 1000, "{f}");
    }
    let svg = std::fs::read_to_string(sweep.out.join("convergence.svg")).unwrap();
    assert!(
        svg.contains("<svg") && svg.contains("polyline"),
        "the SVG has the error lines"
    );
}

#[test]
fn several_thresholds_trace_the_adaptive_sampler_at_its_largest_sample_count() {
    let sweep = SweepFolder::new("thresholds", 96, 72);
    let options = ["--spp", "1,4,16", "--sampler", "adaptive", "--repeats", "1"];
    let options = [&options[..], &["--adaptive-threshold", "0.2,0.05,0.01"]].concat();
    let table = sweep.rows(&options);
    // One point per threshold, each at the cap of 16 samples (not one per sample count).
    assert_eq!(table.numbers(None, "threshold"), [0.2, 0.05, 0.01], "{}", table.csv);
    assert!(
        table.column(None, "spp").iter().all(|&spp| spp == "16"),
        "{}",
        table.csv
    );
    // A lower threshold takes more samples and leaves less error.
    let mean_spp = table.numbers(None, "mean_spp");
    let rmse = table.numbers(None, "rmse");
    assert!(mean_spp.windows(2).all(|w| w[1] > w[0]), "samples: {mean_spp:?}");
    assert!(rmse.windows(2).all(|w| w[1] < w[0]), "error: {rmse:?}");
}

#[test]
fn a_threshold_list_with_a_bad_entry_fails_with_one_line_before_anything_is_written() {
    let sweep = SweepFolder::new("bad-threshold", 48, 36);
    for (list, says) in [
        ("0.01,x", "--adaptive-threshold"),
        ("0.01,NaN", "adaptive_threshold"),
        ("0.01,2", "adaptive_threshold"),
    ] {
        let options = ["--sampler", "adaptive", "--adaptive-threshold", list];
        sweep.fails_before_writing(&options, list, &[says]);
    }
    sweep.fails_before_writing(&["--metric", "mse"], "an unknown metric", &["--metric", "mse"]);
}

#[test]
#[cfg_attr(
    not(system_font),
    ignore = "needs a font: POINTSHADE_FONT or one of src/reports/convergence/fonts.txt"
)]
fn the_plot_shows_the_metric_asked_for() {
    let sweep = SweepFolder::new("metric", 48, 36);
    sweep.rows(&[
        "--spp",
        "1,4",
        "--sampler",
        "sobol",
        "--repeats",
        "1",
        "--metric",
        "rel-mse",
    ]);
    let svg = std::fs::read_to_string(sweep.out.join("convergence.svg")).unwrap();
    assert!(
        svg.contains("<text"),
        "a font was found at build time, so the plot has text"
    );
    assert!(svg.contains("relative MSE against time"), "the title names the metric");
    assert!(!svg.contains("RMSE"), "and RMSE appears nowhere");
}

#[test]
fn the_grid_takes_the_square_counts_and_fails_with_none() {
    let sweep = SweepFolder::new("grid-counts", 48, 36);
    // 2 is not square: the grid runs at 4 only, the other sampler at both.
    let table = sweep.rows(&["--spp", "2,4", "--sampler", "sobol,grid", "--repeats", "1"]);
    let runs: Vec<(&str, &str)> = table
        .column(None, "sampler")
        .into_iter()
        .zip(table.column(None, "spp"))
        .collect();
    assert_eq!(runs, [("sobol", "2"), ("sobol", "4"), ("grid", "4")], "{}", table.csv);
    std::fs::remove_dir_all(&sweep.out).unwrap();
    // No square count at all: one line, nothing written.
    let options = ["--spp", "2,3", "--sampler", "sobol,grid"];
    sweep.fails_before_writing(&options, "a grid with no square count", &["--spp", "grid"]);
}

#[test]
fn time_budgets_add_runs_to_every_sampler_but_the_grid() {
    let sweep = SweepFolder::new("budgets", 96, 72);
    let options = ["--spp", "1,4", "--sampler", "sobol,grid,cells", "--repeats", "1"];
    let table = sweep.rows(&[&options[..], &["--time-budget", "0.01,0.3"]].concat());
    // Each sampler's counts first, then (but for the grid) one run per budget.
    for sampler in ["sobol", "cells"] {
        assert_eq!(
            table.column(Some(sampler), "time_budget"),
            ["", "", "0.01", "0.3"],
            "{}",
            table.csv
        );
    }
    assert_eq!(table.column(Some("grid"), "time_budget"), ["", ""], "{}", table.csv);
    assert_eq!(table.column(Some("grid"), "spp"), ["1", "4"], "{}", table.csv);
    assert_eq!(table.column(Some("sobol"), "spp")[..2], ["1", "4"], "{}", table.csv);
    // Each budget's point is the count its run reached, at least the one first pass; thirty
    // times the budget reaches at least as many.
    let spp = &table.numbers(Some("sobol"), "spp")[2..];
    assert!(spp[0] >= 1.0 && spp[1] >= spp[0], "{}", table.csv);
    assert_eq!(spp, &table.numbers(Some("sobol"), "mean_spp")[2..], "{}", table.csv);
    // The cells' budget points name the threshold reached, a rung of the ladder down to
    // 1/1024, and the longer budget reaches one at least as fine.
    let ladder = pointshade::render::threshold_ladder(1.0 / 1024.0);
    let thresholds = &table.numbers(Some("cells"), "threshold")[2..];
    assert!(
        thresholds.iter().all(|&t| ladder.contains(&(t as f32))),
        "{}",
        table.csv
    );
    assert!(thresholds[1] <= thresholds[0], "{}", table.csv);
}

#[test]
fn time_budgets_with_the_grid_alone_or_with_a_bad_entry_fail_before_anything_is_written() {
    let sweep = SweepFolder::new("bad-budget", 48, 36);
    for (sampler, list, says) in [
        ("grid", "0.1", "--time-budget"),
        ("sobol", "0.1,x", "--time-budget"),
        ("sobol", "0.1,NaN", "time_budget"),
        ("independent", "0", "time_budget"),
    ] {
        let options = ["--sampler", sampler, "--time-budget", list];
        sweep.fails_before_writing(&options, list, &[says]);
    }
}
