//! Watertight ray–triangle intersection (Woop, Benthin & Wald, "Watertight Ray/Triangle
//! Intersection", JCGT 2(1), 2013). A ray through a shared edge or vertex hits at least one of
//! the triangles that share it, which obvhs's own Möller–Trumbore test does not guarantee.
//!
//! The hard reference's shadow rays use the certified form of this test (certified.rs);
//! `intersect_beyond_error` also bounds the rounding error of the hit distance (Pharr, Jakob &
//! Humphreys, *Physically Based Rendering*, 4th ed., §6.8.4) and accepts a hit only when its
//! distance is positive beyond that bound.

use glam::{DVec3, Vec3A};

/// A ray prepared for the watertight test: the axis permutation and shear are per ray.
#[derive(Clone, Copy, Debug)]
pub struct WatertightRay {
    pub origin: Vec3A,
    pub direction: Vec3A,
    pub(in crate::trace) kx: usize,
    pub(in crate::trace) ky: usize,
    pub(in crate::trace) kz: usize,
    pub(in crate::trace) sx: f32,
    pub(in crate::trace) sy: f32,
    pub(in crate::trace) sz: f32,
}

/// A hit: distance along the (unit) direction and the barycentric weights of v0, v1, v2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayTriangleHit {
    pub t: f32,
    pub barycentric: [f32; 3],
}

/// A triangle in the ray's sheared frame: the ray runs along +z through (0, 0).
struct Sheared {
    /// x, y of the vertices A, B, C.
    x: [f32; 3],
    y: [f32; 3],
    /// z of the vertices before scaling by `sz` (scaled only once a hit is likely).
    z_unscaled: [f32; 3],
    sz: f32,
    /// Edge functions: twice the signed areas opposite A, B and C; the unnormalised barycentrics.
    e: [f32; 3],
}

/// γ(n) of Higham: n f32 roundings (unit roundoff u = 2⁻²⁴) compound to at most γ(n)·|x|.
const fn gamma(n: i32) -> f64 {
    let u = f32::EPSILON as f64 * 0.5;
    n as f64 * u / (1.0 - n as f64 * u)
}

impl WatertightRay {
    /// A placeholder for storage that rays are written into before use.
    pub(in crate::trace) const UNUSED: WatertightRay = WatertightRay {
        origin: Vec3A::ZERO,
        direction: Vec3A::Z,
        kx: 0,
        ky: 1,
        kz: 2,
        sx: 0.0,
        sy: 0.0,
        sz: 1.0,
    };

    pub fn new(origin: Vec3A, direction: Vec3A) -> Self {
        let abs = direction.abs();
        let kz = if abs.x > abs.y {
            if abs.x > abs.z { 0 } else { 2 }
        } else if abs.y > abs.z {
            1
        } else {
            2
        };
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        // Keep the winding of the projected triangle independent of the ray's octant.
        if direction[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let sz = 1.0 / direction[kz];
        WatertightRay { origin, direction, kx, ky, kz, sx: direction[kx] * sz, sy: direction[ky] * sz, sz }
    }

    #[inline(always)]
    fn shear(&self, v0: Vec3A, v1: Vec3A, v2: Vec3A) -> Sheared {
        // Indexing arrays, not `Vec3A`s (whose indexing by a run-time axis branches).
        let (kx, ky, kz) = (self.kx, self.ky, self.kz);
        let a = (v0 - self.origin).to_array();
        let b = (v1 - self.origin).to_array();
        let c = (v2 - self.origin).to_array();
        let x = [a[kx] - self.sx * a[kz], b[kx] - self.sx * b[kz], c[kx] - self.sx * c[kz]];
        let y = [a[ky] - self.sy * a[kz], b[ky] - self.sy * b[kz], c[ky] - self.sy * c[kz]];
        let e = [x[2] * y[1] - y[2] * x[1], x[0] * y[2] - y[0] * x[2], x[1] * y[0] - y[1] * x[0]];
        Sheared { x, y, z_unscaled: [a[kz], b[kz], c[kz]], sz: self.sz, e }
    }

    /// The hit with t in the closed interval [tmin, tmax], from either side of the triangle.
    #[inline]
    pub fn intersect(
        &self,
        v0: impl Into<Vec3A>,
        v1: impl Into<Vec3A>,
        v2: impl Into<Vec3A>,
        tmin: f32,
        tmax: f32,
    ) -> Option<RayTriangleHit> {
        let s = self.shear(v0.into(), v1.into(), v2.into());
        let solved = solve(&s)?;
        (solved.hit.t >= tmin && solved.hit.t <= tmax).then_some(solved.hit)
    }

    /// The distance of a hit whose distance is certainly positive (beyond the rounding bound of
    /// the test) and at most `tmax`: what a shadow ray counts as an occluder.
    #[inline]
    pub fn intersect_beyond_error(&self, v0: Vec3A, v1: Vec3A, v2: Vec3A, tmax: f32) -> Option<f32> {
        let s = self.shear(v0, v1, v2);
        let solved = solve(&s)?;
        let t = solved.hit.t;
        (t <= tmax && t as f64 > distance_error_bound(&s, &solved)).then_some(t)
    }
}

impl Sheared {
    /// The vertices' z scaled by `sz`: the hit distance is their barycentric mean.
    #[inline(always)]
    fn z(&self) -> [f32; 3] {
        self.z_unscaled.map(|z| self.sz * z)
    }
}

/// A hit with the edge functions it came from (in the precision that decided it).
struct Solved {
    hit: RayTriangleHit,
    max_abs_edge: f64,
    det: f64,
}

/// The hit of the ray with a sheared triangle, if the edge functions agree in sign.
#[inline(always)]
fn solve(s: &Sheared) -> Option<Solved> {
    let [u, v, w] = s.e;
    // An edge function that is exactly zero in f32 (a ray through an edge or vertex, or a
    // product that underflowed on a tiny triangle) sends the whole test to f64, so that the
    // two triangles sharing an edge agree on the sign.
    if u == 0.0 || v == 0.0 || w == 0.0 {
        return solve_f64(s);
    }
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return None;
    }
    let det = u + v + w;
    if det == 0.0 {
        return None;
    }
    let z = s.z();
    let t_scaled = u * z[0] + v * z[1] + w * z[2];
    // A division (not a multiplication by 1/det) keeps t exact when the hit distance is.
    let t = t_scaled / det;
    let inv_det = 1.0 / det;
    let max_abs_edge = u.abs().max(v.abs()).max(w.abs()) as f64;
    let hit = RayTriangleHit { t, barycentric: [u * inv_det, v * inv_det, w * inv_det] };
    Some(Solved { hit, max_abs_edge, det: det as f64 })
}

