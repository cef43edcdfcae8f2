//! SplitMix64 (Steele, Lea & Flood, "Fast splittable pseudorandom number generators", OOPSLA
//! 2014; the constants are its published ones): a 64-bit counter advanced by a fixed odd step and
//! hashed by a bijective finalizer. The soft references' jitter hashes (pixel, sample) with it;
//! the papers' island draws its terrain and trees from it.

/// The counter's step (2⁶⁴/φ, odd).
const GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;

/// The finalizer: a bijective avalanche of 64 bits.
#[inline(always)]
pub fn finalizer(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The first output of a generator seeded with `z` (the finalizer of `z + GAMMA`): a bijective
/// hash whose outputs for consecutive inputs are statistically independent enough for jitter.
#[inline(always)]
pub fn mix64(z: u64) -> u64 {
    finalizer(z.wrapping_add(GAMMA))
}

/// A uniform number in [0, 1) from the top 53 bits of `h`.
#[inline(always)]
pub fn unit_f64(h: u64) -> f64 {
    (h >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// The generator: its state is the counter.
pub struct SplitMix64(u64);

impl SplitMix64 {
    pub fn new(seed: u64) -> Self {
        SplitMix64(seed)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(GAMMA);
        finalizer(self.0)
    }

    /// Uniform in [0, 1), from the top 53 bits.
    pub fn next_f64(&mut self) -> f64 {
        unit_f64(self.next_u64())
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, [lo, hi]: [f64; 2]) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splitmix64_matches_reference_values() {
        // First outputs for seed 0 from the reference C implementation (Vigna's splitmix64.c).
        let mut rng = SplitMix64::new(0);
        assert_eq!(rng.next_u64(), 0xE220_A839_7B1D_CDAF);
        assert_eq!(rng.next_u64(), 0x6E78_9E6A_A1B9_65F4);
        assert_eq!(mix64(0), 0xE220_A839_7B1D_CDAF);
    }
}
