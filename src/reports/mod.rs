//! Reports: product features that check the renderer and print what they found.

#[cfg(feature = "convergence")]
pub mod convergence;
pub mod stability;
