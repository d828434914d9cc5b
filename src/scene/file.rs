//! TOML scene files (the contract in README.md, "Scene files"); objects are OBJ or glTF meshes.
//!
//! Parsing is strict: unknown keys, wrong types and unknown names are errors with the file, line
//! and column. Each section is kept with its span so that checks made after parsing (a NaN, an
//! unknown material name) also point at the right place. Normal-map scene files (a
//! `[normal_map]` section) share the light and material sections and are read by
//! [`super::normal_map`].

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::{EulerRot, Mat4, Quat, Vec3};
use serde::Deserialize;
use toml::Spanned;

use crate::error::{InputError, InputResult};
use crate::film::{FilmSettings, SamplerKind};
use crate::scene::framing::{default_lights, default_material, frame_bounds};
use crate::scene::gltf::load_gltf;
use crate::scene::mesh::DerivedNormals;
use crate::scene::mesh::TriangleMesh;
use crate::scene::obj::{load_obj_underived, NO_MATERIAL};
use crate::scene::textures::{decode_used_images, offset_images, PendingImage};
use crate::scene::{extension, Scene, SceneObject};
use crate::shading::light::{Falloff, Light, LightKind};
use crate::shading::material::{BlinnPhong, CookTorrance, Material, Specular};
use crate::shading::shadow::{ShadowOffset, ShadowTerminator};
use crate::surface::camera::{CameraSpec, FovAxis, Projection};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    /// Only to say that such a file is for `pointshade normalmap`.
    normal_map: Option<Spanned<toml::Table>>,
    film: Option<Spanned<FilmSection>>,
    camera: Option<Spanned<CameraSection>>,
    render: Option<RenderSection>,
    #[serde(default)]
    light: Vec<Spanned<LightSection>>,
    #[serde(default)]
    material: BTreeMap<String, Spanned<MaterialSection>>,
    #[serde(default)]
    object: Vec<Spanned<ObjectSection>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FilmSection {
    width: Option<u32>,
    height: Option<u32>,
    spp: Option<u32>,
    sampler: Option<Spanned<String>>,
    filter: Option<FilterName>,
    exposure: Option<f32>,
    seed: Option<u64>,
    adaptive_threshold: Option<f32>,
    time_budget: Option<f32>,
}

#[derive(Deserialize)]
#[serde(rename_all = "kebab-case")]
enum FilterName {
    Box,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CameraSection {
    #[serde(rename = "type", default)]
    kind: CameraType,
    position: [f32; 3],
    look_at: [f32; 3],
    #[serde(default = "y_up")]
    up: [f32; 3],
    fov: Option<f32>,
    #[serde(default)]
    fov_axis: FovAxisName,
    scale: Option<f32>,
    #[serde(default)]
    near_clip: f32,
    far_clip: Option<f32>,
}

fn y_up() -> [f32; 3] {
    [0.0, 1.0, 0.0]
}

#[derive(Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
enum CameraType {
    #[default]
    Perspective,
    Orthographic,
}

#[derive(Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
enum FovAxisName {
    X,
    #[default]
    Y,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RenderSection {
    shadows: Option<bool>,
    shadow_offset: Option<Spanned<String>>,
    shadow_terminator: Option<Spanned<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct LightSection {
    #[serde(rename = "type")]
    kind: LightType,
    position: Option<[f32; 3]>,
    direction: Option<[f32; 3]>,
    #[serde(default = "white")]
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
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MaterialSection {
    #[serde(default)]
    model: ModelName,
    albedo: Option<[f32; 3]>,
    kd: Option<f32>,
    two_sided: Option<bool>,
    // Blinn-Phong
    ks: Option<f32>,
    shininess: Option<f32>,
    specular_color: Option<[f32; 3]>,
    // Cook-Torrance
    roughness: Option<f32>,
    metallic: Option<bool>,
    ior: Option<f32>,
    d: Option<Spanned<String>>,
    g: Option<Spanned<String>>,
    fresnel: Option<Spanned<String>>,
    eta: Option<[f32; 3]>,
    k: Option<[f32; 3]>,
}

/// A material model, as named in scene files and on the command line.
#[derive(Deserialize, Default, PartialEq, Eq, Clone, Copy, Debug)]
#[serde(rename_all = "kebab-case")]
pub enum ModelName {
    /// Lambert diffuse only.
    #[default]
    Lambert,
    /// Lambert + Blinn-Phong.
    BlinnPhong,
    /// Lambert + Cook-Torrance.
    CookTorrance,
}

impl ModelName {
    /// Every model, in documentation order.
    pub const ALL: [ModelName; 3] = [ModelName::Lambert, ModelName::BlinnPhong, ModelName::CookTorrance];

    /// The name used in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            ModelName::Lambert => "lambert",
            ModelName::BlinnPhong => "blinn-phong",
            ModelName::CookTorrance => "cook-torrance",
        }
    }
}

impl std::str::FromStr for ModelName {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        ModelName::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| format!("unknown BRDF '{s}' (expected lambert, blinn-phong or cook-torrance)"))
    }
}

