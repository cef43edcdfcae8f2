//! Where a primary ray crosses its own hit's triangle, in f64: the interval that holds the exact
//! distance, which bounds the certificate's search for anything nearer (primary_certificate.rs),
//! and the barycentrics that define the surface point (docs/reference.md, "The definition").
//! `OwnCrossing::of` takes one ray; `own_crossings` a packet's at once, eight lanes to an
//! AVX-512 vector or four to an AVX2 one, with the very f64 operations of the certified test
//! (certified.rs) in the same order, so the same bits: on the forest at 1920×1080 this work was
//! a fifth of the G-buffer's time.

use super::certified::{CertifiedRay, Crossing, walk_limit};
use super::hit::Hit;
use super::watertight::WatertightRay;

/// What the certificate takes from the hit's own triangle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(in crate::trace) struct OwnCrossing {
    /// The exact distance lies within `length` ± `length_error` (∞ for a miss).
    pub(in crate::trace) length: f64,
    pub(in crate::trace) length_error: f64,
    /// The hit's triangle is not certainly crossed.
    pub(in crate::trace) uncertain: bool,
    /// The hit's barycentrics computed in f64, rounded to f32 (`None` edge-on).
    pub(in crate::trace) refined: Option<[f32; 3]>,
}

impl OwnCrossing {
    /// How far the certificate looks along the ray: the exact distance's upper bound, rounded
    /// up to f32 (∞ for a miss).
    pub(in crate::trace) fn reach(&self) -> f32 {
        walk_limit(self.length, self.length_error)
    }

    /// A ray that hits nothing.
    const MISS: OwnCrossing =
        OwnCrossing { length: f64::INFINITY, length_error: 0.0, uncertain: false, refined: None };

    /// The crossing of `walk` (the camera's f32 origin and the pixel's f32 direction, exact)
    /// with its closest hit's triangle. In f64: f32's bound on the distance grows with the cube
    /// of the distance over the triangle's projected area, too loose to order surfaces that
    /// nearly touch.
    pub(in crate::trace) fn of(walk: &WatertightRay, hit: Option<&Hit>) -> Self {
        let Some(h) = hit else {
            return OwnCrossing::MISS;
        };
        let v = h.vertices.map(|p| p.as_dvec3().to_array());
        let ray = in_f64(walk);
        let (crossing, b) = ray.crossing_and_barycentrics(&v);
        let refined = b.map(|b| b.map(|b| b as f32));
        match crossing {
            Crossing::Through { t_lo, t_hi } => OwnCrossing {
                length: 0.5 * (t_lo + t_hi),
                length_error: 0.5 * (t_hi - t_lo),
                uncertain: false,
                refined,
            },
            _ => OwnCrossing { length: 0.0, length_error: 0.0, uncertain: true, refined },
        }
    }
}

/// The exact ray `walk` stands for, in f64, without end.
pub(in crate::trace) fn in_f64(walk: &WatertightRay) -> CertifiedRay<f64> {
    let (o, d) = (walk.origin.as_dvec3(), walk.direction.as_dvec3());
    CertifiedRay::new(o.to_array(), 0.0, d.to_array(), 0.0, f64::INFINITY, 0.0)
}

#[cfg(target_arch = "x86_64")]
pub(in crate::trace) use wide::own_crossings;

#[cfg(target_arch = "x86_64")]
mod wide {
    use super::OwnCrossing;
    use crate::trace::bvh::certified::Real;
    use crate::trace::bvh::hit::Hit;
    use crate::trace::bvh::lane_vector::LaneVector;
    use crate::trace::bvh::watertight::WatertightRay;
    use std::arch::x86_64::*;

