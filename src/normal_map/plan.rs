//! The normal-map mode's plan, for `--explain`: surface points come from the image's pixels, so
//! there is no BVH and no ray of any kind.

use crate::normal_map::image::NormalImage;
use crate::normal_map::scene_file::{NormalMapScene, Preset};
use crate::plan::{explain_stages, StageDecision};

/// What the normal-map mode does with one image, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct NormalMapPlan {
    /// Every decision.
    pub stages: Vec<StageDecision>,
}

/// The plan for shading `image` as `scene` says; `output` describes the output encoding.
pub fn plan(scene: &NormalMapScene, image: &NormalImage, output: &str) -> NormalMapPlan {
    let (w, h) = (image.width, image.height);
    let decoding = match scene.preset {
        Preset::Tp => {
            "n = (c − min)/(max − min) over all RGB values, used as is; background max(rgb) ≤ 4/255; \
             x = (row, col, 0) in pixels"
        }
        Preset::Physical => {
            "n = normalise(2c − 1); background alpha = 0 or rgb = 0; x on the plane z = 0, image height 2 units"
        }
    };
    let stage = |stage, kept, why: String| StageDecision { stage, kept, why };
    NormalMapPlan {
        stages: vec![
            stage(
                "normal image → surface points",
                true,
                format!(
                    "{w}x{h} {}-bit image, {} preset: {decoding}",
                    image.bit_depth(),
                    scene.preset.name(),
                ),
            ),
            stage(
                "bvh + primary rays",
                false,
                "normal-map mode: every surface point comes from a pixel, there is no geometry to trace".into(),
            ),
            stage(
                "shadow rays",
                false,
                "normal-map mode: a normal image has no geometry that could occlude a light".into(),
            ),
            stage(
                "specular BRDF terms",
                scene.material.has_specular(),
                format!("material '{}' is {}", scene.material.name, scene.material.model_name()),
            ),
            stage("shading convention", true, scene.preset.convention().describe().into()),
            stage("output", true, output.into()),
        ],
    }
}

impl NormalMapPlan {
    /// The plan as text, for `--explain`.
    pub fn explain(&self, scene: &NormalMapScene, image: &NormalImage) -> String {
        let film = format!(
            "{}x{}, one surface point per non-background pixel",
            image.width, image.height
        );
        explain_stages(
            &scene.source,
            &film,
            &scene.notes,
            &self.stages,
            "0 primary, at most 0 shadow",
        )
    }
}
