//! Homogeneous clipping of a triangle against the depth range (0 ≤ z ≤ w) and an x/y guard
//! band (|x|, |y| ≤ g·w), before the perspective divide, as a GPU's clipper does.
//!
//! Clipping at z ≥ 0 also keeps w > 0 for a perspective light (z ≥ 0 ⇔ D ≥ near > 0), so a
//! triangle crossing the light's plane is cut instead of wrapping through infinity. The guard
//! band only bounds the screen coordinates (so that fixed-point edge functions cannot overflow);
//! it lies far outside the map and does not change coverage inside it.

use glam::Vec4;

/// Each of the 6 planes adds at most one vertex to a convex polygon.
pub(crate) const MAX_CLIPPED_VERTICES: usize = 3 + 6;

/// A convex polygon in clip space, in the winding of the input triangle.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ClippedPolygon {
    pub len: usize,
    pub vertices: [Vec4; MAX_CLIPPED_VERTICES],
}

impl ClippedPolygon {
    pub fn as_slice(&self) -> &[Vec4] {
        &self.vertices[..self.len]
    }
}

/// Signed distance of `p` to clip plane `plane` (≥ 0 inside), guard band `guard`.
#[inline]
fn distance(p: Vec4, plane: usize, guard: f32) -> f32 {
    match plane {
        0 => p.z,               // near: d ≥ 0
        1 => p.w - p.z,         // far: d ≤ 1
        2 => guard * p.w - p.x, // x ≤ g·w
        3 => guard * p.w + p.x, // x ≥ −g·w
        4 => guard * p.w - p.y,
        _ => guard * p.w + p.y,
    }
}

/// Bit i set when `p` is outside plane i (same planes and tests as `distance`).
#[inline]
pub(crate) fn outcode(p: Vec4, guard: f32) -> u8 {
    let g = guard * p.w;
    (p.z < 0.0) as u8
        | ((p.w - p.z < 0.0) as u8) << 1
        | ((g - p.x < 0.0) as u8) << 2
        | ((g + p.x < 0.0) as u8) << 3
        | ((g - p.y < 0.0) as u8) << 4
        | ((g + p.y < 0.0) as u8) << 5
}

/// The point where edge (a, b) crosses `plane`, computed from the endpoints in a canonical
/// order so that two triangles sharing the edge get bit-identical points (no cracks).
#[inline]
fn intersection(a: Vec4, b: Vec4, plane: usize, guard: f32) -> Vec4 {
    let key = |p: Vec4| p.to_array().map(f32::to_bits);
    let (p, q) = if key(a) <= key(b) { (a, b) } else { (b, a) };
    let (dp, dq) = (distance(p, plane, guard), distance(q, plane, guard));
    let t = dp / (dp - dq);
    p + (q - p) * t
}

/// Whether every vertex of `tri` lies inside every plane: `clip_triangle` then returns the
/// triangle itself.
#[inline]
pub(crate) fn inside_every_plane(tri: &[Vec4; 3], guard: f32) -> bool {
    tri.iter().all(|&p| outcode(p, guard) == 0)
}

/// Clips triangle `tri` (clip-space vertices) to the depth range and the guard band `guard`
/// (≥ 1). Returns an empty polygon when nothing is left.
pub(crate) fn clip_triangle(tri: [Vec4; 3], guard: f32) -> ClippedPolygon {
    let mut out = ClippedPolygon { len: 3, vertices: [Vec4::ZERO; MAX_CLIPPED_VERTICES] };
    out.vertices[..3].copy_from_slice(&tri);

    // Fast paths by outcodes (bit i set: outside plane i): entirely inside every plane (the
    // common case), or entirely outside one plane.
    let codes = tri.map(|p| outcode(p, guard));
    if codes[0] & codes[1] & codes[2] != 0 {
        out.len = 0;
        return out;
    }
    if codes[0] | codes[1] | codes[2] == 0 {
        return out;
    }

    // Sutherland–Hodgman, one plane at a time.
    let mut scratch = out;
    for plane in 0..6 {
        let (src, dst) = (&out, &mut scratch);
        dst.len = 0;
        for i in 0..src.len {
            let a = src.vertices[i];
            let b = src.vertices[(i + 1) % src.len];
            let (da, db) = (distance(a, plane, guard), distance(b, plane, guard));
            if da >= 0.0 {
                dst.vertices[dst.len] = a;
                dst.len += 1;
            }
            if (da >= 0.0) != (db >= 0.0) {
                dst.vertices[dst.len] = intersection(a, b, plane, guard);
                dst.len += 1;
            }
        }
        std::mem::swap(&mut out, &mut scratch);
        if out.len < 3 {
            out.len = 0;
            return out;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inside_triangle_is_unchanged() {
        let t = [Vec4::new(0.0, 0.0, 0.5, 1.0), Vec4::new(0.5, 0.0, 0.5, 1.0), Vec4::new(0.0, 0.5, 0.2, 1.0)];
        let p = clip_triangle(t, 4.0);
        assert_eq!(p.as_slice(), &t);
    }

    #[test]
    fn near_plane_cuts_a_corner_into_a_quad() {
        let t =
            [Vec4::new(0.0, 0.0, -0.5, 1.0), Vec4::new(0.5, 0.0, 0.5, 1.0), Vec4::new(0.0, 0.5, 0.5, 1.0)];
        let p = clip_triangle(t, 4.0);
        assert_eq!(p.len, 4);
        assert!(p.as_slice().iter().all(|v| v.z >= 0.0));
        assert!(p.as_slice().iter().filter(|v| v.z == 0.0).count() == 2);
    }

    #[test]
    fn outside_one_plane_is_empty() {
        let t = [Vec4::new(0.0, 0.0, 1.5, 1.0), Vec4::new(0.5, 0.0, 1.2, 1.0), Vec4::new(0.0, 0.5, 1.1, 1.0)];
        assert_eq!(clip_triangle(t, 4.0).len, 0);
    }

    #[test]
    fn shared_edges_get_identical_cut_points() {
        let (a, b) = (Vec4::new(0.1, 0.2, -0.3, 1.0), Vec4::new(0.7, -0.2, 0.9, 1.0));
        assert_eq!(intersection(a, b, 0, 4.0), intersection(b, a, 0, 4.0));
    }
}
