//! A 4-wide BVH for traversal: nodes of four children with their boxes stored as float lanes,
//! and leaves of four triangles stored as float lanes. `binned.rs` builds it directly (the
//! default); for obvhs's presets, obvhs builds a binary tree (PLOC, reinsertion, leaves of up to
//! four triangles, padded leaf boxes) and this module collapses it ([`WideBvh::from_bvh2`]).
//!
//! One node test is then 12 lane-wise subtractions/multiplications and a few min/max — four
//! boxes at once, with no dequantisation — and one leaf test runs the watertight
//! ray/triangle test (Woop et al.) on four triangles at once ([`TriangleQuad::intersect`]),
//! bit-identical per lane to the scalar test in [`super::triangle`].
//!
//! Traversal (the loops, the stack) is in `walk.rs`.

use glam::{BVec4A, Vec3A, Vec4};
use rayon::prelude::*;

use super::alpha::HitFilter;
use super::triangle::WatertightRay;
use obvhs::aabb::Aabb;
use obvhs::bvh2::Bvh2;

/// Marks a child slot that holds a leaf (the rest of the value is the quad index).
pub(super) const LEAF: u32 = 1 << 31;
/// Marks an unused child slot.
pub(super) const EMPTY: u32 = u32::MAX;

/// Deepest tree the fixed-size traversal stack serves (3·21 + 1 = 64 entries).
pub const FIXED_STACK_DEPTH: u32 = 21;

/// Which stack a tree is traversed with (chosen from its depth at build time).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TraversalStack {
    /// A 64-entry array: trees of depth ≤ [`FIXED_STACK_DEPTH`] (every ordinary mesh).
    Fixed,
    /// A growable vector: deeper trees.
    Growable,
}

/// Levels of 4-wide nodes whose subtrees are collapsed in parallel (up to 4² = 16 tasks: work for
/// a few cores without splitting small trees into many tiny tasks).
const PARALLEL_LEVELS: u32 = 2;

/// The number of leaves under `bvh2` node `node`.
fn leaf_count(bvh2: &Bvh2, node: usize) -> usize {
    let mut stack = vec![node];
    let mut leaves = 0;
    while let Some(n) = stack.pop() {
        let first = bvh2.nodes[n].first_index as usize;
        if bvh2.nodes[n].is_leaf() {
            leaves += 1;
        } else {
            stack.extend([first, first + 1]);
        }
    }
    leaves
}