    /// `OwnCrossing::of` for each lane: eight lanes to a vector where the packet's lanes are
    /// sixteen (`V`, AVX-512), four otherwise (AVX2). The lanes share the watertight test's axis
    /// order, as a packet's rays do (`Packet::new`); `CertifiedRay::new` picks the same order
    /// for the same direction in f64 (the same rule on the same values). Runs inside a packet
    /// walk (packet_isa.rs) compiled for `V`'s instruction set.
    #[inline(always)]
    pub(in crate::trace) fn own_crossings<V: LaneVector, const N: usize>(
        watertight: &[WatertightRay; N],
        hits: &[Option<Hit>; N],
    ) -> [OwnCrossing; N] {
        let axes = [watertight[0].kx, watertight[0].ky, watertight[0].kz];
        assert!(
            watertight.iter().all(|w| [w.kx, w.ky, w.kz] == axes),
            "a packet's rays share the watertight test's axis order"
        );
        let mut out = [OwnCrossing::MISS; N];
        // SAFETY: a `V` of sixteen lanes exists only where the processor has AVX-512 F, one of
        // eight where it has AVX2 (lane_vector.rs), and the caller is compiled for it.
        unsafe {
            if V::LANES == 16 {
                crossings_of::<F8, N>(watertight, hits, axes, &mut out);
            } else {
                crossings_of::<F4, N>(watertight, hits, axes, &mut out);
            }
        }
        out
    }

    /// f64 lanes: four in AVX2 (`F4`), eight in AVX-512 (`F8`). Comparisons give a bit per lane.
    trait F64Lanes: Copy {
        const LANES: usize;
        /// # Safety
        /// The processor has the vector's instruction set, and the caller is compiled for it.
        unsafe fn splat(x: f64) -> Self;
        /// The first `LANES` values of `x`.
        ///
        /// # Safety
        /// As `splat`.
        unsafe fn load(x: &[f64; 8]) -> Self;
        fn store(self) -> [f64; 8];
        fn add(self, o: Self) -> Self;
        fn sub(self, o: Self) -> Self;
        fn mul(self, o: Self) -> Self;
        fn div(self, o: Self) -> Self;
        /// `o` where either is NaN (as `maxpd`).
        fn max(self, o: Self) -> Self;
        /// `o` where either is NaN (as `minpd`).
        fn min(self, o: Self) -> Self;
        fn abs(self) -> Self;
        /// Ordered: false where either is NaN.
        fn gt(self, o: Self) -> u32;
        fn lt(self, o: Self) -> u32;
        fn eq(self, o: Self) -> u32;
    }

    #[derive(Clone, Copy)]
    struct F4(__m256d);

    #[derive(Clone, Copy)]
    struct F8(__m512d);

