//! What bounds a packet of parallel rays (shadow rays towards a directional light) at once: the
//! beam of lines through their origins along the shared direction, tested against a node's
//! eight child boxes in one go (`ParallelBeam::meets`). The packet walk tests lane by lane only
//! the children the beam keeps (packet.rs), instead of all eight.
//!
//! Shear the world along the direction d, with main axis z (|d_z| the largest component) and
//! s = (d_x/d_z, d_y/d_z): a point p goes to u(p) = (p_x − s_x·p_z, p_y − s_y·p_z). Every point of
//! a ray o + t·d has the u of its origin, so a box that holds a point of the ray has the ray's u
//! within its u-range, [x_lo − s_x·z, x_hi − s_x·z′] with z and z′ the planes that make it
//! widest; and the point lies past the origin along z. The beam keeps a child where the lanes'
//! rectangle of u meets that range (widened) and some origin lies before its far z plane.
//!
//! It keeps every child that some lane's own node test keeps (node_test.rs), so each lane still
//! reaches exactly the nodes its own walk reaches. That test keeps a box only if the ray, in
//! exact arithmetic, meets the box grown by 2⁻²⁰·|plane − origin| per axis: its distances are
//! within a relative 2⁻²¹ + 2⁻²² of the exact ones (the slack and four roundings). With R the
//! largest magnitude of any plane or origin, that growth is at most 2⁻¹⁹·R, which widens the
//! u-range by (1 + |s|)·2⁻¹⁹·R ≤ 2⁻¹⁸·R (|s| ≤ 1) and the z plane by 2⁻¹⁹·R. Evaluating u as
//! fl(x − fl(s̃·z)) with s̃ = fl(d_x·fl(1/d_z)) errs by at most 5.001·2⁻²⁴·R on each side of the
//! comparison, and the widening rounds once more. So the rectangle and the origins' z are
//! widened by 2⁻¹⁷·R, which covers all of it, plus the smallest normal f32 for values near zero.

#![cfg(target_arch = "x86_64")]

use super::packet::lane_extremes;
use super::wide_bvh::WideNode;
use std::arch::x86_64::*;

/// The widened rectangle and start of a packet of parallel rays, each value in every lane (so
/// that the test reads it as an operand), and which planes of a node's boxes the test reads.
pub(in crate::trace) struct ParallelBeam {
    /// Per sheared axis (x, y of the watertight test's order), the origins' lowest and highest
    /// u, widened.
    lo: [__m256; 2],
    hi: [__m256; 2],
    /// s̃.
    shear: [__m256; 2],
    /// Byte offsets in a `WideNode`: per sheared axis, its low and high planes, and the main
    /// axis's planes that make the u-range widest below and above.
    low_plane: [usize; 2],
    high_plane: [usize; 2],
    main_for_low: [usize; 2],
    main_for_high: [usize; 2],
    /// The main-axis plane a box must reach past the origins (the high one where the rays move
    /// up the axis), and the origins' lowest coordinate along it (highest, moving down), widened.
    far_plane: usize,
    moves_up: bool,
    start: __m256,
}

impl ParallelBeam {
    /// The beam of rays from `origin` (lane by lane) along one direction with the watertight
    /// test's axis order `axes` and shear `shear` (`WatertightRay`), moving up its main axis or
    /// not, over a tree whose planes lie within `plane_reach` of zero.
    ///
    /// # Safety
    /// The caller runs where the processor has AVX2, in code compiled for it.
    #[inline(always)]
    pub(in crate::trace) unsafe fn new(
        origin: &[__m256; 3],
        axes: [usize; 3],
        shear: [f32; 2],
        moves_up: bool,
        plane_reach: f32,
    ) -> ParallelBeam {
        // SAFETY: the caller's.
        unsafe {
            let [kx, ky, kz] = axes;
            let abs = |v: __m256| _mm256_andnot_ps(_mm256_set1_ps(-0.0), v);
            let [_, origin_reach] =
                lane_extremes(_mm256_max_ps(_mm256_max_ps(abs(origin[0]), abs(origin[1])), abs(origin[2])));
            let reach = _mm256_max_ps(origin_reach, _mm256_set1_ps(plane_reach));
            let pad = _mm256_add_ps(
                _mm256_mul_ps(reach, _mm256_set1_ps(2f32.powi(-17))),
                _mm256_set1_ps(f32::MIN_POSITIVE),
            );
            let lo_plane = |axis: usize| std::mem::offset_of!(WideNode, lo) + 32 * axis;
            let hi_plane = |axis: usize| std::mem::offset_of!(WideNode, hi) + 32 * axis;
            let [lowest, highest] = lane_extremes(origin[kz]);
            let zero = _mm256_setzero_ps();
            let mut beam = ParallelBeam {
                lo: [zero; 2],
                hi: [zero; 2],
                shear: [_mm256_set1_ps(shear[0]), _mm256_set1_ps(shear[1])],
                low_plane: [lo_plane(kx), lo_plane(ky)],
                high_plane: [hi_plane(kx), hi_plane(ky)],
                main_for_low: [0; 2],
                main_for_high: [0; 2],
                far_plane: if moves_up { hi_plane(kz) } else { lo_plane(kz) },
                moves_up,
                start: if moves_up { _mm256_sub_ps(lowest, pad) } else { _mm256_add_ps(highest, pad) },
            };
            for (j, axis) in [kx, ky].into_iter().enumerate() {
                let u = _mm256_sub_ps(origin[axis], _mm256_mul_ps(beam.shear[j], origin[kz]));
                let [lo, hi] = lane_extremes(u);
                beam.lo[j] = _mm256_sub_ps(lo, pad);
                beam.hi[j] = _mm256_add_ps(hi, pad);
                // x − s·z is least at the highest z where s > 0, at the lowest where s < 0.
                (beam.main_for_low[j], beam.main_for_high[j]) =
                    if shear[j] >= 0.0 { (hi_plane(kz), lo_plane(kz)) } else { (lo_plane(kz), hi_plane(kz)) };
            }
            beam
        }
    }

