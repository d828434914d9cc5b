//! Walking the 4-wide tree: the two traversal loops, written once for one ray and for a packet.
//!
//! What tests a node's boxes is a [`NodeTest`] — a single ray ([`super::wide::WideRay`]) or a
//! packet with interval bounds ([`super::packet::RayPacket`]); what happens at a leaf is the
//! caller's closure. Two orders:
//! - [`WideBvh::walk_nearest_first`] (closest hits): children in order of entry distance, and
//!   nodes entered beyond the current `t_max` skipped, so hits found early prune the rest;
//! - [`WideBvh::walk_until`] (any hit): children in slot order, no distances kept, and the walk
//!   stops as soon as the leaf closure says so. Order cannot change an any-hit answer.
//!
//! The stack holds (child value, entry distance) pairs. A node pushes at most three children
//! besides the one it descends into, so a tree of depth D needs at most 3·D + 1 entries: a fixed
//! array serves every tree up to [`FIXED_STACK_DEPTH`](super::wide::FIXED_STACK_DEPTH) levels, a
//! growable one the (rare, pathological) deeper trees — nothing is ever dropped.

use std::mem::MaybeUninit;

use glam::Vec4;

use super::alpha::HitFilter;
use super::wide::{Nearest, Node4, QuadHit, TraversalStack, WideBvh, WideRay, EMPTY, FIXED_STACK_DEPTH, LEAF};

/// Entries of the fixed stack: 3·21 + 1 = 64.
const FIXED_STACK: usize = 64;
// The deepest tree served needs 3·depth + 1 entries.
const _: () = assert!((3 * FIXED_STACK_DEPTH as usize) < FIXED_STACK);

/// Tests a node's four child boxes: one ray, or a packet of rays.
pub(super) trait NodeTest {
    /// Which of the node's four boxes (bit k = child k) the segment [0, `t_max`] may enter,
    /// and a lower bound of where (per lane).
    fn boxes(&self, node: &Node4, t_max: f32) -> (u32, Vec4);
}

/// A traversal stack of (child value, entry distance) pairs.
pub(super) trait Stack {
    fn push(&mut self, entry: (u32, f32));
    fn pop(&mut self) -> Option<(u32, f32)>;
}

/// A 64-entry stack (512 bytes) that is not zeroed per ray: zeroing it per ray was a visible
/// cost (docs/performance-log.md).
pub(super) struct FixedStack {
    entries: [MaybeUninit<(u32, f32)>; FIXED_STACK],
    len: usize,
}

impl FixedStack {
    #[inline(always)]
    pub(super) fn new() -> Self {
        Self {
            entries: [const { MaybeUninit::uninit() }; FIXED_STACK],
            len: 0,
        }
    }
}

impl Stack for FixedStack {
    #[inline(always)]
    fn push(&mut self, entry: (u32, f32)) {
        // Capacity 64 ≥ 3·depth + 1 for every tree this stack is used with ([`WideBvh::stack`]);
        // indexing is still bounds-checked, so a wrong bound panics instead of corrupting.
        self.entries[self.len].write(entry);
        self.len += 1;
    }
    #[inline(always)]
    fn pop(&mut self) -> Option<(u32, f32)> {
        self.len = self.len.checked_sub(1)?;
        // SAFETY: every index below `len` was written by `push` before `len` passed it.
        Some(unsafe { self.entries[self.len].assume_init() })
    }
}

impl Stack for Vec<(u32, f32)> {
    #[inline(always)]
    fn push(&mut self, entry: (u32, f32)) {
        Vec::push(self, entry);
    }
    #[inline(always)]
    fn pop(&mut self) -> Option<(u32, f32)> {
        Vec::pop(self)
    }
}

impl WideBvh {
    /// Calls `leaf(quad, t_max)` on every leaf whose box `test` enters at or before `t_max`,
    /// nearest child first; `leaf` returns the new `t_max` (smaller once it found a hit), and
    /// whatever is entered beyond it is skipped.
    #[inline(always)]
    pub(super) fn walk_nearest_first(
        &self,
        test: &impl NodeTest,
        t_max: f32,
        stack: &mut impl Stack,
        mut leaf: impl FnMut(u32, f32) -> f32,
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let mut t_max = t_max;
        let mut current = (0u32, 0.0f32);
        loop {
            let (child, t_enter) = current;
            // `<=`: a triangle at exactly `t_max` may still win a tie (see `Nearest`).
            if t_enter <= t_max {
                if child & LEAF != 0 {
                    t_max = leaf(child & !LEAF, t_max);
                } else {
                    let node = &self.nodes[child as usize];
                    let (mask, t_near) = test.boxes(node, t_max);
                    if mask != 0 {
                        current = descend_nearest(node, mask, t_near, stack);
                        continue;
                    }
                }
            }
            match stack.pop() {
                Some(next) => current = next,
                None => return,
            }
        }
    }

