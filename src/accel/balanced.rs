//! The balanced binary tree: the build for inputs on which PLOC degenerates.
//!
//! PLOC merges each cluster with its cheapest neighbour in Morton order. On boxes that all
//! overlap — a triangle fan around one vertex (what a 40,000-vertex polygon becomes), or a mesh
//! translated so far that every vertex rounds to the same few floats — every merge is as cheap as
//! the next, few clusters agree on a partner per pass, and the build takes time quadratic in the
//! triangle count and yields a chain hundreds of levels deep. There a surface-area heuristic has
//! nothing to gain anyway: every split cuts through the same overlapping boxes.
//!
//! This builder splits the primitives top-down at the median of their centroids along the longest
//! axis of the centroid bounds (ties broken by index), so every split halves the count whatever
//! the boxes are: depth ⌈log₂(n / leaf)⌉ + 1, time O(n log n), no recursion.

use glam::Vec3A;
use obvhs::aabb::Aabb;
use obvhs::bvh2::{node::Bvh2Node, Bvh2};
use rayon::prelude::*;

/// Binary trees deeper than this are rebuilt balanced ([`balanced_bvh2`]). An ordinary mesh of a
/// few million triangles builds to depth 30–40 with PLOC; a balanced tree of 2³² triangles is 31
/// levels deep.
pub const MAX_BINARY_DEPTH: usize = 64;

/// Boxes per window of the overlap test ([`overlaps_too_much`]).
pub const WINDOW: usize = 64;
/// A window whose boxes' summed half areas exceed this many times its union's is degenerate: a
/// tessellated surface's windows tile it (about 1–4), a fan's boxes all share a corner (about
/// the window's size).
pub const MAX_WINDOW_OVERLAP: f64 = 16.0;
/// This many degenerate windows in a row (1,024 boxes) make PLOC's cost matter: a cluster of
/// m such boxes costs it about m² box unions. Shorter runs (a sphere's pole, a cylinder's cap)
/// are left to it.
pub const MAX_DEGENERATE_RUN: usize = 16;

/// Whether PLOC would degenerate on `boxes`: whether, in Morton order of their centroids, a run
/// of [`MAX_DEGENERATE_RUN`] consecutive windows of [`WINDOW`] boxes each overlap as a fan's
/// do ([`MAX_WINDOW_OVERLAP`]), wherever in the scene that fan is. A window of boxes that are
/// all one point counts as degenerate.
pub fn overlaps_too_much(boxes: &[Aabb]) -> bool {
    if boxes.len() < WINDOW * MAX_DEGENERATE_RUN {
        return false; // PLOC is quick on a thousand boxes, whatever their shape
    }
    let mut centres = Aabb::empty();
    for b in boxes {
        centres.extend((b.min + b.max) * 0.5);
    }
    let extent = (centres.max - centres.min).max(Vec3A::splat(f32::MIN_POSITIVE));
    let mut order: Vec<u64> = boxes
        .par_iter()
        .enumerate()
        .map(|(i, b)| {
            let unit = (((b.min + b.max) * 0.5 - centres.min) / extent).clamp(Vec3A::ZERO, Vec3A::ONE);
            let cell = (unit * 1023.0).as_uvec3();
            (u64::from(morton3(cell.x, cell.y, cell.z)) << 32) | i as u64
        })
        .collect();
    order.par_sort_unstable();
    let mut run = 0;
    for window in order.chunks(WINDOW) {
        let mut union = Aabb::empty();
        let mut summed = 0.0f64;
        for &key in window {
            let b = &boxes[(key & u64::from(u32::MAX)) as usize];
            union.extend(b.min);
            union.extend(b.max);
            summed += f64::from(b.half_area());
        }
        let total = f64::from(union.half_area());
        let degenerate = if total > 0.0 {
            summed > MAX_WINDOW_OVERLAP * total
        } else {
            true
        };
        run = if degenerate { run + 1 } else { 0 };
        if run >= MAX_DEGENERATE_RUN {
            return true;
        }
    }
    false
}

/// The 30-bit Morton code of a cell (10 bits per axis, interleaved x, y, z).
fn morton3(x: u32, y: u32, z: u32) -> u32 {
    let spread = |v: u32| {
        let mut v = v & 0x3ff;
        v = (v | (v << 16)) & 0x0300_00ff;
        v = (v | (v << 8)) & 0x0300_f00f;
        v = (v | (v << 4)) & 0x030c_30c3;
        (v | (v << 2)) & 0x0924_9249
    };
    spread(x) | (spread(y) << 1) | (spread(z) << 2)
}

/// Depth of `bvh2` (a single leaf or the root alone = 1), walked without recursion.
pub fn bvh2_depth(bvh2: &Bvh2) -> usize {
    if bvh2.nodes.is_empty() {
        return 0;
    }
    let mut deepest = 0;
    let mut stack = vec![(0usize, 1usize)];
    while let Some((node, depth)) = stack.pop() {
        deepest = deepest.max(depth);
        let n = &bvh2.nodes[node];
        if !n.is_leaf() {
            let first = n.first_index as usize;
            stack.extend([(first, depth + 1), (first + 1, depth + 1)]);
        }
    }
    deepest
}

