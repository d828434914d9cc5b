//! A 4-wide BVH built by binned SAH, straight from the triangles' boxes into [`WideBvh`]
//! ([`super::BvhPreset::Binned`], the default). No binary tree in between and no collapse: the
//! build that a render from nothing (a fresh command, the explorer's first image) waits for.
//!
//! Each split sorts the centres of a node's boxes into 16 bins along the axis where the
//! centres spread most, and cuts between the two bins where the surface area heuristic is
//! least (Wald 2007, "On fast construction of SAH-based bounding volume hierarchies"). Children
//! are counted in quads, ⌈n/4⌉, since a leaf holds up to four triangles and tests them at once.
//! A 4-wide node opens its widest child until it has four, the rule [`WideBvh::from_bvh2`]
//! follows when it collapses obvhs's binary tree.
//!
//! Hits do not depend on the tree (the nearest hit and its ties are decided per triangle:
//! `tests.rs` checks every preset), so this tree gives every ray the same answer as obvhs's.
//!
//! Parts of at most 16 triangles are cut at their median centre into whole quads.
//!
//! Bounded: where a node's centres all coincide it is split by count; deeper than 48 binary
//! levels, by the median centre, so no input makes the tree deeper than about 48 + log₂ n binary
//! levels, and the recursion is as deep as the tree's 4-wide levels.
//!
//! Deterministic: the top of the tree is split on one thread down to parts of at most
//! n/8 triangles, which are built in parallel and appended in the order they were found.

use glam::Vec3A;
use obvhs::aabb::Aabb;
use rayon::prelude::*;

use super::bvh_space::padded_box;
use super::wide::{leaf_parts, WideBvh, EMPTY, LEAF};

/// Bins per split.
const BINS: usize = 16;
/// Triangles per leaf at most: one quad.
const LEAF_SIZE: usize = 4;
/// Binary levels split by SAH; deeper parts are split at their median centre.
const MAX_SAH_DEPTH: u32 = 48;
/// Parts of at most this many quads' worth of triangles are split at their median centre
/// rather than binned: for a handful of triangles, setting up the bins costs more than the
/// split, and the median cut into whole quads fills the leaves.
const SMALL_QUADS: usize = 4;
/// Parts of at least this many triangles are binned on all threads.
const PARALLEL_SPLIT: usize = 16384;
/// Triangles per piece of work in those.
const PARALLEL_CHUNK: usize = 4096;
/// About how many parts the top of the tree is cut into, to be built in parallel.
const TASKS: usize = 8;
/// Parts smaller than this are not worth a task of their own.
const MIN_TASK: usize = 2048;

/// One triangle's box, with its index in the input.
#[derive(Clone, Copy)]
struct PrimRef {
    lo: Vec3A,
    hi: Vec3A,
    index: u32,
}

impl PrimRef {
    /// Twice the box's centre (the halving changes no comparison).
    #[inline(always)]
    fn centre2(&self) -> Vec3A {
        self.lo + self.hi
    }
}

/// A run `start..end` of the primitives, with the box of their boxes, the box of their
/// [`PrimRef::centre2`] and its binary depth.
#[derive(Clone, Copy)]
struct Part {
    start: usize,
    end: usize,
    bounds: Aabb,
    centres: Aabb,
    depth: u32,
}

impl Part {
    fn of(prims: &[PrimRef], start: usize, end: usize, depth: u32) -> Part {
        let mut all = Bin::EMPTY;
        for p in &prims[start..end] {
            all.add(p);
        }
        Part::with(&all, start, end, depth)
    }

    /// The part `start..end` whose primitives `bin` summarises.
    fn with(bin: &Bin, start: usize, end: usize, depth: u32) -> Part {
        Part {
            start,
            end,
            bounds: bin.bounds,
            centres: bin.centres,
            depth,
        }
    }

    fn len(&self) -> usize {
        self.end - self.start
    }
}

/// A part of the top of the tree left for a parallel build: it becomes child `slot` of node
/// `node`, at 4-wide depth `depth`.
struct Task {
    part: Part,
    node: usize,
    slot: usize,
    depth: u32,
}

/// A leaf before its quad is written: `count` primitives from `start` on in the primitives'
/// final order, and their box.
struct Leaf {
    start: usize,
    count: usize,
    bounds: Aabb,
}

/// A tree while it is built: its nodes (in a [`WideBvh`] without quads yet), whose leaf
/// references index `leaves`.
struct Tree {
    wide: WideBvh,
    leaves: Vec<Leaf>,
}

