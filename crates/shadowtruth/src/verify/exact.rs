//! Exact signs of small determinants on f32 inputs: the arithmetic of the adjudicator.
//!
//! Every entry is a difference x − y of two f32 values (y = 0 for a plain value). The sign is
//! first taken from an f64 evaluation with Shewchuk's forward error bound for `orient3d`
//! ("Adaptive Precision Floating-Point Arithmetic and Fast Robust Geometric Predicates",
//! Discrete Comput. Geom. 18, 1997: the bound (7 + 56ε)ε·permanent, ε = 2⁻⁵³); where the value
//! is within that bound of zero it is recomputed exactly in integers. An f32 is an integer
//! multiple of 2⁻¹⁴⁹, so scaled by 2¹⁴⁹ every entry is an exact big integer and so is the
//! determinant. Nothing here rounds in a way that can change a sign.

use glam::Vec3;
use num_bigint::BigInt;
use num_traits::{Signed, Zero};
use std::cmp::Ordering;

/// The exact value x − y of two f32 values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Diff {
    pub x: f32,
    pub y: f32,
}

impl Diff {
    pub fn of(x: f32) -> Diff {
        Diff { x, y: 0.0 }
    }

    /// The vector a − b, entry by entry.
    pub fn vec(a: Vec3, b: Vec3) -> [Diff; 3] {
        [0, 1, 2].map(|k| Diff { x: a[k], y: b[k] })
    }

    /// The vector a itself.
    pub fn plain(a: Vec3) -> [Diff; 3] {
        [0, 1, 2].map(|k| Diff::of(a[k]))
    }

    fn approx(self) -> f64 {
        self.x as f64 - self.y as f64
    }

    fn exact(self) -> BigInt {
        scaled(self.x) - scaled(self.y)
    }
}

/// x·2¹⁴⁹ as an integer (exact for every finite f32).
fn scaled(x: f32) -> BigInt {
    let bits = x.to_bits();
    let exponent = ((bits >> 23) & 0xff) as i32;
    let fraction = (bits & 0x7f_ffff) as i64;
    let (mantissa, shift) = if exponent == 0 { (fraction, 0) } else { (fraction | 0x80_0000, exponent - 1) };
    let magnitude = BigInt::from(mantissa) << shift as usize;
    if bits >> 31 == 1 { -magnitude } else { magnitude }
}

fn sign_of(v: &BigInt) -> Ordering {
    if v.is_zero() {
        Ordering::Equal
    } else if v.is_positive() {
        Ordering::Greater
    } else {
        Ordering::Less
    }
}

/// Shewchuk's orient3d error coefficient, (7 + 56ε)ε with ε = 2⁻⁵³.
const DET3_ERROR: f64 = (7.0 + 56.0 * f64::EPSILON * 0.5) * f64::EPSILON * 0.5;
/// Shewchuk's orient2d error coefficient, (3 + 16ε)ε.
const DET2_ERROR: f64 = (3.0 + 16.0 * f64::EPSILON * 0.5) * f64::EPSILON * 0.5;

/// The sign of the 3×3 determinant with rows `m` (entries exact differences of f32 values).
pub fn det3_sign(m: [[Diff; 3]; 3]) -> Ordering {
    let a = m.map(|row| row.map(Diff::approx));
    let minor = |i: usize, j: usize, k: usize, l: usize| a[1][i] * a[2][j] - a[1][k] * a[2][l];
    let det = a[0][0] * minor(1, 2, 2, 1) - a[0][1] * minor(0, 2, 2, 0) + a[0][2] * minor(0, 1, 1, 0);
    let pminor =
        |i: usize, j: usize, k: usize, l: usize| (a[1][i] * a[2][j]).abs() + (a[1][k] * a[2][l]).abs();
    let permanent = a[0][0].abs() * pminor(1, 2, 2, 1)
        + a[0][1].abs() * pminor(0, 2, 2, 0)
        + a[0][2].abs() * pminor(0, 1, 1, 0);
    let bound = DET3_ERROR * permanent;
    if det > bound {
        return Ordering::Greater;
    }
    if -det > bound {
        return Ordering::Less;
    }
    let e = m.map(|row| row.map(Diff::exact));
    let minor = |i: usize, j: usize, k: usize, l: usize| &e[1][i] * &e[2][j] - &e[1][k] * &e[2][l];
    let det = &e[0][0] * minor(1, 2, 2, 1) - &e[0][1] * minor(0, 2, 2, 0) + &e[0][2] * minor(0, 1, 1, 0);
    sign_of(&det)
}

/// The sign of the 2×2 determinant with rows `m`.
pub fn det2_sign(m: [[Diff; 2]; 2]) -> Ordering {
    let a = m.map(|row| row.map(Diff::approx));
    let (l, r) = (a[0][0] * a[1][1], a[0][1] * a[1][0]);
    let bound = DET2_ERROR * (l.abs() + r.abs());
    if l - r > bound {
        return Ordering::Greater;
    }
    if r - l > bound {
        return Ordering::Less;
    }
    let e = m.map(|row| row.map(Diff::exact));
    sign_of(&(&e[0][0] * &e[1][1] - &e[0][1] * &e[1][0]))
}

