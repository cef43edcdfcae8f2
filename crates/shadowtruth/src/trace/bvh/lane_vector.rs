//! The vectors a packet walk (packet.rs) computes with, one ray per lane: eight lanes in AVX2
//! (`L8`), sixteen in AVX-512 (`L16`). Written once over `LaneVector`, the walk is compiled for
//! each width; every operation rounds once, as IEEE arithmetic does, so a lane's numbers are the
//! same in either.
//!
//! A vector exists only where the processor has its instruction set: the constructors (`splat`,
//! `load`) are `unsafe`, and their callers check the set first (`packet_isa.rs`). The other
//! operations take an existing vector, and so are safe.

#![cfg(target_arch = "x86_64")]

use std::arch::x86_64::*;

/// A vector of f32, one per ray of a packet.
pub(in crate::trace) trait LaneVector: Copy {
    /// Rays in a packet.
    const LANES: usize;
    /// Every lane's bit.
    const ALL: u32;
    /// The lanes in memory: `[f32; LANES]`.
    type Array: Copy + Default + AsRef<[f32]> + AsMut<[f32]>;
    /// A yes or no per lane.
    type Mask: LaneMask;

    /// # Safety
    /// The processor has the vector's instruction set, and the caller is compiled for it.
    unsafe fn splat(x: f32) -> Self;
    /// # Safety
    /// As `splat`.
    unsafe fn load(lanes: &Self::Array) -> Self;
    fn store(self, lanes: &mut Self::Array);
    fn add(self, o: Self) -> Self;
    fn sub(self, o: Self) -> Self;
    fn mul(self, o: Self) -> Self;
    fn div(self, o: Self) -> Self;
    /// self · m − s, rounded once.
    fn mul_sub(self, m: Self, s: Self) -> Self;
    /// Lane by lane, `o` where either is NaN (as `minps`).
    fn min(self, o: Self) -> Self;
    /// Lane by lane, `o` where either is NaN (as `maxps`).
    fn max(self, o: Self) -> Self;
    fn abs(self) -> Self;
    /// The comparisons are ordered: false where either lane is NaN.
    fn lt(self, o: Self) -> Self::Mask;
    fn gt(self, o: Self) -> Self::Mask;
    fn le(self, o: Self) -> Self::Mask;
    fn ge(self, o: Self) -> Self::Mask;
    fn eq(self, o: Self) -> Self::Mask;
    /// The lanes whose bits are `bits`, compared as integers (a lane carrying an id).
    fn bits_equal(self, bits: u32) -> Self::Mask;
    /// The lanes whose bits, as an unsigned integer, exceed `bits`.
    fn bits_above(self, bits: u32) -> Self::Mask;
    /// Lane by lane, `self` where `m` holds, else `o`.
    fn select(self, m: Self::Mask, o: Self) -> Self;
    /// The least and the greatest of the lanes.
    fn extremes(self) -> [f32; 2];
    /// Lane `k`.
    fn lane(self, k: usize) -> f32;
}

/// A yes or no per lane of a `LaneVector`.
pub(in crate::trace) trait LaneMask: Copy {
    fn and(self, o: Self) -> Self;
    fn or(self, o: Self) -> Self;
    /// Bit k set where lane k holds.
    fn bits(self) -> u32;
    /// Lane k holds where bit k of `bits` is set.
    ///
    /// # Safety
    /// As `LaneVector::splat`.
    unsafe fn from_bits(bits: u32) -> Self;
}

/// Eight lanes, AVX2 with FMA.
#[derive(Clone, Copy)]
pub(in crate::trace) struct L8(__m256);

/// Eight lanes' yes or no: all bits of a lane set where it holds.
#[derive(Clone, Copy)]
pub(in crate::trace) struct M8(__m256);

/// Sixteen lanes, AVX-512 F.
#[derive(Clone, Copy)]
pub(in crate::trace) struct L16(__m512);

/// Sixteen lanes' yes or no: a mask register.
#[derive(Clone, Copy)]
pub(in crate::trace) struct M16(__mmask16);

// SAFETY (every block below): an `L8` or `M8` exists only where the processor has AVX2 and FMA,
// an `L16` or `M16` only where it has AVX-512 F (the constructors' contract).

impl LaneVector for L8 {
    const LANES: usize = 8;
    const ALL: u32 = 0xff;
    type Array = [f32; 8];
    type Mask = M8;

