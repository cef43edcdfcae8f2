//! Exact signs of small determinants on the adjudicator's inputs: f32 values and the exact
//! coordinates of anchored surface points (docs/reference.md, "The definition").
//!
//! Every entry is a difference x − y of two terms, each an f32 or a coordinate of an
//! [`AnchoredPoint`] (v0 + b1·(v1 − v0) + b2·(v2 − v0) with f32 vertices and barycentrics, not
//! rounded). The sign is first taken from an f64 evaluation with a forward error bound; where the
//! value is within that bound of zero it is recomputed exactly in integers. An f32 is an integer
//! multiple of 2⁻¹⁴⁹, so an anchored coordinate is one of 2⁻²⁹⁸: scaled by 2¹⁴⁹ (f32 entries
//! only) or 2²⁹⁸ (any anchored entry) every entry is an exact big integer, and so is the
//! determinant. Nothing here rounds in a way that can change a sign.
//!
//! Entries of f32 values alone keep Shewchuk's orient3d/orient2d bounds ("Adaptive Precision
//! Floating-Point Arithmetic and Fast Robust Geometric Predicates", Discrete Comput. Geom. 18,
//! 1997); entries with an anchored coordinate take the bound proven at [`det3_filtered`].

use glam::{DVec3, Vec3};
use num_bigint::BigInt;
use num_traits::{Signed, Zero};
use std::cmp::Ordering;

/// f64's unit roundoff, 2⁻⁵³.
const U: f64 = f64::EPSILON * 0.5;

/// A surface point on its triangle: exactly v0 + b1·(v1 − v0) + b2·(v2 − v0), with its f64
/// approximation and a per-axis bound on that approximation's error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AnchoredPoint {
    pub vertices: [Vec3; 3],
    pub barycentric: [f32; 2],
    approx: DVec3,
    error: DVec3,
}

impl AnchoredPoint {
    /// The point with barycentrics (b1, b2) on `vertices`.
    ///
    /// The approximation is fl(fl(v0 + fl(b1·fl(v1 − v0))) + fl(b2·fl(v2 − v0))) per axis. With
    /// each operation's rounding (1 + δ), |δ| ≤ u = 2⁻⁵³, it equals
    /// v0(1+δ5)(1+δ6) + b1(v1−v0)(1+δ1)(1+δ2)(1+δ5)(1+δ6) + b2(v2−v0)(1+δ3)(1+δ4)(1+δ6), so
    /// |error| ≤ γ4·M with M = |v0| + |b1|·|v1 − v0| + |b2|·|v2 − v0| and γ4 = 4u/(1 − 4u). No
    /// step underflows (a nonzero product of two f32 values is at least 2⁻²⁹⁸, a normal f64)
    /// or overflows (below 2²⁵⁸). M computed in f64 is at least M(1 − u)⁴, and 8u·M̃ (8u a power
    /// of two, so exact) is then above γ4·M. With b1 = b2 = 0 both products are zero and the
    /// approximation is v0 itself: its error is 0.
    pub fn new(vertices: [Vec3; 3], barycentric: [f32; 2]) -> AnchoredPoint {
        let [v0, v1, v2] = vertices.map(|v| v.as_dvec3());
        let (b1, b2) = (barycentric[0] as f64, barycentric[1] as f64);
        let (d1, d2) = (v1 - v0, v2 - v0);
        let approx = v0 + d1 * b1 + d2 * b2;
        let error = if b1 == 0.0 && b2 == 0.0 {
            DVec3::ZERO
        } else {
            (v0.abs() + d1.abs() * b1.abs() + d2.abs() * b2.abs()) * (8.0 * U)
        };
        AnchoredPoint { vertices, barycentric, approx, error }
    }

    /// An f32 point, exactly (the first vertex of a triangle collapsed onto it).
    pub fn at(p: Vec3) -> AnchoredPoint {
        AnchoredPoint::new([p; 3], [0.0; 2])
    }

    /// The f64 approximation of the point.
    pub fn approx(&self) -> DVec3 {
        self.approx
    }

    /// A per-axis bound on |approx − exact|.
    pub fn error(&self) -> DVec3 {
        self.error
    }

    /// The three coordinates as terms of a difference.
    pub fn terms(&self) -> [Term<'_>; 3] {
        [0, 1, 2].map(|k| Term::Point(self, k))
    }

