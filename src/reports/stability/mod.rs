//! `pointshade stability`: numerical stability on stiff and extreme inputs, as a table of cases.
//!
//! Every case runs real pointshade code and is judged against a stated criterion:
//! - **BRDF cases** evaluate the *same generic code* (`shading::brdf` terms and
//!   `Material::eval`) in f32 and in f64 on the same f32 inputs (cast exactly to f64), and
//!   compare: relative error ≤ [`REL_TOL`] unless the case is *singular* (an ill-conditioned
//!   input, a documented clamp or limit), in which case the documented value is checked instead.
//!   Random and adversarial sweeps count NaN, infinite and negative values, which must all be 0.
//! - **Geometry cases** fire rays from inside closed meshes (none may escape), through degenerate
//!   and sliver triangles, and render one scene at scales 1e-6 … 1e6 and offset 1e5 against the
//!   same scene at the origin; they also report each BVH's depth and traversal stack.
//! - **Light cases** shade points at, near and around lights of extreme intensity.
//! - **Normal-map cases** run the `tp` preset's pixel path on its degenerate inputs and on random
//!   pixels, against the same generic code in f64.
//!
//! The relative error is |f32 − f64| / max(|f64|, 2⁻¹²⁶): values below f32's normal range are
//! compared on an absolute scale.
//!
//! The suite is split by kind of case: [`brdf_cases`] (fixed singular and extreme inputs, one or
//! more per term), [`brdf_sweep`] (random and adversarial evaluations), [`geometry_cases`],
//! [`scale_cases`] (one scene at many scales and offsets), [`far_cases`] (the dragon in map coordinates), [`light_cases`], [`normal_map_cases`], and [`table`] (the printed table, the summary and the CSV file).

pub mod brdf_cases;
pub mod brdf_sweep;
pub mod case;
pub mod far_cases;
pub mod geometry_cases;
pub mod light_cases;
pub mod normal_map_cases;
pub mod scale_cases;
pub mod table;

pub use case::{num, rel_err, Case, Options, Report, Rng, REL_TOL};

/// Runs every group of cases. Each group is one module's `run`; the normal-map `tp` preset's
/// degenerate inputs are a group of their own, added beside these when that mode exists.
pub fn run(options: &Options) -> Report {
    let mut cases = Vec::new();
    let mut notes = Vec::new();
    cases.extend(brdf_cases::run());
    cases.extend(brdf_sweep::run(options));
    cases.extend(geometry_cases::run(options, &mut notes));
    cases.extend(scale_cases::run(&mut notes));
    cases.extend(far_cases::run(options.shared_meshes.as_deref(), &mut notes));
    cases.extend(light_cases::run());
    cases.extend(normal_map_cases::run(options.cases.min(1_000_000), options.seed));
    Report { cases, notes }
}
