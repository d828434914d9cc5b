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
use crate::lanes::{dot3, lane_vec3, map3, F32x8, Real, LANES};
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
    let (uv, uv1) = texture_coordinates(mesh, [i0, i1, i2], [b0, b1, b2], options);
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

/// Both sets of texture coordinates at barycentrics `b` of the triangle with vertices `corners`,
/// where the plan asks for them (zero otherwise, and for a set the mesh lacks).
#[inline(always)]
fn texture_coordinates(mesh: &TriangleMesh, corners: [usize; 3], b: [f32; 3], options: PointOptions) -> (Vec2, Vec2) {
    let interpolate = |uvs: &Option<Vec<Vec2>>| match uvs {
        Some(uvs) if options.uvs => b[0] * uvs[corners[0]] + b[1] * uvs[corners[1]] + b[2] * uvs[corners[2]],
        _ => Vec2::ZERO,
    };
    (interpolate(&mesh.uvs), interpolate(&mesh.uvs1))
}

/// [`surface_point`] of every hit among `hits` (ray `k` travelling along `direction(k)`),
/// given to `out` as `(k, hit, point)` in the order of `k`: the surface points of a packet's hits, up
/// to [`LANES`] at a time in [`F32x8`] lanes.
///
/// Why: after the BVH walk, a camera sample's own arithmetic — two square roots and two
/// divisions for the normals, the interpolations, the smooth shadow origin — cost about half as
/// much as the walk itself, one hit at a time (docs/performance-log.md). In lanes each operation
/// serves eight hits, and the vertex loads of eight hits are issued together.
///
/// Exactness: each lane runs [`surface_point`]'s operations in its order (glam's `Vec3`
/// arithmetic is per component, its dot products summed x, y, z, no fused multiply-add), so a
/// lane's point is `surface_point`'s to the bit. A lane that would need one of its fallbacks — a
/// cross product whose squared length is not a normal f32, interpolated normals that cancel, a
/// non-finite smooth origin — is recomputed by `surface_point` itself.
#[inline(always)]
pub fn surface_points(
    mesh: &TriangleMesh,
    hits: &[Option<Hit>],
    direction: impl Fn(usize) -> Vec3,
    options: PointOptions,
    mut out: impl FnMut(usize, &Hit, SurfacePoint),
) {
    let mut lanes_of = |rays: &[usize]| {
        let found = |i: usize| hits[rays[i.min(rays.len() - 1)]].as_ref().expect("a hit");
        let points = PointLanes::of(mesh, found, options);
        for (i, &k) in rays.iter().enumerate() {
            let hit = found(i);
            out(k, hit, points.point(i, mesh, hit, direction(k), options));
        }
    };
    let (mut rays, mut count) = ([0usize; LANES], 0);
    for k in (0..hits.len()).filter(|&k| hits[k].is_some()) {
        rays[count] = k;
        count += 1;
        if count == LANES {
            lanes_of(&rays);
            count = 0;
        }
    }
    if count > 0 {
        lanes_of(&rays[..count]);
    }
}

/// The positions, normals and shadow lifts of [`LANES`] hits (the last one repeated to fill
/// the lanes), and which lanes need [`surface_point`]'s fallbacks.
struct PointLanes {
    position: [F32x8; 3],
    geometric_normal: [F32x8; 3],
    shading_normal: [F32x8; 3],
    shadow_lift: F32x8,
    /// Lanes whose values above are [`surface_point`]'s without a fallback.
    plain: [bool; LANES],
}