    // SAFETY (both blocks): an `F4` exists only where the processor has AVX2, an `F8` only
    // where it has AVX-512 F (the constructors' contract).
    impl F64Lanes for F4 {
        const LANES: usize = 4;
        #[inline(always)]
        unsafe fn splat(x: f64) -> Self {
            unsafe { F4(_mm256_set1_pd(x)) }
        }
        #[inline(always)]
        unsafe fn load(x: &[f64; 8]) -> Self {
            unsafe { F4(_mm256_loadu_pd(x.as_ptr())) }
        }
        #[inline(always)]
        fn store(self) -> [f64; 8] {
            let mut out = [0.0; 8];
            unsafe { _mm256_storeu_pd(out.as_mut_ptr(), self.0) };
            out
        }
        #[inline(always)]
        fn add(self, o: Self) -> Self {
            unsafe { F4(_mm256_add_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn sub(self, o: Self) -> Self {
            unsafe { F4(_mm256_sub_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn mul(self, o: Self) -> Self {
            unsafe { F4(_mm256_mul_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn div(self, o: Self) -> Self {
            unsafe { F4(_mm256_div_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn max(self, o: Self) -> Self {
            unsafe { F4(_mm256_max_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn min(self, o: Self) -> Self {
            unsafe { F4(_mm256_min_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn abs(self) -> Self {
            unsafe { F4(_mm256_andnot_pd(_mm256_set1_pd(-0.0), self.0)) }
        }
        #[inline(always)]
        fn gt(self, o: Self) -> u32 {
            unsafe { _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_GT_OQ>(self.0, o.0)) as u32 }
        }
        #[inline(always)]
        fn lt(self, o: Self) -> u32 {
            unsafe { _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_LT_OQ>(self.0, o.0)) as u32 }
        }
        #[inline(always)]
        fn eq(self, o: Self) -> u32 {
            unsafe { _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_EQ_OQ>(self.0, o.0)) as u32 }
        }
    }

    impl F64Lanes for F8 {
        const LANES: usize = 8;
        #[inline(always)]
        unsafe fn splat(x: f64) -> Self {
            unsafe { F8(_mm512_set1_pd(x)) }
        }
        #[inline(always)]
        unsafe fn load(x: &[f64; 8]) -> Self {
            unsafe { F8(_mm512_loadu_pd(x.as_ptr())) }
        }
        #[inline(always)]
        fn store(self) -> [f64; 8] {
            let mut out = [0.0; 8];
            unsafe { _mm512_storeu_pd(out.as_mut_ptr(), self.0) };
            out
        }
        #[inline(always)]
        fn add(self, o: Self) -> Self {
            unsafe { F8(_mm512_add_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn sub(self, o: Self) -> Self {
            unsafe { F8(_mm512_sub_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn mul(self, o: Self) -> Self {
            unsafe { F8(_mm512_mul_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn div(self, o: Self) -> Self {
            unsafe { F8(_mm512_div_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn max(self, o: Self) -> Self {
            unsafe { F8(_mm512_max_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn min(self, o: Self) -> Self {
            unsafe { F8(_mm512_min_pd(self.0, o.0)) }
        }
        #[inline(always)]
        fn abs(self) -> Self {
            unsafe { F8(_mm512_abs_pd(self.0)) }
        }
        #[inline(always)]
        fn gt(self, o: Self) -> u32 {
            unsafe { _mm512_cmp_pd_mask::<_CMP_GT_OQ>(self.0, o.0) as u32 }
        }
        #[inline(always)]
        fn lt(self, o: Self) -> u32 {
            unsafe { _mm512_cmp_pd_mask::<_CMP_LT_OQ>(self.0, o.0) as u32 }
        }
        #[inline(always)]
        fn eq(self, o: Self) -> u32 {
            unsafe { _mm512_cmp_pd_mask::<_CMP_EQ_OQ>(self.0, o.0) as u32 }
        }
    }

    /// `OwnCrossing::of` for every lane into `out`, `F::LANES` at a time.
    ///
    /// # Safety
    /// The processor has `F`'s instruction set, and the caller is compiled for it.
    #[inline(always)]
    unsafe fn crossings_of<F: F64Lanes, const N: usize>(
        watertight: &[WatertightRay; N],
        hits: &[Option<Hit>; N],
        axes: [usize; 3],
        out: &mut [OwnCrossing; N],
    ) {
        assert!(N.is_multiple_of(F::LANES), "lanes come {} at a time", F::LANES);
        for first in (0..N).step_by(F::LANES) {
            // Lanes whose rays all miss (the sky) keep `OwnCrossing::MISS`.
            if hits[first..first + F::LANES].iter().all(Option::is_none) {
                continue;
            }
            // SAFETY: the caller's.
            let crossings = unsafe { crossings_of_lanes::<F, N>(watertight, hits, first, axes) };
            for (j, crossing) in crossings.into_iter().take(F::LANES).enumerate() {
                if hits[first + j].is_some() {
                    out[first + j] = crossing;
                }
            }
        }
    }

    /// Lanes `first..first + F::LANES`: `CertifiedRay::<f64>::new` (no origin or direction
    /// error, no end), `shear`, `crossing_of` (no segment), `crossing_near` and
    /// `barycentrics_of`, operation for operation. A lane without a hit computes on zero
    /// vertices, and is not read.
    ///
    /// # Safety
    /// As `crossings_of`.
    #[inline(always)]
    unsafe fn crossings_of_lanes<F: F64Lanes, const N: usize>(
        watertight: &[WatertightRay; N],
        hits: &[Option<Hit>; N],
        first: usize,
        [kx, ky, kz]: [usize; 3],
    ) -> [OwnCrossing; 8] {
        // SAFETY: the caller's.
        let splat = |x: f64| unsafe { F::splat(x) };
        // The lanes' numbers gathered component by component, in plain loops: closures
        // passed to `array::from_fn` or `map` are not compiled for the walk's instruction set,
        // so each vector operation in them would be a call.
        let (mut o, mut d, mut v) = ([[0.0; 8]; 3], [[0.0; 8]; 3], [[[0.0; 8]; 3]; 3]);
        for j in 0..F::LANES {
            let ray = &watertight[first + j];
            let vertices = hits[first + j].map_or([glam::Vec3::ZERO; 3], |h| h.vertices);
            for c in 0..3 {
                o[c][j] = ray.origin[c] as f64;
                d[c][j] = ray.direction[c] as f64;
                for i in 0..3 {
                    v[i][c][j] = vertices[i][c] as f64;
                }
            }
        }
        // SAFETY: the caller's.
        let load = |x: &[f64; 8]| unsafe { F::load(x) };
        // `CertifiedRay::new`, then `sheared`: no origin or direction error.
        let u = f64::UNIT_ROUNDOFF;
        let sz = splat(1.0).div(load(&d[kz]));
        let (sx, sy) = (load(&d[kx]).mul(sz), load(&d[ky]).mul(sz));
        let scale_error = 4.0 * 0.0 + 2.0 * u;
        let shear_error = 4.0 * 0.0 + 2.1 * u;
        // `shear`.
        let zero = splat(0.0);
        let mut a = [[zero; 3]; 3];
        for i in 0..3 {
            for c in 0..3 {
                a[i][c] = load(&v[i][c]).sub(load(&o[c]));
            }
        }
        let (mut x, mut y, mut z) = ([zero; 3], [zero; 3], [zero; 3]);
        for i in 0..3 {
            x[i] = a[i][kx].sub(sx.mul(a[i][kz]));
            y[i] = a[i][ky].sub(sy.mul(a[i][kz]));
            z[i] = sz.mul(a[i][kz]);
        }
        let e = [
            x[2].mul(y[1]).sub(y[2].mul(x[1])),
            x[0].mul(y[2]).sub(y[0].mul(x[2])),
            x[1].mul(y[0]).sub(y[1].mul(x[0])),
        ];
        let mut across = zero;
        for k in 0..3 {
            across = across.max(x[k].abs()).max(y[k].abs());
        }
        let along = a[0][kz].abs().max(a[1][kz].abs()).max(a[2][kz].abs());
        let reach = across.max(along);
        // `crossing_of`: `sheared_error`, `edge_error`, and a certain miss where the edge
        // functions have opposite signs beyond their bound.
        let (fixed, per_reach) =
            (2.0 * (2.0 * 0.0 + shear_error * 0.0), 2.0 * (2.01 * shear_error + 12.1 * u));
        let sheared = splat(fixed).add(splat(per_reach).mul(reach));
        let products = splat(2.0)
            .mul(sheared)
            .mul(splat(2.0).mul(across).add(sheared))
            .add(splat(4.01 * u).mul(across).mul(across));
        let edge = splat(2.0).mul(products.add(splat(2.0 * f64::SMALLEST_SUBNORMAL)));
        let below = edge.mul(splat(-1.0));
        // Per edge function, the lanes where it lies above 0, below 0, above the bound, below
        // minus the bound.
        let (mut pos, mut neg, mut clear_pos, mut clear_neg) = ([0; 3], [0; 3], [0; 3], [0; 3]);
        for k in 0..3 {
            pos[k] = e[k].gt(zero);
            neg[k] = e[k].lt(zero);
            clear_pos[k] = e[k].gt(edge);
            clear_neg[k] = e[k].lt(below);
        }
        let some = |m: [u32; 3]| m[0] | m[1] | m[2];
        let every = |m: [u32; 3]| m[0] & m[1] & m[2];
        let mixed = some(pos) & some(neg);
        let clearly_mixed = some(clear_pos) & some(clear_neg);
        // `crossing_near`: the z range (origin error 0, length ∞).
        let z_error = splat(2.0).mul(
            splat(2.0 * 0.0)
                .add(splat(scale_error).mul(splat(2.01).mul(reach).add(splat(0.0))))
                .add(splat(8.0 * u).mul(reach)),
        );
        let (z_min, z_max) = (z[0].min(z[1]).min(z[2]), z[0].max(z[1]).max(z[2]));
        let behind = z_max.add(z_error).lt(zero);
        let beyond = z_min.sub(z_error).gt(splat(f64::INFINITY));
        let miss = (mixed & clearly_mixed) | behind | beyond;
        let all_clear = every(clear_pos) | every(clear_neg);
        let (range_lo, range_hi) = (z_min.sub(z_error), z_max.add(z_error));
        let det = e[0].add(e[1]).add(e[2]);
        let t = e[0].mul(z[0]).add(e[1].mul(z[1])).add(e[2].mul(z[2])).div(det);
        let z_abs = z_min.abs().max(z_max.abs());
        let numerator_error = splat(3.0)
            .mul(edge)
            .mul(z_abs.add(z_error))
            .add(det.abs().mul(z_error))
            .add(splat(2f64.powi(-50)).mul(det.abs()).mul(z_abs));
        let det_error = splat(3.0).mul(edge);
        let t_error = splat(2.0)
            .mul(numerator_error.add(t.abs().mul(det_error)))
            .div(det.abs().sub(det_error))
            .add(splat(2f64.powi(-50)).mul(t.abs()));
        let t_lo = t.sub(t_error).max(range_lo);
        let t_hi = t.add(t_error).min(range_hi);
        let through = !miss & all_clear;
        let length = splat(0.5).mul(t_lo.add(t_hi)).store();
        let length_error = splat(0.5).mul(t_hi.sub(t_lo)).store();
        // `barycentrics_of`.
        let b = [e[0].div(det).store(), e[1].div(det).store(), e[2].div(det).store()];
        let edge_on = det.eq(zero);
        let mut out = [OwnCrossing::MISS; 8];
        for (j, out) in out.iter_mut().enumerate().take(F::LANES) {
            let refined = (edge_on >> j & 1 == 0).then_some([b[0][j] as f32, b[1][j] as f32, b[2][j] as f32]);
            *out = match through >> j & 1 != 0 {
                true => OwnCrossing {
                    length: length[j],
                    length_error: length_error[j],
                    uncertain: false,
                    refined,
                },
                false => OwnCrossing { length: 0.0, length_error: 0.0, uncertain: true, refined },
            };
        }
        out
    }
}

#[cfg(all(test, target_arch = "x86_64"))]
mod tests {
    use super::{OwnCrossing, own_crossings};
    use crate::trace::bvh::hit::Hit;
    use crate::trace::bvh::lane_vector::{L8, L16};
    use crate::trace::bvh::packet_isa::{PacketIsa, PacketQuery, in_packet_isa, packet_isa_for};
    use crate::trace::bvh::watertight::WatertightRay;
    use crate::trace::splitmix::SplitMix64;
    use glam::{Vec3, vec3};

    /// The bits of a crossing, so that −0 and 0 (or two NaNs) count as different.
    fn bits(c: &OwnCrossing) -> (u64, u64, bool, Option<[u32; 3]>) {
        (c.length.to_bits(), c.length_error.to_bits(), c.uncertain, c.refined.map(|b| b.map(f32::to_bits)))
    }

    /// Lanes four at a time (AVX2, a packet of eight) and eight at a time (AVX-512, a packet of
    /// sixteen, where the processor has it) give `OwnCrossing::of` bit for bit: rays from one
    /// camera through
    /// triangles they cross (well inside, on an edge or a vertex), miss narrowly or widely, lie
    /// behind or edge-on to, and degenerate ones, near the origin and 10⁴ away, with directions
    /// whose largest components tie (the axis order's rule) and lanes without a hit.
    #[test]
    fn packet_lanes_give_the_single_crossings_bit_for_bit() {
        if !crate::trace::bvh::node_test::wide_form_testable() {
            return;
        }
        let mut rng = SplitMix64::new(17);
        let (mut through, mut uncertain, mut edge_on) = (0, 0, 0);
        for round in 0..4000 {
            let scale = [1.0, 1e4][round % 2];
            let origin = Vec3::from_array(std::array::from_fn(|_| (rng.range([-1.0, 1.0]) * scale) as f32));
            let main = match round % 3 {
                0 => vec3(1.0, 1.0, 0.5),
                1 => vec3(-0.3, 1.0, -1.0),
                _ => Vec3::from_array(std::array::from_fn(|_| rng.range([-1.0, 1.0]) as f32)),
            };
            let mut watertight = [WatertightRay::UNUSED; 16];
            let mut hits = [None; 16];
            for k in 0..16 {
                // Ties stay ties in every lane of the first two kinds (no jitter on them).
                let jitter = if round % 3 == 2 { 0.02 } else { 0.0 };
                let direction = (main
                    + Vec3::from_array(std::array::from_fn(|_| rng.range([-jitter, jitter]) as f32)))
                .normalize();
                watertight[k] = WatertightRay::new(origin.into(), direction.into());
                let along = (rng.range([-0.5, 3.0]) * scale) as f32;
                let centre = origin + direction * along;
                let size = (rng.range([1e-3, 1.0]) * scale) as f32;
                let mut corner = || {
                    centre + Vec3::from_array(std::array::from_fn(|_| rng.range([-1.0, 1.0]) as f32)) * size
                };
                let mut vertices = [corner(), corner(), corner()];
                match rng.next_u64() % 6 {
                    0 => vertices[2] = vertices[0] + (vertices[1] - vertices[0]) * 0.5,
                    1 => vertices[0] = centre,
                    2 => vertices[2] = vertices[1],
                    3 => vertices = [centre, centre + direction * size, vertices[2]],
                    _ => {}
                }
                if !rng.next_u64().is_multiple_of(8) {
                    hits[k] = Some(Hit { triangle: k as u32, t: along, barycentric: [0.0; 3], vertices });
                }
            }
            if watertight
                .iter()
                .any(|w| [w.kx, w.ky, w.kz] != [watertight[0].kx, watertight[0].ky, watertight[0].kz])
            {
                continue;
            }
            let eight: (&[_; 8], &[_; 8]) =
                (watertight[..8].try_into().unwrap(), hits[..8].try_into().unwrap());
            let mut wide =
                in_packet_isa(PacketIsa::Avx2, || own_crossings::<L8, 8>(eight.0, eight.1)).to_vec();
            if let Some(isa) = packet_isa_for(PacketQuery::SixteenLanes) {
                let sixteen = in_packet_isa(isa, || own_crossings::<L16, 16>(&watertight, &hits));
                assert_eq!(
                    sixteen[..8].iter().map(bits).collect::<Vec<_>>(),
                    wide.iter().map(bits).collect::<Vec<_>>()
                );
                wide = sixteen.to_vec();
            }
            for k in 0..wide.len() {
                let single = OwnCrossing::of(&watertight[k], hits[k].as_ref());
                assert_eq!(bits(&wide[k]), bits(&single), "round {round}, lane {k}");
                through += (hits[k].is_some() && !single.uncertain) as usize;
                uncertain += single.uncertain as usize;
                edge_on += (hits[k].is_some() && single.refined.is_none()) as usize;
            }
        }
        assert!(
            through > 1000 && uncertain > 1000 && edge_on > 100,
            "the cases must include crossings ({through}), uncertain ones ({uncertain}) and edge-on triangles ({edge_on})"
        );
    }
}
