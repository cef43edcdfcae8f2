//! Where a filter's taps fall (docs/formulas.md, "PCF kernels"): box k×k point taps, the
//! bilinear 2×2 of hardware PCF, Poisson disks of 16, 25 and 32 taps, a stratified 4×4 jitter,
//! and the regular grids of PCSS. Positions are in texel space (x = u·N, y = (1 − v)·N, y down
//! the map's rows), so a tap at (x, y) reads texel (⌊x⌋, ⌊y⌋).

/// A filter kernel. Poisson, jitter and grid kernels are scaled by a radius in texels given per
/// receiver (fixed for PCF, the penumbra estimate for PCSS).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Kernel {
    /// k×k point taps one texel apart, centred on the receiver (half-integer offsets for even k,
    /// as GPU Gems 1 ch. 11's 4×4), equal weights.
    Box { size: u32 },
    /// Compare-then-filter over the 2×2 texels around the receiver with bilinear weights
    /// (D3D10+ `SampleCmp` with a linear comparison filter).
    Bilinear,
    /// The first `taps` points of the published unit-disk sets (16: Myers, Fernando & Bavoil 2008;
    /// 25 and 32: NVIDIA SoftShadows `Poisson.fxh`), scaled by the radius, equal weights.
    Poisson { taps: u32 },
    /// One point per cell of a 4×4 grid over the square [−r, r]², jittered inside its cell by a
    /// hash of the receiver (deterministic), equal weights (the stratified reading of Uralsky,
    /// GPU Gems 2 ch. 17).
    Jitter4x4,
    /// k×k cell centres over [−r, r]² (the regular-grid preset of the NVIDIA SoftShadows sample).
    Grid { size: u32 },
}

impl Kernel {
    /// The number of taps.
    pub fn taps(&self) -> u32 {
        match *self {
            Kernel::Box { size } | Kernel::Grid { size } => size * size,
            Kernel::Bilinear => 4,
            Kernel::Poisson { taps } => taps,
            Kernel::Jitter4x4 => 16,
        }
    }

    /// Calls `tap(x, row, weight)` for every tap of a receiver at texel-space (`xs`, `ys`);
    /// texel indices are not clamped (the caller clamps to the edge, as a sampler would). The
    /// weights sum to 1. `seed` varies the jitter from receiver to receiver.
    #[inline]
    pub fn for_each_tap(
        &self,
        xs: f32,
        ys: f32,
        radius_texels: f32,
        seed: u32,
        mut tap: impl FnMut(i64, i64, f32),
    ) {
        let texel = |x: f32, y: f32| (x.floor() as i64, y.floor() as i64);
        match *self {
            Kernel::Box { size } => {
                let w = 1.0 / (size * size) as f32;
                let half = (size as f32 - 1.0) * 0.5;
                for b in 0..size {
                    for a in 0..size {
                        let (x, row) = texel(xs + a as f32 - half, ys + b as f32 - half);
                        tap(x, row, w);
                    }
                }
            }
            Kernel::Bilinear => {
                let (s, t) = (xs - 0.5, ys - 0.5);
                let (i, j) = (s.floor(), t.floor());
                let (f, g) = (s - i, t - j);
                let (i, j) = (i as i64, j as i64);
                tap(i, j, (1.0 - f) * (1.0 - g));
                tap(i + 1, j, f * (1.0 - g));
                tap(i, j + 1, (1.0 - f) * g);
                tap(i + 1, j + 1, f * g);
            }
            Kernel::Poisson { taps } => {
                let set = poisson_set(taps);
                let w = 1.0 / set.len() as f32;
                for &(px, py) in set {
                    let (x, row) = texel(xs + radius_texels * px, ys + radius_texels * py);
                    tap(x, row, w);
                }
            }
            Kernel::Jitter4x4 => {
                let cell = 2.0 * radius_texels / 4.0;
                for c in 0..16u32 {
                    let h = hash(seed ^ c.wrapping_mul(0x9E37_79B9));
                    let (jx, jy) = ((h & 0xFFFF) as f32 / 65536.0, (h >> 16) as f32 / 65536.0);
                    let ox = -radius_texels + ((c % 4) as f32 + jx) * cell;
                    let oy = -radius_texels + ((c / 4) as f32 + jy) * cell;
                    let (x, row) = texel(xs + ox, ys + oy);
                    tap(x, row, 1.0 / 16.0);
                }
            }
            Kernel::Grid { size } => {
                let w = 1.0 / (size * size) as f32;
                let step = 2.0 * radius_texels / size as f32;
                for b in 0..size {
                    for a in 0..size {
                        let ox = -radius_texels + (a as f32 + 0.5) * step;
                        let oy = -radius_texels + (b as f32 + 0.5) * step;
                        let (x, row) = texel(xs + ox, ys + oy);
                        tap(x, row, w);
                    }
                }
            }
        }
    }
}

/// A well-mixed 32-bit hash (Wellons's lowbias32), for deterministic jitter.
#[inline]
pub fn hash(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    x
}

/// The Poisson set with `taps` points (16, 25 or 32; the spec validates it).
pub fn poisson_set(taps: u32) -> &'static [(f32, f32)] {
    match taps {
        16 => &POISSON_16,
        25 => &POISSON_25,
        _ => &POISSON_32,
    }
}

/// The Poisson set sizes available.
pub const POISSON_SIZES: [u32; 3] = [16, 25, 32];