    /// Coordinate `k`·2²⁹⁸ as an integer.
    fn exact(&self, k: usize) -> BigInt {
        let [v0, v1, v2] = self.vertices.map(|v| scaled(v[k]));
        let [b1, b2] = self.barycentric.map(scaled);
        (&v0 << 149usize) + b1 * (v1 - &v0) + b2 * (v2 - &v0)
    }
}

/// One side of a difference: an f32 value, or coordinate k of an anchored point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Term<'a> {
    F32(f32),
    Point(&'a AnchoredPoint, usize),
}

impl Term<'_> {
    /// The three coordinates of an f32 vector.
    pub fn vec(v: Vec3) -> [Term<'static>; 3] {
        [Term::F32(v.x), Term::F32(v.y), Term::F32(v.z)]
    }

    /// The f64 approximation and a bound on its error.
    fn approx(self) -> (f64, f64) {
        match self {
            Term::F32(x) => (x as f64, 0.0),
            Term::Point(p, k) => (p.approx[k], p.error[k]),
        }
    }

    fn is_point(self) -> bool {
        matches!(self, Term::Point(..))
    }

    /// The value times 2²⁹⁸ (`wide`) or 2¹⁴⁹ (f32 only) as an integer.
    fn exact(self, wide: bool) -> BigInt {
        match self {
            Term::F32(x) if wide => scaled(x) << 149usize,
            Term::F32(x) => scaled(x),
            Term::Point(p, k) => {
                debug_assert!(wide, "an anchored coordinate needs the 2²⁹⁸ scale");
                p.exact(k)
            }
        }
    }
}

/// The exact value x − y of two terms.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Diff<'a> {
    pub x: Term<'a>,
    pub y: Term<'a>,
}

impl<'a> Diff<'a> {
    /// The f32 value x itself.
    pub fn of(x: f32) -> Diff<'static> {
        Diff { x: Term::F32(x), y: Term::F32(0.0) }
    }

    /// The difference x − y of two f32 values.
    pub fn f32s(x: f32, y: f32) -> Diff<'static> {
        Diff { x: Term::F32(x), y: Term::F32(y) }
    }

    /// The vector a − b of two f32 vectors, entry by entry.
    pub fn vec(a: Vec3, b: Vec3) -> [Diff<'static>; 3] {
        [0, 1, 2].map(|k| Diff::f32s(a[k], b[k]))
    }

    /// The f32 vector a itself.
    pub fn plain(a: Vec3) -> [Diff<'static>; 3] {
        [0, 1, 2].map(|k| Diff::of(a[k]))
    }

    /// The vector x − y of two vectors of terms.
    pub fn between(x: [Term<'a>; 3], y: [Term<'a>; 3]) -> [Diff<'a>; 3] {
        [0, 1, 2].map(|k| Diff { x: x[k], y: y[k] })
    }

    fn has_point(self) -> bool {
        self.x.is_point() || self.y.is_point()
    }

    /// The f64 value v = fl(x̃ − ỹ) and a bound on |v − (x − y)|: the subtraction's rounding,
    /// at most u·|v| (fl(z) = z/(1 + δ′), |δ′| ≤ u), plus the terms' own errors.
    fn approx(self) -> (f64, f64) {
        let ((x, ex), (y, ey)) = (self.x.approx(), self.y.approx());
        let v = x - y;
        (v, U * v.abs() + ex + ey)
    }

    fn exact(self, wide: bool) -> BigInt {
        self.x.exact(wide) - self.y.exact(wide)
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
const DET3_ERROR: f64 = (7.0 + 56.0 * U) * U;
/// Shewchuk's orient2d error coefficient, (3 + 16ε)ε.
const DET2_ERROR: f64 = (3.0 + 16.0 * U) * U;

/// An f64 value and a bound on its distance from the exact one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Filtered {
    pub approx: f64,
    pub bound: f64,
}

impl Filtered {
    /// The exact value's sign, when the bound decides it.
    pub fn sign(self) -> Option<Ordering> {
        if self.approx > self.bound {
            Some(Ordering::Greater)
        } else if -self.approx > self.bound {
            Some(Ordering::Less)
        } else {
            None
        }
    }
}

/// The six products of a 3×3 determinant: the columns taken from rows 0, 1 and 2.
const DET3_TERMS: [(usize, usize, usize); 6] =
    [(0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)];

