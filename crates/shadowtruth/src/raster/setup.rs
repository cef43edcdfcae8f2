//! Triangle set-up, as a GPU's: clip, divide and viewport in f32, snap to 1/256 texel, then the
//! fill-rule edges, the texel box and the depth plane of each triangle (the pipeline in
//! `rasterize.rs`). Shared by the binning (`bands.rs`) and the scan conversion.

use super::clip::{MAX_CLIPPED_VERTICES, clip_triangle, inside_every_plane};
use super::dual_paraboloid::front_part;
use super::{Culling, DepthPlane, LightView, Projection, RasterSettings};

/// Sub-texel precision of snapped vertices: 8 bits, as GPUs.
const SUBTEXEL_BITS: u32 = 8;
pub(super) const SUBTEXEL: i64 = 1 << SUBTEXEL_BITS;
pub(super) const HALF_TEXEL: i64 = SUBTEXEL / 2;
/// Widest texel box (in columns, less one) whose spans are found by testing each centre.
const NARROW_COLUMNS: i64 = 4;

/// One screen-space triangle ready for scan conversion.
#[derive(Clone, Copy, Debug)]
pub(super) struct RasterTriangle {
    /// Snapped vertices in 1/256 texel units (y down), ordered so that the signed area
    /// (x1−x0)(y2−y0) − (x2−x0)(y1−y0) is positive: inside ⇔ every edge function ≥ 0.
    x: [i64; 3],
    y: [i64; 3],
    /// 1 for edges that are not top or left: their own points are outside.
    edge_bias: [i64; 3],
    /// Texel rows and columns whose centres lie in the snapped bounding box, clamped to the map
    /// (inclusive).
    pub(super) rows: (u32, u32),
    cols: (u32, u32),
    /// Depth at a texel centre (col, row): z0 + dz_dx·(col + col_offset) + dz_dy·(row +
    /// row_offset), where the offsets make (col + col_offset) the distance from vertex 0 in
    /// texels. z0 includes the polygon offset.
    z0: f32,
    pub(super) dz_dx: f32,
    dz_dy: f32,
    pub(super) col_offset: f32,
    row_offset: f32,
}

