//! Shading: BRDFs, materials, lights and the shader that combines them.
pub mod brdf;
pub mod convention;
pub mod light;
pub mod material;
pub mod shader;
pub mod shadow;
pub mod texture;
