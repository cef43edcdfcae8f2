//! The shadow ray's triangle test with a certificate: whether the *exact* segment of the
//! definition (docs/reference.md) — from the exact surface point P along the exact direction —
//! meets a triangle, decided from a computed ray that is only known to lie near it.
//!
//! The computed ray has an origin within `origin_error` (per axis) of P and a unit direction
//! within `direction_error` (per axis) of the exact one. The test is Woop, Benthin & Wald's
//! watertight test (JCGT 2(1), 2013), run in f32 or f64 (`Real`), with a bound on how far each
//! computed edge function and distance can lie from the exact segment's: the rounding of the
//! translation, the shear and the products (pbrt-v4 §6.8.4's analysis, Higham's γ) plus the
//! ray's own distance from the exact segment. A triangle is a certain `Miss` when two edge
//! functions have opposite signs beyond their bound (or it lies certainly behind the origin or
//! beyond the light), a certain `Hit` when all three share a sign beyond it and the distance is
//! certainly inside the segment, and a `Doubt` otherwise. Every bound is doubled over its
//! derivation, so that the few roundings of the bound itself never matter.

use super::watertight::WatertightRay;
use glam::Vec3;
use num_traits::Float;

/// f32 or f64, with the unit roundoff the bounds need.
pub(in crate::trace) trait Real: Float + Into<f64> {
    /// Half an ulp of 1: one rounding moves a value by at most this fraction of it.
    const UNIT_ROUNDOFF: f64;
    /// The smallest positive value: the spacing of the subnormals, where rounding is absolute.
    const SMALLEST_SUBNORMAL: f64;
    fn of(value: f64) -> Self;
}

impl Real for f32 {
    const UNIT_ROUNDOFF: f64 = f32::EPSILON as f64 * 0.5;
    const SMALLEST_SUBNORMAL: f64 = f32::from_bits(1) as f64;
    fn of(value: f64) -> f32 {
        value as f32
    }
}

impl Real for f64 {
    const UNIT_ROUNDOFF: f64 = f64::EPSILON * 0.5;
    const SMALLEST_SUBNORMAL: f64 = f64::from_bits(1);
    fn of(value: f64) -> f64 {
        value
    }
}

/// What the test can say of the exact segment and one triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(in crate::trace) enum Verdict {
    Miss,
    Hit,
    /// Too close to call in this precision; `likely_hit` is what the computed numbers say.
    Doubt {
        likely_hit: bool,
    },
}

/// A computed ray standing for an exact segment, prepared for the certified test.
#[derive(Clone, Copy, Debug)]
pub(in crate::trace) struct CertifiedRay<F: Real> {
    origin: [F; 3],
    kx: usize,
    ky: usize,
    kz: usize,
    sx: F,
    sy: F,
    sz: F,
    /// Per axis, a bound on |computed origin − exact origin|.
    origin_error: f64,
    /// Bounds on |sx − sx*|, |sy − sy*| and |sz − sz*| against the exact direction's shear.
    shear_error: f64,
    scale_error: f64,
    /// The exact segment's length lies in [length_lo, length_hi] (both ∞ for a ray).
    length_lo: f64,
    length_hi: f64,
}

/// The watertight test's numbers for one triangle: the vertices' sheared z and edge functions.
struct Sheared<F> {
    z: [F; 3],
    e: [F; 3],
    /// max |x|, |y| and |translated coordinate along the ray's main axis| over the vertices.
    reach: f64,
    /// max |x|, |y| over the vertices: the edge functions are products of these alone.
    reach_across: f64,
}

