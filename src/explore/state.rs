//! The explorer's state: the part of a scene file its page edits (materials, lights, exposure,
//! and a normal image's preset), as JSON. A state is checked by reading it as a scene file is
//! read — the same functions, so a bad value gets the message a file with that value gets — and
//! saved by writing those sections into the scene file the explorer opened.
//!
//! A state names no file: its sections' keys are parameters, and any other key is refused.

use std::collections::BTreeMap;
use std::str::FromStr;

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

/// The keys of one `[material.NAME]` or `[[light]]` section, as JSON.
pub type Keys = Map<String, Value>;

/// The name of a normal image's one material in states and saved files.
pub const NORMAL_MAP_MATERIAL: &str = "normal_map";

/// What the page edits (docs/explore.md, "The HTTP API").
#[derive(Clone, Debug, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct State {
    /// A normal image's preset, `tp` or `physical`; absent for a scene.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub preset: Option<String>,
    /// Each editable material's keys, by name.
    #[serde(default)]
    pub materials: BTreeMap<String, Keys>,
    /// Every light's keys, in order.
    #[serde(default)]
    pub lights: Vec<Keys>,
    /// Exposure in stops of the PNG (not the tp preset's, which is min-max normalised).
    #[serde(default)]
    pub exposure: f32,
}

impl State {
    /// Reads a state from a request's JSON body.
    pub fn from_json(body: &[u8]) -> Result<State, String> {
        serde_json::from_slice(body).map_err(|e| format!("state: {e}"))
    }
}

/// A section's keys as TOML text, every JSON number a float (no key of a material or light
/// section is an integer: `intensity = 1` in JSON is `1.0`). Nested tables are refused.
pub fn section_text(keys: &Keys) -> Result<String, String> {
    let mut table = toml::Table::new();
    for (key, value) in keys {
        table.insert(key.clone(), toml_value(key, value)?);
    }
    toml::to_string(&table).map_err(|e| e.to_string())
}

fn toml_value(key: &str, value: &Value) -> Result<toml::Value, String> {
    Ok(match value {
        Value::Bool(b) => toml::Value::Boolean(*b),
        Value::Number(n) => toml::Value::Float(n.as_f64().ok_or_else(|| format!("{key}: {n} is not a number"))?),
        Value::String(s) => toml::Value::String(s.clone()),
        Value::Array(items) => toml::Value::Array(items.iter().map(|v| toml_value(key, v)).collect::<Result<_, _>>()?),
        Value::Null | Value::Object(_) => {
            return Err(format!("{key}: expected a number, a string, a boolean or an array"));
        }
    })
}

/// A TOML table's keys as JSON (what [`crate::scene::file::material_keys`] and
/// [`crate::scene::file::light_keys`] give, for a state).
pub fn json_keys(table: &toml::Table) -> Keys {
    table
        .iter()
        .map(|(k, v)| (k.clone(), serde_json::to_value(v).unwrap_or(Value::Null)))
        .collect()
}

/// `base` (a scene file's text) with the state's sections written in: each material of the
/// state as `[material.NAME]` (others left as they are), the lights as the `[[light]]` array,
/// the exposure in `[film]`; for a normal image (`preset` set), `[normal_map]` names the preset
/// and the material, and a tp file has no `[film]` (the reader refuses an exposure there).
pub fn scene_file(base: &str, state: &State) -> Result<String, String> {
    let mut doc = toml_edit::DocumentMut::from_str(base).map_err(|e| format!("the scene file: {e}"))?;
    let section = |keys: &Keys| -> Result<toml_edit::Table, String> {
        let text = section_text(keys)?;
        let parsed = toml_edit::DocumentMut::from_str(&text).map_err(|e| e.to_string())?;
        Ok(parsed.as_table().clone())
    };
    if !doc.contains_table("material") {
        let mut materials = toml_edit::Table::new();
        materials.set_implicit(true);
        doc.insert("material", toml_edit::Item::Table(materials));
    }
    let materials = doc["material"]
        .as_table_mut()
        .ok_or("the scene file's material is not a table")?;
    if state.preset.is_some() {
        materials.clear();
    }
    for (name, keys) in &state.materials {
        materials.insert(name, toml_edit::Item::Table(section(keys)?));
    }
    let mut lights = toml_edit::ArrayOfTables::new();
    for keys in &state.lights {
        lights.push(section(keys)?);
    }
    doc.remove("light");
    if !lights.is_empty() {
        doc.insert("light", toml_edit::Item::ArrayOfTables(lights));
    }
    match state.preset.as_deref() {
        Some(preset) => {
            let nm = doc["normal_map"]
                .as_table_mut()
                .ok_or("the scene file has no [normal_map] table")?;
            nm.remove("brdf");
            nm.insert("preset", toml_edit::value(preset));
            nm.insert("material", toml_edit::value(NORMAL_MAP_MATERIAL));
            doc.remove("film");
            if preset != "tp" {
                doc["film"]["exposure"] = toml_edit::value(state.exposure as f64);
            }
        }
        None => {
            if !doc.contains_table("film") {
                doc.insert("film", toml_edit::table());
            }
            doc["film"]["exposure"] = toml_edit::value(state.exposure as f64);
        }
    }
    Ok(doc.to_string())
}