/// The 3×3 determinant with rows `m` in f64, and a bound on its error.
///
/// With f32 entries only, the bound is Shewchuk's for orient3d on the differences' permanent.
/// Otherwise let Â be the computed entries and E their bounds (`Diff::approx`), A the exact
/// ones. The expansion a00(a11a22 − a12a21) − a01(a10a22 − a12a20) + a02(a10a21 − a11a20) rounds
/// each of its six products at most five times (product, minor, factor, two sums), so
/// |fl(det Â) − det Â| ≤ γ5·perm|Â|. And det is a sum of signed products of one entry per row,
/// so |det Â − det A| ≤ Σ over the six products of ∏(|â| + e) − ∏|â|
/// = e0(|â1| + e1)(|â2| + e2) + |â0|·e1(|â2| + e2) + |â0||â1|·e2 =: Δ. Both are sums of
/// nonnegative terms, computed with under ten roundings each (a relative deficit under 10u), so
/// 8u·perm̃ + 2Δ̃, rounded once more, is above γ5·perm + Δ (8(1 − u)¹¹ > 5/(1 − 5u)).
pub fn det3_filtered(m: [[Diff; 3]; 3]) -> Filtered {
    let a = m.map(|row| row.map(|d| d.approx()));
    let v = a.map(|row| row.map(|(v, _)| v));
    let minor = |i: usize, j: usize, k: usize, l: usize| v[1][i] * v[2][j] - v[1][k] * v[2][l];
    let approx = v[0][0] * minor(1, 2, 2, 1) - v[0][1] * minor(0, 2, 2, 0) + v[0][2] * minor(0, 1, 1, 0);
    let bound = if m.iter().flatten().any(|d| d.has_point()) {
        let (mut permanent, mut delta) = (0.0, 0.0);
        for (i, j, k) in DET3_TERMS {
            let ((a0, e0), (a1, e1), (a2, e2)) = (a[0][i], a[1][j], a[2][k]);
            let (a0, a1, a2) = (a0.abs(), a1.abs(), a2.abs());
            permanent += a0 * a1 * a2;
            delta += e0 * (a1 + e1) * (a2 + e2) + a0 * e1 * (a2 + e2) + a0 * a1 * e2;
        }
        8.0 * U * permanent + 2.0 * delta
    } else {
        // f32 differences: their rounding is inside Shewchuk's coefficient, on his permanent.
        let pminor =
            |i: usize, j: usize, k: usize, l: usize| (v[1][i] * v[2][j]).abs() + (v[1][k] * v[2][l]).abs();
        let permanent = v[0][0].abs() * pminor(1, 2, 2, 1)
            + v[0][1].abs() * pminor(0, 2, 2, 0)
            + v[0][2].abs() * pminor(0, 1, 1, 0);
        DET3_ERROR * permanent
    };
    Filtered { approx, bound }
}

/// The 3×3 determinant with rows `m`, exactly, times 2^(3·149) (f32 entries only) or
/// 2^(3·298) (any anchored entry).
pub fn det3_exact(m: [[Diff; 3]; 3]) -> BigInt {
    let wide = m.iter().flatten().any(|d| d.has_point());
    let e = m.map(|row| row.map(|d| d.exact(wide)));
    let minor = |i: usize, j: usize, k: usize, l: usize| &e[1][i] * &e[2][j] - &e[1][k] * &e[2][l];
    &e[0][0] * minor(1, 2, 2, 1) - &e[0][1] * minor(0, 2, 2, 0) + &e[0][2] * minor(0, 1, 1, 0)
}

/// The sign of the 3×3 determinant with rows `m` (entries exact differences of terms).
pub fn det3_sign(m: [[Diff; 3]; 3]) -> Ordering {
    det3_filtered(m).sign().unwrap_or_else(|| sign_of(&det3_exact(m)))
}

