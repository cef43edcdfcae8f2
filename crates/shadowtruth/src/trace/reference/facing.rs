//! Whether a surface faces the light, decided exactly (docs/reference.md, "Facing away"): the
//! side of the hit triangle's plane the light lies on, against the side the camera sees.
//!
//! Both are signs of det[v1 − v0, v2 − v0, w] on T's f32 vertices: w the light's position less
//! v0 (the exact point p lies in T's plane, so the light's side of p is its side of T), the
//! direction towards a directional light, or the primary ray's direction. Computed in f64 with
//! Shewchuk's orient3d error bound ("Adaptive Precision Floating-Point Arithmetic and Fast Robust
//! Geometric Predicates", 1997) and, where that cannot decide, exactly in big integers: a light
//! exactly in the plane of a surface must make it `FacingAway`, or the segment runs inside the
//! plane and touches the neighbour across an edge, a doubt no precision resolves. `robust`'s
//! orient3d takes points, not a direction; `verify` keeps exact arithmetic of its own.

use glam::Vec3;
use num_bigint::BigInt;
use std::cmp::Ordering;

/// Where the light is, as the facing test takes it (f32, exactly as the scene gives it).
#[derive(Clone, Copy, Debug)]
pub(in crate::trace) enum LightPlace {
    /// A spot light's position.
    Point(Vec3),
    /// The direction towards a directional light (its direction reversed, exactly).
    Towards(Vec3),
}

/// Whether the light lies strictly on the side of T's plane the camera sees (`camera_side`). A
/// surface seen exactly edge-on, or with the light exactly in its plane, does not face it.
pub(in crate::trace) fn faces_light(t: &[Vec3; 3], camera: Ordering, light: LightPlace) -> bool {
    let light = match light {
        LightPlace::Point(l) => side(t, [l, t[0]]),
        LightPlace::Towards(w) => side(t, [w, Vec3::ZERO]),
    };
    light != Ordering::Equal && light == camera
}

/// The side of T's plane (that of its normal (v1 − v0) × (v2 − v0)) the primary ray `view`
/// comes from: `Greater` when the normal faces the camera.
pub(in crate::trace) fn camera_side(t: &[Vec3; 3], view: Vec3) -> Ordering {
    side(t, [view, Vec3::ZERO]).reverse()
}

/// The sign of det[v1 − v0, v2 − v0, a − b].
fn side(t: &[Vec3; 3], [a, b]: [Vec3; 2]) -> Ordering {
    let rows = [[t[1], t[0]], [t[2], t[0]], [a, b]];
    let m = rows.map(|[x, y]| (x.as_dvec3() - y.as_dvec3()).to_array());
    let minor = |i: usize, j: usize| m[1][i] * m[2][j] - m[1][j] * m[2][i];
    let det = m[0][0] * minor(1, 2) - m[0][1] * minor(0, 2) + m[0][2] * minor(0, 1);
    let abs = m.map(|row| row.map(f64::abs));
    let permanent_minor = |i: usize, j: usize| abs[1][i] * abs[2][j] + abs[1][j] * abs[2][i];
    let permanent =
        abs[0][0] * permanent_minor(1, 2) + abs[0][1] * permanent_minor(0, 2) + abs[0][2] * permanent_minor(0, 1);
    // Shewchuk's orient3d bound, (7 + 56ε)ε·permanent with ε = 2⁻⁵³, rounded up to 8ε.
    let bound = 8.0 * f64::EPSILON * 0.5 * permanent;
    if det > bound {
        Ordering::Greater
    } else if -det > bound {
        Ordering::Less
    } else {
        exact_side(rows)
    }
}

/// `side` in big integers: every f32 is an integer multiple of 2⁻¹⁴⁹.
#[cold]
fn exact_side(rows: [[Vec3; 2]; 3]) -> Ordering {
    let m = rows.map(|[x, y]| [0, 1, 2].map(|k| scaled(x[k]) - scaled(y[k])));
    let minor = |i: usize, j: usize| &m[1][i] * &m[2][j] - &m[1][j] * &m[2][i];
    let det = &m[0][0] * minor(1, 2) - &m[0][1] * minor(0, 2) + &m[0][2] * minor(0, 1);
    det.sign().cmp(&num_bigint::Sign::NoSign)
}

