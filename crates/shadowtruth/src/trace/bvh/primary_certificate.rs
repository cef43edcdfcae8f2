//! Whether a primary ray's closest hit is certainly the exact one (docs/reference.md, "The
//! reference's uncertainty"). The camera's f32 origin and the pixel's f32 direction define the
//! ray exactly, so the certified test (certified.rs) runs with no origin or direction error:
//! the hit triangle must certainly be crossed, and a second walk over [0, t + δt] must find no
//! other triangle that may be crossed before it — f32 first, f64 where f32 cannot tell. Two
//! triangles in one plane crossed at one point tie exactly; the lowest scene id wins, as the
//! definition says, even where the f32 distances happened to differ. A ray that hits nothing
//! is certified by finding no triangle it may cross at all.

use super::certified::{CertifiedRay, Crossing, Verdict, in_one_plane};
use super::hit::Hit;
#[cfg(target_arch = "x86_64")]
use super::lane_vector::{L8, L16, LaneVector};
use super::node_test::NodeRay;
#[cfg(target_arch = "x86_64")]
use super::own_crossing::own_crossings;
use super::own_crossing::{OwnCrossing, in_f64};
#[cfg(target_arch = "x86_64")]
use super::packet::{LANES, Packet, each_lane};
#[cfg(target_arch = "x86_64")]
use super::packet_isa::{PacketQuery, packet_isa_for};
#[cfg(target_arch = "x86_64")]
use super::scene_bvh::with_primary_packet;
use super::scene_bvh::{RAYS_PER_BATCH, SceneBvh};
use super::scratch::TraversalScratch;
use super::walk::{ANY_ORDER, walk};
use super::watertight::WatertightRay;
use crate::scene::is_degenerate;
use glam::{Vec3, Vec3A};

/// What the certificate says of a primary ray's closest hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(in crate::trace) enum PrimaryCertainty {
    Certain,
    Uncertain,
}

/// The exact ray in f32 and in f64, as segments up to a distance.
struct RayForms {
    origin: Vec3,
    direction: Vec3,
}

impl RayForms {
    fn in_f32(&self, length: f64, length_error: f64) -> CertifiedRay<f32> {
        CertifiedRay::new(self.origin.to_array(), 0.0, self.direction.to_array(), 0.0, length, length_error)
    }

    fn in_f64(&self, length: f64, length_error: f64) -> CertifiedRay<f64> {
        let (o, d) = (self.origin.as_dvec3(), self.direction.as_dvec3());
        CertifiedRay::new(o.to_array(), 0.0, d.to_array(), 0.0, length, length_error)
    }

    /// Whether the ray crosses `v`: f32 first, then f64 where f32 is in doubt.
    fn crossing(&self, v: &[Vec3; 3]) -> Crossing {
        match self.in_f32(f64::INFINITY, 0.0).crossing(&v.map(|p| p.to_array())) {
            Crossing::Doubt { .. } => {
                self.in_f64(f64::INFINITY, 0.0).crossing(&v.map(|p| p.as_dvec3().to_array()))
            }
            decided => decided,
        }
    }
}

/// One primary ray's certificate, triangle by triangle as the walk reaches them. Kept small
/// (a packet holds eight): the f64 forms of the ray are made where f32 is in doubt, rarely.
struct PrimarySearch<'h> {
    /// The walk's bound on the distance: the hit's, rounded up (∞ for a miss).
    tmax: f32,
    own: Option<&'h Hit>,
    fast: CertifiedRay<f32>,
    /// The exact hit's distance lies within `length` ± `length_error`.
    length: f64,
    length_error: f64,
    uncertain: bool,
    tie: Option<(u32, [Vec3; 3])>,
    /// The hit's barycentrics computed in f64 (`refine_barycentrics`).
    refined: Option<[f32; 3]>,
}

impl<'h> PrimarySearch<'h> {
    /// The search for `hit`, the closest hit of `walk` (the ray from the camera along the
    /// pixel's direction), whose crossing of its own triangle is `own` (`OwnCrossing::of`);
    /// already uncertain when the hit itself is not certainly crossed.
    fn new(walk: &WatertightRay, hit: Option<&'h Hit>, own: OwnCrossing) -> Self {
        let tmax = own.reach();
        let OwnCrossing { length, length_error, uncertain, refined } = own;
        let fast = CertifiedRay::of_walk(walk, 0.0, 0.0, length, length_error);
        PrimarySearch { tmax, own: hit, fast, length, length_error, uncertain, tie: None, refined }
    }

