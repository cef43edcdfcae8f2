//! Binary tree to compressed 8-wide BVH, on every core and in little memory.
//!
//! The same conversion as obvhs 0.4's `bvh2_to_cwbvh` (Ylitie et al. 2017: a bottom-up cost
//! table chooses which binary nodes become wide nodes, leaves of up to three triangles, or are
//! distributed into their parent; children are ordered by ray octant), producing the same tree
//! bit for bit (the tests below compare them), with two differences that matter at ten million
//! triangles:
//! - obvhs keeps seven 8-byte decisions per binary node (112 bytes per triangle, the largest
//!   block alive during a build); we keep seven 1-byte decisions per node and pass costs up the
//!   recursion instead of storing them;
//! - obvhs converts on one thread; we cost subtrees in parallel and convert the top wide levels'
//!   subtrees in parallel, then join them in the order obvhs would have written them.

use glam::{Vec3A, vec3a};
use obvhs::aabb::Aabb;
use obvhs::bvh2::Bvh2;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::node::CwBvhNode;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

/// Surface-area cost of a triangle relative to a node visit (obvhs's `PRIM_COST`).
const PRIM_COST: f32 = 0.3;
/// Triangles per wide-tree leaf: three is the most the leaf encoding holds.
const MAX_PRIMS_PER_LEAF: u32 = 3;
/// Child boxes are quantized to 8 bits per axis: 255 steps of a power of two.
const QUANTIZATION_STEPS: f32 = 255.0;
/// The cost pass forks both children of binary nodes shallower than this.
const PARALLEL_COST_DEPTH: u32 = 12;
/// The conversion forks the subtrees of the top wide levels (up to 8³ tasks).
const PARALLEL_WIDE_LEVELS: u32 = 3;

/// What a binary node becomes when `i + 1` wide-node slots are available to its subtree.
#[derive(Clone, Copy, PartialEq, Debug)]
enum Kind {
    /// All its triangles in one leaf.
    Leaf,
    /// A wide node of its own.
    Internal,
    /// Its two children share the slots, `left` + `right` + 2 = `i` + 2 of them.
    Distribute,
}

#[derive(Clone, Copy, PartialEq, Debug)]
struct Decision {
    kind: Kind,
    left: u8,
    right: u8,
}

impl Decision {
    const LEAF: Decision = Decision { kind: Kind::Leaf, left: 0, right: 0 };

    /// Two bits of kind, three of each slot count (0..=6).
    fn pack(self) -> u8 {
        let kind = match self.kind {
            Kind::Leaf => 0,
            Kind::Internal => 1,
            Kind::Distribute => 2,
        };
        kind << 6 | self.left << 3 | self.right
    }

    fn unpack(byte: u8) -> Decision {
        let kind = match byte >> 6 {
            0 => Kind::Leaf,
            1 => Kind::Internal,
            _ => Kind::Distribute,
        };
        Decision { kind, left: (byte >> 3) & 7, right: byte & 7 }
    }
}

/// Converts `bvh2` (one triangle per leaf, as PLOC builds it) to a CWBVH with children ordered
/// by octant, equal to obvhs's `bvh2_to_cwbvh(bvh2, 3, true, false)`.
pub(in crate::trace) fn bvh2_to_cwbvh(bvh2: &Bvh2) -> CwBvh {
    if bvh2.nodes.is_empty() {
        return CwBvh::default();
    }
    let converter = Converter { bvh2, decisions: (0..bvh2.nodes.len()).map(|_| AtomicU64::new(0)).collect() };
    converter.cost(0, 0);
    let tree = converter.subtree(0, PARALLEL_WIDE_LEVELS);
    CwBvh {
        nodes: tree.nodes,
        primitive_indices: tree.primitives,
        total_aabb: *bvh2.nodes[0].aabb(),
        exact_node_aabbs: None,
        uses_spatial_splits: bvh2.uses_spatial_splits,
    }
}

struct Converter<'a> {
    bvh2: &'a Bvh2,
    /// Per binary node, its seven decisions packed one per byte. Written once each by the cost
    /// pass (in parallel, so atomics; relaxed, since the join orders them before the reads).
    decisions: Vec<AtomicU64>,
}

