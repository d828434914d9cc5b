//! Scene loading: a TOML scene file, a bare OBJ mesh or a glTF file becomes a [`Scene`].
//!
//! A scene is everything a render needs, already validated: film settings, a camera, lights,
//! materials, and all objects merged into one world-space [`TriangleMesh`]. Loading is the only
//! stage that reads user files, so every [`InputError`](crate::error::InputError) comes from here (the normal-map mode reads its images and scene files in [`crate::normal_map`]).

pub mod camera;
pub mod extent;
pub mod file;
pub mod framing;
pub mod gltf;
mod load;
pub mod matching;
pub mod mesh;
pub mod obj;
pub mod procedural;
pub mod shadows;
pub mod tangents;
pub mod textures;
pub mod unit_vector;
pub mod uri;

use std::path::{Path, PathBuf};

use crate::film::FilmSettings;
use crate::light::Light;
use crate::material::Material;
use crate::scene::camera::CameraSpec;
use crate::scene::shadows::{ShadowOffset, ShadowTerminator};
use crate::texture::TextureImage;
pub use load::{load, load_with, LoadOptions, SceneSource};
pub use mesh::TriangleMesh;

/// A validated scene, ready to plan and render.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The file it was loaded from.
    pub source: PathBuf,
    /// Image and sampling settings.
    pub film: FilmSettings,
    /// The camera.
    pub camera: CameraSpec,
    /// Lights, in the order they are summed.
    pub lights: Vec<Light>,
    /// Whether `lights` are the automatic key and fill lights (the file has none): those follow
    /// the camera when the command line aims it.
    pub default_lights: bool,
    /// Materials, indexed by `mesh.material_of_triangle`.
    pub materials: Vec<Material>,
    /// Decoded texture images, indexed by the materials' `TextureRef::image`: only those a
    /// rendered material uses (decoded once, while loading).
    pub textures: Vec<TextureImage>,
    /// Every object, in world space.
    pub mesh: TriangleMesh,
    /// Whether shadow rays are traced.
    pub shadows: bool,
    /// How shadow rays leave the surface (`mitsuba` only for validation).
    pub shadow_offset: ShadowOffset,
    /// Whether shadow rays leave from the smooth surface of the vertex normals or the flat
    /// triangle (the error-bound offset only; `mitsuba` is always flat).
    pub shadow_terminator: ShadowTerminator,
    /// Where each part of `mesh` came from (for exporters; rendering uses `mesh` only).
    pub objects: Vec<SceneObject>,
    /// Where the render's coordinates start, in world coordinates (f64): every position of the
    /// scene (geometry, camera, lights, the `position` AOV before it is written) is relative to
    /// it. Zero unless the geometry lies far from the world origin (map coordinates), where f32
    /// world coordinates would snap vertices (`scene::mesh::local_origin`).
    pub origin: glam::DVec3,
    /// Decisions made for the user (automatic camera, default light …), shown by `--explain`.
    pub notes: Vec<String>,
    /// Problems that did not stop loading, printed as warnings.
    pub warnings: Vec<String>,
}

impl Scene {
    /// The scene loaded from `source`, with its film, camera and lights, and the geometry with
    /// the materials (and their decoded texture images) its triangles index; with the defaults a
    /// loader then overrides where its format says otherwise: shadows on, with the error-bound offset from the smooth surface; the whole
    /// mesh one object, the source file placed as it is; coordinates starting at the world
    /// origin; no notes and no warnings.
    ///
    /// Every triangle's material must exist, and every texture reference an image (the loaders
    /// build them so; checked in debug builds).
    pub fn new(
        source: PathBuf,
        film: FilmSettings,
        camera: CameraSpec,
        lights: Vec<Light>,
        materials: Vec<Material>,
        textures: Vec<TextureImage>,
        mesh: TriangleMesh,
    ) -> Scene {
        debug_assert!(mesh
            .material_of_triangle
            .iter()
            .all(|&m| (m as usize) < materials.len()));
        debug_assert!(materials.iter().all(|m| {
            let mut refs = m.textures;
            let in_range = refs.refs_mut().all(|t| (t.image as usize) < textures.len());
            in_range
        }));
        let objects = vec![SceneObject {
            mesh: source.clone(),
            from_arrays: false,
            transform: glam::Mat4::IDENTITY,
            triangles: 0..mesh.triangle_count(),
        }];
        Scene {
            source,
            film,
            camera,
            lights,
            default_lights: false,
            materials,
            textures,
            mesh,
            shadows: true,
            shadow_offset: ShadowOffset::default(),
            shadow_terminator: ShadowTerminator::default(),
            objects,
            origin: glam::DVec3::ZERO,
            notes: Vec::new(),
            warnings: Vec::new(),
        }
    }
}

/// One object of a scene: a mesh file placed by a transform, with the triangles it became.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneObject {
    /// The mesh file (for a mesh given as arrays, the name the scene file gives it).
    pub mesh: PathBuf,
    /// Whether the mesh was given as arrays (the Python module's `Scene`) rather than read from
    /// `mesh`: there is no file to refer to, and exports write the geometry out.
    pub from_arrays: bool,
    /// Object-to-world transform applied to it.
    pub transform: glam::Mat4,
    /// Its triangles in the scene mesh.
    pub triangles: std::ops::Range<usize>,
}

impl SceneObject {
    /// The distinct materials its triangles use, in index order.
    pub fn materials(&self, mesh: &TriangleMesh) -> Vec<u32> {
        let mut used: Vec<u32> = mesh.material_of_triangle[self.triangles.clone()].to_vec();
        used.sort_unstable();
        used.dedup();
        used
    }
}

/// Lower-case file extension.
pub fn extension(path: &Path) -> Option<String> {
    path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase())
}
