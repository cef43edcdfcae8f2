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
use super::shadow_ray::ShadowRay;
use super::simd4::{F4, Span4};
use super::watertight::WatertightRay;
use crate::scene::Scene;
use bytemuck::TransparentWrapper;
use glam::{UVec2, Vec3, Vec3A, uvec2};
use obvhs::BvhBuildParams;
use obvhs::bvh2::reinsertion::ReinsertionOptimizer;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::node::{CwBvhNode, extract_byte64};
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

/// Walks the nodes of `bvh` that the ray may meet within [tmin, *tmax], their boxes widened by
/// `margin` more, and calls `leaf(i, tmax)` for each primitive `i` (in tree order) of the
/// leaves it reaches. `leaf` may shrink `*tmax` (closest hits), and ends the walk by
/// returning true.
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
    let mut node: &CwBvhNode;
    'walk: {
        obvhs::traverse!(bvh, node, state, intersect_node(node, ray, tmin, *tmax, margin), {
            if leaf(state.primitive_id as usize, tmax) {
                break 'walk;
            }
        });
    }
}

/// obvhs's child-ordering code for a direction (private in obvhs, same bits).
#[inline]
fn octant_inv4(dir: Vec3A) -> u32 {
    (if dir.x < 0.0 { 0 } else { 0x0404_0404 })
        | (if dir.y < 0.0 { 0 } else { 0x0202_0202 })
        | (if dir.z < 0.0 { 0 } else { 0x0101_0101 })
}

/// Conservative slab test of the eight children of `node` against the closed interval
/// [tmin, tmax]. Boxes are widened by the rounding of their dequantization, and slab distances
/// by a few ulps (Ize, "Robust BVH Ray Traversal", JCGT 2(2), 2013). An axis along which the ray
/// does not move keeps the children whose slab holds the origin. Four children at a time.
#[inline(always)]
fn intersect_node(node: &CwBvhNode, ray: &NodeRay, tmin: f32, tmax: f32, margin: f32) -> u32 {
    let p = Vec3A::from(node.p);
    let e = node.compute_extent();
    let widen = (p.abs() + e * 255.0) * (4.0 * f32::EPSILON) + Vec3A::splat(margin);
    let (lo_base, hi_base) = ((p - widen).to_array(), (p + widen).to_array());
    let e = e.to_array();
    let quantized = [
        (&node.child_min_x, &node.child_max_x),
        (&node.child_min_y, &node.child_max_y),
        (&node.child_min_z, &node.child_max_z),
    ];
    let mut hits = 0u32;
    for half in 0..2 {
        let mut span = Span4::new(tmin, tmax);
        for (axis, (q_min, q_max)) in quantized.iter().enumerate() {
            let lo = F4::from_u8(q_min, half * 4).mul_add(e[axis], lo_base[axis]);
            let hi = F4::from_u8(q_max, half * 4).mul_add(e[axis], hi_base[axis]);
            if ray.moves[axis] {
                let (o, inv) = (ray.origin[axis], ray.inv_dir[axis]);
                let t0 = lo.sub_scalar(o).mul_scalar(inv);
                let t1 = hi.sub_scalar(o).mul_scalar(inv);
                span.clip(t0.min(t1), t0.max(t1));
            } else {
                span.keep_if_between(lo, hi, ray.origin[axis]);
            }
        }
        hits |= span.hit_bits() << (half * 4);
    }
    let (child_bits8, bit_index8) = node.get_child_and_index_bits(ray.oct_inv4);
    let mut hit_mask = 0;
    for c in 0..8 {
        if hits & (1 << c) != 0 && node.child_meta[c] != 0 {
            hit_mask |= extract_byte64(child_bits8, c) << extract_byte64(bit_index8, c);
        }
    }
    hit_mask
}

/// What the node test needs of a ray.
pub(super) struct NodeRay {
    origin: Vec3A,
    inv_dir: Vec3A,
    /// Whether the ray moves along each axis (a zero component has no slab distances).
    moves: [bool; 3],
    /// The child order for the ray's direction.
    oct_inv4: u32,
}

impl NodeRay {
    pub(super) fn new(origin: Vec3A, direction: Vec3A) -> Self {
        NodeRay {
            origin,
            inv_dir: Vec3A::ONE / direction,
            // A component so small that its reciprocal overflows counts as no motion.
            moves: (Vec3A::ONE / direction).is_finite_mask().into(),
            oct_inv4: octant_inv4(direction),
        }
    }
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
