//! The integration tests: one test binary whose modules are the files beside this one (one
//! link of the whole program instead of one per file: docs/benchmarks.md, "Build and test time").
//! Each module is a group of tests of one part of the product (a folder of one file per topic,
//! with their shared helpers in its mod.rs, where a part has several); `support` holds the
//! helpers every module may use.

mod support;

mod adaptive;
mod aim;
mod bad_input;
mod brdf_properties;
mod compare_cli;
mod confine;
mod convergence;
mod crop_merge;
mod cutouts;
mod end_to_end;
mod examples;
mod far_coordinates;
mod gltf;
mod gltf_mutations;
mod gltf_shared;
mod hostile;
mod meshes;
mod mtl;
mod normalmap;
mod shadow_terminator;
mod shared_data;
mod silent_nonsense;
mod time_budget;
mod validation;
