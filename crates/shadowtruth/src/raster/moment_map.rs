//! The filterable shadow maps' texels: up to four moments of a warped depth per texel, computed
//! from the nearest depth layer, blurred, optionally mipmapped, and read with bilinear or
//! trilinear filtering (docs/formulas.md, "Filterable shadow maps"). The tests that read them are
//! in `technique::filterable`.
//!
//! The moments are of the layer's own depth d ∈ [0, 1] (empty texels hold the far plane, 1), as
//! a renderer that writes them from the depth pass would; everything is f32, the format the
//! papers and engines store them in. The blur is separable, clamped to the edge, and sums in a
//! fixed order, so a map is the same bytes for any thread count.

use super::DepthLayer;
use super::moment_level::{MomentLevel, lerp};
use rayon::prelude::*;

/// What a texel stores: the warp of depth z and how many of its powers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MomentWarp {
    /// (z, z²): variance shadow maps (Donnelly & Lauritzen 2006).
    Depth2,
    /// e^{c·z}: exponential shadow maps (Annen et al. 2008).
    Exponential { exponent: f32 },
    /// (e^{c⁺·z'}, e^{2c⁺·z'}) with z' = 2z − 1: EVSM with the positive warp only.
    Evsm2 { positive: f32 },
    /// EVSM2's two moments and (−e^{−c⁻·z'}, e^{−2c⁻·z'}) (Lauritzen & McCool 2008).
    Evsm4 { positive: f32, negative: f32 },
    /// (z, z², z³, z⁴): the 4-moment shadow map (Peters & Klein 2015).
    Power4,
}

impl MomentWarp {
    /// The moments of depth `z` (unused entries 0).
    #[inline]
    pub fn moments(self, z: f32) -> [f32; 4] {
        match self {
            MomentWarp::Depth2 => [z, z * z, 0.0, 0.0],
            MomentWarp::Exponential { exponent } => [(exponent * z).exp(), 0.0, 0.0, 0.0],
            MomentWarp::Evsm2 { positive } => {
                let p = evsm_positive(z, positive);
                [p, p * p, 0.0, 0.0]
            }
            MomentWarp::Evsm4 { positive, negative } => {
                let (p, n) = (evsm_positive(z, positive), evsm_negative(z, negative));
                [p, p * p, n, n * n]
            }
            MomentWarp::Power4 => {
                let z2 = z * z;
                [z, z2, z2 * z, z2 * z2]
            }
        }
    }

    /// How many of the four entries are used.
    pub fn channels(self) -> usize {
        match self {
            MomentWarp::Exponential { .. } => 1,
            MomentWarp::Depth2 | MomentWarp::Evsm2 { .. } => 2,
            MomentWarp::Evsm4 { .. } | MomentWarp::Power4 => 4,
        }
    }
}

/// EVSM's positive warp e^{c·(2z − 1)}.
#[inline]
pub fn evsm_positive(z: f32, exponent: f32) -> f32 {
    (exponent * (2.0 * z - 1.0)).exp()
}

/// EVSM's negative warp −e^{−c·(2z − 1)}.
#[inline]
pub fn evsm_negative(z: f32, exponent: f32) -> f32 {
    -(-exponent * (2.0 * z - 1.0)).exp()
}

/// The blur applied to the moments before they are read.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MapBlur {
    /// No blur: the hardware's bilinear filter alone.
    None,
    /// A (2r + 1)² box.
    Box { radius_texels: u32 },
    /// A separable Gaussian of σ = r/2 texels over [−r, r], its weights normalised.
    Gaussian { radius_texels: u32 },
}

/// The widest blur radius, in texels.
pub const MAX_BLUR_RADIUS_TEXELS: u32 = 32;

