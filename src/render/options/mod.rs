//! The options a front end sets on a render, declared once.
//!
//! [`RENDER_OPTIONS`] lists each option's name, the values it takes and its help: the CLI makes
//! its flags from it (`--shadow-offset`), the Python module its keywords (`shadow_offset=`), the
//! explorer its controls. [`RenderOptions::set`] is the one place a value given to an option is
//! read and checked, whatever its front end; [`RenderOptions::apply`] then puts the options on a
//! loaded scene, and the render request ([`super::request`]) uses the rest (threads, camera,
//! AOVs).
//!
//! A new option is a row of the table, a field of [`RenderOptions`] that its row's `store`
//! fills, and the code that acts on it (usually [`RenderOptions::apply`]). The CLI and the
//! Python module need nothing more; the Python stub (`__init__.pyi`) lists keywords by hand, and
//! a test holds it to the table.

mod option;
mod read;
mod table;
#[cfg(test)]
mod tests;

pub use option::{End, OptionValue, RenderOption, RenderOptions, Spelling, Values};
pub use table::RENDER_OPTIONS;

use crate::error::{InputError, InputResult};
use crate::film::time_budget_defaults;
use crate::scene::framing::Aim;
use crate::scene::Scene;

/// The option called `name`, if there is one.
pub fn render_option(name: &str) -> Option<&'static RenderOption> {
    RENDER_OPTIONS.iter().find(|o| o.name == name)
}

impl RenderOptions {
    /// Sets option `name` to `value`, checked against what the option takes. The error names
    /// the option as `spelling` writes it and says what it takes.
    pub fn set(&mut self, name: &str, value: &OptionValue, spelling: Spelling) -> InputResult<()> {
        let option =
            render_option(name).ok_or_else(|| InputError::new(spelling.of(name), "is not an option of a render"))?;
        option
            .read(value)
            .and_then(|read| (option.store)(self, read))
            .map_err(|problem| InputError::new(spelling.of(name), problem))
    }

    /// Puts the options that change the scene on it, then validates the film. An error names
    /// the option as `spelling` writes it; a film that does not validate names the scene.
    pub fn apply(&self, scene: &mut Scene, spelling: Spelling) -> InputResult<()> {
        let err = |key: &str, problem: String| InputError::new(spelling.of(key), problem);
        if let Some(m) = self.matching {
            let keys = (spelling.of("sampler"), spelling.of("shadow_offset"));
            if let Some(problem) = m.contradiction(self.sampler, self.shadow_offset, (keys.0.as_str(), keys.1.as_str()))
            {
                return Err(err("match", problem));
            }
        }
        self.aim.apply(scene).map_err(|e| err(aim_key(&self.aim), e))?;
        let f = &mut scene.film;
        f.width = self.width.unwrap_or(f.width);
        f.height = self.height.unwrap_or(f.height);
        f.exposure = self.exposure.unwrap_or(f.exposure);
        f.seed = self.seed.unwrap_or(f.seed);
        f.sampler = self.sampler.unwrap_or(f.sampler);
        if let Some(budget) = self.time_budget {
            f.time_budget = Some(budget);
            (f.spp, f.adaptive_threshold) = time_budget_defaults(f.sampler);
        }
        f.spp = self.spp.unwrap_or(f.spp);
        f.adaptive_threshold = self.adaptive_threshold.unwrap_or(f.adaptive_threshold);
        f.crop = self.crop.or(f.crop);
        scene.shadow_offset = self.shadow_offset.unwrap_or(scene.shadow_offset);
        scene.shadow_terminator = self.shadow_terminator.unwrap_or(scene.shadow_terminator);
        if let Some(m) = self.matching {
            m.apply(scene);
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
