//! The instance level of a scene's BVH: a top tree over the instances' world boxes, and one
//! tree per shared mesh in the mesh's own space, walked with the ray carried into that space.
//!
//! The reference stays exact in the same sense as for flat triangles: the tree of a mesh only
//! culls, and every triangle it reaches is tested in world space, with the world vertices that
//! flattening would have produced (src/scene/instance.rs) and the same watertight test. The
//! walk in mesh space is made conservative by widening the mesh tree's boxes by a margin that
//! bounds every rounding between the two spaces (`Placement::margin`), so it reaches at least
//! every triangle that the flat tree would have reached, and the answers are those of the
//! flattened scene (tests/instancing.rs).

use super::flat_tree::{FlatTree, build_cwbvh};
use super::hit::Hit;
use super::node_test::NodeRay;
use super::scratch::TraversalScratch;
use super::walk::{ANY_ORDER, NEAREST_FIRST, WalkState, walk};
use super::watertight::WatertightRay;
use super::wide_bvh::{WideBvh, tree_depth};
use crate::scene::{Scene, SharedMesh, box_corners, is_degenerate, world_vertex};
use glam::{DAffine3, DVec3, Vec3};
use obvhs::aabb::Aabb;

/// Relative widening of an instance's world box and of the margin's rounding bound: far above
/// the f32 roundings it must cover (2^-24 each), far below anything that costs time.
const SLACK: f64 = 1.0 / (1u64 << 18) as f64;

pub(in crate::trace) struct InstanceLevel {
    top: WideBvh,
    top_depth: usize,
    /// The placement of each top-level primitive, in the top tree's order.
    placements: Vec<Placement>,
    meshes: Vec<MeshTree>,
}

/// One instance, as the walk needs it.
struct Placement {
    world_from_local: DAffine3,
    local_from_world: DAffine3,
    mirrored: bool,
    mesh: u32,
    first_triangle: u32,
    /// The world box of the instance's vertices, widened by `SLACK`.
    world_lo: DVec3,
    world_hi: DVec3,
    /// ‖local_from_world‖∞ · max |world coordinate| + max |local coordinate|: the part of the
    /// margin that does not depend on the ray.
    fixed_extent: f64,
    /// The scene's segment margin carried into the mesh's space (times ‖local_from_world‖∞).
    segment_margin_local: f64,
}

/// The tree of one shared mesh, over its vertices rounded to f32 in its own space, with the
/// f64 vertices of each triangle in the tree's order.
struct MeshTree {
    tree: FlatTree,
    local_triangles: Vec<[DVec3; 3]>,
    local_ids: Vec<u32>,
}

impl InstanceLevel {
    /// The level of `scene`'s instances; every box grows by `segment_margin` world units more,
    /// as the flat tree's do (`SceneBvh::build`).
    pub(in crate::trace) fn build(scene: &Scene, segment_margin: f32) -> Option<Self> {
        if scene.instances.is_empty() {
            return None;
        }
        let meshes: Vec<MeshTree> = scene.meshes.iter().map(MeshTree::build).collect();
        let placements: Vec<Placement> = scene
            .instances
            .iter()
            .map(|i| Placement::new(i, &scene.meshes[i.mesh as usize], segment_margin))
            .collect();
        let boxes: Vec<Aabb> =
            placements.iter().map(|p| Aabb::new(p.world_lo.as_vec3a(), p.world_hi.as_vec3a())).collect();
        let top_order = build_cwbvh(&boxes);
        let top = WideBvh::from_cwbvh(&top_order, |i| {
            let b = &boxes[top_order.primitive_indices[i] as usize];
            (b.min, b.max)
        });
        let mut by_index: Vec<Option<Placement>> = placements.into_iter().map(Some).collect();
        let placements =
            top_order.primitive_indices.iter().map(|&i| by_index[i as usize].take().unwrap()).collect();
        let top_depth = tree_depth(&top);
        Some(InstanceLevel { top, top_depth, placements, meshes })
    }

    /// The deepest top tree and the deepest mesh tree, for the walk stacks.
    pub(in crate::trace) fn depths(&self) -> (usize, usize) {
        (self.top_depth, self.meshes.iter().map(|m| m.tree.depth).max().unwrap_or(0))
    }

