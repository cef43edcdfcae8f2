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

use super::clip::{clip_triangle, inside_every_plane};
use super::dual_paraboloid::front_part;
use super::{DepthFormat, DepthLayer, DepthPairLayer, LightView, Projection};
use crate::scene::{Scene, TriangleCursor};
use rayon::prelude::*;

/// Which faces of closed objects are not rasterized (open objects are never culled).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Culling {
    None,
    BackFacesOfClosed,
    FrontFacesOfClosed,
}

/// Which vertices the depth plane of a triangle goes through (docs/conventions.md, "Rasterizer").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum DepthPlane {
    /// The vertices snapped to 1/256 texel, as coverage uses them (the default).
    #[default]
    Snapped,
    /// The unsnapped vertices (after the divide and viewport), as llvmpipe sets the plane up.
    Exact,
}

/// Everything a depth layer depends on besides the scene and the light view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RasterSettings {
    pub format: DepthFormat,
    pub culling: Culling,
    /// glPolygonOffset `factor` (multiplies the depth slope m, in depth units per texel).
    pub slope_factor: f32,
    /// glPolygonOffset `units` (multiplies the format's minimum resolvable difference r).
    pub slope_units: f32,
    /// The vertices the depth plane goes through; coverage always uses the snapped ones.
    pub depth_plane: DepthPlane,
}

impl Default for RasterSettings {
    fn default() -> Self {
        RasterSettings {
            format: DepthFormat::F32,
            culling: Culling::None,
            slope_factor: 0.0,
            slope_units: 0.0,
            depth_plane: DepthPlane::Snapped,
        }
    }
}

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
        Rasterizer { scene, view, bands: bin_by_band(scene, view) }
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
        let mut pairs = vec![[0.0f32; 2]; n * n];
        let format = settings.format;
        self.rasterize_into(
            settings,
            &mut pairs,
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
        DepthPairLayer { resolution: self.view.resolution, depth: pairs }
    }
}

/// Sub-texel precision of snapped vertices: 8 bits, as GPUs.
const SUBTEXEL_BITS: u32 = 8;
const SUBTEXEL: i64 = 1 << SUBTEXEL_BITS;
const HALF_TEXEL: i64 = SUBTEXEL / 2;
/// Rows per parallel band (fixed: it never changes the arithmetic, only the scheduling).
const BAND_ROWS: u32 = 32;
/// Triangles per parallel setup chunk.
const SETUP_CHUNK: u32 = 2048;

/// One screen-space triangle ready for scan conversion.
#[derive(Clone, Copy, Debug)]
struct RasterTriangle {
    /// Snapped vertices in 1/256 texel units (y down), ordered so that the signed area
    /// (x1−x0)(y2−y0) − (x2−x0)(y1−y0) is positive: inside ⇔ every edge function ≥ 0.
    x: [i64; 3],
    y: [i64; 3],
    /// 1 for edges that are not top or left: their own points are outside.
    edge_bias: [i64; 3],
    /// Texel rows and columns whose centres lie in the snapped bounding box, clamped to the map
    /// (inclusive).
    rows: (u32, u32),
    cols: (u32, u32),
    /// Depth at a texel centre (col, row): z0 + dz_dx·(col + col_offset) + dz_dy·(row +
    /// row_offset), where the offsets make (col + col_offset) the distance from vertex 0 in
    /// texels. z0 includes the polygon offset.
    z0: f32,
    dz_dx: f32,
    dz_dy: f32,
    col_offset: f32,
    row_offset: f32,
}

impl RasterTriangle {
    /// Columns [lo, hi] of row `row` whose centres the triangle covers, if any: each edge
    /// function is linear in the column, so its half-plane is a half-line solved exactly in
    /// integers.
    #[inline]
    fn span(&self, row: u32) -> Option<(u32, u32)> {
        let py = row as i64 * SUBTEXEL + HALF_TEXEL;
        let (mut lo, mut hi) = (self.cols.0 as i64, self.cols.1 as i64);
        for i in 0..3 {
            let j = if i == 2 { 0 } else { i + 1 };
            let (dx, dy) = (self.x[j] - self.x[i], self.y[j] - self.y[i]);
            // E(col) = dx·(py − y_i) − dy·(col·256 + 128 − x_i) − bias = k + step·col ≥ 0.
            let k = dx * (py - self.y[i]) - dy * (HALF_TEXEL - self.x[i]) - self.edge_bias[i];
            let step = -dy * SUBTEXEL;
            if step > 0 {
                lo = lo.max(-k.div_euclid(step)); // col ≥ ceil(−k/step) = −floor(k/step)
            } else if step < 0 {
                hi = hi.min(k.div_euclid(-step)); // col ≤ floor(k/−step)
            } else if k < 0 {
                return None;
            }
        }
        (lo <= hi).then_some((lo as u32, hi as u32))
    }

