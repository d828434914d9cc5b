//! pointshade — a CPU renderer that shades surface points with analytic BRDFs.
//!
//! The module tree is the pipeline, in the order data flows through it:
//! [`scene`] (loading) → [`plan`] (which stages this scene needs) → [`accel`] (BVH, shadow-ray
//! queries) → [`surface`] (camera rays → [`surface::SurfacePoint`]s) → [`shading`] (the shader)
//! → [`film`] (samples → pixels) → [`output`] (PNG / EXR files). Below the scene sit what it is
//! made of: [`lanes`] (the number types), [`brdf`] (the terms), [`material`], [`light`] and
//! [`texture`]. [`render`] drives the stages; see ARCHITECTURE.md. [`normal_map`] is the
//! normal-map mode (pixels of a normal image → surface points → the same shader, and baking, its
//! inverse).

pub mod accel;
pub mod brdf;
pub mod error;
#[cfg(feature = "explore")]
pub mod explore;
pub mod film;
pub mod input_files;
pub mod lanes;
pub mod light;
pub mod material;
pub mod normal_map;
pub mod output;
pub mod plan;
pub mod process_fork;
pub mod render;
pub mod reports;
pub mod scene;
pub mod shading;
pub mod surface;
#[cfg(test)]
mod test_random;
pub mod texture;
pub mod validation;