    /// Replaces `best` by a nearer hit on an instanced triangle with t ∈ [tmin, tmax], where
    /// `tmax` is the caller's bound or `best`'s distance, whichever is nearer.
    pub(in crate::trace) fn closest_hit(
        &self,
        scratch: &mut TraversalScratch,
        ray: &WatertightRay,
        tmin: f32,
        tmax: f32,
        best: &mut Option<Hit>,
    ) {
        let TraversalScratch { outer, inner, .. } = scratch;
        let mut best_t = best.map_or(tmax, |b| b.t.min(tmax));
        let top_ray = NodeRay::new(ray.origin, ray.direction);
        walk::<NEAREST_FIRST>(&self.top, outer, &top_ray, tmin, &mut best_t, 0.0, |i, best_t| {
            let placement = &self.placements[i];
            let mesh = &self.meshes[placement.mesh as usize];
            placement.walk::<NEAREST_FIRST>(mesh, inner, ray, tmin, best_t, |local, best_t| {
                let Some(h) = ray.intersect(local.world[0], local.world[1], local.world[2], tmin, *best_t)
                else {
                    return false;
                };
                let hit =
                    Hit { triangle: local.id, t: h.t, barycentric: h.barycentric, vertices: local.world };
                if hit.beats(best) && !local.degenerate() {
                    *best = Some(hit);
                    *best_t = h.t;
                }
                false
            });
            false
        });
    }

    /// Calls `visit(id, world vertices)` for every non-degenerate instanced triangle the ray
    /// may meet within [0, tmax] (in no particular order) until it returns true; returns
    /// whether it did.
    pub(in crate::trace) fn any_triangle(
        &self,
        scratch: &mut TraversalScratch,
        ray: &WatertightRay,
        tmax: f32,
        mut visit: impl FnMut(u32, &[Vec3; 3]) -> bool,
    ) -> bool {
        let TraversalScratch { outer, inner, .. } = scratch;
        let top_ray = NodeRay::new(ray.origin, ray.direction);
        let mut stopped = false;
        walk::<ANY_ORDER>(&self.top, outer, &top_ray, 0.0, &mut tmax.clone(), 0.0, |i, _| {
            let placement = &self.placements[i];
            let mesh = &self.meshes[placement.mesh as usize];
            placement.walk::<ANY_ORDER>(mesh, inner, ray, 0.0, &mut tmax.clone(), |local, _| {
                stopped = !local.degenerate() && visit(local.id, &local.world);
                stopped
            });
            stopped
        });
        stopped
    }
}

/// A triangle of an instance met by the walk: its scene id and world vertices.
struct LocalTriangle {
    id: u32,
    world: [Vec3; 3],
}

impl LocalTriangle {
    /// Degenerate in world space: flattening would have dropped it, so it occludes nothing.
    fn degenerate(&self) -> bool {
        is_degenerate(&self.world)
    }
}

impl MeshTree {
    fn build(mesh: &SharedMesh) -> Self {
        let local = |t: &[u32; 3]| t.map(|i| mesh.positions[i as usize]);
        let rounded: Vec<[Vec3; 3]> = mesh.triangles.iter().map(|t| local(t).map(|p| p.as_vec3())).collect();
        let mut tree = FlatTree::build(&rounded, 0.0);
        drop(rounded);
        // The walk tests world triangles: the f32 local copies were for the build only.
        tree.triangles = Vec::new();
        let local_ids = std::mem::take(&mut tree.scene_ids);
        let local_triangles = local_ids.iter().map(|&i| local(&mesh.triangles[i as usize])).collect();
        MeshTree { tree, local_triangles, local_ids }
    }
}

