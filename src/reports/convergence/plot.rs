//! The convergence plot: RMSE against seconds, both axes logarithmic, one line per renderer and
//! sampler (plotters; SVG and PNG from the same drawing code). The adaptive sampler's line runs
//! through its sample counts or, when it was swept over several thresholds, through those; a
//! sampler rendered to time budgets has a second, dashed line through them.
//!
//! Text needs a font: the first of a few common system fonts (or `POINTSHADE_FONT`) is
//! registered with plotters. Without one the plot is drawn without text and a note says so.

use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::point::Point;

const SIZE: (u32, u32) = (960, 640);

/// Where fonts are usually found (Debian's fonts-dejavu-core, fonts-liberation; other layouts),
/// one path a line; build.rs reads the same file to tell the tests whether text can be drawn.
const FONT_CANDIDATES: &str = include_str!("fonts.txt");

/// Registers a system font as "sans-serif" once; false when none could be read.
fn font_available() -> bool {
    static FOUND: OnceLock<bool> = OnceLock::new();
    *FOUND.get_or_init(|| {
        let from_env = std::env::var("POINTSHADE_FONT").ok();
        for path in from_env.iter().map(String::as_str).chain(FONT_CANDIDATES.lines()) {
            if let Ok(bytes) = std::fs::read(path) {
                // plotters keeps fonts for the life of the program.
                let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
                if plotters::style::register_font("sans-serif", FontStyle::Normal, bytes).is_ok() {
                    return true;
                }
            }
        }
        false
    })
}

/// Colour of a series.
fn colour(renderer: &str, sampler: &str) -> RGBColor {
    match (renderer, sampler) {
        ("pointshade", "adaptive") => RGBColor(0, 140, 60),
        ("pointshade", "cells") => RGBColor(150, 190, 0),
        ("pointshade", "sobol") => RGBColor(30, 90, 220),
        ("pointshade", "grid") => RGBColor(120, 60, 200),
        ("pointshade", _) => RGBColor(0, 170, 200),
        ("mitsuba", "grid") => RGBColor(210, 30, 30),
        _ => RGBColor(240, 140, 0),
    }
}

/// What the plot's vertical axis shows: one of the errors every point has (`convergence.csv`
/// has all three).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ErrorMetric {
    /// Root mean squared error, the benchmark's measure.
    #[default]
    Rmse,
    /// Relative MSE (squared error over the reference's squared value + 1e-2), the usual measure
    /// in rendering papers: an error in a dark pixel weighs as much as a proportionate one in a
    /// bright pixel.
    RelMse,
    /// The share of pixels off the reference by more than 1e-3 (1 − `within_1e-3`).
    Outside,
}

impl ErrorMetric {
    /// Every metric, in the order `--metric` lists them.
    pub const ALL: [ErrorMetric; 3] = [Self::Rmse, Self::RelMse, Self::Outside];