    /// Tests the scene triangle `id`; true once the search is over: the verdict is uncertain,
    /// for a triangle certainly crossed before the hit or one that may be (an exact tie in the
    /// hit's plane is noted instead).
    fn test(&mut self, walk: &WatertightRay, id: u32, v: &[Vec3; 3]) -> bool {
        if self.uncertain {
            return true;
        }
        if self.own.is_some_and(|own| own.triangle == id) {
            return false;
        }
        let in_doubt = match self.fast.classify(&v.map(|p| p.to_array())) {
            Verdict::Miss => return false,
            Verdict::Hit => false,
            Verdict::Doubt { .. } => match self.classify_precisely(walk, v) {
                Verdict::Miss => return false,
                Verdict::Hit => false,
                Verdict::Doubt { .. } => true,
            },
        };
        if in_doubt && is_degenerate(v) {
            return false;
        }
        if let (true, Some(own)) = (in_doubt, self.own)
            && in_one_plane(&own.vertices, v)
        {
            // Crossed, if at all, at the hit's own point: an exact tie, lowest id first.
            if id > own.triangle || self.tie.is_some_and(|(t, _)| t < id) {
                return false;
            }
            match forms(walk).crossing(v) {
                Crossing::Miss => return false,
                Crossing::Through { .. } => {
                    self.tie = Some((id, *v));
                    return false;
                }
                Crossing::Doubt { .. } => {}
            }
        }
        self.uncertain = true;
        true
    }

    #[cold]
    #[inline(never)]
    fn classify_precisely(&self, walk: &WatertightRay, v: &[Vec3; 3]) -> Verdict {
        let precise = forms(walk).in_f64(self.length, self.length_error);
        precise.classify(&v.map(|p| p.as_dvec3().to_array()))
    }

    /// The verdict, and `hit` as the G-buffer keeps it: its barycentrics computed in f64, or the
    /// exact tie that replaces it.
    fn finish(&self, walk: &WatertightRay, hit: &mut Option<Hit>) -> PrimaryCertainty {
        keep_refined(hit, self.refined);
        match (self.uncertain, self.tie) {
            (true, _) => PrimaryCertainty::Uncertain,
            (false, None) => PrimaryCertainty::Certain,
            (false, Some((id, vertices))) => match tie_hit(walk, id, vertices) {
                Some(mut tie) => {
                    refine_barycentrics(walk, &mut tie);
                    *hit = Some(tie);
                    PrimaryCertainty::Certain
                }
                None => PrimaryCertainty::Uncertain,
            },
        }
    }
}

/// `PrimarySearch::finish` for a search that had nothing to test: the hit's own crossing decides.
#[cfg(target_arch = "x86_64")]
fn settle_untested(own: OwnCrossing, hit: &mut Option<Hit>) -> PrimaryCertainty {
    keep_refined(hit, own.refined);
    if own.uncertain { PrimaryCertainty::Uncertain } else { PrimaryCertainty::Certain }
}

/// The hit with its barycentrics computed in f64, where they were.
fn keep_refined(hit: &mut Option<Hit>, refined: Option<[f32; 3]>) {
    if let (Some(hit), Some(b)) = (hit.as_mut(), refined) {
        hit.barycentric = b;
    }
}

/// The exact ray `walk` stands for (the camera's f32 origin, the pixel's f32 direction).
fn forms(walk: &WatertightRay) -> RayForms {
    RayForms { origin: walk.origin.into(), direction: walk.direction.into() }
}

impl SceneBvh {
    /// Certifies each of `hits`, the closest hits of the rays from `origin` along
    /// `directions`, into `certainties`, and leaves each hit as the G-buffer keeps it: its
    /// barycentrics computed again in f64 (`refine_barycentrics`), and where a triangle in its
    /// plane with a lower id ties with it exactly, that triangle's hit. The rays are walked
    /// `RAYS_PER_BATCH` at a time where they can share a walk (packet.rs), with the answers of
    /// one at a time.
    pub(in crate::trace) fn certify_primaries(
        &self,
        scratch: &mut TraversalScratch,
        origin: Vec3,
        directions: &[Vec3],
        hits: &mut [Option<Hit>],
        certainties: &mut [PrimaryCertainty],
    ) {
        let chunks = directions.chunks(RAYS_PER_BATCH).zip(hits.chunks_mut(RAYS_PER_BATCH));
        for ((directions, hits), out) in chunks.zip(certainties.chunks_mut(RAYS_PER_BATCH)) {
            #[cfg(target_arch = "x86_64")]
            if self.certify_primaries_packet(scratch, origin, directions, hits, out) {
                continue;
            }
            for ((out, &direction), hit) in out.iter_mut().zip(directions).zip(hits) {
                *out = self.certify_primary(scratch, origin, direction, hit);
            }
        }
    }

