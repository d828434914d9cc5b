//! The `perspective` or `orthographic` sensor, with its `hdrfilm` (box filter, float32) and
//! its sampler (`stratified` without jitter for the grid sampler, `independent` otherwise).

use glam::Vec3;

use crate::film::SamplerKind;
use crate::scene::camera::{FovAxis, Projection};
use crate::scene::Scene;
use crate::validation::xml::v3;

/// Mitsuba's default near clip, used where pointshade's is 0 (Mitsuba needs > 0).
const MITSUBA_NEAR_CLIP: f32 = 0.01;

/// The sensor of `scene` at `spp` samples per pixel; what it cannot express goes to
/// `differences`.
pub(super) fn sensor(scene: &Scene, spp: u32, differences: &mut Vec<String>) -> String {
    let c = &scene.camera;
    let f = &scene.film;
    let near = if c.near_clip > 0.0 {
        c.near_clip
    } else {
        MITSUBA_NEAR_CLIP
    };
    // Mitsuba needs a finite far plane: beyond everything in the scene, at least its default.
    let far = if c.far_clip.is_finite() {
        c.far_clip
    } else {
        let farthest = scene.mesh.bounds().map_or(0.0, |(lo, hi)| {
            (0..8)
                .map(|i| {
                    let corner = Vec3::new(
                        if i & 1 == 0 { lo.x } else { hi.x },
                        if i & 2 == 0 { lo.y } else { hi.y },
                        if i & 4 == 0 { lo.z } else { hi.z },
                    );
                    corner.distance(c.position)
                })
                .fold(0.0, f32::max)
        });
        (2.0 * farthest).max(1e4)
    };
    let lookat = format!(
        "<lookat origin=\"{}\" target=\"{}\" up=\"{}\"/>",
        v3(c.position),
        v3(c.look_at),
        v3(c.up)
    );
    let (kind, params, to_world) = match c.projection {
        Projection::Perspective { fov_degrees, fov_axis } => (
            "perspective",
            format!(
                "    <float name=\"fov\" value=\"{fov_degrees}\"/>\n    <string name=\"fov_axis\" value=\"{}\"/>\n",
                match fov_axis {
                    FovAxis::X => "x",
                    FovAxis::Y => "y",
                }
            ),
            format!("      {lookat}\n"),
        ),
        // Mitsuba's orthographic film spans x ∈ [−s, s], y ∈ [−s/aspect, s/aspect] for a to_world
        // scale s: s = half-height · aspect gives pointshade's half-height `scale`.
        Projection::Orthographic { scale } => {
            let s = scale * f.width as f32 / f.height as f32;
            (
                "orthographic",
                String::new(),
                format!("      <scale x=\"{s}\" y=\"{s}\" z=\"1\"/>\n      {lookat}\n"),
            )
        }
    };
    let sampler = match f.sampler {
        SamplerKind::Grid => format!(
            "    <sampler type=\"stratified\">\n      <integer name=\"sample_count\" value=\"{spp}\"/>\n      <boolean name=\"jitter\" value=\"false\"/>\n    </sampler>\n"
        ),
        other => {
            if other == SamplerKind::Sobol {
                differences.push("sobol sampler (exported as Mitsuba's independent sampler)".into());
            }
            format!(
                "    <sampler type=\"independent\">\n      <integer name=\"sample_count\" value=\"{spp}\"/>\n      <integer name=\"seed\" value=\"{}\"/>\n    </sampler>\n",
                f.seed as u32
            )
        }
    };
    format!(
        "  <sensor type=\"{kind}\">\n{params}    <float name=\"near_clip\" value=\"{near}\"/>\n    <float name=\"far_clip\" value=\"{far}\"/>\n    <transform name=\"to_world\">\n{to_world}    </transform>\n{sampler}    <film type=\"hdrfilm\">\n      <integer name=\"width\" value=\"{}\"/>\n      <integer name=\"height\" value=\"{}\"/>\n      <string name=\"pixel_format\" value=\"rgb\"/>\n      <string name=\"component_format\" value=\"float32\"/>\n      <rfilter type=\"box\"/>\n    </film>\n  </sensor>",
        f.width, f.height
    )
}
