//! One BVH per scene: obvhs builds its shape (a CWBVH), and the walks run over our own 8-wide
//! tree with exact f32 child boxes (wide_bvh.rs, walk.rs, packet.rs) and our own node and
//! triangle tests.
//!
//! obvhs 0.4 traps that this file steps around (each pinned by a test in tests/trace_traps.rs):
//! - its node test clamps tmin to 1e-4 ray units, so occluders closer than that are missed:
//!   our node test (node_test.rs) starts at t = 0 and never enters a box late;
//! - its closest-hit and any-hit loops compare `t < tmax`, so an occluder at exactly tmax is
//!   lost: our ray interval is closed;
//! - its triangle test is not watertight: we use `WatertightRay`;
//! - traversal ids index `primitive_indices`: we store the triangles in BVH order with their
//!   scene ids beside them;
//! - its traversal stack holds 32 entries and overwrites silently when full: our stack is
//!   sized to the tree's depth;
//! - `Triangle::compute_barycentric` is wrong: barycentrics come from the watertight test.

use super::flat_tree::FlatTree;
use super::hit::Hit;
use super::instances::InstanceLevel;
use super::node_test;
use super::node_test::NodeRay;
#[cfg(target_arch = "x86_64")]
use super::packet::{LANES, Packet, walk_packet};
use super::scratch::TraversalScratch;
use super::shadow_ray::ShadowRay;
use super::walk::{ANY_ORDER, NEAREST_FIRST, WalkState, walk};
use super::watertight::WatertightRay;
use super::wide_bvh::{ChildRef, WideBvh};
use crate::scene::Scene;
use glam::{Vec3, Vec3A};

/// The BVH of a scene: its flat triangles in traversal order, and its instanced meshes
/// behind a second level (src/trace/bvh/instances.rs).
pub struct SceneBvh {
    pub(in crate::trace) tree: WideBvh,
    /// Triangles in BVH order: `triangles[i]` is scene triangle `scene_ids[i]`.
    pub(in crate::trace) triangles: Vec<[Vec3A; 3]>,
    pub(in crate::trace) scene_ids: Vec<u32>,
    /// Deepest level of the tree: the traversal stack never holds more entries.
    pub(in crate::trace) depth: usize,
    instances: Option<InstanceLevel>,
}

impl SceneBvh {
    pub fn build(scene: &Scene) -> Self {
        let mut bvh = Self::build_from_triangles(&scene.flat_triangles);
        bvh.instances = InstanceLevel::build(scene);
        bvh
    }

    pub fn build_from_triangles(tris: &[[Vec3; 3]]) -> Self {
        let FlatTree { tree, triangles, scene_ids, depth } = FlatTree::build(tris);
        SceneBvh { tree, triangles, scene_ids, depth, instances: None }
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
        TraversalScratch {
            outer: WalkState::new(self.depth.max(top)),
            inner: WalkState::new(mesh),
            packet: vec![(ChildRef::ROOT, 0, 0.0); 7 * self.depth + 1].into_boxed_slice(),
        }
    }

    /// The nearest hit with t ∈ [tmin, tmax] (tmin ≥ 0: the node test bounds distances from the
    /// origin forwards); among hits at the same t the lowest scene triangle id wins, so the
    /// result does not depend on the tree's shape.
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
        walk::<NEAREST_FIRST>(
            &self.tree,
            &mut scratch.outer,
            &node_ray,
            tmin,
            &mut best_t,
            0.0,
            |i, best_t| {
                let [v0, v1, v2] = self.triangles[i];
                if let Some(h) = ray.intersect(v0, v1, v2, tmin, *best_t) {
                    let hit = Hit {
                        triangle: self.scene_ids[i],
                        t: h.t,
                        barycentric: h.barycentric,
                        vertices: [v0, v1, v2].map(Vec3::from),
                    };
                    if hit.beats(&best) {
                        best = Some(hit);
                        *best_t = h.t;
                    }
                }
                false
            },
        );
        if let Some(instances) = &self.instances {
            instances.closest_hit(scratch, &ray, tmin, best_t, &mut best);
        }
        best
    }

    /// Whether any triangle is hit with t ∈ [tmin, tmax] (a closed interval, tmin ≥ 0).
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
        walk::<ANY_ORDER>(&self.tree, &mut scratch.outer, &node_ray, tmin, &mut tmax.clone(), 0.0, |i, _| {
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
        walk::<ANY_ORDER>(
            &self.tree,
            &mut scratch.outer,
            &node_ray,
            0.0,
            &mut shadow.tmax.clone(),
            0.0,
            |i, _| {
                let id = self.scene_ids[i];
                let [v0, v1, v2] = self.triangles[i];
                if id != shadow.skip_triangle && ray.intersect_beyond_error(v0, v1, v2, shadow.tmax).is_some()
                {
                    occluder = Some(id);
                }
                occluder.is_some()
            },
        );
        match &self.instances {
            Some(instances) if occluder.is_none() => {
                instances.any_hit(scratch, &ray, 0.0, shadow.tmax, shadow.skip_triangle, true)
            }
            _ => occluder,
        }
    }
}

/// The most rays `shadow_occluded` takes, and `closest_hits` walks, at once.
pub const RAYS_PER_BATCH: usize = 8;