impl PointLanes {
    /// The lanes of the hits `hit(0)`, …, `hit(LANES − 1)`.
    #[inline(always)]
    fn of<'h>(mesh: &TriangleMesh, hit: impl Fn(usize) -> &'h Hit, options: PointOptions) -> PointLanes {
        // The hits' vertices, gathered first (plain loops: `array::map` and `from_fn` closures
        // are not always inlined): [corner][axis], a lane per hit.
        let mut p = [[F32x8::zero(); 3]; 3];
        let mut n = [[F32x8::zero(); 3]; 3];
        let (mut b1, mut b2) = (F32x8::zero(), F32x8::zero());
        for i in 0..LANES {
            let h = hit(i);
            (b1.0[i], b2.0[i]) = (h.b1, h.b2);
            let corners = mesh.triangles[h.triangle as usize];
            for (corner, &v) in corners.iter().enumerate() {
                let (position, normal) = (mesh.positions[v as usize], mesh.normals[v as usize]);
                for c in 0..3 {
                    p[corner][c].0[i] = position[c];
                    n[corner][c].0[i] = normal[c];
                }
            }
        }
        let b0 = F32x8::one() - b1 - b2;
        let blend = |v: &[[F32x8; 3]; 3], c: usize| b0 * v[0][c] + b1 * v[1][c] + b2 * v[2][c];
        let axes = [0, 1, 2];
        let position = map3(axes, |c| blend(&p, c));
        // `triangle_normal`'s common case: the cross product of the edges, normalised where its
        // squared length is a normal f32.
        let e1 = map3(axes, |c| p[1][c] - p[0][c]);
        let e2 = map3(axes, |c| p[2][c] - p[0][c]);
        let cross = [
            e1[1] * e2[2] - e2[1] * e1[2],
            e1[2] * e2[0] - e2[2] * e1[0],
            e1[0] * e2[1] - e2[0] * e1[1],
        ];
        let squared = dot3(cross, cross);
        let normal_length = squared.is_finite() & squared.ge(F32x8::splat(f32::MIN_POSITIVE));
        let inv_length = squared.sqrt().recip();
        let geometric_normal = map3(cross, |c| c * inv_length);
        // The shading normal, where the interpolated normals do not cancel.
        let blended = map3(axes, |c| blend(&n, c));
        // `normalize_or_zero`'s v · (1/√(v·v)); its zero case is a fallback lane.
        let rcp = dot3(blended, blended).sqrt().recip();
        let shading_ok = rcp.is_finite() & rcp.gt(F32x8::zero());
        let shading_normal = map3(blended, |c| c * rcp);
        let mut moved_ok = normal_length;
        let shadow_lift = if options.smooth_shadow_origins {
            // `smooth_origin`, lane by lane.
            let mut moved = position;
            for (v, b) in [b0, b1, b2].into_iter().enumerate() {
                let below = dot3(map3(axes, |c| p[v][c] - position[c]), n[v]).max(F32x8::zero());
                for c in 0..3 {
                    moved[c] = moved[c] + (b * below) * n[v][c];
                }
            }
            moved_ok = moved[0].is_finite() & moved[1].is_finite() & moved[2].is_finite();
            dot3(map3(axes, |c| moved[c] - position[c]), geometric_normal)
        } else {
            F32x8::zero()
        };
        let plain = normal_length & shading_ok & moved_ok;
        PointLanes {
            position,
            geometric_normal,
            shading_normal,
            shadow_lift,
            plain: plain_lanes(plain),
        }
    }

    /// Lane `i`'s surface point: [`surface_point`]'s, from the lanes or, for a lane that needs a
    /// fallback, from `surface_point` itself.
    #[inline(always)]
    fn point(&self, i: usize, mesh: &TriangleMesh, hit: &Hit, direction: Vec3, options: PointOptions) -> SurfacePoint {
        if !self.plain[i] {
            return surface_point(mesh, hit, direction, options);
        }
        let t = hit.triangle as usize;
        let corners = mesh.triangles[t].map(|v| v as usize);
        let (b1, b2) = (hit.b1, hit.b2);
        let (uv, uv1) = texture_coordinates(mesh, corners, [1.0 - b1 - b2, b1, b2], options);
        SurfacePoint {
            position: lane_vec3(&self.position, i),
            shadow_lift: self.shadow_lift.0[i],
            geometric_normal: lane_vec3(&self.geometric_normal, i),
            shading_normal: lane_vec3(&self.shading_normal, i),
            uv,
            uv1,
            material: mesh.material_of_triangle[t],
            to_viewer: -direction,
        }
    }
}

