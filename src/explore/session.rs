//! The explorer's session: a scene (held in a [`Preview`]) or a normal image, the scene file
//! its state is saved into, and one call per thing the page asks for.

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

use glam::DVec3;
use serde_json::{json, Value};

use super::state::{json_keys, python_string, scene_file, section_text, State, NORMAL_MAP_MATERIAL};
use crate::accel::Bvh;
use crate::error::{InputError, InputResult};
use crate::lanes::dot3;
use crate::material::Material;
use crate::normal_map;
use crate::normal_map::bake::bake_normals;
use crate::normal_map::formats::{encode_min_max_png, encode_normal_png};
use crate::normal_map::image::NormalImage;
use crate::normal_map::scene_file::{NormalMapScene, Preset};
use crate::output::{encode, Format};
use crate::render::preview::Preview;
use crate::scene::file::{
    light_from_toml, light_keys, material_from_toml, material_keys, MaterialDefaults, MeshTable, ModelName,
};
use crate::scene::procedural::{icosphere, plane};
use crate::scene::{extension, load, Scene};
use crate::shading::shader::brdf_value;

/// What the explorer opened.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// A normal image, shaded in the normal-map mode.
    NormalImage,
    /// A scene file, a bare mesh or a glTF file.
    Scene,
}

/// The scene the explorer bakes its default normal image from (shipped, embedded with its two
/// meshes, so that `pointshade explore` needs no file).
const DEFAULT_SCENE: &str = include_str!("../../scenes/lambert.toml");

/// The name a baked normal image is saved under (`GET /api/normals.png`), which the saved scene
/// file of the default session names.
pub const BAKED_IMAGE: &str = "explore-normals.png";

/// Where the explorer looks for Mitsuba 3 unless told: the repository's validation folder, as
/// `pointshade validate` does.
pub const DEFAULT_MITSUBA_DIR: &str = "validation";

/// An open scene or normal image and what its page edits (see the module's comment).
pub struct Explorer {
    held: Held,
    /// The opened file's name without its folder (the page's title; no request learns more).
    name: String,
    /// The scene file the state is written into: the opened one, or for a normal image or a bare
    /// mesh or glTF file, the scene file that opens it.
    base: String,
    /// The state the session starts in.
    initial: State,
    /// The validation folder whose Mitsuba 3 the page compares with (`validation/`).
    mitsuba_dir: PathBuf,
}

enum Held {
    NormalImage {
        image: NormalImage<'static>,
        /// The image's PNG bytes (`GET /api/normals.png`).
        png: Vec<u8>,
        /// Where the image's scene file would sit: the image's folder.
        dir: PathBuf,
    },
    Scene {
        preview: Box<Preview>,
        origin: DVec3,
        /// For a bare mesh or glTF file, its folder: a saved file is checked to open as it did.
        bare: Option<PathBuf>,
    },
}

impl Explorer {
    /// Opens `input`: a PNG normal image, a scene file (a `[normal_map]` file opens as its normal
    /// image), a bare mesh or a glTF file; with none, the assignment's setting (tp preset,
    /// Cook-Torrance) on a normal image baked from the shipped `scenes/lambert.toml`.
    pub fn open(input: Option<&Path>) -> InputResult<Explorer> {
        let Some(path) = input else {
            return Self::baked_default();
        };
        let name = file_name(path);
        match extension(path).as_deref() {
            Some("png") => {
                let png = crate::input_files::read(path).map_err(|e| InputError::new(path, e))?;
                let image = NormalImage::decode(path, &png)?;
                let scene = NormalMapScene::from_preset(path, Preset::Tp, ModelName::CookTorrance);
                let base = format!("[normal_map]\nimage = {}\n", toml::Value::String(name.clone()));
                Self::normal_image(image, png, dir_of(path), &scene, name, base)
            }
            Some("toml") => {
                let text = crate::input_files::read_to_string(path).map_err(|e| InputError::new(path, e))?;
                let table = crate::scene::file::parse_toml_table(path, text.clone())?;
                if table.contains_key("normal_map") {
                    let scene = NormalMapScene::load(path, None)?;
                    let png = crate::input_files::read(&scene.image).map_err(|e| InputError::new(&scene.image, e))?;
                    let image = NormalImage::decode(&scene.image, &png)?;
                    return Self::normal_image(image, png, dir_of(path), &scene, name, text);
                }
                Self::scene(load(path)?, name, text, None)
            }
            // A bare mesh or glTF file is a scene file of one object (its camera and lights
            // automatic, as on the command line): the state is written into that.
            _ => {
                let base = format!("[[object]]\nmesh = {}\n", toml::Value::String(name.clone()));
                Self::scene(load(path)?, name, base, Some(dir_of(path)))
            }
        }
    }