    /// The row's part of the depth plane at the texel centres of `row`:
    /// z0 + dz_dy·(row + row_offset); each texel then adds dz_dx·(col + col_offset).
    #[inline]
    fn depth_row_start(&self, row: u32) -> f32 {
        self.z0 + self.dz_dy * (row as f32 + self.row_offset)
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
                for &id in &bands.triangles[bands.start[band]..bands.start[band + 1]] {
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

/// Scene triangles per band of `BAND_ROWS` rows (CSR: band b owns `triangles[start[b]..start[b + 1]]`),
/// in scene order. A triangle may be listed in a band it turns out not to cover (the bands come
/// from a cheap bound, and culling is left to the bands), never left out of one it covers, so
/// the bins serve every setting.
struct Bands {
    start: Vec<usize>,
    triangles: Vec<u32>,
}

fn bin_by_band(scene: &Scene, view: &LightView) -> Bands {
    let band_count = view.resolution.div_ceil(BAND_ROWS) as usize;
    assert!(band_count < u16::MAX as usize, "a {}² map has too many bands", view.resolution);
    let count = scene.triangle_count() as u32;
    // u16 bands: at most 16384 / 32 of them; at 10M triangles the ranges are the largest block.
    let ranges: Vec<(u16, u16)> = (0..count.div_ceil(SETUP_CHUNK))
        .into_par_iter()
        .flat_map_iter(|chunk| {
            let ids = chunk * SETUP_CHUNK..count.min((chunk + 1) * SETUP_CHUNK);
            let mut scratch = Vec::new();
            // A triangle that `triangles_in` skips (degenerate in world space) covers no band.
            let mut ranges = vec![(0, 0); ids.len()];
            for (id, tri) in scene.triangles_in(ids.clone()) {
                ranges[(id - ids.start) as usize] = band_range(&tri, view, &mut scratch);
            }
            ranges
        })
        .collect();
    let mut start = vec![0usize; band_count + 1];
    for &(lo, hi) in &ranges {
        for b in lo..hi {
            start[b as usize + 1] += 1;
        }
    }
    for b in 0..band_count {
        start[b + 1] += start[b];
    }
    let mut fill = start.clone();
    let mut triangles = vec![0u32; start[band_count]];
    for (index, &(lo, hi)) in ranges.iter().enumerate() {
        for b in lo..hi {
            triangles[fill[b as usize]] = index as u32;
            fill[b as usize] += 1;
        }
    }
    Bands { start, triangles }
}

/// The bands [lo, hi) that a triangle may cover under any setting. Without clipping behind the
/// eye (every w > 0) the rows come from its snapped vertices, widened by a row each way for the
/// rounding of clipped vertices (clipping only shrinks the triangle), and an unclipped triangle
/// whose snapped box holds no texel centre is in no band; otherwise from its full set-up without
/// culling (culling only removes triangles; offsets never move rows).
fn band_range(tri: &[glam::Vec3; 3], view: &LightView, scratch: &mut Vec<RasterTriangle>) -> (u16, u16) {
    let clip = tri.map(|p| view.clip_of(p));
    if !clip.iter().all(|c| c.is_finite()) {
        return (0, 0);
    }
    let paraboloid = view.projection == Projection::Paraboloid;
    let rows = if !paraboloid && clip.iter().all(|c| c.w > 0.0) {
        let n = view.resolution as f32;
        let ys = clip.map(|c| snap((1.0 - (0.5 * c.y * (1.0 / c.w) + 0.5)) * n));
        // A triangle inside every clip plane is set up from exactly these snapped vertices (the
        // set-up's own divide, viewport and snap): when their box holds no texel centre, as for
        // most triangles of a dense mesh at map resolution, it is in no band and never set up.
        if inside_every_plane(&clip, guard_band(view.resolution)) {
            let xs = clip.map(|c| snap((0.5 * c.x * (1.0 / c.w) + 0.5) * n));
            if !centres_in_bounds(&xs, &ys, view.resolution) {
                return (0, 0);
            }
        }
        let lo = ys.iter().min().expect("three") - SUBTEXEL;
        let hi = ys.iter().max().expect("three") + SUBTEXEL;
        centre_range(&[lo, hi], view.resolution).map(|(a, b)| (a as u32, b as u32))
    } else {
        scratch.clear();
        setup_triangle(tri, false, view, &RasterSettings::default(), scratch);
        scratch.iter().map(|t| t.rows).reduce(|a, b| (a.0.min(b.0), a.1.max(b.1)))
    };
    rows.map_or((0, 0), |(first, last)| ((first / BAND_ROWS) as u16, (last / BAND_ROWS + 1) as u16))
}

/// Guard band (in units of w) keeping raster coordinates within ±2^20 texels, so that the
/// fixed-point edge functions (coordinates < 2^28, products < 2^58) cannot overflow i64.
fn guard_band(resolution: u32) -> f32 {
    ((2u64 << 20) as f32 / resolution as f32 - 1.0).max(1.0)
}

/// Appends the raster triangles of world triangle `tri` (none when culled or clipped away,
/// several when clipping made a polygon). A paraboloid's triangle is first cut to its
/// hemisphere, and each triangle of the cut polygon's fan mapped per vertex (`dual_paraboloid.rs`).
fn setup_triangle(
    tri: &[glam::Vec3; 3],
    closed: bool,
    view: &LightView,
    settings: &RasterSettings,
    out: &mut Vec<RasterTriangle>,
) {
    if view.projection == Projection::Paraboloid {
        let (front, len) = front_part(view, tri);
        for k in 1..len.saturating_sub(1) {
            setup_mapped(&[front[0], front[k], front[k + 1]], closed, view, settings, out);
        }
        return;
    }
    setup_mapped(tri, closed, view, settings, out);
}

/// `setup_triangle` of a triangle whose vertices the view maps one by one (`LightView::clip_of`).
fn setup_mapped(
    tri: &[glam::Vec3; 3],
    closed: bool,
    view: &LightView,
    settings: &RasterSettings,
    out: &mut Vec<RasterTriangle>,
) {
    let clip = tri.map(|p| view.clip_of(p));
    if !clip.iter().all(|c| c.is_finite()) {
        return;
    }
    let polygon = clip_triangle(clip, guard_band(view.resolution));
    if polygon.len < 3 {
        return;
    }

    // Divide and viewport in f32 (the same arithmetic as `LightView::project`), then snap.
    let n = view.resolution as f32;
    let mut xs = [0i64; super::clip::MAX_CLIPPED_VERTICES];
    let mut ys = xs;
    let mut zs = [0f32; super::clip::MAX_CLIPPED_VERTICES];
    let mut exact = [(0f32, 0f32); super::clip::MAX_CLIPPED_VERTICES];
    for (i, c) in polygon.as_slice().iter().enumerate() {
        if c.w <= 0.0 {
            return;
        }
        let inv_w = 1.0 / c.w;
        let (u, v) = (0.5 * c.x * inv_w + 0.5, 0.5 * c.y * inv_w + 0.5);
        exact[i] = (u * n, (1.0 - v) * n);
        xs[i] = snap(exact[i].0);
        ys[i] = snap(exact[i].1);
        zs[i] = c.z * inv_w;
    }
    let len = polygon.len;
    // Most triangles of a dense mesh fall between texel centres at low resolutions: reject
    // them before any further set-up.
    if !centres_in_bounds(&xs[..len], &ys[..len], view.resolution) {
        return;
    }

    // Facing from the snapped polygon's signed area (y down): counter-clockwise in (u, v) with
    // v up is negative here; such a face turns its outward normal towards the light.
    let area: i128 = (0..len)
        .map(|i| {
            let j = (i + 1) % len;
            xs[i] as i128 * ys[j] as i128 - xs[j] as i128 * ys[i] as i128
        })
        .sum();
    if area == 0 {
        return;
    }
    let front_facing = area < 0;
    if closed {
        match settings.culling {
            Culling::BackFacesOfClosed if !front_facing => return,
            Culling::FrontFacesOfClosed if front_facing => return,
            _ => {}
        }
    }

    let offset_on = settings.slope_factor != 0.0 || settings.slope_units != 0.0;
    let r = if offset_on {
        let max_z = zs[..len].iter().copied().fold(f32::NEG_INFINITY, f32::max);
        settings.format.min_resolvable_difference(max_z)
    } else {
        0.0
    };
    for k in 1..len - 1 {
        let fan = [0, k, k + 1];
        let vertices = fan.map(|i| RasterVertex { x: xs[i], y: ys[i], z: zs[i], exact: exact[i] });
        if let Some(t) = raster_triangle(vertices, view.resolution, settings, offset_on, r) {
            out.push(t);
        }
    }
}

/// Texels (inclusive range, clamped to the map) whose centre c·256 + 128 lies between the
/// smallest and largest of the snapped `coordinates`; None when there are none.
#[inline]
fn centre_range(coordinates: &[i64], resolution: u32) -> Option<(i64, i64)> {
    let lo = *coordinates.iter().min()?;
    let hi = *coordinates.iter().max()?;
    let first = (lo - HALF_TEXEL + SUBTEXEL - 1).div_euclid(SUBTEXEL).max(0);
    let last = (hi - HALF_TEXEL).div_euclid(SUBTEXEL).min(resolution as i64 - 1);
    (first <= last).then_some((first, last))
}

/// Whether the bounding box of a snapped polygon holds any texel centre of the map.
#[inline]
fn centres_in_bounds(xs: &[i64], ys: &[i64], resolution: u32) -> bool {
    centre_range(xs, resolution).is_some() && centre_range(ys, resolution).is_some()
}

/// Raster coordinate in 1/256 texel units, rounded to nearest. Coordinates are bounded by the
/// guard band (|t| < 2^29), so the conversion cannot saturate.
#[inline]
fn snap(coordinate: f32) -> i64 {
    // Round half away from zero, as f32::round, but exact and inline: the f64 sum cannot round
    // (|t| < 2^29) and the cast truncates towards zero.
    let t = (coordinate * SUBTEXEL as f32) as f64;
    (t + 0.5f64.copysign(t)) as i64
}

/// A vertex after the viewport: snapped (x, y) in 1/256 texels, z/w, and the unsnapped raster
/// position in texels.
#[derive(Clone, Copy, Debug)]
struct RasterVertex {
    x: i64,
    y: i64,
    z: f32,
    exact: (f32, f32),
}

/// Set-up of one snapped triangle: orientation, fill-rule biases, bounding box, depth plane and
/// polygon offset. None when it covers no texel centre.
fn raster_triangle(
    v: [RasterVertex; 3],
    resolution: u32,
    settings: &RasterSettings,
    offset_on: bool,
    r: f32,
) -> Option<RasterTriangle> {
    let area =
        |v: &[RasterVertex; 3]| (v[1].x - v[0].x) * (v[2].y - v[0].y) - (v[2].x - v[0].x) * (v[1].y - v[0].y);
    let mut v = v;
    let a = area(&v);
    if a == 0 {
        return None;
    }
    if a < 0 {
        v.swap(1, 2);
    }
    let x = v.map(|p| p.x);
    let y = v.map(|p| p.y);

    // Top-left rule (D3D) in y-down space for this (clockwise on screen) winding: a top edge is
    // horizontal and runs in +x, a left edge runs upwards (−y).
    let edge_bias = std::array::from_fn(|i| {
        let j = (i + 1) % 3;
        let (dx, dy) = (x[j] - x[i], y[j] - y[i]);
        let top_left = dy < 0 || (dy == 0 && dx > 0);
        if top_left { 0 } else { 1 }
    });

    let (cols, rows) = (centre_range(&x, resolution)?, centre_range(&y, resolution)?);

    let (dz_dx, dz_dy, col_offset, row_offset) = depth_plane(&v, settings.depth_plane, a)?;
    // Polygon offset: m = |∇z| in depth units per texel, constant over the triangle (the fan
    // pieces of a clipped polygon are coplanar: equal m up to rounding), r from the polygon's
    // largest vertex depth. Added to the vertex depth before interpolation, as D3D specifies.
    let offset = if offset_on {
        settings.slope_factor * (dz_dx * dz_dx + dz_dy * dz_dy).sqrt() + settings.slope_units * r
    } else {
        0.0
    };
    Some(RasterTriangle {
        x,
        y,
        edge_bias,
        rows: (rows.0 as u32, rows.1 as u32),
        cols: (cols.0 as u32, cols.1 as u32),
        z0: v[0].z + offset,
        dz_dx,
        dz_dy,
        col_offset,
        row_offset,
    })
}

/// The depth plane of a triangle in f32, as a GPU's setup, in texel units: (∂z/∂x, ∂z/∂y) and
/// the offsets that make a texel index the distance from vertex 0 (`RasterTriangle::col_offset`). `area` is the
/// snapped triangle's doubled area in 1/256² texels (positive). None when the plane is not
/// finite.
fn depth_plane(v: &[RasterVertex; 3], plane: DepthPlane, area: i64) -> Option<(f32, f32, f32, f32)> {
    let texels = |d: i64| d as f32 / SUBTEXEL as f32;
    let (dz1, dz2) = (v[1].z - v[0].z, v[2].z - v[0].z);
    let (dx1, dy1, dx2, dy2, det, (col_offset, row_offset)) = match plane {
        DepthPlane::Snapped => {
            let (dx1, dy1) = (texels(v[1].x - v[0].x), texels(v[1].y - v[0].y));
            let (dx2, dy2) = (texels(v[2].x - v[0].x), texels(v[2].y - v[0].y));
            // Twice the area from the exact integer area: never rounds to zero for a sliver.
            let det = area.abs() as f32 / (SUBTEXEL * SUBTEXEL) as f32;
            let offsets = (texels(HALF_TEXEL - v[0].x), texels(HALF_TEXEL - v[0].y));
            (dx1, dy1, dx2, dy2, det, offsets)
        }
        DepthPlane::Exact => {
            let e = v.map(|p| p.exact);
            let (dx1, dy1) = (e[1].0 - e[0].0, e[1].1 - e[0].1);
            let (dx2, dy2) = (e[2].0 - e[0].0, e[2].1 - e[0].1);
            let det = dx1 * dy2 - dx2 * dy1;
            // A sliver whose unsnapped area is zero, or turned over by snapping, has no usable
            // exact plane: coverage comes from the snapped vertices, and so does its plane.
            let snapped_cross = (v[1].x - v[0].x) as i128 * (v[2].y - v[0].y) as i128
                - (v[2].x - v[0].x) as i128 * (v[1].y - v[0].y) as i128;
            if !(det.is_finite() && det != 0.0 && (det > 0.0) == (snapped_cross > 0)) {
                return depth_plane(v, DepthPlane::Snapped, area);
            }
            (dx1, dy1, dx2, dy2, det, (0.5 - e[0].0, 0.5 - e[0].1))
        }
    };
    let dz_dx = (dz1 * dy2 - dz2 * dy1) / det;
    let dz_dy = (dx1 * dz2 - dx2 * dz1) / det;
    if !(dz_dx.is_finite() && dz_dy.is_finite()) {
        return match plane {
            DepthPlane::Exact => depth_plane(v, DepthPlane::Snapped, area),
            DepthPlane::Snapped => None,
        };
    }
    Some((dz_dx, dz_dy, col_offset, row_offset))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri(points: [(f32, f32); 3]) -> RasterTriangle {
        let v = points.map(|(x, y)| RasterVertex { x: snap(x), y: snap(y), z: 0.5, exact: (x, y) });
        raster_triangle(v, 16, &RasterSettings::default(), false, 0.0).unwrap()
    }

    fn covered(t: &RasterTriangle, col: u32, row: u32) -> bool {
        t.span(row).is_some_and(|(lo, hi)| lo <= col && col <= hi)
    }

    #[test]
    fn top_and_left_edges_own_the_centres_on_them() {
        // Right triangle with its top edge on y = 2.5 and its left edge on x = 2.5 (centres of
        // row 2 and column 2), hypotenuse from (8.5, 2.5) to (2.5, 8.5) through centres.
        for order in [[(2.5, 2.5), (8.5, 2.5), (2.5, 8.5)], [(2.5, 2.5), (2.5, 8.5), (8.5, 2.5)]] {
            let t = tri(order);
            assert!(covered(&t, 2, 2), "top-left corner");
            assert!(covered(&t, 5, 2), "top edge");
            assert!(covered(&t, 2, 5), "left edge");
            assert!(!covered(&t, 5, 5), "on the bottom-right hypotenuse");
            assert!(covered(&t, 4, 5) && covered(&t, 5, 4));
        }
        // Mirror image: bottom edge on y = 8.5 and right edge on x = 8.5 are not owned.
        let t = tri([(8.5, 8.5), (8.5, 2.5), (2.5, 8.5)]);
        assert!(!covered(&t, 5, 8), "bottom edge");
        assert!(!covered(&t, 8, 5), "right edge");
        assert!(covered(&t, 5, 5), "hypotenuse is top-left here");
    }

    #[test]
    fn spans_match_a_brute_force_edge_test() {
        let t = tri([(1.3, 0.7), (14.2, 5.51), (4.9, 15.0)]);
        for row in 0..16u32 {
            for col in 0..16u32 {
                let (px, py) = (col as i64 * SUBTEXEL + HALF_TEXEL, row as i64 * SUBTEXEL + HALF_TEXEL);
                let inside = (0..3).all(|i| {
                    let j = (i + 1) % 3;
                    let e = (t.x[j] - t.x[i]) * (py - t.y[i]) - (t.y[j] - t.y[i]) * (px - t.x[i]);
                    e - t.edge_bias[i] >= 0
                });
                assert_eq!(covered(&t, col, row), inside, "{col} {row}");
            }
        }
    }
}
