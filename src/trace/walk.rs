//! The walk down a wide tree (wide_bvh.rs): which leaves a ray reaches, in which order.
//!
//! Closest hits walk nearest first: a node's children that the ray may meet go on the stack
//! farthest first, with the distance at which the ray enters each, and a child entered beyond
//! the nearest hit found so far is dropped when popped. Any-hit walks (shadow rays) take the
//! children in the order they lie in the node: ordering them costs more than it saves when any
//! occluder ends the walk (tests/node_test_forms.rs keeps the two node-test forms' answers equal;
//! the order is the same in both).

use super::node_test::{self, NodeHits, NodeRay};
use super::wide_bvh::{ChildRef, WideBvh, WideNode};

/// `walk::<NEAREST_FIRST>`: children in the order the ray enters them (closest hits).
pub(super) const NEAREST_FIRST: bool = true;
/// `walk::<ANY_ORDER>`: children in node order (any hit ends the walk).
pub(super) const ANY_ORDER: bool = false;

/// The state of one walk down one tree: its stack of children still to visit (with the distance
/// at which the ray may enter each, for nearest-first walks).
pub(super) struct WalkState {
    nearest: Box<[(ChildRef, f32)]>,
    any: Box<[ChildRef]>,
}

impl WalkState {
    /// Stacks that a walk of a tree `depth` nodes deep never outgrows: each node on the way down
    /// leaves at most seven children behind, and (nearest first) its eighth is pushed before one
    /// is popped.
    pub(super) fn new(depth: usize) -> Self {
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
pub(super) fn walk<const NEAREST: bool>(
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
    if ray.all_axes_move() && node_test::wide_available() {
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
        nearest_first(nodes, &mut state.nearest, tmax, leaf, test);
    } else {
        any_order(nodes, &mut state.any, tmax, leaf, test);
    }
}

/// The nearest-first loop.
#[inline(always)]
fn nearest_first(
    nodes: &[WideNode],
    stack: &mut [(ChildRef, f32)],
    tmax: &mut f32,
    mut leaf: impl FnMut(usize, &mut f32) -> bool,
    test: impl Fn(&WideNode, f32) -> NodeHits,
) {
    let mut depth = 0;
    let mut current = ChildRef::ROOT;
    loop {
        if current.is_leaf() {
            for i in current.primitives() {
                if leaf(i, tmax) {
                    return;
                }
            }
        } else {
            let node = &nodes[current.index()];
            let hits = test(node, *tmax);
            if hits.mask != 0 {
                current = push_sorted(node, &hits, stack, &mut depth);
                continue;
            }
        }
        current = loop {
            if depth == 0 {
                return;
            }
            depth -= 1;
            let (child, enter) = stack[depth];
            if enter <= *tmax {
                break child;
            }
        };
    }
}

/// Pushes the children in `hits` but the nearest onto `stack[..*depth]`, farthest first, and
/// returns the nearest. The children are sorted in place on top of the stack (insertion: a node
/// has few hit children).
#[inline(always)]
fn push_sorted(
    node: &WideNode,
    hits: &NodeHits,
    stack: &mut [(ChildRef, f32)],
    depth: &mut usize,
) -> ChildRef {
    let mut mask = hits.mask;
    if mask & (mask - 1) == 0 {
        return node.child[mask.trailing_zeros() as usize];
    }
    let base = *depth;
    while mask != 0 {
        let c = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        let entry = (node.child[c], hits.enter[c]);
        let mut k = *depth;
        while k > base && stack[k - 1].1 < entry.1 {
            stack[k] = stack[k - 1];
            k -= 1;
        }
        stack[k] = entry;
        *depth += 1;
    }
    *depth -= 1;
    stack[*depth].0
}

/// The any-order loop: the children the ray may meet are pushed in node order but the last,
/// which is visited next.
#[inline(always)]
fn any_order(
    nodes: &[WideNode],
    stack: &mut [ChildRef],
    tmax: &mut f32,
    mut leaf: impl FnMut(usize, &mut f32) -> bool,
    test: impl Fn(&WideNode, f32) -> NodeHits,
) {
    let mut depth = 0;
    let mut current = ChildRef::ROOT;
    loop {
        if current.is_leaf() {
            for i in current.primitives() {
                if leaf(i, tmax) {
                    return;
                }
            }
        } else {
            let node = &nodes[current.index()];
            let mask = test(node, *tmax).mask;
            if mask != 0 {
                current = push_each(node, mask, stack, &mut depth);
                continue;
            }
        }
        if depth == 0 {
            return;
        }
        depth -= 1;
        current = stack[depth];
    }
}

/// The any-order push of a non-empty `mask`, one child at a time: pushes all but the last child
/// and returns it.
#[inline(always)]
fn push_each(node: &WideNode, mut mask: u32, stack: &mut [ChildRef], depth: &mut usize) -> ChildRef {
    loop {
        let child = node.child[mask.trailing_zeros() as usize];
        mask &= mask - 1;
        if mask == 0 {
            return child;
        }
        stack[*depth] = child;
        *depth += 1;
    }
}
