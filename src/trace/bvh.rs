//! One obvhs CWBVH per scene, traversed with our own node and triangle tests.
//!
//! obvhs 0.4 traps that this file steps around (each pinned by a test in tests/trace_traps.rs):
//! - its node test clamps tmin to 1e-4 ray units, so occluders closer than that are missed:
//!   our node test starts at t = 0 and widens boxes by their quantization error;
//! - its closest-hit and any-hit loops compare `t < tmax`, so an occluder at exactly tmax is
//!   lost: our ray interval is closed;
//! - its triangle test is not watertight: we use `WatertightRay`;
//! - traversal ids index `primitive_indices`: we store the triangles in BVH order with their
//!   scene ids beside them;
//! - its traversal stack holds 32 entries and overwrites silently when full: our stack is
//!   sized to the tree's depth;
//! - `Triangle::compute_barycentric` is wrong: barycentrics come from the watertight test.

use super::cwbvh_convert::bvh2_to_cwbvh;
use super::instances::InstanceLevel;
use super::node_test;
pub(super) use super::node_test::NodeRay;
use super::shadow_ray::ShadowRay;
use super::watertight::WatertightRay;
use crate::scene::Scene;
use bytemuck::TransparentWrapper;
use glam::{UVec2, Vec3, Vec3A, uvec2};
use obvhs::BvhBuildParams;
use obvhs::bvh2::reinsertion::ReinsertionOptimizer;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::node::CwBvhNode;
use obvhs::faststack::{FastStack, HeapStack};
use obvhs::ploc::PlocBuilder;
use obvhs::{Boundable, aabb::Aabb};
use rayon::prelude::*;

/// The BVH of a scene: its flat triangles in traversal order, and its instanced meshes
/// behind a second level (src/trace/instances.rs).
pub struct SceneBvh {
    pub(super) bvh: CwBvh,
    /// Triangles in BVH order: `triangles[i]` is scene triangle `scene_ids[i]`.
    pub(super) triangles: Vec<[Vec3A; 3]>,
    pub(super) scene_ids: Vec<u32>,
    /// Deepest level of the tree: the traversal stack never holds more entries.
    pub(super) depth: usize,
    instances: Option<InstanceLevel>,
}

/// A closest hit: the scene triangle, the distance along the unit direction, barycentrics.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub triangle: u32,
    pub t: f32,
    pub barycentric: [f32; 3],
}

impl Hit {
    /// Whether this hit replaces `best`: nearer, or as near with a lower scene triangle id, so
    /// that the closest hit does not depend on the tree's shape.
    #[inline]
    pub(super) fn beats(&self, best: &Option<Hit>) -> bool {
        match best {
            Some(b) => self.t < b.t || (self.t == b.t && self.triangle < b.triangle),
            None => true,
        }
    }
}

/// Per-thread traversal state, reused across rays (no allocation per ray): one walk state for
/// the flat and top levels, one for an instance's mesh.
pub struct TraversalScratch {
    pub(super) outer: WalkState,
    pub(super) inner: WalkState,
}

/// The state of one walk down one tree.
pub(super) struct WalkState {
    stack: HeapStack<UVec2>,
    current_group: UVec2,
    primitive_group: UVec2,
    oct_inv4: u32,
    primitive_id: u32,
    hitmask: u32,
}

impl WalkState {
    pub(super) fn new(depth: usize) -> Self {
        WalkState {
            stack: HeapStack::new_with_capacity(depth + 2),
            current_group: UVec2::ZERO,
            primitive_group: UVec2::ZERO,
            oct_inv4: 0,
            primitive_id: 0,
            hitmask: 0,
        }
    }
}

impl SceneBvh {
    pub fn build(scene: &Scene) -> Self {
        let mut bvh = Self::build_from_triangles(&scene.flat_triangles);
        bvh.instances = InstanceLevel::build(scene);
        bvh
    }

    pub fn build_from_triangles(tris: &[[Vec3; 3]]) -> Self {
        if tris.is_empty() {
            return SceneBvh {
                bvh: CwBvh::default(),
                triangles: Vec::new(),
                scene_ids: Vec::new(),
                depth: 0,
                instances: None,
            };
        }
        let bvh = build_cwbvh(BoundedTriangle::wrap_slice(tris));
        let scene_ids = bvh.primitive_indices.clone();
        let triangles = scene_ids
            .par_iter()
            .map(|&i| {
                let t = &tris[i as usize];
                [t[0].into(), t[1].into(), t[2].into()]
            })
            .collect();
        let depth = tree_depth(&bvh);
        SceneBvh { bvh, triangles, scene_ids, depth, instances: None }
    }

