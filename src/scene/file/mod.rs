//! TOML scene files (the contract in docs/scene-format.md, "Scene files"); objects are OBJ or glTF meshes.
//!
//! Parsing is strict: unknown keys, wrong types and unknown names are errors with the file, line
//! and column. Each section is kept with its span so that checks made after parsing (a NaN, an
//! unknown material name) also point at the right place. Normal-map scene files (a
//! `[normal_map]` section) share the light and material sections and are read by
//! [`crate::normal_map::scene_file`]; their sections are `lights` and `materials`.

use std::collections::BTreeMap;
use std::path::Path;

use glam::{DVec3, EulerRot, Mat3, Mat4, Quat, Vec3};
use serde::Deserialize;
use toml::Spanned;

use crate::error::{InputError, InputResult};
use crate::film::{FilmSettings, SamplerKind};
use crate::light::Falloff;
use crate::material::Material;
use crate::scene::camera::{CameraSpec, FovAxis, Projection};
use crate::scene::framing::{default_lights, default_material, frame_bounds};
use crate::scene::gltf::load_gltf;
use crate::scene::matching::Match;
use crate::scene::mesh::DerivedNormals;
use crate::scene::mesh::{placed_origin, TriangleMesh};
use crate::scene::obj::{load_mesh_arrays, load_obj_underived, MeshArrays, ObjContents, NO_MATERIAL};
use crate::scene::shadows::{ShadowOffset, ShadowTerminator};
use crate::scene::textures::{decode_used_images, offset_images, PendingImage};
use crate::scene::{extension, Scene, SceneObject};

mod key_path;
mod lights;
mod materials;
use values::{point3, resolve, three, vec3};
pub(crate) mod values;

use crate::scene::tangents::complete_tangents;
pub(crate) use lights::{light, LightSection};
pub use lights::{light_from_toml, light_keys};
pub(crate) use materials::{material, MaterialSection};
pub use materials::{material_from_toml, material_keys, MaterialDefaults, ModelName};

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
    #[serde(deserialize_with = "three")]
    position: [f64; 3],
    #[serde(deserialize_with = "three")]
    look_at: [f64; 3],
    #[serde(default = "y_up", deserialize_with = "three")]
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
    #[serde(rename = "match")]
    matching: Option<Spanned<String>>,
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
    #[serde(default, deserialize_with = "three")]
    translate: [f64; 3],
    #[serde(default, deserialize_with = "three")]
    rotate: [f32; 3],
    scale: Option<ScaleValue>,
}

