//! Packets of nearly parallel rays — the samples of one pixel — traced through the 4-wide tree
//! together: one walk of the tree per packet, each node's four boxes tested against the whole
//! packet at once with interval arithmetic, and each ray's own triangle tests at the leaves.
//!
//! Why: the adaptive sampler takes 16, 64, … samples in a pixel that still changes. Their rays
//! differ by less than a pixel and visit nearly the same nodes, so a walk per ray repeats the node
//! tests (most of a primary ray's cost) once per sample.
//!
//! Exactness. A packet's box test bounds every ray's own rounded box test: the ray computes
//! `fl(fl(plane − o)·(1/d))`, and rounding is monotonic, so taking the origins' extreme `o` on
//! each axis and the extreme `1/d` (same sign on each axis across the packet, or no packet) gives
//! an entry distance no later and an exit no earlier than any ray's. Every leaf a ray's own walk
//! reaches is therefore reached, and there each ray runs the same watertight test with its own
//! bound: the closest hit found is the same, bit for bit, and at exactly equal distances the
//! same triangle wins (the lower index, [`Nearest`]), whatever order the leaves came in.

use glam::{Vec3A, Vec4};

use super::alpha::HitFilter;
use super::walk::{FixedStack, NodeTest};
use super::wide::{Nearest, Node4, QuadHit, WideBvh, WideRay};

/// Most rays in one packet.
pub const PACKET: usize = 16;

/// Widest spread of a packet's origins on any axis, in BVH units (the scene is ~256 across).
/// A perspective camera's rays share its origin (an orthographic block's spread is its
/// footprint); this bounds shadow packets above all, whose origins are the hit points of a
/// block's samples. Samples on one surface start within a block's footprint and
/// share most of their walk; samples split across a silhouette start far apart, and the
/// packet's bounds then enclose everything between them, which made the adaptive sampler's edge
/// pixels slow to shade. The bound keeps a block's points on one surface together, walls
/// included (the Cornell box's spread widest), and parts those across a silhouette; 3 units did
/// best in a sweep (docs/performance-log.md).
const MAX_ORIGIN_SPREAD: f32 = 3.0;

/// The rays of a packet and the bounds of their origins and inverse directions, per axis.
pub struct RayPacket<'a> {
    rays: &'a [WideRay],
    /// The extreme origin coordinate to use with the near plane (the largest for a positive
    /// direction, whose near plane is the minimum) and with the far plane.
    origin_near: [Vec4; 3],
    origin_far: [Vec4; 3],
    inv_lo: [Vec4; 3],
    inv_hi: [Vec4; 3],
    near: [usize; 3],
    /// The rays four to a group, one per lane (unused lanes repeat the last ray): origins and
    /// inverse directions per axis, for testing a leaf's box against each ray.
    lane_origin: [[Vec4; 3]; PACKET / 4],
    lane_inv_dir: [[Vec4; 3]; PACKET / 4],
}

