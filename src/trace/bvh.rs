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

use super::watertight::WatertightRay;
use crate::scene::Scene;
use glam::{UVec2, Vec3, Vec3A, uvec2};
use obvhs::BvhBuildParams;
use obvhs::bvh2::reinsertion::ReinsertionOptimizer;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::bvh2_to_cwbvh::bvh2_to_cwbvh;
use obvhs::cwbvh::node::{CwBvhNode, extract_byte64};
use obvhs::faststack::{FastStack, HeapStack};
use obvhs::ploc::PlocBuilder;
use obvhs::triangle::Triangle;

/// The BVH of a scene with its triangles in traversal order.
pub struct SceneBvh {
    bvh: CwBvh,
    /// Triangles in BVH order: `triangles[i]` is scene triangle `scene_ids[i]`.
    triangles: Vec<[Vec3A; 3]>,
    scene_ids: Vec<u32>,
    /// Deepest level of the tree: the traversal stack never holds more entries.
    depth: usize,
}

/// A closest hit: the scene triangle, the distance along the unit direction, barycentrics.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub triangle: u32,
    pub t: f32,
    pub barycentric: [f32; 3],
}

/// Per-thread traversal state, reused across rays (no allocation per ray).
pub struct TraversalScratch {
    stack: HeapStack<UVec2>,
    current_group: UVec2,
    primitive_group: UVec2,
    oct_inv4: u32,
    primitive_id: u32,
    hitmask: u32,
}

impl SceneBvh {
    pub fn build(scene: &Scene) -> Self {
        Self::build_from_triangles(&scene.triangles)
    }

