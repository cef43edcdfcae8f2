//! Watertight ray–triangle intersection (Woop, Benthin & Wald, "Watertight Ray/Triangle
//! Intersection", JCGT 2(1), 2013). A ray through a shared edge or vertex hits at least one of
//! the triangles that share it, which obvhs's own Möller–Trumbore test does not guarantee.

use glam::{DVec3, Vec3A};

/// A ray prepared for the watertight test: the axis permutation and shear are per ray.
#[derive(Clone, Copy, Debug)]
pub struct WatertightRay {
    pub origin: Vec3A,
    pub direction: Vec3A,
    kx: usize,
    ky: usize,
    kz: usize,
    sx: f32,
    sy: f32,
    sz: f32,
}

/// A hit: distance along the (unit) direction and the barycentric weights of v0, v1, v2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayTriangleHit {
    pub t: f32,
    pub barycentric: [f32; 3],
}

impl WatertightRay {
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

    /// The hit with t in the closed interval [tmin, tmax], from either side of the triangle.
    #[inline]
    pub fn intersect(&self, v0: Vec3A, v1: Vec3A, v2: Vec3A, tmin: f32, tmax: f32) -> Option<RayTriangleHit> {
        let (kx, ky, kz) = (self.kx, self.ky, self.kz);
        let a = v0 - self.origin;
        let b = v1 - self.origin;
        let c = v2 - self.origin;
        let ax = a[kx] - self.sx * a[kz];
        let ay = a[ky] - self.sy * a[kz];
        let bx = b[kx] - self.sx * b[kz];
        let by = b[ky] - self.sy * b[kz];
        let cx = c[kx] - self.sx * c[kz];
        let cy = c[ky] - self.sy * c[kz];
        let u = cx * by - cy * bx;
        let v = ax * cy - ay * cx;
        let w = bx * ay - by * ax;
        // An edge function that is exactly zero in f32 (a ray through an edge or vertex, or a
        // product that underflowed on a tiny triangle) sends the whole test to f64, so that the
        // two triangles sharing an edge agree on the sign.
        if u == 0.0 || v == 0.0 || w == 0.0 {
            let z = [self.sz * a[kz], self.sz * b[kz], self.sz * c[kz]];
            return intersect_f64([ax, ay, bx, by, cx, cy], z, tmin, tmax);
        }
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v + w;
        if det == 0.0 {
            return None;
        }
        let az = self.sz * a[kz];
        let bz = self.sz * b[kz];
        let cz = self.sz * c[kz];
        let t_scaled = u * az + v * bz + w * cz;
        // A division (not a multiplication by 1/det) keeps t exact when the hit distance is.
        let t = t_scaled / det;
        let inv_det = 1.0 / det;
        if !(t >= tmin && t <= tmax) {
            return None;
        }
        Some(RayTriangleHit { t, barycentric: [u * inv_det, v * inv_det, w * inv_det] })
    }
}

/// The watertight test in f64 on the sheared vertices (x, y of A, B, C) and their scaled z.
#[cold]
fn intersect_f64(xy: [f32; 6], z: [f32; 3], tmin: f32, tmax: f32) -> Option<RayTriangleHit> {
    let [ax, ay, bx, by, cx, cy] = xy.map(|x| x as f64);
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
    let t = ((u * z[0] as f64 + v * z[1] as f64 + w * z[2] as f64) / det) as f32;
    if !(t >= tmin && t <= tmax) {
        return None;
    }
    Some(RayTriangleHit { t, barycentric: [(u / det) as f32, (v / det) as f32, (w / det) as f32] })
}

/// The point of a hit from the triangle's vertices and barycentrics, in f64 (not origin + t·dir).
pub fn barycentric_point(v: &[glam::Vec3; 3], barycentric: [f32; 3]) -> DVec3 {
    let (v0, v1, v2) = (v[0].as_dvec3(), v[1].as_dvec3(), v[2].as_dvec3());
    let (b1, b2) = (barycentric[1] as f64, barycentric[2] as f64);
    v0 + b1 * (v1 - v0) + b2 * (v2 - v0)
}