/// Queries for many rays at once: the single-ray answers, walked eight at a time where the
/// processor and the rays allow (packet.rs).
impl SceneBvh {
    /// Bit k set where shadow ray k is occluded: `shadow_occluder(rays[k]).is_some()`.
    pub fn shadow_occluded(&self, scratch: &mut TraversalScratch, rays: &[ShadowRay]) -> u32 {
        #[cfg(target_arch = "x86_64")]
        if let Some(bits) = self.shadow_occluded_packet(scratch, rays) {
            return bits;
        }
        (0..rays.len()).map(|k| (self.shadow_occluder(scratch, &rays[k]).is_some() as u32) << k).sum()
    }

    /// `closest_hit(origin, directions[k], 0, ∞)` into `hits[k]` for each k, for any number of
    /// rays: neighbouring rays are walked `RAYS_PER_BATCH` at a time.
    pub fn closest_hits(
        &self,
        scratch: &mut TraversalScratch,
        origin: Vec3,
        directions: &[Vec3],
        hits: &mut [Option<Hit>],
    ) {
        for (directions, hits) in directions.chunks(RAYS_PER_BATCH).zip(hits.chunks_mut(RAYS_PER_BATCH)) {
            #[cfg(target_arch = "x86_64")]
            if self.closest_hits_packet(scratch, origin, directions, hits) {
                continue;
            }
            for (hit, &direction) in hits.iter_mut().zip(directions) {
                *hit = self.closest_hit(scratch, origin, direction, 0.0, f32::INFINITY);
            }
        }
    }

    #[cfg(target_arch = "x86_64")]
    fn shadow_occluded_packet(&self, scratch: &mut TraversalScratch, rays: &[ShadowRay]) -> Option<u32> {
        if rays.len() < 2 || rays.len() > LANES || !node_test::wide_available() {
            return None;
        }
        let lane = |k: usize| k.min(rays.len() - 1);
        let watertight: [WatertightRay; LANES] = std::array::from_fn(|k| {
            WatertightRay::new(rays[lane(k)].origin.into(), rays[lane(k)].direction.into())
        });
        // SAFETY: the processor has AVX2 (`wide_available`).
        let packet = unsafe { Packet::new(&watertight[..rays.len()]) }?;
        let mut tmax: [f32; LANES] = std::array::from_fn(|k| rays[lane(k)].tmax);
        // SAFETY: as above.
        let active = unsafe {
            self.walk_flat::<ANY_ORDER>(scratch, &packet, &mut tmax, |i, k, _| {
                let [v0, v1, v2] = self.triangles[i];
                self.scene_ids[i] != rays[k].skip_triangle
                    && watertight[k].intersect_beyond_error(v0, v1, v2, rays[k].tmax).is_some()
            })
        };
        let mut occluded = packet.lanes & !active;
        if let Some(instances) = &self.instances {
            for k in 0..rays.len() {
                if occluded & (1 << k) == 0 {
                    let hit = instances.any_hit(
                        scratch,
                        &watertight[k],
                        0.0,
                        rays[k].tmax,
                        rays[k].skip_triangle,
                        true,
                    );
                    occluded |= (hit.is_some() as u32) << k;
                }
            }
        }
        Some(occluded)
    }

    /// Walks the flat triangles' tree with `packet`, from every lane, and returns the lanes
    /// still active at the end (`walk_packet`'s `leaf` and `tmax`). Needs AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn walk_flat<const NEAREST: bool>(
        &self,
        scratch: &mut TraversalScratch,
        packet: &Packet,
        tmax: &mut [f32; LANES],
        leaf: impl FnMut(usize, usize, &mut [f32; LANES]) -> bool,
    ) -> u32 {
        let mut active = packet.lanes;
        walk_packet::<NEAREST>(
            &self.tree.nodes,
            &self.triangles,
            &mut scratch.packet,
            packet,
            &mut active,
            tmax,
            leaf,
        );
        active
    }

    #[cfg(target_arch = "x86_64")]
    fn closest_hits_packet(
        &self,
        scratch: &mut TraversalScratch,
        origin: Vec3,
        directions: &[Vec3],
        hits: &mut [Option<Hit>],
    ) -> bool {
        if directions.len() < 2 || directions.len() > LANES || !node_test::wide_available() {
            return false;
        }
        let lane = |k: usize| k.min(directions.len() - 1);
        let watertight: [WatertightRay; LANES] =
            std::array::from_fn(|k| WatertightRay::new(origin.into(), directions[lane(k)].into()));
        // SAFETY: the processor has AVX2 (`wide_available`).
        let Some(packet) = (unsafe { Packet::new(&watertight[..directions.len()]) }) else {
            return false;
        };
        let mut best = [None; LANES];
        let mut tmax = [f32::INFINITY; LANES];
        // SAFETY: as above.
        unsafe {
            self.walk_flat::<NEAREST_FIRST>(scratch, &packet, &mut tmax, |i, k, tmax| {
                let [v0, v1, v2] = self.triangles[i];
                if let Some(h) = watertight[k].intersect(v0, v1, v2, 0.0, tmax[k]) {
                    let hit = Hit {
                        triangle: self.scene_ids[i],
                        t: h.t,
                        barycentric: h.barycentric,
                        vertices: [v0, v1, v2].map(Vec3::from),
                    };
                    if hit.beats(&best[k]) {
                        best[k] = Some(hit);
                        tmax[k] = h.t;
                    }
                }
                false
            })
        };
        for (k, hit) in hits.iter_mut().enumerate().take(directions.len()) {
            if let Some(instances) = &self.instances {
                instances.closest_hit(scratch, &watertight[k], 0.0, tmax[k], &mut best[k]);
            }
            *hit = best[k];
        }
        true
    }
}