    fn baked_default() -> InputResult<Explorer> {
        let name = Path::new("scenes/lambert.toml (embedded)");
        let mut meshes = MeshTable::new();
        meshes.insert("../meshes/icosphere.obj".into(), icosphere(4).to_arrays());
        meshes.insert("../meshes/plane.obj".into(), plane(10.0, 1).to_arrays());
        let scene = crate::scene::file::load_scene_text(name, DEFAULT_SCENE.into(), Path::new("."), &meshes)?;
        let baked = bake_normals(&scene, &Bvh::for_scene(&scene)).map_err(|e| InputError::new(name, e))?;
        let png = encode_normal_png(baked.width, baked.height, &baked.normals).map_err(|e| InputError::new(name, e))?;
        let image = NormalImage::decode(Path::new(BAKED_IMAGE), &png)?;
        let nm = NormalMapScene::from_preset(Path::new(BAKED_IMAGE), Preset::Tp, ModelName::CookTorrance);
        let base = format!("[normal_map]\nimage = \"{BAKED_IMAGE}\"\n");
        Self::normal_image(image, png, PathBuf::from("."), &nm, BAKED_IMAGE.into(), base)
    }

    fn normal_image(
        image: NormalImage<'static>,
        png: Vec<u8>,
        dir: PathBuf,
        scene: &NormalMapScene,
        name: String,
        base: String,
    ) -> InputResult<Explorer> {
        let state = normal_map_state(scene).map_err(|e| InputError::new(Path::new(&name), e))?;
        Ok(Explorer {
            held: Held::NormalImage { image, png, dir },
            name,
            base,
            initial: state,
            mitsuba_dir: PathBuf::from(DEFAULT_MITSUBA_DIR),
        })
    }

    fn scene(mut scene: Scene, name: String, base: String, bare: Option<PathBuf>) -> InputResult<Explorer> {
        let err = |e: String| InputError::new(Path::new(&name), e);
        // Materials a section can describe; the others (textured, glTF's) are shown, not edited.
        let materials = scene
            .materials
            .iter()
            .filter_map(|m| Some((m.name.clone(), json_keys(&material_keys(m).ok()?))))
            .collect();
        let lights = scene
            .lights
            .iter()
            .map(|l| light_keys(l, scene.origin).map(|k| json_keys(&k)))
            .collect::<Result<_, _>>()
            .map_err(err)?;
        let initial = State {
            preset: None,
            materials,
            lights,
            exposure: scene.film.exposure,
        };
        let origin = scene.origin;
        scene.film.crop = None;
        // Preview::new refuses a film without a fixed number of samples per pixel.
        let preview = Preview::new(scene, &[]).map_err(err)?;
        Ok(Explorer {
            held: Held::Scene {
                preview: Box::new(preview),
                origin,
                bare,
            },
            name,
            base,
            initial,
            mitsuba_dir: PathBuf::from(DEFAULT_MITSUBA_DIR),
        })
    }

    /// Compares with the Mitsuba 3 that `validation/install.sh` installed into `dir` (the
    /// repository's `validation` folder by default).
    pub fn set_mitsuba_dir(&mut self, dir: PathBuf) {
        self.mitsuba_dir = dir;
    }

    /// The validation folder the Mitsuba comparison uses.
    pub fn mitsuba_dir(&self) -> &Path {
        &self.mitsuba_dir
    }

    /// The held scene as `state` edits it (what the Mitsuba comparison exports); a normal image
    /// has no scene.
    pub fn edited_scene(&self, state: &State) -> Result<Scene, String> {
        let Held::Scene { preview, origin, .. } = &self.held else {
            return Err("a normal image is shaded by the normal-map mode, which Mitsuba 3 has no counterpart of: open a scene file to compare (pointshade explore scenes/cook-torrance.toml)".into());
        };
        let (materials, lights) = scene_edits(&self.initial, preview, *origin, state)?;
        let mut scene = preview.scene().clone();
        scene.materials = materials;
        scene.lights = lights;
        scene.default_lights = false;
        Ok(scene)
    }