impl Tree {
    /// An empty tree with room for the nodes and leaves that `triangles` triangles usually
    /// take (leaves of three, nodes of three or four children).
    fn with_capacity(triangles: usize) -> Tree {
        let mut wide = WideBvh::with_capacity(0);
        wide.nodes.reserve(triangles / 8 + 1);
        Tree {
            wide,
            leaves: Vec::with_capacity(triangles / 3 + 1),
        }
    }

    /// Appends the leaf of `part` (one to four primitives); returns its child reference.
    fn push_leaf(&mut self, part: &Part) -> u32 {
        self.leaves.push(Leaf {
            start: part.start,
            count: part.len(),
            bounds: part.bounds,
        });
        LEAF | (self.leaves.len() as u32 - 1)
    }

    /// Appends `subtree`, whose leaves start at `offset` in the primitives; returns the index
    /// of its root.
    fn append(&mut self, subtree: Tree, offset: usize) -> u32 {
        let depth = subtree.wide.depth();
        let root = self
            .wide
            .append_nodes(subtree.wide.nodes, depth, self.leaves.len() as u32);
        self.leaves.extend(subtree.leaves.into_iter().map(|leaf| Leaf {
            start: leaf.start + offset,
            ..leaf
        }));
        root
    }
}

/// The tree over `triangles` (BVH space), each in its padded box ([`padded_box`]). Primitive
/// indices in the result are indices into `triangles`.
pub(super) fn build(triangles: &[[Vec3A; 3]]) -> WideBvh {
    let n = triangles.len();
    let mut prims: Vec<PrimRef> = triangles
        .par_iter()
        .enumerate()
        .map(|(i, t)| {
            let b = padded_box(t);
            PrimRef {
                lo: b.min,
                hi: b.max,
                index: i as u32,
            }
        })
        .collect();
    let mut tree = Tree::with_capacity(n);
    if n == 0 {
        return tree.wide;
    }
    let root = Part::of(&prims, 0, n, 0);
    if n <= LEAF_SIZE {
        // A root whose only child is the one leaf.
        let index = tree.wide.push_empty_node(1);
        let leaf = tree.push_leaf(&root);
        tree.wide.set_child(index, 0, &root.bounds, leaf);
    } else {
        let mut top = Builder {
            task_size: (n / TASKS).max(MIN_TASK),
            tasks: Vec::new(),
        };
        top.emit(&mut tree, &mut prims, &root, 1);
        build_tasks(&mut tree, &mut prims, top.tasks);
    }
    // The leaves' quads, from the primitives in their final order.
    let Tree { mut wide, leaves } = tree;
    let prims = &prims;
    let (quads, (quad_triangles, quad_bounds)) = leaves
        .par_iter()
        .map(|leaf| {
            let mut indices = [0; LEAF_SIZE];
            for (index, p) in indices.iter_mut().zip(&prims[leaf.start..leaf.start + leaf.count]) {
                *index = p.index;
            }
            let (quad, primitives, bounds) = leaf_parts(&indices[..leaf.count], triangles, &leaf.bounds);
            (quad, (primitives, bounds))
        })
        .unzip();
    (wide.quads, wide.quad_triangles, wide.quad_bounds) = (quads, quad_triangles, quad_bounds);
    wide
}

/// Builds the subtrees of `tasks` in parallel (their parts are disjoint runs of `prims`) and
/// appends them to `tree` in the order the tasks were found.
fn build_tasks(tree: &mut Tree, prims: &mut [PrimRef], tasks: Vec<Task>) {
    let mut by_start: Vec<usize> = (0..tasks.len()).collect();
    by_start.sort_by_key(|&t| tasks[t].part.start);
    let mut runs: Vec<(usize, &mut [PrimRef])> = Vec::with_capacity(tasks.len());
    let (mut rest, mut offset) = (prims, 0);
    for &t in &by_start {
        let part = &tasks[t].part;
        let (_, tail) = std::mem::take(&mut rest).split_at_mut(part.start - offset);
        let (run, tail) = tail.split_at_mut(part.len());
        runs.push((t, run));
        (rest, offset) = (tail, part.end);
    }
    let mut subtrees: Vec<(usize, Tree)> = runs
        .into_par_iter()
        .map(|(t, run)| {
            let task = &tasks[t];
            let part = Part {
                start: 0,
                end: run.len(),
                ..task.part
            };
            let mut subtree = Tree::with_capacity(run.len());
            let mut builder = Builder {
                task_size: 0,
                tasks: Vec::new(),
            };
            builder.emit(&mut subtree, run, &part, task.depth);
            (t, subtree)
        })
        .collect();
    subtrees.sort_by_key(|&(t, _)| t);
    for (t, subtree) in subtrees {
        let task = &tasks[t];
        let root = tree.append(subtree, task.part.start);
        tree.wide.set_child(task.node, task.slot, &task.part.bounds, root);
    }
}