impl<F: Real> CertifiedRay<F> {
    /// `direction` must be unit to within a few roundings; `origin_error`, `direction_error`
    /// bound (per axis) the computed origin's and direction's distance from the exact ones, and
    /// `length` with `length_error` the exact segment's length (∞ for a ray).
    pub(in crate::trace) fn new(
        origin: [F; 3],
        origin_error: f64,
        direction: [F; 3],
        direction_error: f64,
        length: f64,
        length_error: f64,
    ) -> Self {
        let abs = direction.map(|d| d.abs());
        let kz = if abs[0] > abs[1] {
            if abs[0] > abs[2] { 0 } else { 2 }
        } else if abs[1] > abs[2] {
            1
        } else {
            2
        };
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        // Keep the winding of the projected triangle independent of the ray's octant.
        if direction[kz] < F::zero() {
            std::mem::swap(&mut kx, &mut ky);
        }
        let sz = F::one() / direction[kz];
        let (sx, sy) = (direction[kx] * sz, direction[ky] * sz);
        Self::sheared(origin, [kx, ky, kz], [sx, sy, sz], origin_error, direction_error, length, length_error)
    }

    /// `new` from the axis order and shear factors `new` computes (`[sx, sy, sz]`).
    fn sheared(
        origin: [F; 3],
        [kx, ky, kz]: [usize; 3],
        [sx, sy, sz]: [F; 3],
        origin_error: f64,
        direction_error: f64,
        length: f64,
        length_error: f64,
    ) -> Self {
        let u = F::UNIT_ROUNDOFF;
        // |d_kz| ≥ 1/√3 for a unit direction: the shear factors d_k/d_kz move by at most
        // 2ε/|d_kz| ≤ 3.5ε under a direction error ε, and 1/d_kz by at most 3.1ε; each also
        // rounds (twice for the shear, once for the scale).
        let (shear_error, scale_error) = (4.0 * direction_error + 2.1 * u, 4.0 * direction_error + 2.0 * u);
        CertifiedRay {
            origin,
            kx,
            ky,
            kz,
            sx,
            sy,
            sz,
            origin_error,
            shear_error,
            scale_error,
            length_lo: length - length_error,
            length_hi: length + length_error,
        }
    }

    #[inline(always)]
    fn shear(&self, v: &[[F; 3]; 3]) -> Sheared<F> {
        let (kx, ky, kz) = (self.kx, self.ky, self.kz);
        let a = v.map(|p| [p[0] - self.origin[0], p[1] - self.origin[1], p[2] - self.origin[2]]);
        let x = a.map(|a| a[kx] - self.sx * a[kz]);
        let y = a.map(|a| a[ky] - self.sy * a[kz]);
        let e = [x[2] * y[1] - y[2] * x[1], x[0] * y[2] - y[0] * x[2], x[1] * y[0] - y[1] * x[0]];
        let mut across = F::zero();
        for k in 0..3 {
            across = across.max(x[k].abs()).max(y[k].abs());
        }
        let along = a[0][kz].abs().max(a[1][kz].abs()).max(a[2][kz].abs());
        Sheared {
            z: a.map(|a| self.sz * a[kz]),
            e,
            reach: across.max(along).into(),
            reach_across: across.into(),
        }
    }

    /// A bound on |x − x*| (and |y − y*|) for every vertex: the origin's error (twice, through
    /// the shear), the shear's error times the coordinate along the main axis, and the rounding
    /// of the translation and the shear (coordinates within 2·reach, since |x| ≤ |a_kx| + |a_kz|).
    #[inline(always)]
    fn sheared_error(&self, reach: f64) -> f64 {
        let (fixed, per_reach) = self.sheared_error_coefficients();
        fixed + per_reach * reach
    }

    /// `sheared_error(reach)` = fixed + per_reach · reach: (fixed, per_reach).
    #[inline(always)]
    pub(in crate::trace) fn sheared_error_coefficients(&self) -> (f64, f64) {
        let u = F::UNIT_ROUNDOFF;
        (
            2.0 * (2.0 * self.origin_error + self.shear_error * self.origin_error),
            2.0 * (2.01 * self.shear_error + 12.1 * u),
        )
    }

    /// A bound on |z − z*| for each vertex's scaled distance along the ray, as (fixed, per unit
    /// of reach, the largest |x|, |y| and translated main-axis coordinate): the origin's error
    /// and the scale's, the coordinate's and the product's rounding (|sz| ≤ √3), doubled.
    /// `crossing_near` evaluates the same bound in another order (the two differ by a few
    /// roundings, which the packet's use of this one covers: packet.rs).
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub(in crate::trace) fn distance_error_coefficients(&self) -> (f64, f64) {
        let u = F::UNIT_ROUNDOFF;
        (
            2.0 * (2.0 * self.origin_error + self.scale_error * self.origin_error),
            2.0 * (2.01 * self.scale_error + 8.0 * u),
        )
    }