#[rustfmt::skip]
#[allow(clippy::excessive_precision)] // the published digits, verbatim
const POISSON_16: [(f32, f32); 16] = [
    (-0.94201624, -0.39906216), (0.94558609, -0.76890725), (-0.094184101, -0.92938870),
    (0.34495938, 0.29387760), (-0.91588581, 0.45771432), (-0.81544232, -0.87912464),
    (-0.38277543, 0.27676845), (0.97484398, 0.75648379), (0.44323325, -0.97511554),
    (0.53742981, -0.47373420), (-0.26496911, -0.41893023), (0.79197514, 0.19090188),
    (-0.24188840, 0.99706507), (-0.81409955, 0.91437590), (0.19984126, 0.78641367),
    (0.14383161, -0.14100790),
];

#[rustfmt::skip]
#[allow(clippy::excessive_precision)] // the published digits, verbatim
const POISSON_25: [(f32, f32); 25] = [
    (-0.978698, -0.0884121), (-0.841121, 0.521165), (-0.71746, -0.50322), (-0.702933, 0.903134),
    (-0.663198, 0.15482), (-0.495102, -0.232887), (-0.364238, -0.961791), (-0.345866, -0.564379),
    (-0.325663, 0.64037), (-0.182714, 0.321329), (-0.142613, -0.0227363), (-0.0564287, -0.36729),
    (-0.0185858, 0.918882), (0.0381787, -0.728996), (0.16599, 0.093112), (0.253639, 0.719535),
    (0.369549, -0.655019), (0.423627, 0.429975), (0.530747, -0.364971), (0.566027, -0.940489),
    (0.639332, 0.0284127), (0.652089, 0.669668), (0.773797, 0.345012), (0.968871, 0.840449),
    (0.991882, -0.657338),
];

#[rustfmt::skip]
#[allow(clippy::excessive_precision)] // the published digits, verbatim
const POISSON_32: [(f32, f32); 32] = [
    (-0.975402, -0.0711386), (-0.920347, -0.41142), (-0.883908, 0.217872), (-0.884518, 0.568041),
    (-0.811945, 0.90521), (-0.792474, -0.779962), (-0.614856, 0.386578), (-0.580859, -0.208777),
    (-0.53795, 0.716666), (-0.515427, 0.0899991), (-0.454634, -0.707938), (-0.420942, 0.991272),
    (-0.261147, 0.588488), (-0.211219, 0.114841), (-0.146336, -0.259194), (-0.139439, -0.888668),
    (0.0116886, 0.326395), (0.0380566, 0.625477), (0.0625935, -0.50853), (0.125584, 0.0469069),
    (0.169469, -0.997253), (0.320597, 0.291055), (0.359172, -0.633717), (0.435713, -0.250832),
    (0.507797, -0.916562), (0.545763, 0.730216), (0.56859, 0.11655), (0.743156, -0.505173),
    (0.736442, -0.189734), (0.843562, 0.357036), (0.865413, 0.763726), (0.872005, -0.927),
];

#[cfg(test)]
mod tests {
    use super::*;

    fn taps(k: Kernel, xs: f32, ys: f32, r: f32) -> Vec<(i64, i64, f32)> {
        let mut out = Vec::new();
        k.for_each_tap(xs, ys, r, 7, |x, y, w| out.push((x, y, w)));
        out
    }

    #[test]
    fn weights_sum_to_one_and_counts_match() {
        for k in [
            Kernel::Box { size: 1 },
            Kernel::Box { size: 4 },
            Kernel::Box { size: 11 },
            Kernel::Bilinear,
            Kernel::Poisson { taps: 16 },
            Kernel::Poisson { taps: 25 },
            Kernel::Poisson { taps: 32 },
            Kernel::Jitter4x4,
            Kernel::Grid { size: 8 },
        ] {
            let t = taps(k, 10.3, 20.7, 2.5);
            assert_eq!(t.len() as u32, k.taps(), "{k:?}");
            let sum: f32 = t.iter().map(|t| t.2).sum();
            assert!((sum - 1.0).abs() < 1e-5, "{k:?}: {sum}");
        }
    }

    #[test]
    fn box_taps_are_the_texels_around_the_receiver() {
        // 3×3 around texel (10, 20); 4×4 at half-integer offsets covers texels 8..=11 from 9.6.
        let t = taps(Kernel::Box { size: 3 }, 10.5, 20.5, 0.0);
        let texels: Vec<(i64, i64)> = t.iter().map(|t| (t.0, t.1)).collect();
        assert_eq!(texels[0], (9, 19));
        assert_eq!(texels[4], (10, 20));
        assert_eq!(texels[8], (11, 21));
        let t = taps(Kernel::Box { size: 4 }, 9.6, 9.6, 0.0);
        let xs: Vec<i64> = t.iter().take(4).map(|t| t.0).collect();
        assert_eq!(xs, [8, 9, 10, 11]);
    }

    #[test]
    fn bilinear_weights_follow_the_fraction() {
        // s = 10.75 − ½ = 10.25: texels 10 and 11 weighted ¾ and ¼ in x; t = 20.5 − ½ = 20.
        let t = taps(Kernel::Bilinear, 10.75, 20.5, 0.0);
        assert_eq!(t[0], (10, 20, 0.75));
        assert_eq!(t[1], (11, 20, 0.25));
        assert_eq!(t[2], (10, 21, 0.0));
        assert_eq!(t[3], (11, 21, 0.0));
    }

    #[test]
    fn jitter_is_stratified_and_deterministic() {
        let a = taps(Kernel::Jitter4x4, 100.0, 100.0, 2.0);
        assert_eq!(a, taps(Kernel::Jitter4x4, 100.0, 100.0, 2.0));
        // One tap per texel of the 4×4 block 98..=101 when r = 2 and the receiver sits on a corner.
        let mut cells: Vec<(i64, i64)> = a.iter().map(|t| (t.0, t.1)).collect();
        cells.sort();
        cells.dedup();
        assert_eq!(cells.len(), 16);
        assert!(cells.iter().all(|&(x, y)| (98..=101).contains(&x) && (98..=101).contains(&y)));
    }
}