impl<'a> RayPacket<'a> {
    /// The packet of 1..=[`PACKET`] `rays` that [`may_share_walk`] accepted: the caller asks
    /// once, before preparing the rays, with the same origins and `1/d`, which it passes here
    /// too (`origin[k]`, `inv_dir[k]` for ray k, then copies of the last ray's up to [`PACKET`]:
    /// the copies change no bound and fill the last group's lanes).
    #[inline(always)]
    pub(super) fn new(rays: &'a [WideRay], origin: &[Vec3A; PACKET], inv_dir: &[Vec3A; PACKET]) -> Self {
        debug_assert!(
            rays.len() <= PACKET && may_share_walk(rays.iter().map(origin_and_inverse)),
            "rays that cannot share a walk"
        );
        let (mut o_lo, mut o_hi, mut i_lo, mut i_hi) = (origin[0], origin[0], inv_dir[0], inv_dir[0]);
        for (&o, &i) in origin.iter().zip(inv_dir) {
            (o_lo, o_hi) = (o_lo.min(o), o_hi.max(o));
            (i_lo, i_hi) = (i_lo.min(i), i_hi.max(i));
        }
        let near = rays[0].near;
        // Positive direction: the near plane is the minimum and the earliest entry comes from
        // the largest origin; negative: the other way round.
        let extreme = |axis: usize, nearest: bool| {
            let positive = near[axis] == 0;
            Vec4::splat(if positive == nearest { o_hi[axis] } else { o_lo[axis] })
        };
        // The rays four to a group, per axis.
        let lanes = |v: &[Vec3A; PACKET], group: usize| {
            let ray = |k: usize| v[4 * group + k];
            let (a, b, c, d) = (ray(0), ray(1), ray(2), ray(3));
            [
                Vec4::new(a.x, b.x, c.x, d.x),
                Vec4::new(a.y, b.y, c.y, d.y),
                Vec4::new(a.z, b.z, c.z, d.z),
            ]
        };
        // Arrays written out rather than `[0, 1, 2].map(…)`: the compiler left `map`'s closures
        // as calls once the code around the packet walks changed.
        Self {
            rays,
            origin_near: [extreme(0, true), extreme(1, true), extreme(2, true)],
            origin_far: [extreme(0, false), extreme(1, false), extreme(2, false)],
            inv_lo: [Vec4::splat(i_lo.x), Vec4::splat(i_lo.y), Vec4::splat(i_lo.z)],
            inv_hi: [Vec4::splat(i_hi.x), Vec4::splat(i_hi.y), Vec4::splat(i_hi.z)],
            near,
            lane_origin: [lanes(origin, 0), lanes(origin, 1), lanes(origin, 2), lanes(origin, 3)],
            lane_inv_dir: [
                lanes(inv_dir, 0),
                lanes(inv_dir, 1),
                lanes(inv_dir, 2),
                lanes(inv_dir, 3),
            ],
        }
    }

    /// Each ray's closest hit with 0 < t < `t_max[k]` in [`Nearest`]'s order, written to
    /// `best[k]` (one entry per ray; `t_max` past the rays must be 0). The tree must be
    /// traversable with the fixed stack ([`WideBvh::stack`]).
    pub fn closest_hits(
        &self,
        bvh: &WideBvh,
        t_max: &mut [f32; PACKET],
        best: &mut [Option<(u32, QuadHit)>],
        filter: &impl HitFilter,
    ) {
        debug_assert!(best.len() == self.rays.len() && t_max[self.rays.len()..].iter().all(|&t| t == 0.0));
        let mut nearest = [Nearest::before(0.0); PACKET];
        for (nearest, &t) in nearest.iter_mut().zip(&*t_max) {
            *nearest = Nearest::before(t);
        }
        let packet_t_max = t_max.iter().copied().fold(0.0, f32::max);
        bvh.walk_nearest_first(self, packet_t_max, &mut FixedStack::new(), |quad, packet_t_max| {
            let q = quad as usize;
            let mut found = false;
            for k in self.rays_entering(&bvh.quad_bounds[q], t_max) {
                if let Some(hit) =
                    bvh.quads[q].intersect(&self.rays[k], &bvh.quad_triangles[q], &mut nearest[k], filter)
                {
                    t_max[k] = hit.t;
                    best[k] = Some((quad, hit));
                    found = true;
                }
            }
            if found {
                t_max.iter().copied().fold(0.0, f32::max)
            } else {
                packet_t_max
            }
        });
    }

