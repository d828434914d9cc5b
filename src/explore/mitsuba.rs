//! The page's "Compare with Mitsuba" button: the edited scene rendered by Mitsuba 3 and by
//! pointshade at pixel centres, like for like (`validation::run::compare_at_pixel_centres`, the
//! first comparison `pointshade validate` makes), and the relative error per pixel as a heat map.
//!
//! Mitsuba is the one `validation/install.sh` installs; its files go to a folder of their own
//! under the system's temporary folder, removed afterwards.

use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};

use serde_json::{json, Value};

use super::session::{Explorer, Mode};
use super::state::State;
use crate::output::{encode, Format};
use crate::scene::uri::data_uri;
use crate::validation::run::{compare_at_pixel_centres, meets_thresholds, MitsubaRunner, TOLERANCE};

/// The runner the button uses, or whether Mitsuba is installed and why the button cannot run.
pub fn runner(explorer: &Explorer) -> Result<MitsubaRunner, (bool, String)> {
    match (MitsubaRunner::in_dir(explorer.mitsuba_dir()), explorer.mode()) {
        (Err(e), _) => Err((false, e.to_string())),
        (Ok(_), Mode::NormalImage) => Err((
            true,
            "Mitsuba 3 is installed, but it renders scenes: a normal image is shaded by the normal-map mode alone (open a scene file to compare)".to_string(),
        )),
        (Ok(runner), Mode::Scene) => Ok(runner),
    }
}

/// Whether the button can run: Mitsuba installed and a scene open; else what to do about it.
pub fn status(explorer: &Explorer) -> Value {
    match runner(explorer) {
        Ok(_) => json!({
            "available": true, "installed": true,
            "message": "renders the current scene with Mitsuba 3 and pointshade at pixel centres and compares them",
        }),
        Err((installed, message)) => json!({ "available": false, "installed": installed, "message": message }),
    }
}

/// Runs the comparison for `state` (`scene` is the explorer's scene as `state` edits it): the
/// share of pixels within the validation's tolerance, the mean relative error, and the heat map
/// and both renders as PNG data URLs.
pub fn compare(runner: &MitsubaRunner, scene: &crate::scene::Scene, state: &State) -> Result<Value, String> {
    let work = WorkFolder::new()?;
    let c = compare_at_pixel_centres(scene, runner, &work.0).map_err(|e| e.to_string())?;
    let (w, h) = (c.ours.width, c.ours.height);
    let png = |image| encode(image, Format::Png, state.exposure).map(|bytes| data_uri("image/png", &bytes));
    let m = &c.comparison;
    let message = match (c.differences.is_empty(), meets_thresholds(m)) {
        (true, true) => "the two renderers agree as the validation requires".to_string(),
        (true, false) => "the two renderers disagree: the validation would fail this scene".to_string(),
        (false, _) => format!(
            "Mitsuba cannot express all of this scene, so the images may differ: {}",
            c.differences.join("; ")
        ),
    };
    Ok(json!({
        "available": true,
        "message": message,
        "tolerance": TOLERANCE,
        "within": m.within_tolerance,
        "within_rounding_band": m.within_rounding_band,
        "mean_relative_error": m.mean_relative_error,
        "non_finite": m.non_finite_ours + m.non_finite_reference,
        "differences": c.differences,
        "variant": c.mitsuba.variant,
        "mitsuba_seconds": (c.mitsuba.load + c.mitsuba.render).as_secs_f64(),
        "heatmap": data_uri("image/png", &encode(&m.heat_map(w, h), Format::Png, 0.0)?),
        "mitsuba_image": png(&c.reference)?,
        "pointshade_image": png(&c.ours)?,
    }))
}

/// A folder of the system's temporary folder for one comparison, removed when dropped.
struct WorkFolder(PathBuf);

impl WorkFolder {
    fn new() -> Result<WorkFolder, String> {
        static NEXT: AtomicU64 = AtomicU64::new(0);
        let n = NEXT.fetch_add(1, Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("pointshade-explore-{}-{n}", std::process::id()));
        std::fs::create_dir_all(&dir).map_err(|e| format!("{}: cannot create: {e}", dir.display()))?;
        Ok(WorkFolder(dir))
    }
}

impl Drop for WorkFolder {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}