    /// The least the exact segment's length may be (∞ for a ray).
    #[cfg(target_arch = "x86_64")]
    pub(in crate::trace) fn least_length(&self) -> f64 {
        self.length_lo
    }

    /// A bound on |e − e*| for each edge function: two products of sheared coordinates within
    /// `reach_across` (their largest magnitude, not the distance along the ray, which enters
    /// only through `sheared`) whose factors are off by `sheared` each, the products' and the
    /// difference's rounding, and their underflow (half the smallest subnormal each).
    #[inline(always)]
    pub(in crate::trace) fn edge_error(reach_across: f64, sheared: f64) -> f64 {
        let u = F::UNIT_ROUNDOFF;
        let products =
            2.0 * sheared * (2.0 * reach_across + sheared) + 4.01 * u * reach_across * reach_across;
        2.0 * (products + 2.0 * F::SMALLEST_SUBNORMAL)
    }

    /// The barycentrics (b0, b1, b2) of the point where this ray's line crosses the plane of
    /// `v`: the watertight test's edge functions over their sum (`None` edge-on).
    pub(in crate::trace) fn barycentrics(&self, v: &[[F; 3]; 3]) -> Option<[F; 3]> {
        Self::barycentrics_of(&self.shear(v))
    }

    /// `crossing(v)` and `barycentrics(v)` from one shear.
    pub(in crate::trace) fn crossing_and_barycentrics(&self, v: &[[F; 3]; 3]) -> (Crossing, Option<[F; 3]>) {
        let s = self.shear(v);
        (self.crossing_of(&s, false), Self::barycentrics_of(&s))
    }

    fn barycentrics_of(s: &Sheared<F>) -> Option<[F; 3]> {
        let det = s.e[0] + s.e[1] + s.e[2];
        (det != F::zero()).then(|| s.e.map(|e| e / det))
    }

    /// Whether the exact segment meets the closed triangle `v`.
    #[inline(always)]
    pub(in crate::trace) fn classify(&self, v: &[[F; 3]; 3]) -> Verdict {
        match self.crossing_within(v, true) {
            Crossing::Miss => Verdict::Miss,
            Crossing::Doubt { likely_hit } => Verdict::Doubt { likely_hit },
            Crossing::Through { t_lo, t_hi } => {
                if t_hi < 0.0 || t_lo > self.length_hi {
                    Verdict::Miss
                } else if t_lo > 0.0 && t_hi < self.length_lo {
                    Verdict::Hit
                } else {
                    let t = 0.5 * (t_lo + t_hi);
                    Verdict::Doubt { likely_hit: t > 0.0 && t <= self.length_hi }
                }
            }
        }
    }

    /// Where the exact line crosses the closed triangle `v`, if it certainly does; a certain
    /// `Miss` also where the triangle lies wholly behind the origin or beyond the segment.
    #[inline(always)]
    pub(in crate::trace) fn crossing(&self, v: &[[F; 3]; 3]) -> Crossing {
        self.crossing_within(v, false)
    }

    /// `crossing`; with `segment`, a crossing whose whole z range lies within the segment is
    /// reported with that range (enough to call it a hit) rather than a tighter distance.
    #[inline(always)]
    fn crossing_within(&self, v: &[[F; 3]; 3], segment: bool) -> Crossing {
        self.crossing_of(&self.shear(v), segment)
    }

    /// `crossing_within` from the triangle's sheared numbers.
    #[inline(always)]
    fn crossing_of(&self, s: &Sheared<F>, segment: bool) -> Crossing {
        let [e0, e1, e2] = s.e;
        let zero = F::zero();
        let positive = e0 > zero || e1 > zero || e2 > zero;
        let negative = e0 < zero || e1 < zero || e2 < zero;
        let sheared = self.sheared_error(s.reach);
        let edge = F::of(Self::edge_error(s.reach_across, sheared));
        if positive && negative {
            let clearly_positive = e0 > edge || e1 > edge || e2 > edge;
            let clearly_negative = e0 < -edge || e1 < -edge || e2 < -edge;
            if clearly_positive && clearly_negative {
                return Crossing::Miss;
            }
        }
        self.crossing_near(s, edge.into(), segment)
    }

