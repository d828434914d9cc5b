//! Surface points: what the shader shades, wherever it came from.
//!
//! A [`SurfacePoint`] is made from a camera ray's hit ([`primary`]) or from a pixel of a normal
//! image ([`normal_image`], the normal-map mode); neither it nor the shader knows which.

pub mod camera;
pub mod normal_image;
pub mod normal_texture;
pub mod primary;

use glam::{Vec2, Vec3};

/// A point on a surface, seen from a direction, ready to be shaded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// World-space position.
    pub position: Vec3,
    /// Unit normal of the flat surface element (for shadow-ray offsets and sidedness).
    pub geometric_normal: Vec3,
    /// Normal used for shading (interpolated vertex normals, or a normal image's pixel): unit
    /// length, except under the assignment convention (the `tp` preset), which uses the image's
    /// scaled colour as it is.
    pub shading_normal: Vec3,
    /// Texture coordinates (set 0); zero unless the scene's plan asks for them.
    pub uv: Vec2,
    /// Second texture-coordinate set (glTF's `TEXCOORD_1`); zero unless the plan asks for it.
    pub uv1: Vec2,
    /// Index into the scene's materials.
    pub material: u32,
    /// Unit direction from the point towards the viewer (ω_o).
    pub to_viewer: Vec3,
}