/// A Python string literal of `text` (TOML text has no triple quotes of its own to escape but
/// may hold backslashes and quotes).
pub fn python_string(text: &str) -> String {
    format!(
        "\"\"\"\\\n{}\"\"\"",
        text.replace('\\', "\\\\").replace("\"\"\"", "\\\"\\\"\\\"")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_state_with_another_key_is_refused_and_names_it() {
        let e = State::from_json(br#"{"materials": {}, "mesh": "/etc/passwd"}"#).unwrap_err();
        assert!(e.contains("unknown field `mesh`"), "{e}");
        let e = State::from_json(b"[1, 2]").unwrap_err();
        assert!(e.starts_with("state: "), "{e}");
    }

    #[test]
    fn section_text_writes_numbers_as_floats_and_refuses_tables() {
        let keys: Keys = serde_json::from_str(r#"{"intensity": 1, "color": [1, 0.5, 0], "type": "point"}"#).unwrap();
        let text = section_text(&keys).unwrap();
        assert!(
            text.contains("intensity = 1.0") && text.contains("color = [1.0, 0.5, 0.0]"),
            "{text}"
        );
        let nested: Keys = serde_json::from_str(r#"{"position": {"x": 1}}"#).unwrap();
        assert!(section_text(&nested).unwrap_err().starts_with("position: "));
    }

    #[test]
    fn scene_file_replaces_the_sections_the_state_holds_and_keeps_the_rest() {
        let base = "# my scene\n[[object]]\nmesh = \"m.obj\"\nmaterial = \"a\"\n\n[material.a]\nmodel = \"lambert\"\n\n[material.b]\nmodel = \"lambert\"\n\n[[light]]\ntype = \"point\"\nposition = [0.0, 1.0, 0.0]\n";
        let state = State::from_json(
            br#"{"materials": {"a": {"model": "cook-torrance", "roughness": 0.25}},
                 "lights": [{"type": "directional", "direction": [0, -1, 0]}], "exposure": 1.5}"#,
        )
        .unwrap();
        let text = scene_file(base, &state).unwrap();
        let doc: toml::Table = toml::from_str(&text).unwrap();
        assert_eq!(doc["material"]["a"]["roughness"].as_float(), Some(0.25));
        assert_eq!(doc["material"]["b"]["model"].as_str(), Some("lambert"));
        assert_eq!(doc["light"].as_array().unwrap().len(), 1);
        assert_eq!(doc["light"][0]["type"].as_str(), Some("directional"));
        assert_eq!(doc["film"]["exposure"].as_float(), Some(1.5));
        assert!(text.starts_with("# my scene\n"), "{text}");
    }

    #[test]
    fn a_normal_image_file_names_its_preset_and_material() {
        let base = "[normal_map]\nimage = \"n.png\"\nbrdf = \"lambert\"\n\n[film]\nexposure = 2.0\n";
        let state = State::from_json(
            br#"{"preset": "tp", "materials": {"normal_map": {"model": "lambert"}}, "lights": [], "exposure": 3}"#,
        )
        .unwrap();
        let doc: toml::Table = toml::from_str(&scene_file(base, &state).unwrap()).unwrap();
        assert_eq!(doc["normal_map"]["preset"].as_str(), Some("tp"));
        assert_eq!(doc["normal_map"]["material"].as_str(), Some(NORMAL_MAP_MATERIAL));
        assert!(doc["normal_map"].get("brdf").is_none() && doc.get("film").is_none() && doc.get("light").is_none());
    }

    #[test]
    fn python_string_survives_quotes_and_backslashes() {
        assert_eq!(python_string("a = \"\\\\x\"\n"), "\"\"\"\\\na = \"\\\\\\\\x\"\n\"\"\"");
    }
}