    /// Name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::Rmse => "rmse",
            Self::RelMse => "rel-mse",
            Self::Outside => "outside",
        }
    }

    /// Parses a name; the error lists the valid ones.
    pub fn parse(name: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|m| m.name() == name)
            .ok_or_else(|| format!("unknown metric '{name}' (expected rmse, rel-mse or outside)"))
    }

    /// The axis's title.
    pub fn label(self) -> &'static str {
        match self {
            Self::Rmse => "RMSE",
            Self::RelMse => "relative MSE",
            Self::Outside => "share of pixels off by more than 1e-3",
        }
    }

    /// `p`'s error by this metric.
    pub fn of(self, p: &Point) -> f64 {
        match self {
            Self::Rmse => p.rmse,
            Self::RelMse => p.rel_mse,
            Self::Outside => 1.0 - p.within,
        }
    }
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    title: &str,
    subtitle: &str,
    points: &[Point],
    metric: ErrorMetric,
    text: bool,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(err)?;
    let finite: Vec<&Point> = points
        .iter()
        .filter(|p| p.seconds > 0.0 && metric.of(p) > 0.0 && metric.of(p).is_finite())
        .collect();
    if finite.is_empty() {
        return Err(format!("no point with a positive time and {} to plot", metric.label()));
    }
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for p in &finite {
        let (fastest, slowest) = time_spread(p).unwrap_or((p.seconds, p.seconds));
        (x0, x1) = (x0.min(fastest.min(p.seconds)), x1.max(slowest.max(p.seconds)));
        (y0, y1) = (y0.min(metric.of(p)), y1.max(metric.of(p)));
    }
    let (x0, x1, y0, y1) = (x0 / 1.5, x1 * 1.5, y0 / 1.5, y1 * 1.5);
    let mut builder = ChartBuilder::on(&root);
    builder.margin(16);
    if text {
        builder
            .caption(title, ("sans-serif", 24))
            .x_label_area_size(50)
            .y_label_area_size(80);
    } else {
        builder.x_label_area_size(10).y_label_area_size(10);
    }
    let mut chart = builder
        .build_cartesian_2d(
            (x0..x1).log_scale().with_key_points(log_ticks(x0, x1)),
            (y0..y1).log_scale().with_key_points(log_ticks(y0, y1)),
        )
        .map_err(err)?;
    let mut mesh = chart.configure_mesh();
    if text {
        mesh.x_desc(format!(
            "seconds (scene load + render): median, bar = fastest…slowest repeat — reference: {subtitle}"
        ))
        .y_desc(metric.label())
        .x_label_formatter(&|v| tick_label(*v))
        .y_label_formatter(&|v| format!("{v:.1e}"))
        .label_style(("sans-serif", 14));
    } else {
        mesh.disable_x_axis().disable_y_axis();
    }
    mesh.draw().map_err(err)?;
    let mut series: Vec<_> = finite.iter().map(|p| series_of(p)).collect();
    series.sort();
    series.dedup();
    for (renderer, sampler, budgets) in series {
        let members: Vec<&&Point> = finite
            .iter()
            .filter(|p| series_of(p) == (renderer, sampler, budgets))
            .collect();
        let mut pts: Vec<(f64, f64)> = members.iter().map(|p| (p.seconds, metric.of(p))).collect();
        // A budget line's thresholds are what its budgets reached, not what traced it.
        let label = label(
            renderer,
            sampler,
            members.iter().filter(|_| !budgets).filter_map(|p| p.threshold),
            members.iter().filter_map(|p| p.time_budget),
        );
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        let c = colour(renderer, sampler);
        // The budgets' line is dashed, in the colour of the sampler's own line.
        let line = if budgets {
            let dashed = DashedLineSeries::new(pts.clone(), 10, 6, c.stroke_width(2));
            chart.draw_series(dashed).map_err(err)?
        } else {
            chart
                .draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))
                .map_err(err)?
        };
        if text {
            line.label(label).legend(move |(x, y)| {
                // Dashed: two dashes with a gap; solid: the first stroke runs the whole length.
                let (first, second) = if budgets { (10, 14) } else { (24, 24) };
                EmptyElement::at((x, y))
                    + PathElement::new(vec![(0, 0), (first, 0)], c.stroke_width(2))
                    + PathElement::new(vec![(second, 0), (24, 0)], c.stroke_width(2))
            });
        }
        chart
            .draw_series(pts.into_iter().map(|p| Circle::new(p, 4, c.filled())))
            .map_err(err)?;
        // The repeats' spread: a bar from the fastest to the slowest, with end ticks.
        for (p, (fastest, slowest)) in members.iter().filter_map(|p| Some((p, time_spread(p)?))) {
            let style = c.stroke_width(1);
            let error = metric.of(p);
            let tick = |x: f64| EmptyElement::at((x, error)) + PathElement::new(vec![(0, -4), (0, 4)], style);
            chart
                .draw_series([PathElement::new(vec![(fastest, error), (slowest, error)], style)])
                .map_err(err)?;
            chart.draw_series([tick(fastest), tick(slowest)]).map_err(err)?;
        }
    }
    if text {
        chart
            .configure_series_labels()
            .label_font(("sans-serif", 16))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(err)?;
    }
    root.present().map_err(err)
}

/// Mantissas of a logarithmic axis's ticks, sparsest first: the first set that puts at least
/// [`MIN_TICKS`] ticks on the axis is used.
const TICK_MANTISSAS: [&[f64]; 4] = [
    &[1.0],
    &[1.0, 2.0, 5.0],
    &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0],
    &[1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 4.5, 5.0, 6.0, 7.0, 8.0, 9.0],
];
const MIN_TICKS: usize = 3;
/// More than this many powers of ten are thinned to every n-th decade.
const MAX_TICKS: usize = 10;

