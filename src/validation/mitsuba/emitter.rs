//! Lights as emitters: `point`, `directional` and `spot`, each with the power pointshade's light
//! has; what Mitsuba's emitters cannot express goes to the export's differences.

use glam::Vec3;

use crate::light::{Falloff, Light, LightKind};
use crate::validation::xml::{rgb, v3};

/// `light` as an emitter element.
pub(super) fn emitter(light: &Light, differences: &mut Vec<String>) -> String {
    let power = light.power.to_array();
    if light.falloff == Falloff::None && !matches!(light.kind, LightKind::Directional { .. }) {
        differences.push("falloff = \"none\" (exported with Mitsuba's inverse-square falloff)".into());
    }
    if let Falloff::InverseSquareWithin { range } = light.falloff {
        differences.push(format!(
            "a KHR_lights_punctual range of {range} (exported with Mitsuba's unwindowed inverse-square falloff)"
        ));
    }
    match light.kind {
        LightKind::Point { position } => format!(
            "  <emitter type=\"point\"><point name=\"position\" x=\"{}\" y=\"{}\" z=\"{}\"/>{}</emitter>",
            position.x,
            position.y,
            position.z,
            rgb("intensity", power)
        ),
        LightKind::Directional { direction } => format!(
            "  <emitter type=\"directional\"><vector name=\"direction\" x=\"{}\" y=\"{}\" z=\"{}\"/>{}</emitter>",
            direction.x,
            direction.y,
            direction.z,
            rgb("irradiance", power)
        ),
        LightKind::Spot {
            position,
            direction,
            cos_inner,
            cos_outer,
        } => {
            differences.push(
                "spot light cone falloff (Mitsuba's is linear in angle, pointshade's quadratic in cos as \
                 KHR_lights_punctual)"
                    .into(),
            );
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
    }
}