impl MapBlur {
    /// The 1D weights over [−r, r] (one weight of 1 without a blur).
    pub fn weights(self) -> Vec<f32> {
        match self {
            MapBlur::None => vec![1.0],
            MapBlur::Box { radius_texels: r } => vec![1.0 / (2 * r + 1) as f32; 2 * r as usize + 1],
            MapBlur::Gaussian { radius_texels: 0 } => vec![1.0],
            MapBlur::Gaussian { radius_texels: r } => {
                let sigma = r as f64 / 2.0;
                let raw: Vec<f64> = (-(r as i64)..=r as i64)
                    .map(|x| (-(x * x) as f64 / (2.0 * sigma * sigma)).exp())
                    .collect();
                let total: f64 = raw.iter().sum();
                raw.iter().map(|w| (w / total) as f32).collect()
            }
        }
    }
}

/// The moments of a filterable map: level 0, and with mipmaps the rest of its mip chain down to
/// 1×1.
#[derive(Clone, Debug, PartialEq)]
pub struct MomentLayer {
    pub warp: MomentWarp,
    /// Level 0 first, each level half the one before.
    pub levels: Vec<MomentLevel>,
}

impl MomentLayer {
    /// The moments of every texel of `base` under `warp`, blurred by `blur`, with the mip chain of
    /// the blurred level when `mipmaps`.
    pub fn from_depth(base: &DepthLayer, warp: MomentWarp, blur: MapBlur, mipmaps: bool) -> Self {
        let n = base.resolution as usize;
        let raw: Vec<[f32; 4]> = base.depth.par_iter().map(|&z| warp.moments(z)).collect();
        let weights = blur.weights();
        let moments = if weights.len() == 1 { raw } else { blur_rows_then_columns(&raw, n, &weights) };
        let mut levels = vec![MomentLevel { resolution: base.resolution, moments }];
        while let Some(last) = levels.last().filter(|l| mipmaps && l.resolution > 1) {
            let next = last.halved();
            levels.push(next);
        }
        MomentLayer { warp, levels }
    }

    /// Level 0's side, in texels.
    pub fn resolution(&self) -> u32 {
        self.levels[0].resolution
    }

    /// The moments at map coordinates (u, v) of level 0, bilinearly filtered.
    #[inline]
    pub fn sample(&self, u: f32, v: f32) -> [f32; 4] {
        self.levels[0].sample(u, v)
    }

    /// The moments at (u, v) and level of detail `lod`, as a sampler with `LINEAR_MIPMAP_LINEAR`
    /// minification and `LINEAR` magnification filters reads them (OpenGL 4.6 §8.14.2–8.14.3):
    /// level 0 bilinearly at λ ≤ 0, else the two levels around λ, each bilinearly, blended by
    /// λ's fraction; the last level alone from it on. NaN reads the last level.
    #[inline]
    pub fn sample_at_lod(&self, u: f32, v: f32, lod: f32) -> [f32; 4] {
        let last = (self.levels.len() - 1) as f32;
        if lod <= 0.0 {
            return self.levels[0].sample(u, v);
        }
        if lod >= last || lod.is_nan() {
            return self.levels[last as usize].sample(u, v);
        }
        let below = lod.floor();
        let fine = self.levels[below as usize].sample(u, v);
        let coarse = self.levels[below as usize + 1].sample(u, v);
        lerp(fine, coarse, lod - below)
    }

    /// Bytes of moment data over every level (the channels the warp uses, as a renderer would
    /// store them).
    pub fn memory_bytes(&self) -> usize {
        let texels: usize = self.levels.iter().map(|l| l.moments.len()).sum();
        texels * self.warp.channels() * std::mem::size_of::<f32>()
    }
}

