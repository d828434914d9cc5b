//! Loading any scene: a TOML scene file, a bare OBJ mesh or a glTF file, by extension.

use std::path::Path;

use crate::error::{InputError, InputResult};
use crate::scene::{extension, extent, file, framing, gltf, Scene};

/// Choices the command line makes about loading.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LoadOptions {
    /// `--camera N`: which camera of a glTF file to render through.
    pub camera: Option<usize>,
}

/// Loads a scene from a `.toml` scene file, a bare `.obj` mesh or a `.gltf`/`.glb` file.
pub fn load(path: &Path) -> InputResult<Scene> {
    load_with(path, LoadOptions::default())
}

/// [`load`] with command-line choices.
#[inline(never)] // a stage boundary that benches/instructions.sh counts
pub fn load_with(path: &Path, options: LoadOptions) -> InputResult<Scene> {
    let ext = extension(path);
    let is_gltf = matches!(ext.as_deref(), Some("gltf" | "glb"));
    if options.camera.is_some() && !is_gltf {
        return Err(InputError::new(
            "--camera",
            "only glTF files (.gltf, .glb) have cameras to choose from",
        ));
    }
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
