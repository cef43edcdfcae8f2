//! The depths of a multiple-depth shadow map (Pagot, Comba & Oliveira, "Multiple-Depth Shadow
//! Maps", SIBGRAPI 2004): n depths per texel, the base map's own depth plus n − 1 chosen from the
//! minimum and/or maximum over square neighbourhoods of the base map around the texel. The test
//! that reads them (the n-shadow test) is in `technique::pcf`.
//!
//! Which extra depths, in order (our reading of the paper's min/max selection, with growing
//! neighbourhoods when more depths are asked for than one q×q window gives):
//! `max`: max over q×q, (q+2)², (q+4)²; `min`: likewise with min; `min_max`: max over q×q, min
//! over q×q, max over (q+2)². Texels beyond the edge repeat the edge (clamp to edge).

use super::DepthLayer;
use rayon::prelude::*;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DepthSelection {
    Min,
    Max,
    MinMax,
}

/// n depths per texel, interleaved (texel-major), same texel layout as `DepthLayer`.
#[derive(Clone, Debug, PartialEq)]
pub struct MultiDepthLayer {
    pub resolution: u32,
    pub depths_per_texel: u32,
    pub depth: Vec<f32>,
}

/// Most depths per texel of a multiple-depth map.
pub const MAX_DEPTHS_PER_TEXEL: u32 = 4;

impl MultiDepthLayer {
    /// The n-SM of `base` with `n` depths (1 to [`MAX_DEPTHS_PER_TEXEL`]), extra depths selected over `neighbourhood`²
    /// texels (odd, ≥ 1) and larger windows as described in the module notes.
    pub fn from_base(base: &DepthLayer, n: u32, neighbourhood: u32, selection: DepthSelection) -> Self {
        let res = base.resolution as usize;
        let n = n.clamp(1, MAX_DEPTHS_PER_TEXEL) as usize;
        let mut depth = vec![0.0f32; res * res * n];
        let r0 = (neighbourhood.max(1) / 2) as usize;
        let extra: Vec<(bool, usize)> = (1..n)
            .map(|i| match selection {
                DepthSelection::Max => (true, r0 + (i - 1)),
                DepthSelection::Min => (false, r0 + (i - 1)),
                DepthSelection::MinMax => (i % 2 == 1, r0 + (i - 1) / 2),
            })
            .collect();
        let filtered: Vec<Vec<f32>> =
            extra.par_iter().map(|&(is_max, radius)| window_extreme(base, radius, is_max)).collect();
        depth.par_chunks_mut(n).enumerate().for_each(|(t, out)| {
            out[0] = base.depth[t];
            for (o, f) in out[1..].iter_mut().zip(&filtered) {
                *o = f[t];
            }
        });
        MultiDepthLayer { resolution: base.resolution, depths_per_texel: n as u32, depth }
    }

    /// The depths of texel (x, row).
    #[inline]
    pub fn at(&self, x: u32, row: u32) -> &[f32] {
        let n = self.depths_per_texel as usize;
        let t = row as usize * self.resolution as usize + x as usize;
        &self.depth[t * n..t * n + n]
    }

    pub fn memory_bytes(&self) -> usize {
        self.depth.len() * std::mem::size_of::<f32>()
    }
}

/// The max (or min) over the (2·radius + 1)² window around every texel, separably (rows, then
/// columns), clamped to the edge.
fn window_extreme(base: &DepthLayer, radius: usize, is_max: bool) -> Vec<f32> {
    let res = base.resolution as usize;
    let pick = |a: f32, b: f32| if is_max { a.max(b) } else { a.min(b) };
    let mut rows = vec![0.0f32; res * res];
    rows.par_chunks_mut(res).zip(base.depth.par_chunks(res)).for_each(|(out, src)| {
        for (x, o) in out.iter_mut().enumerate() {
            let (lo, hi) = (x.saturating_sub(radius), (x + radius).min(res - 1));
            *o = src[lo..=hi].iter().copied().reduce(pick).expect("non-empty window");
        }
    });
    let mut out = vec![0.0f32; res * res];
    out.par_chunks_mut(res).enumerate().for_each(|(y, o_row)| {
        let (lo, hi) = (y.saturating_sub(radius), (y + radius).min(res - 1));
        o_row.copy_from_slice(&rows[lo * res..lo * res + res]);
        for yy in lo + 1..=hi {
            for (o, &v) in o_row.iter_mut().zip(&rows[yy * res..yy * res + res]) {
                *o = pick(*o, v);
            }
        }
    });
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extra_depths_are_window_extremes() {
        // 4×4 base with one near texel (0.2) at (1, 1) and one far texel (0.9) at (3, 3).
        let mut base = DepthLayer { resolution: 4, depth: vec![0.5; 16] };
        base.depth[5] = 0.2;
        base.depth[15] = 0.9;
        let m = MultiDepthLayer::from_base(&base, 3, 3, DepthSelection::MinMax);
        assert_eq!(m.depths_per_texel, 3);
        // Texel (0, 0): its own 0.5, max over 3×3 (clamped) 0.5, min 0.2.
        assert_eq!(m.at(0, 0), &[0.5, 0.5, 0.2]);
        // Texel (2, 2): own 0.5, max 0.9 (from (3, 3)), min 0.2 (from (1, 1)).
        assert_eq!(m.at(2, 2), &[0.5, 0.9, 0.2]);
        // Texel (0, 3): window x 0..=1, rows 2..=3: no extreme texel in it.
        assert_eq!(m.at(0, 3), &[0.5, 0.5, 0.5]);
        let one = MultiDepthLayer::from_base(&base, 1, 3, DepthSelection::Max);
        assert_eq!(one.depth, base.depth);
        // Max selection widens the window: 3×3, 5×5, then 7×7 reaches (3, 3) from (0, 0).
        let four = MultiDepthLayer::from_base(&base, 4, 3, DepthSelection::Max);
        assert_eq!(four.at(0, 0), &[0.5, 0.5, 0.5, 0.9]);
    }
}