    /// `certify_primaries` for one ray.
    pub(in crate::trace) fn certify_primary(
        &self,
        scratch: &mut TraversalScratch,
        origin: Vec3,
        direction: Vec3,
        hit: &mut Option<Hit>,
    ) -> PrimaryCertainty {
        let walk_ray = WatertightRay::new(origin.into(), direction.into());
        let own = *hit;
        let mut search =
            PrimarySearch::new(&walk_ray, own.as_ref(), OwnCrossing::of(&walk_ray, own.as_ref()));
        if !search.uncertain {
            let node_ray = NodeRay::new(walk_ray.origin, walk_ray.direction);
            let mut tmax = search.tmax;
            let mut over = false;
            walk::<ANY_ORDER>(&self.tree, &mut scratch.outer, &node_ray, 0.0, &mut tmax, 0.0, |i, _| {
                over = search.test(&walk_ray, self.scene_ids[i], &self.triangles[i]);
                over
            });
            if let (Some(instances), false) = (&self.instances, over) {
                instances.any_triangle(scratch, &walk_ray, tmax, |id, v| search.test(&walk_ray, id, v));
            }
        }
        search.finish(&walk_ray, hit)
    }

    #[cfg(target_arch = "x86_64")]
    fn certify_primaries_packet(
        &self,
        scratch: &mut TraversalScratch,
        origin: Vec3,
        directions: &[Vec3],
        hits: &mut [Option<Hit>],
        out: &mut [PrimaryCertainty],
    ) -> bool {
        with_primary_packet::<L8, { L8::LANES }>(
            PacketQuery::CertifiedHits,
            origin,
            directions,
            #[inline(always)]
            |watertight, packet| self.certify_packet(scratch, watertight, packet, hits, out),
        )
    }