    #[inline(always)]
    unsafe fn splat(x: f32) -> Self {
        unsafe { L8(_mm256_set1_ps(x)) }
    }
    #[inline(always)]
    unsafe fn load(lanes: &[f32; 8]) -> Self {
        unsafe { L8(_mm256_loadu_ps(lanes.as_ptr())) }
    }
    #[inline(always)]
    fn store(self, lanes: &mut [f32; 8]) {
        unsafe { _mm256_storeu_ps(lanes.as_mut_ptr(), self.0) }
    }
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        unsafe { L8(_mm256_add_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        unsafe { L8(_mm256_sub_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        unsafe { L8(_mm256_mul_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        unsafe { L8(_mm256_div_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn mul_sub(self, m: Self, s: Self) -> Self {
        unsafe { L8(_mm256_fmsub_ps(self.0, m.0, s.0)) }
    }
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        unsafe { L8(_mm256_min_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        unsafe { L8(_mm256_max_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn abs(self) -> Self {
        unsafe { L8(_mm256_andnot_ps(_mm256_set1_ps(-0.0), self.0)) }
    }
    #[inline(always)]
    fn lt(self, o: Self) -> M8 {
        unsafe { M8(_mm256_cmp_ps::<_CMP_LT_OQ>(self.0, o.0)) }
    }
    #[inline(always)]
    fn gt(self, o: Self) -> M8 {
        unsafe { M8(_mm256_cmp_ps::<_CMP_GT_OQ>(self.0, o.0)) }
    }
    #[inline(always)]
    fn le(self, o: Self) -> M8 {
        unsafe { M8(_mm256_cmp_ps::<_CMP_LE_OQ>(self.0, o.0)) }
    }
    #[inline(always)]
    fn ge(self, o: Self) -> M8 {
        unsafe { M8(_mm256_cmp_ps::<_CMP_GE_OQ>(self.0, o.0)) }
    }
    #[inline(always)]
    fn eq(self, o: Self) -> M8 {
        unsafe { M8(_mm256_cmp_ps::<_CMP_EQ_OQ>(self.0, o.0)) }
    }
    #[inline(always)]
    fn bits_equal(self, bits: u32) -> M8 {
        unsafe {
            let equal = _mm256_cmpeq_epi32(_mm256_castps_si256(self.0), _mm256_set1_epi32(bits as i32));
            M8(_mm256_castsi256_ps(equal))
        }
    }
    #[inline(always)]
    fn bits_above(self, bits: u32) -> M8 {
        // AVX2 compares signed integers only: flipping both sign bits orders them unsigned.
        unsafe {
            let flip = _mm256_set1_epi32(i32::MIN);
            let lanes = _mm256_xor_si256(_mm256_castps_si256(self.0), flip);
            let above = _mm256_cmpgt_epi32(lanes, _mm256_set1_epi32((bits ^ 0x8000_0000) as i32));
            M8(_mm256_castsi256_ps(above))
        }
    }
    #[inline(always)]
    fn select(self, m: M8, o: Self) -> Self {
        unsafe { L8(_mm256_blendv_ps(o.0, self.0, m.0)) }
    }
    #[inline(always)]
    fn extremes(self) -> [f32; 2] {
        unsafe {
            let v = self.0;
            let swapped = _mm256_permute2f128_ps::<1>(v, v);
            let (lo, hi) = (_mm256_min_ps(v, swapped), _mm256_max_ps(v, swapped));
            let (lo, hi) = (
                _mm256_min_ps(lo, _mm256_permute_ps::<0b01_00_11_10>(lo)),
                _mm256_max_ps(hi, _mm256_permute_ps::<0b01_00_11_10>(hi)),
            );
            [
                _mm256_cvtss_f32(_mm256_min_ps(lo, _mm256_permute_ps::<0b10_11_00_01>(lo))),
                _mm256_cvtss_f32(_mm256_max_ps(hi, _mm256_permute_ps::<0b10_11_00_01>(hi))),
            ]
        }
    }
    #[inline(always)]
    fn lane(self, k: usize) -> f32 {
        unsafe { _mm256_cvtss_f32(_mm256_permutevar8x32_ps(self.0, _mm256_set1_epi32(k as i32))) }
    }
}

impl LaneMask for M8 {
    #[inline(always)]
    fn and(self, o: Self) -> Self {
        unsafe { M8(_mm256_and_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn or(self, o: Self) -> Self {
        unsafe { M8(_mm256_or_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn bits(self) -> u32 {
        unsafe { _mm256_movemask_ps(self.0) as u32 }
    }
    #[inline(always)]
    unsafe fn from_bits(bits: u32) -> Self {
        unsafe {
            let lane_bits = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
            let set = _mm256_and_si256(_mm256_set1_epi32(bits as i32), lane_bits);
            M8(_mm256_castsi256_ps(_mm256_cmpgt_epi32(set, _mm256_setzero_si256())))
        }
    }
}

impl LaneVector for L16 {
    const LANES: usize = 16;
    const ALL: u32 = 0xffff;
    type Array = [f32; 16];
    type Mask = M16;

    #[inline(always)]
    unsafe fn splat(x: f32) -> Self {
        unsafe { L16(_mm512_set1_ps(x)) }
    }
    #[inline(always)]
    unsafe fn load(lanes: &[f32; 16]) -> Self {
        unsafe { L16(_mm512_loadu_ps(lanes.as_ptr())) }
    }
    #[inline(always)]
    fn store(self, lanes: &mut [f32; 16]) {
        unsafe { _mm512_storeu_ps(lanes.as_mut_ptr(), self.0) }
    }
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        unsafe { L16(_mm512_add_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        unsafe { L16(_mm512_sub_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        unsafe { L16(_mm512_mul_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        unsafe { L16(_mm512_div_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn mul_sub(self, m: Self, s: Self) -> Self {
        unsafe { L16(_mm512_fmsub_ps(self.0, m.0, s.0)) }
    }
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        unsafe { L16(_mm512_min_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        unsafe { L16(_mm512_max_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn abs(self) -> Self {
        unsafe { L16(_mm512_abs_ps(self.0)) }
    }
    #[inline(always)]
    fn lt(self, o: Self) -> M16 {
        unsafe { M16(_mm512_cmp_ps_mask::<_CMP_LT_OQ>(self.0, o.0)) }
    }
    #[inline(always)]
    fn gt(self, o: Self) -> M16 {
        unsafe { M16(_mm512_cmp_ps_mask::<_CMP_GT_OQ>(self.0, o.0)) }
    }
    #[inline(always)]
    fn le(self, o: Self) -> M16 {
        unsafe { M16(_mm512_cmp_ps_mask::<_CMP_LE_OQ>(self.0, o.0)) }
    }
    #[inline(always)]
    fn ge(self, o: Self) -> M16 {
        unsafe { M16(_mm512_cmp_ps_mask::<_CMP_GE_OQ>(self.0, o.0)) }
    }
    #[inline(always)]
    fn eq(self, o: Self) -> M16 {
        unsafe { M16(_mm512_cmp_ps_mask::<_CMP_EQ_OQ>(self.0, o.0)) }
    }
    #[inline(always)]
    fn bits_equal(self, bits: u32) -> M16 {
        unsafe { M16(_mm512_cmpeq_epi32_mask(_mm512_castps_si512(self.0), _mm512_set1_epi32(bits as i32))) }
    }
    #[inline(always)]
    fn bits_above(self, bits: u32) -> M16 {
        unsafe { M16(_mm512_cmpgt_epu32_mask(_mm512_castps_si512(self.0), _mm512_set1_epi32(bits as i32))) }
    }
    #[inline(always)]
    fn select(self, m: M16, o: Self) -> Self {
        unsafe { L16(_mm512_mask_blend_ps(m.0, o.0, self.0)) }
    }
    #[inline(always)]
    fn extremes(self) -> [f32; 2] {
        unsafe { [_mm512_reduce_min_ps(self.0), _mm512_reduce_max_ps(self.0)] }
    }
    #[inline(always)]
    fn lane(self, k: usize) -> f32 {
        unsafe { _mm512_cvtss_f32(_mm512_permutexvar_ps(_mm512_set1_epi32(k as i32), self.0)) }
    }
}

impl LaneMask for M16 {
    #[inline(always)]
    fn and(self, o: Self) -> Self {
        M16(self.0 & o.0)
    }
    #[inline(always)]
    fn or(self, o: Self) -> Self {
        M16(self.0 | o.0)
    }
    #[inline(always)]
    fn bits(self) -> u32 {
        self.0 as u32
    }
    #[inline(always)]
    unsafe fn from_bits(bits: u32) -> Self {
        M16(bits as __mmask16)
    }
}

#[cfg(test)]
mod tests {
    use super::{L8, L16, LaneMask, LaneVector};

    /// `bits_above` orders lanes as unsigned integers in both widths, on either side of the sign
    /// bit (which AVX2's signed comparison would misorder).
    #[test]
    fn bits_above_compares_as_unsigned_integers() {
        if !super::super::node_test::wide_form_testable() {
            return;
        }
        let values = [0, 1, 7, 0x7fff_ffff, 0x8000_0000, 0x8000_0001, 0xffff_fffe, u32::MAX];
        let lanes: [f32; 16] =
            std::array::from_fn(|k| f32::from_bits(values[k % 8].wrapping_add(k as u32 / 8)));
        for &bits in &values {
            let expected =
                |n: usize| (0..n).filter(|&k| lanes[k].to_bits() > bits).fold(0, |m, k| m | 1 << k);
            let eight: [f32; 8] = lanes[..8].try_into().expect("eight lanes");
            // SAFETY: the processor has AVX2 (`wide_form_testable`).
            assert_eq!(unsafe { L8::load(&eight) }.bits_above(bits).bits(), expected(8), "above {bits:#x}");
            if is_x86_feature_detected!("avx512f") {
                // SAFETY: the processor has AVX-512 F.
                assert_eq!(
                    unsafe { L16::load(&lanes) }.bits_above(bits).bits(),
                    expected(16),
                    "above {bits:#x}"
                );
            }
        }
    }
}
