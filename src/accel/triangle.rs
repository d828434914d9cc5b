//! Watertight ray/triangle intersection (Woop, Benthin & Wald, JCGT 2013).
//!
//! obvhs's own Möller–Trumbore test leaks rays through shared edges seen from the back; this one
//! shears the triangle into ray space so that two triangles sharing an edge compute that edge's
//! 2D edge function from identical inputs: a ray through the edge hits at least one of them.
//! Edge functions that come out exactly zero are recomputed in f64, as the paper prescribes.

use glam::Vec3A;

/// A ray prepared for the watertight test: the axis permutation and the shear constants.
///
/// Woop et al. permute the axes so that the ray's largest component is z (kz), then shear:
/// `x' = a[kx] − s_x·a[kz]`, `y' = a[ky] − s_y·a[kz]`, `z' = s_z·a[kz]`, for `a = v − origin`.
#[derive(Clone, Copy, Debug)]
pub struct WatertightRay {
    origin: Vec3A,
    /// kx, ky, kz.
    axes: [usize; 3],
    /// s_x, s_y, s_z.
    shear: [f32; 3],
}

/// Where a ray meets a triangle: distance and the barycentric weights of vertices 1 and 2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleHit {
    /// Distance along the (unnormalised) ray direction.
    pub t: f32,
    /// Weight of vertex 1.
    pub b1: f32,
    /// Weight of vertex 2.
    pub b2: f32,
}

impl WatertightRay {
    /// Precomputes the shear for `direction` (must be non-zero and finite).
    #[inline]
    pub fn new(origin: Vec3A, direction: Vec3A) -> Self {
        let abs = direction.abs();
        let kz = if abs.x >= abs.y && abs.x >= abs.z {
            0
        } else if abs.y >= abs.z {
            1
        } else {
            2
        };
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        // Keep the winding of the projected triangle independent of the ray's sign.
        if direction[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        // direction[kz] is the largest component of a non-zero vector: never 0.
        let dz = direction[kz];
        Self {
            origin,
            axes: [kx, ky, kz],
            shear: [direction[kx] / dz, direction[ky] / dz, 1.0 / dz],
        }
    }

    /// kx, ky, kz: the permutation that makes the ray's largest component z.
    #[inline(always)]
    pub fn axes(&self) -> [usize; 3] {
        self.axes
    }

    /// s_x, s_y, s_z: the shear constants.
    #[inline(always)]
    pub fn shear_constants(&self) -> [f32; 3] {
        self.shear
    }

    /// `v − origin` permuted and sheared: (x', y') for the edge functions, z' for the distance.
    #[inline(always)]
    fn shear(&self, v: Vec3A) -> Vec3A {
        let a = (v - self.origin).to_array();
        let [kx, ky, kz] = self.axes;
        let [sx, sy, sz] = self.shear;
        Vec3A::new(a[kx] - sx * a[kz], a[ky] - sy * a[kz], sz * a[kz])
    }

    /// Intersects triangle (v0, v1, v2); hits with 0 < t < t_max count. Both faces are hit.
    #[inline]
    pub fn intersect(&self, v: &[Vec3A; 3], t_max: f32) -> Option<TriangleHit> {
        let a = self.shear(v[0]);
        let b = self.shear(v[1]);
        let c = self.shear(v[2]);
        let (ax, ay, bx, by, cx, cy) = (a.x, a.y, b.x, b.y, c.x, c.y);
        let mut u = cx * by - cy * bx;
        let mut v_ = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        if u == 0.0 || v_ == 0.0 || w == 0.0 {
            // Exactly on an edge in f32: decide in f64 so neighbours agree.
            let (ax, ay, bx, by, cx, cy) = (ax as f64, ay as f64, bx as f64, by as f64, cx as f64, cy as f64);
            u = (cx * by - cy * bx) as f32;
            v_ = (ax * cy - ay * cx) as f32;
            w = (bx * ay - by * ax) as f32;
        }
        if (u < 0.0 || v_ < 0.0 || w < 0.0) && (u > 0.0 || v_ > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v_ + w;
        if det == 0.0 {
            return None; // ray parallel to the triangle plane, or a degenerate triangle
        }
        let t_scaled = u * a.z + v_ * b.z + w * c.z;
        // Compare t = t_scaled/det with (0, t_max) without dividing: flip signs by det's sign.
        let sign = det.signum();
        let (t_scaled, det_abs) = (t_scaled * sign, det * sign);
        if t_scaled <= 0.0 || t_scaled >= t_max * det_abs {
            return None;
        }
        let inv_det = 1.0 / det; // det ≠ 0 checked above
        Some(TriangleHit {
            t: t_scaled / det_abs,
            b1: v_ * inv_det,
            b2: w * inv_det,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::vec3a;

    const TRI: [Vec3A; 3] = [
        Vec3A::new(0.0, 0.0, 0.0),
        Vec3A::new(1.0, 0.0, 0.0),
        Vec3A::new(0.0, 1.0, 0.0),
    ];

    #[test]
    fn hit_reports_distance_and_barycentrics() {
        let ray = WatertightRay::new(vec3a(0.25, 0.5, 2.0), vec3a(0.0, 0.0, -1.0));
        let hit = ray.intersect(&TRI, f32::INFINITY).unwrap();
        assert!((hit.t - 2.0).abs() < 1e-6);
        assert!((hit.b1 - 0.25).abs() < 1e-6 && (hit.b2 - 0.5).abs() < 1e-6);
        // From the back side too.
        let back = WatertightRay::new(vec3a(0.25, 0.5, -2.0), vec3a(0.0, 0.0, 1.0));
        assert!(back.intersect(&TRI, f32::INFINITY).is_some());
    }

    #[test]
    fn misses_outside_behind_and_beyond_t_max() {
        let outside = WatertightRay::new(vec3a(0.75, 0.75, 2.0), vec3a(0.0, 0.0, -1.0));
        assert!(outside.intersect(&TRI, f32::INFINITY).is_none());
        let behind = WatertightRay::new(vec3a(0.25, 0.25, 2.0), vec3a(0.0, 0.0, 1.0));
        assert!(behind.intersect(&TRI, f32::INFINITY).is_none());
        let short = WatertightRay::new(vec3a(0.25, 0.25, 2.0), vec3a(0.0, 0.0, -1.0));
        assert!(short.intersect(&TRI, 1.9).is_none());
        let parallel = WatertightRay::new(vec3a(0.25, 0.25, 0.0), vec3a(1.0, 0.0, 0.0));
        assert!(parallel.intersect(&TRI, f32::INFINITY).is_none());
    }

    #[test]
    fn rays_through_a_shared_edge_hit_one_of_the_two_triangles_from_both_sides() {
        // Two triangles sharing the diagonal (1,0,0)–(0,1,0) of the unit square.
        let other = [TRI[1], vec3a(1.0, 1.0, 0.0), TRI[2]];
        for i in 0..=1000 {
            let s = i as f32 / 1000.0;
            let on_edge = vec3a(1.0 - s, s, 0.0);
            for dir in [vec3a(0.3, -0.2, -1.0), vec3a(-0.1, 0.4, 1.0)] {
                let ray = WatertightRay::new(on_edge - dir * 3.0, dir);
                let hits = [&TRI, &other]
                    .iter()
                    .filter(|t| ray.intersect(t, f32::INFINITY).is_some())
                    .count();
                assert!(hits >= 1, "ray through edge point {on_edge} leaked (dir {dir})");
            }
        }
    }
}