/// A converted subtree: `nodes[0]` is its root; child and primitive indices count from the
/// subtree's own start.
struct Subtree {
    nodes: Vec<CwBvhNode>,
    primitives: Vec<u32>,
}

impl Subtree {
    /// Appends the root's converted internal children as obvhs lays them out: their roots side
    /// by side at index 1 (where the root's `child_base_idx` points), then each one's
    /// descendants, with their indices moved to where they land.
    fn append_children(&mut self, children: Vec<Subtree>) {
        let nodes: usize = children.iter().map(|c| c.nodes.len()).sum();
        self.nodes.reserve(nodes);
        let mut descendants_at = 1 + children.len() as u32;
        let mut primitives_at = self.primitives.len() as u32;
        let mut offsets = Vec::with_capacity(children.len());
        for child in &children {
            offsets.push((descendants_at, primitives_at));
            self.nodes.push(moved(child.nodes[0], descendants_at, primitives_at));
            descendants_at += child.nodes.len() as u32 - 1;
            primitives_at += child.primitives.len() as u32;
        }
        for (child, (descendants_at, primitives_at)) in children.into_iter().zip(offsets) {
            self.nodes.extend(child.nodes[1..].iter().map(|&n| moved(n, descendants_at, primitives_at)));
            self.primitives.extend_from_slice(&child.primitives);
        }
    }
}

/// A node of a subtree whose descendants (from its index 1) now start at `descendants_at` and
/// whose primitives start at `primitives_at`.
fn moved(mut node: CwBvhNode, descendants_at: u32, primitives_at: u32) -> CwBvhNode {
    node.child_base_idx = node.child_base_idx - 1 + descendants_at;
    node.primitive_base_idx += primitives_at;
    node
}

