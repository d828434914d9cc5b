//! Acceleration: a BVH over the scene's triangles — built by binned SAH straight into a 4-wide
//! SIMD tree ([`binned`]; obvhs's PLOC presets, collapsed by [`wide`], stay to compare with),
//! traversed with a watertight ray/triangle test ([`triangle`]).
//!
//! Choices that shape this module:
//! - **Power-of-two rescaling.** The BVH lives in "BVH space" = world × 2^e, with e chosen so the
//!   scene's bounding-box diagonal is about 256, so the leaf-box padding and every absolute
//!   tolerance mean the same at any scene scale. Multiplying by a power of two is exact in
//!   floating point; distances come back divided by the same factor.
//! - **Leaf-ordered triangles.** Triangle vertices are copied into the leaves' SIMD quads in
//!   traversal order, so traversal reads memory linearly and needs no index indirection.
//! - **Bounded depth.** The binned build splits by the median centre below a fixed depth; where
//!   PLOC degenerates (boxes that all overlap, as a fan's do) its tree is built balanced instead
//!   ([`balanced`]), so no input makes either deep or slow; trees deeper than the fixed stack
//!   are traversed with a growable one ([`TraversalStack`]); padded leaf boxes keep rays through
//!   shared vertices.
//! - **Any tree, the same hits.** The nearest hit and its ties are decided per triangle, so
//!   every preset gives every ray the same answer, bit for bit (`tests.rs`), and the choice of
//!   builder is one of speed alone.

pub mod alpha;
pub mod balanced;
pub mod binned;
mod bvh_space;
pub mod packet;
pub mod quad;
pub mod shadow;
pub mod triangle;
mod walk;
pub mod wide;

use std::mem::MaybeUninit;
use std::time::{Duration, Instant};

use glam::{Vec3, Vec3A};
use obvhs::BvhBuildParams;
use rayon::prelude::*;

use crate::accel::shadow::{Occluder, ShadowRay};
use crate::scene::mesh::TriangleMesh;
use crate::scene::Scene;
use alpha::{AlphaMask, HitFilter, Opaque};
use bvh_space::{padded_box, world_to_bvh_scale};
use packet::{RayPacket, PACKET};
use triangle::WatertightRay;
pub use wide::TraversalStack;
use wide::{QuadHit, WideBvh, WideRay};

/// How the tree is built: obvhs's presets (PLOC, from fastest build to best traversal, then
/// collapsed to 4-wide), or pointshade's binned SAH.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BvhPreset {
    /// `BvhBuildParams::fastest_build`.
    Fastest,
    /// `BvhBuildParams::fast_build`.
    Fast,
    /// `BvhBuildParams::medium_build`.
    Medium,
    /// `BvhBuildParams::slow_build` (spatial pre-splits).
    Slow,
    /// Binned SAH straight into the 4-wide tree ([`binned`]): on the dragon, half the build
    /// time of `Fast` and faster traversal (docs/performance-log.md), so the default.
    Binned,
}

impl BvhPreset {
    /// Every preset, for benchmarks.
    pub const ALL: [BvhPreset; 5] = [Self::Fastest, Self::Fast, Self::Medium, Self::Slow, Self::Binned];

    /// The preset renders use: chosen with `cargo bench --bench rays` (see README, Benchmarks).
    pub const DEFAULT: BvhPreset = BvhPreset::Binned;

    /// obvhs's parameters (`None`: not an obvhs build).
    fn params(self) -> Option<BvhBuildParams> {
        match self {
            Self::Fastest => Some(BvhBuildParams::fastest_build()),
            Self::Fast => Some(BvhBuildParams::fast_build()),
            Self::Medium => Some(BvhBuildParams::medium_build()),
            Self::Slow => Some(BvhBuildParams::slow_build()),
            Self::Binned => None,
        }
    }

    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Fastest => "fastest",
            Self::Fast => "fast",
            Self::Medium => "medium",
            Self::Slow => "slow",
            Self::Binned => "binned",
        }
    }
}