    /// The rest of `crossing`, for a triangle the line may meet.
    #[cold]
    #[inline(never)]
    fn crossing_near(&self, s: &Sheared<F>, edge: f64, segment: bool) -> Crossing {
        let e = s.e.map(|e| e.into());
        let z = s.z.map(|z| z.into());
        let u = F::UNIT_ROUNDOFF;
        // z* of each vertex: `distance_error_coefficients`' bound, evaluated as the vectorised
        // crossings evaluate it (own_crossing.rs), so that they are the same bits.
        let z_error = 2.0
            * (2.0 * self.origin_error
                + self.scale_error * (2.01 * s.reach + self.origin_error)
                + 8.0 * u * s.reach);
        let (z_min, z_max) = (z[0].min(z[1]).min(z[2]), z[0].max(z[1]).max(z[2]));
        // A hit's distance is a convex combination of the vertices' z.
        if z_max + z_error < 0.0 || z_min - z_error > self.length_hi {
            return Crossing::Miss;
        }
        let all_clear =
            (e[0] > edge && e[1] > edge && e[2] > edge) || (e[0] < -edge && e[1] < -edge && e[2] < -edge);
        // The crossing is a convex combination of the exact vertices, so its distance lies
        // within their z range: often bound enough (the common hit, decided before the
        // division below), and far tighter than the bound below for a triangle wholly ahead of
        // the origin.
        let (range_lo, range_hi) = (z_min - z_error, z_max + z_error);
        if all_clear && segment && range_lo > 0.0 && range_hi < self.length_lo {
            return Crossing::Through { t_lo: range_lo, t_hi: range_hi };
        }
        let det = e[0] + e[1] + e[2];
        let t = (e[0] * z[0] + e[1] * z[1] + e[2] * z[2]) / det;
        if !all_clear {
            let signs_agree = !(e.iter().any(|&e| e > 0.0) && e.iter().any(|&e| e < 0.0)) && det != 0.0;
            return Crossing::Doubt { likely_hit: signs_agree && t > 0.0 && t <= self.length_hi };
        }
        // t* = Σe*z*/Σe*: |N − N*| ≤ 3·edge·Z + (|det| + 3·edge)·z_error, |det − det*| ≤ 3·edge,
        // and the f64 evaluation's own rounding (2⁻⁵⁰ of the terms).
        let z_abs = z_min.abs().max(z_max.abs());
        let numerator_error =
            3.0 * edge * (z_abs + z_error) + det.abs() * z_error + 2f64.powi(-50) * det.abs() * z_abs;
        let det_error = 3.0 * edge;
        let t_error = 2.0 * (numerator_error + t.abs() * det_error) / (det.abs() - det_error)
            + 2f64.powi(-50) * t.abs();
        Crossing::Through { t_lo: (t - t_error).max(range_lo), t_hi: (t + t_error).min(range_hi) }
    }
}

impl CertifiedRay<f32> {
    /// `new` for the f32 ray `walk` is: `WatertightRay::new` computes the same axis order and
    /// shear factors by the same operations, so they are taken rather than computed again
    /// (a shadow ray's setup is a large part of its cost in a simple scene).
    pub(in crate::trace) fn of_walk(
        walk: &WatertightRay,
        origin_error: f64,
        direction_error: f64,
        length: f64,
        length_error: f64,
    ) -> Self {
        Self::sheared(
            walk.origin.to_array(),
            [walk.kx, walk.ky, walk.kz],
            [walk.sx, walk.sy, walk.sz],
            origin_error,
            direction_error,
            length,
            length_error,
        )
    }
}