impl Converter<'_> {
    fn decision(&self, node_index: u32, slots: u8) -> Decision {
        let packed = self.decisions[node_index as usize].load(Relaxed);
        Decision::unpack((packed >> (8 * slots)) as u8)
    }

    /// Fills the decisions of `node_index`'s subtree; returns its seven costs and its triangle
    /// count. The arithmetic is obvhs's, in its order, so that ties fall the same way.
    fn cost(&self, node_index: u32, depth: u32) -> ([f32; 7], u32) {
        let node = &self.bvh2.nodes[node_index as usize];
        let half_area = node.aabb().half_area();
        if node.is_leaf() {
            assert_eq!(node.prim_count, 1, "the wide conversion needs one triangle per leaf");
            self.store(node_index, [Decision::LEAF; 7]);
            return ([half_area * PRIM_COST; 7], 1);
        }
        let (left, right) = (node.first_index, node.first_index + 1);
        let ((left_cost, left_count), (right_cost, right_count)) = if depth < PARALLEL_COST_DEPTH {
            rayon::join(|| self.cost(left, depth + 1), || self.cost(right, depth + 1))
        } else {
            (self.cost(left, depth + 1), self.cost(right, depth + 1))
        };
        let count = left_count + right_count;
        let (costs, decisions) = choose(half_area, count, &left_cost, &right_cost);
        self.store(node_index, decisions);
        (costs, count)
    }

    fn store(&self, node_index: u32, decisions: [Decision; 7]) {
        let packed = decisions.iter().rev().fold(0u64, |all, d| all << 8 | u64::from(d.pack()));
        self.decisions[node_index as usize].store(packed, Relaxed);
    }

    /// Converts the subtree under binary node `bvh2_index`, forking its internal children's
    /// subtrees while `levels` remain.
    fn subtree(&self, bvh2_index: u32, levels: u32) -> Subtree {
        let mut tree = Subtree { nodes: vec![CwBvhNode::default()], primitives: Vec::new() };
        if levels == 0 {
            self.fill(&mut tree, 0, bvh2_index);
            return tree;
        }
        let (root, internal, count) = self.wide_node(bvh2_index, 1, &mut tree.primitives);
        tree.nodes[0] = root;
        let children: Vec<Subtree> =
            internal[..count].par_iter().map(|&child| self.subtree(child, levels - 1)).collect();
        tree.append_children(children);
        tree
    }

    /// obvhs's depth-first layout: a node's internal children side by side, then each child's
    /// subtree in slot order.
    fn fill(&self, tree: &mut Subtree, slot: usize, bvh2_index: u32) {
        let child_base = tree.nodes.len() as u32;
        let (node, internal, count) = self.wide_node(bvh2_index, child_base, &mut tree.primitives);
        tree.nodes[slot] = node;
        tree.nodes.resize(tree.nodes.len() + count, CwBvhNode::default());
        for (offset, &child) in internal[..count].iter().enumerate() {
            self.fill(tree, child_base as usize + offset, child);
        }
    }

    /// The wide node for binary node `bvh2_index`: its children's quantized boxes and slots,
    /// the triangles of its leaf children appended to `primitives`; returns it with its internal
    /// children's binary indices in slot order, and their count.
    fn wide_node(
        &self,
        bvh2_index: u32,
        child_base: u32,
        primitives: &mut Vec<u32>,
    ) -> (CwBvhNode, [u32; 8], usize) {
        let aabb = self.bvh2.nodes[bvh2_index as usize].aabb();
        let (mut node, scale) = quantization_frame(aabb);
        node.child_base_idx = child_base;
        node.primitive_base_idx = primitives.len() as u32;
        let mut children = [u32::MAX; 8];
        let mut count = 0;
        self.gather_children(bvh2_index, 0, &mut children, &mut count);
        order_children(self.bvh2, aabb, &mut children, count);
        let (mut internal, mut internal_count) = ([u32::MAX; 8], 0);
        let mut primitive_offset = 0u32;
        for (slot, &child) in children.iter().enumerate().filter(|(_, c)| **c != u32::MAX) {
            quantize_child(&mut node, slot, self.bvh2.nodes[child as usize].aabb(), scale);
            if self.decision(child, 0).kind == Kind::Leaf {
                let before = primitives.len();
                self.leaf_primitives(child, primitives);
                let leaf_count = (primitives.len() - before) as u32;
                node.child_meta[slot] = primitive_offset as u8 | unary_count(leaf_count);
                primitive_offset += leaf_count;
            } else {
                node.imask |= 1 << slot;
                node.child_meta[slot] = (24 + slot as u8) | 0b0010_0000;
                internal[internal_count] = child;
                internal_count += 1;
            }
        }
        (node, internal, internal_count)
    }

    /// The binary nodes that become the wide node's children: those its decisions do not
    /// distribute further.
    fn gather_children(&self, bvh2_index: u32, slots: u8, children: &mut [u32; 8], count: &mut usize) {
        let node = &self.bvh2.nodes[bvh2_index as usize];
        if node.is_leaf() {
            children[*count] = bvh2_index;
            *count += 1;
            return;
        }
        let split = self.decision(bvh2_index, slots);
        for (child, child_slots) in [(node.first_index, split.left), (node.first_index + 1, split.right)] {
            if self.decision(child, child_slots).kind == Kind::Distribute {
                self.gather_children(child, child_slots, children, count);
            } else {
                children[*count] = child;
                *count += 1;
            }
        }
    }

    fn leaf_primitives(&self, bvh2_index: u32, primitives: &mut Vec<u32>) {
        let node = &self.bvh2.nodes[bvh2_index as usize];
        if node.is_leaf() {
            primitives.push(self.bvh2.primitive_indices[node.first_index as usize]);
        } else {
            self.leaf_primitives(node.first_index, primitives);
            self.leaf_primitives(node.first_index + 1, primitives);
        }
    }
}

