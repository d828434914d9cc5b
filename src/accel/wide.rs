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

use glam::{Vec3A, Vec4};
use rayon::prelude::*;

pub use super::quad::{Nearest, QuadHit, TriangleQuad, WideRay};
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
