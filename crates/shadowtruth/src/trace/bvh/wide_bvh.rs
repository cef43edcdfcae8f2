//! The tree the walks traverse: eight children per node, each child's box stored as exact f32
//! planes, one array of eight per plane, so that a node test loads them as they lie.
//!
//! Its shape is that of the CWBVH the builder makes (cwbvh_convert.rs): the same nodes, the
//! same leaves of up to three primitives, the same primitive order. Only the boxes differ: the
//! CWBVH stores each child's box quantized to 8 bits per axis, which the node test would have to
//! dequantize and widen by the dequantization's rounding on every visit; here each child's box
//! is the exact f32 box of the primitives beneath it (a minimum and maximum of f32 coordinates
//! rounds nothing), so the node test has only its own slab arithmetic to bound (node_test.rs).

use glam::Vec3A;
use obvhs::cwbvh::CwBvh;
use rayon::prelude::*;

/// One node: the boxes of its eight children, plane by plane, and where each child leads.
/// Empty slots hold an inverted box (+∞ below, −∞ above), which every ray misses.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub(in crate::trace) struct WideNode {
    /// `lo[axis][child]`: each child's minimum plane along an axis.
    pub(in crate::trace) lo: [[f32; 8]; 3],
    /// `hi[axis][child]`: each child's maximum plane along an axis.
    pub(in crate::trace) hi: [[f32; 8]; 3],
    pub(in crate::trace) child: [ChildRef; 8],
}

/// Where a child leads: an inner node, or a leaf's run of primitives in tree order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[repr(transparent)]
pub(in crate::trace) struct ChildRef(u32);

/// The leaf flag of a `ChildRef`; below it, the leaf's first primitive (shifted by 2) and its
/// count less one (2 bits: a leaf holds at most four).
const LEAF: u32 = 1 << 31;
/// The most primitives a tree may have: a leaf's first primitive has 29 bits.
pub(in crate::trace) const MAX_PRIMITIVES: usize = 1 << 29;

impl ChildRef {
    pub(in crate::trace) const ROOT: ChildRef = ChildRef(0);
    /// An empty slot: node 0 is the root, which is no node's child.
    pub(in crate::trace) const EMPTY: ChildRef = ChildRef(0);

    fn node(index: u32) -> Self {
        debug_assert!(index < LEAF);
        ChildRef(index)
    }

    fn leaf(first: u32, count: u32) -> Self {
        debug_assert!((1..=4).contains(&count) && (first as usize) < MAX_PRIMITIVES);
        ChildRef(LEAF | first << 2 | (count - 1))
    }

    #[inline(always)]
    pub(in crate::trace) fn is_leaf(self) -> bool {
        self.0 & LEAF != 0
    }

    /// The node's index (an inner child only).
    #[inline(always)]
    pub(in crate::trace) fn index(self) -> usize {
        self.0 as usize
    }

    /// The leaf's primitives, in tree order (a leaf child only).
    #[inline(always)]
    pub(in crate::trace) fn primitives(self) -> std::ops::Range<usize> {
        let first = ((self.0 & !LEAF) >> 2) as usize;
        first..first + (self.0 & 3) as usize + 1
    }
}

/// A tree of `WideNode`s; node 0 is the root. Empty for a scene without primitives.
#[derive(Default)]
pub(in crate::trace) struct WideBvh {
    pub(in crate::trace) nodes: Vec<WideNode>,
}