    /// Normal image or scene.
    pub fn mode(&self) -> Mode {
        match self.held {
            Held::NormalImage { .. } => Mode::NormalImage,
            Held::Scene { .. } => Mode::Scene,
        }
    }

    /// The opened file's name, without its folder.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The state the session started in.
    pub fn initial_state(&self) -> &State {
        &self.initial
    }

    /// A scene's samples per pixel (the last pass of a progressive preview); none for a normal
    /// image.
    pub fn spp(&self) -> Option<u32> {
        match &self.held {
            Held::NormalImage { .. } => None,
            Held::Scene { preview, .. } => Some(preview.scene().film.spp),
        }
    }

    /// The image's size in pixels.
    pub fn size(&self) -> (u32, u32) {
        match &self.held {
            Held::NormalImage { image, .. } => (image.width, image.height),
            Held::Scene { preview, .. } => (preview.scene().film.width, preview.scene().film.height),
        }
    }

    /// The normal image's PNG bytes (none for a scene).
    pub fn normals_png(&self) -> Option<&[u8]> {
        match &self.held {
            Held::NormalImage { png, .. } => Some(png),
            Held::Scene { .. } => None,
        }
    }

    /// A normal image's state under each preset, its material of the same model (what the page
    /// switches to when the preset changes); `null` for a scene.
    pub fn preset_states(&self) -> serde_json::Value {
        if self.mode() == Mode::Scene {
            return serde_json::Value::Null;
        }
        let model = self.initial.materials[NORMAL_MAP_MATERIAL]
            .get("model")
            .and_then(|m| m.as_str())
            .and_then(|m| m.parse::<ModelName>().ok())
            .unwrap_or(ModelName::CookTorrance);
        let mut states = serde_json::Map::new();
        for preset in [Preset::Tp, Preset::Physical] {
            let scene = NormalMapScene::from_preset(Path::new(&self.name), preset, model);
            if let Ok(state) = normal_map_state(&scene) {
                states.insert(preset.name().into(), serde_json::to_value(state).unwrap_or_default());
            }
        }
        serde_json::Value::Object(states)
    }

    /// The scene file of `state`: `pointshade normalmap` or `pointshade render` of it gives the
    /// image [`Explorer::render`] gives. A file that would not load is not saved: the state is
    /// read back first.
    pub fn save(&self, state: &State) -> Result<String, String> {
        match &self.held {
            Held::NormalImage { dir, .. } => Ok(normal_map_scene(&self.name, &self.base, dir, state)?.0),
            Held::Scene { preview, origin, bare } => {
                scene_edits(&self.initial, preview, *origin, state)?;
                let text = scene_file(&self.base, state)?;
                if let Some(dir) = bare {
                    check_view_saved(&self.name, preview.scene(), dir, &text)?;
                }
                Ok(text)
            }
        }
    }

    /// Python that renders `state` as the page shows it.
    pub fn python(&self, state: &State) -> Result<String, String> {
        let text = self.save(state)?;
        let call = match self.mode() {
            Mode::NormalImage => "radiance = pointshade.shade_normal_image(SCENE)  # L_o, float32 (H, W, 3)",
            Mode::Scene => {
                "out = pointshade.render(\"scene.toml\", text=SCENE)  # out[\"image\"]: L_o, float32 (H, W, 3)"
            }
        };
        Ok(format!(
            "import pointshade\n\n# The explorer's state as a scene file (its paths relative to the folder of {}).\nSCENE = {}\n{call}\n",
            self.name,
            python_string(&text)
        ))
    }