/// Tick values in `[lo, hi]` (0 < lo < hi) for a logarithmic axis. plotters' own log axis
/// places ticks from the first power of ten in the range on, so an axis within one decade (all
/// points between 0.15 and 0.56 s, say) had no tick and no label at all; here an axis gets
/// powers of ten when it spans enough decades, and 1-2-5 or finer steps when it does not.
fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let decades = (lo.log10().floor() as i32)..=(hi.log10().ceil() as i32);
    let ticks = |mantissas: &[f64]| -> Vec<f64> {
        decades
            .clone()
            .flat_map(|e| mantissas.iter().map(move |m| m * 10f64.powi(e)))
            .filter(|v| (lo..=hi).contains(v))
            .collect()
    };
    let mut chosen = TICK_MANTISSAS.map(ticks);
    let at = chosen
        .iter()
        .position(|t| t.len() >= MIN_TICKS)
        .unwrap_or(chosen.len() - 1);
    let mut ticks = std::mem::take(&mut chosen[at]);
    if ticks.len() > MAX_TICKS {
        let every = ticks.len().div_ceil(MAX_TICKS);
        ticks = ticks.into_iter().step_by(every).collect();
    }
    ticks
}

/// A tick's label: plain decimals with up to three significant digits between 0.001 and
/// 10000 (trailing zeros dropped), scientific notation outside.
fn tick_label(v: f64) -> String {
    if !(1e-3..1e4).contains(&v) {
        return format!("{v:.1e}");
    }
    let decimals = (2 - v.log10().floor() as i32).max(0) as usize;
    let text = format!("{v:.decimals$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

/// The spread of a point's repeats: (fastest, slowest) of its positive, finite times, when they
/// differ (one repeat, or equal times, draw no bar).
fn time_spread(p: &Point) -> Option<(f64, f64)> {
    let times = p.all_seconds.iter().copied().filter(|t| t.is_finite() && *t > 0.0);
    let (fastest, slowest) = times.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), t| (lo.min(t), hi.max(t)));
    (fastest < slowest).then_some((fastest, slowest))
}

/// The series a point is drawn in: one per renderer and sampler, and apart from it the
/// sampler's time budgets.
fn series_of(p: &Point) -> (&str, &str, bool) {
    (p.renderer, &p.sampler, p.time_budget.is_some())
}

/// A series' legend: renderer and sampler, the range of thresholds when the adaptive sampler's
/// points were traced by several, and the range of time budgets when the line runs through them.
fn label(
    renderer: &str,
    sampler: &str,
    thresholds: impl Iterator<Item = f32>,
    budgets: impl Iterator<Item = f32>,
) -> String {
    let range = |values: &mut dyn Iterator<Item = f32>| {
        values.fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), t| (lo.min(t), hi.max(t)))
    };
    let mut label = format!("{renderer} {sampler}");
    let (lo, hi) = range(&mut { thresholds });
    if lo < hi {
        label += &format!(", thresholds {hi}…{lo}");
    }
    let (lo, hi) = range(&mut { budgets });
    if lo <= hi {
        label += &format!(", time budgets {lo}…{hi} s");
    }
    label
}

/// The plot as SVG text.
pub fn svg(title: &str, subtitle: &str, points: &[Point], metric: ErrorMetric) -> Result<String, String> {
    let mut out = String::new();
    draw(
        SVGBackend::with_string(&mut out, SIZE).into_drawing_area(),
        title,
        subtitle,
        points,
        metric,
        font_available(),
    )?;
    Ok(out)
}

/// The plot as PNG bytes, and a note when it has no text (no font found).
pub fn png(
    title: &str,
    subtitle: &str,
    points: &[Point],
    metric: ErrorMetric,
) -> Result<(Vec<u8>, Option<String>), String> {
    let text = font_available();
    let mut rgb = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
    draw(
        BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area(),
        title,
        subtitle,
        points,
        metric,
        text,
    )?;
    let image = image::RgbImage::from_raw(SIZE.0, SIZE.1, rgb).ok_or("plot buffer size")?;
    let mut bytes = std::io::Cursor::new(Vec::new());
    image
        .write_to(&mut bytes, image::ImageFormat::Png)
        .map_err(|e| e.to_string())?;
    let note = (!text).then(|| {
        format!(
            "no font found ({} or POINTSHADE_FONT): the plots have no text",
            FONT_CANDIDATES.lines().collect::<Vec<_>>().join(", ")
        )
    });
    Ok((bytes.into_inner(), note))
}

#[cfg(test)]
mod tests {
    use super::{label, log_ticks, svg, tick_label, time_spread, ErrorMetric};
    use crate::reports::convergence::point::Point;

