//! KHR_lights_punctual lights → [`Light`]s, placed by their nodes.
//!
//! Point and spot intensities are candela and directional ones lux; pointshade's lights are in
//! the same units up to the unit of radiance (I = color × intensity, E = I/d²; directional
//! E = color × intensity), so the values are used as they are. Point and spot lights sit at the
//! node's origin; spot and directional lights point along the node's −Z. `range` windows the
//! inverse square as the extension recommends; the spot cone falloff is the extension's (see
//! `shading::light`).

use glam::{Mat4, Vec3};

use crate::error::InputResult;
use crate::light::{Falloff, Light, LightKind, SpotProfile};
use crate::scene::gltf::document::GltfDocument;

/// The light `light` placed by a node with world matrix `world`.
pub fn light_at(d: &GltfDocument, light: &::gltf::khr_lights_punctual::Light, world: Mat4) -> InputResult<Light> {
    use ::gltf::khr_lights_punctual::Kind;
    let index = light.index();
    let err = |problem: String| d.error(format!("light {index}: {problem}"));
    let color = Vec3::from(light.color());
    if !color.is_finite() || color.min_element() < 0.0 {
        return Err(err(format!("color must have finite components ≥ 0, got {color}")));
    }
    let intensity = light.intensity();
    if !(intensity.is_finite() && intensity >= 0.0) {
        return Err(err(format!("intensity must be a finite number ≥ 0, got {intensity}")));
    }
    let position = world.w_axis.truncate();
    let direction = || {
        (-world.z_axis.truncate())
            .try_normalize()
            .ok_or_else(|| err("its node's transform collapses the light's direction".into()))
    };
    let kind = match light.kind() {
        Kind::Point => LightKind::Point { position },
        Kind::Directional => LightKind::Directional {
            direction: direction()?,
        },
        Kind::Spot {
            inner_cone_angle,
            outer_cone_angle,
        } => {
            let (inner, outer) = (inner_cone_angle, outer_cone_angle);
            if !(0.0 <= inner && inner < outer && outer <= std::f32::consts::FRAC_PI_2) {
                return Err(err(format!(
                    "spot cones must satisfy 0 ≤ innerConeAngle < outerConeAngle ≤ π/2, got {inner} and {outer}"
                )));
            }
            LightKind::Spot {
                position,
                direction: direction()?,
                cos_inner: inner.cos(),
                cos_outer: outer.cos(),
                profile: SpotProfile::Gltf,
            }
        }
    };
    let falloff = match light.range() {
        None => Falloff::InverseSquare,
        Some(range) if range > 0.0 && range.is_finite() => Falloff::InverseSquareWithin { range },
        Some(range) => return Err(err(format!("range must be a finite number > 0, got {range}"))),
    };
    Ok(Light {
        kind,
        power: color * intensity,
        falloff,
    })
}