/// How [`Builder::emit`] splits: where it leaves parts for a parallel build.
struct Builder {
    /// Children of at most this many triangles that need a node are left as [`Task`]s (0: none).
    task_size: usize,
    tasks: Vec<Task>,
}

impl Builder {
    /// Writes the node of `part` (more than one leaf's worth) and its subtree at 4-wide depth
    /// `depth`; returns its index. Children left as tasks have the slot [`EMPTY`] until then.
    fn emit(&mut self, tree: &mut Tree, prims: &mut [PrimRef], part: &Part, depth: u32) -> u32 {
        let index = tree.wide.push_empty_node(depth);
        let (children, count) = children(prims, part);
        for (slot, child) in children[..count].iter().enumerate() {
            let reference = if child.len() <= LEAF_SIZE {
                tree.push_leaf(child)
            } else if child.len() <= self.task_size {
                self.tasks.push(Task {
                    part: *child,
                    node: index,
                    slot,
                    depth: depth + 1,
                });
                EMPTY
            } else {
                self.emit(tree, prims, child, depth + 1)
            };
            tree.wide.set_child(index, slot, &child.bounds, reference);
        }
        index as u32
    }
}

/// The children of a 4-wide node over `part` (more than one leaf's worth): `part` split in
/// two, then the child with the largest box that is more than a leaf split again, until there
/// are four or every child is a leaf.
fn children(prims: &mut [PrimRef], part: &Part) -> ([Part; 4], usize) {
    let (a, b) = split(prims, part);
    let mut slots = [a, b, a, a];
    let mut count = 2;
    while count < 4 {
        let widest = (0..count)
            .filter(|&i| slots[i].len() > LEAF_SIZE)
            .max_by(|&i, &j| slots[i].bounds.half_area().total_cmp(&slots[j].bounds.half_area()));
        let Some(i) = widest else { break };
        (slots[i], slots[count]) = split(prims, &slots[i]);
        count += 1;
    }
    (slots, count)
}

/// Splits `part` (at least two primitives) in two non-empty parts, reordering its primitives.
fn split(prims: &mut [PrimRef], part: &Part) -> (Part, Part) {
    let run = &mut prims[part.start..part.end];
    let axis = part.centres.largest_axis();
    let depth = part.depth + 1;
    let halves = |prims: &[PrimRef], mid: usize| {
        (
            Part::of(prims, part.start, part.start + mid, depth),
            Part::of(prims, part.start + mid, part.end, depth),
        )
    };
    if !(part.centres.max[axis] > part.centres.min[axis]) {
        // Every centre the same point: by count.
        return halves(prims, part.len() / 2);
    }
    let quads = part.len().div_ceil(LEAF_SIZE);
    if part.depth < MAX_SAH_DEPTH && quads > SMALL_QUADS {
        if let Some((left, right)) = split_by_sah(run, part, axis) {
            return (left, right);
        }
    }
    // The median centre, in whole quads where the part is small (16 triangles: four full
    // leaves).
    let mid = if quads <= SMALL_QUADS {
        quads / 2 * LEAF_SIZE
    } else {
        run.len() / 2
    };
    run.select_nth_unstable_by(mid, |a, b| {
        a.centre2()[axis]
            .total_cmp(&b.centre2()[axis])
            .then(a.index.cmp(&b.index))
    });
    halves(prims, mid)
}

/// Some primitives summed up — one bin of a split, or a whole part: the box of their boxes,
/// the box of their [`PrimRef::centre2`], and how many they are.
#[derive(Clone, Copy)]
struct Bin {
    bounds: Aabb,
    centres: Aabb,
    count: usize,
}

impl Bin {
    const EMPTY: Bin = Bin {
        bounds: Aabb::INVALID,
        centres: Aabb::INVALID,
        count: 0,
    };

    #[inline(always)]
    fn add(&mut self, p: &PrimRef) {
        self.bounds.min = self.bounds.min.min(p.lo);
        self.bounds.max = self.bounds.max.max(p.hi);
        let c = p.centre2();
        self.centres.min = self.centres.min.min(c);
        self.centres.max = self.centres.max.max(c);
        self.count += 1;
    }

    fn merge(&mut self, other: &Bin) {
        self.bounds = self.bounds.union(&other.bounds);
        self.centres = self.centres.union(&other.centres);
        self.count += other.count;
    }
}

