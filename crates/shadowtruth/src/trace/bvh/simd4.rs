//! Four-lane f32 arithmetic for the BVH node test: SSE2 on x86_64, plain arrays elsewhere. Each
//! operation rounds once, as its AVX2 counterpart in node_test.rs does.

#[cfg(target_arch = "x86_64")]
use std::arch::x86_64::*;

/// Four f32 lanes.
#[derive(Clone, Copy)]
pub struct F4(#[cfg(target_arch = "x86_64")] __m128, #[cfg(not(target_arch = "x86_64"))] [f32; 4]);

/// Per-lane entry and exit distances of four boxes.
pub struct Span4 {
    enter: F4,
    exit: F4,
}

#[cfg(target_arch = "x86_64")]
impl F4 {
    #[inline(always)]
    pub fn splat(x: f32) -> Self {
        unsafe { F4(_mm_set1_ps(x)) }
    }
    /// Lanes `v[first..first + 4]`.
    #[inline(always)]
    pub fn load(v: &[f32; 8], first: usize) -> Self {
        let four: &[f32; 4] = v[first..first + 4].try_into().unwrap();
        unsafe { F4(_mm_loadu_ps(four.as_ptr())) }
    }
    #[inline(always)]
    pub fn add(self, o: Self) -> Self {
        unsafe { F4(_mm_add_ps(self.0, o.0)) }
    }
    #[inline(always)]
    pub fn sub(self, o: Self) -> Self {
        unsafe { F4(_mm_sub_ps(self.0, o.0)) }
    }
    #[inline(always)]
    pub fn mul(self, o: Self) -> Self {
        unsafe { F4(_mm_mul_ps(self.0, o.0)) }
    }
    /// Lane by lane, `o` where either is NaN (as `_mm_min_ps`).
    #[inline(always)]
    pub fn min(self, o: Self) -> Self {
        unsafe { F4(_mm_min_ps(self.0, o.0)) }
    }
    /// Lane by lane, `o` where either is NaN (as `_mm_max_ps`).
    #[inline(always)]
    pub fn max(self, o: Self) -> Self {
        unsafe { F4(_mm_max_ps(self.0, o.0)) }
    }
    #[inline(always)]
    pub fn abs(self) -> Self {
        unsafe { F4(_mm_andnot_ps(_mm_set1_ps(-0.0), self.0)) }
    }
    #[inline(always)]
    fn store(self, out: &mut [f32; 8], first: usize) {
        let four: &mut [f32; 4] = (&mut out[first..first + 4]).try_into().unwrap();
        unsafe { _mm_storeu_ps(four.as_mut_ptr(), self.0) }
    }
    /// Bit k set where lane k of self ≤ lane k of o.
    #[inline(always)]
    fn le_bits(self, o: Self) -> u32 {
        unsafe { _mm_movemask_ps(_mm_cmple_ps(self.0, o.0)) as u32 }
    }
    /// `inside` where lo ≤ x ≤ hi, `outside` elsewhere.
    #[inline(always)]
    fn select_between(lo: Self, hi: Self, x: f32, inside: f32, outside: f32) -> Self {
        unsafe {
            let x = _mm_set1_ps(x);
            let mask = _mm_and_ps(_mm_cmple_ps(lo.0, x), _mm_cmple_ps(x, hi.0));
            F4(_mm_or_ps(_mm_and_ps(mask, _mm_set1_ps(inside)), _mm_andnot_ps(mask, _mm_set1_ps(outside))))
        }
    }
}

#[cfg(not(target_arch = "x86_64"))]
impl F4 {
    #[inline(always)]
    pub fn splat(x: f32) -> Self {
        F4([x; 4])
    }
    #[inline(always)]
    pub fn load(v: &[f32; 8], first: usize) -> Self {
        F4(std::array::from_fn(|k| v[first + k]))
    }
    #[inline(always)]
    pub fn add(self, o: Self) -> Self {
        F4(std::array::from_fn(|k| self.0[k] + o.0[k]))
    }
    #[inline(always)]
    pub fn sub(self, o: Self) -> Self {
        F4(std::array::from_fn(|k| self.0[k] - o.0[k]))
    }
    #[inline(always)]
    pub fn mul(self, o: Self) -> Self {
        F4(std::array::from_fn(|k| self.0[k] * o.0[k]))
    }
    #[inline(always)]
    pub fn min(self, o: Self) -> Self {
        F4(std::array::from_fn(|k| if self.0[k] < o.0[k] { self.0[k] } else { o.0[k] }))
    }
    #[inline(always)]
    pub fn max(self, o: Self) -> Self {
        F4(std::array::from_fn(|k| if self.0[k] > o.0[k] { self.0[k] } else { o.0[k] }))
    }
    #[inline(always)]
    pub fn abs(self) -> Self {
        F4(self.0.map(f32::abs))
    }
    #[inline(always)]
    fn store(self, out: &mut [f32; 8], first: usize) {
        out[first..first + 4].copy_from_slice(&self.0);
    }
    #[inline(always)]
    fn le_bits(self, o: Self) -> u32 {
        (0..4).map(|k| ((self.0[k] <= o.0[k]) as u32) << k).sum()
    }
    #[inline(always)]
    fn select_between(lo: Self, hi: Self, x: f32, inside: f32, outside: f32) -> Self {
        F4(std::array::from_fn(|k| if lo.0[k] <= x && x <= hi.0[k] { inside } else { outside }))
    }
}

impl Span4 {
    #[inline(always)]
    pub fn new(tmin: f32, tmax: f32) -> Self {
        Span4 { enter: F4::splat(tmin), exit: F4::splat(tmax) }
    }

    /// Intersects with the slab distances [near, far].
    #[inline(always)]
    pub fn clip(&mut self, near: F4, far: F4) {
        self.enter = self.enter.max(near);
        self.exit = self.exit.min(far);
    }

    /// Along an axis the ray does not move: keep the lanes whose slab [lo, hi] holds `origin`.
    #[inline(always)]
    pub fn keep_if_between(&mut self, lo: F4, hi: F4, origin: f32) {
        self.enter = self.enter.max(F4::select_between(lo, hi, origin, f32::NEG_INFINITY, f32::INFINITY));
    }

    /// Bit k set where box k is entered no later than it is left.
    #[inline(always)]
    pub fn hit_bits(&self) -> u32 {
        self.enter.le_bits(self.exit)
    }

    /// The entry distances into `out[first..first + 4]`.
    #[inline(always)]
    pub fn store_enter(&self, out: &mut [f32; 8], first: usize) {
        self.enter.store(out, first);
    }
}