/// The sign of the 2×2 determinant with rows `m`.
///
/// fl(fl(a00·a11) − fl(a01·a10)) rounds each product twice: |fl(det Â) − det Â| ≤
/// γ2·(|a00a11| + |a01a10|), and |det Â − det A| ≤ Σ e0(|â1| + e1) + |â0|·e1 over the two
/// products; 4u·perm̃ + 2Δ̃ is above their sum as for `det3_filtered`.
pub fn det2_sign(m: [[Diff; 2]; 2]) -> Ordering {
    let a = m.map(|row| row.map(|d| d.approx()));
    let ((a00, e00), (a01, e01)) = (a[0][0], a[0][1]);
    let ((a10, e10), (a11, e11)) = (a[1][0], a[1][1]);
    let (l, r) = (a00 * a11, a01 * a10);
    let permanent = l.abs() + r.abs();
    let wide = m.iter().flatten().any(|d| d.has_point());
    let delta = e00 * (a11.abs() + e11) + a00.abs() * e11 + e01 * (a10.abs() + e10) + a01.abs() * e10;
    let bound = if wide { 4.0 * U * permanent + 2.0 * delta } else { DET2_ERROR * permanent };
    let filtered = Filtered { approx: l - r, bound };
    filtered.sign().unwrap_or_else(|| {
        let e = m.map(|row| row.map(|d| d.exact(wide)));
        sign_of(&(&e[0][0] * &e[1][1] - &e[0][1] * &e[1][0]))
    })
}

