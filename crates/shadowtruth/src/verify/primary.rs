//! The exact closest hit of a primary ray (docs/reference.md, "The adjudicator"): the ray from
//! the camera's f32 position along the G-buffer's f32 pixel-centre direction, s > 0.
//!
//! A triangle is met when the line crosses its plane (it is not parallel to it) at s > 0 inside
//! the closed triangle; degenerate triangles, and rays lying in a triangle's plane (they see it
//! edge-on, as a line of no area), never. The parameter is s = N/D with
//! N = det(e1, e2, v0 − o) and D = det(e1, e2, d); two hits are ordered by their exact s, compared
//! as intervals from the f64 filter and, where those overlap, cross-multiplied in big integers.
//! Equal distances go to the lowest triangle id.

use super::exact::{Diff, Filtered, Term, det3_exact, det3_filtered, det3_sign};
use super::segment::no_opposite_signs;
use crate::scene::{Light, LightKind};
use glam::{DVec3, Vec3};
use num_bigint::BigInt;
use num_traits::{Signed, ToPrimitive, Zero};
use std::cmp::Ordering;

/// A primary ray: f32 origin and direction, both exact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrimaryRay {
    pub origin: Vec3,
    pub direction: Vec3,
}

/// Where a ray meets a triangle: s = numerator / denominator, both taken positive, with f64
/// approximations and error bounds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHit {
    pub triangle: u32,
    numerator: Filtered,
    denominator: Filtered,
}

/// The rows of N and D: (e1, e2, v0 − o) and (e1, e2, d).
fn rows(ray: &PrimaryRay, t: &[Vec3; 3]) -> ([[Diff<'static>; 3]; 3], [[Diff<'static>; 3]; 3]) {
    let (e1, e2) = (Diff::vec(t[1], t[0]), Diff::vec(t[2], t[0]));
    ([e1, e2, Diff::vec(t[0], ray.origin)], [e1, e2, Diff::plain(ray.direction)])
}

fn exact_sign(f: Filtered, m: [[Diff; 3]; 3]) -> Ordering {
    f.sign().unwrap_or_else(|| det3_exact(m).sign_ordering())
}

trait SignOrdering {
    fn sign_ordering(&self) -> Ordering;
}

impl SignOrdering for BigInt {
    fn sign_ordering(&self) -> Ordering {
        self.cmp(&BigInt::zero())
    }
}

/// Whether the surface of triangle `t`, seen along `ray`, faces `light` (docs/reference.md,
/// "Facing away"): the light lies strictly on the side of T's plane the ray comes from. The
/// light's side of p is its side of T, since p lies in T's plane.
pub fn faces_light(ray: &PrimaryRay, t: &[Vec3; 3], light: &Light) -> bool {
    let (e1, e2) = (Diff::vec(t[1], t[0]), Diff::vec(t[2], t[0]));
    let camera = det3_sign([e1, e2, Diff::plain(ray.direction)]).reverse();
    let light = match &light.kind {
        LightKind::Spot { position, .. } | LightKind::Point { position, .. } => {
            det3_sign([e1, e2, Diff::vec(*position, t[0])])
        }
        LightKind::Directional { direction, .. } => det3_sign([e1, e2, Diff::plain(-*direction)]),
    };
    light != Ordering::Equal && light == camera
}

/// Whether `ray` meets triangle `id` (vertices `t`) at some s > 0, and where.
pub fn ray_hit(ray: &PrimaryRay, id: u32, t: &[Vec3; 3]) -> Option<RayHit> {
    let (n_rows, d_rows) = rows(ray, t);
    let denominator = det3_filtered(d_rows);
    let d_sign = exact_sign(denominator, d_rows);
    if d_sign == Ordering::Equal {
        return None;
    }
    let numerator = det3_filtered(n_rows);
    if exact_sign(numerator, n_rows) != d_sign {
        return None;
    }
    let o = Term::vec(ray.origin);
    let dir = Diff::plain(ray.direction);
    let edge = |u: Vec3, v: Vec3| {
        let m = [Diff::between(Term::vec(u), o), Diff::between(Term::vec(v), o), dir];
        exact_sign(det3_filtered(m), m)
    };
    let signs = [edge(t[0], t[1]), edge(t[1], t[2]), edge(t[2], t[0])];
    if !no_opposite_signs(&signs) {
        return None;
    }
    // N and D have the same sign on a hit: s is the ratio of their magnitudes.
    let abs = |f: Filtered| Filtered { approx: f.approx.abs(), bound: f.bound };
    Some(RayHit { triangle: id, numerator: abs(numerator), denominator: abs(denominator) })
}

