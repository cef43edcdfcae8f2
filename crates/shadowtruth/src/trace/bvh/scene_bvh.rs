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

#[cfg(target_arch = "x86_64")]
use super::best_hits::BestHits;
use super::flat_tree::FlatTree;
use super::hit::Hit;
use super::instances::InstanceLevel;
#[cfg(target_arch = "x86_64")]
use super::lane_vector::{L8, L16, LaneMask, LaneVector};
use super::node_test::NodeRay;
#[cfg(target_arch = "x86_64")]
use super::packet::{LANES, LaneTriangle, Packet, each_lane, walk_packet};
#[cfg(target_arch = "x86_64")]
use super::packet_isa::{self, PacketQuery, in_packet_isa, packet_isa_for};
use super::scratch::TraversalScratch;
use super::shadow_ray::ShadowRay;
use super::shadow_search::{ShadowAnswer, ShadowSearch};
use super::walk::{ANY_ORDER, NEAREST_FIRST, WalkState, walk};
use super::watertight::WatertightRay;
use super::wide_bvh::{ChildRef, WideBvh};
use crate::scene::Scene;
use glam::Vec3;

/// The BVH of a scene: its flat triangles in traversal order, and its instanced meshes
/// behind a second level (src/trace/bvh/instances.rs).
pub struct SceneBvh {
    pub(in crate::trace) tree: WideBvh,
    /// Triangles in BVH order: `triangles[i]` is scene triangle `scene_ids[i]`.
    pub(in crate::trace) triangles: Vec<[Vec3; 3]>,
    pub(in crate::trace) scene_ids: Vec<u32>,
    /// Where each triangle's leaf hangs in the tree (`WideBvh::leaf_slots`), for the packet
    /// walks' certificates.
    #[cfg(target_arch = "x86_64")]
    pub(in crate::trace) leaf_slots: Vec<u32>,
    /// Deepest level of the tree: the traversal stack never holds more entries.
    pub(in crate::trace) depth: usize,
    pub(in crate::trace) instances: Option<InstanceLevel>,
    /// The triangles' exact bounds (min, max), computed once at build.
    bounds: (Vec3, Vec3),
}

impl SceneBvh {
    pub fn build(scene: &Scene) -> Self {
        let (lo, hi) = scene.bounds();
        let margin = segment_margin(lo, hi);
        let mut bvh = Self::build_with_margin(&scene.flat_triangles, margin, (lo, hi));
        bvh.instances = InstanceLevel::build(scene, margin);
        bvh
    }

    pub fn build_from_triangles(tris: &[[Vec3; 3]]) -> Self {
        let (lo, hi) = tris
            .iter()
            .flatten()
            .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), v| (lo.min(*v), hi.max(*v)));
        Self::build_with_margin(tris, segment_margin(lo, hi), (lo, hi))
    }

    fn build_with_margin(tris: &[[Vec3; 3]], margin: f32, bounds: (Vec3, Vec3)) -> Self {
        let FlatTree { tree, triangles, scene_ids, depth } = FlatTree::build(tris, margin);
        SceneBvh {
            #[cfg(target_arch = "x86_64")]
            leaf_slots: tree.leaf_slots(triangles.len()),
            tree,
            triangles,
            scene_ids,
            depth,
            instances: None,
            bounds,
        }
    }

    /// The exact bounds (min, max) of the triangles it was built from: `Scene::bounds` of its
    /// scene, which walks every instanced triangle again (at 100 M triangles, seconds).
    pub fn scene_bounds(&self) -> (Vec3, Vec3) {
        self.bounds
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
                        vertices: [v0, v1, v2],
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
            Some(instances) if !hit => instances.any_triangle(scratch, &ray, tmax, |_, v| {
                ray.intersect(v[0], v[1], v[2], tmin, tmax).is_some()
            }),
            _ => hit,
        }
    }
}

