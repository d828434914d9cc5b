//! `[[light]]` sections: the point, directional and spot lights of mesh and normal-map scene
//! files, checked (finite, non-negative, non-zero directions, ordered cones) as they are read.

use glam::{DVec3, Vec3};
use serde::Deserialize;

use super::values::{point3, three, three_opt, vec3};
use crate::light::{Falloff, Light, LightKind, SpotProfile};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct LightSection {
    #[serde(rename = "type")]
    kind: LightType,
    #[serde(default, deserialize_with = "three_opt")]
    position: Option<[f64; 3]>,
    #[serde(default, deserialize_with = "three_opt")]
    direction: Option<[f32; 3]>,
    #[serde(default = "white", deserialize_with = "three")]
    color: [f32; 3],
    #[serde(default = "one")]
    intensity: f32,
    falloff: Option<FalloffName>,
    inner_cone: Option<f32>,
    outer_cone: Option<f32>,
}

fn white() -> [f32; 3] {
    [1.0; 3]
}
fn one() -> f32 {
    1.0
}

#[derive(Deserialize)]
#[serde(rename_all = "kebab-case")]
enum LightType {
    Point,
    Directional,
    Spot,
}

#[derive(Deserialize)]
#[serde(rename_all = "kebab-case")]
enum FalloffName {
    InverseSquare,
    None,
    Mitsuba,
}

/// The light a `[[light]]` section describes, its position relative to `origin` (the scene's,
/// `Scene::origin`); `falloff` when the section does not say.
pub(crate) fn light(l: &LightSection, default_falloff: Falloff, origin: DVec3) -> Result<Light, String> {
    let color = vec3("color", l.color)?;
    if color.min_element() < 0.0 {
        return Err(format!("light color must be ≥ 0, got {color}"));
    }
    if !(l.intensity.is_finite() && l.intensity >= 0.0) {
        return Err(format!("light intensity must be finite and ≥ 0, got {}", l.intensity));
    }
    let direction = |name| -> Result<Vec3, String> {
        let d = vec3(name, l.direction.ok_or(format!("this light needs {name}"))?)?;
        d.try_normalize()
            .ok_or_else(|| "direction must not be zero".to_string())
    };
    let position = || point3("position", l.position.ok_or("this light needs position")?, origin);
    let kind = match l.kind {
        LightType::Point => LightKind::Point { position: position()? },
        LightType::Directional => LightKind::Directional {
            direction: direction("direction")?,
        },
        LightType::Spot => {
            let inner = l.inner_cone.unwrap_or(0.0);
            let outer = l.outer_cone.unwrap_or(45.0);
            if !(0.0..=90.0).contains(&inner) || !(0.0..=90.0).contains(&outer) || inner >= outer {
                return Err(format!(
                    "spot cones must satisfy 0 ≤ inner_cone < outer_cone ≤ 90 degrees, got {inner} and {outer}"
                ));
            }
            LightKind::Spot {
                position: position()?,
                direction: direction("direction")?,
                cos_inner: inner.to_radians().cos(),
                cos_outer: outer.to_radians().cos(),
                profile: match l.falloff {
                    Some(FalloffName::Mitsuba) => SpotProfile::Mitsuba,
                    _ => SpotProfile::Gltf,
                },
            }
        }
    };
    let falloff = match l.falloff {
        None => default_falloff,
        Some(FalloffName::InverseSquare) => Falloff::InverseSquare,
        Some(FalloffName::None) => Falloff::None,
        // Mitsuba's spot: the inverse square with its cone profile (set above).
        Some(FalloffName::Mitsuba) if matches!(l.kind, LightType::Spot) => Falloff::InverseSquare,
        Some(FalloffName::Mitsuba) => {
            return Err("falloff = \"mitsuba\" is Mitsuba's spot-light profile: only a spot light takes it".into())
        }
    };
    Ok(Light {
        kind,
        power: color * l.intensity,
        falloff,
    })
}

/// The light of a `[[light]]` section's `text` (its keys), in a scene whose coordinates are
/// relative to `origin` (`Scene::origin`): the Python module's lights, checked as scene files'
/// are (the message names the key).
pub fn light_from_toml(text: &str, origin: DVec3) -> Result<Light, String> {
    let section: LightSection = toml::from_str(text).map_err(|e| e.message().to_string())?;
    light(&section, Falloff::InverseSquare, origin)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<Light, String> {
        light_from_toml(text, DVec3::ZERO)
    }

    #[test]
    fn falloff_mitsuba_is_a_spot_profile_with_the_inverse_square() {
        let spot =
            read("type = \"spot\"\nposition = [0.0, 2.0, 0.0]\ndirection = [0.0, -1.0, 0.0]\nfalloff = \"mitsuba\"\n")
                .unwrap();
        assert!(matches!(
            spot.kind,
            LightKind::Spot {
                profile: SpotProfile::Mitsuba,
                ..
            }
        ));
        assert_eq!(spot.falloff, Falloff::InverseSquare);
        let plain = read("type = \"spot\"\nposition = [0.0, 2.0, 0.0]\ndirection = [0.0, -1.0, 0.0]\n").unwrap();
        assert!(matches!(
            plain.kind,
            LightKind::Spot {
                profile: SpotProfile::Gltf,
                ..
            }
        ));
        let point = read("type = \"point\"\nposition = [0.0, 2.0, 0.0]\nfalloff = \"mitsuba\"\n").unwrap_err();
        assert!(point.contains("only a spot light"), "{point}");
    }
}
