//! The walk down a wide tree (wide_bvh.rs): which leaves a ray reaches, in which order.
//!
//! Closest hits walk nearest first: a node's children that the ray may meet go on the stack
//! farthest first, with the distance at which the ray enters each, and a child entered beyond
//! the nearest hit found so far is dropped when popped. Any-hit walks (shadow rays) take the
//! children in the order they lie in the node: ordering them costs more than it saves when any
//! occluder ends the walk (tests/node_test_forms.rs keeps the two node-test forms' answers
//! equal; the order is the same in both). Packets take the slots in the order of their rays'
//! octant instead, which costs a xor (packet.rs).

use super::node_test::{self, NodeHits, NodeRay};
use super::wide_bvh::{ChildRef, WideBvh, WideNode};

/// `walk::<NEAREST_FIRST>`: children in the order the ray enters them (closest hits).
pub(in crate::trace) const NEAREST_FIRST: bool = true;
/// `walk::<ANY_ORDER>`: children in node order (any hit ends the walk).
pub(in crate::trace) const ANY_ORDER: bool = false;

/// The state of one walk down one tree: its stack of children still to visit (with the distance
/// at which the ray may enter each, for nearest-first walks).
pub(in crate::trace) struct WalkState {
    nearest: Box<[(ChildRef, f32)]>,
    any: Box<[ChildRef]>,
}

impl WalkState {
    /// Stacks that a walk of a tree `depth` nodes deep never outgrows: each node on the way down
    /// leaves at most seven children behind, and (nearest first) its eighth is pushed before one
    /// is popped.
    pub(in crate::trace) fn new(depth: usize) -> Self {
        WalkState {
            nearest: vec![(ChildRef::ROOT, 0.0); 7 * depth + 1].into_boxed_slice(),
            any: vec![ChildRef::ROOT; 7 * depth + 1].into_boxed_slice(),
        }
    }
}

/// Walks the nodes of `tree` that the ray may meet within [tmin, *tmax] (tmin ≥ 0), their
/// boxes widened by `margin` more, and calls `leaf(i, tmax)` for each primitive `i` (in tree
/// order) of the leaves it reaches. `leaf` may shrink `*tmax` (closest hits), and ends the walk
/// by returning true. Where the processor has AVX2 and the ray moves along every axis, the node
/// test takes eight children at once (node_test.rs); its answers and the order are the same.
#[inline(always)]
pub(in crate::trace) fn walk<const NEAREST: bool>(
    tree: &WideBvh,
    state: &mut WalkState,
    ray: &NodeRay,
    tmin: f32,
    tmax: &mut f32,
    margin: f32,
    leaf: impl FnMut(usize, &mut f32) -> bool,
) {
    debug_assert!(tmin >= 0.0, "the node test needs tmin ≥ 0");
    if tree.nodes.is_empty() {
        return;
    }
    #[cfg(target_arch = "x86_64")]
    if ray.all_axes_move() && super::packet_isa::wide_available() {
        // SAFETY: the processor has AVX2 (checked at run time).
        unsafe { walk_wide::<NEAREST>(tree, state, ray, tmin, tmax, margin, leaf) };
        return;
    }
    let nodes = &tree.nodes;
    match margin > 0.0 {
        true => visit::<NEAREST>(nodes, state, tmax, leaf, |node, tmax| {
            node_test::intersect_node::<true>(node, ray, tmin, tmax, margin)
        }),
        false => visit::<NEAREST>(nodes, state, tmax, leaf, |node, tmax| {
            node_test::intersect_node::<false>(node, ray, tmin, tmax, 0.0)
        }),
    }
}

/// `walk` with the 8-lane node test, compiled for AVX2 as a whole so that the test is inlined
/// into the loop. (A closure inside it is compiled with AVX2 too, so it may call the test.)
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn walk_wide<const NEAREST: bool>(
    tree: &WideBvh,
    state: &mut WalkState,
    ray: &NodeRay,
    tmin: f32,
    tmax: &mut f32,
    margin: f32,
    leaf: impl FnMut(usize, &mut f32) -> bool,
) {
    let wide = node_test::WideRay::new(ray);
    let nodes = &tree.nodes;
    match margin > 0.0 {
        true => visit::<NEAREST>(nodes, state, tmax, leaf, |node, tmax| {
            node_test::intersect_node_wide::<true>(node, &wide, tmin, tmax, margin)
        }),
        false => visit::<NEAREST>(nodes, state, tmax, leaf, |node, tmax| {
            node_test::intersect_node_wide::<false>(node, &wide, tmin, tmax, 0.0)
        }),
    }
}