impl SceneBvh {
    /// The hard answer for one shadow ray: a triangle certainly meets its exact segment, none
    /// does, or neither is certain (shadow_search.rs).
    pub fn shadow_answer(&self, scratch: &mut TraversalScratch, shadow: &ShadowRay) -> ShadowAnswer {
        let (ray, mut tmax) = ShadowSearch::walk_ray(shadow);
        let node_ray = NodeRay::new(ray.origin, ray.direction);
        let (mut search, fast) = (ShadowSearch::new(shadow), ShadowSearch::fast_test(shadow, &ray));
        let mut over = false;
        walk::<ANY_ORDER>(&self.tree, &mut scratch.outer, &node_ray, 0.0, &mut tmax, 0.0, |i, _| {
            over = search.test(&fast, self.scene_ids[i], &self.triangles[i]);
            over
        });
        if let (Some(instances), false) = (&self.instances, over) {
            instances.any_triangle(scratch, &ray, tmax, |id, v| search.test(&fast, id, v));
        }
        search.answer()
    }

    /// The scene id of a triangle that occludes a shadow ray (any one, not the nearest), or
    /// `None`: the best guess of `shadow_answer`.
    pub fn shadow_occluder(&self, scratch: &mut TraversalScratch, shadow: &ShadowRay) -> Option<u32> {
        match self.shadow_answer(scratch, shadow) {
            ShadowAnswer::Lit => None,
            ShadowAnswer::Shadowed { occluder } => Some(occluder),
            ShadowAnswer::Uncertain { triangle, likely_shadowed } => likely_shadowed.then_some(triangle),
        }
    }
}

/// The answers for a batch of shadow rays: bit k for ray k.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ShadowBits {
    /// Shadowed, certainly or by the best guess.
    pub occluded: u32,
    /// Not decided beyond doubt.
    pub uncertain: u32,
}

impl ShadowBits {
    fn of(answers: impl Iterator<Item = ShadowAnswer>) -> ShadowBits {
        answers.enumerate().fold(ShadowBits::default(), |bits, (k, a)| ShadowBits {
            occluded: bits.occluded | (a.shadowed() as u32) << k,
            uncertain: bits.uncertain | (a.is_uncertain() as u32) << k,
        })
    }
}

/// How far every box of the tree grows so that walking a shadow ray's f32 ray never drops a box
/// its exact segment enters (shadow_search.rs), for a scene within the box [lo, hi]. Inside
/// that box the f32 ray lies within ε_o + t·ε_d of the exact segment: the f32 origin within
/// 2⁻²⁴·reach (reach the largest coordinate magnitude) plus the f64 point's error
/// (ε_p < 2⁻⁴⁵·reach), the f32 direction within 2⁻²⁴ plus the f64 direction's error, whose
/// part that grows with 1/length adds at most 3.5·ε_p over the segment, and t at most the box's
/// diagonal. So 2⁻²⁴·(reach + diagonal), and a little; twice that is the margin (and the
/// smallest normal f32, for a scene at the origin). Far from the origin the diagonal, not the
/// distance, sets the second term: the margin of a 12-unit island 10⁵ units out is 0.012.
fn segment_margin(lo: Vec3, hi: Vec3) -> f32 {
    let reach = lo.abs().max(hi.abs()).max_element() as f64;
    let diagonal = (hi.as_dvec3() - lo.as_dvec3()).length();
    ((reach + diagonal) * 2f64.powi(-23)) as f32 + f32::MIN_POSITIVE
}

/// The most rays `closest_hits` walks at once.
pub const RAYS_PER_BATCH: usize = 8;

/// The most rays `shadow_answers` takes at once, and the batch in which the references give rays
/// to `closest_hits`: one packet of sixteen where the processor has AVX-512, packets of eight
/// otherwise.
pub const WIDE_BATCH: usize = 16;

