//! CWBVH traversal that cannot lose nodes, for BVHs deeper than obvhs's fixed stack allows.
//!
//! obvhs 0.4 traverses a CWBVH with a `StackStack<UVec2, 32>` (`cwbvh/mod.rs`,
//! `TRAVERSAL_STACK_SIZE`). Its `push` (`faststack.rs`) writes at the current index and then
//! clamps the index to 31, so once 31 node groups are pending every further push overwrites the
//! top entry: those subtrees are never visited and rays pass through their triangles, silently.
//! (obvhs only checks the depth in `CwBvh::validate`, which its builder runs in debug builds.)
//!
//! When is that reachable? The `traverse!` loop pushes the rest of a group of intersected inner
//! children when it descends into one of them, and pops a group before taking from it, so the
//! stack holds at most one group per level between the root and the node being entered: at most
//! D groups, D being the largest depth of an inner node (root = 0). A BVH with D ≤ 31 can
//! therefore never overflow ([`max_inner_depth`]). Ordinary meshes are far from that (`pointshade
//! stability` prints the depth of the sphere, torus and dragon BVHs), but geometry spread over
//! many orders of magnitude makes PLOC chain its merges: 123 triangles at positions 2^−k gave
//! D = 37 with the default preset. [`Bvh::build`] measures D and uses
//! [`TraversalStack::Growable`] — obvhs's own `traverse!` loop, driven with a `Vec` stack — for
//! those BVHs only. (D > 31 is necessary for an overflow, not sufficient: a group is pushed only
//! where two or more intersected inner children remain, so the chains found so far use about 12
//! entries. The fallback costs nothing on ordinary BVHs, so the bound is used as is.)
//!
//! In debug builds obvhs's builder validates the BVH and asserts D < 32 itself, so deep BVHs
//! panic there before traversal; release builds, which pointshade is run and tested with, do not.
//!
//! [`Bvh::build`]: super::Bvh::build

use glam::{UVec2, Vec3A};
use obvhs::cwbvh::CwBvh;
use obvhs::ray::{Ray, RayHit};

/// Deepest inner-node depth (root = 0) that obvhs's 32-entry stack is proven to handle.
pub const FIXED_STACK_MAX_DEPTH: u32 = 31;

/// Which stack a [`super::Bvh`] traverses with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TraversalStack {
    /// obvhs's `ray_traverse` with its fixed 32-entry stack (every BVH of depth ≤ 31).
    Fixed,
    /// The same loop with a growable stack (deeper BVHs).
    Growable,
}

/// The largest depth of an inner node below the root (root = 0), computed without recursion.
pub fn max_inner_depth(cwbvh: &CwBvh) -> u32 {
    if cwbvh.nodes.is_empty() {
        return 0;
    }
    let mut deepest = 0;
    let mut pending = vec![(0usize, 0u32)];
    while let Some((index, depth)) = pending.pop() {
        deepest = deepest.max(depth);
        let node = &cwbvh.nodes[index];
        for child in 0..8 {
            if !node.is_child_empty(child) && !node.is_leaf(child) {
                pending.push((node.child_node_index(child) as usize, depth + 1));
            }
        }
    }
    deepest
}

/// The stack a BVH of this inner depth needs.
pub fn stack_for_depth(depth: u32) -> TraversalStack {
    if depth <= FIXED_STACK_MAX_DEPTH {
        TraversalStack::Fixed
    } else {
        TraversalStack::Growable
    }
}

/// The field names obvhs's `traverse!` macro reads and writes, with a `Vec` as the stack.
struct GrowableState {
    stack: Vec<UVec2>,
    current_group: UVec2,
    primitive_group: UVec2,
    oct_inv4: u32,
    primitive_id: u32,
    hitmask: u32,
}

impl GrowableState {
    fn new(cwbvh: &CwBvh, direction: Vec3A) -> Self {
        Self {
            stack: Vec::with_capacity(64),
            // The root is the only member of the first group (bit 31 of the inner-node mask).
            current_group: if cwbvh.nodes.is_empty() {
                UVec2::ZERO
            } else {
                UVec2::new(0, 0x8000_0000)
            },
            primitive_group: UVec2::ZERO,
            oct_inv4: octant_inv4(direction),
            primitive_id: 0,
            hitmask: 0,
        }
    }
}

/// The ray octant in the byte-replicated, inverted form CWBVH nodes order their children by:
/// per byte, bit 2/1/0 set when the x/y/z component is non-negative.
fn octant_inv4(d: Vec3A) -> u32 {
    (if d.x < 0.0 { 0 } else { 0x0404_0404 })
        | (if d.y < 0.0 { 0 } else { 0x0202_0202 })
        | (if d.z < 0.0 { 0 } else { 0x0101_0101 })
}

/// Closest hit, as `CwBvh::ray_traverse`: `intersect(ray, primitive)` returns the hit distance or
/// infinity; the ray's t_max shrinks to each closer hit. Returns whether anything was hit.
pub fn closest_hit<F: FnMut(&Ray, usize) -> f32>(cwbvh: &CwBvh, ray: Ray, hit: &mut RayHit, mut intersect: F) -> bool {
    let mut traverse_ray = ray;
    let mut state = GrowableState::new(cwbvh, ray.direction);
    let mut node;
    obvhs::traverse!(cwbvh, node, state, node.intersect_ray(&traverse_ray, state.oct_inv4), {
        let t = intersect(&traverse_ray, state.primitive_id as usize);
        if t < traverse_ray.tmax {
            hit.primitive_id = state.primitive_id;
            hit.t = t;
            traverse_ray.tmax = t;
        }
    });
    hit.t < ray.tmax
}