    /// `certify_primaries` for the rays of `packet` (`watertight`, as `primary_packet` makes
    /// them), whose closest hits are `hits`.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn certify_packet<V: LaneVector, const N: usize>(
        &self,
        scratch: &mut TraversalScratch,
        watertight: &[WatertightRay; N],
        mut packet: Packet<V>,
        hits: &mut [Option<Hit>],
        out: &mut [PrimaryCertainty],
    ) {
        let lane = |k: usize| k.min(hits.len() - 1);
        let own: [Option<Hit>; N] = std::array::from_fn(|k| hits[lane(k)]);
        let crossings = own_crossings::<V, N>(watertight, &own);
        let mut searches: [PrimarySearch; N] =
            std::array::from_fn(|k| PrimarySearch::new(&watertight[k], own[k].as_ref(), crossings[k]));
        packet.certify(&searches.each_ref().map(|s| s.fast.sheared_error_coefficients()));
        let mut tmax = reaches::<V, N>(&crossings);
        let active = self.walk_flat_any_hit(
            scratch,
            &packet,
            &mut tmax,
            |_| 0,
            #[inline(always)]
            |i, k| searches[k].test(&watertight[k], self.scene_ids[i], &self.triangles[i]),
        );
        for (k, (out, hit)) in out.iter_mut().zip(hits.iter_mut()).enumerate() {
            let (search, walk_ray) = (&mut searches[k], &watertight[k]);
            if let (Some(instances), true) = (&self.instances, active & (1 << k) != 0) {
                instances
                    .any_triangle(scratch, walk_ray, tmax.as_ref()[k], |id, v| search.test(walk_ray, id, v));
            }
            *out = search.finish(walk_ray, hit);
        }
    }

    /// `closest_hits_of_packet` then `certify_packet` in one walk where it can: the closest-hit
    /// walk notes, for each lane, the flat triangles that the certificate's test does not reject
    /// outright (`Noted`), looking a little beyond each hit (`look_beyond`). The certificate then
    /// tests those of the noted triangles whose leaf box (`SceneBvh::leaf_slots`) the lane's own
    /// node test meets within the certificate's reach: exactly the triangles its own walk would
    /// test. That walk reaches a leaf for a lane when the lane's test meets the
    /// leaf's box within its reach (the frustum keeps every box around it, the test being
    /// monotone in the planes), and the closest-hit walk tested the same box with a reach no
    /// shorter, so it noted every such triangle; the order of the tests does not change the
    /// verdict. Where a lane noted more than `Noted` holds, or its certificate reaches beyond
    /// the walk's, the certificate walks on its own (`certify_packet`).
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn certified_hits_of_packet<V: LaneVector, const N: usize>(
        &self,
        scratch: &mut TraversalScratch,
        watertight: &[WatertightRay; N],
        mut packet: Packet<V>,
        hits: &mut [Option<Hit>],
        out: &mut [PrimaryCertainty],
    ) {
        // The certificate's rejection of the leaves' triangles, as `certify_packet` sets it: its
        // slack depends only on the ray's errors (none: the ray is exact), not on the hit.
        let unbounded = |k: usize| CertifiedRay::<f32>::of_walk(&watertight[k], 0.0, 0.0, f64::INFINITY, 0.0);
        packet.certify(&std::array::from_fn::<_, N, _>(|k| unbounded(k).sheared_error_coefficients()));
        let mut noted = Noted::<N>::new();
        let mut tmax = V::Array::default();
        tmax.as_mut().fill(f32::INFINITY);
        let best =
            self.walk_closest_hits(scratch, watertight, &packet, &mut tmax, look_beyond, |i, lanes| {
                noted.note(i, lanes)
            });
        hits.copy_from_slice(&best[..hits.len()]);
        let crossings = own_crossings::<V, N>(watertight, &best);
        let reach = reaches::<V, N>(&crossings);
        let complete = each_lane(packet.lanes, |k| {
            noted.overflow & (1 << k) == 0 && reach.as_ref()[k] <= tmax.as_ref()[k]
        });
        if complete != packet.lanes {
            return self.certify_packet(scratch, watertight, packet, hits, out);
        }
        for (k, (out, hit)) in out.iter_mut().zip(hits.iter_mut()).enumerate() {
            // Most of what a lane notes is its hit's own triangle, which the certificate passes
            // over: a lane left nothing else to test is settled without a search.
            let own_id = hit.map(|h| h.triangle);
            let mut others =
                noted.of(k).iter().filter(|&&i| Some(self.scene_ids[i as usize]) != own_id).peekable();
            if others.peek().is_none() && self.instances.is_none() {
                *out = settle_untested(crossings[k], hit);
                continue;
            }
            let walk_ray = &watertight[k];
            let mut search = PrimarySearch::new(walk_ray, best[k].as_ref(), crossings[k]);
            debug_assert_eq!(
                search.fast.sheared_error_coefficients(),
                unbounded(k).sheared_error_coefficients()
            );
            let mut over = false;
            for &i in others {
                let (node, slot) = self.tree.leaf_box(self.leaf_slots[i as usize]);
                let reached = packet.lanes_meeting(node, slot, &reach) & (1 << k) != 0;
                if reached && search.test(walk_ray, self.scene_ids[i as usize], &self.triangles[i as usize]) {
                    over = true;
                    break;
                }
            }
            if let (Some(instances), false) = (&self.instances, over) {
                instances
                    .any_triangle(scratch, walk_ray, reach.as_ref()[k], |id, v| search.test(walk_ray, id, v));
            }
            *out = search.finish(walk_ray, hit);
        }
    }

    /// The closest hits of the rays from `origin` along `directions`, certified as
    /// `certify_primaries` certifies them: `closest_hits` then `certify_primaries`, the two walks
    /// as one where they can (`certified_hits_of_packet`), sixteen rays at a time where the
    /// processor has AVX-512, otherwise `RAYS_PER_BATCH`.
    pub(in crate::trace) fn certified_closest_hits(
        &self,
        scratch: &mut TraversalScratch,
        origin: Vec3,
        directions: &[Vec3],
        hits: &mut [Option<Hit>],
        certainties: &mut [PrimaryCertainty],
    ) {
        #[cfg(target_arch = "x86_64")]
        if packet_isa_for(PacketQuery::SixteenLanes).is_some() {
            let chunks = directions.chunks(L16::LANES).zip(hits.chunks_mut(L16::LANES));
            for ((directions, hits), out) in chunks.zip(certainties.chunks_mut(L16::LANES)) {
                let sixteen = directions.len() > LANES
                    && with_primary_packet::<L16, { L16::LANES }>(
                        PacketQuery::SixteenLanes,
                        origin,
                        directions,
                        #[inline(always)]
                        |watertight, packet| {
                            self.certified_hits_of_packet(scratch, watertight, packet, hits, out)
                        },
                    );
                if !sixteen {
                    self.certified_closest_hits_by_eight(scratch, origin, directions, hits, out);
                }
            }
            return;
        }
        self.certified_closest_hits_by_eight(scratch, origin, directions, hits, certainties);
    }

    /// `certified_closest_hits`, `RAYS_PER_BATCH` rays at a time.
    fn certified_closest_hits_by_eight(
        &self,
        scratch: &mut TraversalScratch,
        origin: Vec3,
        directions: &[Vec3],
        hits: &mut [Option<Hit>],
        certainties: &mut [PrimaryCertainty],
    ) {
        let chunks = directions.chunks(RAYS_PER_BATCH).zip(hits.chunks_mut(RAYS_PER_BATCH));
        for ((directions, hits), out) in chunks.zip(certainties.chunks_mut(RAYS_PER_BATCH)) {
            #[cfg(target_arch = "x86_64")]
            if with_primary_packet::<L8, { L8::LANES }>(
                PacketQuery::CertifiedHits,
                origin,
                directions,
                #[inline(always)]
                |watertight, packet| self.certified_hits_of_packet(scratch, watertight, packet, hits, out),
            ) {
                continue;
            }
            self.closest_hits(scratch, origin, directions, hits);
            self.certify_primaries(scratch, origin, directions, hits, out);
        }
    }
}