/// A binary tree over `boxes` (at least one) with leaves of at most `max_leaf` primitives, by
/// median splits (see the module's documentation). Laid out as obvhs lays its trees out: the
/// root is node 0, an inner node's children are `first_index` and `first_index + 1`, a leaf's
/// primitives are `primitive_indices[first_index..first_index + prim_count]`.
pub fn balanced_bvh2(boxes: &[Aabb], max_leaf: usize) -> Bvh2 {
    assert!(!boxes.is_empty() && max_leaf >= 1);
    let centroids: Vec<Vec3A> = boxes.iter().map(|b| (b.min + b.max) * 0.5).collect();
    let mut indices: Vec<u32> = (0..boxes.len() as u32).collect();
    let mut nodes = vec![Bvh2Node::default()];
    nodes.reserve(2 * boxes.len().div_ceil(max_leaf));
    // (node, first primitive, primitive count), processed depth first.
    let mut tasks = vec![(0usize, 0usize, boxes.len())];
    while let Some((node, start, count)) = tasks.pop() {
        let range = &mut indices[start..start + count];
        let mut bounds = Aabb::empty();
        let mut centre_bounds = Aabb::empty();
        for &i in range.iter() {
            bounds.extend(boxes[i as usize].min);
            bounds.extend(boxes[i as usize].max);
            centre_bounds.extend(centroids[i as usize]);
        }
        if count <= max_leaf {
            nodes[node] = Bvh2Node::new(bounds, count as u32, start as u32);
            continue;
        }
        let extent = centre_bounds.max - centre_bounds.min;
        let axis = if extent.x >= extent.y && extent.x >= extent.z {
            0
        } else if extent.y >= extent.z {
            1
        } else {
            2
        };
        let half = count / 2;
        range.select_nth_unstable_by(half, |&a, &b| {
            let (ca, cb) = (centroids[a as usize][axis], centroids[b as usize][axis]);
            ca.total_cmp(&cb).then(a.cmp(&b))
        });
        let first = nodes.len();
        nodes.extend([Bvh2Node::default(); 2]);
        nodes[node] = Bvh2Node::new(bounds, 0, first as u32);
        tasks.push((first + 1, start + half, count - half));
        tasks.push((first, start, half));
    }
    Bvh2 {
        nodes,
        primitive_indices: indices,
        ..Bvh2::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fan(n: usize) -> Vec<Aabb> {
        (0..n)
            .map(|i| {
                let angle = |k: usize| std::f32::consts::PI * k as f32 / n as f32;
                let (a, b) = (angle(i), angle(i + 1));
                let p = [
                    Vec3A::ZERO,
                    Vec3A::new(a.cos(), a.sin(), 0.0),
                    Vec3A::new(b.cos(), b.sin(), 0.0),
                ];
                Aabb::new(p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]))
            })
            .collect()
    }

    /// A grid of `side`² unit squares' boxes: a tessellated surface.
    fn grid(side: usize) -> Vec<Aabb> {
        (0..side * side)
            .map(|i| {
                let corner = Vec3A::new((i % side) as f32, (i / side) as f32, 0.0);
                Aabb::new(corner, corner + Vec3A::new(1.0, 1.0, 0.0))
            })
            .collect()
    }

    #[test]
    fn fans_and_coincident_boxes_overlap_too_much_and_surfaces_do_not() {
        assert!(overlaps_too_much(&fan(30_000)));
        assert!(overlaps_too_much(&fan(5_000)));
        // A fan inside a large scene: the windows see it where a test of the whole scene's
        // overlap would not (a fuzz input of this shape took PLOC minutes).
        let mut scene = grid(300);
        scene.extend(fan(20_000).into_iter().map(|b| Aabb::new(b.min * 3.0, b.max * 3.0)));
        assert!(overlaps_too_much(&scene));
        // Shuffled, it is still found (Morton order, not the input's).
        let mut shuffled = fan(20_000);
        let n = shuffled.len();
        for i in 0..n {
            shuffled.swap(i, (i * 7919 + 13) % n);
        }
        assert!(overlaps_too_much(&shuffled));
        assert!(overlaps_too_much(&vec![Aabb::new(Vec3A::ONE, Vec3A::ONE); 5_000]));
        assert!(!overlaps_too_much(&grid(300)));
        assert!(!overlaps_too_much(&grid(10)), "small inputs always go to PLOC");
    }

    #[test]
    fn the_balanced_tree_holds_every_primitive_once_in_leaves_that_bound_them() {
        for boxes in [
            fan(10_001),
            grid(57),
            vec![Aabb::new(Vec3A::ZERO, Vec3A::ONE); 999],
            fan(1),
        ] {
            let bvh2 = balanced_bvh2(&boxes, 4);
            let n = boxes.len();
            let bound = (n.div_ceil(4) as f64).log2().ceil() as usize + 1;
            assert!(bvh2_depth(&bvh2) <= bound, "depth {} for {n} boxes", bvh2_depth(&bvh2));
            let mut seen = vec![false; n];
            for node in bvh2.nodes.iter().filter(|node| node.is_leaf()) {
                assert!(node.prim_count <= 4);
                let first = node.first_index as usize;
                for &p in &bvh2.primitive_indices[first..first + node.prim_count as usize] {
                    assert!(!std::mem::replace(&mut seen[p as usize], true), "primitive {p} twice");
                    let b = boxes[p as usize];
                    assert!(node.aabb().min.cmple(b.min).all() && node.aabb().max.cmpge(b.max).all());
                }
            }
            assert!(seen.iter().all(|&s| s), "every primitive in a leaf");
        }
    }
}