/// Which of [`BINS`] bins along `axis` each centre of a part with centre box `centres` falls in
/// (more than one point: max > min on `axis`).
#[derive(Clone, Copy)]
struct Binning {
    axis: usize,
    first: f32,
    scale: f32,
}

impl Binning {
    fn new(centres: &Aabb, axis: usize) -> Binning {
        let first = centres.min[axis];
        // The largest centre lands in the last bin. Where the extent is so small that the scale
        // overflows, (c − first)·∞ is ∞ (the last bin) or NaN for c = first, which `as` takes
        // to 0 (the first bin): still a bin for every centre, the same every time it is asked.
        let scale = (BINS as f32 * (1.0 - 1e-6)) / (centres.max[axis] - first);
        Binning { axis, first, scale }
    }

    #[inline(always)]
    fn of(&self, p: &PrimRef) -> usize {
        (((p.centre2()[self.axis] - self.first) * self.scale) as usize).min(BINS - 1)
    }

    /// The bins of `prims`.
    fn fill(&self, prims: &[PrimRef]) -> [Bin; BINS] {
        let mut bins = [Bin::EMPTY; BINS];
        for p in prims {
            bins[self.of(p)].add(p);
        }
        bins
    }

    /// [`Self::fill`] on all threads (unions and counts: the same bins in any order).
    fn fill_parallel(&self, prims: &[PrimRef]) -> [Bin; BINS] {
        prims.par_chunks(PARALLEL_CHUNK).map(|chunk| self.fill(chunk)).reduce(
            || [Bin::EMPTY; BINS],
            |mut a, b| {
                for (a, b) in a.iter_mut().zip(&b) {
                    a.merge(b);
                }
                a
            },
        )
    }
}

/// The SAH split of `run` (the primitives of `part`) on `axis` between two of [`BINS`] bins,
/// with `run` reordered so that the left part comes first; `None` if every centre fell in
/// one bin. Large runs are binned on all threads.
fn split_by_sah(run: &mut [PrimRef], part: &Part, axis: usize) -> Option<(Part, Part)> {
    let binning = Binning::new(&part.centres, axis);
    let parallel = run.len() >= PARALLEL_SPLIT;
    let bins = if parallel {
        binning.fill_parallel(run)
    } else {
        binning.fill(run)
    };
    // Areas and counts of every right side, bins k.. (k ≥ 1).
    let mut right = [(0.0f32, 0usize); BINS];
    let mut acc = Bin::EMPTY;
    for k in (1..BINS).rev() {
        acc.merge(&bins[k]);
        right[k] = (acc.bounds.half_area(), acc.count);
    }
    let quads = |n: usize| n.div_ceil(LEAF_SIZE) as f32;
    let mut left = Bin::EMPTY;
    let mut best: Option<(f32, usize)> = None;
    for k in 1..BINS {
        left.merge(&bins[k - 1]);
        let (right_area, right_count) = right[k];
        if left.count == 0 || right_count == 0 {
            continue;
        }
        let cost = quads(left.count) * left.bounds.half_area() + quads(right_count) * right_area;
        if best.is_none_or(|(c, _)| cost < c) {
            best = Some((cost, k));
        }
    }
    let (_, k) = best?;
    let goes_left = |p: &PrimRef| binning.of(p) < k;
    let mid = partition(run, goes_left);
    let mut sides = [Bin::EMPTY; 2];
    for (b, bin) in bins.iter().enumerate() {
        sides[usize::from(b >= k)].merge(bin);
    }
    let depth = part.depth + 1;
    Some((
        Part::with(&sides[0], part.start, part.start + mid, depth),
        Part::with(&sides[1], part.start + mid, part.end, depth),
    ))
}