    /// The PNG `pointshade normalmap` or `pointshade render` writes for the saved `state`
    /// (`stop`, when set, ends a scene's render early with an error). A scene may be rendered
    /// at `spp` samples per pixel instead of its film's (a progressive preview's coarse pass:
    /// [`Preview::render_pass`]); a normal image has one evaluation per pixel, nothing to refine.
    pub fn render(&mut self, state: &State, spp: Option<u32>, stop: Option<&AtomicBool>) -> Result<Vec<u8>, String> {
        match &mut self.held {
            Held::NormalImage { .. } if spp.is_some() => {
                Err("spp: a normal image is shaded once per pixel, it has no samples to refine".into())
            }
            Held::NormalImage { image, dir, .. } => {
                let (_, scene) = normal_map_scene(&self.name, &self.base, dir, state)?;
                let shaded = normal_map::shade(&scene, image, "the explorer's image").map_err(|e| e.to_string())?;
                match scene.preset {
                    Preset::Tp => encode_min_max_png(&shaded.radiance).map(|(bytes, _)| bytes),
                    Preset::Physical => encode(&shaded.radiance, Format::Png, scene.exposure),
                }
            }
            Held::Scene { preview, origin, .. } => {
                apply(&self.initial, preview, *origin, state)?;
                let spp = spp.unwrap_or(preview.scene().film.spp);
                let rendered = preview.render_pass(spp, stop)?;
                encode(&rendered.image, Format::Png, state.exposure)
            }
        }
    }

    /// What shades pixel (`x`, `y`) under `state`: its normal, the direction to the first light
    /// that reaches it, the direction to the viewer, its material and f_r; angles in the local
    /// frame of its normal (θ from the normal, φ from the frame's first axis).
    pub fn pixel(&mut self, state: &State, x: u32, y: u32) -> Result<Value, String> {
        let (w, h) = self.size();
        if x >= w || y >= h {
            return Err(format!("pixel ({x}, {y}) is outside the {w}×{h} image"));
        }
        let (point, material, lights) = match &mut self.held {
            Held::NormalImage { image, dir, .. } => {
                let (_, scene) = normal_map_scene(&self.name, &self.base, dir, state)?;
                let surface = normal_map::image_surface(&scene, image)?;
                let (rgb, alpha) = image.pixel((y * w + x) as usize);
                (surface.point(x, y, rgb, alpha), scene.material, scene.lights)
            }
            Held::Scene { preview, origin, .. } => {
                apply(&self.initial, preview, *origin, state)?;
                let point = preview.surface_at(x, y);
                let material = point.map(|p| preview.scene().materials[p.material as usize].clone());
                (
                    point,
                    material.unwrap_or_else(|| Material::lambert("", [0.0; 3])),
                    preview.scene().lights.clone(),
                )
            }
        };
        let Some(p) = point else {
            return Ok(json!({"hit": false, "x": x, "y": y}));
        };
        let wo = p.to_viewer.as_dvec3().to_array();
        let mut n = p.shading_normal.as_dvec3().normalize_or_zero().to_array();
        if material.two_sided && dot3(n, wo) < 0.0 {
            n = n.map(|c| -c);
        }
        let wi = lights
            .iter()
            .filter_map(|l| l.sample(p.position))
            .map(|s| s.wi.as_dvec3().to_array())
            .find(|wi| dot3(n, *wi) > 0.0)
            .unwrap_or([0.0; 3]);
        let f_r = brdf_value(&material, n, wi, wo);
        let (theta_i, phi_i) = local_angles(n, wi);
        let (theta_o, phi_o) = local_angles(n, wo);
        let keys = material_keys(&material).map(|k| json_keys(&k)).unwrap_or_default();
        Ok(json!({
            "hit": true, "x": x, "y": y, "n": n, "wi": wi, "wo": wo,
            "material": material.name, "material_keys": keys, "f_r": f_r,
            "theta_i": theta_i, "phi_i": phi_i, "theta_o": theta_o, "phi_o": phi_o,
        }))
    }
}

/// Checks that `state` is one of a `mode` session: a preset for a normal image, none for a scene.
fn check_preset(mode: Mode, state: &State) -> Result<(), String> {
    match (mode, state.preset.as_deref()) {
        (Mode::NormalImage, Some("tp" | "physical")) | (Mode::Scene, None) => Ok(()),
        (Mode::NormalImage, Some(p)) => Err(format!("unknown preset '{p}' (expected tp or physical)")),
        (Mode::NormalImage, None) => Err("a normal image's state needs a preset: tp or physical".into()),
        (Mode::Scene, Some(_)) => Err("preset applies to a normal image, not to a scene".into()),
    }
}

/// The scene file of a normal image's `state` (written into `base`) and the normal-map scene
/// read from it, as `pointshade normalmap` reads it from the folder `dir`.
fn normal_map_scene(name: &str, base: &str, dir: &Path, state: &State) -> Result<(String, NormalMapScene), String> {
    check_preset(Mode::NormalImage, state)?;
    let text = scene_file(base, state)?;
    let scene = NormalMapScene::from_text(Path::new(name), text.clone(), dir, None).map_err(|e| e.to_string())?;
    Ok((text, scene))
}