/// The costs and decisions of an internal binary node from its children's (Ylitie et al.
/// 2017, section 4; obvhs's `calculate_cost_impl`).
fn choose(half_area: f32, count: u32, left: &[f32; 7], right: &[f32; 7]) -> ([f32; 7], [Decision; 7]) {
    let mut costs = [0.0f32; 7];
    let mut decisions = [Decision::LEAF; 7];
    let cost_leaf =
        if count <= MAX_PRIMS_PER_LEAF { (count as f32) * half_area * PRIM_COST } else { f32::INFINITY };
    // Slot counts 6 and 0 are always a valid split, so a tree with infinite areas still decodes.
    let (mut cost_distribute, mut split) = (f32::INFINITY, (0, 6));
    for k in 0..7 {
        let c = left[k] + right[6 - k];
        if c < cost_distribute {
            cost_distribute = c;
            split = (k as u8, 6 - k as u8);
        }
    }
    let cost_internal = cost_distribute + half_area;
    let kind = if cost_leaf < cost_internal { Kind::Leaf } else { Kind::Internal };
    costs[0] = if kind == Kind::Leaf { cost_leaf } else { cost_internal };
    decisions[0] = Decision { kind, left: split.0, right: split.1 };
    for i in 1..7 {
        let (mut cost_distribute, mut split) = (costs[i - 1], None);
        for k in 0..i {
            let c = left[k] + right[i - k - 1];
            if c < cost_distribute {
                cost_distribute = c;
                split = Some((k as u8, (i - k - 1) as u8));
            }
        }
        costs[i] = cost_distribute;
        decisions[i] = match split {
            Some((left, right)) => Decision { kind: Kind::Distribute, left, right },
            None => decisions[i - 1],
        };
    }
    (costs, decisions)
}

/// The node's origin and per-axis power-of-two step, in a node with no children yet.
fn quantization_frame(aabb: &Aabb) -> (CwBvhNode, Vec3A) {
    let step =
        ((aabb.max - aabb.min).max(Vec3A::splat(1e-20)) * (1.0 / QUANTIZATION_STEPS)).log2().ceil().exp2();
    // A power of two: only its exponent bits are set.
    let exponent = step.to_array().map(|s| (s.to_bits() >> 23) as u8);
    let node = CwBvhNode { p: aabb.min.into(), e: exponent, ..CwBvhNode::default() };
    (node, 1.0 / step)
}

/// The child's box rounded outwards to the node's 8-bit grid.
fn quantize_child(node: &mut CwBvhNode, slot: usize, child: &Aabb, scale: Vec3A) {
    let origin = Vec3A::from(node.p);
    let lo = ((child.min - origin) * scale).floor().clamp(Vec3A::ZERO, Vec3A::splat(255.0));
    let hi = ((child.max - origin) * scale).ceil().clamp(Vec3A::ZERO, Vec3A::splat(255.0));
    node.child_min_x[slot] = lo.x as u8;
    node.child_min_y[slot] = lo.y as u8;
    node.child_min_z[slot] = lo.z as u8;
    node.child_max_x[slot] = hi.x as u8;
    node.child_max_y[slot] = hi.y as u8;
    node.child_max_z[slot] = hi.z as u8;
}

/// A leaf's triangle count in the top three bits, unary.
fn unary_count(count: u32) -> u8 {
    match count {
        1 => 0b0010_0000,
        2 => 0b0110_0000,
        3 => 0b1110_0000,
        _ => unreachable!("a leaf holds 1 to 3 triangles, not {count}"),
    }
}

