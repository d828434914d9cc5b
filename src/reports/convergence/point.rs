//! One measured point of a convergence run: what was rendered, how long it took, its error.

/// One measured point.
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    /// "pointshade" or "mitsuba".
    pub renderer: &'static str,
    /// The sampler (pointshade's names; Mitsuba's grid is `stratified` without jitter).
    pub sampler: String,
    /// Samples per pixel asked for (the most, for the adaptive sampler; the count reached, for
    /// a time budget).
    pub spp: u32,
    /// The adaptive sampler's threshold (adaptive points only).
    pub threshold: Option<f32>,
    /// The time budget in seconds (BVH build and render), for points rendered to one.
    pub time_budget: Option<f32>,
    /// Samples per pixel actually taken, on average.
    pub mean_spp: f64,
    /// Median time over the repeats, in seconds.
    pub seconds: f64,
    /// Every repeat's time, in seconds.
    pub all_seconds: Vec<f64>,
    /// Root mean squared error against the reference.
    pub rmse: f64,
    /// Relative MSE against the reference.
    pub rel_mse: f64,
    /// Share of pixels within [`TOLERANCE`](super::TOLERANCE) of the reference.
    pub within: f64,
}