/// The closest intersection of a ray with the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Index of the triangle in the scene mesh.
    pub triangle: u32,
    /// World-space distance along the (unit) ray direction.
    pub t: f32,
    /// Barycentric weight of vertex 1.
    pub b1: f32,
    /// Barycentric weight of vertex 2.
    pub b2: f32,
}

/// A BVH over every triangle of a scene.
pub struct Bvh {
    wide: WideBvh,
    /// World → BVH space factor (a power of two).
    scale: f32,
    /// The mesh's bounding box in world space (`TriangleMesh::bounds`), kept from the build.
    bounds: Option<(Vec3, Vec3)>,
    /// Time spent building.
    pub build_time: Duration,
    /// The scene's cut-outs, when it has any ([`Self::set_alpha_mask`]): hits they cut out do
    /// not count for any query.
    alpha: Option<Box<AlphaMask>>,
}

impl Bvh {
    /// Builds the BVH over `mesh` (which must have at least one triangle).
    #[inline(never)] // a stage boundary that benches/instructions.sh counts
    pub fn build(mesh: &TriangleMesh, preset: BvhPreset) -> Bvh {
        let start = Instant::now();
        let bounds = mesh.bounds();
        let scale = world_to_bvh_scale(bounds);
        // Triangles without area (exactly zero cross product: repeated or collinear vertices)
        // have no normal and nothing to show; rounding in the sheared ray space could still
        // report hits on them, so they are left out of the BVH (unless nothing else is left).
        // Then each kept triangle's vertices in BVH space and its padded box. Every parallel
        // step is an indexed map, which rayon collects in place, cheaper than a filtered collect
        // of (index, triangle) pairs and an unzip (docs/performance-log.md).
        let n = mesh.triangle_count();
        let has_area: Vec<bool> = (0..n)
            .into_par_iter()
            .map(|t| {
                let [a, b, c] = mesh.triangle_positions(t);
                (b - a).cross(c - a) != Vec3::ZERO
            })
            .collect();
        let keep_all = !has_area.contains(&true);
        let kept: Vec<u32> = (0..n as u32).filter(|&t| keep_all || has_area[t as usize]).collect();
        let triangles: Vec<[Vec3A; 3]> = kept
            .par_iter()
            .map(|&t| mesh.triangle_positions(t as usize).map(|p| Vec3A::from(p * scale)))
            .collect();
        let mut wide = match preset.params() {
            None => binned::build(&triangles),
            Some(params) => {
                let boxes: Vec<_> = triangles.par_iter().map(padded_box).collect();
                let params = BvhBuildParams {
                    max_prims_per_leaf: 4,
                    ..params
                };
                // PLOC, unless the boxes overlap so that it would take quadratic time; its tree
                // rebuilt balanced if it came out too deep all the same ([`balanced`]).
                let bvh2 = if balanced::overlaps_too_much(&boxes) {
                    balanced::balanced_bvh2(&boxes, 4)
                } else {
                    let bvh2 = obvhs::bvh2::builder::build_bvh2(&boxes, params, &mut Duration::default());
                    if balanced::bvh2_depth(&bvh2) > balanced::MAX_BINARY_DEPTH {
                        balanced::balanced_bvh2(&boxes, 4)
                    } else {
                        bvh2
                    }
                };
                WideBvh::from_bvh2(&bvh2, &triangles)
            }
        };
        wide.map_primitives(|p| kept[p as usize]);
        Bvh {
            wide,
            scale,
            bounds,
            build_time: start.elapsed(),
            alpha: None,
        }
    }

    /// The BVH that a render of `scene` traces (and a bake, and anything else that looks at the
    /// scene as rendered): [`Self::build`] with the default preset, with the cut-outs of the
    /// MASK materials that triangles use ([`AlphaMask`]), when there are any.
    pub fn for_scene(scene: &Scene) -> Bvh {
        let mut bvh = Bvh::build(&scene.mesh, BvhPreset::DEFAULT);
        if let Some(mask) = AlphaMask::new(&scene.mesh, &scene.materials, &scene.textures) {
            bvh.set_alpha_mask(mask);
        }
        bvh
    }

