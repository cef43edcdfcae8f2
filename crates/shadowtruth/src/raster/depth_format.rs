//! Depth buffer formats: how a depth in [0, 1] is stored, and the minimum resolvable difference r
//! that glPolygonOffset's `units` multiply.

use half::f16;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum DepthFormat {
    F32,
    Unorm24,
    Unorm16,
    /// A half float, as engines that write the depth into an RGBA16F colour target store it
    /// (Babylon.js's default shadow map where the device renders half floats).
    F16,
}

impl DepthFormat {
    /// Every format, in the order help texts list them.
    pub const ALL: [DepthFormat; 4] =
        [DepthFormat::F32, DepthFormat::Unorm24, DepthFormat::Unorm16, DepthFormat::F16];

    pub fn name(self) -> &'static str {
        match self {
            DepthFormat::F32 => "f32",
            DepthFormat::Unorm24 => "unorm24",
            DepthFormat::Unorm16 => "unorm16",
            DepthFormat::F16 => "f16",
        }
    }

    pub fn parse(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|f| f.name() == name)
    }

    /// Bits of a unorm format, None for the float formats.
    fn unorm_bits(self) -> Option<i32> {
        match self {
            DepthFormat::F32 | DepthFormat::F16 => None,
            DepthFormat::Unorm24 => Some(24),
            DepthFormat::Unorm16 => Some(16),
        }
    }

    /// Explicit mantissa bits of a float format, None for unorm.
    fn mantissa_bits(self) -> Option<i32> {
        match self {
            DepthFormat::F32 => Some(23),
            DepthFormat::F16 => Some(10),
            DepthFormat::Unorm24 | DepthFormat::Unorm16 => None,
        }
    }

    /// The depth as stored (unorm: clamp to [0, 1], round to nearest).
    ///
    /// Unorm: q = round(d·(2^b − 1)) (ties away from zero), decoded as q/(2^b − 1); computed in
    /// f64 and rounded once to f32. NaN stores as 0, as D3D's float-to-unorm conversion does.
    /// f16: rounded to the nearest half float, ties to even (IEEE 754's default, the GPU's
    /// conversion on a write to a half-float target), not clamped.
    pub fn store(self, depth: f32) -> f32 {
        if self == DepthFormat::F16 {
            return f16::from_f32(depth).to_f32();
        }
        let Some(bits) = self.unorm_bits() else {
            return depth;
        };
        if depth.is_nan() {
            return 0.0;
        }
        let max_code = ((1u64 << bits) - 1) as f64;
        let q = (depth.clamp(0.0, 1.0) as f64 * max_code).round();
        (q / max_code) as f32
    }

    /// r: 1/(2^b − 1) for unorm, 2^(e − m) for a float format of m mantissa bits (23 for f32, 10
    /// for f16) where e is the exponent of `max_depth`.
    ///
    /// e = floor(log2(max_depth)) (z ∈ [0.5, 1) gives r = 2^−24 in f32), taken from the depth as
    /// an f32. Zero, negative, subnormal and NaN depths use f32's smallest normal exponent (−126),
    /// so r is never zero; infinity uses 127.
    pub fn min_resolvable_difference(self, max_depth: f32) -> f32 {
        if let Some(bits) = self.unorm_bits() {
            return (1.0 / ((1u64 << bits) - 1) as f64) as f32;
        }
        let mantissa_bits = self.mantissa_bits().expect("a format is unorm or float");
        let biased = ((max_depth.to_bits() >> 23) & 0xff) as i32;
        let e = if max_depth.is_nan() || max_depth <= 0.0 || biased == 0 { -126 } else { biased - 127 };
        // 2^(e − m) ≥ 2^−149, the smallest subnormal: exact in f32.
        2f64.powi(e - mantissa_bits) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for f in DepthFormat::ALL {
            assert_eq!(DepthFormat::parse(f.name()), Some(f));
        }
        assert_eq!(DepthFormat::parse("F16"), None);
    }

    #[test]
    fn f16_rounds_to_the_nearest_half_ties_to_even() {
        let f = DepthFormat::F16;
        // In [0.5, 1) a half's step is 2^-11: 0.5 + 2^-12 is a tie that goes to the even 0.5,
        // 0.5 + 3·2^-12 a tie that goes to the even 0.5 + 2^-10.
        assert_eq!(f.store(0.5 + 2f32.powi(-12)), 0.5);
        assert_eq!(f.store(0.5 + 3.0 * 2f32.powi(-12)), 0.5 + 2f32.powi(-10));
        assert_eq!(f.store(0.5 + 1.1 * 2f32.powi(-12)), 0.5 + 2f32.powi(-11));
        assert_eq!(f.store(0.75), 0.75);
        // Not clamped: a half holds values outside [0, 1].
        assert_eq!(f.store(-0.25), -0.25);
        assert_eq!(f.store(2.0), 2.0);
        assert!(f.store(f32::NAN).is_nan());
    }

    #[test]
    fn f16_r_is_one_half_step() {
        let f = DepthFormat::F16;
        assert_eq!(f.min_resolvable_difference(0.5), 2f32.powi(-11));
        assert_eq!(f.min_resolvable_difference(0.999), 2f32.powi(-11));
        assert_eq!(f.min_resolvable_difference(0.3), 2f32.powi(-12));
        // The step is what store rounds to: the next half above 0.6 is one r away.
        let d = f.store(0.6);
        assert_eq!(f.store(d + f.min_resolvable_difference(d)), d + f.min_resolvable_difference(d));
    }

    #[test]
    fn f32_store_is_identity() {
        for d in [-0.5f32, 0.0, 0.123_456_79, 1.0, 2.0] {
            assert_eq!(DepthFormat::F32.store(d).to_bits(), d.to_bits());
        }
    }

    #[test]
    fn unorm16_rounds_to_nearest_code() {
        let f = DepthFormat::Unorm16;
        // 0.5·65535 = 32767.5 rounds up to code 32768.
        assert_eq!(f.store(0.5), (32768.0f64 / 65535.0) as f32);
        // Just over half a code rounds up, just under rounds down (exactly half a code, 1/131070,
        // is not an f32 value; 0.5 above is the tie that is).
        let step = 1.0f64 / 65535.0;
        assert_eq!(f.store((0.51 * step) as f32), step as f32);
        assert_eq!(f.store((0.49 * step) as f32), 0.0);
        assert_eq!(f.store((1000.3 * step) as f32), (1000.0 * step) as f32);
        // Clamped to [0, 1].
        assert_eq!(f.store(-3.0), 0.0);
        assert_eq!(f.store(7.0), 1.0);
        assert_eq!(f.store(1.0), 1.0);
        assert_eq!(f.store(f32::NAN), 0.0);
    }

    #[test]
    fn unorm24_rounds_to_nearest_code() {
        let f = DepthFormat::Unorm24;
        let step = 1.0f64 / 16_777_215.0;
        assert_eq!(f.store(0.5), (8_388_608.0 * step) as f32);
        assert_eq!(f.store((12_345.7 * step) as f32), (12_346.0 * step) as f32);
    }

    #[test]
    fn unorm_r_is_one_code() {
        assert_eq!(DepthFormat::Unorm16.min_resolvable_difference(0.3), (1.0f64 / 65535.0) as f32);
        assert_eq!(DepthFormat::Unorm24.min_resolvable_difference(0.9), (1.0f64 / 16_777_215.0) as f32);
    }

    #[test]
    fn f32_r_follows_the_exponent_of_the_max_depth() {
        let f = DepthFormat::F32;
        assert_eq!(f.min_resolvable_difference(0.5), 2f32.powi(-24));
        assert_eq!(f.min_resolvable_difference(0.999_999_9), 2f32.powi(-24));
        assert_eq!(f.min_resolvable_difference(1.0), 2f32.powi(-23));
        assert_eq!(f.min_resolvable_difference(0.25), 2f32.powi(-25));
        assert_eq!(f.min_resolvable_difference(0.3), 2f32.powi(-25));
        // The smallest subnormal, 2^-149, by its bits: `powi(-149)` computes 1 / 2^149, whose
        // divisor overflows f32 where the call is not folded at compile time.
        let smallest_subnormal = f32::from_bits(1);
        assert_eq!(f.min_resolvable_difference(0.0), smallest_subnormal);
        assert_eq!(f.min_resolvable_difference(-1.0), smallest_subnormal);
        assert!(f.min_resolvable_difference(f32::NAN) > 0.0);
    }
}