impl RayHit {
    /// An interval holding s: [(N − δN)/(D + δD), (N + δN)/(D − δD)], each end pushed out by
    /// 2⁻⁵⁰ of itself, more than its three roundings.
    pub fn interval(&self) -> (f64, f64) {
        let (n, d) = (self.numerator, self.denominator);
        let lo = ((n.approx - n.bound).max(0.0) / (d.approx + d.bound)) * (1.0 - 2f64.powi(-50));
        let hi = if d.approx > d.bound {
            (n.approx + n.bound) / (d.approx - d.bound) * (1.0 + 2f64.powi(-50))
        } else {
            f64::INFINITY
        };
        (lo, hi)
    }

    /// N and D exactly, both positive (same scale for every hit of f32 inputs: 2^(3·149)).
    fn exact(&self, ray: &PrimaryRay, t: &[Vec3; 3]) -> (BigInt, BigInt) {
        let (n_rows, d_rows) = rows(ray, t);
        (det3_exact(n_rows).abs(), det3_exact(d_rows).abs())
    }

    /// s in f64, to within a few units of its last place: from the filter when it is that
    /// precise, else from the exact quotient.
    pub fn s(&self, ray: &PrimaryRay, t: &[Vec3; 3]) -> f64 {
        let (n, d) = (self.numerator, self.denominator);
        if n.bound <= 2f64.powi(-40) * n.approx && d.bound <= 2f64.powi(-40) * d.approx {
            return n.approx / d.approx;
        }
        let (n, d) = self.exact(ray, t);
        quotient(&n, &d)
    }
}

/// n/d for positive integers, in f64 (within two units of its last place).
fn quotient(n: &BigInt, d: &BigInt) -> f64 {
    // Shift so that the integer quotient has at least 64 bits, then scale back.
    let shift = 64 + d.bits() as i64 - n.bits() as i64;
    let q = if shift >= 0 { (n << shift as usize) / d } else { n / (d << (-shift) as usize) };
    q.to_f64().unwrap_or(f64::INFINITY) * 2f64.powi(-shift as i32)
}

/// Which of two hits of the same ray is nearer: by the exact s, equal ones by triangle id.
pub fn nearer(ray: &PrimaryRay, a: &RayHit, ta: &[Vec3; 3], b: &RayHit, tb: &[Vec3; 3]) -> bool {
    let ((a_lo, a_hi), (b_lo, b_hi)) = (a.interval(), b.interval());
    if a_hi < b_lo {
        return true;
    }
    if b_hi < a_lo {
        return false;
    }
    let ((na, da), (nb, db)) = (a.exact(ray, ta), b.exact(ray, tb));
    match (na * db).cmp(&(nb * da)) {
        Ordering::Less => true,
        Ordering::Greater => false,
        Ordering::Equal => a.triangle < b.triangle,
    }
}