    /// The obvhs tree, whose primitive order is that of `triangles_in_tree_order`.
    #[doc(hidden)]
    pub fn cwbvh(&self) -> &CwBvh {
        &self.bvh
    }

    /// The triangles in the tree's primitive order.
    #[doc(hidden)]
    pub fn triangles_in_tree_order(&self) -> &[[Vec3A; 3]] {
        &self.triangles
    }

    /// Depth of the tree in nodes (root = 1).
    pub fn depth(&self) -> usize {
        self.depth
    }

    /// The flat triangles (instanced ones are stored once per mesh, in the instance level).
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    pub fn scratch(&self) -> TraversalScratch {
        let (top, mesh) = self.instances.as_ref().map_or((0, 0), InstanceLevel::depths);
        TraversalScratch { outer: WalkState::new(self.depth.max(top)), inner: WalkState::new(mesh) }
    }

    /// The nearest hit with t ∈ [tmin, tmax]; among hits at the same t the lowest scene triangle
    /// id wins, so the result does not depend on the tree's shape.
    pub fn closest_hit(
        &self,
        scratch: &mut TraversalScratch,
        origin: Vec3,
        direction: Vec3,
        tmin: f32,
        tmax: f32,
    ) -> Option<Hit> {
        let ray = WatertightRay::new(origin.into(), direction.into());
        let node_ray = NodeRay::new(ray.origin, ray.direction);
        let mut best: Option<Hit> = None;
        let mut best_t = tmax;
        walk(&self.bvh, &mut scratch.outer, &node_ray, tmin, &mut best_t, 0.0, |i, best_t| {
            let [v0, v1, v2] = self.triangles[i];
            if let Some(h) = ray.intersect(v0, v1, v2, tmin, *best_t) {
                let hit = Hit { triangle: self.scene_ids[i], t: h.t, barycentric: h.barycentric };
                if hit.beats(&best) {
                    best = Some(hit);
                    *best_t = h.t;
                }
            }
            false
        });
        if let Some(instances) = &self.instances {
            instances.closest_hit(scratch, &ray, tmin, best_t, &mut best);
        }
        best
    }

    /// Whether any triangle is hit with t ∈ [tmin, tmax] (a closed interval).
    pub fn occluded(
        &self,
        scratch: &mut TraversalScratch,
        origin: Vec3,
        direction: Vec3,
        tmin: f32,
        tmax: f32,
    ) -> bool {
        let ray = WatertightRay::new(origin.into(), direction.into());
        let node_ray = NodeRay::new(ray.origin, ray.direction);
        let mut hit = false;
        walk(&self.bvh, &mut scratch.outer, &node_ray, tmin, &mut tmax.clone(), 0.0, |i, _| {
            let [v0, v1, v2] = self.triangles[i];
            hit = ray.intersect(v0, v1, v2, tmin, tmax).is_some();
            hit
        });
        match &self.instances {
            Some(instances) if !hit => {
                instances.any_hit(scratch, &ray, tmin, tmax, u32::MAX, false).is_some()
            }
            _ => hit,
        }
    }
}

impl SceneBvh {
    /// The scene id of a triangle that occludes a shadow ray (any one, not the nearest), or
    /// `None`: a hit counts when its distance is certainly positive and at most `tmax`, and
    /// the ray's own triangle is never tested (shadow_ray.rs).
    pub fn shadow_occluder(&self, scratch: &mut TraversalScratch, shadow: &ShadowRay) -> Option<u32> {
        let ray = WatertightRay::new(shadow.origin.into(), shadow.direction.into());
        let node_ray = NodeRay::new(ray.origin, ray.direction);
        let mut occluder = None;
        walk(&self.bvh, &mut scratch.outer, &node_ray, 0.0, &mut shadow.tmax.clone(), 0.0, |i, _| {
            let id = self.scene_ids[i];
            let [v0, v1, v2] = self.triangles[i];
            if id != shadow.skip_triangle && ray.intersect_beyond_error(v0, v1, v2, shadow.tmax).is_some() {
                occluder = Some(id);
            }
            occluder.is_some()
        });
        match &self.instances {
            Some(instances) if occluder.is_none() => {
                instances.any_hit(scratch, &ray, 0.0, shadow.tmax, shadow.skip_triangle, true)
            }
            _ => occluder,
        }
    }
}

/// obvhs's group traversal with `$test` as the node test: `leaf` for each primitive reached,
/// until it returns true.
macro_rules! walk_loop {
    ($bvh:expr, $state:expr, $ray:expr, $tmin:expr, $tmax:expr, $margin:expr, $leaf:expr, $test:path) => {{
        let mut node: &CwBvhNode;
        'walk: {
            obvhs::traverse!($bvh, node, $state, $test(node, $ray, $tmin, *$tmax, $margin), {
                if $leaf($state.primitive_id as usize, $tmax) {
                    break 'walk;
                }
            });
        }
    }};
}

