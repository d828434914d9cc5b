//! Helpers shared by integration tests.
pub mod gltf_builder;
