//! The CPU depth rasterizer: texel centres, top-left fill rule, depth linear in screen space,
//! f32 arithmetic, near-plane clipping, per-object back-face culling of closed objects.
//!
//! The pipeline of a GPU (D3D11 / Vulkan rules):
//! 1. vertex: clip = clip_from_world · p in f32 (a dual paraboloid's hemisphere: the triangle
//!    cut to the hemisphere, then each vertex mapped to its disk, `dual_paraboloid.rs`);
//! 2. clip against the depth range 0 ≤ z ≤ w (near and far planes, so no texel gets a depth
//!    outside [0, 1] and nothing behind a spot light wraps) and an x/y guard band far outside
//!    the map (`clip.rs`); fan-triangulate the clipped polygon;
//! 3. divide, viewport (raster x = u·N, y = (1 − v)·N, y down) in f32, then snap to a 1/256
//!    texel fixed-point grid (8 sub-texel bits, as GPUs);
//! 4. coverage of texel centres by exact integer (i64) edge functions with the top-left fill
//!    rule: shared edges are covered exactly once, whatever the band split or thread count;
//! 5. depth: the z/w plane through the snapped vertices, evaluated in f32 at the texel centre,
//!    plus the polygon offset factor·m + units·r, clamped to [0, 1]; the nearest depth wins and
//!    is stored in the depth format.
//!
//! Work is split into horizontal bands of rows rasterized in parallel, each band owning its
//! slice of the map. Every texel's value is computed from the triangle alone (no incremental
//! state crossing rows), so the split never changes the result.

use super::bands::{BAND_ROWS, Bands};
use super::setup::setup_triangle;
use super::{DepthFormat, DepthLayer, DepthPairLayer, LightView, RasterSettings};
use crate::scene::{Scene, TriangleCursor};
use rayon::prelude::*;

/// The nearest depth per texel of every (non-culled) triangle.
pub fn rasterize_nearest(scene: &Scene, view: &LightView, settings: &RasterSettings) -> DepthLayer {
    Rasterizer::new(scene, view).nearest(settings)
}

/// `rasterize_nearest` into an existing layer, reusing its allocation (at 4096², the first touch
/// of a fresh 64 MiB buffer costs about as much as rasterizing a 10k-triangle scene).
pub fn rasterize_nearest_into(
    scene: &Scene,
    view: &LightView,
    settings: &RasterSettings,
    layer: &mut DepthLayer,
) {
    Rasterizer::new(scene, view).nearest_into(settings, layer);
}

/// The two nearest distinct depths per texel (see [`Rasterizer::two_nearest`]).
pub fn rasterize_two_nearest(scene: &Scene, view: &LightView, settings: &RasterSettings) -> DepthPairLayer {
    Rasterizer::new(scene, view).two_nearest(settings)
}

/// How many times each texel (row-major, row 0 at the top) is covered by a rasterized
/// triangle: the coverage path of `rasterize_nearest`, for testing the fill rule.
#[doc(hidden)]
pub fn rasterize_coverage(scene: &Scene, view: &LightView, settings: &RasterSettings) -> Vec<u32> {
    let n = view.resolution as usize;
    let mut count = vec![0u32; n * n];
    Rasterizer::new(scene, view).rasterize_into(settings, &mut count, |_| {}, |count, _| *count += 1, |_| {});
    count
}

/// A scene seen from one light view, its triangles binned by band of rows once: every layer
/// rasterized from the view (any culling, offset or format) reuses the bins.
pub struct Rasterizer<'a> {
    scene: &'a Scene,
    view: &'a LightView,
    bands: Bands,
}

impl<'a> Rasterizer<'a> {
    pub fn new(scene: &'a Scene, view: &'a LightView) -> Self {
        Rasterizer { scene, view, bands: Bands::new(scene, view) }
    }

    /// The nearest depth per texel of every (non-culled) triangle.
    pub fn nearest(&self, settings: &RasterSettings) -> DepthLayer {
        let n = self.view.resolution as usize;
        // Zeroed memory comes lazily from the system; each band then initialises its own rows in
        // parallel, while they are in cache.
        let mut layer = DepthLayer { resolution: self.view.resolution, depth: vec![0.0; n * n] };
        self.nearest_into(settings, &mut layer);
        layer
    }

    /// `nearest` into an existing layer, reusing its allocation.
    pub fn nearest_into(&self, settings: &RasterSettings, layer: &mut DepthLayer) {
        let n = self.view.resolution as usize;
        layer.resolution = self.view.resolution;
        layer.depth.resize(n * n, 1.0);
        let format = settings.format;
        self.rasterize_into(
            settings,
            &mut layer.depth,
            |band| band.fill(1.0),
            // Depth clamp after the offset, as for unorm (and Vulkan float) depth buffers;
            // branch-free minimum (a NaN depth never wins) so that the span loop vectorizes.
            |d, z| *d = d.min(z.clamp(0.0, 1.0)),
            |band| {
                if format != DepthFormat::F32 {
                    band.iter_mut().for_each(|d| *d = format.store(*d));
                }
            },
        );
    }