    /// The children of `node` that some ray of the beam may meet, as bits. An empty slot's
    /// inverted box gives +∞ or NaN for its low u and fails the comparisons.
    #[inline(always)]
    pub(in crate::trace) fn meets(&self, node: &WideNode) -> u32 {
        // SAFETY: a `ParallelBeam` exists only where the processor has AVX2 (`new`), and its
        // test is compiled for it (`packet_isa.rs`).
        unsafe {
            let bytes = node as *const WideNode as *const u8;
            // SAFETY: every offset is that of one of the node's plane arrays (`new`).
            let planes = |offset: usize| _mm256_loadu_ps(bytes.add(offset) as *const f32);
            let far = planes(self.far_plane);
            let mut met = if self.moves_up {
                _mm256_cmp_ps::<_CMP_GE_OQ>(far, self.start)
            } else {
                _mm256_cmp_ps::<_CMP_LE_OQ>(far, self.start)
            };
            for j in 0..2 {
                let low = _mm256_sub_ps(
                    planes(self.low_plane[j]),
                    _mm256_mul_ps(self.shear[j], planes(self.main_for_low[j])),
                );
                let high = _mm256_sub_ps(
                    planes(self.high_plane[j]),
                    _mm256_mul_ps(self.shear[j], planes(self.main_for_high[j])),
                );
                met = _mm256_and_ps(met, _mm256_cmp_ps::<_CMP_LE_OQ>(low, self.hi[j]));
                met = _mm256_and_ps(met, _mm256_cmp_ps::<_CMP_GE_OQ>(high, self.lo[j]));
            }
            _mm256_movemask_ps(met) as u32
        }
    }
}

#[cfg(test)]
mod tests {
    use super::ParallelBeam;
    use crate::trace::WatertightRay;
    use crate::trace::bvh::packet::{LANES, Packet};
    use crate::trace::bvh::wide_bvh::{ChildRef, WideNode};
    use crate::trace::splitmix::SplitMix64;
    use glam::{Vec3, Vec3A};
    use std::arch::x86_64::*;

    /// A node of eight boxes, each from its low and high corners.
    fn node(boxes: &[(Vec3, Vec3); 8]) -> WideNode {
        WideNode {
            lo: std::array::from_fn(|axis| std::array::from_fn(|c| boxes[c].0[axis])),
            hi: std::array::from_fn(|axis| std::array::from_fn(|c| boxes[c].1[axis])),
            child: [ChildRef::EMPTY; 8],
        }
    }

    /// The beam of a packet of parallel `rays`, over planes within `reach` of zero.
    fn beam_of(rays: &[WatertightRay; LANES], reach: f32) -> ParallelBeam {
        let lanes = |axis: usize| -> [f32; LANES] { std::array::from_fn(|k| rays[k].origin[axis]) };
        let r = &rays[0];
        // SAFETY: AVX2 checked by the caller; eight f32 each.
        unsafe {
            let origin = [0, 1, 2].map(|axis| _mm256_loadu_ps(lanes(axis).as_ptr()));
            ParallelBeam::new(&origin, [r.kx, r.ky, r.kz], [r.sx, r.sy], r.sz > 0.0, reach)
        }
    }

    /// The lanes whose own node test keeps the box from `lo` to `hi` (`Packet::lanes_meeting`).
    fn lanes_keeping(packet: &Packet, lo: Vec3, hi: Vec3) -> u32 {
        let empty = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        let tested = node(&std::array::from_fn(|c| if c == 0 { (lo, hi) } else { empty }));
        packet.lanes_meeting(&tested, 0, &[f32::INFINITY; LANES])
    }