/// How far a walk looks along a segment whose exact length lies within `length_error` of
/// `length`: its upper bound, rounded up to f32 (∞ for a ray without end).
pub(in crate::trace) fn walk_limit(length: f64, length_error: f64) -> f32 {
    let reach = length + length_error;
    if reach.is_finite() { (reach as f32).next_up() } else { f32::INFINITY }
}

/// What the certified test says of the exact line and a triangle, before the segment's ends.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(in crate::trace) enum Crossing {
    Miss,
    Doubt {
        likely_hit: bool,
    },
    /// The line certainly crosses the triangle's interior at a distance t* ∈ [t_lo, t_hi].
    Through {
        t_lo: f64,
        t_hi: f64,
    },
}

/// Whether every vertex of `other` lies exactly in the plane of `surface` (Shewchuk's exact
/// orientation test). An exact zero takes orient3d's slowest, exact stage, and the rays of
/// neighbouring pixels ask it of the same pair again and again (every pixel of a surface under a
/// decal), so each thread keeps its last answers, keyed by the coordinates themselves (so valid
/// for any scene).
pub(in crate::trace) fn in_one_plane(surface: &[Vec3; 3], other: &[Vec3; 3]) -> bool {
    let (key, slot) = pair_key(surface, other);
    COPLANAR.with_borrow_mut(|memo| match memo[slot] {
        Some((k, answer)) if k == key => answer,
        _ => {
            let answer = orient_all_zero(surface, other);
            memo[slot] = Some((key, answer));
            answer
        }
    })
}

/// Whether this thread already found `other` exactly in the plane of `surface` (`in_one_plane`),
/// without computing it: lets a shadow ray skip the f64 test of a triangle that can never
/// occlude it.
pub(in crate::trace) fn known_in_one_plane(surface: &[Vec3; 3], other: &[Vec3; 3]) -> bool {
    let (key, slot) = pair_key(surface, other);
    COPLANAR.with_borrow(|memo| memo[slot] == Some((key, true)))
}

/// The pair itself, and its slot: a hash of a few coordinates (cheap, since every doubt far from
/// the origin asks; the full key is compared).
fn pair_key(surface: &[Vec3; 3], other: &[Vec3; 3]) -> (PairKey, usize) {
    let bits =
        [surface[0].x, surface[1].y, surface[2].z, other[0].x, other[1].y, other[2].z].map(f32::to_bits);
    let hash = bits.iter().fold(0u32, |h, &x| (h.rotate_left(5) ^ x).wrapping_mul(0x9E37_79B9));
    ((*surface, *other), (hash >> 28) as usize % COPLANAR_SLOTS)
}

/// Two triangles, as asked (coordinates are finite: `==` is equality of the values, and ±0
/// lie in the same planes).
type PairKey = ([Vec3; 3], [Vec3; 3]);

const COPLANAR_SLOTS: usize = 16;

thread_local! {
    static COPLANAR: std::cell::RefCell<[Option<(PairKey, bool)>; COPLANAR_SLOTS]> =
        const { std::cell::RefCell::new([None; COPLANAR_SLOTS]) };
}