/// Queries for many rays at once: the single-ray answers, walked eight at a time (sixteen with
/// AVX-512) where the processor and the rays allow (packet.rs).
impl SceneBvh {
    /// `shadow_answer` for each ray (at most `WIDE_BATCH`), as bits.
    pub fn shadow_answers(&self, scratch: &mut TraversalScratch, rays: &[ShadowRay]) -> ShadowBits {
        assert!(rays.len() <= WIDE_BATCH, "at most {WIDE_BATCH} shadow rays at once");
        #[cfg(target_arch = "x86_64")]
        {
            if let Some(bits) = self.shadow_answers_packet(scratch, rays) {
                return bits;
            }
            if rays.len() > LANES {
                let (low, high) = (
                    self.shadow_answers(scratch, &rays[..LANES]),
                    self.shadow_answers(scratch, &rays[LANES..]),
                );
                return ShadowBits {
                    occluded: low.occluded | high.occluded << LANES,
                    uncertain: low.uncertain | high.uncertain << LANES,
                };
            }
        }
        ShadowBits::of(rays.iter().map(|ray| self.shadow_answer(scratch, ray)))
    }

    /// Bit k set where shadow ray k is occluded (by `shadow_answer`'s best guess).
    pub fn shadow_occluded(&self, scratch: &mut TraversalScratch, rays: &[ShadowRay]) -> u32 {
        self.shadow_answers(scratch, rays).occluded
    }

    /// `closest_hit(origin, directions[k], 0, ∞)` into `hits[k]` for each k, for any number of
    /// rays: neighbouring rays are walked sixteen at a time where the processor has AVX-512,
    /// otherwise `RAYS_PER_BATCH` at a time.
    pub fn closest_hits(
        &self,
        scratch: &mut TraversalScratch,
        origin: Vec3,
        directions: &[Vec3],
        hits: &mut [Option<Hit>],
    ) {
        #[cfg(target_arch = "x86_64")]
        if packet_isa_for(PacketQuery::SixteenLanes).is_some() {
            for (directions, hits) in directions.chunks(L16::LANES).zip(hits.chunks_mut(L16::LANES)) {
                let sixteen = directions.len() > LANES
                    && self.closest_hits_packet::<L16, { L16::LANES }>(
                        PacketQuery::SixteenLanes,
                        scratch,
                        origin,
                        directions,
                        hits,
                    );
                if !sixteen {
                    self.closest_hits_by_eight(scratch, origin, directions, hits);
                }
            }
            return;
        }
        self.closest_hits_by_eight(scratch, origin, directions, hits);
    }

    /// `closest_hits`, walked `RAYS_PER_BATCH` at a time.
    fn closest_hits_by_eight(
        &self,
        scratch: &mut TraversalScratch,
        origin: Vec3,
        directions: &[Vec3],
        hits: &mut [Option<Hit>],
    ) {
        for (directions, hits) in directions.chunks(RAYS_PER_BATCH).zip(hits.chunks_mut(RAYS_PER_BATCH)) {
            #[cfg(target_arch = "x86_64")]
            if self.closest_hits_packet::<L8, { L8::LANES }>(
                PacketQuery::ClosestHits,
                scratch,
                origin,
                directions,
                hits,
            ) {
                continue;
            }
            for (hit, &direction) in hits.iter_mut().zip(directions) {
                *hit = self.closest_hit(scratch, origin, direction, 0.0, f32::INFINITY);
            }
        }
    }

    #[cfg(target_arch = "x86_64")]
    fn shadow_answers_packet(
        &self,
        scratch: &mut TraversalScratch,
        rays: &[ShadowRay],
    ) -> Option<ShadowBits> {
        match rays.len() {
            // One ray walks alone.
            0..=1 => None,
            // SAFETY: the processor has AVX2 and FMA (`packet_isa_for`), and the walk is
            // compiled for it.
            2..=LANES => in_packet_isa(
                packet_isa_for(PacketQuery::Shadows)?,
                #[inline(always)]
                || unsafe { self.shadow_answers_wide::<L8, { L8::LANES }>(scratch, rays) },
            ),
            // SAFETY: the processor has AVX-512 (`packet_isa_for`), and the walk is compiled
            // for it.
            _ => in_packet_isa(
                packet_isa_for(PacketQuery::SixteenLanes)?,
                #[inline(always)]
                || unsafe { self.shadow_answers_wide::<L16, { L16::LANES }>(scratch, rays) },
            ),
        }
    }