/// The lanes of `mask` as booleans.
#[inline(always)]
fn plain_lanes(mask: crate::lanes::Mask8) -> [bool; LANES] {
    let mut lanes = [false; LANES];
    for (i, lane) in lanes.iter_mut().enumerate() {
        *lane = mask.test(i);
    }
    lanes
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

    /// A torus with smooth normals, and triangles that take `surface_point`'s fallbacks: a
    /// sliver whose cross product underflows, one whose squared cross product overflows, one
    /// whose vertex normals cancel at its centre, one with zero normals, one with a vertex far
    /// enough out for the smooth origin to overflow.
    fn mesh_with_fallbacks() -> TriangleMesh {
        let mut mesh = crate::scene::procedural::torus(1.0, 0.35, 24, 12).into_triangle_mesh();
        let mut add = |p: [Vec3; 3], n: [Vec3; 3]| {
            let first = mesh.positions.len() as u32;
            mesh.positions.extend(p);
            mesh.normals.extend(n);
            mesh.triangles.push([first, first + 1, first + 2]);
            mesh.material_of_triangle.push(0);
        };
        let (x, y, z) = (Vec3::X, Vec3::Y, Vec3::Z);
        add([Vec3::ZERO, x * 1e-30, y * 1e-30], [z; 3]);
        add([Vec3::ZERO, x * 1e30, y * 1e30], [z; 3]);
        add([Vec3::ZERO, x, y], [z, -z, z]);
        add([Vec3::ZERO, x, y], [Vec3::ZERO; 3]);
        add([Vec3::ZERO, x * 3e38, y], [-x, x, z]);
        mesh
    }

    #[test]
    fn points_in_lanes_are_the_single_points_to_the_bit() {
        let mesh = mesh_with_fallbacks();
        let mut random = crate::test_random::XorShift32::new(0x9e37_79b9);
        // Every triangle, at random barycentrics and at its centre (where the cancelling normals
        // cancel exactly), in packets of up to 16 rays with some misses among them.
        let mut hits = Vec::new();
        for t in 0..mesh.triangle_count() as u32 {
            let (b1, b2) = (random.unit() * 0.5, random.unit() * 0.5);
            hits.push(Some(Hit {
                triangle: t,
                t: 1.0,
                b1,
                b2,
            }));
            hits.push(Some(Hit {
                triangle: t,
                t: 1.0,
                b1: 0.5,
                b2: 0.0,
            }));
            if t % 3 == 0 {
                hits.push(None);
            }
        }
        let direction = |k: usize| Vec3::new(0.3, -0.5, -(k as f32 + 1.0)).normalize();
        let bits = |p: &SurfacePoint| {
            let v = |v: Vec3| v.to_array().map(f32::to_bits);
            (
                v(p.position),
                p.shadow_lift.to_bits(),
                v(p.geometric_normal),
                v(p.shading_normal),
            )
        };
        let mut fallbacks = 0;
        for smooth_shadow_origins in [false, true] {
            let options = PointOptions {
                uvs: true,
                smooth_shadow_origins,
            };
            for packet in hits.chunks(16) {
                let mut seen = Vec::new();
                surface_points(&mesh, packet, direction, options, |k, hit, point| {
                    let single = surface_point(&mesh, hit, direction(k), options);
                    assert_eq!(bits(&point), bits(&single), "hit {hit:?}: {point:?} against {single:?}");
                    assert_eq!(
                        (point.uv, point.material, point.to_viewer),
                        (single.uv, single.material, single.to_viewer)
                    );
                    fallbacks += usize::from(
                        point.geometric_normal == point.to_viewer || point.shading_normal == point.geometric_normal,
                    );
                    seen.push(k);
                });
                let want: Vec<usize> = (0..packet.len()).filter(|&k| packet[k].is_some()).collect();
                assert_eq!(seen, want, "every hit once, in order");
            }
        }
        assert!(
            fallbacks >= 4,
            "the degenerate triangles took their fallbacks ({fallbacks})"
        );
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