    /// Whether each ray hits anything with 0 < t < `t_max[k]`, written to `occluded[k]` (one
    /// entry per ray; `t_max` past the rays must be 0): exactly the answer of the ray's own
    /// any-hit walk, since the packet reaches every leaf the ray's walk reaches. The walk ends
    /// when every ray is occluded. The tree must be traversable with the fixed stack ([`WideBvh::stack`]).
    pub fn any_hits(&self, bvh: &WideBvh, t_max: &[f32; PACKET], occluded: &mut [bool], filter: &impl HitFilter) {
        debug_assert!(occluded.len() == self.rays.len() && t_max[self.rays.len()..].iter().all(|&t| t == 0.0));
        occluded.fill(false);
        let packet_t_max = t_max.iter().copied().fold(0.0, f32::max);
        bvh.walk_until(self, packet_t_max, &mut FixedStack::new(), |quad, packet_t_max| {
            let triangles = &bvh.quads[quad as usize];
            let primitives = || &bvh.quad_triangles[quad as usize];
            let mut found = false;
            for k in self.rays_entering(&bvh.quad_bounds[quad as usize], t_max) {
                if !occluded[k] && triangles.hits_any(&self.rays[k], t_max[k], primitives, filter) {
                    occluded[k] = true;
                    found = true;
                }
            }
            if !found {
                return Some(packet_t_max);
            }
            // The farthest segment still open bounds the rest of the walk; none left: done.
            let open = t_max.iter().zip(&*occluded).filter(|(_, &o)| !o).map(|(&t, _)| t);
            open.reduce(f32::max)
        });
    }
}

/// Whether rays with these origins and inverse directions (BVH space) can share a walk: every
/// inverse direction finite (a zero component needs the single-ray test's NaN rule, which
/// interval bounds do not follow) and of one sign per axis across the rays, and the origins
/// within [`MAX_ORIGIN_SPREAD`] on every axis. Asked before the rays are prepared, so that
/// rays that will go one by one are not (refusals are common where pixels span silhouettes).
pub(super) fn may_share_walk(mut rays: impl Iterator<Item = (Vec3A, Vec3A)>) -> bool {
    let Some((origin, inv_dir)) = rays.next() else {
        return false;
    };
    let negative = inv_dir.cmplt(Vec3A::ZERO);
    let (mut lo, mut hi) = (origin, origin);
    let mut ok = inv_dir.is_finite();
    for (origin, inv_dir) in rays {
        ok &= inv_dir.is_finite() && inv_dir.cmplt(Vec3A::ZERO) == negative;
        (lo, hi) = (lo.min(origin), hi.max(origin));
    }
    ok && (hi - lo).cmple(Vec3A::splat(MAX_ORIGIN_SPREAD)).all()
}

/// A prepared ray's origin and inverse direction, as [`may_share_walk`] takes them.
fn origin_and_inverse(ray: &WideRay) -> (Vec3A, Vec3A) {
    let axes = |v: &[Vec4; 3]| Vec3A::new(v[0].x, v[1].x, v[2].x);
    (axes(&ray.origin), axes(&ray.inv_dir))
}

impl RayPacket<'_> {
    /// The rays (indices into the packet) whose own box test enters the leaf box `bounds`
    /// within (0, `t_max[k]`]: the very arithmetic of [`WideRay`]'s node test, lane for lane,
    /// so a ray skipped here is one its own walk would not have tested this leaf with. (The
    /// packet reaches every leaf some ray may enter; most rays of a packet enter few of them.)
    #[inline(always)]
    fn rays_entering(&self, bounds: &[[f32; 3]; 2], t_max: &[f32; PACKET]) -> impl Iterator<Item = usize> {
        let n = self.rays.len();
        let mut mask = 0u32;
        for group in 0..n.div_ceil(4) {
            // Lanes past the rays (t_max 0) are masked off below.
            let t_max = Vec4::from_slice(&t_max[4 * group..]);
            let (origin, inv_dir) = (&self.lane_origin[group], &self.lane_inv_dir[group]);
            let mut t_near = Vec4::ZERO;
            let mut t_far = t_max;
            for axis in 0..3 {
                let near = (Vec4::splat(bounds[self.near[axis]][axis]) - origin[axis]) * inv_dir[axis];
                let far = (Vec4::splat(bounds[1 - self.near[axis]][axis]) - origin[axis]) * inv_dir[axis];
                t_near = near.max(t_near);
                t_far = far.min(t_far);
            }
            mask |= t_near.cmple(t_far).bitmask() << (4 * group);
        }
        mask &= (1u32 << n) - 1;
        std::iter::from_fn(move || {
            (mask != 0).then(|| {
                let k = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                k
            })
        })
    }
}

