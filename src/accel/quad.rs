//! The leaf test of the 4-wide BVH: four triangles in float lanes ([`TriangleQuad`]), tested
//! against one prepared ray ([`WideRay`]) by the watertight ray/triangle test (Woop et al.)
//! lane by lane, bit-identical per lane to the scalar test in [`super::triangle`], and the
//! order of hits ([`Nearest`]: distance, then triangle index).

use glam::{BVec4A, Vec3A, Vec4};

use super::alpha::HitFilter;
use super::triangle::WatertightRay;

/// Four triangles in lanes: `v[vertex][axis]`. Unused lanes repeat lane 0 and are masked off.
#[derive(Clone, Copy, Debug)]
pub struct TriangleQuad {
    v: [[Vec4; 3]; 3],
    lanes: BVec4A,
}

/// The closest hit found in a quad.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadHit {
    /// Lane of the hit triangle.
    pub lane: usize,
    /// Distance along the ray (units of its direction).
    pub t: f32,
    /// Barycentric weight of the triangle's vertex 1.
    pub b1: f32,
    /// Barycentric weight of its vertex 2.
    pub b2: f32,
}

/// The lanes whose triangle a ray's line crosses in front of its origin, and what their
/// distances and barycentrics are made of (the watertight test's terms, lane by lane).
struct Crossing {
    lanes: BVec4A,
    /// t·|det| and |det| (> 0 on crossed lanes).
    t_scaled: Vec4,
    det_abs: Vec4,
    /// The signed determinant u + v + w and the edge functions v, w.
    det: Vec4,
    v: Vec4,
    w: Vec4,
}

impl Crossing {
    /// Whether `filter` keeps lane `k`'s hit (always, without asking, when it filters nothing).
    #[inline(always)]
    fn kept_by(&self, k: usize, primitives: &[u32; 4], filter: &impl HitFilter) -> bool {
        if !filter.filters() {
            return true;
        }
        // det ≠ 0 on crossed lanes.
        let inv_det = 1.0 / self.det.to_array()[k];
        filter.keeps(
            primitives[k],
            self.v.to_array()[k] * inv_det,
            self.w.to_array()[k] * inv_det,
        )
    }
}

/// The closest hit so far, as hits are ordered: by distance, then by the triangle's index in the
/// scene mesh.
///
/// Why the index: triangles at exactly the same distance (coincident faces, a ray through a
/// shared edge) would otherwise go to whichever the walk tested first, and the walk's order
/// depends on the tree and on the packet a ray travels in. With ties broken by index the closest
/// hit is a function of the ray and the mesh alone, so a pixel traced alone, in a packet of its
/// neighbours (which depend on the crop) or through another preset's tree gives the same image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Nearest {
    /// Distance (units of the ray's direction).
    pub t: f32,
    /// Scene triangle index.
    pub primitive: u32,
}

impl Nearest {
    /// Nothing found yet: any hit with t < `t_max` beats it (at t = `t_max` no index is below 0).
    #[inline(always)]
    pub fn before(t_max: f32) -> Self {
        Self { t: t_max, primitive: 0 }
    }

    /// Whether a hit of `primitive` at `t` comes first.
    #[inline(always)]
    fn beaten_by(&self, t: f32, primitive: u32) -> bool {
        t < self.t || (t == self.t && primitive < self.primitive)
    }
}

/// A ray prepared for the wide traversal (BVH space).
#[derive(Clone, Copy, Debug)]
pub struct WideRay {
    pub(super) origin: [Vec4; 3],
    pub(super) inv_dir: [Vec4; 3],
    /// Per axis: which of `bounds[axis]` is the near plane (0 = minimum for a positive direction).
    pub(super) near: [usize; 3],
    /// The watertight test's permutation kx, ky, kz (see [`WatertightRay`]).
    axes: [usize; 3],
    /// Its shear constants s_x, s_y, s_z, each splat across lanes.
    shear: [Vec4; 3],
}

impl WideRay {
    /// Prepares `origin + t·direction`. `direction` must be finite, non-zero and free of −0.0
    /// (the caller normalises −0.0 to +0.0 so that 1/d and the near-plane choice agree).
    #[inline]
    pub fn new(origin: Vec3A, direction: Vec3A, watertight: &WatertightRay) -> Self {
        let inv = direction.recip();
        let splat3 = |v: Vec3A| [Vec4::splat(v.x), Vec4::splat(v.y), Vec4::splat(v.z)];
        Self {
            origin: splat3(origin),
            inv_dir: splat3(inv),
            near: [(inv.x < 0.0) as usize, (inv.y < 0.0) as usize, (inv.z < 0.0) as usize],
            axes: watertight.axes(),
            shear: watertight.shear_constants().map(Vec4::splat),
        }
    }
}

impl TriangleQuad {
    /// The quad of triangles `triangle(0)`, …, `triangle(n − 1)` (1 ≤ n ≤ 4).
    #[inline]
    pub(super) fn from_fn(n: usize, triangle: impl Fn(usize) -> [Vec3A; 3]) -> Self {
        debug_assert!((1..=4).contains(&n));
        let lanes = [0, 1, 2, 3].map(|k| triangle(k.min(n - 1)));
        let mut v = [[Vec4::ZERO; 3]; 3];
        for (vertex, row) in v.iter_mut().enumerate() {
            for (axis, value) in row.iter_mut().enumerate() {
                *value = Vec4::from_array(lanes.map(|t| t[vertex][axis]));
            }
        }
        Self {
            v,
            lanes: BVec4A::new(n > 0, n > 1, n > 2, n > 3),
        }
    }