    /// From now on, hits on the parts of triangles that `mask` cuts out do not count, for every
    /// query (closest hits and shadow segments, alone or in packets).
    pub fn set_alpha_mask(&mut self, mask: AlphaMask) {
        self.alpha = Some(Box::new(mask));
    }

    /// Replaces the cut-outs hits are filtered by (`None`: none), as [`Self::set_alpha_mask`].
    pub fn replace_alpha_mask(&mut self, mask: Option<AlphaMask>) {
        self.alpha = mask.map(Box::new);
    }

    /// Whether hits are filtered by cut-outs ([`Self::set_alpha_mask`]).
    pub fn has_alpha_mask(&self) -> bool {
        self.alpha.is_some()
    }

    /// Depth of the deepest inner node (root = 1); trees deeper than
    /// [`wide::FIXED_STACK_DEPTH`] are traversed with a growable stack.
    pub fn depth(&self) -> u32 {
        self.wide.depth()
    }

    /// The traversal stack its depth calls for.
    pub fn stack(&self) -> TraversalStack {
        self.wide.stack()
    }

    /// Closest hit along `origin + t·direction`, 0 < t < t_max (world units; `direction` unit).
    /// Of triangles at exactly the same distance the one with the lowest index wins, so the
    /// answer does not depend on the tree's shape (see [`wide::Nearest`]).
    #[inline]
    pub fn intersect(&self, origin: Vec3, direction: Vec3, t_max: f32) -> Option<Hit> {
        if let Some(mask) = &self.alpha {
            return self.intersect_masked(origin, direction, t_max, mask);
        }
        self.intersect_with(origin, direction, t_max, &Opaque)
    }

    // The masked variants stay out of line: the opaque walk that nearly every scene takes is
    // inlined on its own, and the masked copy does not weigh on its inlining.
    #[inline(never)]
    fn intersect_masked(&self, origin: Vec3, direction: Vec3, t_max: f32, mask: &AlphaMask) -> Option<Hit> {
        self.intersect_with(origin, direction, t_max, mask)
    }

    #[inline(always)]
    fn intersect_with(&self, origin: Vec3, direction: Vec3, t_max: f32, filter: &impl HitFilter) -> Option<Hit> {
        let origin = Vec3A::from(origin * self.scale);
        let direction = without_negative_zeros(direction);
        let ray = WideRay::new(origin, direction, &WatertightRay::new(origin, direction));
        let (quad, hit) = self.wide.closest_hit(&ray, t_max * self.scale, filter)?;
        Some(self.hit(quad, hit))
    }

    /// The closest hits of up to [`PACKET`] rays `(origin, direction, t_max)` at once, into
    /// `hits` (one per ray): one walk of the tree for the packet ([`packet`]). Each ray's hit is
    /// exactly the one [`Self::intersect`] finds. Rays that cannot share a walk (fewer than
    /// `MIN_PACKET`, directions of different signs, a zero direction component, origins far
    /// apart, a tree too deep for the fixed stack) are traced one by one.
    pub fn intersect_packet(&self, rays: &[(Vec3, Vec3, f32)], hits: &mut [Option<Hit>]) {
        if let Some(mask) = &self.alpha {
            return self.intersect_packet_masked(rays, hits, mask);
        }
        self.intersect_packet_with(rays, hits, &Opaque)
    }

    #[inline(never)]
    fn intersect_packet_masked(&self, rays: &[(Vec3, Vec3, f32)], hits: &mut [Option<Hit>], mask: &AlphaMask) {
        self.intersect_packet_with(rays, hits, mask)
    }

    #[inline(always)]
    fn intersect_packet_with(&self, rays: &[(Vec3, Vec3, f32)], hits: &mut [Option<Hit>], filter: &impl HitFilter) {
        assert!(hits.len() == rays.len(), "one hit per ray");
        let traced = self.with_packet(rays, |packet, wide, t_max| {
            let mut best = [None; PACKET];
            packet.closest_hits(&self.wide, t_max, &mut best[..wide.len()], filter);
            for (hit, best) in hits.iter_mut().zip(best) {
                *hit = best.map(|(quad, h)| self.hit(quad, h));
            }
        });
        if traced.is_none() {
            for (&(o, d, t), hit) in rays.iter().zip(hits) {
                *hit = self.intersect_with(o, d, t, filter);
            }
        }
    }

