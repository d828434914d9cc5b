//! Loading any scene: a TOML scene file, a bare OBJ mesh or a glTF file, by extension.

use std::path::{Path, PathBuf};

use crate::error::{InputError, InputResult};
use crate::scene::file::MeshTable;
use crate::scene::{extension, extent, file, framing, gltf, Scene};

/// Choices a front end makes about loading.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LoadOptions {
    /// Which camera of a glTF file to render through (other files have none to choose from:
    /// the render request refuses the option for them).
    pub camera: Option<usize>,
}

/// Where a scene comes from: a file, or a scene file's text whose meshes may be given as
/// arrays (the Python module's `Scene`).
#[derive(Clone, Debug)]
pub enum SceneSource {
    /// A `.toml` scene file, a bare `.obj` mesh or a `.gltf`/`.glb` file.
    File(PathBuf),
    /// A scene file's text.
    Text {
        /// The name messages give it.
        name: PathBuf,
        /// The scene file's text.
        text: String,
        /// Where its relative paths start.
        dir: PathBuf,
        /// Meshes given as arrays, by the file names the text gives them.
        meshes: MeshTable,
    },
}

impl SceneSource {
    /// The name messages give the scene.
    pub fn name(&self) -> &Path {
        match self {
            SceneSource::File(path) => path,
            SceneSource::Text { name, .. } => name,
        }
    }

    /// Whether the scene is a glTF file, the one kind with cameras to choose from.
    pub fn is_gltf(&self) -> bool {
        matches!(self, SceneSource::File(p) if matches!(extension(p).as_deref(), Some("gltf" | "glb")))
    }

    /// Loads the scene.
    pub fn load(&self, options: LoadOptions) -> InputResult<Scene> {
        match self {
            SceneSource::File(path) => load_with(path, options),
            SceneSource::Text {
                name,
                text,
                dir,
                meshes,
            } => file::load_scene_text(name, text.clone(), dir, meshes),
        }
    }
}

/// Loads a scene from a `.toml` scene file, a bare `.obj` mesh or a `.gltf`/`.glb` file.
pub fn load(path: &Path) -> InputResult<Scene> {
    load_with(path, LoadOptions::default())
}

/// [`load`] with command-line choices.
#[inline(never)] // a stage boundary that benches/instructions.sh counts
pub fn load_with(path: &Path, options: LoadOptions) -> InputResult<Scene> {
    let ext = extension(path);
    let scene = match ext.as_deref() {
        Some("toml") => file::load_scene_file(path),
        Some("obj") => framing::scene_for_bare_mesh(path),
        Some("gltf" | "glb") => gltf::scene_for_gltf(path, options.camera),
        _ => Err(InputError::new(
            path,
            "unsupported scene type (expected a .toml scene file, an .obj mesh or a .gltf/.glb file)",
        )),
    }?;
    extent::check(&scene).map_err(|e| InputError::new(path, e))?;
    Ok(scene)
}