    /// `shadow_answers_packet` in packets of `V` (`N` = `V::LANES` rays, at most), once the
    /// processor is known to have its instruction set.
    ///
    /// # Safety
    /// The processor has `V`'s instruction set, and the caller is compiled for it
    /// (`in_packet_isa`).
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    unsafe fn shadow_answers_wide<V: LaneVector, const N: usize>(
        &self,
        scratch: &mut TraversalScratch,
        rays: &[ShadowRay],
    ) -> Option<ShadowBits> {
        assert!(N == V::LANES && (1..=N).contains(&rays.len()));
        let lane = |k: usize| k.min(rays.len() - 1);
        // Written in place, in plain loops: the arrays `array::from_fn` and `map` made were
        // copied again (1 % of the shadow rays' instructions; 1.8 KB of searches), and so was a
        // constant array of rays to start from (1.3 KB).
        let (first, first_tmax) = ShadowSearch::walk_ray(&rays[0]);
        let (mut watertight, mut tmax) = ([first; N], V::Array::default());
        tmax.as_mut()[0] = first_tmax;
        for k in 1..N {
            (watertight[k], tmax.as_mut()[k]) = ShadowSearch::walk_ray(&rays[lane(k)]);
        }
        // SAFETY: the caller's.
        let mut packet = unsafe { Packet::<V>::new(&watertight[..rays.len()]) }?;
        // Each lane's f32 test is made here for its bounds, and again for each triangle the
        // packet leaves to it (about one a hundred rays on the forest): kept, the sixteen tests
        // were 1.5 KB written for every packet.
        let fast_test = |k: usize| ShadowSearch::fast_test(&rays[lane(k)], &watertight[k]);
        let (mut slack, mut segments) = ([(0.0, 0.0); N], [(0.0, 0.0, 0.0); N]);
        for k in 0..N {
            let fast = fast_test(k);
            slack[k] = fast.sheared_error_coefficients();
            let (fixed, per_reach) = fast.distance_error_coefficients();
            segments[k] = (fixed, per_reach, fast.least_length());
        }
        packet.certify(&slack);
        packet.certify_hits(&segments);
        let mut searches = [ShadowSearch::new(&rays[0]); N];
        for (k, search) in searches.iter_mut().enumerate().skip(1) {
            *search = ShadowSearch::new(&rays[lane(k)]);
        }
        // Each lane's own triangle, which it never tests, found for the whole packet at once: it
        // was most of the lanes a leaf's rejection left to their own test (docs/scale.md).
        let mut own = V::Array::default();
        for (k, own) in own.as_mut().iter_mut().enumerate() {
            *own = f32::from_bits(rays[lane(k)].skip_triangle);
        }
        // SAFETY: the caller's.
        let own = unsafe { V::load(&own) };
        let reach = tmax;
        let active = self.walk_flat_any_hit(
            scratch,
            &packet,
            &mut tmax,
            #[inline(always)]
            |i| own.bits_equal(self.scene_ids[i]).bits(),
            #[inline(always)]
            |i, k| searches[k].test(&fast_test(k), self.scene_ids[i], &self.triangles[i]),
        );
        if let Some(instances) = &self.instances {
            for k in 0..rays.len() {
                if active & (1 << k) != 0 {
                    let (search, fast, walk) = (&mut searches[k], fast_test(k), &watertight[k]);
                    instances
                        .any_triangle(scratch, walk, reach.as_ref()[k], |id, v| search.test(&fast, id, v));
                }
            }
        }
        // A lane that left the walk found a certain occluder, by its own test or the packet's.
        let occluded = packet.lanes & !active;
        let bits = ShadowBits::of(searches[..rays.len()].iter().map(ShadowSearch::answer));
        Some(ShadowBits { occluded: bits.occluded | occluded, uncertain: bits.uncertain & !occluded })
    }