    /// [`Self::any_hit`] of up to [`PACKET`] segments `(origin, direction, t_max)` at once, into
    /// `occluded` (one per ray): one walk for the packet, which ends when every segment is
    /// blocked. The answers are exactly [`Self::any_hit`]'s (occlusion does not depend on the
    /// order leaves are visited in). Rays that cannot share a walk are traced one by one, as for
    /// [`Self::intersect_packet`].
    pub fn any_hit_packet(&self, rays: &[(Vec3, Vec3, f32)], occluded: &mut [bool]) {
        if let Some(mask) = &self.alpha {
            return self.any_hit_packet_masked(rays, occluded, mask);
        }
        self.any_hit_packet_with(rays, occluded, &Opaque)
    }

    #[inline(never)]
    fn any_hit_packet_masked(&self, rays: &[(Vec3, Vec3, f32)], occluded: &mut [bool], mask: &AlphaMask) {
        self.any_hit_packet_with(rays, occluded, mask)
    }

    #[inline(always)]
    fn any_hit_packet_with(&self, rays: &[(Vec3, Vec3, f32)], occluded: &mut [bool], filter: &impl HitFilter) {
        assert!(occluded.len() == rays.len(), "one answer per ray");
        let traced = self.with_packet(rays, |packet, _, t_max| {
            packet.any_hits(&self.wide, t_max, occluded, filter)
        });
        if traced.is_none() {
            for (&(o, d, t), blocked) in rays.iter().zip(occluded) {
                *blocked = self.any_hit_with(o, d, t, filter);
            }
        }
    }

    /// Runs `trace(packet, rays, t_max)` on `rays` prepared as one packet in BVH space (one
    /// prepared ray per ray; `t_max` per ray, then 0 up to [`PACKET`], so that the leaf tests
    /// load it four rays at a time), or returns `None` when they are too few for a
    /// packet walk, cannot share one ([`packet::may_share_walk`], asked before preparing
    /// anything) or the tree is too deep for the packet's fixed stack.
    ///
    /// The prepared rays (~3 KB for a full packet) are written in place, in this frame: built as
    /// a value and returned, they would be copied (`memmove`) once more for every packet.
    #[inline(always)]
    fn with_packet<R>(
        &self,
        rays: &[(Vec3, Vec3, f32)],
        trace: impl FnOnce(&RayPacket, &[WideRay], &mut [f32; PACKET]) -> R,
    ) -> Option<R> {
        let n = rays.len();
        assert!(n <= PACKET, "a packet holds at most {PACKET} rays");
        if n < MIN_PACKET || self.wide.stack() != TraversalStack::Fixed {
            return None;
        }
        // Origins, directions and 1/d in BVH space; past the rays, copies of the last one.
        let mut origin = [Vec3A::ZERO; PACKET];
        let mut direction = [Vec3A::ZERO; PACKET];
        let mut inv_dir = [Vec3A::ZERO; PACKET];
        for k in 0..PACKET {
            let ray = &rays[k.min(n - 1)];
            origin[k] = Vec3A::from(ray.0 * self.scale);
            direction[k] = without_negative_zeros(ray.1);
            inv_dir[k] = direction[k].recip();
        }
        if !packet::may_share_walk(origin[..n].iter().copied().zip(inv_dir[..n].iter().copied())) {
            return None;
        }
        let mut wide = [const { MaybeUninit::<WideRay>::uninit() }; PACKET];
        let mut t_max = [0.0f32; PACKET];
        for k in 0..n {
            let (o, d) = (origin[k], direction[k]);
            wide[k].write(WideRay::new(o, d, &WatertightRay::new(o, d)));
            t_max[k] = rays[k].2 * self.scale;
        }
        // SAFETY: entries 0..n were written just above, and `MaybeUninit<WideRay>` has the
        // layout of `WideRay`.
        let wide = unsafe { std::slice::from_raw_parts(wide.as_ptr().cast::<WideRay>(), n) };
        Some(trace(&RayPacket::new(wide, &origin, &inv_dir), wide, &mut t_max))
    }

