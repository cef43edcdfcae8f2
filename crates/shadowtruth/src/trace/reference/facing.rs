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

use glam::{DVec3, Vec3};
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

/// T's plane as the facing test needs it: the normal n = (v1 − v0) × (v2 − v0) in f64, and the
/// permanents of its 2×2 minors for the bound, both computed once for every side asked.
pub(in crate::trace) struct Plane<'t> {
    t: &'t [Vec3; 3],
    normal: DVec3,
    permanent: DVec3,
}

impl<'t> Plane<'t> {
    #[inline(always)]
    pub(in crate::trace) fn new(t: &'t [Vec3; 3]) -> Self {
        let (e1, e2) = (t[1].as_dvec3() - t[0].as_dvec3(), t[2].as_dvec3() - t[0].as_dvec3());
        let (a1, a2) = (e1.abs(), e2.abs());
        let permanent =
            DVec3::new(a1.y * a2.z + a1.z * a2.y, a1.z * a2.x + a1.x * a2.z, a1.x * a2.y + a1.y * a2.x);
        Plane { t, normal: e1.cross(e2), permanent }
    }

    /// The normal (v1 − v0) × (v2 − v0), in f64, not normalized.
    #[inline(always)]
    pub(in crate::trace) fn normal(&self) -> DVec3 {
        self.normal
    }

    /// The side of the plane (that of its normal) the primary ray `view` comes from:
    /// `Greater` when the normal faces the camera.
    #[inline(always)]
    pub(in crate::trace) fn camera_side(&self, view: Vec3) -> Ordering {
        self.side(view, Vec3::ZERO).reverse()
    }

    /// Whether the light lies strictly on the side the camera sees (`camera_side`). A surface
    /// seen exactly edge-on, or with the light exactly in its plane, does not face it.
    #[inline(always)]
    pub(in crate::trace) fn faces_light(&self, camera: Ordering, light: LightPlace) -> bool {
        let light = match light {
            LightPlace::Point(l) => self.side(l, self.t[0]),
            LightPlace::Towards(w) => self.side(w, Vec3::ZERO),
        };
        light != Ordering::Equal && light == camera
    }

    /// The sign of det[v1 − v0, v2 − v0, a − b] = n·(a − b), expanded along a − b as
    /// Shewchuk's orient3d is along its third coordinate, with his bound (7 + 56ε)ε·permanent
    /// (ε = 2⁻⁵³), rounded up to 8ε; where that cannot decide, in big integers.
    #[inline(always)]
    fn side(&self, a: Vec3, b: Vec3) -> Ordering {
        let w = a.as_dvec3() - b.as_dvec3();
        let det = self.normal.dot(w);
        let bound = 8.0 * (f64::EPSILON * 0.5) * self.permanent.dot(w.abs());
        if det > bound {
            Ordering::Greater
        } else if -det > bound {
            Ordering::Less
        } else {
            exact_side([[self.t[1], self.t[0]], [self.t[2], self.t[0]], [a, b]])
        }
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
    /// The coordinates are exact f32 values (multiples of 2⁻⁹), written out in full.
    #[allow(clippy::excessive_precision)]
    mod island {
        use glam::Vec3;
        pub const A: Vec3 = Vec3::new(60073.625, 30036.521484375, -74088.5);
        pub const B: Vec3 = Vec3::new(60073.75, 30036.4453125, -74088.375);
        pub const C: Vec3 = Vec3::new(60073.75, 30036.47265625, -74088.5);
        pub const D: Vec3 = Vec3::new(60073.625, 30036.4921875, -74088.375);
    }
    use island::{A, B, C, D};
    const LIGHT: Vec3 = Vec3::new(60061.0, 30042.0, -74091.0);

    #[test]
    fn a_light_exactly_in_the_plane_is_not_faced() {
        let light = LightPlace::Point(LIGHT);
        // Seen from either side, the plane holding the light is edge-on to it.
        for camera in [Ordering::Greater, Ordering::Less] {
            assert!(!Plane::new(&[A, B, C]).faces_light(camera, light));
        }
        assert_eq!(Plane::new(&[A, B, C]).side(LIGHT, A), Ordering::Equal);
        // The neighbour's normal (D − A) × (B − A) has n·(L − A) = +81/32768.
        assert_eq!(Plane::new(&[A, D, B]).side(LIGHT, A), Ordering::Greater);
        assert_eq!(Plane::new(&[A, B, D]).side(LIGHT, A), Ordering::Less);
    }

    #[test]
    fn the_camera_turns_the_normal() {
        let t = [Vec3::ZERO, Vec3::X, Vec3::Y]; // normal +z
        let above = LightPlace::Towards(Vec3::new(0.0, 0.6, 0.8));
        let plane = Plane::new(&t);
        let seen = |view: Vec3, light| plane.faces_light(plane.camera_side(view), light);
        assert!(seen(Vec3::new(0.0, 0.0, -1.0), above));
        assert!(!seen(Vec3::new(0.0, 0.0, 1.0), above));
        let below = LightPlace::Point(Vec3::new(0.2, 0.2, -3.0));
        assert!(seen(Vec3::new(0.1, 0.0, 1.0), below));
        assert!(!seen(Vec3::new(0.1, 0.0, -1.0), below));
        assert_eq!(plane.camera_side(Vec3::new(1.0, 0.0, 0.0)), Ordering::Equal);
    }

    #[test]
    fn exact_where_f64_cannot_tell() {
        // C − A lies in the plane of (A, B, C); 2⁻⁶⁰ out of it the determinant is about 3·10⁻²¹
        // against an f64 bound near 3·10⁻¹⁸, so only the integers decide. The normal's z is
        // (B − A)ₓ(C − A)ᵧ − (B − A)ᵧ(C − A)ₓ = 0.125 · 0.02734375 > 0.
        let in_plane = C - A;
        assert_eq!(in_plane, Vec3::new(0.125, -0.048828125, 0.0));
        let t = [A, B, C];
        let plane = Plane::new(&t);
        let out = |z: f32| plane.side(in_plane + Vec3::new(0.0, 0.0, z), Vec3::ZERO);
        assert_eq!(out(2f32.powi(-60)), Ordering::Greater);
        assert_eq!(out(-(2f32.powi(-60))), Ordering::Less);
        assert_eq!(out(0.0), Ordering::Equal);
        assert_eq!(exact_side([[B, A], [C, A], [LIGHT, A]]), Ordering::Equal);
        // Subnormal entries are exact too.
        let w = Vec3::new(3.0, -2.0, f32::from_bits(1));
        assert_eq!(
            exact_side([[Vec3::X, Vec3::ZERO], [Vec3::Y, Vec3::ZERO], [w, Vec3::ZERO]]),
            Ordering::Greater
        );
    }
}