/// What the keys a material section leaves out default to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MaterialDefaults {
    /// Diffuse colour.
    pub albedo: [f32; 3],
    /// Diffuse weight.
    pub kd: f32,
    /// Two-sided or one-sided.
    pub two_sided: bool,
    /// The Blinn-Phong lobe of a `blinn-phong` material.
    pub blinn_phong: BlinnPhong,
    /// The Cook-Torrance lobe of a `cook-torrance` material.
    pub cook_torrance: CookTorrance,
}

impl MaterialDefaults {
    /// The defaults of mesh scene files (README.md, "Scene files").
    pub const SCENE: MaterialDefaults = MaterialDefaults {
        albedo: [0.8; 3],
        kd: 1.0,
        two_sided: true,
        blinn_phong: BlinnPhong {
            ks: 1.0,
            shininess: 32.0,
            color: [1.0; 3],
        },
        cook_torrance: CookTorrance::ASSIGNMENT,
    };

    /// A material of `model` with every parameter at its default.
    pub fn material(&self, name: &str, model: ModelName) -> Material {
        Material {
            name: name.to_string(),
            albedo: self.albedo,
            kd: self.kd,
            two_sided: self.two_sided,
            specular: match model {
                ModelName::Lambert => Specular::None,
                ModelName::BlinnPhong => Specular::BlinnPhong(self.blinn_phong),
                ModelName::CookTorrance => Specular::CookTorrance(self.cook_torrance),
            },
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ObjectSection {
    mesh: String,
    material: Option<Spanned<String>>,
    transform: Option<TransformSection>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TransformSection {
    #[serde(default)]
    translate: [f32; 3],
    #[serde(default)]
    rotate: [f32; 3],
    scale: Option<ScaleValue>,
}

#[derive(Deserialize)]
#[serde(untagged)]
enum ScaleValue {
    Uniform(f32),
    PerAxis([f32; 3]),
}

/// Reads a scene file and everything it references.
pub fn load_scene_file(path: &Path) -> InputResult<Scene> {
    let text = std::fs::read_to_string(path).map_err(|e| InputError::new(path, format!("cannot read: {e}")))?;
    let at = |span: std::ops::Range<usize>, problem: String| {
        let (line, col) = line_col(&text, span.start);
        InputError::new(path, format!("line {line}, column {col}: {problem}"))
    };
    let file: SceneFile = toml::from_str(&text).map_err(|e| match e.span() {
        Some(span) => at(span, e.message().to_string()),
        None => InputError::new(path, e.message()),
    })?;
    let dir = path.parent().unwrap_or(Path::new("."));

    if let Some(nm) = &file.normal_map {
        return Err(at(
            nm.span(),
            "a scene with a [normal_map] section is shaded by `pointshade normalmap`, not `render`".into(),
        ));
    }
    let film = match &file.film {
        Some(f) => film_settings(f.get_ref()).map_err(|m| at(f.span(), m))?,
        None => FilmSettings::default(),
    };

    // Materials: named ones first, in name order; the default material is appended if needed.
    let mut materials = Vec::new();
    let mut index_of = BTreeMap::new();
    for (name, section) in &file.material {
        let m = material(name, section.get_ref(), &MaterialDefaults::SCENE)
            .map_err(|(span, m)| at(span.unwrap_or(section.span()), format!("material '{name}': {m}")))?;
        index_of.insert(name.clone(), materials.len() as u32);
        materials.push(m);
    }

    let mut mesh = TriangleMesh::default();
    let mut warnings = Vec::new();
    let mut default_index = None;
    let mut images = Vec::new();
    let mut notes = Vec::new();
    let mut objects = Vec::new();
    for object in &file.object {
        let o = object.get_ref();
        let mesh_path = resolve(dir, &o.mesh);
        let contents = load_object(&mesh_path).map_err(|e| match e {
            ObjectError::Input(e) => e,
            ObjectError::Unsupported => at(
                object.span(),
                format!("mesh '{}': only .obj, .gltf and .glb meshes are supported", o.mesh),
            ),
        })?;
        let mut part = contents.mesh;
        let assigned = match &o.material {
            Some(name) => Some(*index_of.get(name.get_ref()).ok_or_else(|| {
                at(
                    name.span(),
                    format!("unknown material '{}' (defined: {})", name.get_ref(), names(&index_of)),
                )
            })?),
            None => None,
        };
        warnings.extend(contents.warnings);
        notes.extend(contents.notes);
        let base = materials.len() as u32;
        let own_count = contents.materials.len() as u32;
        if assigned.is_none() {
            warnings.extend(contents.material_warning);
            let mut own = contents.materials;
            offset_images(&mut own, images.len() as u32);
            images.extend(contents.images);
            materials.extend(own);
        }
        for m in &mut part.material_of_triangle {
            *m = match (assigned, *m) {
                (Some(a), _) => a,
                (None, NO_MATERIAL) => *default_index.get_or_insert_with(|| {
                    materials.push(default_material());
                    materials.len() as u32 - 1
                }),
                (None, local) if local < own_count => base + local,
                (None, _) => unreachable!("mesh loaders return valid material indices"),
            };
        }
        let transform = match &o.transform {
            Some(t) => transform_matrix(t).map_err(|m| at(object.span(), m))?,
            None => Mat4::IDENTITY,
        };
        if transform != Mat4::IDENTITY {
            part.transform(transform);
        }
        // From world positions, as Mitsuba does (a non-uniform scale changes the angles).
        part.derive_normals(&contents.derived_normals);
        let first = mesh.triangle_count();
        mesh.append(part, 0);
        objects.push(SceneObject {
            mesh: mesh_path,
            transform,
            triangles: first..mesh.triangle_count(),
        });
    }
    let textures = decode_used_images(&mut materials, &mesh.material_of_triangle, &images)?;

    let bounds = mesh.bounds().unwrap_or((Vec3::splat(-1.0), Vec3::ONE));
    let camera = match &file.camera {
        Some(c) => camera(c.get_ref()).map_err(|m| at(c.span(), m))?,
        None => {
            notes.push("camera: none in the scene file, framed automatically on the bounding box".into());
            frame_bounds(bounds.0, bounds.1)
        }
    };
    let lights = if file.light.is_empty() {
        notes.push("lights: none in the scene file, default key + fill lights".into());
        default_lights(bounds.0, bounds.1, &camera)
    } else {
        file.light
            .iter()
            .map(|l| light(l.get_ref(), Falloff::InverseSquare).map_err(|m| at(l.span(), m)))
            .collect::<InputResult<_>>()?
    };
    if file.object.is_empty() {
        warnings.push(format!("{}: no [[object]]: the image will be black", path.display()));
    }
    Ok(Scene {
        source: path.to_path_buf(),
        film,
        camera,
        lights,
        materials,
        textures,
        mesh,
        shadows: file.render.as_ref().and_then(|r| r.shadows).unwrap_or(true),
        shadow_offset: match file.render.as_ref().and_then(|r| r.shadow_offset.as_ref()) {
            Some(name) => ShadowOffset::parse(name.get_ref()).map_err(|m| at(name.span(), m))?,
            None => ShadowOffset::default(),
        },
        shadow_terminator: match file.render.as_ref().and_then(|r| r.shadow_terminator.as_ref()) {
            Some(name) => ShadowTerminator::parse(name.get_ref()).map_err(|m| at(name.span(), m))?,
            None => ShadowTerminator::default(),
        },
        objects,
        notes,
        warnings,
    })
}

/// The geometry and materials of one `[[object]]` mesh file, in the file's own coordinates.
struct ObjectContents {
    /// Triangles; material indices index `materials`, or are `NO_MATERIAL`.
    mesh: TriangleMesh,
    /// The parts whose normals are still to be derived, once the object is transformed.
    derived_normals: Vec<DerivedNormals>,
    /// The file's own materials.
    materials: Vec<Material>,
    /// Images the materials reference, not decoded.
    images: Vec<PendingImage>,
    /// Why the file's materials could not be loaded (worth a warning only if they are used).
    material_warning: Option<String>,
    /// Warnings about the geometry.
    warnings: Vec<String>,
    /// Facts for `--explain`.
    notes: Vec<String>,
}

enum ObjectError {
    Input(InputError),
    Unsupported,
}

/// Loads an `[[object]]` mesh: OBJ (with its MTL materials) or glTF (its default scene's
/// geometry and materials; its cameras and lights are not used, the scene file defines those).
fn load_object(path: &Path) -> Result<ObjectContents, ObjectError> {
    match extension(path).as_deref() {
        Some("obj") => {
            let (c, derived_normals) = load_obj_underived(path).map_err(ObjectError::Input)?;
            Ok(ObjectContents {
                mesh: c.mesh,
                derived_normals,
                materials: c.materials,
                images: Vec::new(),
                material_warning: c.material_warning,
                warnings: Vec::new(),
                notes: Vec::new(),
            })
        }
        Some("gltf" | "glb") => {
            let c = load_gltf(path).map_err(ObjectError::Input)?;
            let mut notes: Vec<String> = c.notes.iter().map(|n| format!("{}: {n}", path.display())).collect();
            if !c.cameras.is_empty() || !c.lights.is_empty() {
                notes.push(format!(
                    "{}: its {} camera(s) and {} light(s) are not used (the scene file's [camera] and [[light]] are)",
                    path.display(),
                    c.cameras.len(),
                    c.lights.len()
                ));
            }
            Ok(ObjectContents {
                mesh: c.mesh,
                derived_normals: Vec::new(),
                materials: c.materials,
                images: c.images,
                material_warning: None,
                warnings: c.warnings,
                notes,
            })
        }
        _ => Err(ObjectError::Unsupported),
    }
}

/// 1-based line and column of byte `offset`.
pub(super) fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

fn names(index_of: &BTreeMap<String, u32>) -> String {
    if index_of.is_empty() {
        "none".into()
    } else {
        index_of.keys().cloned().collect::<Vec<_>>().join(", ")
    }
}

/// `file` relative to the directory `dir` of the scene file (absolute paths unchanged).
pub(super) fn resolve(dir: &Path, file: &str) -> PathBuf {
    let p = Path::new(file);
    if p.is_absolute() {
        p.to_path_buf()
    } else {
        dir.join(p)
    }
}

fn film_settings(f: &FilmSection) -> Result<FilmSettings, String> {
    let d = FilmSettings::default();
    let sampler = match &f.sampler {
        Some(s) => SamplerKind::parse(s.get_ref())?,
        None => d.sampler,
    };
    // `filter` can only be "box" (parsing rejects anything else), the one filter pointshade has.
    let _ = &f.filter;
    let budget = crate::film::time_budget_defaults(sampler);
    let s = FilmSettings {
        width: f.width.unwrap_or(d.width),
        height: f.height.unwrap_or(d.height),
        // A time budget without a count (or threshold) renders until the budget, not until the
        // default count.
        spp: f.spp.unwrap_or(match (f.time_budget, sampler) {
            (Some(_), _) => budget.0,
            (None, SamplerKind::Grid) => 1,
            (None, _) => d.spp,
        }),
        sampler,
        seed: f.seed.unwrap_or(d.seed),
        exposure: f.exposure.unwrap_or(d.exposure),
        adaptive_threshold: f.adaptive_threshold.unwrap_or(match f.time_budget {
            Some(_) => budget.1,
            None => d.adaptive_threshold,
        }),
        crop: None,
        time_budget: f.time_budget,
    };
    s.validate()?;
    Ok(s)
}

/// A finite vector, or an error naming the key.
pub(super) fn vec3(name: &str, v: [f32; 3]) -> Result<Vec3, String> {
    let v = Vec3::from(v);
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("{name} must be finite, got {v}"))
    }
}

fn camera(c: &CameraSection) -> Result<CameraSpec, String> {
    let projection = match c.kind {
        CameraType::Perspective => Projection::Perspective {
            fov_degrees: c.fov.ok_or("a perspective camera needs fov (degrees)")?,
            fov_axis: match c.fov_axis {
                FovAxisName::X => FovAxis::X,
                FovAxisName::Y => FovAxis::Y,
            },
        },
        CameraType::Orthographic => Projection::Orthographic {
            scale: c
                .scale
                .ok_or("an orthographic camera needs scale (half-height in scene units)")?,
        },
    };
    let spec = CameraSpec {
        position: vec3("position", c.position)?,
        look_at: vec3("look_at", c.look_at)?,
        up: vec3("up", c.up)?,
        projection,
        near_clip: c.near_clip,
        far_clip: c.far_clip.unwrap_or(f32::INFINITY),
    };
    // Build once at a nominal size to check the frame and projection now, with the file's span.
    crate::surface::camera::Camera::new(spec, 1, 1)?;
    Ok(spec)
}

/// The light a `[[light]]` section describes; `falloff` when the section does not say.
pub(super) fn light(l: &LightSection, default_falloff: Falloff) -> Result<Light, String> {
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
    let position = || vec3("position", l.position.ok_or("this light needs position")?);
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
            }
        }
    };
    let falloff = match l.falloff {
        None => default_falloff,
        Some(FalloffName::InverseSquare) => Falloff::InverseSquare,
        Some(FalloffName::None) => Falloff::None,
    };
    Ok(Light {
        kind,
        power: color * l.intensity,
        falloff,
    })
}

