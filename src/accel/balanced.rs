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

/// Binary trees deeper than this are rebuilt balanced ([`balanced_bvh2`]). An ordinary mesh of a
/// few million triangles builds to depth 30–40 with PLOC; a balanced tree of 2³² triangles is 31
/// levels deep.
pub const MAX_BINARY_DEPTH: usize = 64;

/// Above this mean overlap — the boxes' summed half areas over the half area of their union, per
/// √n — PLOC is not tried. A tessellated surface has a mean overlap of order one whatever its
/// triangle count (its boxes tile its surface); n boxes that all share a point have one of order
/// n, which grows past any multiple of √n.
const MAX_OVERLAP_PER_SQRT_N: f64 = 4.0;

/// Whether PLOC would degenerate on `boxes`: whether they overlap as a fan's do (see
/// [`MAX_OVERLAP_PER_SQRT_N`]). Flat or empty unions (a plane seen edge-on has zero area in one
/// projection only; half areas sum three projections) count as overlapping only when every
/// box is a point.
pub fn overlaps_too_much(boxes: &[Aabb]) -> bool {
    if boxes.len() < 1024 {
        return false; // PLOC is quick on a thousand boxes, whatever their shape
    }
    let mut union = Aabb::empty();
    let mut summed = 0.0f64;
    for b in boxes {
        union.extend(b.min);
        union.extend(b.max);
        summed += f64::from(b.half_area());
    }
    let total = f64::from(union.half_area());
    if !(total > 0.0) {
        return true; // every box is one point: nothing to sort
    }
    summed / total > MAX_OVERLAP_PER_SQRT_N * (boxes.len() as f64).sqrt()
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
        assert!(overlaps_too_much(&fan(2_000)));
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