/// Walks the nodes of `bvh` that the ray may meet within [tmin, *tmax], their boxes widened by
/// `margin` more, and calls `leaf(i, tmax)` for each primitive `i` (in tree order) of the
/// leaves it reaches. `leaf` may shrink `*tmax` (closest hits), and ends the walk by
/// returning true. Where the processor has AVX2 and FMA and the ray moves along every axis,
/// the node test takes eight children at once (`node_test.rs`); its answers are the same.
#[inline(always)]
pub(super) fn walk(
    bvh: &CwBvh,
    state: &mut WalkState,
    ray: &NodeRay,
    tmin: f32,
    tmax: &mut f32,
    margin: f32,
    mut leaf: impl FnMut(usize, &mut f32) -> bool,
) {
    state.stack.clear();
    state.current_group = if bvh.nodes.is_empty() { UVec2::ZERO } else { uvec2(0, 0x8000_0000) };
    state.primitive_group = UVec2::ZERO;
    state.oct_inv4 = ray.oct_inv4;
    state.primitive_id = 0;
    state.hitmask = 0;
    #[cfg(target_arch = "x86_64")]
    if ray.all_axes_move() && node_test::wide_available() {
        // SAFETY: the processor has AVX2 and FMA (checked at run time).
        unsafe { walk_wide(bvh, state, ray, tmin, tmax, margin, leaf) };
        return;
    }
    walk_loop!(bvh, state, ray, tmin, tmax, margin, leaf, node_test::intersect_node);
}

/// `walk` with the 8-lane node test, compiled for AVX2 and FMA as a whole so that the test is
/// inlined into the loop.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline]
fn walk_wide(
    bvh: &CwBvh,
    state: &mut WalkState,
    ray: &NodeRay,
    tmin: f32,
    tmax: &mut f32,
    margin: f32,
    mut leaf: impl FnMut(usize, &mut f32) -> bool,
) {
    walk_loop!(bvh, state, ray, tmin, tmax, margin, leaf, node_test::intersect_node_wide);
}

/// A scene triangle as obvhs bounds it: the builder reads the scene's own triangles, with no
/// copy of them.
#[derive(bytemuck::TransparentWrapper)]
#[repr(transparent)]
struct BoundedTriangle([Vec3; 3]);

impl Boundable for BoundedTriangle {
    #[inline]
    fn aabb(&self) -> Aabb {
        let [a, b, c] = self.0.map(Vec3A::from);
        Aabb::new(a.min(b).min(c), a.max(b).max(c))
    }
}

/// obvhs's `build_cwbvh_from_tris` without its debug validation, which panics on trees deeper
/// than its traversal stack (ours is sized to the tree), over any primitives (the scene's
/// triangles in place, or instance boxes), freeing each intermediate as soon as it is no longer
/// read: the PLOC builder after the build, the parent links before the conversion, the binary
/// tree after it. No spatial splits, so every primitive is referenced once and
/// `primitive_indices` is a permutation. PLOC and reinsertion run on rayon's threads
/// (obvhs's `parallel` feature); the tree's shape never changes a result (the closest hit breaks
/// ties by scene id). Reinsertion keeps obvhs's medium ratio: on a generated 10M-triangle city it
/// is a third of the build, but without it (or at 0.02) primary rays were up to 15 % slower
/// (docs/scale.md).
pub(super) fn build_cwbvh<T: Boundable>(primitives: &[T]) -> CwBvh {
    let params = BvhBuildParams::medium_build();
    let mut bvh2 = PlocBuilder::with_capacity(primitives.len()).build(
        params.ploc_search_distance,
        primitives,
        (0..primitives.len() as u32).collect(),
        params.sort_precision,
        params.search_depth_threshold,
    );
    ReinsertionOptimizer::default().run(&mut bvh2, params.reinsertion_batch_ratio, None);
    bvh2.parents = Vec::new();
    bvh2.primitives_to_nodes = Vec::new();
    bvh2_to_cwbvh(&bvh2)
}

/// Depth of a CWBVH in nodes, by walking it.
pub(super) fn tree_depth(bvh: &CwBvh) -> usize {
    if bvh.nodes.is_empty() {
        return 0;
    }
    let mut deepest = 0;
    let mut todo = vec![(0u32, 1usize)];
    while let Some((index, depth)) = todo.pop() {
        deepest = deepest.max(depth);
        let node = &bvh.nodes[index as usize];
        for child in 0..8 {
            if !node.is_leaf(child) && !node.is_child_empty(child) {
                todo.push((node.child_node_index(child), depth + 1));
            }
        }
    }
    deepest
}