/// The level of detail λ = log₂ ρ of a pixel whose neighbours' map coordinates differ from its
/// own by `duv_dx` and `duv_dy`, on a map of `resolution` texels a side: ρ is the longer of the
/// two differences in texels (OpenGL 4.6 eq. 8.7 without anisotropy). +∞ for an unbounded
/// footprint.
pub fn level_of_detail(resolution: u32, duv_dx: [f32; 2], duv_dy: [f32; 2]) -> f32 {
    // ρ² from squared lengths (log₂ ρ = ½·log₂ ρ²): no square root per pixel.
    let n = resolution as f32;
    let texels_squared = |d: [f32; 2]| (n * d[0]) * (n * d[0]) + (n * d[1]) * (n * d[1]);
    let (x, y) = (texels_squared(duv_dx), texels_squared(duv_dy));
    // `max` would drop a NaN; a difference that is not a number is a footprint without bound.
    if x.is_nan() || y.is_nan() { f32::INFINITY } else { 0.5 * x.max(y).log2() }
}

/// The separable blur of an n×n image: each row, then each column, with `weights` over
/// [−r, r] and edge texels repeated.
fn blur_rows_then_columns(image: &[[f32; 4]], n: usize, weights: &[f32]) -> Vec<[f32; 4]> {
    let r = (weights.len() / 2) as i64;
    let tap = |line: &dyn Fn(usize) -> [f32; 4], i: usize| -> [f32; 4] {
        let mut sum = [0.0f32; 4];
        for (k, &w) in weights.iter().enumerate() {
            let j = (i as i64 + k as i64 - r).clamp(0, n as i64 - 1) as usize;
            let m = line(j);
            for c in 0..4 {
                sum[c] += w * m[c];
            }
        }
        sum
    };
    let mut rows = vec![[0.0f32; 4]; n * n];
    rows.par_chunks_mut(n).enumerate().for_each(|(y, out)| {
        let line = |x: usize| image[y * n + x];
        for (x, o) in out.iter_mut().enumerate() {
            *o = tap(&line, x);
        }
    });
    let mut out = vec![[0.0f32; 4]; n * n];
    out.par_chunks_mut(n).enumerate().for_each(|(y, row)| {
        for (x, o) in row.iter_mut().enumerate() {
            let column = |j: usize| rows[j * n + x];
            *o = tap(&column, y);
        }
    });
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layer(n: u32, depth: impl Fn(u32, u32) -> f32) -> DepthLayer {
        let depth = (0..n).flat_map(|row| (0..n).map(move |x| (x, row))).map(|(x, r)| depth(x, r)).collect();
        DepthLayer { resolution: n, depth }
    }

    #[test]
    fn a_box_blur_averages_its_window_and_repeats_the_edge() {
        // One texel at depth 0.5 in a map at 1: a 3×3 box spreads 1/9 of the difference.
        let base = layer(5, |x, r| if (x, r) == (2, 2) { 0.5 } else { 1.0 });
        let m = MomentLayer::from_depth(&base, MomentWarp::Depth2, MapBlur::Box { radius_texels: 1 }, false);
        let at = |x: usize, r: usize| m.levels[0].moments[r * 5 + x];
        let mean = (8.0 + 0.5) / 9.0;
        let second = (8.0 + 0.25) / 9.0;
        for (x, r) in [(1, 1), (2, 2), (3, 1), (3, 3)] {
            assert!((at(x, r)[0] - mean).abs() < 1e-6 && (at(x, r)[1] - second).abs() < 1e-6);
        }
        assert_eq!(at(0, 0), [1.0, 1.0, 0.0, 0.0]);
        // Clamped at the edge: the corner texel of a map with a dark left column sees it 3 times
        // of 9 along each row (twice through the repeat).
        let base = layer(4, |x, _| if x == 0 { 0.0 } else { 1.0 });
        let m = MomentLayer::from_depth(&base, MomentWarp::Depth2, MapBlur::Box { radius_texels: 1 }, false);
        assert!((m.levels[0].moments[0][0] - 1.0 / 3.0).abs() < 1e-6, "{:?}", m.levels[0].moments[0]);
    }

    #[test]
    fn gaussian_weights_are_normalised_and_symmetric() {
        let w = MapBlur::Gaussian { radius_texels: 4 }.weights();
        assert_eq!(w.len(), 9);
        assert!((w.iter().sum::<f32>() - 1.0).abs() < 1e-6);
        assert_eq!(w[0], w[8]);
        // σ = 2: the centre over the end is e^{16/8} = e².
        assert!((w[4] / w[0] - std::f32::consts::E.powi(2)).abs() < 1e-4);
    }

    #[test]
    fn trilinear_reads_blend_the_two_levels_around_the_level_of_detail() {
        // Texel (x, r) of a 4² map holds 4r + x: level 1 holds the 2×2 means, level 2 their mean.
        let base = layer(4, |x, r| (4 * r + x) as f32 / 16.0);
        let m = MomentLayer::from_depth(&base, MomentWarp::Depth2, MapBlur::None, true);
        assert_eq!(m.levels.iter().map(|l| l.resolution).collect::<Vec<_>>(), [4, 2, 1]);
        // The centre of level 1's top-left texel, (¼, ¾): level 0 there is the mean of texels
        // 0, 1, 4, 5 by bilinear weights ¼ each, as level 1 is.
        let (u, v) = (0.25, 0.75);
        let at = |lod| m.sample_at_lod(u, v, lod)[0];
        assert_eq!(at(-3.0), m.levels[0].sample(u, v)[0]);
        assert_eq!(at(1.0), 2.5 / 16.0);
        assert_eq!(at(2.0), 7.5 / 16.0);
        assert_eq!(at(9.0), 7.5 / 16.0);
        assert_eq!(at(f32::NAN), 7.5 / 16.0);
        assert!((at(1.25) - (0.75 * 2.5 + 0.25 * 7.5) / 16.0).abs() < 1e-7);
        // Memory counts every level: (16 + 4 + 1) texels of two f32s.
        assert_eq!(m.memory_bytes(), 21 * 8);
        let flat = MomentLayer::from_depth(&base, MomentWarp::Depth2, MapBlur::None, false);
        assert_eq!((flat.levels.len(), flat.memory_bytes()), (1, 16 * 8));
    }

    #[test]
    fn the_level_of_detail_is_the_longer_footprint_in_texels() {
        let texels = |n: f32| n / 256.0;
        assert_eq!(level_of_detail(256, [texels(1.0), 0.0], [0.0, texels(0.5)]), 0.0);
        assert_eq!(level_of_detail(256, [texels(3.0), texels(4.0)], [0.0, texels(2.0)]), 5f32.log2());
        assert_eq!(level_of_detail(256, [0.0; 2], [0.0; 2]), f32::NEG_INFINITY);
        assert_eq!(level_of_detail(256, [f32::NAN, 0.0], [0.0; 2]), f32::INFINITY);
        assert_eq!(level_of_detail(256, [f32::INFINITY, 0.0], [0.0; 2]), f32::INFINITY);
    }

    #[test]
    fn warps_store_the_papers_moments() {
        let z = 0.3f32;
        let z2 = z * z;
        assert_eq!(MomentWarp::Power4.moments(z), [z, z2, z2 * z, z2 * z2]);
        let esm = MomentWarp::Exponential { exponent: 80.0 }.moments(z)[0] as f64;
        assert!((esm / 24f64.exp() - 1.0).abs() < 1e-5, "{esm}");
        let got = MomentWarp::Evsm4 { positive: 40.0, negative: 5.0 }.moments(z);
        // z' = 2z − 1 = −0.4: e^{−16}, e^{−32}, −e^{2}, e^{4} (to f32's rounding of z' and e^x).
        let want = [(-16f64).exp(), (-32f64).exp(), -(2f64).exp(), (4f64).exp()];
        for (g, w) in got.iter().zip(want) {
            assert!(((*g as f64 - w) / w).abs() < 2e-5, "{got:?} vs {want:?}");
        }
    }
}