/// The exact hit point o + s·d in f64 (within a few units of the last place of its
/// magnitudes).
pub fn hit_point(ray: &PrimaryRay, hit: &RayHit, t: &[Vec3; 3]) -> DVec3 {
    ray.origin.as_dvec3() + ray.direction.as_dvec3() * hit.s(ray, t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::vec3;

    const T: [Vec3; 3] = [vec3(0.0, 1.0, 0.0), vec3(2.0, 1.0, 0.0), vec3(0.0, 1.0, 2.0)];

    fn ray(o: Vec3, d: Vec3) -> PrimaryRay {
        PrimaryRay { origin: o, direction: d }
    }

    #[test]
    fn hits_are_closed_in_front_and_never_edge_on() {
        let up = vec3(0.0, 1.0, 0.0);
        let h = ray_hit(&ray(vec3(0.5, 0.0, 0.5), up), 0, &T).expect("interior");
        assert_eq!(h.s(&ray(vec3(0.5, 0.0, 0.5), up), &T), 1.0);
        // The hypotenuse's midpoint and a vertex are inside the closed triangle.
        assert!(ray_hit(&ray(vec3(1.0, 0.0, 1.0), up), 0, &T).is_some());
        assert!(ray_hit(&ray(vec3(2.0, -3.0, 0.0), up), 0, &T).is_some());
        // One ulp past the hypotenuse, behind the origin, from on the plane, along the plane.
        assert!(ray_hit(&ray(vec3(1.0f32.next_up(), 0.0, 1.0), up), 0, &T).is_none());
        assert!(ray_hit(&ray(vec3(0.5, 2.0, 0.5), up), 0, &T).is_none());
        assert!(ray_hit(&ray(vec3(0.5, 1.0, 0.5), up), 0, &T).is_none());
        assert!(ray_hit(&ray(vec3(-1.0, 1.0, 0.5), vec3(1.0, 0.0, 0.0)), 0, &T).is_none());
        // Degenerate: collinear vertices.
        let flat = [vec3(0.0, 1.0, 0.0), vec3(1.0, 1.0, 1.0), vec3(2.0, 1.0, 2.0)];
        assert!(ray_hit(&ray(vec3(1.0, 0.0, 1.0), up), 0, &flat).is_none());
        // From below both determinants are negative (T's normal points down), from above both
        // positive: s is the same ratio of magnitudes either way.
        let down = ray(vec3(0.5, 3.0, 0.5), -up);
        let h = ray_hit(&down, 0, &T).expect("from above");
        assert_eq!(h.s(&down, &T), 2.0);
        let (lo, hi) = h.interval();
        assert!(lo <= 2.0 && 2.0 <= hi && hi - lo < 1e-12, "[{lo}, {hi}]");
    }

    #[test]
    fn the_nearer_of_two_hits_is_decided_exactly_even_one_ulp_apart() {
        // Two parallel triangles 2e4 from the origin, one f32 step apart along the ray: the f64
        // intervals overlap only for the exact path to order, and equal planes go to the lower id.
        let base = 20_000.0f32;
        let lift = |t: [Vec3; 3], y: f32| t.map(|v| vec3(v.x + base, y, v.z + base));
        let (upper_y, lower_y) = (base.next_up(), base);
        let o = vec3(base + 0.3, 0.0, base + 0.4);
        let r = ray(o, vec3(1e-6, 1.0, 2e-6));
        let (ta, tb) = (lift(T, upper_y), lift(T, lower_y));
        let (a, b) = (ray_hit(&r, 7, &ta).unwrap(), ray_hit(&r, 3, &tb).unwrap());
        assert!(!nearer(&r, &a, &ta, &b, &tb), "the lower plane is nearer");
        assert!(nearer(&r, &b, &tb, &a, &ta));
        let same = ray_hit(&r, 9, &tb).unwrap();
        assert!(nearer(&r, &b, &tb, &same, &tb) && !nearer(&r, &same, &tb, &b, &tb), "ties by id");
        let x = hit_point(&r, &b, &tb);
        assert!((x.y - base as f64).abs() <= 1e-9 * base as f64, "{x}");
    }

    #[test]
    fn quotients_are_correct_to_the_last_places() {
        let third = quotient(&BigInt::from(1), &BigInt::from(3));
        assert!((third - 1.0 / 3.0).abs() <= 2.0 * f64::EPSILON / 3.0);
        let big = quotient(&(BigInt::from(7) << 900usize), &(BigInt::from(2) << 900usize));
        assert_eq!(big, 3.5);
    }
}
