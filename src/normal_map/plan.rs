//! The normal-map mode's render plan: which stages run (surface points from pixels, no rays),
//! and its `--explain` text.

use crate::normal_map::image::NormalImage;
use crate::normal_map::scene_file::{NormalMapScene, Preset};
use crate::plan::{RenderPlan, StageDecision};

/// The plan for shading `image` as `scene` says (normal-map mode): surface points come from
/// the image's pixels, so there is no BVH and no ray of any kind. `output` describes the
/// output encoding.
pub fn plan(scene: &NormalMapScene, image: &NormalImage, output: &str) -> RenderPlan {
    let mut stages = Vec::new();
    let mut decide = |stage, kept: bool, why: String| {
        stages.push(StageDecision { stage, kept, why });
        kept
    };
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
    decide(
        "normal image → surface points",
        true,
        format!(
            "{w}x{h} {}-bit image, {} preset: {decoding}",
            image.bit_depth(),
            scene.preset.name(),
        ),
    );
    decide(
        "bvh + primary rays",
        false,
        "normal-map mode: every surface point comes from a pixel, there is no geometry to trace".into(),
    );
    decide(
        "shadow rays",
        false,
        "normal-map mode: a normal image has no geometry that could occlude a light".into(),
    );
    let specular = decide(
        "specular BRDF terms",
        scene.material.has_specular(),
        format!("material '{}' is {}", scene.material.name, scene.material.model_name()),
    );
    let convention = scene.preset.convention();
    decide("shading convention", true, convention.describe().into());
    decide("output", true, output.into());
    RenderPlan {
        trace_rays: false,
        shadows: false,
        specular,
        uvs: false,
        textures: false,
        normal_textures: false,
        emission: false,
        cutouts: false,
        aovs: Vec::new(),
        stages,
        primary_rays: 0,
        adaptive: false,
        smooth_shadow_origins: false,
        max_shadow_rays: 0,
        convention,
    }
}

/// The normal-map plan as text, for `--explain`.
pub fn explain(plan: &RenderPlan, scene: &NormalMapScene, image: &NormalImage) -> String {
    let film = format!(
        "{}x{}, one surface point per non-background pixel",
        image.width, image.height
    );
    plan.explain_with(&scene.source, &film, &scene.notes)
}
