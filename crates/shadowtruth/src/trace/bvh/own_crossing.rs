//! Where a primary ray crosses its own hit's triangle, in f64: the interval that holds the exact
//! distance, which bounds the certificate's search for anything nearer (primary_certificate.rs),
//! and the barycentrics that define the surface point (docs/reference.md, "The definition").
//! `OwnCrossing::of` takes one ray; `own_crossings` eight at once, four lanes to an AVX vector,
//! with the very f64 operations of the certified test (certified.rs) in the same order, so the
//! same bits: on the forest at 1920×1080 this work was a fifth of the G-buffer's time.

use super::certified::{CertifiedRay, Crossing};
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
    use crate::trace::bvh::watertight::WatertightRay;
    use std::arch::x86_64::*;

    /// `OwnCrossing::of` for each lane, four lanes at a time. The lanes share the watertight
    /// test's axis order, as a packet's rays do (`Packet::new`); `CertifiedRay::new` picks the
    /// same order for the same direction in f64 (the same rule on the same values). Runs inside
    /// a packet walk (packet_isa.rs), where the processor has AVX2.
    #[inline(always)]
    pub(in crate::trace) fn own_crossings<const N: usize>(
        watertight: &[WatertightRay; N],
        hits: &[Option<Hit>; N],
    ) -> [OwnCrossing; N] {
        let axes = [watertight[0].kx, watertight[0].ky, watertight[0].kz];
        assert!(
            watertight.iter().all(|w| [w.kx, w.ky, w.kz] == axes),
            "a packet's rays share the watertight test's axis order"
        );
        assert!(N.is_multiple_of(4), "lanes come four at a time");
        let mut out = [OwnCrossing::MISS; N];
        for first in (0..N).step_by(4) {
            // SAFETY: the caller runs inside a packet walk, compiled for AVX2 and run where the
            // processor has it.
            let four = unsafe { crossings_of_four(watertight, hits, first, axes) };
            for (j, crossing) in four.into_iter().enumerate() {
                if hits[first + j].is_some() {
                    out[first + j] = crossing;
                }
            }
        }
        out
    }

    /// Lanes `first..first + 4`: `CertifiedRay::<f64>::new` (no origin or direction error, no
    /// end), `shear`, `crossing_of` (no segment), `crossing_near` and `barycentrics_of`,
    /// operation for operation. A lane without a hit computes on zero vertices, and is not read.
    ///
    /// # Safety
    /// The processor has AVX, and the caller is compiled for it.
    #[inline(always)]
    unsafe fn crossings_of_four<const N: usize>(
        watertight: &[WatertightRay; N],
        hits: &[Option<Hit>; N],
        first: usize,
        [kx, ky, kz]: [usize; 3],
    ) -> [OwnCrossing; 4] {
        // SAFETY: the caller's.
        unsafe {
            let splat = |x: f64| _mm256_set1_pd(x);
            let (add, sub, mul, div) = (_mm256_add_pd, _mm256_sub_pd, _mm256_mul_pd, _mm256_div_pd);
            let (max, min) = (_mm256_max_pd, _mm256_min_pd);
            let abs = |x: __m256d| _mm256_andnot_pd(splat(-0.0), x);
            // The lanes' numbers gathered component by component, in plain loops: closures
            // passed to `array::from_fn` or `map` are not compiled for AVX, so each vector
            // operation in them would be a call.
            let (mut o, mut d, mut v) = ([[0.0; 4]; 3], [[0.0; 4]; 3], [[[0.0; 4]; 3]; 3]);
            for j in 0..4 {
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
            let load = |x: &[f64; 4]| _mm256_loadu_pd(x.as_ptr());
            // `CertifiedRay::new`, then `sheared`: no origin or direction error.
            let u = f64::UNIT_ROUNDOFF;
            let sz = div(splat(1.0), load(&d[kz]));
            let (sx, sy) = (mul(load(&d[kx]), sz), mul(load(&d[ky]), sz));
            let scale_error = 4.0 * 0.0 + 2.0 * u;
            let shear_error = 4.0 * 0.0 + 2.1 * u;
            // `shear`.
            let zero = splat(0.0);
            let mut a = [[zero; 3]; 3];
            for i in 0..3 {
                for c in 0..3 {
                    a[i][c] = sub(load(&v[i][c]), load(&o[c]));
                }
            }
            let (mut x, mut y, mut z) = ([zero; 3], [zero; 3], [zero; 3]);
            for i in 0..3 {
                x[i] = sub(a[i][kx], mul(sx, a[i][kz]));
                y[i] = sub(a[i][ky], mul(sy, a[i][kz]));
                z[i] = mul(sz, a[i][kz]);
            }
            let e = [
                sub(mul(x[2], y[1]), mul(y[2], x[1])),
                sub(mul(x[0], y[2]), mul(y[0], x[2])),
                sub(mul(x[1], y[0]), mul(y[1], x[0])),
            ];
            let mut across = splat(0.0);
            for k in 0..3 {
                across = max(max(across, abs(x[k])), abs(y[k]));
            }
            let along = max(max(abs(a[0][kz]), abs(a[1][kz])), abs(a[2][kz]));
            let reach = max(across, along);
            // `crossing_of`: `sheared_error`, `edge_error`, and a certain miss where the edge
            // functions have opposite signs beyond their bound.
            let (fixed, per_reach) =
                (2.0 * (2.0 * 0.0 + shear_error * 0.0), 2.0 * (2.01 * shear_error + 12.1 * u));
            let sheared = add(splat(fixed), mul(splat(per_reach), reach));
            let products = add(
                mul(mul(splat(2.0), sheared), add(mul(splat(2.0), across), sheared)),
                mul(mul(splat(4.01 * u), across), across),
            );
            let edge = mul(splat(2.0), add(products, splat(2.0 * f64::SMALLEST_SUBNORMAL)));
            let below = _mm256_xor_pd(edge, splat(-0.0));
            // Per lane and edge function, whether it lies above 0, below 0, above the bound,
            // below minus the bound. Written out: a closure around a vector operation is not
            // compiled for AVX, so the operation would be a call.
            let (or, and) = (_mm256_or_pd, _mm256_and_pd);
            let (mut pos, mut neg, mut clear_pos, mut clear_neg) =
                ([zero; 3], [zero; 3], [zero; 3], [zero; 3]);
            for k in 0..3 {
                pos[k] = _mm256_cmp_pd::<_CMP_GT_OQ>(e[k], zero);
                neg[k] = _mm256_cmp_pd::<_CMP_LT_OQ>(e[k], zero);
                clear_pos[k] = _mm256_cmp_pd::<_CMP_GT_OQ>(e[k], edge);
                clear_neg[k] = _mm256_cmp_pd::<_CMP_LT_OQ>(e[k], below);
            }
            let some = |m: [__m256d; 3]| or(or(m[0], m[1]), m[2]);
            let every = |m: [__m256d; 3]| and(and(m[0], m[1]), m[2]);
            let mixed = and(some(pos), some(neg));
            let clearly_mixed = and(some(clear_pos), some(clear_neg));
            let mut miss = _mm256_and_pd(mixed, clearly_mixed);
            // `crossing_near`: the z range (origin error 0, length ∞).
            let z_error = mul(
                splat(2.0),
                add(
                    add(splat(2.0 * 0.0), mul(splat(scale_error), add(mul(splat(2.01), reach), splat(0.0)))),
                    mul(splat(8.0 * u), reach),
                ),
            );
            let (z_min, z_max) = (min(min(z[0], z[1]), z[2]), max(max(z[0], z[1]), z[2]));
            let behind = _mm256_cmp_pd::<_CMP_LT_OQ>(add(z_max, z_error), zero);
            let beyond = _mm256_cmp_pd::<_CMP_GT_OQ>(sub(z_min, z_error), splat(f64::INFINITY));
            miss = _mm256_or_pd(miss, _mm256_or_pd(behind, beyond));
            let all_clear = or(every(clear_pos), every(clear_neg));
            let (range_lo, range_hi) = (sub(z_min, z_error), add(z_max, z_error));
            let det = add(add(e[0], e[1]), e[2]);
            let t = div(add(add(mul(e[0], z[0]), mul(e[1], z[1])), mul(e[2], z[2])), det);
            let z_abs = max(abs(z_min), abs(z_max));
            let numerator_error = add(
                add(mul(mul(splat(3.0), edge), add(z_abs, z_error)), mul(abs(det), z_error)),
                mul(mul(splat(2f64.powi(-50)), abs(det)), z_abs),
            );
            let det_error = mul(splat(3.0), edge);
            let t_error = add(
                div(mul(splat(2.0), add(numerator_error, mul(abs(t), det_error))), sub(abs(det), det_error)),
                mul(splat(2f64.powi(-50)), abs(t)),
            );
            let t_lo = max(sub(t, t_error), range_lo);
            let t_hi = min(add(t, t_error), range_hi);
            let through = _mm256_andnot_pd(miss, all_clear);
            let length = mul(splat(0.5), add(t_lo, t_hi));
            let length_error = mul(splat(0.5), sub(t_hi, t_lo));
            // `barycentrics_of`.
            let b = [div(e[0], det), div(e[1], det), div(e[2], det)];
            let edge_on = _mm256_cmp_pd::<_CMP_EQ_OQ>(det, zero);
            let store = |v: __m256d| {
                let mut out = [0.0; 4];
                _mm256_storeu_pd(out.as_mut_ptr(), v);
                out
            };
            let (through, edge_on) = (_mm256_movemask_pd(through), _mm256_movemask_pd(edge_on));
            let (length, length_error) = (store(length), store(length_error));
            let b = [store(b[0]), store(b[1]), store(b[2])];
            let mut out = [OwnCrossing::MISS; 4];
            for (j, out) in out.iter_mut().enumerate() {
                let refined =
                    (edge_on >> j & 1 == 0).then_some([b[0][j] as f32, b[1][j] as f32, b[2][j] as f32]);
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
}

#[cfg(all(test, target_arch = "x86_64"))]
mod tests {
    use super::{OwnCrossing, own_crossings};
    use crate::trace::bvh::hit::Hit;
    use crate::trace::bvh::packet::LANES;
    use crate::trace::bvh::packet_isa::{PacketIsa, in_packet_isa};
    use crate::trace::bvh::watertight::WatertightRay;
    use crate::trace::splitmix::SplitMix64;
    use glam::{Vec3, vec3};

    /// The bits of a crossing, so that −0 and 0 (or two NaNs) count as different.
    fn bits(c: &OwnCrossing) -> (u64, u64, bool, Option<[u32; 3]>) {
        (c.length.to_bits(), c.length_error.to_bits(), c.uncertain, c.refined.map(|b| b.map(f32::to_bits)))
    }

    /// Eight lanes at a time give `OwnCrossing::of` bit for bit: rays from one camera through
    /// triangles they cross (well inside, on an edge or a vertex), miss narrowly or widely, lie
    /// behind or edge-on to, and degenerate ones, near the origin and 10⁴ away, with directions
    /// whose largest components tie (the axis order's rule) and lanes without a hit.
    #[test]
    fn eight_lanes_give_the_single_crossings_bit_for_bit() {
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
            let mut watertight = [WatertightRay::UNUSED; LANES];
            let mut hits = [None; LANES];
            for k in 0..LANES {
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
            let wide = in_packet_isa(PacketIsa::Avx2, || own_crossings(&watertight, &hits));
            for k in 0..LANES {
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