    /// Walks the flat triangles' tree with `packet`, from every lane, and returns the lanes
    /// still active at the end (`walk_packet`'s `skipped`, `leaf` and `tmax`).
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub(in crate::trace) fn walk_flat<V: LaneVector, const NEAREST: bool>(
        &self,
        scratch: &mut TraversalScratch,
        packet: &Packet<V>,
        tmax: &mut V::Array,
        skipped: impl Fn(usize) -> u32,
        leaf: impl FnMut(usize, u32, &LaneTriangle<V>, &mut V::Array) -> u32,
    ) -> u32 {
        let mut active = packet.lanes;
        let (nodes, triangles) = (&self.tree.nodes, &self.triangles);
        walk_packet::<V, NEAREST>(
            nodes,
            triangles,
            &mut scratch.packet,
            packet,
            &mut active,
            tmax,
            skipped,
            leaf,
        );
        active
    }

    /// `walk_flat` in node order, with `test(i, lane)` for each lane that may hit flat
    /// triangle `i`, but those of `skipped(i)`: true finishes the lane. A lane the packet found
    /// certainly hitting it (`Packet::certify_hits`) is finished without its test. Returns the
    /// lanes still active at the end.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub(in crate::trace) fn walk_flat_any_hit<V: LaneVector>(
        &self,
        scratch: &mut TraversalScratch,
        packet: &Packet<V>,
        tmax: &mut V::Array,
        skipped: impl Fn(usize) -> u32,
        mut test: impl FnMut(usize, usize) -> bool,
    ) -> u32 {
        // Both closures inlined: where the compiler called them instead, the leaf test ran
        // outside the packet walk's instruction set, and shadow rays ran 7 % slower.
        self.walk_flat::<V, ANY_ORDER>(
            scratch,
            packet,
            tmax,
            skipped,
            #[inline(always)]
            |i, candidates, seen, _| {
                let certain = seen.certain & candidates;
                certain
                    | each_lane(
                        candidates & !certain,
                        #[inline(always)]
                        |k| test(i, k),
                    )
            },
        )
    }

    /// The closest hits of the rays along `directions` as one packet of `V` (`N` = `V::LANES`),
    /// walked compiled for the instruction set of `query`, which must have `V`'s; false, without
    /// walking, where they cannot walk so.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn closest_hits_packet<V: LaneVector, const N: usize>(
        &self,
        query: PacketQuery,
        scratch: &mut TraversalScratch,
        origin: Vec3,
        directions: &[Vec3],
        hits: &mut [Option<Hit>],
    ) -> bool {
        with_primary_packet::<V, N>(
            query,
            origin,
            directions,
            #[inline(always)]
            |watertight, packet| self.closest_hits_of_packet(scratch, watertight, &packet, hits),
        )
    }

    /// The closest hits of `packet`'s rays (`watertight`, as `primary_packet` makes them) into
    /// `hits`, one per ray.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub(in crate::trace) fn closest_hits_of_packet<V: LaneVector, const N: usize>(
        &self,
        scratch: &mut TraversalScratch,
        watertight: &[WatertightRay; N],
        packet: &Packet<V>,
        hits: &mut [Option<Hit>],
    ) {
        let mut tmax = V::Array::default();
        tmax.as_mut().fill(f32::INFINITY);
        let best = self.walk_closest_hits(scratch, watertight, packet, &mut tmax, |t| t, |_, _| {});
        hits.copy_from_slice(&best[..hits.len()]);
    }

    /// The closest hit of each lane of `packet` (`watertight`, as `primary_packet` makes them),
    /// flat triangles and instances: the least (distance, scene id) of the watertight hits. Each
    /// lane looks as far as `tmax`, which ends as `look_beyond(t)` of its hit's distance t
    /// (`look_beyond(t) ≥ t`: a walk that looks further reaches more leaves, and the same least
    /// hit). `seen(i, lanes)` hears of each flat triangle `i` with the lanes `walk_packet` gave
    /// it.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub(in crate::trace) fn walk_closest_hits<V: LaneVector, const N: usize>(
        &self,
        scratch: &mut TraversalScratch,
        watertight: &[WatertightRay; N],
        packet: &Packet<V>,
        tmax: &mut V::Array,
        look_beyond: impl Fn(V) -> V,
        mut seen: impl FnMut(usize, u32),
    ) -> [Option<Hit>; N] {
        // SAFETY: `packet` exists, so the processor has `V`'s set.
        let mut closest = unsafe { BestHits::<V>::new() };
        self.walk_flat::<V, NEAREST_FIRST>(
            scratch,
            packet,
            tmax,
            |_| 0,
            #[inline(always)]
            |i, candidates, triangle, tmax| {
                seen(i, candidates);
                // Every lane solved at once; those the f64 test must settle, one by one.
                let mut solved = packet.intersect(triangle, candidates, tmax);
                each_lane(solved.scalar, |k| {
                    let [v0, v1, v2] = self.triangles[i];
                    if let Some(h) = watertight[k].intersect(v0, v1, v2, 0.0, tmax.as_ref()[k]) {
                        solved.set_lane(k, h);
                    }
                    false
                });
                closest.take(&solved, i, self.scene_ids[i], tmax, &look_beyond);
                0
            },
        );
        let mut best = closest.hits::<N>(|i| (self.scene_ids[i], self.triangles[i]));
        if let Some(instances) = &self.instances {
            each_lane(packet.lanes, |k| {
                instances.closest_hit(scratch, &watertight[k], 0.0, tmax.as_ref()[k], &mut best[k]);
                false
            });
        }
        best
    }
}

