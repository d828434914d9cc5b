//! Rendering like another renderer: one word (`match = "mitsuba"` under `[render]`,
//! `--match mitsuba`, `render(..., match="mitsuba")`) for every setting that makes pointshade
//! take the samples and trace the shadow rays another renderer does, so that the two images can
//! be compared pixel by pixel (docs/validation.md, "Like for like").

use crate::film::SamplerKind;
use crate::scene::shadows::ShadowOffset;
use crate::scene::Scene;

/// A renderer whose samples and shadow rays a render takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Match {
    /// Mitsuba 3 as pointshade exports scenes to it: the `grid` sampler (N×N sub-pixel centres,
    /// one sample at each pixel centre at spp = 1: Mitsuba's `stratified` sampler without
    /// jitter, which the export writes) and Mitsuba's shadow offset (its fixed epsilon, from the
    /// flat triangle). Without the grid, the two renderers sample other points of each pixel
    /// and edges and highlights disagree; without the offset, pixels along shadow edges do.
    Mitsuba,
}

impl Match {
    /// Every name [`Match::parse`] knows.
    pub const NAMES: &'static [&'static str] = &["mitsuba"];

    /// Name in scene files, on the command line and in Python.
    pub fn name(self) -> &'static str {
        match self {
            Self::Mitsuba => "mitsuba",
        }
    }

    /// Parses a name; the error lists the valid ones.
    pub fn parse(name: &str) -> Result<Self, String> {
        match name {
            "mitsuba" => Ok(Self::Mitsuba),
            other => Err(format!("unknown renderer to match '{other}' (expected mitsuba)")),
        }
    }

    /// The sampler this match renders with.
    pub fn sampler(self) -> SamplerKind {
        match self {
            Self::Mitsuba => SamplerKind::Grid,
        }
    }

    /// The shadow offset this match renders with.
    pub fn shadow_offset(self) -> ShadowOffset {
        match self {
            Self::Mitsuba => ShadowOffset::Mitsuba,
        }
    }

    /// Why a sampler and shadow offset given beside the match (in the same scene file, or the
    /// same call) contradict it, if they do. `sampler_key` and `offset_key` are the settings'
    /// names as the caller's front end spells them.
    pub fn contradiction(
        self,
        sampler: Option<SamplerKind>,
        offset: Option<ShadowOffset>,
        (sampler_key, offset_key): (&str, &str),
    ) -> Option<String> {
        let name = self.name();
        if let Some(s) = sampler.filter(|&s| s != self.sampler()) {
            return Some(format!(
                "{name} renders with the {} sampler, but {sampler_key} is {}: give one or the other",
                self.sampler().name(),
                s.name()
            ));
        }
        offset.filter(|&o| o != self.shadow_offset()).map(|o| {
            format!(
                "{name} renders with the {} shadow offset, but {offset_key} is {}: give one or the other",
                self.shadow_offset().name(),
                o.name()
            )
        })
    }

    /// Puts the match's settings on `scene`.
    pub fn apply(self, scene: &mut Scene) {
        scene.film.sampler = self.sampler();
        scene.shadow_offset = self.shadow_offset();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_back_and_settings_contradict_only_when_they_differ() {
        for name in Match::NAMES {
            assert_eq!(Match::parse(name).unwrap().name(), *name);
        }
        assert!(Match::parse("pbrt").unwrap_err().contains("expected mitsuba"));
        let keys = ("sampler", "shadow_offset");
        let m = Match::Mitsuba;
        assert_eq!(m.contradiction(None, None, keys), None);
        assert_eq!(
            m.contradiction(Some(SamplerKind::Grid), Some(ShadowOffset::Mitsuba), keys),
            None
        );
        let sobol = m.contradiction(Some(SamplerKind::Sobol), None, keys).unwrap();
        assert!(sobol.contains("grid sampler, but sampler is sobol"), "{sobol}");
        let offset = m.contradiction(None, Some(ShadowOffset::ErrorBound), keys).unwrap();
        assert!(offset.contains("shadow_offset is error-bound"), "{offset}");
    }
}
