//! Validation against Mitsuba 3: export a scene as Mitsuba XML ([`mitsuba`]), run both renderers,
//! compare their images pixel by pixel ([`crate::film::compare`]) and report ([`run`], [`report`]).
//!
//! The Python side (installing Mitsuba, the `pointshade` BSDF plugin, rendering references)
//! lives in the repository's `validation/` folder.

pub mod export;
pub mod mitsuba;
pub mod ply;
pub mod report;
pub mod rounding;
pub mod run;
pub mod staleness;
pub mod textures;
pub mod xml;
