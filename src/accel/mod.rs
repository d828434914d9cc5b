//! Acceleration: a BVH over the scene's triangles — built by obvhs, traversed by pointshade as a
//! 4-wide SIMD tree ([`wide`]) with a watertight ray/triangle test ([`triangle`]).
//!
//! Choices that shape this module:
//! - **Power-of-two rescaling.** The BVH lives in "BVH space" = world × 2^e, with e chosen so the
//!   scene's bounding-box diagonal is about 256, so the leaf-box padding and every absolute
//!   tolerance mean the same at any scene scale. Multiplying by a power of two is exact in
//!   floating point; distances come back divided by the same factor.
//! - **Leaf-ordered triangles.** Triangle vertices are copied into the leaves' SIMD quads in
//!   traversal order, so traversal reads memory linearly and needs no index indirection.
//! - **Bounded depth.** Where PLOC degenerates (boxes that all overlap, as a fan's do) the tree is
//!   built balanced instead ([`balanced`]), so no input makes it deep or slow; trees deeper than
//!   the fixed stack are traversed with a growable one ([`TraversalStack`]); padded leaf boxes
//!   keep rays through shared vertices.

pub mod alpha;
pub mod balanced;
mod bvh_space;
pub mod packet;
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

/// The obvhs build presets, from fastest build to best traversal.
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
}

impl BvhPreset {
    /// Every preset, for benchmarks.
    pub const ALL: [BvhPreset; 4] = [Self::Fastest, Self::Fast, Self::Medium, Self::Slow];

    /// The preset renders use: chosen with `cargo bench --bench rays` (see README, Benchmarks).
    pub const DEFAULT: BvhPreset = BvhPreset::Fast;

    fn params(self) -> BvhBuildParams {
        match self {
            Self::Fastest => BvhBuildParams::fastest_build(),
            Self::Fast => BvhBuildParams::fast_build(),
            Self::Medium => BvhBuildParams::medium_build(),
            Self::Slow => BvhBuildParams::slow_build(),
        }
    }

    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Fastest => "fastest",
            Self::Fast => "fast",
            Self::Medium => "medium",
            Self::Slow => "slow",
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
        let boxes: Vec<_> = triangles.par_iter().map(padded_box).collect();
        let params = BvhBuildParams {
            max_prims_per_leaf: 4,
            ..preset.params()
        };
        // PLOC, unless the boxes overlap so that it would take quadratic time; its tree rebuilt
        // balanced if it came out too deep all the same ([`balanced`]).
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
        let mut wide = WideBvh::from_bvh2(&bvh2, &triangles);
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
/// must agree, and with +0.0 they do by construction. (obvhs's CWBVH traversal, used before,
/// took the sign from `d < 0` but divided by −0.0, and culled whole subtrees: Mitsuba validation
/// caught shadows missing under a directional light of direction (0, −1, −1). The regression
/// test stays.)
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
mod tests {
    use super::*;

    /// `n` triangles of radius `radius` around `offset`, as an OBJ polygon of n + 1 vertices
    /// triangulates.
    fn fan(n: usize, offset: Vec3, radius: f32) -> TriangleMesh {
        let mut positions = vec![offset];
        positions.extend((0..=n).map(|k| {
            let a = std::f32::consts::PI * k as f32 / n as f32;
            offset + radius * Vec3::new(a.cos(), a.sin(), 0.0)
        }));
        TriangleMesh {
            normals: vec![Vec3::Z; positions.len()],
            positions,
            triangles: (0..n as u32).map(|k| [0, k + 1, k + 2]).collect(),
            material_of_triangle: vec![0; n],
            ..Default::default()
        }
    }

    #[test]
    fn fans_build_balanced_trees_and_are_hit_where_they_are() {
        // PLOC built a chain about 600 levels deep for 30,000 triangles, in time quadratic in
        // their count, and its collapse overflowed the stack.
        // The radius 5.7e27 is the geometry fuzz target's finding (fuzz/README.md): the f32
        // diagonal overflowed, the scene stayed at scale 1 with boxes of infinite area, and the
        // window test could not see the fan.
        for (offset, radius) in [
            (Vec3::ZERO, 1.0),
            (Vec3::new(9.2e18, 0.0, 0.0), 1.0),
            (Vec3::ZERO, 5.7e27),
        ] {
            let mesh = fan(30_000, offset, radius);
            let bvh = Bvh::build(&mesh, BvhPreset::DEFAULT);
            let depth = bvh.depth();
            assert!(depth <= 12, "depth {depth} at offset {offset}, radius {radius:e}");
            if offset == Vec3::ZERO && radius == 1.0 {
                let hit = bvh.intersect(Vec3::new(0.3, 0.4, 1.0), Vec3::NEG_Z, f32::INFINITY);
                assert!(hit.is_some_and(|h| (h.t - 1.0).abs() < 1e-5), "{hit:?}");
            }
        }
    }