impl Placement {
    fn new(instance: &crate::scene::Instance, mesh: &SharedMesh, segment_margin: f32) -> Self {
        let (lo, hi) = mesh.bounds();
        let world = box_corners(lo, hi).map(|c| instance.world_from_local.transform_point3(c));
        let world_lo = world.iter().fold(DVec3::INFINITY, |a, &c| a.min(c));
        let world_hi = world.iter().fold(DVec3::NEG_INFINITY, |a, &c| a.max(c));
        let world_extent = world_lo.abs().max(world_hi.abs()).max_element();
        let widen =
            DVec3::splat(world_extent * SLACK + f64::from(f32::MIN_POSITIVE) + f64::from(segment_margin));
        let local_from_world = instance.world_from_local.inverse();
        let inverse_norm = row_sum_norm(&local_from_world);
        Placement {
            world_from_local: instance.world_from_local,
            local_from_world,
            mirrored: instance.mirrored,
            mesh: instance.mesh,
            first_triangle: instance.first_triangle,
            world_lo: world_lo - widen,
            world_hi: world_hi + widen,
            fixed_extent: inverse_norm * world_extent + lo.abs().max(hi.abs()).max_element(),
            segment_margin_local: inverse_norm * f64::from(segment_margin),
        }
    }

    /// Walks this instance's mesh tree with `ray` carried into the mesh's space, calling
    /// `leaf(triangle, tmax)` with the world triangles it reaches; `leaf` may shrink `*tmax`,
    /// and ends the walk by returning true.
    #[inline]
    fn walk<const NEAREST: bool>(
        &self,
        mesh: &MeshTree,
        state: &mut WalkState,
        ray: &WatertightRay,
        tmin: f32,
        tmax: &mut f32,
        mut leaf: impl FnMut(&LocalTriangle, &mut f32) -> bool,
    ) -> bool {
        let Some(t_exit) = self.exit_distance(ray, tmin, *tmax) else {
            return false;
        };
        let origin = self.local_from_world.transform_point3(ray.origin.as_dvec3());
        let direction = self.local_from_world.transform_vector3(ray.direction.as_dvec3());
        let extent = self.fixed_extent + origin.abs().max_element() + t_exit * direction.abs().max_element();
        let margin = (extent * SLACK + self.segment_margin_local) as f32;
        let local_ray = NodeRay::new(origin.as_vec3a(), direction.as_vec3a());
        let mut local_tmax = tmax.min(t_exit as f32);
        let mut stopped = false;
        walk::<NEAREST>(
            &mesh.tree.tree,
            state,
            &local_ray,
            tmin,
            &mut local_tmax,
            margin,
            |i, local_tmax| {
                let [a, b, c] = mesh.local_triangles[i].map(|p| world_vertex(&self.world_from_local, p));
                let world = if self.mirrored { [a, c, b] } else { [a, b, c] };
                let triangle = LocalTriangle { id: self.first_triangle + mesh.local_ids[i], world };
                stopped = leaf(&triangle, tmax);
                *local_tmax = local_tmax.min(*tmax);
                stopped
            },
        );
        stopped
    }

    /// The distance at which the ray leaves this instance's world box, widened so that it
    /// bounds every hit on its triangles; `None` when the ray misses the box within
    /// [tmin, tmax]. In f64, where the slab distances of f32 inputs carry no error that matters
    /// next to `SLACK`.
    fn exit_distance(&self, ray: &WatertightRay, tmin: f32, tmax: f32) -> Option<f64> {
        let (o, d) = (ray.origin.as_dvec3(), ray.direction.as_dvec3());
        let (mut enter, mut exit) = (f64::from(tmin), f64::from(tmax));
        for axis in 0..3 {
            let (lo, hi) = (self.world_lo[axis], self.world_hi[axis]);
            if d[axis] == 0.0 {
                if o[axis] < lo || o[axis] > hi {
                    return None;
                }
                continue;
            }
            let (t0, t1) = ((lo - o[axis]) / d[axis], (hi - o[axis]) / d[axis]);
            enter = enter.max(t0.min(t1));
            exit = exit.min(t0.max(t1));
        }
        let exit = exit * (1.0 + SLACK) + f64::from(f32::MIN_POSITIVE);
        (enter <= exit).then_some(exit)
    }
}

/// The maximum absolute row sum of the linear part: how much a map can stretch a max-norm.
fn row_sum_norm(m: &DAffine3) -> f64 {
    let rows = m.matrix3.transpose();
    [rows.x_axis, rows.y_axis, rows.z_axis].iter().map(|r| r.abs().element_sum()).fold(0.0, f64::max)
}