    fn point(all_seconds: Vec<f64>) -> Point {
        Point {
            renderer: "pointshade",
            sampler: "cells".into(),
            spp: 256,
            threshold: None,
            time_budget: None,
            mean_spp: 6.6,
            seconds: 0.2,
            all_seconds,
            rmse: 1e-4,
            rel_mse: 1e-3,
            within: 0.9,
        }
    }

    #[test]
    fn each_metric_reads_its_own_error_and_names_its_axis() {
        let p = point(vec![0.2]);
        let values = ErrorMetric::ALL.map(|m| m.of(&p));
        assert_eq!(values, [1e-4, 1e-3, 1.0 - 0.9]);
        for m in ErrorMetric::ALL {
            assert_eq!(ErrorMetric::parse(m.name()), Ok(m));
        }
        assert!(ErrorMetric::parse("mse")
            .unwrap_err()
            .contains("rmse, rel-mse or outside"));
        // Every point at zero error by one metric: nothing to draw on a log axis, said so.
        let perfect = Point {
            within: 1.0,
            ..point(vec![0.2])
        };
        let e = svg("t", "s", &[perfect], ErrorMetric::Outside).unwrap_err();
        assert!(e.contains("share of pixels off"), "{e}");
    }

    #[test]
    fn a_points_bar_spans_its_fastest_and_slowest_repeat() {
        assert_eq!(time_spread(&point(vec![0.21, 0.19, 0.25])), Some((0.19, 0.25)));
        // Nothing to draw for one repeat or equal times; unusable times are left out.
        assert_eq!(time_spread(&point(vec![0.2])), None);
        assert_eq!(time_spread(&point(vec![0.2, 0.2])), None);
        assert_eq!(time_spread(&point(vec![f64::NAN, 0.2, 0.0, 0.3])), Some((0.2, 0.3)));
    }

    #[test]
    fn an_axis_within_one_decade_still_gets_ticks() {
        // Points between 0.15 and 0.56 s, with the plot's margin of 1.5 either side: no power
        // of ten lies on the axis (plotters' own log axis drew no tick there).
        let (lo, hi) = (0.15 / 1.5 + 1e-12, 0.56 * 1.5);
        let ticks = log_ticks(lo, hi);
        assert!(ticks.len() >= 3, "{ticks:?}");
        assert!(ticks.iter().all(|t| (lo..=hi).contains(t)), "{ticks:?}");
        // 1-2-5 would give two ticks (0.2 and 0.5): the next set, every tenth, gives seven.
        let labels: Vec<String> = ticks.iter().map(|&t| tick_label(t)).collect();
        assert_eq!(labels, ["0.2", "0.3", "0.4", "0.5", "0.6", "0.7", "0.8"]);
    }

    #[test]
    fn an_axis_over_several_decades_gets_powers_of_ten() {
        let ticks = log_ticks(2e-6, 3e-3);
        assert_eq!(ticks.len(), 3, "{ticks:?}");
        for (t, e) in ticks.iter().zip([-5, -4, -3]) {
            assert!((t / 10f64.powi(e) - 1.0).abs() < 1e-12, "{ticks:?}");
        }
        // Forty decades are thinned to at most ten ticks.
        assert!(log_ticks(1e-20, 1e20).len() <= 10);
    }

    #[test]
    fn tick_labels_keep_three_significant_digits_at_most() {
        let labels = [0.15, 0.0015, 2.5, 100.0, 0.3000000000000001, 1e-5].map(tick_label);
        assert_eq!(labels, ["0.15", "0.0015", "2.5", "100", "0.3", "1.0e-5"]);
    }

    #[test]
    fn the_legend_names_the_thresholds_only_when_they_trace_the_line() {
        let none = || [].into_iter();
        assert_eq!(label("pointshade", "sobol", none(), none()), "pointshade sobol");
        let one = [0.005f32; 3].into_iter();
        assert_eq!(label("pointshade", "adaptive", one, none()), "pointshade adaptive");
        let several = [0.02f32, 0.005, 0.01].into_iter();
        assert_eq!(
            label("pointshade", "adaptive", several, none()),
            "pointshade adaptive, thresholds 0.02…0.005"
        );
    }

    #[test]
    fn the_legend_names_the_time_budgets_that_trace_the_line() {
        let budgets = [0.2f32, 0.05, 0.1].into_iter();
        assert_eq!(
            label("pointshade", "sobol", [].into_iter(), budgets),
            "pointshade sobol, time budgets 0.05…0.2 s"
        );
    }
}