impl NodeTest for RayPacket<'_> {
    /// Which of the node's four boxes some ray of the packet may enter within [0, t_max], and a
    /// lower bound of where (never NaN: every bound is finite, see [`Self::new`]).
    #[inline(always)]
    fn boxes(&self, node: &Node4, t_max: f32) -> (u32, Vec4) {
        let mut t_near = Vec4::ZERO;
        let mut t_far = Vec4::splat(t_max);
        for axis in 0..3 {
            let x = node.bounds[axis][self.near[axis]] - self.origin_near[axis];
            let y = node.bounds[axis][1 - self.near[axis]] - self.origin_far[axis];
            let (lo, hi) = (self.inv_lo[axis], self.inv_hi[axis]);
            t_near = (x * lo).min(x * hi).max(t_near);
            t_far = (y * lo).max(y * hi).min(t_far);
        }
        (t_near.cmple(t_far).bitmask(), t_near)
    }
}

#[cfg(test)]
mod tests {
    use glam::{Vec3, Vec3A};

    use super::{may_share_walk, origin_and_inverse, PACKET};
    use crate::accel::triangle::WatertightRay;
    use crate::accel::wide::WideRay;
    use crate::accel::{Bvh, BvhPreset};
    use crate::scene::camera::Camera;
    use crate::scene::framing::frame_bounds;
    use crate::scene::mesh::TriangleMesh;
    use crate::scene::procedural::torus;

    const SIZE: u32 = 192;

    fn torus_mesh() -> TriangleMesh {
        torus(1.0, 0.35, 160, 48).into_triangle_mesh()
    }

    /// The torus's tree and a camera framing it.
    fn torus_scene() -> (Bvh, Camera) {
        let mesh = torus_mesh();
        let (lo, hi) = mesh.bounds().unwrap();
        let camera = Camera::new(frame_bounds(lo, hi), SIZE, SIZE).unwrap();
        (Bvh::build(&mesh, BvhPreset::Fast), camera)
    }

    /// `PACKET` rays on a 4×4 grid inside pixel (px, py), as `(origin, direction, t_max)`.
    fn pixel_rays(camera: &Camera, px: u32, py: u32) -> Vec<(Vec3, Vec3, f32)> {
        (0..PACKET)
            .map(|k| {
                let (jx, jy) = ((k % 4) as f32 * 0.25 + 0.125, (k / 4) as f32 * 0.25 + 0.125);
                let r = camera.ray((px as f32 + jx) / SIZE as f32, (py as f32 + jy) / SIZE as f32);
                (r.origin, r.direction, r.t_max)
            })
            .collect()
    }

    /// Asserts that every ray's packet hit is its single-ray hit, bit for bit; returns the hits.
    fn compare(bvh: &Bvh, rays: &[(Vec3, Vec3, f32)], what: &str) -> usize {
        let mut got = [None; PACKET];
        bvh.intersect_packet(rays, &mut got);
        for (&(o, d, t), got) in rays.iter().zip(got) {
            let want = bvh.intersect(o, d, t);
            let bits = |h: Option<crate::accel::Hit>| h.map(|h| (h.triangle, [h.t, h.b1, h.b2].map(f32::to_bits)));
            assert_eq!(bits(want), bits(got), "{what}: single ray {want:?}, packet {got:?}");
        }
        got.iter().filter(|h| h.is_some()).count()
    }

    #[test]
    fn a_packet_finds_each_rays_own_closest_hit() {
        let (bvh, camera) = torus_scene();
        let mut hits = 0;
        // The samples of each pixel (nearly one origin, nearly parallel).
        for py in 0..SIZE {
            for px in 0..SIZE {
                hits += compare(&bvh, &pixel_rays(&camera, px, py), &format!("pixel ({px}, {py})"));
            }
        }
        // Parallel rays from origins spread over a quarter of the torus (the origin bounds).
        let d = Vec3::new(0.3, -1.0, 0.2).normalize();
        for i in 0..400 {
            let corner = Vec3::new(-1.4 + 0.14 * (i % 20) as f32, 2.0, -1.4 + 0.14 * (i / 20) as f32);
            let rays: Vec<_> = (0..PACKET)
                .map(|k| (corner + Vec3::new((k % 4) as f32, 0.0, (k / 4) as f32) * 0.09, d, 10.0))
                .collect();
            hits += compare(&bvh, &rays, &format!("parallel packet {i}"));
        }
        assert!(
            hits > 50_000,
            "the torus should fill a good part of the frame: {hits} hits"
        );
    }