impl WideBvh {
    /// The tree of `cwbvh`, with each child's box the exact union of `bounds(i)` over the
    /// primitives `i` (in tree order) beneath it.
    pub(in crate::trace) fn from_cwbvh(
        cwbvh: &CwBvh,
        bounds: impl Fn(usize) -> (Vec3A, Vec3A) + Sync,
    ) -> Self {
        assert!(
            cwbvh.primitive_indices.len() <= MAX_PRIMITIVES,
            "a tree holds at most {MAX_PRIMITIVES} primitives, not {}",
            cwbvh.primitive_indices.len()
        );
        let mut nodes: Vec<WideNode> = cwbvh
            .nodes
            .par_iter()
            .map(|node| {
                let mut wide = WideNode::EMPTY;
                for c in 0..8 {
                    if node.is_child_empty(c) {
                        continue;
                    }
                    if node.is_leaf(c) {
                        let (first, count) = node.child_primitives(c);
                        let range = first as usize..(first + count) as usize;
                        let (lo, hi) = range.map(&bounds).fold(EMPTY_BOX, union);
                        wide.set(c, ChildRef::leaf(first, count), lo, hi);
                    } else {
                        wide.child[c] = ChildRef::node(node.child_node_index(c));
                    }
                }
                wide
            })
            .collect();
        // A node's inner children lie after it (the conversion writes a node before its
        // children), so a backward pass meets every child's box before its parent needs it.
        for parent in (0..nodes.len()).rev() {
            for c in 0..8 {
                let child = nodes[parent].child[c];
                if child.is_leaf() || child == ChildRef::EMPTY {
                    continue;
                }
                assert!(child.index() > parent, "the CWBVH lists a child before its parent");
                let (lo, hi) = nodes[child.index()].bounds();
                nodes[parent].set(c, child, lo, hi);
            }
        }
        WideBvh { nodes }
    }

    /// The root's box (all of the tree's primitives), or `None` for an empty tree.
    #[cfg(test)]
    pub(in crate::trace) fn bounds(&self) -> Option<(Vec3A, Vec3A)> {
        self.nodes.first().map(WideNode::bounds)
    }
}

const EMPTY_BOX: (Vec3A, Vec3A) = (Vec3A::INFINITY, Vec3A::NEG_INFINITY);

fn union(a: (Vec3A, Vec3A), b: (Vec3A, Vec3A)) -> (Vec3A, Vec3A) {
    (a.0.min(b.0), a.1.max(b.1))
}

impl WideNode {
    const EMPTY: WideNode = WideNode {
        lo: [[f32::INFINITY; 8]; 3],
        hi: [[f32::NEG_INFINITY; 8]; 3],
        child: [ChildRef::EMPTY; 8],
    };

    fn set(&mut self, c: usize, child: ChildRef, lo: Vec3A, hi: Vec3A) {
        self.child[c] = child;
        for axis in 0..3 {
            self.lo[axis][c] = lo[axis];
            self.hi[axis][c] = hi[axis];
        }
    }

    /// The union of the children's boxes.
    fn bounds(&self) -> (Vec3A, Vec3A) {
        let lo = Vec3A::from_array(std::array::from_fn(|axis| {
            self.lo[axis].iter().copied().fold(f32::INFINITY, f32::min)
        }));
        let hi = Vec3A::from_array(std::array::from_fn(|axis| {
            self.hi[axis].iter().copied().fold(f32::NEG_INFINITY, f32::max)
        }));
        (lo, hi)
    }
}

#[cfg(target_arch = "x86_64")]
impl WideBvh {
    /// Where each of the tree's `primitives` (in tree order) hangs: the index of the node that
    /// holds its leaf, times eight, plus the leaf's slot there (`leaf_box`). A tree has fewer
    /// nodes than primitives (`MAX_PRIMITIVES`), so this fits a u32.
    pub(in crate::trace) fn leaf_slots(&self, primitives: usize) -> Vec<u32> {
        let mut slots = vec![u32::MAX; primitives];
        for (n, node) in self.nodes.iter().enumerate() {
            for (c, child) in node.child.iter().enumerate() {
                if child.is_leaf() {
                    child.primitives().for_each(|i| slots[i] = (n * 8 + c) as u32);
                }
            }
        }
        slots
    }

    /// The node and the slot of a leaf, from `leaf_slots`.
    #[inline(always)]
    pub(in crate::trace) fn leaf_box(&self, leaf_slot: u32) -> (&WideNode, usize) {
        (&self.nodes[leaf_slot as usize / 8], leaf_slot as usize % 8)
    }
}