/// x·2¹⁴⁹ as an integer (exact for every finite f32).
fn scaled(x: f32) -> BigInt {
    let bits = x.to_bits();
    let exponent = (bits >> 23) & 0xff;
    let fraction = bits & 0x7f_ffff;
    let (mantissa, shift) = if exponent == 0 { (fraction, 0) } else { (fraction | 0x80_0000, exponent - 1) };
    let magnitude = BigInt::from(mantissa) << shift as usize;
    if bits >> 31 == 1 { -magnitude } else { magnitude }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A triangle of an island moved 10⁵ units out whose plane holds the spot light exactly
    /// (checked in rationals), and its two neighbours, which face it by 81/32768 and 35/4096.
    const A: Vec3 = Vec3::new(60073.625, 30036.521484375, -74088.5);
    const B: Vec3 = Vec3::new(60073.75, 30036.4453125, -74088.375);
    const C: Vec3 = Vec3::new(60073.75, 30036.47265625, -74088.5);
    const D: Vec3 = Vec3::new(60073.625, 30036.4921875, -74088.375);
    const LIGHT: Vec3 = Vec3::new(60061.0, 30042.0, -74091.0);

    #[test]
    fn a_light_exactly_in_the_plane_is_not_faced() {
        let light = LightPlace::Point(LIGHT);
        // Seen from either side, the plane holding the light is edge-on to it.
        for camera in [Ordering::Greater, Ordering::Less] {
            assert!(!faces_light(&[A, B, C], camera, light));
        }
        assert_eq!(side(&[A, B, C], [LIGHT, A]), Ordering::Equal);
        // The neighbour's normal (D − A) × (B − A) has n·(L − A) = +81/32768.
        assert_eq!(side(&[A, D, B], [LIGHT, A]), Ordering::Greater);
        assert_eq!(side(&[A, B, D], [LIGHT, A]), Ordering::Less);
    }

    #[test]
    fn the_camera_turns_the_normal() {
        let t = [Vec3::ZERO, Vec3::X, Vec3::Y]; // normal +z
        let above = LightPlace::Towards(Vec3::new(0.0, 0.6, 0.8));
        let seen = |view: Vec3, light| faces_light(&t, camera_side(&t, view), light);
        assert!(seen(Vec3::new(0.0, 0.0, -1.0), above));
        assert!(!seen(Vec3::new(0.0, 0.0, 1.0), above));
        let below = LightPlace::Point(Vec3::new(0.2, 0.2, -3.0));
        assert!(seen(Vec3::new(0.1, 0.0, 1.0), below));
        assert!(!seen(Vec3::new(0.1, 0.0, -1.0), below));
        assert_eq!(camera_side(&t, Vec3::new(1.0, 0.0, 0.0)), Ordering::Equal);
    }

    #[test]
    fn exact_where_f64_cannot_tell() {
        // C − A lies in the plane of (A, B, C); 2⁻⁶⁰ out of it the determinant is about 3·10⁻²¹
        // against an f64 bound near 3·10⁻¹⁸, so only the integers decide. The normal's z is
        // (B − A)ₓ(C − A)ᵧ − (B − A)ᵧ(C − A)ₓ = 0.125 · 0.02734375 > 0.
        let in_plane = C - A;
        assert_eq!(in_plane, Vec3::new(0.125, -0.048828125, 0.0));
        let out = |z: f32| [in_plane + Vec3::new(0.0, 0.0, z), Vec3::ZERO];
        let t = [A, B, C];
        assert_eq!(side(&t, out(2f32.powi(-60))), Ordering::Greater);
        assert_eq!(side(&t, out(-(2f32.powi(-60)))), Ordering::Less);
        assert_eq!(side(&t, out(0.0)), Ordering::Equal);
        assert_eq!(exact_side([[B, A], [C, A], [LIGHT, A]]), Ordering::Equal);
        // Subnormal entries are exact too.
        let w = Vec3::new(3.0, -2.0, f32::from_bits(1));
        assert_eq!(exact_side([[Vec3::X, Vec3::ZERO], [Vec3::Y, Vec3::ZERO], [w, Vec3::ZERO]]), Ordering::Greater);
    }
}