/// The sign of the dot product of two vectors of differences, exactly (a rare path: no filter).
pub fn dot_sign<const N: usize>(a: [Diff; N], b: [Diff; N]) -> Ordering {
    let sum = (0..N).fold(BigInt::zero(), |acc, k| acc + a[k].exact() * b[k].exact());
    sign_of(&sum)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scaled_integers_are_exact_at_both_ends_of_the_range() {
        assert_eq!(scaled(1.0), BigInt::from(1) << 149usize);
        assert_eq!(scaled(-0.5), -(BigInt::from(1) << 148usize));
        assert_eq!(scaled(f32::from_bits(1)), BigInt::from(1));
        assert_eq!(scaled(f32::MAX), BigInt::from(0xff_ffffu32) << (127usize - 23 + 149));
        assert_eq!(scaled(0.0), BigInt::zero());
        assert_eq!(scaled(-0.0), BigInt::zero());
    }

    fn orient_rows(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> [[Diff; 3]; 3] {
        [Diff::vec(a, d), Diff::vec(b, d), Diff::vec(c, d)]
    }

    fn robust_sign(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> Ordering {
        let p = |v: Vec3| robust::Coord3D { x: v.x as f64, y: v.y as f64, z: v.z as f64 };
        robust::orient3d(p(a), p(b), p(c), p(d)).partial_cmp(&0.0).unwrap()
    }

    #[test]
    fn coplanar_points_give_zero_and_one_ulp_off_the_plane_agrees_with_shewchuk() {
        // a, b, c and d = b + c − a lie on one plane exactly (all sums exact in f32), far from
        // the origin so that the f64 filter cannot decide; d moved by one ulp either way leaves
        // it. robust::orient3d (Shewchuk's adaptive predicate) is the independent oracle.
        let mut checked = 0;
        for k in 0..200u32 {
            let s = 1024.0 + k as f32;
            let a = Vec3::new(s, 3.0 * s, -2.0 * s);
            let b = a + Vec3::new(1.0, 0.5, 0.25 * (k % 7) as f32);
            let c = a + Vec3::new(-0.5, 2.0, 0.125 * (k % 5) as f32);
            let d = b + c - a;
            assert_eq!(det3_sign(orient_rows(a, b, c, d)), Ordering::Equal, "k = {k}");
            for axis in 0..3 {
                for up in [true, false] {
                    let mut e = d;
                    e[axis] = if up { e[axis].next_up() } else { e[axis].next_down() };
                    assert_eq!(det3_sign(orient_rows(a, b, c, e)), robust_sign(a, b, c, e), "k = {k}");
                    checked += 1;
                }
            }
        }
        assert_eq!(checked, 1200);
    }

    #[test]
    fn random_and_nearly_degenerate_orientations_agree_with_shewchuk() {
        let mut h = 0x1234_5678_9abc_def0u64;
        let mut next = || {
            h = h.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((h >> 40) as f32 / (1u64 << 24) as f32 - 0.5) * 2.0f32.powi((h >> 33 & 31) as i32 - 12)
        };
        for _ in 0..20_000 {
            let (a, b, c) = (
                Vec3::new(next(), next(), next()),
                Vec3::new(next(), next(), next()),
                Vec3::new(next(), next(), next()),
            );
            // d near the plane of a, b, c: an affine combination rounded to f32.
            let (s, t) = (next().abs().fract(), next().abs().fract());
            let d = a + (b - a) * s + (c - a) * t;
            assert_eq!(det3_sign(orient_rows(a, b, c, d)), robust_sign(a, b, c, d), "{a} {b} {c} {d}");
        }
    }

    #[test]
    fn det2_and_dot_signs_are_exact() {
        // (1 + 2⁻²³)(1 − 2⁻²³) − 1 = −2⁻⁴⁶: f64 products are exact, but a pair of f32
        // differences makes the filter undecided when both sides nearly cancel.
        let (p, m) = (1.0f32 + f32::EPSILON, 1.0f32 - f32::EPSILON);
        assert_eq!(det2_sign([[Diff::of(p), Diff::of(1.0)], [Diff::of(1.0), Diff::of(m)]]), Ordering::Less);
        assert_eq!(
            det2_sign([[Diff::of(2.0), Diff::of(4.0)], [Diff::of(1.0), Diff::of(2.0)]]),
            Ordering::Equal
        );
        assert_eq!(
            dot_sign(
                [Diff::of(1e30), Diff::of(1e-30), Diff::of(-1e30)],
                [Diff::of(1.0), Diff::of(1.0), Diff::of(1.0)]
            ),
            Ordering::Greater
        );
        assert_eq!(
            dot_sign([Diff { x: 3.0, y: 1.0 }, Diff::of(-4.0)], [Diff::of(2.0), Diff::of(1.0)]),
            Ordering::Equal
        );
    }
}