/// Reorders `run` so that the primitives `goes_left` takes come first; returns how many.
///
/// Without a branch on the answer (a coin toss near the cut, which mispredicted branches made
/// the larger part of the build): every element is swapped with the first element of the right
/// side found so far, and the left side grows by one when it goes left. When it goes right, the
/// swap exchanges two right-side elements, which leaves the order's invariant as it was.
fn partition(run: &mut [PrimRef], goes_left: impl Fn(&PrimRef) -> bool) -> usize {
    let mut left = 0;
    for i in 0..run.len() {
        let goes = goes_left(&run[i]);
        run.swap(i, left);
        left += usize::from(goes);
    }
    left
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_random::XorShift32;

    /// Checks that every triangle is in exactly one leaf, that each leaf's box holds its
    /// triangles' padded boxes, and each node's boxes lie within the box its parent gives it;
    /// returns the tree's 4-wide depth as walked.
    fn check(tree: &WideBvh, triangles: &[[Vec3A; 3]]) -> u32 {
        let within = |inner: &Aabb, outer: &Aabb| inner.min.cmpge(outer.min).all() && inner.max.cmple(outer.max).all();
        let slot_box = |node: usize, k: usize| {
            let b = &tree.nodes[node].bounds;
            Aabb::new(
                Vec3A::new(b[0][0][k], b[1][0][k], b[2][0][k]),
                Vec3A::new(b[0][1][k], b[1][1][k], b[2][1][k]),
            )
        };
        let mut seen = vec![0u32; triangles.len()];
        let mut deepest = 0;
        let mut stack = vec![(0usize, Aabb::LARGEST, 1u32)];
        while let Some((node, parent_box, depth)) = stack.pop() {
            deepest = deepest.max(depth);
            for k in 0..4 {
                let child = tree.nodes[node].child[k];
                if child == EMPTY {
                    continue;
                }
                let b = slot_box(node, k);
                assert!(within(&b, &parent_box), "node {node} slot {k} outside its parent's box");
                if child & LEAF != 0 {
                    let quad = (child & !LEAF) as usize;
                    for &p in tree.quad_triangles[quad].iter().filter(|&&p| p != EMPTY) {
                        seen[p as usize] += 1;
                        assert!(
                            within(&padded_box(&triangles[p as usize]), &b),
                            "triangle {p} outside its leaf"
                        );
                    }
                } else {
                    stack.push((child as usize, b, depth + 1));
                }
            }
        }
        assert!(seen.iter().all(|&s| s == 1), "every triangle in exactly one leaf");
        assert_eq!(deepest, tree.depth());
        deepest
    }

    fn random_triangles(n: usize, seed: u32) -> Vec<[Vec3A; 3]> {
        let mut rng = XorShift32::new(seed);
        (0..n)
            .map(|_| {
                let c = Vec3A::new(rng.unit(), rng.unit(), rng.unit()) * 200.0;
                [0, 1, 2].map(|_| c + Vec3A::new(rng.unit(), rng.unit(), rng.unit()) * 3.0)
            })
            .collect()
    }

    #[test]
    fn every_triangle_lands_in_one_leaf_inside_its_boxes() {
        for n in [1, 3, 4, 5, 17, 1000, 40_000] {
            let triangles = random_triangles(n, 7 + n as u32);
            let depth = check(&build(&triangles), &triangles);
            // ⌈log₄(n/4)⌉ is the least a 4-wide tree can have; SAH trees come close.
            assert!(
                depth <= 2 + 2 * (n as f32).log(4.0).ceil() as u32,
                "{n} triangles: depth {depth}"
            );
        }
    }

    #[test]
    fn the_tree_does_not_depend_on_the_thread_count() {
        let triangles = random_triangles(60_000, 3);
        let on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            let tree = pool.install(|| build(&triangles));
            let nodes: Vec<_> = tree
                .nodes
                .iter()
                .map(|n| {
                    (
                        n.child,
                        n.bounds.map(|axis| axis.map(|v| v.to_array().map(f32::to_bits))),
                    )
                })
                .collect();
            (nodes, tree.quad_triangles.clone(), tree.depth())
        };
        let one = on(1);
        assert!(one.0.len() > 1000);
        assert_eq!(one, on(2));
        assert_eq!(one, on(3));
    }

    #[test]
    fn hostile_centres_keep_the_tree_bounded() {
        // Centres spread so unevenly that SAH would peel off one triangle per level, all
        // centres at one point, and a fan of 30,000 triangles sharing a vertex.
        let tiny = |c: Vec3A| [c, c + Vec3A::X * 1e-3, c + Vec3A::Y * 1e-3];
        let spread: Vec<_> = (0..20_000).map(|k| tiny(Vec3A::X * (k as f32).powi(6))).collect();
        let stacked: Vec<_> = (0..5_000).map(|_| tiny(Vec3A::ZERO)).collect();
        let fan: Vec<_> = (0..30_000)
            .map(|k| {
                let angle = |k: usize| k as f32 / 30_000.0 * std::f32::consts::TAU;
                let at = |a: f32| Vec3A::new(a.cos(), a.sin(), 0.0) * 100.0;
                [Vec3A::ZERO, at(angle(k)), at(angle(k + 1))]
            })
            .collect();
        for (name, triangles) in [("spread", spread), ("stacked", stacked), ("fan", fan)] {
            let depth = check(&build(&triangles), &triangles);
            assert!(depth <= MAX_SAH_DEPTH + 20, "{name}: depth {depth}");
        }
    }
}
