//! One level of a filterable map: N×N texels of four moments in `DepthLayer`'s layout, read with
//! bilinear filtering, and the level below it in a mip chain.

use rayon::prelude::*;

#[derive(Clone, Debug, PartialEq)]
pub struct MomentLevel {
    pub resolution: u32,
    pub moments: Vec<[f32; 4]>,
}

impl MomentLevel {
    /// The moments at map coordinates (u, v), bilinearly filtered between the four nearest texel
    /// centres, clamped to the edge (as a linear sampler with clamp-to-edge reads them).
    #[inline]
    pub fn sample(&self, u: f32, v: f32) -> [f32; 4] {
        let n = self.resolution as f32;
        let last = self.resolution as i64 - 1;
        // Texel centres sit at (x + ½)/N; rows run from the top down.
        let (fx, fy) = (u * n - 0.5, (1.0 - v) * n - 0.5);
        let (fx, fy) = (if fx.is_finite() { fx } else { 0.0 }, if fy.is_finite() { fy } else { 0.0 });
        let (x0, y0) = (fx.floor(), fy.floor());
        let (tx, ty) = (fx - x0, fy - y0);
        let clamp = |i: f32| (i as i64).clamp(0, last) as usize;
        let (xa, xb, ya, yb) = (clamp(x0), clamp(x0 + 1.0), clamp(y0), clamp(y0 + 1.0));
        let stride = self.resolution as usize;
        let at = |x: usize, y: usize| self.moments[y * stride + x];
        let top = lerp(at(xa, ya), at(xb, ya), tx);
        let bottom = lerp(at(xa, yb), at(xb, yb), tx);
        lerp(top, bottom, ty)
    }

    /// The next level of a mip chain: ⌊N/2⌋ texels a side (at least 1), each the mean of the 2×2
    /// texels it covers, the box filter `glGenerateMipmap` and D3D's `GenerateMips` apply. Of an
    /// odd side the last row and column are left out, as that filter's ⌊N/2⌋ rounding does.
    pub fn halved(&self) -> MomentLevel {
        let n = self.resolution as usize;
        let half = (n / 2).max(1);
        let last = n - 1;
        let mut moments = vec![[0.0f32; 4]; half * half];
        moments.par_chunks_mut(half).enumerate().for_each(|(y, row)| {
            let (ya, yb) = ((2 * y).min(last), (2 * y + 1).min(last));
            for (x, out) in row.iter_mut().enumerate() {
                let (xa, xb) = ((2 * x).min(last), (2 * x + 1).min(last));
                let [a, b, c, d] =
                    [(xa, ya), (xb, ya), (xa, yb), (xb, yb)].map(|(x, y)| self.moments[y * n + x]);
                *out = std::array::from_fn(|k| 0.25 * ((a[k] + b[k]) + (c[k] + d[k])));
            }
        });
        MomentLevel { resolution: half as u32, moments }
    }
}

#[inline]
pub(super) fn lerp(a: [f32; 4], b: [f32; 4], t: f32) -> [f32; 4] {
    std::array::from_fn(|c| a[c] + t * (b[c] - a[c]))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn level(n: u32, value: impl Fn(u32, u32) -> f32) -> MomentLevel {
        let moments =
            (0..n).flat_map(|row| (0..n).map(move |x| (x, row))).map(|(x, r)| [value(x, r), 0.0, 0.0, 0.0]);
        MomentLevel { resolution: n, moments: moments.collect() }
    }

    #[test]
    fn halving_averages_each_two_by_two_block() {
        // Texel (x, r) holds 4r + x: the 2×2 means are 2.5, 4.5, 10.5, 12.5, and their mean 7.5.
        let l = level(4, |x, r| (4 * r + x) as f32);
        let half = l.halved();
        assert_eq!(half.resolution, 2);
        let got: Vec<f32> = half.moments.iter().map(|m| m[0]).collect();
        assert_eq!(got, [2.5, 4.5, 10.5, 12.5]);
        assert_eq!(half.halved().moments, vec![[7.5, 0.0, 0.0, 0.0]]);
        // An odd side: 3 → 1, its last row and column left out.
        let odd = level(3, |x, r| (3 * r + x) as f32).halved();
        assert_eq!(odd.moments, vec![[(0.0 + 1.0 + 3.0 + 4.0) / 4.0, 0.0, 0.0, 0.0]]);
        assert_eq!(level(1, |_, _| 2.0).halved().moments, vec![[2.0, 0.0, 0.0, 0.0]]);
    }

    #[test]
    fn bilinear_sampling_interpolates_between_texel_centres() {
        let (left, right) = ([0.2, 0.04, 0.0, 0.0], [0.6, 0.36, 0.0, 0.0]);
        let l = MomentLevel { resolution: 2, moments: vec![left, right, left, right] };
        // At a texel centre the texel itself; halfway between the two centres their mean; past
        // the last centre the edge texel.
        assert_eq!(l.sample(0.25, 0.75)[0], 0.2);
        assert!((l.sample(0.5, 0.5)[0] - 0.4).abs() < 1e-6);
        assert!((l.sample(0.5, 0.5)[1] - 0.5 * (0.04 + 0.36)).abs() < 1e-6);
        assert_eq!(l.sample(0.99, 0.1)[0], 0.6);
        assert_eq!(l.sample(-3.0, 7.0)[0], 0.2);
        assert_eq!(l.sample(f32::NAN, 0.5)[0], 0.2);
    }
}