impl RasterTriangle {
    /// Columns [lo, hi] of row `row` whose centres the triangle covers, if any: each edge
    /// function is linear in the column, so its half-plane is a half-line solved exactly in
    /// integers. A box up to `NARROW_COLUMNS` wide (most triangles of a dense mesh) has its
    /// centres tested one by one instead, which needs no division: the same inequalities, and
    /// a convex triangle's covered centres in a row are contiguous.
    #[inline]
    pub(super) fn span(&self, row: u32) -> Option<(u32, u32)> {
        let py = row as i64 * SUBTEXEL + HALF_TEXEL;
        // E(col) = dx·(py − y_i) − dy·(col·256 + 128 − x_i) − bias = k + step·col ≥ 0.
        let edges: [(i64, i64); 3] = std::array::from_fn(|i| {
            let j = if i == 2 { 0 } else { i + 1 };
            let (dx, dy) = (self.x[j] - self.x[i], self.y[j] - self.y[i]);
            (dx * (py - self.y[i]) - dy * (HALF_TEXEL - self.x[i]) - self.edge_bias[i], -dy * SUBTEXEL)
        });
        let (mut lo, mut hi) = (self.cols.0 as i64, self.cols.1 as i64);
        if hi - lo < NARROW_COLUMNS {
            let inside = |col: i64| edges.iter().all(|&(k, step)| k + step * col >= 0);
            while lo <= hi && !inside(lo) {
                lo += 1;
            }
            while hi > lo && !inside(hi) {
                hi -= 1;
            }
            return (lo <= hi).then_some((lo as u32, hi as u32));
        }
        for (k, step) in edges {
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
    pub(super) fn depth_row_start(&self, row: u32) -> f32 {
        self.z0 + self.dz_dy * (row as f32 + self.row_offset)
    }
}

/// Guard band (in units of w) keeping raster coordinates within ±2^20 texels, so that the
/// fixed-point edge functions (coordinates < 2^28, products < 2^58) cannot overflow i64.
pub(super) fn guard_band(resolution: u32) -> f32 {
    ((2u64 << 20) as f32 / resolution as f32 - 1.0).max(1.0)
}

/// Appends the raster triangles of world triangle `tri` (none when culled or clipped away,
/// several when clipping made a polygon). A paraboloid's triangle is first cut to its
/// hemisphere, and each triangle of the cut polygon's fan mapped per vertex (`dual_paraboloid.rs`).
pub(super) fn setup_triangle(
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
    let guard = guard_band(view.resolution);
    // Inside every plane (nearly every triangle), the clipper would return the triangle itself:
    // set it up directly, without the polygon.
    if inside_every_plane(&clip, guard) {
        setup_polygon(&clip, closed, view, settings, out);
        return;
    }
    let polygon = clip_triangle(clip, guard);
    if polygon.len >= 3 {
        setup_polygon(polygon.as_slice(), closed, view, settings, out);
    }
}

/// Appends the raster triangles of the convex clip-space `polygon` (inside every clip plane).
#[inline(always)]
fn setup_polygon(
    polygon: &[glam::Vec4],
    closed: bool,
    view: &LightView,
    settings: &RasterSettings,
    out: &mut Vec<RasterTriangle>,
) {
    // Divide and viewport in f32 (the same arithmetic as `LightView::project`), then snap.
    let n = view.resolution as f32;
    let mut xs = [0i64; MAX_CLIPPED_VERTICES];
    let mut ys = xs;
    let mut zs = [0f32; MAX_CLIPPED_VERTICES];
    let mut exact = [(0f32, 0f32); MAX_CLIPPED_VERTICES];
    for (i, c) in polygon.iter().enumerate() {
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
    let len = polygon.len();
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
pub(super) fn centre_range(coordinates: &[i64], resolution: u32) -> Option<(i64, i64)> {
    centres_between(*coordinates.iter().min()?, *coordinates.iter().max()?, resolution)
}

/// Texels (inclusive range, clamped to the map) whose centre c·256 + 128 lies in [lo, hi]
/// (snapped units). Shifts divide by 256 rounding down, as `div_euclid`, without a division:
/// this runs for every triangle of the scene.
#[inline(always)]
pub(super) fn centres_between(lo: i64, hi: i64, resolution: u32) -> Option<(i64, i64)> {
    let first = ((lo - HALF_TEXEL + SUBTEXEL - 1) >> SUBTEXEL_BITS).max(0);
    let last = ((hi - HALF_TEXEL) >> SUBTEXEL_BITS).min(resolution as i64 - 1);
    (first <= last).then_some((first, last))
}

/// Whether the bounding box of a snapped polygon holds any texel centre of the map.
#[inline]
pub(super) fn centres_in_bounds(xs: &[i64], ys: &[i64], resolution: u32) -> bool {
    centre_range(xs, resolution).is_some() && centre_range(ys, resolution).is_some()
}

/// Raster coordinate in 1/256 texel units, rounded to nearest. Coordinates are bounded by the
/// guard band (|t| < 2^29), so the conversion cannot saturate.
#[inline]
pub(super) fn snap(coordinate: f32) -> i64 {
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
        // A wide triangle (spans solved by division) and narrow ones (centres tested one by one),
        // with edges through centres.
        for points in [
            [(1.3, 0.7), (14.2, 5.51), (4.9, 15.0)],
            [(2.5, 1.5), (5.5, 2.5), (3.5, 9.5)],
            [(6.2, 3.0), (4.1, 11.7), (8.9, 6.6)],
            [(7.5, 7.5), (7.5, 8.5), (8.5, 7.5)],
        ] {
            spans_match_brute_force(&tri(points));
        }
    }

    fn spans_match_brute_force(t: &RasterTriangle) {
        for row in 0..16u32 {
            for col in 0..16u32 {
                let (px, py) = (col as i64 * SUBTEXEL + HALF_TEXEL, row as i64 * SUBTEXEL + HALF_TEXEL);
                let inside = (0..3).all(|i| {
                    let j = (i + 1) % 3;
                    let e = (t.x[j] - t.x[i]) * (py - t.y[i]) - (t.y[j] - t.y[i]) * (px - t.x[i]);
                    e - t.edge_bias[i] >= 0
                });
                assert_eq!(covered(t, col, row), inside, "{col} {row}");
            }
        }
    }
}
