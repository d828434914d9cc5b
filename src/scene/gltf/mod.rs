//! glTF 2.0 files (`.gltf` + buffers/images, or `.glb`): meshes, node transforms, cameras,
//! KHR_lights_punctual lights and metallic-roughness materials with textures.
//!
//! [`load_gltf`] reads a file into world-space geometry, `gltf-pbr` materials, not-yet-decoded
//! images, cameras and lights; [`scene_for_gltf`] makes a scene of a file given alone on the
//! command line, and TOML scenes use [`load_gltf`] for `[[object]] mesh = "x.gltf"`.
//! The stages live in one module each: [`document`] (container, extensions, buffers),
//! [`accessor`] (checked reads), [`nodes`] (hierarchy), [`meshes`] (geometry; generated tangents
//! in [`crate::scene::tangents`]), [`cameras`], [`lights`], [`materials`] (materials and images).

pub mod accessor;
pub mod cameras;
pub mod document;
pub mod lights;
pub mod materials;
pub mod meshes;
pub mod nodes;
pub mod texture_transform;

use std::path::Path;

use crate::error::{InputError, InputResult};
use crate::film::FilmSettings;
use crate::light::Light;
use crate::material::Material;
use crate::scene::framing::{default_lights, frame_bounds};
use crate::scene::mesh::TriangleMesh;
use crate::scene::textures::{decode_used_images, PendingImage};
use crate::scene::Scene;
use cameras::GltfCamera;
use document::SUPPORTED_EXTENSIONS;

/// Everything a glTF file's rendered scene contains, in world space.
pub struct GltfContents {
    /// Where `mesh`'s, the cameras' and the lights' coordinates start, in the file's world
    /// coordinates (f64): zero unless the scene lies far from the origin.
    pub origin: glam::DVec3,
    /// All triangles; `material_of_triangle` indexes `materials`.
    pub mesh: TriangleMesh,
    /// The file's materials (plus the glTF default material if a primitive has none); their
    /// texture references index `images`.
    pub materials: Vec<Material>,
    /// The file's images, not decoded.
    pub images: Vec<PendingImage>,
    /// Cameras placed by nodes, in node order.
    pub cameras: Vec<GltfCamera>,
    /// Number of cameras the file defines (placed or not).
    pub camera_count: usize,
    /// Lights placed by nodes, in node order.
    pub lights: Vec<Light>,
    /// Facts for `--explain`.
    pub notes: Vec<String>,
    /// Problems that did not stop loading.
    pub warnings: Vec<String>,
}

/// Reads `path` and everything its default scene places.
pub fn load_gltf(path: &Path) -> InputResult<GltfContents> {
    let d = document::read_document(path)?;
    let mut warnings = Vec::new();
    let ignored: Vec<&str> = d
        .doc
        .extensions_used()
        .filter(|e| !SUPPORTED_EXTENSIONS.contains(e))
        .collect();
    if !ignored.is_empty() {
        warnings.push(format!(
            "{}: uses glTF extension(s) pointshade ignores: {}",
            path.display(),
            ignored.join(", ")
        ));
    }
    let instances = nodes::walk_scene(&d)?;
    let converted = materials::convert_materials(&d)?;
    let mut materials = converted.materials;
    let geometry = meshes::build_geometry(&d, &instances.meshes, &materials)?;
    if geometry.uses_default_material {
        materials.push(materials::default_material());
    }
    let images = materials::pending_images(&d)?;
    let cameras: Vec<GltfCamera> = instances
        .cameras
        .iter()
        .map(|&(i, world)| {
            let camera = d.doc.cameras().nth(i).expect("validated index");
            cameras::camera_at(&d, &camera, world.relative_to(geometry.origin))
        })
        .collect::<InputResult<_>>()?;
    let lights = match d.doc.lights() {
        Some(all) => {
            let all: Vec<_> = all.collect();
            instances
                .lights
                .iter()
                .map(|&(i, world)| lights::light_at(&d, &all[i], world.relative_to(geometry.origin)))
                .collect::<InputResult<_>>()?
        }
        None => Vec::new(),
    };
    warnings.extend(converted.warnings);
    warnings.extend(geometry.warnings);
    let mut notes: Vec<String> = instances.note.into_iter().collect();
    notes.extend(geometry.notes);
    notes.extend(converted.notes);
    Ok(GltfContents {
        origin: geometry.origin,
        mesh: geometry.mesh,
        materials,
        images,
        cameras,
        camera_count: d.doc.cameras().len(),
        lights,
        notes,
        warnings,
    })
}

/// A scene for a glTF file given alone on the command line. The camera is `camera` (a camera
/// index of the file) if given, else the file's first camera (lowest index placed by a node),
/// else an automatic one framing the geometry; the file's lights, else the default key and fill
/// lights.
pub fn scene_for_gltf(path: &Path, camera: Option<usize>) -> InputResult<Scene> {
    let contents = load_gltf(path)?;
    let mut warnings = contents.warnings;
    let mut materials = contents.materials;
    let mesh = contents.mesh;
    let (lo, hi) = mesh
        .bounds()
        .ok_or_else(|| InputError::new(path, "the scene has no triangles: nothing to render"))?;
    let mut notes = contents.notes;
    let mut film = FilmSettings::default();
    let chosen = match camera {
        Some(n) => Some(pick_camera(&contents.cameras, contents.camera_count, n)?),
        None => contents.cameras.iter().min_by_key(|c| c.index).copied(),
    };
    let camera = match chosen {
        Some(c) => {
            notes.push(format!(
                "camera: the file's camera {} (of {}; --camera N picks another)",
                c.index, contents.camera_count
            ));
            if let Some(aspect) = c.aspect {
                match cameras::film_width(film.height, aspect, c.index) {
                    Ok(width) => film.width = width,
                    Err(warning) => warnings.push(format!("{}: {warning}", path.display())),
                }
            }
            c.spec
        }
        None => {
            notes.push("camera: the file has none, framed automatically on the bounding box".into());
            frame_bounds(lo, hi)
        }
    };
    let automatic_lights = contents.lights.is_empty();
    let lights = if automatic_lights {
        notes.push("lights: the file has none, default key + fill lights".into());
        default_lights(lo, hi, &camera)
    } else {
        notes.push(format!(
            "lights: the file's {} KHR_lights_punctual light(s)",
            contents.lights.len()
        ));
        contents.lights
    };
    let textures = decode_used_images(&mut materials, &mesh.material_of_triangle, &contents.images)?;
    let mut scene = Scene::new(path.to_path_buf(), film, camera, lights, materials, textures, mesh);
    scene.origin = contents.origin;
    scene.default_lights = automatic_lights;
    scene.notes = notes;
    scene.warnings = warnings;
    Ok(scene)
}

/// Camera `n` of the file, as its first node places it.
fn pick_camera(placed: &[GltfCamera], count: usize, n: usize) -> InputResult<GltfCamera> {
    if n >= count {
        let have = match count {
            0 => "the file has no camera".to_string(),
            1 => "the file has 1 camera: 0".to_string(),
            _ => format!("the file has {count} cameras: 0 to {}", count - 1),
        };
        return Err(InputError::new(
            "--camera",
            format!("camera {n} does not exist ({have})"),
        ));
    }
    placed
        .iter()
        .find(|c| c.index == n)
        .copied()
        .ok_or_else(|| InputError::new("--camera", format!("camera {n} is not placed by any node of the scene")))
}
