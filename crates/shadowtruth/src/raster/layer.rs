//! A depth layer: one depth per shadow-map texel, rows from the top (largest v) down.

/// N×N depths in [0, 1]; empty texels hold 1.0. Texel (x, row) covers u ∈ [x/N, (x+1)/N) and
/// v ∈ [1 − (row+1)/N, 1 − row/N): rows run from the top of the map (largest v) down, as in the
/// y-down raster space x = u·N, y = (1 − v)·N.
#[derive(Clone, Debug, PartialEq)]
pub struct DepthLayer {
    pub resolution: u32,
    pub depth: Vec<f32>,
}

impl DepthLayer {
    pub fn new_empty(resolution: u32) -> Self {
        DepthLayer { resolution, depth: vec![1.0; resolution as usize * resolution as usize] }
    }

    /// Depth of texel (x, row); both must be < resolution.
    #[inline]
    pub fn at(&self, x: u32, row: u32) -> f32 {
        self.depth[row as usize * self.resolution as usize + x as usize]
    }

    /// The texel containing map coordinates (u, v), or None outside [0, 1)².
    #[inline]
    pub fn texel_of(&self, u: f32, v: f32) -> Option<(u32, u32)> {
        let n = self.resolution as f32;
        let x = (u * n).floor();
        let y = ((1.0 - v) * n).floor();
        if x >= 0.0 && y >= 0.0 && x < n && y < n { Some((x as u32, y as u32)) } else { None }
    }

    /// Bytes of depth data.
    pub fn memory_bytes(&self) -> usize {
        self.depth.len() * std::mem::size_of::<f32>()
    }
}

/// The two nearest distinct depths (z1, z2) per texel, interleaved so that a lookup reads both
/// from one cache line. Same texel layout as `DepthLayer`; empty entries hold 1.0.
#[derive(Clone, Debug, PartialEq)]
pub struct DepthPairLayer {
    pub resolution: u32,
    pub depth: Vec<[f32; 2]>,
}

impl DepthPairLayer {
    /// (z1, z2) of texel (x, row); both must be < resolution.
    #[inline]
    pub fn at(&self, x: u32, row: u32) -> [f32; 2] {
        self.depth[row as usize * self.resolution as usize + x as usize]
    }

    /// Bytes of depth data.
    pub fn memory_bytes(&self) -> usize {
        self.depth.len() * std::mem::size_of::<[f32; 2]>()
    }
}