/// How far a closest-hit walk that certifies its hits looks beyond a hit at distance `t`: the
/// certificate's reach is the hit's exact distance and its error bound, rounded up, which lies
/// within a few ulps of t but for the most grazing hits (those beyond walk on their own).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn look_beyond<V: LaneVector>(t: V) -> V {
    // SAFETY: `t` exists, so the processor has `V`'s set.
    t.mul(unsafe { V::splat(1.0 + 2f32.powi(-12)) })
}

/// Each lane's certificate's search radius (`OwnCrossing::reach`).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn reaches<V: LaneVector, const N: usize>(crossings: &[OwnCrossing; N]) -> V::Array {
    let mut reach = V::Array::default();
    for (r, own) in reach.as_mut().iter_mut().zip(crossings) {
        *r = own.reach();
    }
    reach
}

/// A lane's triangles noted at most: a pixel's ray passes through few triangles' outlines
/// before the walk is done.
#[cfg(target_arch = "x86_64")]
const NOTED_CAPACITY: usize = 16;

/// The flat triangles a packet's closest-hit walk noted for each of its `N` lanes'
/// certificates (`certified_hits_of_packet`).
#[cfg(target_arch = "x86_64")]
struct Noted<const N: usize> {
    triangles: [[u32; NOTED_CAPACITY]; N],
    count: [u8; N],
    /// Lanes that noted more than `NOTED_CAPACITY`.
    overflow: u32,
}

#[cfg(target_arch = "x86_64")]
impl<const N: usize> Noted<N> {
    fn new() -> Self {
        Noted { triangles: [[0; NOTED_CAPACITY]; N], count: [0; N], overflow: 0 }
    }

    /// Notes triangle `i` for each lane of `lanes`.
    #[inline(always)]
    fn note(&mut self, i: usize, lanes: u32) {
        each_lane(lanes, |k| {
            let n = self.count[k] as usize;
            if n == NOTED_CAPACITY {
                self.overflow |= 1 << k;
            } else {
                self.triangles[k][n] = i as u32;
                self.count[k] += 1;
            }
            false
        });
    }

    /// The triangles lane `k` noted.
    fn of(&self, k: usize) -> &[u32] {
        &self.triangles[k][..self.count[k] as usize]
    }
}

/// `hit`'s barycentrics computed again in f64 and rounded to f32. The f32 watertight test's
/// are off by up to a few ulps of the edge functions over their sum, which on a sliver moves
/// the point along its long edges by more than the point's documented precision
/// (docs/reference.md, "The adjudicator"); in f64 the point lies within f32 rounding of the
/// ray's exact crossing.
pub(in crate::trace) fn refine_barycentrics(walk: &WatertightRay, hit: &mut Hit) {
    if let Some(b) = in_f64(walk).barycentrics(&hit.vertices.map(|p| p.as_dvec3().to_array())) {
        hit.barycentric = b.map(|b| b as f32);
    }
}

/// The hit on triangle `id` (which ties with the tracer's), from the watertight test.
fn tie_hit(ray: &WatertightRay, id: u32, vertices: [Vec3; 3]) -> Option<Hit> {
    let [a, b, c] = vertices.map(Vec3A::from);
    let h = ray.intersect(a, b, c, 0.0, f32::INFINITY)?;
    Some(Hit { triangle: id, t: h.t, barycentric: h.barycentric, vertices })
}