#[derive(Deserialize)]
#[serde(untagged)]
enum ScaleValue {
    Uniform(f32),
    PerAxis(#[serde(deserialize_with = "three")] [f32; 3]),
}

/// Meshes given as arrays, by the name an `[[object]]`'s `mesh` key gives them; looked up before
/// the file system.
pub type MeshTable = BTreeMap<String, MeshArrays>;

/// Reads a scene file and everything it references.
pub fn load_scene_file(path: &Path) -> InputResult<Scene> {
    let source = TomlSource::read(path)?;
    load_scene_source(&source, path.parent().unwrap_or(Path::new(".")), &MeshTable::new())
}

/// A scene file's `text` (named `name` in messages), whose relative paths start at `dir` and
/// whose objects may name `arrays` instead of files: what the Python module renders.
pub fn load_scene_text(name: &Path, text: String, dir: &Path, arrays: &MeshTable) -> InputResult<Scene> {
    load_scene_source(&TomlSource::from_text(name, text), dir, arrays)
}

fn load_scene_source(source: &TomlSource, dir: &Path, arrays: &MeshTable) -> InputResult<Scene> {
    let path = source.path;
    let at = |span, problem| source.at(span, problem);
    let file: SceneFile = source.parse()?;

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
    let mut origin = None;
    for object in &file.object {
        let o = object.get_ref();
        let mesh_path = resolve(dir, &o.mesh);
        let from_arrays = arrays.contains_key(&o.mesh);
        let contents = match arrays.get(&o.mesh) {
            Some(a) => load_mesh_arrays(Path::new(&o.mesh), a)
                .map(ObjectContents::of_obj)
                .map_err(ObjectError::Input),
            None => load_object(&mesh_path),
        };
        let contents = contents.map_err(|e| match e {
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
            warnings.extend(contents.material_warnings);
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
        let (matrix, translate) = match &o.transform {
            Some(t) => transform_matrix(t).map_err(|m| at(object.span(), m))?,
            None => (Mat4::IDENTITY, DVec3::ZERO),
        };
        // The file's coordinates x map to the world as L·x + t; the part's positions are
        // relative to its own origin o, so they map to L·x + (L·o + t), taken relative to the
        // scene's origin in f64. (With o and the scene's origin zero: the matrix as written.)
        let linear = Mat3::from_mat4(matrix).as_dmat3();
        let part_offset = linear * contents.origin + translate;
        // The scene's origin: zero, or the first object's centre when it lies far from the world
        // origin; every position (geometry, camera, lights) is taken relative to it in f64.
        let origin = *origin.get_or_insert_with(|| placed_origin(&part, |p| linear * p + part_offset));
        let placed = with_translation(matrix, part_offset - origin);
        if placed != Mat4::IDENTITY {
            part.transform(placed);
        }
        let transform = with_translation(matrix, translate - origin);
        // From world positions, as Mitsuba does (a non-uniform scale changes the angles).
        part.derive_normals(&contents.derived_normals);
        let first = mesh.triangle_count();
        mesh.append(part, 0);
        objects.push(SceneObject {
            mesh: mesh_path,
            from_arrays,
            transform,
            triangles: first..mesh.triangle_count(),
        });
    }
    complete_tangents(&mut mesh, &materials);
    let textures = decode_used_images(&mut materials, &mesh.material_of_triangle, &images)?;
    let origin = origin.unwrap_or(DVec3::ZERO);

    let bounds = mesh.bounds().unwrap_or((Vec3::splat(-1.0), Vec3::ONE));
    let camera = match &file.camera {
        Some(c) => camera(c.get_ref(), origin).map_err(|m| at(c.span(), m))?,
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
            .map(|l| light(l.get_ref(), Falloff::InverseSquare, origin).map_err(|m| at(l.span(), m)))
            .collect::<InputResult<_>>()?
    };
    if file.object.is_empty() {
        warnings.push(format!("{}: no [[object]]: the image will be black", path.display()));
    }
    let render = file.render.as_ref();
    let mut scene = Scene::new(path.to_path_buf(), film, camera, lights, materials, textures, mesh);
    scene.default_lights = file.light.is_empty();
    scene.shadows = render.and_then(|r| r.shadows).unwrap_or(true);
    if let Some(name) = render.and_then(|r| r.shadow_offset.as_ref()) {
        scene.shadow_offset = ShadowOffset::parse(name.get_ref()).map_err(|m| at(name.span(), m))?;
    }
    if let Some(name) = render.and_then(|r| r.shadow_terminator.as_ref()) {
        scene.shadow_terminator = ShadowTerminator::parse(name.get_ref()).map_err(|m| at(name.span(), m))?;
    }
    if let Some(name) = render.and_then(|r| r.matching.as_ref()) {
        let matching = Match::parse(name.get_ref()).map_err(|m| at(name.span(), m))?;
        let sampler = file
            .film
            .as_ref()
            .and_then(|f| f.get_ref().sampler.as_ref())
            .map(|_| scene.film.sampler);
        let keys = ("[film] sampler", "[render] shadow_offset");
        if let Some(problem) = matching.contradiction(
            sampler,
            render
                .and_then(|r| r.shadow_offset.as_ref())
                .map(|_| scene.shadow_offset),
            keys,
        ) {
            return Err(at(name.span(), problem));
        }
        matching.apply(&mut scene);
        scene.film.validate().map_err(|m| at(name.span(), m))?;
    }
    scene.objects = objects;
    scene.origin = origin;
    scene.notes = notes;
    scene.warnings = warnings;
    Ok(scene)
}

/// `m` with its translation replaced by `t` (computed in f64, rounded once).
fn with_translation(m: Mat4, t: DVec3) -> Mat4 {
    let mut placed = m;
    placed.w_axis = t.as_vec3().extend(1.0);
    placed
}

/// The geometry and materials of one `[[object]]` mesh file, in the file's own coordinates.
struct ObjectContents {
    /// Triangles; material indices index `materials`, or are `NO_MATERIAL`. Positions are
    /// relative to `origin`.
    mesh: TriangleMesh,
    /// Where the mesh's coordinates start, in the file's coordinates (f64).
    origin: DVec3,
    /// The parts whose normals are still to be derived, once the object is transformed.
    derived_normals: Vec<DerivedNormals>,
    /// The file's own materials.
    materials: Vec<Material>,
    /// Images the materials reference, not decoded.
    images: Vec<PendingImage>,
    /// Why the file's materials could not be loaded, or which of their statements are not used
    /// (worth a warning only if they are rendered).
    material_warnings: Vec<String>,
    /// Warnings about the geometry.
    warnings: Vec<String>,
    /// Facts for `--explain`.
    notes: Vec<String>,
}

impl ObjectContents {
    fn of_obj((c, derived_normals): (ObjContents, Vec<DerivedNormals>)) -> Self {
        ObjectContents {
            mesh: c.mesh,
            origin: c.origin,
            derived_normals,
            materials: c.materials,
            images: c.images,
            material_warnings: c.material_warnings,
            warnings: c.warnings,
            notes: Vec::new(),
        }
    }
}

enum ObjectError {
    Input(InputError),
    Unsupported,
}

/// Loads an `[[object]]` mesh: OBJ (with its MTL materials) or glTF (its default scene's
/// geometry and materials; its cameras and lights are not used, the scene file defines those).
fn load_object(path: &Path) -> Result<ObjectContents, ObjectError> {
    match extension(path).as_deref() {
        Some("obj") => load_obj_underived(path)
            .map(ObjectContents::of_obj)
            .map_err(ObjectError::Input),
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
                origin: c.origin,
                derived_normals: Vec::new(),
                materials: c.materials,
                images: c.images,
                material_warnings: Vec::new(),
                warnings: c.warnings,
                notes,
            })
        }
        _ => Err(ObjectError::Unsupported),
    }
}

