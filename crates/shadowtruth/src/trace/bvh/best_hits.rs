//! A packet's closest hits so far (packet.rs), one per lane, kept in vectors: each triangle's
//! hits are taken a vector at a time, and a hit's barycentrics stay its edge functions and their
//! sum until the walk ends, so that the division that normalizes them is made once per lane
//! rather than for every triangle a lane hits. `1/det` and `edge·(1/det)` are the scalar test's
//! own operations (`WatertightRay::intersect`), so the barycentrics are the same bits.

#![cfg(target_arch = "x86_64")]

use super::hit::Hit;
use super::lane_vector::{LaneMask, LaneVector};
use super::packet::LaneHits;
use glam::Vec3;

/// Each lane's closest hit so far: the least (distance, scene id), as `Hit::beats` orders them.
pub(in crate::trace) struct BestHits<V: LaneVector> {
    t: V,
    /// The hit triangle's scene id, as bits; u32::MAX before a lane's first hit, so that any
    /// hit beats none (its distance is below +∞, or equal with a lower id).
    scene_id: V,
    /// The hit triangle in tree order, as bits; u32::MAX where the lane has no hit.
    primitive: V,
    /// The hit's edge functions and their sum: its barycentrics before the division.
    edges: [V; 3],
    det: V,
}

/// No hit, as a lane's bits.
const NONE: u32 = u32::MAX;

impl<V: LaneVector> BestHits<V> {
    /// No lane has a hit.
    ///
    /// # Safety
    /// The processor has `V`'s instruction set, and the caller is compiled for it.
    #[inline(always)]
    pub(in crate::trace) unsafe fn new() -> Self {
        // SAFETY: the caller's.
        unsafe {
            let none = V::splat(f32::from_bits(NONE));
            let zero = V::splat(0.0);
            BestHits {
                t: V::splat(f32::INFINITY),
                scene_id: none,
                primitive: none,
                edges: [zero; 3],
                det: zero,
            }
        }
    }

    /// Takes the hits of `hits` on tree triangle `primitive` (scene id `scene_id`) that beat the
    /// lanes' best, and sets those lanes' `tmax` to `look_beyond` of their new distance.
    #[inline(always)]
    pub(in crate::trace) fn take(
        &mut self,
        hits: &LaneHits<V>,
        primitive: usize,
        scene_id: u32,
        tmax: &mut V::Array,
        look_beyond: impl Fn(V) -> V,
    ) {
        let t = hits.t;
        let nearer = t.lt(self.t).or(t.eq(self.t).and(self.scene_id.bits_above(scene_id)));
        let beats = nearer.bits() & hits.hit;
        if beats == 0 {
            return;
        }
        // SAFETY: `hits` exists, so the processor has `V`'s set.
        let (beats, id, primitive, reach) = unsafe {
            (
                V::Mask::from_bits(beats),
                V::splat(f32::from_bits(scene_id)),
                V::splat(f32::from_bits(primitive as u32)),
                V::load(tmax),
            )
        };
        self.t = t.select(beats, self.t);
        self.scene_id = id.select(beats, self.scene_id);
        self.primitive = primitive.select(beats, self.primitive);
        for (best, edge) in self.edges.iter_mut().zip(hits.edges) {
            *best = edge.select(beats, *best);
        }
        self.det = hits.det.select(beats, self.det);
        look_beyond(t).select(beats, reach).store(tmax);
    }

    /// Each lane's closest hit (`N` = `V::LANES`), with `triangle(i)` the scene id and world
    /// vertices of tree triangle `i`.
    #[inline(always)]
    pub(in crate::trace) fn hits<const N: usize>(
        &self,
        triangle: impl Fn(usize) -> (u32, [Vec3; 3]),
    ) -> [Option<Hit>; N] {
        // SAFETY: `self` exists, so the processor has `V`'s set.
        let inv_det = unsafe { V::splat(1.0) }.div(self.det);
        let (mut t, mut primitive, mut barycentric) =
            (V::Array::default(), V::Array::default(), [V::Array::default(); 3]);
        self.t.store(&mut t);
        self.primitive.store(&mut primitive);
        for (b, edge) in barycentric.iter_mut().zip(self.edges) {
            edge.mul(inv_det).store(b);
        }
        let mut best = [None; N];
        for (k, best) in best.iter_mut().enumerate() {
            let i = primitive.as_ref()[k].to_bits();
            if i == NONE {
                continue;
            }
            let (scene_id, vertices) = triangle(i as usize);
            *best = Some(Hit {
                triangle: scene_id,
                t: t.as_ref()[k],
                barycentric: [0, 1, 2].map(|b| barycentric[b].as_ref()[k]),
                vertices,
            });
        }
        best
    }
}
