//! What a caller changes on a loaded scene before rendering it: the options of `pointshade
//! render` and the keywords of the Python module's `render()`, applied by one function so the two
//! cannot drift apart.

use crate::error::{InputError, InputResult};
use crate::film::{time_budget_defaults, PixelRect, SamplerKind};
use crate::scene::framing::Aim;
use crate::scene::shadows::{ShadowOffset, ShadowTerminator};
use crate::scene::Scene;

/// Settings that replace the scene's own; `None` keeps the scene's.
#[derive(Clone, Debug, Default)]
pub struct Overrides {
    /// Image width in pixels.
    pub width: Option<u32>,
    /// Image height in pixels.
    pub height: Option<u32>,
    /// Samples per pixel (with a time budget: the most it may reach).
    pub spp: Option<u32>,
    /// Sampler name (`SamplerKind::parse`).
    pub sampler: Option<String>,
    /// Relative tolerance of the adaptive samplers.
    pub adaptive_threshold: Option<f32>,
    /// Seconds the BVH build and the render may take.
    pub time_budget: Option<f32>,
    /// Seed of the random sequences.
    pub seed: Option<u64>,
    /// The part of the frame to render.
    pub crop: Option<PixelRect>,
    /// Exposure in stops for 8-bit output.
    pub exposure: Option<f32>,
    /// Shadow-ray offset name (`ShadowOffset::parse`).
    pub shadow_offset: Option<String>,
    /// Shadow-terminator name (`ShadowTerminator::parse`).
    pub shadow_terminator: Option<String>,
    /// A camera aimed anew.
    pub aim: Aim,
}

impl Overrides {
    /// Applies every override to `scene` and validates the film. An error names the setting as
    /// `name` spells it (`--shadow-offset` on the command line, `shadow_offset` in Python), a film
    /// that does not validate names the scene.
    pub fn apply(&self, scene: &mut Scene, name: &dyn Fn(&str) -> String) -> InputResult<()> {
        let err = |key: &str, problem: String| InputError::new(name(key), problem);
        self.aim.apply(scene).map_err(|e| err(aim_key(&self.aim), e))?;
        let f = &mut scene.film;
        f.width = self.width.unwrap_or(f.width);
        f.height = self.height.unwrap_or(f.height);
        f.exposure = self.exposure.unwrap_or(f.exposure);
        f.seed = self.seed.unwrap_or(f.seed);
        if let Some(sampler) = &self.sampler {
            f.sampler = SamplerKind::parse(sampler).map_err(|e| err("sampler", e))?;
        }
        if let Some(budget) = self.time_budget {
            f.time_budget = Some(budget);
            (f.spp, f.adaptive_threshold) = time_budget_defaults(f.sampler);
        }
        f.spp = self.spp.unwrap_or(f.spp);
        f.adaptive_threshold = self.adaptive_threshold.unwrap_or(f.adaptive_threshold);
        f.crop = self.crop.or(f.crop);
        if let Some(offset) = &self.shadow_offset {
            scene.shadow_offset = ShadowOffset::parse(offset).map_err(|e| err("shadow_offset", e))?;
        }
        if let Some(terminator) = &self.shadow_terminator {
            scene.shadow_terminator = ShadowTerminator::parse(terminator).map_err(|e| err("shadow_terminator", e))?;
        }
        scene.film.validate().map_err(|e| InputError::new(&scene.source, e))
    }
}

/// The setting an aiming error is reported under: the last of them that was given.
fn aim_key(aim: &Aim) -> &'static str {
    if aim.fov.is_some() {
        "fov"
    } else if aim.look_at.is_some() {
        "look_at"
    } else if aim.look_from.is_some() {
        "look_from"
    } else {
        "view"
    }
}