/// The text of a TOML scene file, kept so that errors found after parsing can name the line
/// and column of the value they are about.
pub(crate) struct TomlSource<'a> {
    pub(crate) path: &'a Path,
    text: String,
    /// Errors name keys (`light[0].intensity`) rather than lines and columns: the text was
    /// written by a program from its user's values (the Python module), not by the user.
    by_key: bool,
}

impl<'a> TomlSource<'a> {
    /// Reads `path`; a missing or unreadable file is an error naming it.
    pub(crate) fn read(path: &'a Path) -> InputResult<Self> {
        let text = crate::input_files::read_to_string(path).map_err(|e| InputError::new(path, e))?;
        Ok(TomlSource {
            path,
            text,
            by_key: false,
        })
    }

    /// `text`, named `path` in messages, which locate errors by key: a document written from
    /// values its user gave (the Python module's dicts), whose lines the user never saw.
    pub(crate) fn from_text(path: &'a Path, text: String) -> Self {
        TomlSource {
            path,
            text,
            by_key: true,
        }
    }

    /// The file parsed as `T` (strictly, as the sections' serde attributes say), or the parser's
    /// error at its line and column.
    pub(crate) fn parse<T: serde::de::DeserializeOwned>(&self) -> InputResult<T> {
        toml::from_str(&self.text).map_err(|e| match e.span() {
            Some(span) => self.at(span, e.message().to_string()),
            None => InputError::new(self.path, e.message()),
        })
    }

    /// `problem` at the start of byte range `span`: "FILE: line L, column C: problem", or for
    /// text given in memory "NAME: light[0].intensity: problem".
    pub(crate) fn at(&self, span: std::ops::Range<usize>, problem: String) -> InputError {
        if let Some(key) = self
            .by_key
            .then(|| key_path::key_path_at(&self.text, span.start))
            .flatten()
        {
            return InputError::new(self.path, format!("{key}: {problem}"));
        }
        let (line, col) = line_col(&self.text, span.start);
        InputError::new(self.path, format!("line {line}, column {col}: {problem}"))
    }
}

/// A TOML document as a table, without a scene's checks; a syntax error is named at its line
/// and column of `text`, read from the file `name` (the Python module's `Scene.from_toml`).
pub fn parse_toml_table(name: &Path, text: String) -> InputResult<toml::Table> {
    TomlSource {
        path: name,
        text,
        by_key: false,
    }
    .parse()
}

/// 1-based line and column of byte `offset`.
fn line_col(text: &str, offset: usize) -> (usize, usize) {
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

fn camera(c: &CameraSection, origin: DVec3) -> Result<CameraSpec, String> {
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
        position: point3("position", c.position, origin)?,
        look_at: point3("look_at", c.look_at, origin)?,
        up: vec3("up", c.up)?,
        projection,
        near_clip: c.near_clip,
        far_clip: c.far_clip.unwrap_or(f32::INFINITY),
    };
    // Build once at a nominal size to check the frame and projection now, with the file's span.
    crate::scene::camera::Camera::new(spec, 1, 1)?;
    Ok(spec)
}

/// The camera of a `[camera]` section's `text` (its keys), in a scene whose coordinates are
/// relative to `origin` (`Scene::origin`): the Python module's cameras, checked as scene files'
/// are (the message names the key).
pub fn camera_from_toml(text: &str, origin: DVec3) -> Result<CameraSpec, String> {
    let section: CameraSection = toml::from_str(text).map_err(|e| e.message().to_string())?;
    camera(&section, origin)
}

/// The transform of an `[[object]]`: its f32 matrix (scale, rotate, then the translation in
/// f32) and its translation as written, in f64.
fn transform_matrix(t: &TransformSection) -> Result<(Mat4, DVec3), String> {
    let exact = DVec3::from(t.translate);
    let translate = exact.as_vec3();
    if !(exact.is_finite() && translate.is_finite()) {
        return Err(format!("translate must be finite, got {exact}"));
    }
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
    Ok((Mat4::from_scale_rotation_translation(scale, r, translate), exact))
}