    /// The [`Hit`] of lane `hit.lane` of quad `quad`, in world units.
    #[inline]
    fn hit(&self, quad: u32, hit: QuadHit) -> Hit {
        Hit {
            triangle: self.wide.primitive(quad, hit.lane),
            t: hit.t / self.scale,
            b1: hit.b1,
            b2: hit.b2,
        }
    }

    /// True if anything lies along `origin + t·direction` for 0 < t < t_max (stops at the first hit).
    #[inline]
    pub fn any_hit(&self, origin: Vec3, direction: Vec3, t_max: f32) -> bool {
        if let Some(mask) = &self.alpha {
            return self.any_hit_masked(origin, direction, t_max, mask);
        }
        self.any_hit_with(origin, direction, t_max, &Opaque)
    }

    #[inline(never)]
    fn any_hit_masked(&self, origin: Vec3, direction: Vec3, t_max: f32, mask: &AlphaMask) -> bool {
        self.any_hit_with(origin, direction, t_max, mask)
    }

    #[inline(always)]
    fn any_hit_with(&self, origin: Vec3, direction: Vec3, t_max: f32, filter: &impl HitFilter) -> bool {
        let origin = Vec3A::from(origin * self.scale);
        let direction = without_negative_zeros(direction);
        let shear = WatertightRay::new(origin, direction);
        self.wide
            .any_hit(&WideRay::new(origin, direction, &shear), t_max * self.scale, filter)
    }

    /// World length of one BVH-space unit (about the scene's size / 200): the unit the
    /// shadow-ray offset is measured in.
    pub fn scene_unit(&self) -> f32 {
        1.0 / self.scale
    }

    /// The bounding box `(min, max)` in world space of the mesh it was built over.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        self.bounds
    }

    /// Number of 4-wide nodes.
    pub fn node_count(&self) -> usize {
        self.wide.node_count()
    }
}

impl Occluder for Bvh {
    #[inline]
    fn occluded(&self, ray: &ShadowRay) -> bool {
        self.any_hit(ray.origin, ray.direction, ray.t_max)
    }

    /// Always inlined into the lane shader: left to the compiler, it became a call once the
    /// shader grew.
    #[inline(always)]
    fn occluded_batch(&self, rays: &[ShadowRay], occluded: &mut [bool]) {
        for (rays, occluded) in rays.chunks(PACKET).zip(occluded.chunks_mut(PACKET)) {
            let segments: [(Vec3, Vec3, f32); PACKET] = std::array::from_fn(|k| {
                let r = rays[k.min(rays.len() - 1)];
                (r.origin, r.direction, r.t_max)
            });
            self.any_hit_packet(&segments[..rays.len()], occluded);
        }
    }
}

/// `direction` with every −0.0 component turned into +0.0 (x + 0.0 does exactly that and leaves
/// every other value unchanged).
///
/// Traversal decides a slab's near plane from a sign and intersects it with 1/d; for −0.0 the two
/// must agree, and with +0.0 they do by construction: a sign taken from `d < 0` beside a division
/// by −0.0 would put the near plane on the far side and cull whole subtrees (the test
/// `directions_with_negative_zero_components_find_their_hits` holds the walk to it).
#[inline(always)]
fn without_negative_zeros(direction: Vec3) -> Vec3A {
    Vec3A::from(direction) + Vec3A::ZERO
}

/// Fewest rays worth a packet walk. The interval box test costs about two single-ray tests, and
/// every ray is tried at every leaf the packet reaches, so too few rays lose to single walks.
/// With each ray's own leaf box test, `t_max` loaded four at a time and origins and 1/d
/// computed once, packets pay from a pixel's 4 samples on (the sweep of this threshold:
/// docs/performance-log.md). Images do not depend on it: packets answer exactly as single rays.
const MIN_PACKET: usize = 4;

#[cfg(test)]
mod tests;