    /// The two nearest distinct depths per texel, (z1, z2) with z1 < z2 — CPU depth peeling: z2
    /// is the nearest fragment strictly behind z1, as a second pass testing `d > z1` would keep.
    /// Texels with fewer surfaces hold the cleared value 1. z1 equals `nearest`'s layer.
    pub fn two_nearest(&self, settings: &RasterSettings) -> DepthPairLayer {
        let n = self.view.resolution as usize;
        // Zeroed memory comes lazily from the system; each band initialises its own rows.
        let mut layer = DepthPairLayer { resolution: self.view.resolution, depth: vec![[0.0f32; 2]; n * n] };
        self.two_nearest_into(settings, &mut layer);
        layer
    }

    /// `two_nearest` into an existing layer, reusing its allocation.
    pub fn two_nearest_into(&self, settings: &RasterSettings, layer: &mut DepthPairLayer) {
        let n = self.view.resolution as usize;
        layer.resolution = self.view.resolution;
        layer.depth.resize(n * n, [1.0, 1.0]);
        let format = settings.format;
        self.rasterize_into(
            settings,
            &mut layer.depth,
            |band| band.fill([1.0, 1.0]),
            // Branch-free, so that the span loop vectorizes: a nearer fragment pushes z1 down to
            // z2; one strictly between them replaces z2; one equal to z1 is the same surface.
            |[z1, z2], z| {
                let z = z.clamp(0.0, 1.0);
                let nearer = z < *z1;
                let between = z > *z1 && z < *z2;
                *z2 = if nearer {
                    *z1
                } else if between {
                    z
                } else {
                    *z2
                };
                *z1 = if nearer { z } else { *z1 };
            },
            |band| {
                if format != DepthFormat::F32 {
                    band.iter_mut().for_each(|p| *p = p.map(|d| format.store(d)));
                }
            },
        );
    }
}

impl Rasterizer<'_> {
    /// Rasterizes every triangle of `scene` into the N×N `buffer` (row-major, row 0 at the top):
    /// per band of rows, `init(rows)`, then `fragment(texel, depth)` for every covered texel
    /// centre, then `finish(rows)`. The common path of the depth and coverage rasterizers.
    fn rasterize_into<T, I, F, R>(
        &self,
        settings: &RasterSettings,
        buffer: &mut [T],
        init: I,
        fragment: F,
        finish: R,
    ) where
        T: Send,
        I: Fn(&mut [T]) + Sync,
        F: Fn(&mut T, f32) + Sync,
        R: Fn(&mut [T]) + Sync,
    {
        let (scene, view, bands) = (self.scene, self.view, &self.bands);
        let n = view.resolution;
        debug_assert_eq!(buffer.len(), n as usize * n as usize);
        if n == 0 {
            return;
        }

        // Each band sets its triangles up again (the same arithmetic as any other band, so the split
        // never changes a texel) instead of holding every set-up triangle of the scene at once: at
        // 10M triangles those would take more memory than the scene.
        buffer.par_chunks_mut(BAND_ROWS as usize * n as usize).enumerate().for_each_init(
            Vec::new,
            |setup, (band, texels)| {
                let first_row = band as u32 * BAND_ROWS;
                let last_row = first_row + (texels.len() / n as usize) as u32 - 1;
                init(texels);
                // A band lists its triangles in id order: the cursor searches once per instance.
                let mut triangles = TriangleCursor::new(scene);
                for &id in bands.band(band) {
                    setup.clear();
                    let (triangle, closed) = triangles.triangle(id);
                    setup_triangle(&triangle, closed, view, settings, setup);
                    for tri in setup.iter() {
                        for row in tri.rows.0.max(first_row)..=tri.rows.1.min(last_row) {
                            let Some((lo, hi)) = tri.span(row) else {
                                continue;
                            };
                            let z_row = tri.depth_row_start(row);
                            let line = &mut texels[(row - first_row) as usize * n as usize..][..n as usize];
                            // i32 → f32 column conversions vectorize; the arithmetic per texel is
                            // `z_row + dz_dx·(col + col_offset)` whatever the span or band.
                            for (col, texel) in (lo as i32..).zip(&mut line[lo as usize..=hi as usize]) {
                                fragment(texel, z_row + tri.dz_dx * (col as f32 + tri.col_offset));
                            }
                        }
                    }
                }
                finish(texels);
            },
        );
    }
}