/// The sign of the dot product of two vectors of differences, exactly (a rare path: no filter).
pub fn dot_sign<const N: usize>(a: [Diff; N], b: [Diff; N]) -> Ordering {
    let wide = a.iter().chain(&b).any(|d| d.has_point());
    let sum = (0..N).fold(BigInt::zero(), |acc, k| acc + a[k].exact(wide) * b[k].exact(wide));
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

    fn orient_rows(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> [[Diff<'static>; 3]; 3] {
        [Diff::vec(a, d), Diff::vec(b, d), Diff::vec(c, d)]
    }

    fn robust_sign(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> Ordering {
        let p = |v: Vec3| robust::Coord3D { x: v.x as f64, y: v.y as f64, z: v.z as f64 };
        robust::orient3d(p(a), p(b), p(c), p(d)).partial_cmp(&0.0).unwrap()
    }

    /// A deterministic generator of f32 values over many magnitudes.
    fn generator(seed: u64) -> impl FnMut() -> f32 {
        let mut h = seed;
        move || {
            h = h.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((h >> 40) as f32 / (1u64 << 24) as f32 - 0.5) * 2.0f32.powi((h >> 33 & 31) as i32 - 12)
        }
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
        let mut next = generator(0x1234_5678_9abc_def0);
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
            dot_sign([Diff::f32s(3.0, 1.0), Diff::of(-4.0)], [Diff::of(2.0), Diff::of(1.0)]),
            Ordering::Equal
        );
    }

    /// x·2¹⁰⁷⁴ as an integer (exact for every finite f64).
    fn scaled_f64(x: f64) -> BigInt {
        let bits = x.to_bits();
        let exponent = ((bits >> 52) & 0x7ff) as i64;
        let fraction = (bits & ((1u64 << 52) - 1)) as i64;
        let (mantissa, shift) =
            if exponent == 0 { (fraction, 0) } else { (fraction | (1i64 << 52), exponent - 1) };
        let magnitude = BigInt::from(mantissa) << shift as usize;
        if bits >> 63 == 1 { -magnitude } else { magnitude }
    }

    #[test]
    fn an_anchored_points_approximation_lies_within_its_error_bound() {
        // Checked exactly: |approx − exact| ≤ error, at the scale 2¹⁰⁷⁴ where all three are
        // integers. Triangles far from the origin and near it, barycentrics inside and beyond.
        let mut next = generator(0x0bad_5eed_1234_5678);
        let mut tight = 0;
        for k in 0..5_000 {
            let offset = [0.0f32, 2e4, 1e5, 1e6][k % 4];
            let v = [0; 3].map(|_| Vec3::new(next() + offset, next() - offset, next() + 0.5 * offset));
            let b = [next().abs().fract(), next().abs().fract() * 0.5];
            let p = AnchoredPoint::new(v, b);
            for axis in 0..3 {
                let exact = p.exact(axis) << (1074usize - 298);
                let gap = (scaled_f64(p.approx()[axis]) - exact).abs();
                let error = scaled_f64(p.error()[axis]);
                assert!(gap <= error, "{v:?} {b:?} axis {axis}");
                // The bound is not vacuous: within 2¹⁰ of the actual rounding on some points.
                tight += (gap > BigInt::zero() && (gap << 10usize) > error) as usize;
            }
        }
        assert!(tight > 100, "{tight}");
        let q = AnchoredPoint::at(Vec3::new(1e5, -3.25, 7.0));
        assert_eq!((q.approx(), q.error()), (DVec3::new(1e5, -3.25, 7.0), DVec3::ZERO));
    }

    #[test]
    fn an_anchored_point_lies_exactly_on_its_triangles_plane() {
        // Far from the origin the f32 rounding of the point is off the plane; the anchored point
        // itself never is, and its side of a neighbour's plane is the exact one.
        let mut next = generator(0xfeed_beef_0000_0001);
        let (mut off_plane_when_rounded, mut undecided_by_f64) = (0, 0);
        for k in 0..3_000 {
            let offset = [2e4f32, 1e5, 1e6][k % 3];
            let o = Vec3::new(offset, 0.5 * offset, -offset);
            let mut unit = || next().abs().fract() - 0.5;
            let v = [0; 3].map(|_| o + Vec3::new(unit(), unit(), unit()) * 16.0);
            let b = [unit() + 0.5, unit() * 0.5 + 0.25];
            let p = AnchoredPoint::new(v, b);
            fn rows<'a>(v: &[Vec3; 3], q: [Term<'a>; 3]) -> [[Diff<'a>; 3]; 3] {
                let a = Term::vec(v[0]);
                [Diff::between(Term::vec(v[1]), a), Diff::between(Term::vec(v[2]), a), Diff::between(q, a)]
            }
            let rows = |q| rows(&v, q);
            assert_eq!(det3_sign(rows(p.terms())), Ordering::Equal, "{v:?} {b:?}");
            undecided_by_f64 += det3_filtered(rows(p.terms())).sign().is_none() as usize;
            let rounded = p.approx().as_vec3();
            off_plane_when_rounded += (det3_sign(rows(Term::vec(rounded))) != Ordering::Equal) as usize;
            // The filter never decides against the exact sign, on or beside the plane.
            let beside = [v[0], v[1], v[2] + Vec3::new(0.0, unit() * 1e-3, 0.0)];
            let a = Term::vec(beside[0]);
            let m = [
                Diff::between(Term::vec(beside[1]), a),
                Diff::between(Term::vec(beside[2]), a),
                Diff::between(p.terms(), a),
            ];
            let exact = sign_of(&det3_exact(m));
            if let Some(s) = det3_filtered(m).sign() {
                assert_eq!(s, exact, "{beside:?} {b:?}");
            }
            assert_eq!(det3_sign(m), exact);
        }
        assert_eq!(undecided_by_f64, 3_000, "on the plane only the exact path can say zero");
        assert!(off_plane_when_rounded > 2_500, "{off_plane_when_rounded}");
    }

    #[test]
    fn anchored_points_that_are_f32_points_agree_with_shewchuk() {
        // Vertices on a grid of 1/8 around 2¹⁴ or 2¹⁷, where half a grid step is still an f32
        // value: with barycentrics 0, ½ and 1 the anchored point is an f32 point, and
        // robust::orient3d decides its side of a plane through nearby grid points.
        let mut h = 0x5eed_0000_abcd_ef01u64;
        let mut grid = || {
            h = h.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((h >> 40) % 1024) as f32 / 8.0 - 64.0
        };
        let mut unequal = 0;
        for k in 0..5_000 {
            let s = [0.0f32, 16384.0, 131072.0][k % 3];
            let mut point = || Vec3::new(grid(), grid(), grid()) + Vec3::splat(s);
            let v = [point(), point(), point()];
            let b = [[0.0, 0.5], [0.5, 0.5], [0.0, 1.0], [0.5, 0.0]][k % 4];
            let p = AnchoredPoint::new(v, b);
            let f = p.approx().as_vec3();
            let exact = v[0].as_dvec3()
                + (v[1].as_dvec3() - v[0].as_dvec3()) * b[0] as f64
                + (v[2].as_dvec3() - v[0].as_dvec3()) * b[1] as f64;
            assert_eq!(f.as_dvec3(), exact);
            let (a, c) = (point(), point());
            let d = f + Vec3::new(grid(), 0.0, grid()) / 64.0;
            let rows = [Diff::vec(a, d), Diff::vec(c, d), Diff::between(p.terms(), Term::vec(d))];
            let sign = det3_sign(rows);
            assert_eq!(sign, robust_sign(a, c, f, d), "{v:?} {b:?}");
            unequal += (sign != Ordering::Equal) as usize;
        }
        assert!(unequal > 4_000, "{unequal}");
    }
}