    #[test]
    fn a_fan_of_subnormal_size_builds() {
        // The geometry fuzz target's third finding: a scale of 2^133 was infinite, and obvhs's
        // PLOC indexed with −1 on the boxes it made.
        let bvh = Bvh::build(&fan(160, Vec3::ZERO, 1.1755033e-38), BvhPreset::DEFAULT);
        assert!(bvh.depth() <= 64 && bvh.scene_unit().is_finite());
    }

    fn quad(y: f32, half: f32, offset: Vec3) -> TriangleMesh {
        let p = [
            Vec3::new(-half, y, -half),
            Vec3::new(half, y, -half),
            Vec3::new(half, y, half),
            Vec3::new(-half, y, half),
        ]
        .map(|v| v + offset);
        TriangleMesh {
            positions: p.to_vec(),
            normals: vec![Vec3::Y; 4],
            triangles: vec![[0, 2, 1], [0, 3, 2]],
            material_of_triangle: vec![0, 0],
            ..Default::default()
        }
    }

    #[test]
    fn triangles_without_area_are_left_out_unless_nothing_else_is_left() {
        let stored = |bvh: &Bvh| {
            let mut p: Vec<u32> = bvh
                .wide
                .quad_triangles
                .iter()
                .flatten()
                .copied()
                .filter(|&p| p != wide::EMPTY)
                .collect();
            p.sort_unstable();
            p
        };
        // Triangle 1 repeats a vertex and triangle 3 has collinear vertices.
        let mut mesh = quad(0.0, 1.0, Vec3::ZERO);
        mesh.positions.push(Vec3::new(3.0, 0.0, -1.0)); // on the line through vertices 0 and 1
        mesh.triangles = vec![[0, 2, 1], [0, 0, 2], [0, 3, 2], [0, 1, 4]];
        mesh.material_of_triangle = vec![0; 4];
        let bvh = Bvh::build(&mesh, BvhPreset::DEFAULT);
        assert_eq!(stored(&bvh), [0, 2]);
        // The degenerate ones alone: kept, so that the tree is not empty.
        mesh.triangles = vec![[0, 0, 2], [0, 1, 4]];
        mesh.material_of_triangle = vec![0; 2];
        assert_eq!(stored(&Bvh::build(&mesh, BvhPreset::DEFAULT)), [0, 1]);
    }

    #[test]
    fn closest_hit_and_occlusion_at_any_scale_and_offset() {
        for &(size, offset) in &[(1.0f32, 0.0f32), (1e-6, 0.0), (1e6, 0.0), (1.0, 1e5)] {
            let off = Vec3::splat(offset);
            let mut mesh = quad(0.0, size, off);
            mesh.append(quad(size, size, off), 0);
            let bvh = Bvh::build(&mesh, BvhPreset::DEFAULT);
            let from = off + Vec3::new(0.1, 3.0, 0.2) * size;
            let hit = bvh.intersect(from, Vec3::NEG_Y, f32::INFINITY).expect("hit");
            assert!(hit.triangle >= 2, "upper quad first (size {size})");
            assert!(
                (hit.t - 2.0 * size).abs() <= 1e-4 * size + offset * 1e-6,
                "t {} size {size}",
                hit.t
            );
            assert!(bvh.any_hit(from, Vec3::NEG_Y, 10.0 * size));
            assert!(!bvh.any_hit(from, Vec3::NEG_Y, 1.5 * size), "t_max respected");
            assert!(!bvh.any_hit(from, Vec3::Y, f32::INFINITY));
        }
    }

    #[test]
    fn point_under_a_plane_is_in_shadow_and_a_point_on_it_is_not() {
        for &offset in &[0.0f32, 1e5] {
            let off = Vec3::splat(offset);
            let bvh = Bvh::build(&quad(0.0, 4.0, off), BvhPreset::DEFAULT);
            let light = off + Vec3::new(0.3, 5.0, -0.2);
            let unit = bvh.scene_unit();
            let ray_to_light = |p: Vec3, ng: Vec3| {
                let to = light - p;
                ShadowRay::towards_light(p, ng, to.normalize(), to.length(), unit)
            };
            // Under the plane: occluded, down to depths of 1e-3 of the plane's size or 16 ulps of
            // the coordinates (0.125 at 1e5), whichever is larger; closer than that a point cannot
            // be told from one on the plane in f32.
            let ulp16 = 16.0 * (offset.max(1.0) * f32::EPSILON);
            for depth in [1.0f32, 1e-1, 1e-2, 1e-3].into_iter().filter(|&d| d >= ulp16) {
                let under = off + Vec3::new(-0.4, -depth, 0.7);
                assert!(
                    bvh.occluded(&ray_to_light(under, Vec3::NEG_Y)),
                    "offset {offset}, {depth} below"
                );
            }
            // On the plane, computed from barycentrics as the renderer does: lit, everywhere.
            let mesh = quad(0.0, 4.0, off);
            for k in 0..100 {
                let (b1, b2) = ((k % 10) as f32 / 10.0 * 0.9, (k / 10) as f32 / 10.0 * 0.09);
                let [p0, p1, p2] = mesh.triangle_positions(k % 2);
                let on = (1.0 - b1 - b2) * p0 + b1 * p1 + b2 * p2;
                assert!(
                    !bvh.occluded(&ray_to_light(on, Vec3::Y)),
                    "offset {offset}: acne at {on}"
                );
            }
        }
    }

