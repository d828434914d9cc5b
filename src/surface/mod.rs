//! Surface points: what the shader shades, wherever it came from.
//!
//! A [`SurfacePoint`] is made from a camera ray's hit ([`primary`]) or from a pixel of a normal
//! image ([`crate::normal_map::pixels`], the normal-map mode); neither it nor the shader
//! knows which.

pub mod normal_texture;
pub mod primary;

use glam::{Vec2, Vec3};

use crate::lanes::{F32x8, Real};

/// A point on a surface, seen from a direction, ready to be shaded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// World-space position.
    pub position: Vec3,
    /// Height along `geometric_normal` at which shadow rays leave, before their offset: 0, or on
    /// a mesh whose vertex normals bend away from its flat triangles, the height of the smooth
    /// surface the normals describe, so that the faces beside the point do not shadow it where
    /// its shading normal turns towards the light (the "shadow terminator"; see [`primary`]).
    /// A height, not a second position: the point stays as small as it was.
    pub shadow_lift: f32,
    /// Unit normal of the flat surface element (for shadow-ray offsets and sidedness).
    pub geometric_normal: Vec3,
    /// Normal used for shading (interpolated vertex normals, or a normal image's pixel): unit
    /// length, except under the clamped convention (the normal-map `tp` preset's), which uses a
    /// normal image's scaled colour as it is.
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

/// Surface points of one material, each coordinate in the lanes of `R` — [`LANES`](crate::lanes::LANES) of them in
/// [`F32x8`] by default, four `tp` pixels in [`F64x4`](crate::lanes::F64x4), one point
/// in a scalar: what the shader's lane path reads. Only the fields that path uses (the
/// clamped convention has no sides, textures or shadow rays); the normal-map mode fills them
/// straight from the image.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceLanes<R: Real = F32x8> {
    /// World-space positions.
    pub position: [R; 3],
    /// Shading normals (see [`SurfacePoint::shading_normal`]).
    pub shading_normal: [R; 3],
    /// Unit directions towards the viewer (ω_o), or zero.
    pub to_viewer: [R; 3],
    /// Index into the scene's materials, the same for every lane.
    pub material: u32,
}