/// Places the children in the slots whose octant direction they lie furthest along, greedily
/// (obvhs's `order_children`), so that traversal can order them by the ray's octant.
fn order_children(bvh2: &Bvh2, parent: &Aabb, children: &mut [u32; 8], count: usize) {
    let centre = parent.center();
    let direction = |s: usize| {
        vec3a(
            if s & 0b100 != 0 { -1.0 } else { 1.0 },
            if s & 0b010 != 0 { -1.0 } else { 1.0 },
            if s & 0b001 != 0 { -1.0 } else { 1.0 },
        )
    };
    let mut cost = [[f32::MAX; 8]; 8];
    for (c, &child) in children[..count].iter().enumerate() {
        let offset = bvh2.nodes[child as usize].aabb().center() - centre;
        for (s, slot_cost) in cost[c].iter_mut().enumerate() {
            *slot_cost = direction(s).dot(offset);
        }
    }
    let mut assignment = [usize::MAX; 8];
    let mut slot_filled = [false; 8];
    loop {
        let mut best: Option<(f32, usize, usize)> = None;
        for c in (0..count).filter(|&c| assignment[c] == usize::MAX) {
            for s in (0..8).filter(|&s| !slot_filled[s]) {
                if cost[c][s] < best.map_or(f32::MAX, |b| b.0) {
                    best = Some((cost[c][s], c, s));
                }
            }
        }
        let Some((_, c, s)) = best else { break };
        slot_filled[s] = true;
        assignment[c] = s;
    }
    let original = std::mem::replace(children, [u32::MAX; 8]);
    for (c, &child) in original[..count].iter().enumerate() {
        children[assignment[c]] = child;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trace::splitmix::SplitMix64;
    use obvhs::BvhBuildParams;
    use obvhs::ploc::PlocBuilder;
    use obvhs::triangle::Triangle;

    fn binary_tree(triangles: &[Triangle]) -> Bvh2 {
        let params = BvhBuildParams::medium_build();
        PlocBuilder::with_capacity(triangles.len()).build(
            params.ploc_search_distance,
            triangles,
            (0..triangles.len() as u32).collect(),
            params.sort_precision,
            params.search_depth_threshold,
        )
    }

    /// The same tree as obvhs's own conversion, node for node and index for index: the
    /// parallel joins, the packed decisions and the ordering change nothing.
    fn assert_same_as_obvhs(triangles: &[Triangle]) {
        let bvh2 = binary_tree(triangles);
        let ours = bvh2_to_cwbvh(&bvh2);
        let theirs = obvhs::cwbvh::bvh2_to_cwbvh::bvh2_to_cwbvh(&bvh2, 3, true, false);
        assert_eq!(ours.nodes.len(), theirs.nodes.len());
        for (i, (a, b)) in ours.nodes.iter().zip(&theirs.nodes).enumerate() {
            assert_eq!(a, b, "node {i} of {}", theirs.nodes.len());
        }
        assert_eq!(ours, theirs);
    }

    fn random_triangles(count: usize, extent: f32, size: f32, seed: u64) -> Vec<Triangle> {
        let mut rng = SplitMix64::new(seed);
        let mut unit = move || rng.next_f64() as f32;
        (0..count)
            .map(|_| {
                let c = Vec3A::new(unit(), unit(), unit()) * extent;
                let mut corner = || c + Vec3A::new(unit(), unit(), unit()) * size;
                Triangle { v0: corner(), v1: corner(), v2: corner() }
            })
            .collect()
    }

    #[test]
    fn equals_obvhs_on_random_soups_of_every_size() {
        for (count, seed) in [(1, 1), (2, 2), (3, 3), (4, 4), (9, 5), (100, 6), (5_000, 7), (60_000, 8)] {
            assert_same_as_obvhs(&random_triangles(count, 100.0, 2.0, seed));
        }
    }

    #[test]
    fn equals_obvhs_on_a_flat_grid_and_on_repeated_triangles() {
        let grid: Vec<Triangle> = (0..200 * 200)
            .flat_map(|i| {
                let (x, z) = ((i % 200) as f32, (i / 200) as f32);
                let v = |dx: f32, dz: f32| Vec3A::new(x + dx, 0.0, z + dz);
                [
                    Triangle { v0: v(0.0, 0.0), v1: v(1.0, 0.0), v2: v(0.0, 1.0) },
                    Triangle { v0: v(1.0, 0.0), v1: v(1.0, 1.0), v2: v(0.0, 1.0) },
                ]
            })
            .collect();
        assert_same_as_obvhs(&grid);
        let same = random_triangles(1, 1.0, 1.0, 9)[0];
        assert_same_as_obvhs(&vec![same; 1_000]);
    }

    #[test]
    fn decisions_survive_packing() {
        for kind in [Kind::Leaf, Kind::Internal, Kind::Distribute] {
            for left in 0..7 {
                for right in 0..7 {
                    let d = Decision { kind, left, right };
                    assert_eq!(Decision::unpack(d.pack()), d);
                }
            }
        }
    }
}