    /// Compares every segment's packet answer with its single-ray answer; returns (blocked, open).
    fn compare_occlusion(bvh: &Bvh, segments: &[(Vec3, Vec3, f32)], what: &str) -> (usize, usize) {
        let mut got = [false; PACKET];
        bvh.any_hit_packet(segments, &mut got);
        for (&(o, d, t), &got) in segments.iter().zip(&got) {
            assert_eq!(bvh.any_hit(o, d, t), got, "{what}: segment from {o} along {d} to {t}");
        }
        let blocked = got.iter().filter(|&&b| b).count();
        (blocked, segments.len() - blocked)
    }

    #[test]
    fn a_packet_answers_each_segments_own_occlusion() {
        let (bvh, camera) = torus_scene();
        let light = Vec3::new(0.4, 2.5, 0.9);
        let (mut blocked, mut open, mut packets) = (0, 0, 0);
        for py in (0..SIZE).step_by(2) {
            for px in (0..SIZE).step_by(2) {
                let rays = pixel_rays(&camera, px, py);
                let hit_t: Vec<Option<f32>> = rays.iter().map(|&(o, d, t)| Some(bvh.intersect(o, d, t)?.t)).collect();
                // Camera segments cut from 8% short of their hit to 7% beyond it.
                let cut: Vec<_> = (rays.iter().zip(&hit_t).enumerate())
                    .map(|(k, (&(o, d, t), hit))| (o, d, hit.map_or(t, |h| h * (0.92 + 0.01 * k as f32))))
                    .collect();
                // Shadow segments towards a point light from just before each ray's hit.
                let shadow: Vec<_> = (rays.iter().zip(&hit_t))
                    .map(|(&(o, d, _), hit)| {
                        let p = o + d * hit.map_or(3.0, |h| h * 0.999);
                        (p, (light - p).normalize(), (light - p).length())
                    })
                    .collect();
                for (segments, what) in [(&cut, "camera"), (&shadow, "shadow")] {
                    let (b, o) = compare_occlusion(&bvh, segments, &format!("{what} segments of ({px}, {py})"));
                    (blocked, open) = (blocked + b, open + o);
                    packets += shares_walk(&wide(segments)) as usize;
                }
            }
        }
        let groups = 2 * (SIZE as usize / 2).pow(2);
        assert!(
            packets * 10 > groups * 9,
            "{packets} of {groups} groups went as packets"
        );
        assert!(blocked > 10_000 && open > 10_000, "{blocked} blocked, {open} open");
    }

    /// Whether prepared rays may go through the tree as one packet.
    fn shares_walk(rays: &[WideRay]) -> bool {
        may_share_walk(rays.iter().map(origin_and_inverse))
    }

    /// The rays prepared for the wide traversal, as [`Bvh::intersect_packet`] does (unit scale).
    fn wide(rays: &[(Vec3, Vec3, f32)]) -> Vec<WideRay> {
        rays.iter()
            .map(|&(o, d, _)| {
                let (o, d) = (Vec3A::from(o), Vec3A::from(d));
                WideRay::new(o, d, &WatertightRay::new(o, d))
            })
            .collect()
    }

    #[test]
    fn the_rays_of_a_pixel_share_a_walk_and_mixed_signs_do_not() {
        let mesh = torus_mesh();
        let (lo, hi) = mesh.bounds().unwrap();
        let camera = Camera::new(frame_bounds(lo, hi), SIZE, SIZE).unwrap();
        let pixel = wide(&pixel_rays(&camera, 40, 50));
        assert!(shares_walk(&pixel));
        let mixed = wide(&[(Vec3::ZERO, Vec3::X, 1.0), (Vec3::ZERO, -Vec3::X, 1.0)]);
        assert!(!shares_walk(&mixed));
    }
}
