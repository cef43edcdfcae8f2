//! A tree over triangles as they are given (a scene's flat triangles, or a shared mesh's in its
//! own space): obvhs builds its shape, our 8-wide tree with exact f32 boxes is what is walked.

use super::cwbvh_convert::bvh2_to_cwbvh;
use super::wide_bvh::{WideBvh, tree_depth};
use bytemuck::TransparentWrapper;
use glam::{Vec3, Vec3A};
use obvhs::BvhBuildParams;
use obvhs::bvh2::reinsertion::ReinsertionOptimizer;
use obvhs::cwbvh::CwBvh;
use obvhs::ploc::PlocBuilder;
use obvhs::{Boundable, aabb::Aabb};
use rayon::prelude::*;

/// The tree, its triangles in traversal order (`triangles[i]` is triangle `scene_ids[i]` of the
/// input) and its deepest level (the traversal stack never holds more entries).
pub(in crate::trace) struct FlatTree {
    pub(in crate::trace) tree: WideBvh,
    pub(in crate::trace) triangles: Vec<[Vec3; 3]>,
    pub(in crate::trace) scene_ids: Vec<u32>,
    pub(in crate::trace) depth: usize,
}

impl FlatTree {
    /// The tree of `tris`, each leaf box widened outwards by `widen` (0 for exact f32 boxes).
    pub(in crate::trace) fn build(tris: &[[Vec3; 3]], widen: f32) -> Self {
        if tris.is_empty() {
            return FlatTree {
                tree: WideBvh::default(),
                triangles: Vec::new(),
                scene_ids: Vec::new(),
                depth: 0,
            };
        }
        let cwbvh = build_cwbvh(BoundedTriangle::wrap_slice(tris));
        let triangles: Vec<[Vec3; 3]> =
            cwbvh.primitive_indices.par_iter().map(|&i| tris[i as usize]).collect();
        let tree = WideBvh::from_cwbvh(&cwbvh, |i| {
            let [a, b, c] = triangles[i].map(Vec3A::from);
            let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
            match widen > 0.0 {
                true => (outwards(lo, -widen), outwards(hi, widen)),
                false => (lo, hi),
            }
        });
        let scene_ids = cwbvh.primitive_indices;
        let depth = tree_depth(&tree);
        FlatTree { tree, triangles, scene_ids, depth }
    }
}

/// `v + step` per axis, rounded away from `v` (one f32 step further), so that the result is
/// at least `|step|` from `v`.
fn outwards(v: Vec3A, step: f32) -> Vec3A {
    let moved = v + Vec3A::splat(step);
    Vec3A::from_array(moved.to_array().map(|m| if step > 0.0 { m.next_up() } else { m.next_down() }))
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
pub(in crate::trace) fn build_cwbvh<T: Boundable>(primitives: &[T]) -> CwBvh {
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