    /// The beam keeps every box that some lane's own node test keeps, tested where that matters:
    /// boxes that touch a lane's ray at one corner, moved off it by the farthest distance at
    /// which some lane's test still keeps them (its slack lets it keep boxes the exact ray just
    /// misses). Over every octant and main axis, at distances along the rays up to 60, 40 units
    /// from the origin (so that rounding is coarse). And boxes well to the side of the beam, or
    /// wholly behind the origins, are dropped: the beam does not keep everything.
    #[test]
    fn keeps_whatever_a_lane_keeps_and_drops_what_lies_aside() {
        if !super::super::node_test::wide_form_testable() {
            return;
        }
        let mut rng = SplitMix64::new(0x5eed_bea3);
        let (mut grazing, mut kept_past_the_ray) = (0, 0);
        for _ in 0..2000 {
            let vector = |rng: &mut SplitMix64, s: f64| {
                Vec3::from_array(std::array::from_fn(|_| rng.range([-s, s]) as f32))
            };
            let d = vector(&mut rng, 1.0).normalize();
            let centre = Vec3::splat(40.0) + vector(&mut rng, 8.0);
            if d.abs().min_element() < 1e-3 {
                continue;
            }
            // Origins within a unit of one another across the beam, up to four along it.
            let rays: [WatertightRay; LANES] = std::array::from_fn(|_| {
                let along = rng.range([-2.0, 2.0]) as f32;
                WatertightRay::new(Vec3A::from(centre + vector(&mut rng, 0.5) + along * d), Vec3A::from(d))
            });
            // SAFETY: AVX2 checked above.
            let Some(packet) = (unsafe { Packet::new(&rays) }) else { continue };
            for k in 0..LANES {
                // A box touching lane k's ray at p, at one corner: beyond p along axis a, before
                // it along axis b, so that the ray is outside before p and after it.
                let p = Vec3::from(rays[k].origin) + rng.range([0.0, 60.0]) as f32 * d;
                let a = (rng.next_u64() % 3) as usize;
                let b = (a + 1 + (rng.next_u64() % 2) as usize) % 3;
                let size = Vec3::from_array(std::array::from_fn(|_| rng.range([0.01, 2.0]) as f32));
                let moved_off = |gap: f32| {
                    let (mut lo, mut hi) = (p - size, p + size);
                    let up = |axis: usize| d[axis] > 0.0;
                    (lo[a], hi[a]) = if up(a) {
                        (p[a] + gap, p[a] + gap + size[a])
                    } else {
                        (p[a] - gap - size[a], p[a] - gap)
                    };
                    (lo[b], hi[b]) = if up(b) { (p[b] - size[b], p[b]) } else { (p[b], p[b] + size[b]) };
                    (lo, hi)
                };
                // The largest gap some lane's test still keeps, by bisection.
                let (mut kept, mut dropped) = (0.0f32, 1e-2f32);
                if lanes_keeping(&packet, moved_off(kept).0, moved_off(kept).1) == 0 {
                    continue;
                }
                for _ in 0..40 {
                    let mid = 0.5 * (kept + dropped);
                    let (lo, hi) = moved_off(mid);
                    if lanes_keeping(&packet, lo, hi) != 0 { kept = mid } else { dropped = mid }
                }
                let (lo, hi) = moved_off(kept);
                let reach = lo.abs().max(hi.abs()).max_element();
                let met = beam_of(&rays, reach).meets(&node(&[(lo, hi); 8]));
                assert_eq!(met, 0xff, "the beam dropped a box ({lo}, {hi}) that a lane keeps");
                grazing += 1;
                kept_past_the_ray += (kept > 0.0) as u32;
            }
            // Boxes far to the side of every ray, and boxes wholly behind every origin.
            let side = d.any_orthogonal_vector().normalize();
            let aside: [(Vec3, Vec3); 8] = std::array::from_fn(|c| {
                let t = rng.range([-10.0, 60.0]) as f32;
                let p = if c < 4 { centre + t * d + 6.0 * side } else { centre - 12.0 * d };
                (p - Vec3::splat(0.5), p + Vec3::splat(0.5))
            });
            let reach = aside.iter().flat_map(|(lo, hi)| [lo.abs().max_element(), hi.abs().max_element()]);
            assert_eq!(beam_of(&rays, reach.fold(0.0, f32::max)).meets(&node(&aside)), 0, "{aside:?}");
        }
        assert!(grazing > 10_000, "{grazing} grazing boxes");
        assert!(kept_past_the_ray > grazing / 2, "the lanes' slack kept {kept_past_the_ray} of {grazing}");
    }
}
