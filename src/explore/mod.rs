//! The interactive explorer behind `pointshade explore` and `pointshade.explore`: a scene or a
//! normal image held open, edited by a page in the browser, rendered by the same code as
//! `pointshade render` and `pointshade normalmap` (docs/explore.md).
//!
//! [`Explorer`] is the session: what was opened, its [`state::State`] and one call per request.
//! [`server`] puts it behind a local HTTP server; [`plots`] evaluates what the page plots. Nothing
//! a request carries names a file: the scene is the one given at start-up.

pub mod plots;
pub mod server;
pub mod state;

mod api;
mod keys;
mod mitsuba;
mod session;

pub use session::{Explorer, Mode, DEFAULT_MITSUBA_DIR};
