//! Primary visibility: a camera ray and its BVH hit become a [`SurfacePoint`].
//!
//! As in Mitsuba: the position is recomputed from the barycentrics (not o + t·d), the geometric
//! normal is normalize((p1 − p0) × (p2 − p0)) (counter-clockwise = front), and the shading normal
//! is the normalised barycentric interpolation of the unit vertex normals.

use glam::{Vec2, Vec3};

use crate::accel::Hit;
use crate::scene::mesh::TriangleMesh;
use crate::surface::SurfacePoint;

/// Builds the surface point of `hit` for a ray travelling along `direction`.
/// Texture coordinates (both sets) are interpolated only when `with_uv` (the plan decides).
#[inline]
pub fn surface_point(mesh: &TriangleMesh, hit: &Hit, direction: Vec3, with_uv: bool) -> SurfacePoint {
    let t = hit.triangle as usize;
    let [i0, i1, i2] = mesh.triangles[t].map(|i| i as usize);
    let (b1, b2) = (hit.b1, hit.b2);
    let b0 = 1.0 - b1 - b2;
    let [p0, p1, p2] = [mesh.positions[i0], mesh.positions[i1], mesh.positions[i2]];
    let position = b0 * p0 + b1 * p1 + b2 * p2;
    let to_viewer = -direction;
    // A triangle the ray hit has a non-zero area in f32 (the watertight test rejects det = 0),
    // but the cross product can still underflow for microscopic slivers: fall back to facing
    // the viewer.
    let mut geometric_normal = (p1 - p0).cross(p2 - p0).normalize_or_zero();
    if geometric_normal == Vec3::ZERO {
        geometric_normal = to_viewer;
    }
    let n = &mesh.normals;
    let mut shading_normal = (b0 * n[i0] + b1 * n[i1] + b2 * n[i2]).normalize_or_zero();
    if shading_normal == Vec3::ZERO {
        // Opposite vertex normals cancel, or the file had zero normals: shade flat.
        shading_normal = geometric_normal;
    }
    let (mut uv, mut uv1) = Default::default();
    if with_uv {
        let interpolate = |uvs: &[Vec2]| b0 * uvs[i0] + b1 * uvs[i1] + b2 * uvs[i2];
        if let Some(uvs) = &mesh.uvs {
            uv = interpolate(uvs);
        }
        if let Some(uvs) = &mesh.uvs1 {
            uv1 = interpolate(uvs);
        }
    }
    SurfacePoint {
        position,
        geometric_normal,
        shading_normal,
        uv,
        uv1,
        material: mesh.material_of_triangle[t],
        to_viewer,
    }
}