fn orient_all_zero(surface: &[Vec3; 3], other: &[Vec3; 3]) -> bool {
    let c = |v: Vec3| robust::Coord3D { x: v.x as f64, y: v.y as f64, z: v.z as f64 };
    let [a, b, d] = surface.map(c);
    other.iter().all(|&v| robust::orient3d(a, b, d, c(v)) == 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trace::splitmix::SplitMix64;
    use glam::DVec3;

    /// The remembered answers are the computed ones, whatever the order of the questions and
    /// however many pairs share a slot: coplanar pairs on a lattice and pairs one ulp off it.
    #[test]
    fn remembered_coplanarity_is_the_computed_one() {
        let mut rng = SplitMix64::new(11);
        let plane = |x: f32, z: f32| Vec3::new(x, x / 8.0 + z / 16.0, z);
        let pairs: Vec<([Vec3; 3], [Vec3; 3])> = (0..200)
            .map(|k| {
                let mut p = || {
                    plane(rng.range([-64.0, 64.0]).round() as f32, rng.range([-64.0, 64.0]).round() as f32)
                };
                let surface = [p(), p(), p()];
                let mut other = [p(), p(), p()];
                if k % 3 == 0 {
                    other[1].y = other[1].y.next_up();
                }
                (surface, other)
            })
            .collect();
        let mut coplanar = 0;
        for round in 0..3 {
            for (k, (surface, other)) in pairs.iter().enumerate().rev().skip(round) {
                let expected = orient_all_zero(surface, other);
                assert!(expected || !known_in_one_plane(surface, other), "round {round}, pair {k}");
                assert_eq!(in_one_plane(surface, other), expected, "round {round}, pair {k}");
                assert_eq!(
                    known_in_one_plane(surface, other),
                    expected,
                    "just asked: round {round}, pair {k}"
                );
                coplanar += expected as usize;
            }
        }
        assert!(coplanar > 100, "both kinds of pair are needed ({coplanar} coplanar)");
    }

    /// The exact answer for the closed segment [o, l] and the closed triangle t (points exact
    /// in f64), from Shewchuk's exact orientations: the ends on opposite sides of the plane (or
    /// one on it) and the line through the triangle, its three edge volumes never of opposite
    /// signs.
    fn exact_meets(o: Vec3, l: Vec3, t: &[Vec3; 3]) -> bool {
        exact_meets_f64(o.as_dvec3(), l.as_dvec3(), &t.map(Vec3::as_dvec3))
    }

    fn exact_meets_f64(o: DVec3, l: DVec3, t: &[DVec3; 3]) -> bool {
        let c = |v: DVec3| robust::Coord3D { x: v.x, y: v.y, z: v.z };
        let sign = |a: DVec3, b: DVec3, d: DVec3, e: DVec3| {
            robust::orient3d(c(a), c(b), c(d), c(e)).partial_cmp(&0.0).unwrap()
        };
        let (so, sl) = (sign(t[0], t[1], t[2], o), sign(t[0], t[1], t[2], l));
        if so == sl && so != std::cmp::Ordering::Equal {
            return false;
        }
        let edges = [sign(o, l, t[0], t[1]), sign(o, l, t[1], t[2]), sign(o, l, t[2], t[0])];
        let (lt, gt) =
            (edges.contains(&std::cmp::Ordering::Less), edges.contains(&std::cmp::Ordering::Greater));
        !(lt && gt)
    }

    /// Segments between f32 points near the origin and 10⁵ away, aimed at random triangles,
    /// at their edges and vertices: every certain verdict of either precision is the exact one,
    /// and most are certain (the test would pass vacuously if everything were in doubt).
    #[test]
    fn certain_verdicts_are_the_exact_ones() {
        let mut rng = SplitMix64::new(11);
        let (mut decided, mut total) = (0usize, 0usize);
        for round in 0..20_000 {
            let offset = [0.0, 1e3, 1e5][round % 3];
            let point = |rng: &mut SplitMix64, s: f64| {
                DVec3::from_array(std::array::from_fn(|_| rng.range([-s, s]))) + offset
            };
            let t = [point(&mut rng, 1.0), point(&mut rng, 1.0), point(&mut rng, 1.0)].map(|p| p.as_vec3());
            let o = point(&mut rng, 3.0).as_vec3();
            // The far end aimed at the triangle, at one of its edges or at a vertex.
            let (a, b) = (rng.range([0.0, 1.0]), rng.range([0.0, 1.0]));
            let target = match round % 4 {
                0 => {
                    t[0].as_dvec3() + a * (t[1] - t[0]).as_dvec3() + (1.0 - a) * b * (t[2] - t[0]).as_dvec3()
                }
                1 => t[0].as_dvec3() + a * (t[1] - t[0]).as_dvec3(),
                2 => t[(round / 4) % 3].as_dvec3(),
                _ => point(&mut rng, 2.0),
            };
            let l = (o.as_dvec3() + (target - o.as_dvec3()) * rng.range([0.5, 2.0])).as_vec3();
            let exact = exact_meets(o, l, &t);
            let to = l.as_dvec3() - o.as_dvec3();
            let (length, direction) = (to.length(), to.normalize());
            let direction_error =
                2.0 * 3f64.sqrt() * f64::EPSILON * to.abs().max_element() / length + 4.0 * f64::EPSILON;
            let length_error = 4.0 * f64::EPSILON * length;
            let fast = CertifiedRay::<f32>::new(
                o.to_array(),
                0.0,
                direction.as_vec3().to_array(),
                direction_error + 2f64.powi(-24),
                length,
                length_error,
            );
            let precise = CertifiedRay::<f64>::new(
                o.as_dvec3().to_array(),
                0.0,
                direction.to_array(),
                direction_error,
                length,
                length_error,
            );
            for verdict in [
                fast.classify(&t.map(|v| v.to_array())),
                precise.classify(&t.map(|v| v.as_dvec3().to_array())),
            ] {
                total += 1;
                match verdict {
                    Verdict::Hit => assert!(exact, "round {round}: a certain hit the exact test misses"),
                    Verdict::Miss => assert!(!exact, "round {round}: a certain miss the exact test meets"),
                    Verdict::Doubt { .. } => continue,
                }
                decided += 1;
            }
        }
        assert!(decided * 10 > total * 8, "only {decided} of {total} verdicts were certain");
    }

    /// Rays as the primary rays are (an f32 origin and an f32 direction, exact) towards small
    /// triangles far along them, aimed at their interiors, edges and vertices: every certain
    /// verdict in f32 is the exact one, and nearly every ray aimed at an interior or at random
    /// near the triangle is certain. The edge functions' bound scales with the sheared
    /// coordinates across the ray, not with the distance along it; scaled with the distance, as
    /// it once was, it left most of those in doubt.
    #[test]
    fn small_triangles_far_along_the_ray_are_decided_exactly_in_f32() {
        let mut rng = SplitMix64::new(12);
        let (mut decided, mut total) = (0usize, 0usize);
        for round in 0..20_000 {
            let vector =
                |rng: &mut SplitMix64, s: f64| DVec3::from_array(std::array::from_fn(|_| rng.range([-s, s])));
            // Multiples of 2⁻²⁰, so that the far end below is exact.
            let o = (vector(&mut rng, 1.0) * 2f64.powi(20)).round().as_vec3() * 2f32.powi(-20);
            let (distance, size) = (rng.range([10.0, 100.0]), rng.range([0.05, 0.5]));
            let centre = o.as_dvec3() + distance * vector(&mut rng, 1.0).normalize();
            let t = [0, 1, 2].map(|_| (centre + size * vector(&mut rng, 1.0)).as_vec3());
            let (a, b) = (rng.range([0.0, 1.0]), rng.range([0.0, 1.0]));
            let [t0, t1, t2] = t.map(Vec3::as_dvec3);
            let target = match round % 4 {
                0 => t0 + a * (t1 - t0) + (1.0 - a) * b * (t2 - t0),
                1 => t0 + a * (t1 - t0),
                2 => [t0, t1, t2][(round / 4) % 3],
                _ => centre + size * vector(&mut rng, 2.0),
            };
            let d = (target - o.as_dvec3()).normalize().as_vec3();
            // The ray's far end 2¹² along it, exact in f64: 2¹²·d and o span fewer than 53 bits
            // (unless a component of d is below 2⁻²⁹, about once in 10⁹).
            let far = o.as_dvec3() + 4096.0 * d.as_dvec3();
            let exact = exact_meets_f64(o.as_dvec3(), far, &t.map(Vec3::as_dvec3));
            let fast = CertifiedRay::<f32>::new(o.to_array(), 0.0, d.to_array(), 0.0, 4096.0, 0.0);
            let away_from_edges = round % 4 == 0 || round % 4 == 3;
            total += away_from_edges as usize;
            match fast.classify(&t.map(|v| v.to_array())) {
                Verdict::Hit => assert!(exact, "round {round}: a certain hit the exact test misses"),
                Verdict::Miss => assert!(!exact, "round {round}: a certain miss the exact test meets"),
                Verdict::Doubt { .. } => continue,
            }
            decided += away_from_edges as usize;
        }
        assert!(decided * 10 > total * 9, "only {decided} of {total} verdicts were certain in f32");
    }
}