/// The held scene's materials and lights under `state` (its editable materials — those of the
/// `initial` state — and every light), checked as a scene file's sections are; the scene is
/// left as it is.
fn scene_edits(
    initial: &State,
    preview: &Preview,
    origin: DVec3,
    state: &State,
) -> Result<(Vec<Material>, Vec<crate::light::Light>), String> {
    check_preset(Mode::Scene, state)?;
    let editable = &initial.materials;
    let mut materials = preview.scene().materials.clone();
    for (name, keys) in &state.materials {
        if !editable.contains_key(name) {
            let names: Vec<&str> = editable.keys().map(String::as_str).collect();
            return Err(format!(
                "material '{name}' cannot be edited here (editable: {})",
                names.join(", ")
            ));
        }
        let m = materials
            .iter_mut()
            .find(|m| &m.name == name)
            .expect("editable names are the scene's");
        *m = material_from_toml(name, &section_text(keys)?, &MaterialDefaults::SCENE)?;
    }
    let lights = state
        .lights
        .iter()
        .enumerate()
        .map(|(i, keys)| light_from_toml(&section_text(keys)?, origin).map_err(|e| format!("light {}: {e}", i + 1)))
        .collect::<Result<Vec<_>, String>>()?;
    Ok((materials, lights))
}

/// Applies `state` to `preview` ([`scene_edits`]).
fn apply(initial: &State, preview: &mut Preview, origin: DVec3, state: &State) -> Result<(), String> {
    let (materials, lights) = scene_edits(initial, preview, origin, state)?;
    preview.set_materials(materials)?;
    preview.set_lights(lights)
}

/// A bare mesh or glTF file is saved as a scene file of one object, which frames the mesh
/// automatically and takes a default film: where the file chose otherwise (a glTF file's own
/// camera), the saved file `text` would render another view than `held`'s, and is refused.
fn check_view_saved(name: &str, held: &Scene, dir: &Path, text: &str) -> Result<(), String> {
    let saved = crate::scene::file::load_scene_text(Path::new(name), text.into(), dir, &MeshTable::new())
        .map_err(|e| e.to_string())?;
    let film = |s: &Scene| (s.film.width, s.film.height, s.film.spp, s.film.sampler);
    if saved.camera != held.camera || film(&saved) != film(held) {
        return Err(format!(
            "{name}: its own camera cannot be written into a scene file (a scene file frames a mesh itself), so a saved file would show another view; write a scene file with a [camera] and open that"
        ));
    }
    Ok(())
}

/// The state of a normal-map scene: its material, lights, preset and exposure, every key written.
fn normal_map_state(scene: &NormalMapScene) -> Result<State, String> {
    Ok(State {
        preset: Some(scene.preset.name().into()),
        materials: [(
            NORMAL_MAP_MATERIAL.to_string(),
            json_keys(&material_keys(&scene.material)?),
        )]
        .into(),
        lights: scene
            .lights
            .iter()
            .map(|l| light_keys(l, DVec3::ZERO).map(|k| json_keys(&k)))
            .collect::<Result<_, _>>()?,
        exposure: scene.exposure,
    })
}

/// θ from `n` and φ of `d` in a frame around `n` whose first axis is the world axis least
/// aligned with it, projected (degrees; 0, 0 for a zero direction).
fn local_angles(n: [f64; 3], d: [f64; 3]) -> (f64, f64) {
    let n = DVec3::from(n);
    let d = DVec3::from(d);
    if d == DVec3::ZERO || n == DVec3::ZERO {
        return (0.0, 0.0);
    }
    let (t, b) = n.any_orthonormal_pair();
    let theta = n.dot(d).clamp(-1.0, 1.0).acos().to_degrees();
    let phi = d.dot(b).atan2(d.dot(t)).to_degrees();
    (theta, phi.rem_euclid(360.0))
}

fn file_name(path: &Path) -> String {
    path.file_name()
        .unwrap_or(path.as_os_str())
        .to_string_lossy()
        .into_owned()
}

fn dir_of(path: &Path) -> PathBuf {
    path.parent().map(Path::to_path_buf).unwrap_or_default()
}

#[cfg(test)]
mod tests;