    /// Calls `leaf(quad, t_max)` on the leaves whose boxes `test` enters within [0, `t_max`],
    /// in no particular order, until `leaf` returns `None` (done: the walk returns true);
    /// `Some(t)` continues with `t_max = t`. False: every such leaf was visited.
    #[inline(always)]
    pub(super) fn walk_until(
        &self,
        test: &impl NodeTest,
        t_max: f32,
        stack: &mut impl Stack,
        mut leaf: impl FnMut(u32, f32) -> Option<f32>,
    ) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        let mut t_max = t_max;
        let mut current = 0u32;
        loop {
            if current & LEAF != 0 {
                match leaf(current & !LEAF, t_max) {
                    Some(t) => t_max = t,
                    None => return true,
                }
            } else {
                let node = &self.nodes[current as usize];
                let (mask, _) = test.boxes(node, t_max);
                for k in (0..4).filter(|&k| mask & (1 << k) != 0) {
                    stack.push((node.child[k], 0.0));
                }
            }
            match stack.pop() {
                Some((next, _)) => current = next,
                None => return false,
            }
        }
    }
}

/// The child of `node` (among those in `mask`, entered at `t_near`) to visit next — the nearest —
/// after pushing the others onto `stack`, farthest first. An insertion sort: on coherent rays
/// its branches predict well (docs/performance-log.md compares branch-free orderings).
#[inline(always)]
fn descend_nearest(node: &Node4, mask: u32, t_near: Vec4, stack: &mut impl Stack) -> (u32, f32) {
    let t = t_near.to_array();
    let mut order = [(f32::INFINITY, EMPTY); 4];
    let mut n = 0;
    for k in (0..4).filter(|&k| mask & (1 << k) != 0) {
        let mut i = n;
        while i > 0 && order[i - 1].0 < t[k] {
            order[i] = order[i - 1];
            i -= 1;
        }
        order[i] = (t[k], node.child[k]);
        n += 1;
    }
    for &(t, c) in &order[..n - 1] {
        stack.push((c, t));
    }
    (order[n - 1].1, order[n - 1].0)
}
impl NodeTest for WideRay {
    /// Which of the node's four boxes the segment [0, t_max] enters, and where.
    ///
    /// NaN-safe: a zero direction component gives ±∞ in `inv_dir`, and an origin exactly on that
    /// slab's plane gives 0·∞ = NaN. `max`/`min` are applied with the per-axis value as the first
    /// operand, which SSE (and glam's scalar fallback) answer with the other operand when it is
    /// NaN: that axis then does not restrict the interval — right, since the ray runs inside
    /// the (closed) slab.
    #[inline(always)]
    fn boxes(&self, node: &Node4, t_max: f32) -> (u32, Vec4) {
        let mut t_near = Vec4::ZERO;
        let mut t_far = Vec4::splat(t_max);
        for axis in 0..3 {
            let near = (node.bounds[axis][self.near[axis]] - self.origin[axis]) * self.inv_dir[axis];
            let far = (node.bounds[axis][1 - self.near[axis]] - self.origin[axis]) * self.inv_dir[axis];
            t_near = near.max(t_near);
            t_far = far.min(t_far);
        }
        (t_near.cmple(t_far).bitmask(), t_near)
    }
}

/// Single-ray queries: the traversal loops with [`WideRay`] as the node test and the quads'
/// intersection at the leaves.
impl WideBvh {
    /// The closest hit with 0 < t < `t_max` in [`Nearest`]'s order that `filter` keeps:
    /// (quad, lane, t).
    #[inline(always)]
    pub fn closest_hit(&self, ray: &WideRay, t_max: f32, filter: &impl HitFilter) -> Option<(u32, QuadHit)> {
        if self.stack() == TraversalStack::Fixed {
            self.closest_hit_with(ray, t_max, &mut FixedStack::new(), filter)
        } else {
            self.closest_hit_with(ray, t_max, &mut Vec::new(), filter)
        }
    }

    /// Whether anything `filter` keeps lies at 0 < t < `t_max` (stops at the first such hit).
    #[inline(always)]
    pub fn any_hit(&self, ray: &WideRay, t_max: f32, filter: &impl HitFilter) -> bool {
        if self.stack() == TraversalStack::Fixed {
            self.any_hit_with(ray, t_max, &mut FixedStack::new(), filter)
        } else {
            self.any_hit_with(ray, t_max, &mut Vec::new(), filter)
        }
    }

    #[inline(always)]
    fn closest_hit_with(
        &self,
        ray: &WideRay,
        t_max: f32,
        stack: &mut impl Stack,
        filter: &impl HitFilter,
    ) -> Option<(u32, QuadHit)> {
        let mut best = None;
        let mut nearest = Nearest::before(t_max);
        self.walk_nearest_first(ray, t_max, stack, |quad, _| {
            let q = quad as usize;
            if let Some(hit) = self.quads[q].intersect(ray, &self.quad_triangles[q], &mut nearest, filter) {
                best = Some((quad, hit));
            }
            nearest.t
        });
        best
    }

    #[inline(always)]
    fn any_hit_with(&self, ray: &WideRay, t_max: f32, stack: &mut impl Stack, filter: &impl HitFilter) -> bool {
        self.walk_until(ray, t_max, stack, |quad, t_max| {
            let q = quad as usize;
            (!self.quads[q].hits_any(ray, t_max, || &self.quad_triangles[q], filter)).then_some(t_max)
        })
    }
}
