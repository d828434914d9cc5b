//! Reports: product features that check the renderer and print what they found.

pub mod convergence;
pub mod stability;
