//! `[[light]]` sections: the point, directional and spot lights of mesh and normal-map scene
//! files, checked (finite, non-negative, non-zero directions, ordered cones) as they are read.

use glam::{DVec3, Vec3};
use serde::Deserialize;

use super::materials::shortest;
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

/// The keys of a `[[light]]` section that [`light_from_toml`] reads back as `light` in a scene
/// whose coordinates are relative to `origin`: what the explorer's state and its saved scene files
/// hold. Colour and intensity are written as the light's power and 1; a spot's cones as degrees
/// (read back within an ulp of its cosines), a direction as the unit vector it is (normalised
/// again on reading, it may move by an ulp). A light with a glTF `range` is refused: a section
/// cannot describe it.
pub fn light_keys(light: &Light, origin: DVec3) -> Result<toml::Table, String> {
    let mut keys = toml::Table::new();
    let floats = |v: [f64; 3]| toml::Value::Array(v.iter().map(|&c| toml::Value::Float(c)).collect());
    let shortest3 = |d: glam::Vec3| floats(d.to_array().map(shortest));
    // Without an origin, the shortest decimals; with one, the exact sum (decimals of the local
    // value, moved by the origin, could round to a neighbouring f32).
    let position = |p: glam::Vec3| match origin == DVec3::ZERO {
        true => shortest3(p),
        false => floats((p.as_dvec3() + origin).to_array()),
    };
    let (kind, falloff) = match light.kind {
        LightKind::Point { position: p } => {
            keys.insert("position".into(), position(p));
            ("point", light.falloff)
        }
        LightKind::Directional { direction: d } => {
            keys.insert("direction".into(), shortest3(d));
            ("directional", Falloff::None)
        }
        LightKind::Spot {
            position: p,
            direction: d,
            cos_inner,
            cos_outer,
            profile,
        } => {
            keys.insert("position".into(), position(p));
            keys.insert("direction".into(), shortest3(d));
            let degrees = |c: f32| (c.clamp(-1.0, 1.0) as f64).acos().to_degrees();
            keys.insert("inner_cone".into(), degrees(cos_inner).into());
            keys.insert("outer_cone".into(), degrees(cos_outer).into());
            if profile == SpotProfile::Mitsuba {
                keys.insert("falloff".into(), "mitsuba".into());
            }
            ("spot", light.falloff)
        }
    };
    keys.insert("type".into(), kind.into());
    keys.insert("color".into(), shortest3(light.power));
    keys.insert("intensity".into(), 1.0.into());
    if !keys.contains_key("falloff") && kind != "directional" {
        let name = match falloff {
            Falloff::InverseSquare => "inverse-square",
            Falloff::None => "none",
            Falloff::InverseSquareWithin { .. } => {
                return Err("a light with a range (glTF's KHR_lights_punctual) has no scene-file section".into())
            }
        };
        keys.insert("falloff".into(), name.into());
    }
    Ok(keys)
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

    /// What `light_keys` writes reads back as the same light: exactly for point lights, within an
    /// ulp for a directional light's direction and a spot's cone cosines; a light with a range is refused.
    #[test]
    fn light_keys_read_back_as_the_light() {
        let origin = DVec3::new(4.0e5, 0.0, -2.0e5);
        let texts = [
            "type = \"point\"\nposition = [400001.5, 2.0, -199999.0]\ncolor = [0.5, 0.25, 1.0]\nintensity = 3.0\n",
            "type = \"point\"\nposition = [400000.0, 1.0, -200000.0]\nfalloff = \"none\"\n",
            "type = \"directional\"\ndirection = [1.0, -2.0, 0.5]\nintensity = 2.0\n",
            "type = \"spot\"\nposition = [400000.0, 2.0, -200000.0]\ndirection = [0.0, -1.0, 0.0]\ninner_cone = 10.0\nouter_cone = 30.0\nfalloff = \"mitsuba\"\n",
        ];
        for text in texts {
            let light = light_from_toml(text, origin).unwrap();
            let keys = light_keys(&light, origin).unwrap();
            let back = light_from_toml(&toml::to_string(&keys).unwrap(), origin).unwrap();
            match (light.kind, back.kind) {
                (
                    LightKind::Spot {
                        cos_inner: a,
                        cos_outer: b,
                        ..
                    },
                    LightKind::Spot {
                        cos_inner: c,
                        cos_outer: d,
                        ..
                    },
                ) => {
                    assert!((a - c).abs() <= f32::EPSILON && (b - d).abs() <= f32::EPSILON, "{text}");
                    assert_eq!((light.power, light.falloff), (back.power, back.falloff), "{text}");
                }
                // A unit direction normalised again may move by an ulp.
                (LightKind::Directional { direction: a }, LightKind::Directional { direction: b }) => {
                    assert!((a - b).abs().max_element() <= f32::EPSILON, "{text}");
                    assert_eq!(light.power, back.power, "{text}");
                }
                _ => assert_eq!(light, back, "{text}"),
            }
        }
        let ranged = Light {
            falloff: Falloff::InverseSquareWithin { range: 3.0 },
            ..light_from_toml(texts[0], origin).unwrap()
        };
        assert!(light_keys(&ranged, origin).unwrap_err().contains("range"));
    }
}