/// Runs `walk` on the primary rays from `origin` along `directions` as a packet, with each
/// lane's watertight ray (`primary_packet`), compiled for the instruction set of `query`
/// (`packet_isa_for`); false, without running it, where the rays cannot walk as a packet.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(in crate::trace) fn with_primary_packet<V: LaneVector, const N: usize>(
    query: PacketQuery,
    origin: Vec3,
    directions: &[Vec3],
    walk: impl FnOnce(&[WatertightRay; N], Packet<V>),
) -> bool {
    let Some(isa) = packet_isa_for(query) else {
        return false;
    };
    in_packet_isa(
        isa,
        #[inline(always)]
        || {
            let mut watertight = [WatertightRay::UNUSED; N];
            // SAFETY: `query`'s set has `V`'s (the caller's).
            let Some(packet) = (unsafe { primary_packet::<V, N>(origin, directions, &mut watertight) })
            else {
                return false;
            };
            walk(&watertight, packet);
            true
        },
    )
}

/// The primary rays from `origin` along `directions` (two to `N` = `V::LANES`) as a packet,
/// each lane's watertight ray written to `watertight` (lanes past the last repeat it), or `None`
/// where they cannot share a walk or the processor has no AVX2. The rays are written in place,
/// not returned: moving eight of them and the packet cost a tenth of a packet's walk in copies.
///
/// # Safety
/// The processor has `V`'s instruction set where it has AVX2.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(in crate::trace) unsafe fn primary_packet<V: LaneVector, const N: usize>(
    origin: Vec3,
    directions: &[Vec3],
    watertight: &mut [WatertightRay; N],
) -> Option<Packet<V>> {
    assert_eq!(N, V::LANES);
    if directions.len() < 2 || directions.len() > N || !packet_isa::wide_available() {
        return None;
    }
    // SAFETY: the processor has AVX2 and FMA (`wide_available`), and so `V`'s set (the caller's).
    unsafe { Packet::<V>::from_origin(origin, directions, watertight) }
}