/// An error with the span of the value it is about, when narrower than the section.
pub(super) type Located = (Option<std::ops::Range<usize>>, String);

/// The material a `[material.NAME]` section describes, missing keys taken from `defaults`.
pub(super) fn material(name: &str, m: &MaterialSection, defaults: &MaterialDefaults) -> Result<Material, Located> {
    let plain = |msg: String| (None, msg);
    let mut material = defaults.material(name, m.model);
    material.albedo = m.albedo.unwrap_or(material.albedo);
    material.kd = m.kd.unwrap_or(material.kd);
    material.two_sided = m.two_sided.unwrap_or(material.two_sided);
    let unused_for = |keys: &[(&str, bool)], model: &str| -> Result<(), Located> {
        match keys.iter().find(|(_, present)| *present) {
            Some((key, _)) => Err(plain(format!("key '{key}' does not apply to the {model} model"))),
            None => Ok(()),
        }
    };
    let ct_keys = [
        ("roughness", m.roughness.is_some()),
        ("metallic", m.metallic.is_some()),
        ("ior", m.ior.is_some()),
        ("d", m.d.is_some()),
        ("g", m.g.is_some()),
        ("fresnel", m.fresnel.is_some()),
        ("eta", m.eta.is_some()),
        ("k", m.k.is_some()),
    ];
    let bp_keys = [("ks", m.ks.is_some()), ("shininess", m.shininess.is_some())];
    match m.model {
        ModelName::Lambert => {
            unused_for(&ct_keys, "lambert")?;
            unused_for(&bp_keys, "lambert")?;
            unused_for(&[("specular_color", m.specular_color.is_some())], "lambert")?;
        }
        ModelName::BlinnPhong => {
            unused_for(&ct_keys, "blinn-phong")?;
            let d = defaults.blinn_phong;
            material.specular = Specular::BlinnPhong(BlinnPhong {
                ks: m.ks.unwrap_or(d.ks),
                shininess: m.shininess.unwrap_or(d.shininess),
                color: m.specular_color.unwrap_or(d.color),
            });
        }
        ModelName::CookTorrance => {
            unused_for(&bp_keys, "cook-torrance")?;
            let d = defaults.cook_torrance;
            let mut ct = CookTorrance {
                alpha: m.roughness.unwrap_or(d.alpha),
                metallic: m.metallic.unwrap_or(d.metallic),
                specular_color: m.specular_color.unwrap_or(d.specular_color),
                ior: m.ior.unwrap_or(d.ior),
                eta: m.eta.unwrap_or(d.eta),
                k: m.k.unwrap_or(d.k),
                ..d
            };
            if let Some(v) = &m.d {
                ct.d = v.get_ref().parse().map_err(|e| (Some(v.span()), format!("{e}")))?;
            }
            if let Some(v) = &m.g {
                ct.g = v.get_ref().parse().map_err(|e| (Some(v.span()), format!("{e}")))?;
            }
            if let Some(v) = &m.fresnel {
                ct.f = v.get_ref().parse().map_err(|e| (Some(v.span()), format!("{e}")))?;
            }
            material.specular = Specular::CookTorrance(ct);
        }
    }
    material.validate().map_err(plain)?;
    Ok(material)
}

fn transform_matrix(t: &TransformSection) -> Result<Mat4, String> {
    let translate = vec3("translate", t.translate)?;
    let rotate = vec3("rotate", t.rotate)?;
    let scale = match t.scale {
        None => Vec3::ONE,
        Some(ScaleValue::Uniform(s)) => Vec3::splat(s),
        Some(ScaleValue::PerAxis(v)) => vec3("scale", v)?,
    };
    if !scale.is_finite() || scale.min_element().abs() == 0.0 || scale.abs().min_element() == 0.0 {
        return Err(format!("transform scale must be finite and non-zero, got {scale}"));
    }
    // Scale, then rotate about x, then y, then z (degrees), then translate.
    let r = Quat::from_euler(
        EulerRot::ZYX,
        rotate.z.to_radians(),
        rotate.y.to_radians(),
        rotate.x.to_radians(),
    );
    Ok(Mat4::from_scale_rotation_translation(scale, r, translate))
}