/// True if any primitive is hit within the ray's interval, as `!CwBvh::ray_traverse_miss`.
pub fn any_hit<F: FnMut(&Ray, usize) -> f32>(cwbvh: &CwBvh, ray: Ray, mut intersect: F) -> bool {
    let mut state = GrowableState::new(cwbvh, ray.direction);
    let mut node;
    let mut found = false;
    'traversal: {
        obvhs::traverse!(cwbvh, node, state, node.intersect_ray(&ray, state.oct_inv4), {
            if intersect(&ray, state.primitive_id as usize) < ray.tmax {
                found = true;
                break 'traversal;
            }
        });
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::triangle::WatertightRay;
    use crate::accel::{Bvh, BvhPreset};
    use crate::scene::mesh::TriangleMesh;
    use obvhs::faststack::{FastStack, StackStack};

    #[test]
    fn obvhs_fixed_stack_loses_entries_beyond_31() {
        // The premise of this module: the 32nd pending group overwrites the 31st... slot.
        let mut stack = StackStack::<UVec2, 32>::default();
        for k in 0..33 {
            stack.push(UVec2::new(k, 0));
        }
        let mut popped = Vec::new();
        while let Some(v) = stack.pop() {
            popped.push(v.x);
        }
        assert_eq!(popped.len(), 31, "pushes past 31 are not kept");
        assert_eq!(popped[0], 30, "entries 31 and 32 were overwritten and lost");
        // Up to 31 pending entries survive intact.
        let mut stack = StackStack::<UVec2, 32>::default();
        (0..31).for_each(|k| stack.push(UVec2::new(k, 0)));
        assert_eq!(
            (0..31).map(|_| stack.pop_fast().x).collect::<Vec<_>>(),
            (0..31).rev().collect::<Vec<_>>()
        );
    }

    /// The adversarial chain the stability report uses: 600 levels give depth 75.
    fn nested_levels(levels: usize) -> TriangleMesh {
        crate::reports::stability::geometry_cases::nested_chain(levels)
    }

    /// Every triangle the ray crosses, by traversal (`growable` or obvhs's fixed stack) and by
    /// testing each triangle, in BVH space.
    fn all_hits(bvh: &Bvh, origin: Vec3A, d: Vec3A, stack: TraversalStack) -> (usize, usize) {
        let shear = WatertightRay::new(origin, d);
        let ray = Ray::new(origin, d, 0.0, f32::INFINITY);
        let mut count = 0;
        let mut hit = RayHit::none();
        let test = |_: &Ray, leaf: usize| {
            count += shear.intersect(&bvh.leaf_triangles[leaf], f32::INFINITY).is_some() as usize;
            f32::INFINITY // never shrink the ray: visit everything it crosses
        };
        match stack {
            TraversalStack::Fixed => bvh.cwbvh.ray_traverse(ray, &mut hit, test),
            TraversalStack::Growable => closest_hit(&bvh.cwbvh, ray, &mut hit, test),
        };
        let brute = bvh
            .leaf_triangles
            .iter()
            .filter(|t| shear.intersect(t, f32::INFINITY).is_some())
            .count();
        (count, brute)
    }

    #[test]
    #[cfg_attr(debug_assertions, ignore = "obvhs's builder asserts depth < 32 in debug builds")]
    fn deep_bvh_is_detected_and_its_growable_traversal_finds_every_crossing() {
        let mesh = nested_levels(600);
        let bvh = Bvh::build(&mesh, BvhPreset::DEFAULT);
        assert!(
            bvh.depth() > FIXED_STACK_MAX_DEPTH,
            "depth {} is too shallow to test",
            bvh.depth()
        );
        assert_eq!(bvh.stack(), TraversalStack::Growable);
        let centre = Vec3A::splat(0.5) * bvh.scale;
        for d in [Vec3A::ONE, Vec3A::new(0.3, -0.2, -1.0), Vec3A::new(-1.0, 0.9, 0.8)] {
            let d = d.normalize();
            let (found, brute) = all_hits(&bvh, centre - d * 300.0, d, TraversalStack::Growable);
            assert!(brute > 10, "the ray crosses {brute} triangles");
            assert_eq!(found, brute, "direction {d}");
            // Closest hit and any-hit through the public interface agree with it.
            let o = (centre - d * 300.0) / bvh.scale;
            assert!(bvh.intersect(o.into(), d.into(), f32::INFINITY).is_some());
            assert!(bvh.any_hit(o.into(), d.into(), f32::INFINITY));
        }
    }

    #[test]
    fn both_stacks_find_the_same_crossings_on_shallow_bvhs() {
        let mesh = nested_levels(6);
        let bvh = Bvh::build(&mesh, BvhPreset::DEFAULT);
        assert_eq!(bvh.stack(), TraversalStack::Fixed);
        let centre = Vec3A::splat(0.5) * bvh.scale;
        for d in [Vec3A::ONE, Vec3A::new(0.3, -0.2, -1.0)] {
            let d = d.normalize();
            let fixed = all_hits(&bvh, centre - d * 300.0, d, TraversalStack::Fixed);
            let growable = all_hits(&bvh, centre - d * 300.0, d, TraversalStack::Growable);
            assert_eq!(fixed, growable);
            assert_eq!(fixed.0, fixed.1);
        }
        let sphere = crate::scene::procedural::icosphere(5);
        let sphere_mesh = TriangleMesh {
            normals: sphere.positions.clone(),
            material_of_triangle: vec![0; sphere.triangles.len()],
            positions: sphere.positions,
            triangles: sphere.triangles,
            ..Default::default()
        };
        assert!(Bvh::build(&sphere_mesh, BvhPreset::DEFAULT).depth() <= FIXED_STACK_MAX_DEPTH);
    }
}
