//! Reports: product features that check the renderer and print what they found.

pub mod stability;
