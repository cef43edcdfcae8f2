//! Self-intersection avoidance for secondary rays (Wächter & Binder, "A Fast and Robust Method
//! for Avoiding Self-Intersection", Ray Tracing Gems ch. 6): the origin moves along the
//! geometric normal by a few ulps of its own coordinates, never by a scene-dependent epsilon.

use glam::Vec3;

const ORIGIN: f32 = 1.0 / 32.0;
const FLOAT_SCALE: f32 = 1.0 / 65536.0;
const INT_SCALE: f32 = 256.0;

/// `p` moved off its surface along `n` (unit, on the side the ray leaves towards).
#[inline]
pub fn offset_ray_origin(p: Vec3, n: Vec3) -> Vec3 {
    let of_i = [(INT_SCALE * n.x) as i32, (INT_SCALE * n.y) as i32, (INT_SCALE * n.z) as i32];
    let p = p.to_array();
    let n = n.to_array();
    let mut out = [0.0f32; 3];
    for k in 0..3 {
        let shift = if p[k] < 0.0 { -of_i[k] } else { of_i[k] };
        let p_i = f32::from_bits((p[k].to_bits() as i32).wrapping_add(shift) as u32);
        out[k] = if p[k].abs() < ORIGIN { p[k] + FLOAT_SCALE * n[k] } else { p_i };
    }
    Vec3::from_array(out)
}