    /// The closest of the four triangles (scene indices `primitives`) that the ray hits at
    /// 0 < t and before `nearest` in [`Nearest`]'s order, if any; `nearest` becomes that hit.
    ///
    /// Lane by lane this is [`WatertightRay::intersect`]: the same sheared coordinates, the same
    /// edge functions with the same f64 recomputation of exact zeros, the same distance
    /// t = t·|det| / |det| — compared itself with `nearest.t`, so that exact ties are seen — and
    /// the same barycentrics v/det, w/det, computed for the winning lane only. Hits `filter`
    /// does not keep (cut-outs) do not count.
    #[inline(always)]
    pub fn intersect(
        &self,
        ray: &WideRay,
        primitives: &[u32; 4],
        nearest: &mut Nearest,
        filter: &impl HitFilter,
    ) -> Option<QuadHit> {
        let c = self.crossed(ray)?;
        // det_abs > 0 on crossed lanes; the others' quotients are never read.
        let t = (c.t_scaled / c.det_abs).to_array();
        let mut lane = None;
        for k in 0..4 {
            if c.lanes.test(k)
                && t[k] > 0.0
                && nearest.beaten_by(t[k], primitives[k])
                && c.kept_by(k, primitives, filter)
            {
                *nearest = Nearest {
                    t: t[k],
                    primitive: primitives[k],
                };
                lane = Some(k);
            }
        }
        let lane = lane?;
        // det ≠ 0 on crossed lanes.
        let inv_det = 1.0 / c.det.to_array()[lane];
        Some(QuadHit {
            lane,
            t: t[lane],
            b1: c.v.to_array()[lane] * inv_det,
            b2: c.w.to_array()[lane] * inv_det,
        })
    }

    /// Whether the ray hits any of the four triangles with 0 < t < `t_max` (without dividing
    /// out the distances: t·|det| < `t_max`·|det|), counting only hits `filter` keeps. The
    /// triangles' scene indices come from `primitives`, asked only when the filter filters (an
    /// unused lookup of them still cost a bounds check per leaf).
    #[inline(always)]
    pub fn hits_any<'p>(
        &self,
        ray: &WideRay,
        t_max: f32,
        primitives: impl FnOnce() -> &'p [u32; 4],
        filter: &impl HitFilter,
    ) -> bool {
        let Some(c) = self.crossed(ray) else {
            return false;
        };
        let hit = c.lanes & c.t_scaled.cmplt(c.det_abs * t_max);
        if !filter.filters() {
            return hit.any();
        }
        let primitives = primitives();
        (0..4).any(|k| hit.test(k) && c.kept_by(k, primitives, filter))
    }

    /// The lanes whose triangle the ray's line crosses at t > 0 (none: `None`).
    #[inline(always)]
    fn crossed(&self, ray: &WideRay) -> Option<Crossing> {
        let [kx, ky, kz] = ray.axes;
        let [sx, sy, sz] = ray.shear;
        let sheared = |vertex: usize| -> [Vec4; 3] {
            // The vertex relative to the origin, on the permuted axes only.
            let d = |axis: usize| self.v[vertex][axis] - ray.origin[axis];
            let (dx, dy, dz) = (d(kx), d(ky), d(kz));
            [dx - sx * dz, dy - sy * dz, sz * dz]
        };
        let (a, b, c) = (sheared(0), sheared(1), sheared(2));
        let mut u = c[0] * b[1] - c[1] * b[0];
        let mut v = a[0] * c[1] - a[1] * c[0];
        let mut w = b[0] * a[1] - b[1] * a[0];
        let zero = Vec4::ZERO;
        let exact_edge = (u.cmpeq(zero) | v.cmpeq(zero) | w.cmpeq(zero)) & self.lanes;
        if exact_edge.any() {
            // Exactly on an edge in f32: decide in f64 so neighbours agree (the paper's fallback).
            let (mut ua, mut va, mut wa) = (u.to_array(), v.to_array(), w.to_array());
            for k in (0..4).filter(|&k| exact_edge.test(k)) {
                let f = |x: Vec4| x.to_array()[k] as f64;
                let (ax, ay, bx, by, cx, cy) = (f(a[0]), f(a[1]), f(b[0]), f(b[1]), f(c[0]), f(c[1]));
                ua[k] = (cx * by - cy * bx) as f32;
                va[k] = (ax * cy - ay * cx) as f32;
                wa[k] = (bx * ay - by * ax) as f32;
            }
            (u, v, w) = (Vec4::from_array(ua), Vec4::from_array(va), Vec4::from_array(wa));
        }
        let negative = u.cmplt(zero) | v.cmplt(zero) | w.cmplt(zero);
        let positive = u.cmpgt(zero) | v.cmpgt(zero) | w.cmpgt(zero);
        let det = u + v + w;
        let mut hit = self.lanes & !(negative & positive) & det.cmpne(zero);
        if !hit.any() {
            return None;
        }
        let t_scaled = u * a[2] + v * b[2] + w * c[2];
        // Fold det's sign into both terms: t > 0 is then t_scaled > 0, without dividing.
        let flip = det.cmplt(zero);
        let t_scaled = Vec4::select(flip, -t_scaled, t_scaled);
        let det_abs = Vec4::select(flip, -det, det);
        hit &= t_scaled.cmpgt(zero);
        hit.any().then_some(Crossing {
            lanes: hit,
            t_scaled,
            det_abs,
            det,
            v,
            w,
        })
    }
}