    pub fn build_from_triangles(tris: &[[Vec3; 3]]) -> Self {
        if tris.is_empty() {
            return SceneBvh {
                bvh: CwBvh::default(),
                triangles: Vec::new(),
                scene_ids: Vec::new(),
                depth: 0,
            };
        }
        let obvhs_tris: Vec<Triangle> = tris
            .iter()
            .map(|t| Triangle {
                v0: t[0].into(),
                v1: t[1].into(),
                v2: t[2].into(),
            })
            .collect();
        // obvhs's `build_cwbvh_from_tris` without its debug validation, which panics on trees
        // deeper than its traversal stack (ours is sized to the tree). No spatial splits, so
        // every triangle is referenced once and the reordering below is a permutation.
        let params = BvhBuildParams::medium_build();
        let mut bvh2 = PlocBuilder::with_capacity(obvhs_tris.len()).build(
            params.ploc_search_distance,
            &obvhs_tris,
            (0..obvhs_tris.len() as u32).collect(),
            params.sort_precision,
            params.search_depth_threshold,
        );
        ReinsertionOptimizer::default().run(&mut bvh2, params.reinsertion_batch_ratio, None);
        let bvh = bvh2_to_cwbvh(&bvh2, params.max_prims_per_leaf.clamp(1, 3), true, false);
        let scene_ids = bvh.primitive_indices.clone();
        let triangles = scene_ids
            .iter()
            .map(|&i| {
                let t = &tris[i as usize];
                [t[0].into(), t[1].into(), t[2].into()]
            })
            .collect();
        let depth = tree_depth(&bvh);
        SceneBvh {
            bvh,
            triangles,
            scene_ids,
            depth,
        }
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

    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    pub fn scratch(&self) -> TraversalScratch {
        TraversalScratch {
            stack: HeapStack::new_with_capacity(self.depth + 2),
            current_group: UVec2::ZERO,
            primitive_group: UVec2::ZERO,
            oct_inv4: 0,
            primitive_id: 0,
            hitmask: 0,
        }
    }

    fn reset(&self, s: &mut TraversalScratch, direction: Vec3A) {
        s.stack.clear();
        s.current_group = if self.bvh.nodes.is_empty() {
            UVec2::ZERO
        } else {
            uvec2(0, 0x8000_0000)
        };
        s.primitive_group = UVec2::ZERO;
        s.oct_inv4 = octant_inv4(direction);
        s.primitive_id = 0;
        s.hitmask = 0;
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
        let inv_dir = Vec3A::ONE / ray.direction;
        let mut best: Option<Hit> = None;
        let mut best_t = tmax;
        self.reset(scratch, ray.direction);
        let state = scratch;
        let mut node: &CwBvhNode;
        obvhs::traverse!(
            self.bvh,
            node,
            state,
            intersect_node(node, ray.origin, inv_dir, tmin, best_t, state.oct_inv4),
            {
                let i = state.primitive_id as usize;
                let [v0, v1, v2] = self.triangles[i];
                if let Some(h) = ray.intersect(v0, v1, v2, tmin, best_t) {
                    let id = self.scene_ids[i];
                    let better = match best {
                        Some(b) => h.t < b.t || (h.t == b.t && id < b.triangle),
                        None => true,
                    };
                    if better {
                        best = Some(Hit {
                            triangle: id,
                            t: h.t,
                            barycentric: h.barycentric,
                        });
                        best_t = h.t;
                    }
                }
            }
        );
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
        let inv_dir = Vec3A::ONE / ray.direction;
        self.reset(scratch, ray.direction);
        let state = scratch;
        let mut node: &CwBvhNode;
        let mut hit = false;
        'search: {
            obvhs::traverse!(
                self.bvh,
                node,
                state,
                intersect_node(node, ray.origin, inv_dir, tmin, tmax, state.oct_inv4),
                {
                    let [v0, v1, v2] = self.triangles[state.primitive_id as usize];
                    if ray.intersect(v0, v1, v2, tmin, tmax).is_some() {
                        hit = true;
                        break 'search;
                    }
                }
            );
        }
        hit
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
/// [tmin, tmax]. Boxes are widened by the rounding of their dequantization, and the far distance
/// by a few ulps (Ize, "Robust BVH Ray Traversal", JCGT 2(2), 2013). Zero direction components
/// give infinite reciprocals; a NaN slab (origin on the plane, parallel ray) is ignored by
/// `min`/`max`, which keeps the test conservative.
#[inline]
fn intersect_node(
    node: &CwBvhNode,
    origin: Vec3A,
    inv_dir: Vec3A,
    tmin: f32,
    tmax: f32,
    oct_inv4: u32,
) -> u32 {
    let p = Vec3A::from(node.p);
    let e = node.compute_extent();
    let widen = (p.abs() + e * 255.0) * (4.0 * f32::EPSILON);
    let (child_bits8, bit_index8) = node.get_child_and_index_bits(oct_inv4);
    let mut hit_mask = 0;
    for child in 0..8 {
        if node.child_meta[child] == 0 {
            continue;
        }
        let q_lo = Vec3A::new(
            node.child_min_x[child] as f32,
            node.child_min_y[child] as f32,
            node.child_min_z[child] as f32,
        );
        let q_hi = Vec3A::new(
            node.child_max_x[child] as f32,
            node.child_max_y[child] as f32,
            node.child_max_z[child] as f32,
        );
        let lo = q_lo * e + p - widen;
        let hi = q_hi * e + p + widen;
        let t0 = ((lo - origin) * inv_dir).to_array();
        let t1 = ((hi - origin) * inv_dir).to_array();
        // Scalar f32::min/max return the other operand for a NaN, unlike the SIMD lanes.
        let mut enter = tmin;
        let mut exit = tmax;
        for k in 0..3 {
            enter = enter.max(t0[k].min(t1[k]));
            exit = exit.min(t0[k].max(t1[k]) * (1.0 + 4.0 * f32::EPSILON));
        }
        if enter <= exit {
            let child_bits = extract_byte64(child_bits8, child);
            let bit_index = extract_byte64(bit_index8, child);
            hit_mask |= child_bits << bit_index;
        }
    }
    hit_mask
}

/// Depth of a CWBVH in nodes, by walking it.
fn tree_depth(bvh: &CwBvh) -> usize {
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
