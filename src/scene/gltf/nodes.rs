//! The node hierarchy: which meshes, cameras and lights the rendered scene places, and where.
//!
//! The scene rendered is the file's default scene (`scene`), else its first scene, else every
//! root node. Each node's world matrix is its parent's times its own (a `matrix`, or
//! T·R·S from translation, rotation — normalised — and scale).

use glam::{DMat4, Mat4};

use crate::error::InputResult;
use crate::scene::gltf::document::{f32_matrix, GltfDocument};

/// A node's world matrix: composed in f32 as the gltf crate reads the transforms, and in f64
/// from the JSON text. The f32 one places scenes near the origin exactly as before f64 existed;
/// the f64 one places scenes far from it (`meshes::build_geometry` decides).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct World {
    /// Parent's times the node's own, in f32.
    pub f32: Mat4,
    /// The same in f64.
    pub f64: DMat4,
}

impl World {
    /// The matrix to place things with in a frame whose origin is `origin` (f64 world
    /// coordinates): the f32 matrix when the origin is zero, else the f64 one moved by −origin.
    pub fn relative_to(&self, origin: glam::DVec3) -> Mat4 {
        if origin == glam::DVec3::ZERO {
            self.f32
        } else {
            let mut m = self.f64;
            m.w_axis = (m.w_axis.truncate() - origin).extend(1.0);
            m.as_mat4()
        }
    }
}

/// Everything a scene places, in depth-first node order.
#[derive(Debug, Default)]
pub struct Instances {
    /// (mesh index, world matrix).
    pub meshes: Vec<(usize, World)>,
    /// (camera index, world matrix).
    pub cameras: Vec<(usize, World)>,
    /// (KHR_lights_punctual light index, world matrix).
    pub lights: Vec<(usize, World)>,
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
    let root = World {
        f32: Mat4::IDENTITY,
        f64: DMat4::IDENTITY,
    };
    let mut stack: Vec<(usize, World)> = roots.into_iter().rev().map(|i| (i, root)).collect();
    while let Some((index, parent)) = stack.pop() {
        if std::mem::replace(&mut visited[index], true) {
            return Err(d.error(format!(
                "node {index} is reached twice from the scene (node hierarchies must be trees)"
            )));
        }
        let node = &nodes[index];
        let world = World {
            f32: parent.f32 * f32_matrix(node),
            f64: parent.f64 * d.node_transforms[index],
        };
        if !(world.f32.is_finite() && world.f64.is_finite()) {
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