    #[test]
    fn directions_with_negative_zero_components_find_their_hits() {
        // A quad in the plane z = 2, off the axis so the ray starts beside it in x; directions
        // with −0.0 components (e.g. the negation of a light's direction) must hit as +0.0 does.
        let mut mesh = quad(0.0, 1.0, Vec3::ZERO);
        mesh.transform(glam::Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2));
        mesh.append(quad(-3.0, 5.0, Vec3::ZERO), 0); // a large floor so the BVH has several nodes
        let bvh = Bvh::build(&mesh, BvhPreset::DEFAULT);
        for d in [
            Vec3::new(-0.0, -0.0, 1.0),
            Vec3::new(-0.0, 0.0, -1.0),
            Vec3::new(0.3, -0.0, 0.9).normalize(),
        ] {
            let from = Vec3::new(0.2, 0.1, 0.0) - d * 5.0;
            let plus = Vec3::new(d.x + 0.0, d.y + 0.0, d.z + 0.0);
            assert_eq!(bvh.intersect(from, d, 100.0), bvh.intersect(from, plus, 100.0), "{d:?}");
            assert!(bvh.any_hit(from, d, 100.0), "{d:?}");
        }
    }

    /// The torus with every triangle listed twice (the copies, at index + n, coincide exactly).
    fn doubled_torus() -> (TriangleMesh, u32) {
        let mut mesh = crate::scene::procedural::torus(1.0, 0.35, 64, 24).into_triangle_mesh();
        let n = mesh.triangle_count();
        mesh.append(mesh.clone(), 0);
        (mesh, n as u32)
    }

    #[test]
    fn coincident_triangles_resolve_to_the_lower_index_in_every_tree_and_packet() {
        let (mesh, n) = doubled_torus();
        let trees: Vec<Bvh> = BvhPreset::ALL.iter().map(|&p| Bvh::build(&mesh, p)).collect();
        let (lo, hi) = mesh.bounds().unwrap();
        let camera = crate::scene::camera::Camera::new(crate::scene::framing::frame_bounds(lo, hi), 64, 64).unwrap();
        let bits = |h: Option<Hit>| h.map(|h| (h.triangle, [h.t, h.b1, h.b2].map(f32::to_bits)));
        let mut hits = 0;
        for py in 0..64 {
            // A row of 16 pixels at a time: packets of rays of neighbouring pixels.
            for px0 in (0..64).step_by(PACKET) {
                let rays: Vec<(Vec3, Vec3, f32)> = (px0..px0 + PACKET as u32)
                    .map(|px| {
                        let r = camera.ray((px as f32 + 0.5) / 64.0, (py as f32 + 0.5) / 64.0);
                        (r.origin, r.direction, r.t_max)
                    })
                    .collect();
                for (k, &(o, d, t)) in rays.iter().enumerate() {
                    let want = trees[0].intersect(o, d, t);
                    if let Some(h) = want {
                        assert!(
                            h.triangle < n,
                            "pixel ({}, {py}): the copy {} won",
                            px0 + k as u32,
                            h.triangle
                        );
                        hits += 1;
                    }
                    for (tree, preset) in trees.iter().zip(BvhPreset::ALL) {
                        assert_eq!(bits(tree.intersect(o, d, t)), bits(want), "{preset:?}");
                    }
                }
                for (tree, preset) in trees.iter().zip(BvhPreset::ALL) {
                    let mut got = [None; PACKET];
                    tree.intersect_packet(&rays, &mut got);
                    for (&(o, d, t), got) in rays.iter().zip(got) {
                        assert_eq!(bits(got), bits(trees[0].intersect(o, d, t)), "{preset:?} packet");
                    }
                }
            }
        }
        assert!(hits > 500, "the torus should fill part of the frame: {hits} hits");
    }

    #[test]
    fn scale_is_a_power_of_two() {
        let s = world_to_bvh_scale(quad(0.0, 3.7e-5, Vec3::ZERO).bounds());
        assert_eq!(s.log2().fract(), 0.0);
        assert!(s > 1.0);
    }
}
