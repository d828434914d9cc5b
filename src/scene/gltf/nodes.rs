//! The node hierarchy: which meshes, cameras and lights the rendered scene places, and where.
//!
//! The scene rendered is the file's default scene (`scene`), else its first scene, else every
//! root node. Each node's world matrix is its parent's times its own (a `matrix`, or
//! T·R·S from translation, rotation — normalised — and scale).

use glam::{Mat4, Quat, Vec3};

use crate::error::InputResult;
use crate::scene::gltf::document::GltfDocument;

/// Everything a scene places, in depth-first node order.
#[derive(Debug, Default)]
pub struct Instances {
    /// (mesh index, world matrix).
    pub meshes: Vec<(usize, Mat4)>,
    /// (camera index, world matrix).
    pub cameras: Vec<(usize, Mat4)>,
    /// (KHR_lights_punctual light index, world matrix).
    pub lights: Vec<(usize, Mat4)>,
    /// How the rendered scene was chosen, when the file does not name a default.
    pub note: Option<String>,
}

/// Walks the rendered scene of `d`. Errors: a node reached twice (the hierarchy must be a forest,
/// which also rules out cycles) or a transform that is not finite.
pub fn walk_scene(d: &GltfDocument) -> InputResult<Instances> {
    let doc = &d.doc;
    let mut instances = Instances::default();
    let roots: Vec<usize> = match doc.default_scene().or_else(|| doc.scenes().next()) {
        Some(scene) => {
            if doc.default_scene().is_none() {
                instances.note = Some(format!(
                    "the file names no default scene: rendering scene {}",
                    scene.index()
                ));
            }
            scene.nodes().map(|n| n.index()).collect()
        }
        None => {
            let mut is_child = vec![false; doc.nodes().len()];
            for node in doc.nodes() {
                for child in node.children() {
                    is_child[child.index()] = true;
                }
            }
            instances.note = Some("the file has no scene: rendering every root node".into());
            (0..is_child.len()).filter(|&i| !is_child[i]).collect()
        }
    };
    let nodes: Vec<_> = doc.nodes().collect();
    let mut visited = vec![false; nodes.len()];
    let mut stack: Vec<(usize, Mat4)> = roots.into_iter().rev().map(|i| (i, Mat4::IDENTITY)).collect();
    while let Some((index, parent)) = stack.pop() {
        if std::mem::replace(&mut visited[index], true) {
            return Err(d.error(format!(
                "node {index} is reached twice from the scene (node hierarchies must be trees)"
            )));
        }
        let node = &nodes[index];
        let world = parent * local_matrix(node);
        if !world.is_finite() {
            return Err(d.error(format!("node {index} has a transform that is not finite")));
        }
        if let Some(mesh) = node.mesh() {
            instances.meshes.push((mesh.index(), world));
        }
        if let Some(camera) = node.camera() {
            instances.cameras.push((camera.index(), world));
        }
        if let Some(light) = node.light() {
            instances.lights.push((light.index(), world));
        }
        let children: Vec<usize> = node.children().map(|c| c.index()).collect();
        stack.extend(children.into_iter().rev().map(|c| (c, world)));
    }
    Ok(instances)
}

/// The node's own transform.
fn local_matrix(node: &::gltf::Node) -> Mat4 {
    match node.transform() {
        ::gltf::scene::Transform::Matrix { matrix } => Mat4::from_cols_array_2d(&matrix),
        ::gltf::scene::Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => Mat4::from_scale_rotation_translation(
            Vec3::from(scale),
            Quat::from_array(rotation).normalize(),
            Vec3::from(translation),
        ),
    }
}