/// The watertight test in f64 on the sheared vertices.
#[cold]
fn solve_f64(s: &Sheared) -> Option<Solved> {
    let [ax, bx, cx] = s.x.map(|x| x as f64);
    let [ay, by, cy] = s.y.map(|y| y as f64);
    let u = cx * by - cy * bx;
    let v = ax * cy - ay * cx;
    let w = bx * ay - by * ax;
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return None;
    }
    let det = u + v + w;
    if det == 0.0 {
        return None;
    }
    let z = s.z();
    let t = ((u * z[0] as f64 + v * z[1] as f64 + w * z[2] as f64) / det) as f32;
    let hit = RayTriangleHit { t, barycentric: [(u / det) as f32, (v / det) as f32, (w / det) as f32] };
    Some(Solved { hit, max_abs_edge: u.abs().max(v.abs()).max(w.abs()), det })
}

/// A bound on |t − t_exact|, where t_exact is the distance along this ray (its f32 origin and
/// direction taken as exact) to the plane of the f32 triangle: pbrt-v4's error analysis of the
/// watertight test (§6.8.4), term for term. It bounds the rounding of the translation to the
/// origin, the shear, the edge functions and the final division, with the edge functions of
/// whichever precision decided the hit (the f64 path rounds less, so the bound holds for it).
/// Evaluated in f64 so that the bound itself neither rounds down nor underflows.
#[inline(always)]
fn distance_error_bound(s: &Sheared, solved: &Solved) -> f64 {
    let max3 = |v: [f32; 3]| v[0].abs().max(v[1].abs()).max(v[2].abs()) as f64;
    let (max_x, max_y, max_z, max_e) = (max3(s.x), max3(s.y), max3(s.z()), solved.max_abs_edge);
    let delta_z = gamma(3) * max_z;
    let delta_x = gamma(5) * (max_x + max_z);
    let delta_y = gamma(5) * (max_y + max_z);
    let delta_e = 2.0 * (gamma(2) * max_x * max_y + delta_y * max_x + delta_x * max_y);
    3.0 * (gamma(3) * max_e * max_z + delta_e * max_z + delta_z * max_e) / solved.det.abs()
}

/// The point of a hit from the triangle's vertices and barycentrics, in f64 (not origin + t·dir).
#[inline(always)]
pub fn barycentric_point(v: &[glam::Vec3; 3], barycentric: [f32; 3]) -> DVec3 {
    let (v0, v1, v2) = (v[0].as_dvec3(), v[1].as_dvec3(), v[2].as_dvec3());
    let (b1, b2) = (barycentric[1] as f64, barycentric[2] as f64);
    v0 + b1 * (v1 - v0) + b2 * (v2 - v0)
}
