//! Shading: BRDFs, materials, lights and the shader that combines them.
pub mod convention;
pub mod shader;
