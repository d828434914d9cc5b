//! Primary visibility: a camera ray and its BVH hit become a [`SurfacePoint`].
//!
//! As in Mitsuba: the position is recomputed from the barycentrics (not o + t·d), the geometric
//! normal is normalize((p1 − p0) × (p2 − p0)) (counter-clockwise = front), and the shading normal
//! is the normalised barycentric interpolation of the unit vertex normals.
//!
//! Where the plan asks for it (pointshade's default offset on a smooth-shaded mesh), shadow rays
//! then leave from the smooth surface the vertex normals describe rather than the flat triangle
//! (Hanika, "Hacking the Shadow Terminator", Ray Tracing Gems II ch. 4). On a coarse mesh with
//! smooth normals, a point whose shading normal still faces the light can lie below the plane of
//! the neighbouring faces, which then shadow it in the faceted steps known as the shadow
//! terminator. The point is projected onto the tangent plane of each vertex (its position and
//! normal) where it lies below that plane, and the three projections are interpolated with the
//! barycentrics ([`smooth_origin`]). Convex regions move out; concave ones and flat meshes, whose
//! points lie on or above every vertex's plane, do not move; at a vertex the point is that
//! vertex. The surface point keeps only the height of the moved point above its triangle
//! ([`SurfacePoint::shadow_lift`]); the shaded position stays on the triangle, as in Mitsuba.

use glam::{Vec2, Vec3};

use crate::accel::Hit;
use crate::scene::mesh::TriangleMesh;
use crate::scene::unit_vector::triangle_normal;
use crate::surface::SurfacePoint;

/// What [`surface_point`] computes beyond the position and the normals (the plan decides).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PointOptions {
    /// Interpolate texture coordinates (both sets); else they are zero.
    pub uvs: bool,
    /// Lift shadow-ray origins to the smooth surface of the vertex normals; else they leave
    /// from the triangle.
    pub smooth_shadow_origins: bool,
}

/// Builds the surface point of `hit` for a ray travelling along `direction`.
///
/// Always inlined: the shadow lift grew it past what the compiler inlines into the render's hit
/// loop, and a call per hit costs even renders that lift nothing (docs/performance-log.md).
#[inline(always)]
pub fn surface_point(mesh: &TriangleMesh, hit: &Hit, direction: Vec3, options: PointOptions) -> SurfacePoint {
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
    let mut geometric_normal = triangle_normal(p0, p1, p2);
    if geometric_normal == Vec3::ZERO {
        geometric_normal = to_viewer;
    }
    let n = &mesh.normals;
    let mut shading_normal = (b0 * n[i0] + b1 * n[i1] + b2 * n[i2]).normalize_or_zero();
    if shading_normal == Vec3::ZERO {
        // Opposite vertex normals cancel, or the file had zero normals: shade flat.
        shading_normal = geometric_normal;
    }
    // The moved point's height above the triangle: finite, as `smooth_origin` returns p for
    // anything else and the normal is unit.
    let shadow_lift = if options.smooth_shadow_origins {
        let moved = smooth_origin(position, [b0, b1, b2], [p0, p1, p2], [n[i0], n[i1], n[i2]]);
        (moved - position).dot(geometric_normal)
    } else {
        0.0
    };
    let (mut uv, mut uv1) = Default::default();
    if options.uvs {
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
        shadow_lift,
        geometric_normal,
        shading_normal,
        uv,
        uv1,
        material: mesh.material_of_triangle[t],
        to_viewer,
    }
}

/// `p` (barycentrics `b` of the triangle `vertices`) moved onto the smooth surface of the unit
/// vertex `normals`: p + Σ b_i·max(0, (v_i − p)·n_i)·n_i, the barycentric blend of p's
/// projections onto each vertex's tangent plane, taken only where p lies below it.
///
/// Safe: sums and products of finite values, no division; the move is at most the triangle's
/// size (|v_i − p| ≤ its longest edge, |n_i| = 1 or 0 for a file's zero normals). A non-finite
/// result (a non-finite input) falls back to `p`.
#[inline(always)]
pub fn smooth_origin(p: Vec3, b: [f32; 3], vertices: [Vec3; 3], normals: [Vec3; 3]) -> Vec3 {
    let mut moved = p;
    for ((b, v), n) in b.into_iter().zip(vertices).zip(normals) {
        let below = (v - p).dot(n).max(0.0);
        moved += (b * below) * n;
    }
    if moved.is_finite() {
        moved
    } else {
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A triangle of a coarse unit sphere around the origin: vertices on the sphere, vertex
    /// normals radial, so its interior lies inside the sphere (convex).
    fn sphere_facet() -> ([Vec3; 3], [Vec3; 3]) {
        let v = [
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
        ];
        (v, v)
    }

    #[test]
    fn a_convex_facet_moves_out_towards_the_sphere() {
        let (v, n) = sphere_facet();
        let b = [1.0 / 3.0; 3];
        let p = b[0] * v[0] + b[1] * v[1] + b[2] * v[2];
        let moved = smooth_origin(p, b, v, n);
        let ng = (v[1] - v[0]).cross(v[2] - v[0]).normalize();
        assert!((moved - p).dot(ng) > 0.1, "out of the facet's plane: {moved} from {p}");
        // Closer to the sphere it approximates (|p| = 0.577), and not past it.
        assert!(
            moved.length() > p.length() + 0.1 && moved.length() <= 1.0 + 1e-6,
            "{}",
            moved.length()
        );
    }

    #[test]
    fn vertices_flat_meshes_and_concave_facets_do_not_move() {
        let (v, n) = sphere_facet();
        assert_eq!(smooth_origin(v[1], [0.0, 1.0, 0.0], v, n), v[1], "a vertex is itself");
        let ng = (v[1] - v[0]).cross(v[2] - v[0]).normalize();
        let p = (v[0] + v[1] + v[2]) / 3.0;
        assert_eq!(smooth_origin(p, [1.0 / 3.0; 3], v, [ng; 3]), p, "flat normals");
        // The inside of the sphere seen from within: normals pointing inwards (concave).
        assert_eq!(smooth_origin(p, [1.0 / 3.0; 3], v, n.map(|n| -n)), p, "concave");
        assert_eq!(smooth_origin(p, [1.0 / 3.0; 3], v, [Vec3::ZERO; 3]), p, "zero normals");
    }

    #[test]
    fn non_finite_inputs_leave_the_point_where_it_is() {
        let (v, mut n) = sphere_facet();
        n[0] = Vec3::new(f32::NAN, 0.0, 0.0);
        let p = (v[0] + v[1] + v[2]) / 3.0;
        assert_eq!(smooth_origin(p, [1.0 / 3.0; 3], v, n), p);
        n[0] = Vec3::new(f32::MAX, 0.0, 0.0);
        assert_eq!(smooth_origin(p, [1.0 / 3.0; 3], [Vec3::splat(f32::MAX); 3], n), p);
    }
}