/// The walk's loop for either order, over any form of the node test (`test(node, tmax)`).
#[inline(always)]
fn visit<const NEAREST: bool>(
    nodes: &[WideNode],
    state: &mut WalkState,
    tmax: &mut f32,
    leaf: impl FnMut(usize, &mut f32) -> bool,
    test: impl Fn(&WideNode, f32) -> NodeHits,
) {
    if NEAREST {
        walk_loop(nodes, NearestFirst { stack: &mut state.nearest, depth: 0 }, tmax, leaf, test);
    } else {
        walk_loop(nodes, AnyOrder { stack: &mut state.any, depth: 0 }, tmax, leaf, test);
    }
}

/// The loop: a leaf's primitives go to `leaf`, an inner node's children that the ray may meet
/// to the stack, which says which child is next.
#[inline(always)]
fn walk_loop(
    nodes: &[WideNode],
    mut stack: impl ChildStack,
    tmax: &mut f32,
    mut leaf: impl FnMut(usize, &mut f32) -> bool,
    test: impl Fn(&WideNode, f32) -> NodeHits,
) {
    let mut current = Some(ChildRef::ROOT);
    while let Some(child) = current {
        if child.is_leaf() {
            for i in child.primitives() {
                if leaf(i, tmax) {
                    return;
                }
            }
        } else {
            let node = &nodes[child.index()];
            let hits = test(node, *tmax);
            if hits.mask != 0 {
                current = Some(stack.push(node, &hits));
                continue;
            }
        }
        current = stack.pop(*tmax);
    }
}

/// A walk's stack of children still to visit, and the order it visits them in.
trait ChildStack {
    /// Pushes the children in `hits` (at least one) but the one to visit next, and returns it.
    fn push(&mut self, node: &WideNode, hits: &NodeHits) -> ChildRef;
    /// The next child to visit, given how far the ray still looks; `None` ends the walk.
    fn pop(&mut self, tmax: f32) -> Option<ChildRef>;
}

/// Nearest first: the children stacked with the distance at which the ray enters them,
/// farthest first, and dropped when popped if the ray no longer looks that far.
struct NearestFirst<'a> {
    stack: &'a mut [(ChildRef, f32)],
    depth: usize,
}

impl ChildStack for NearestFirst<'_> {
    /// The children are sorted in place on top of the stack (insertion: a node has few hit
    /// children).
    #[inline(always)]
    fn push(&mut self, node: &WideNode, hits: &NodeHits) -> ChildRef {
        let mut mask = hits.mask;
        if mask & (mask - 1) == 0 {
            return node.child[mask.trailing_zeros() as usize];
        }
        let base = self.depth;
        while mask != 0 {
            let c = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            let entry = (node.child[c], hits.enter[c]);
            let mut k = self.depth;
            while k > base && self.stack[k - 1].1 < entry.1 {
                self.stack[k] = self.stack[k - 1];
                k -= 1;
            }
            self.stack[k] = entry;
            self.depth += 1;
        }
        self.depth -= 1;
        self.stack[self.depth].0
    }

    #[inline(always)]
    fn pop(&mut self, tmax: f32) -> Option<ChildRef> {
        while self.depth > 0 {
            self.depth -= 1;
            let (child, enter) = self.stack[self.depth];
            if enter <= tmax {
                return Some(child);
            }
        }
        None
    }
}

/// Node order: the children pushed as they lie in the node but the last, which is next.
struct AnyOrder<'a> {
    stack: &'a mut [ChildRef],
    depth: usize,
}

impl ChildStack for AnyOrder<'_> {
    #[inline(always)]
    fn push(&mut self, node: &WideNode, hits: &NodeHits) -> ChildRef {
        let mut mask = hits.mask;
        loop {
            let child = node.child[mask.trailing_zeros() as usize];
            mask &= mask - 1;
            if mask == 0 {
                return child;
            }
            self.stack[self.depth] = child;
            self.depth += 1;
        }
    }

    #[inline(always)]
    fn pop(&mut self, _tmax: f32) -> Option<ChildRef> {
        self.depth = self.depth.checked_sub(1)?;
        Some(self.stack[self.depth])
    }
}