/// Depth of a tree in nodes (root = 1), by walking it.
pub(in crate::trace) fn tree_depth(tree: &WideBvh) -> usize {
    if tree.nodes.is_empty() {
        return 0;
    }
    let mut deepest = 0;
    let mut todo = vec![(0usize, 1usize)];
    while let Some((index, depth)) = todo.pop() {
        deepest = deepest.max(depth);
        for &child in &tree.nodes[index].child {
            if !child.is_leaf() && child != ChildRef::EMPTY {
                todo.push((child.index(), depth + 1));
            }
        }
    }
    deepest
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trace::SceneBvh;
    use crate::trace::bvh::flat_tree::FlatTree;
    use crate::trace::splitmix::SplitMix64;
    use glam::Vec3;

    /// Every child's box is exactly the box of the triangles beneath it, and every triangle
    /// lies beneath exactly one leaf; a scene's tree holds those boxes grown by its segment
    /// margin (`SceneBvh::build`), never less.
    #[test]
    fn child_boxes_are_the_exact_boxes_of_their_triangles() {
        let mut rng = SplitMix64::new(3);
        let mut point = || Vec3::from_array(std::array::from_fn(|_| rng.range([-10.0, 10.0]) as f32));
        let tris: Vec<[Vec3; 3]> = (0..5000)
            .map(|_| {
                let c = point();
                [c, c + point() * 0.1, c + point() * 0.1]
            })
            .collect();
        let exact = FlatTree::build(&tris, 0.0);
        let mut seen = vec![0u32; tris.len()];
        let root = subtree_box(&exact.tree, 0, &exact.triangles, &mut seen);
        assert_eq!(exact.tree.bounds(), Some(root));
        assert!(seen.iter().all(|&n| n == 1), "each triangle in exactly one leaf");
        let bvh = SceneBvh::build_from_triangles(&tris);
        let (lo, hi) = bvh.tree.bounds().expect("a tree");
        // The points reach a little past 10 (a corner plus a tenth of another point).
        let reach = tris.iter().flatten().fold(0.0f32, |m, v| m.max(v.abs().max_element()));
        // 2⁻²³ of the reach plus the diagonal of the triangles' box (`segment_margin`).
        let diagonal = (root.1 - root.0).as_dvec3().length();
        let margin = ((reach as f64 + diagonal) * 2f64.powi(-23)) as f32;
        assert!(
            lo.cmple(root.0 - Vec3A::splat(margin)).all() && hi.cmpge(root.1 + Vec3A::splat(margin)).all()
        );
        // The sum rounds to nearest, then one step outwards: two ulps of a coordinate.
        let most = Vec3A::splat(margin + 2.0 * reach * f32::EPSILON);
        assert!(
            lo.cmpge(root.0 - most).all() && hi.cmple(root.1 + most).all(),
            "grown by the margin, not more: {lo} {hi} {root:?}"
        );
    }

    /// The exact box of node `index`'s triangles, checking each child's stored box on the way.
    fn subtree_box(tree: &WideBvh, index: usize, tris: &[[Vec3; 3]], seen: &mut [u32]) -> (Vec3A, Vec3A) {
        let node = &tree.nodes[index];
        let mut all = EMPTY_BOX;
        for c in 0..8 {
            let child = node.child[c];
            let stored = (
                Vec3A::from_array(std::array::from_fn(|a| node.lo[a][c])),
                Vec3A::from_array(std::array::from_fn(|a| node.hi[a][c])),
            );
            let exact = if child == ChildRef::EMPTY {
                EMPTY_BOX
            } else if child.is_leaf() {
                child.primitives().fold(EMPTY_BOX, |b, i| {
                    seen[i] += 1;
                    let [p, q, r] = tris[i].map(Vec3A::from);
                    union(b, (p.min(q).min(r), p.max(q).max(r)))
                })
            } else {
                subtree_box(tree, child.index(), tris, seen)
            };
            assert_eq!(stored, exact, "node {index}, child {c}");
            all = union(all, exact);
        }
        all
    }
}
