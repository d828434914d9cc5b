//! Lights as emitters: Mitsuba's own `point`, `directional` and `spot` where one computes exactly
//! pointshade's light, the `pointshade_light` plugin (validation/pointshade_light.py) elsewhere:
//! spot lights with KHR_lights_punctual's cone, and positional lights without the inverse square
//! or with a KHR range window.

use glam::Vec3;

use crate::light::{Falloff, Light, LightKind, SpotProfile};
use crate::validation::xml::{rgb, v3};

/// The emitter type of the plugin.
pub(super) const PLUGIN: &str = "pointshade_light";

/// `light` as an emitter element, each with the power pointshade's light has.
pub(super) fn emitter(light: &Light) -> String {
    let power = light.power.to_array();
    let native_falloff = light.falloff == Falloff::InverseSquare;
    match light.kind {
        LightKind::Directional { direction } => format!(
            "  <emitter type=\"directional\"><vector name=\"direction\" x=\"{}\" y=\"{}\" z=\"{}\"/>{}</emitter>",
            direction.x,
            direction.y,
            direction.z,
            rgb("irradiance", power)
        ),
        LightKind::Point { position } if native_falloff => format!(
            "  <emitter type=\"point\"><point name=\"position\" x=\"{}\" y=\"{}\" z=\"{}\"/>{}</emitter>",
            position.x,
            position.y,
            position.z,
            rgb("intensity", power)
        ),
        LightKind::Spot {
            position,
            direction,
            cos_inner,
            cos_outer,
            profile: SpotProfile::Mitsuba,
        } if native_falloff => {
            let up = if direction.y.abs() < 0.9 { Vec3::Y } else { Vec3::X };
            format!(
                "  <emitter type=\"spot\"><transform name=\"to_world\"><lookat origin=\"{}\" target=\"{}\" up=\"{}\"/></transform>{}<float name=\"cutoff_angle\" value=\"{}\"/><float name=\"beam_width\" value=\"{}\"/></emitter>",
                v3(position),
                v3(position + direction),
                v3(up),
                rgb("intensity", power),
                cos_outer.acos().to_degrees(),
                cos_inner.acos().to_degrees()
            )
        }
        LightKind::Point { position } | LightKind::Spot { position, .. } => plugin(light, position),
    }
}

/// A positional light as the plugin reads it: position, intensity, distance falloff (and the
/// range of KHR's window), and for a spot its direction, cones and profile.
fn plugin(light: &Light, position: Vec3) -> String {
    let (falloff, range) = match light.falloff {
        Falloff::InverseSquare => ("inverse-square", 0.0),
        Falloff::None => ("none", 0.0),
        Falloff::InverseSquareWithin { range } => ("range", range),
    };
    let cone = match light.kind {
        LightKind::Spot {
            direction,
            cos_inner,
            cos_outer,
            profile,
            ..
        } => format!(
            "<vector name=\"direction\" x=\"{}\" y=\"{}\" z=\"{}\"/><float name=\"cos_inner\" value=\"{cos_inner}\"/><float name=\"cos_outer\" value=\"{cos_outer}\"/><string name=\"profile\" value=\"{}\"/>",
            direction.x,
            direction.y,
            direction.z,
            match profile {
                SpotProfile::Gltf => "gltf",
                SpotProfile::Mitsuba => "mitsuba",
            }
        ),
        _ => String::new(),
    };
    format!(
        "  <emitter type=\"{PLUGIN}\"><point name=\"position\" x=\"{}\" y=\"{}\" z=\"{}\"/>{}<string name=\"falloff\" value=\"{falloff}\"/><float name=\"range\" value=\"{range}\"/>{cone}</emitter>",
        position.x,
        position.y,
        position.z,
        rgb("intensity", light.power.to_array()),
    )
}