/// Four child boxes, lane k = child k; `bounds[axis][0]` = minima, `[1]` = maxima.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
pub(super) struct Node4 {
    pub(super) bounds: [[Vec4; 2]; 3],
    pub(super) child: [u32; 4],
}

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
    fn from_fn(n: usize, triangle: impl Fn(usize) -> [Vec3A; 3]) -> Self {
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

/// The collapsed tree: nodes, leaf quads in traversal order, and each lane's input triangle.
pub struct WideBvh {
    pub(super) nodes: Vec<Node4>,
    pub(super) quads: Vec<TriangleQuad>,
    pub(super) quad_triangles: Vec<[u32; 4]>,
    /// Each quad's box (the one its parent holds): [minimum, maximum], each [x, y, z]. Packets
    /// test it per ray before the triangles ([`super::packet`]).
    pub(super) quad_bounds: Vec<[[f32; 3]; 2]>,
    depth: u32,
}

impl WideBvh {
    /// Collapses `bvh2` (leaves of at most four primitives; `triangles[i]` are the vertices of
    /// its primitive i) into a 4-wide tree.
    pub fn from_bvh2(bvh2: &Bvh2, triangles: &[[Vec3A; 3]]) -> Self {
        Self::collapse(bvh2, triangles, PARALLEL_LEVELS)
    }

    /// [`WideBvh::from_bvh2`] with the top `parallel` levels' subtrees written in parallel.
    fn collapse(bvh2: &Bvh2, triangles: &[[Vec3A; 3]], parallel: u32) -> Self {
        // A binary tree of L leaves has L − 1 inner nodes; a 4-wide one has at least (L − 1)/3.
        let mut out = WideBvh::with_capacity(bvh2.nodes.len().div_ceil(2));
        if bvh2.nodes.is_empty() {
            return out;
        }
        if bvh2.nodes[0].is_leaf() {
            // A tree of one leaf: a root whose only child is that leaf.
            out.push_empty_node(1);
            let leaf = out.push_leaf(bvh2, 0, triangles);
            out.set_bounds(0, 0, bvh2, 0, leaf);
        } else {
            out.emit(bvh2, 0, triangles, 1, parallel);
        }
        out
    }

    /// Writes node `node2` (inner) of `bvh2` and its subtree; returns its index. Nodes and quads
    /// come out in depth-first order, children in slot order. The subtrees of the top `parallel`
    /// levels are written in parallel into trees of their own and appended in that same order,
    /// so the result does not depend on it; below them [`Self::emit_sequential`] writes them.
    fn emit(&mut self, bvh2: &Bvh2, node2: usize, triangles: &[[Vec3A; 3]], depth: u32, parallel: u32) -> u32 {
        if parallel == 0 {
            return self.emit_sequential(bvh2, node2, triangles, depth);
        }
        let (index, slots, count) = self.push_node(bvh2, node2, depth);
        let subtrees: Vec<Option<WideBvh>> = slots[..count]
            .par_iter()
            .map(|&slot| {
                (!bvh2.nodes[slot].is_leaf()).then(|| {
                    // Sized up front: growing from empty copied each subtree on every
                    // doubling, before appending copies it again.
                    let mut subtree = WideBvh::with_capacity(leaf_count(bvh2, slot));
                    subtree.emit(bvh2, slot, triangles, depth + 1, parallel - 1);
                    subtree
                })
            })
            .collect();
        for (k, (&slot, subtree)) in slots[..count].iter().zip(subtrees).enumerate() {
            let child = match subtree {
                Some(subtree) => self.append(subtree),
                None => self.push_leaf(bvh2, slot, triangles),
            };
            self.set_bounds(index, k, bvh2, slot, child);
        }
        index as u32
    }

    /// [`Self::emit`] without parallel levels, with an explicit stack instead of recursion, so
    /// that no tree is too deep to collapse: the same depth-first order, each node written when
    /// it is reached and its children queued in reverse slot order.
    fn emit_sequential(&mut self, bvh2: &Bvh2, node2: usize, triangles: &[[Vec3A; 3]], depth: u32) -> u32 {
        let (root, slots, count) = self.push_node(bvh2, node2, depth);
        // (parent node, its slot k, bvh2 node, the parent's depth)
        let mut pending: Vec<(usize, usize, usize, u32)> = Vec::new();
        pending.extend((0..count).rev().map(|k| (root, k, slots[k], depth)));
        while let Some((parent, k, slot, parent_depth)) = pending.pop() {
            let child = if bvh2.nodes[slot].is_leaf() {
                self.push_leaf(bvh2, slot, triangles)
            } else {
                let (index, slots, count) = self.push_node(bvh2, slot, parent_depth + 1);
                pending.extend((0..count).rev().map(|k| (index, k, slots[k], parent_depth + 1)));
                index as u32
            };
            self.set_bounds(parent, k, bvh2, slot, child);
        }
        root as u32
    }

    /// Appends an empty node for `bvh2` inner node `node2` at `depth`; returns its index and the
    /// bvh2 nodes of its children (`slots[..count]`): the largest inner child opened until there
    /// are four children or only leaves are left.
    fn push_node(&mut self, bvh2: &Bvh2, node2: usize, depth: u32) -> (usize, [usize; 4], usize) {
        let first = bvh2.nodes[node2].first_index as usize;
        let mut slots = [first, first + 1, 0, 0];
        let mut count = 2;
        while count < 4 {
            let widest = (0..count)
                .filter(|&i| !bvh2.nodes[slots[i]].is_leaf())
                .max_by(|&a, &b| {
                    let area = |i: usize| bvh2.nodes[slots[i]].aabb().half_area();
                    area(a).total_cmp(&area(b))
                });
            let Some(i) = widest else { break };
            let opened = bvh2.nodes[slots[i]].first_index as usize;
            slots[i] = opened;
            slots[count] = opened + 1;
            count += 1;
        }
        (self.push_empty_node(depth), slots, count)
    }

    /// Appends the quad of `bvh2` leaf `slot`; returns its child reference.
    fn push_leaf(&mut self, bvh2: &Bvh2, slot: usize, triangles: &[[Vec3A; 3]]) -> u32 {
        let node2 = &bvh2.nodes[slot];
        let range = node2.first_index as usize..(node2.first_index + node2.prim_count) as usize;
        let (quad, primitives, bounds) = leaf_parts(&bvh2.primitive_indices[range], triangles, node2.aabb());
        self.quads.push(quad);
        self.quad_triangles.push(primitives);
        self.quad_bounds.push(bounds);
        LEAF | (self.quads.len() as u32 - 1)
    }

    /// Appends a node without children (its slots [`EMPTY`], its boxes empty) at `depth`;
    /// returns its index.
    pub(super) fn push_empty_node(&mut self, depth: u32) -> usize {
        self.depth = self.depth.max(depth);
        self.nodes.push(Node4 {
            bounds: empty_bounds(),
            child: [EMPTY; 4],
        });
        self.nodes.len() - 1
    }

    /// Appends `subtree` (its root first), renumbering its node and quad references; returns
    /// the index of its root.
    fn append(&mut self, subtree: WideBvh) -> u32 {
        let root = self.append_nodes(subtree.nodes, subtree.depth, self.quads.len() as u32);
        self.quads.extend(subtree.quads);
        self.quad_triangles.extend(subtree.quad_triangles);
        self.quad_bounds.extend(subtree.quad_bounds);
        root
    }

    /// Appends the nodes of a subtree of depth `depth` (its root first), renumbering their
    /// node references to follow this tree's nodes and their quad references to count from
    /// `quad_base`; returns the index of its root.
    pub(super) fn append_nodes(&mut self, nodes: Vec<Node4>, depth: u32, quad_base: u32) -> u32 {
        let node_base = self.nodes.len() as u32;
        self.nodes.extend(nodes.into_iter().map(|mut node| {
            for c in node.child.iter_mut().filter(|c| **c != EMPTY) {
                *c = if *c & LEAF != 0 {
                    LEAF | ((*c & !LEAF) + quad_base)
                } else {
                    *c + node_base
                };
            }
            node
        }));
        self.depth = self.depth.max(depth);
        node_base
    }

    /// Child slot `k` of node `index` becomes `child`, with the box of `bvh2` node `slot`.
    fn set_bounds(&mut self, index: usize, k: usize, bvh2: &Bvh2, slot: usize, child: u32) {
        self.set_child(index, k, bvh2.nodes[slot].aabb(), child);
    }

    /// Child slot `k` of node `index` becomes `child`, with box `b`.
    pub(super) fn set_child(&mut self, index: usize, k: usize, b: &Aabb, child: u32) {
        let node = &mut self.nodes[index];
        for axis in 0..3 {
            node.bounds[axis][0][k] = b.min[axis];
            node.bounds[axis][1][k] = b.max[axis];
        }
        node.child[k] = child;
    }

    /// An empty tree with room for `leaves` leaves (one quad each, and a node per three).
    pub(super) fn with_capacity(leaves: usize) -> Self {
        WideBvh {
            nodes: Vec::with_capacity(leaves / 3 + 1),
            quads: Vec::with_capacity(leaves),
            quad_triangles: Vec::with_capacity(leaves),
            quad_bounds: Vec::with_capacity(leaves),
            depth: 0,
        }
    }

    /// Depth of the deepest inner node (root = 1).
    pub fn depth(&self) -> u32 {
        self.depth
    }

    /// The stack this tree is traversed with.
    pub fn stack(&self) -> TraversalStack {
        if self.depth <= FIXED_STACK_DEPTH {
            TraversalStack::Fixed
        } else {
            TraversalStack::Growable
        }
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Replaces every stored primitive index p by `f(p)` (e.g. to the scene's triangle index).
    pub fn map_primitives(&mut self, f: impl Fn(u32) -> u32) {
        for q in &mut self.quad_triangles {
            for p in q.iter_mut().filter(|p| **p != EMPTY) {
                *p = f(*p);
            }
        }
    }

    /// The input primitive of lane `lane` of quad `quad`.
    #[inline(always)]
    pub fn primitive(&self, quad: u32, lane: usize) -> u32 {
        self.quad_triangles[quad as usize][lane]
    }
}

/// What the tree stores of a leaf of primitives `prims` (one to four; `triangles[p]` are the
/// vertices of primitive p) with box `bounds`: its quad, its primitives (padded with [`EMPTY`])
/// and its box.
pub(super) fn leaf_parts(
    prims: &[u32],
    triangles: &[[Vec3A; 3]],
    bounds: &Aabb,
) -> (TriangleQuad, [u32; 4], [[f32; 3]; 2]) {
    (
        TriangleQuad::from_fn(prims.len(), |l| triangles[prims[l] as usize]),
        [0, 1, 2, 3].map(|l| prims.get(l).copied().unwrap_or(EMPTY)),
        [bounds.min.to_array(), bounds.max.to_array()],
    )
}

/// Boxes that no ray enters (min = +∞, max = −∞ on every axis).
fn empty_bounds() -> [[Vec4; 2]; 3] {
    [[Vec4::splat(f32::INFINITY), Vec4::splat(f32::NEG_INFINITY)]; 3]
}

#[cfg(test)]
mod tests {
    use super::*;
    use obvhs::bvh2::builder::build_bvh2;
    use obvhs::BvhBuildParams;

    /// A binary chain of `n` leaves (each inner node: a leaf and the rest of the chain), as PLOC
    /// builds for degenerate inputs, over triangles along x.
    fn chain(n: usize) -> (Bvh2, Vec<[Vec3A; 3]>) {
        let triangles: Vec<[Vec3A; 3]> = (0..n)
            .map(|i| {
                let x = i as f32;
                [
                    Vec3A::new(x, 0.0, 0.0),
                    Vec3A::new(x + 1.0, 0.0, 0.0),
                    Vec3A::new(x, 1.0, 0.0),
                ]
            })
            .collect();
        let leaf_box = |i: usize| obvhs::aabb::Aabb::new(triangles[i][0], triangles[i][1] + Vec3A::Y);
        let rest_box = |i: usize| obvhs::aabb::Aabb::new(triangles[i][0], Vec3A::new(n as f32, 1.0, 0.0));
        // Node 0 is the root; inner node j's children are 2j + 1 (leaf j) and 2j + 2.
        let mut nodes = vec![obvhs::bvh2::node::Bvh2Node::new(rest_box(0), 0, 1)];
        for j in 0..n - 1 {
            nodes.push(obvhs::bvh2::node::Bvh2Node::new(leaf_box(j), 1, j as u32));
            nodes.push(if j + 1 == n - 1 {
                obvhs::bvh2::node::Bvh2Node::new(leaf_box(j + 1), 1, (j + 1) as u32)
            } else {
                obvhs::bvh2::node::Bvh2Node::new(rest_box(j + 1), 0, nodes.len() as u32 + 1)
            });
        }
        let bvh2 = Bvh2 {
            nodes,
            primitive_indices: (0..n as u32).collect(),
            ..Bvh2::default()
        };
        (bvh2, triangles)
    }

    #[test]
    fn a_chain_a_hundred_thousand_deep_collapses_without_recursion() {
        // The recursive collapse overflowed the stack on chains some thousands deep (a
        // 30,000-triangle fan); the explicit stack does not care.
        let n = 100_000;
        let (bvh2, triangles) = chain(n);
        let tree = WideBvh::from_bvh2(&bvh2, &triangles);
        assert_eq!(tree.quads.len(), n, "one leaf of one triangle each");
        assert!(
            tree.depth() as usize > n / 4,
            "a chain stays a chain: depth {}",
            tree.depth()
        );
        assert_eq!(tree.stack(), TraversalStack::Growable);
        let mut seen: Vec<u32> = tree.quad_triangles.iter().map(|q| q[0]).collect();
        seen.sort_unstable();
        assert!(seen.iter().copied().eq(0..n as u32));
    }

    #[test]
    fn collapsing_subtrees_in_parallel_gives_the_sequential_tree() {
        let mesh = crate::scene::procedural::torus(2.0, 0.5, 96, 48);
        let triangles: Vec<[Vec3A; 3]> = mesh
            .triangles
            .iter()
            .map(|t| t.map(|i| Vec3A::from(mesh.positions[i as usize])))
            .collect();
        let boxes: Vec<obvhs::aabb::Aabb> = triangles
            .iter()
            .map(|[a, b, c]| obvhs::aabb::Aabb::new(a.min(*b).min(*c), a.max(*b).max(*c)))
            .collect();
        let params = BvhBuildParams {
            max_prims_per_leaf: 4,
            ..BvhBuildParams::fast_build()
        };
        let bvh2 = build_bvh2(&boxes, params, &mut std::time::Duration::default());
        let sequential = WideBvh::collapse(&bvh2, &triangles, 0);
        assert!(
            sequential.depth > 3,
            "a tree deep enough to split: depth {}",
            sequential.depth
        );
        for parallel in [1, 2, 3] {
            let tree = WideBvh::collapse(&bvh2, &triangles, parallel);
            assert_eq!(tree.depth, sequential.depth);
            assert_eq!(
                tree.quad_triangles, sequential.quad_triangles,
                "{parallel} parallel levels"
            );
            assert_eq!(tree.quad_bounds, sequential.quad_bounds);
            assert_eq!(tree.nodes.len(), sequential.nodes.len());
            for (a, b) in tree.nodes.iter().zip(&sequential.nodes) {
                assert_eq!(a.child, b.child, "{parallel} parallel levels");
                assert_eq!(format!("{:?}", a.bounds), format!("{:?}", b.bounds));
            }
            for (a, b) in tree.quads.iter().zip(&sequential.quads) {
                assert_eq!(format!("{a:?}"), format!("{b:?}"));
            }
        }
    }
}
