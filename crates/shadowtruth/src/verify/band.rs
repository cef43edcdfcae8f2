//! The error band (docs/reference.md, "Which pixels can still differ"): whether the tracer's
//! f32 arithmetic is certain to decide one triangle the way the exact test does.
//!
//! The tracer tests a ray that differs from the exact segment by the origin offset (at most
//! r_p), by the rounding of its direction (2⁻²³ radians, so 2⁻²³·R sideways at distance R) and
//! by the rounding of its triangle test: pbrt-v4's bounds on the sheared coordinates (under
//! 20u·R for vertices within R of p, u = 2⁻²⁴), on the edge functions (2u·|q_i||q_j| per
//! product pair) and on the hit distance (δt). Each bound is taken with a safety factor of 2 to
//! 4. A triangle is a *robust hit* when every such perturbation still crosses it strictly
//! inside, beyond δt from the origin and short of the light; a *robust miss* when every
//! perturbation misses it; otherwise it is *fragile*: its exact answer lies inside the band and
//! either answer is accepted. Computed in f64, whose rounding (2⁻⁵³) is far below every term.

use crate::trace::SurfacePoint;
use glam::{DVec2, DVec3, Vec3};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Robustness {
    Hit,
    Miss,
    Fragile,
}

/// The exact segment as the band sees it: origin p, unit direction, length (∞ towards a
/// directional light) and r_p, the bound on how far the tracer's origin lies from p.
pub struct Frame {
    origin: DVec3,
    direction: DVec3,
    tangent: DVec3,
    bitangent: DVec3,
    length: f64,
    r_p: f64,
}

/// f32's unit roundoff and Higham's γ(n), written here again rather than taken from
/// `trace/bvh/watertight.rs`: the adjudicator shares no arithmetic with the tracer it checks.
const U: f64 = f32::EPSILON as f64 * 0.5;

fn gamma(n: f64) -> f64 {
    n * U / (1.0 - n * U)
}

impl Frame {
    /// `direction` need not be unit. r_p bounds how far the tracer's origin lies from p: the
    /// offset moves it by |n|·error along the unit normal n, then by at most one ulp per axis
    /// (2⁻²³·|p|, doubled for margin).
    pub fn new(point: &SurfacePoint, direction: DVec3, length: f64) -> Frame {
        let p = point.position;
        let d = direction.normalize();
        let tangent = d.any_orthonormal_vector();
        Frame {
            origin: p.as_dvec3(),
            direction: d,
            tangent,
            bitangent: d.cross(tangent),
            length,
            r_p: point.normal.abs().as_dvec3().dot(point.error.as_dvec3())
                + 2f64.powi(-22) * p.abs().as_dvec3().element_sum(),
        }
    }

    pub fn robustness(&self, triangle: &[Vec3; 3]) -> Robustness {
        let r = triangle.map(|v| v.as_dvec3() - self.origin);
        let z = r.map(|v| v.dot(self.direction));
        let q = r.map(|v| DVec2::new(v.dot(self.tangent), v.dot(self.bitangent)));
        let reach = r.iter().map(|v| v.length()).fold(0.0, f64::max);
        // Sideways error of the ray (origin offset, direction rounding) and of the vertices
        // (the test's shear), each with a factor 2–4 over pbrt-v4's bounds.
        let ray_error = self.r_p + 2f64.powi(-22) * reach;
        let vertex_error = 2f64.powi(-18) * reach;
        // Near the light's position (spot lights only: a directional light has no end).
        let r_far = if self.length.is_finite() { self.r_p + 2f64.powi(-22) * self.length } else { 0.0 };
        // Behind the origin, or beyond the light, whatever the perturbation.
        let (z_min, z_max) = (z[0].min(z[1]).min(z[2]), z[0].max(z[1]).max(z[2]));
        if z_max < -(self.r_p + vertex_error) || z_min > self.length + r_far + vertex_error {
            return Robustness::Miss;
        }
        // Edge functions opposite each vertex: twice the signed area of (origin, q_j, q_k).
        let edges = [(1, 2), (2, 0), (0, 1)].map(|(j, k)| {
            let e = q[j].perp_dot(q[k]);
            let error = ray_error * (q[k] - q[j]).length()
                + vertex_error * (q[j].length() + q[k].length() + vertex_error)
                + 8.0 * U * q[j].length() * q[k].length();
            (e, error)
        });
        let positive = edges.iter().filter(|(e, err)| *e > *err).count();
        let negative = edges.iter().filter(|(e, err)| *e < -*err).count();
        if positive > 0 && negative > 0 {
            return Robustness::Miss;
        }
        if positive < 3 && negative < 3 {
            return Robustness::Fragile;
        }
        // Strictly inside under every perturbation: where along the ray, and how surely.
        let det: f64 = edges.iter().map(|(e, _)| e).sum();
        let z_hit = (edges[0].0 * z[0] + edges[1].0 * z[1] + edges[2].0 * z[2]) / det;
        let gradient = ((z[1] - z[0]) * (q[2] - q[0]).perp() - (z[2] - z[0]) * (q[1] - q[0]).perp()).length()
            / det.abs();
        let z_error = (1.0 + gradient) * (ray_error + vertex_error);
        let max_edge = edges.iter().map(|(e, _)| e.abs()).fold(0.0, f64::max);
        let lateral = q.iter().map(|v| v.length()).fold(0.0, f64::max);
        let near = self.r_p + 2.0 * distance_error_bound(max_edge / det.abs(), det.abs(), lateral, reach);
        if z_hit < -(self.r_p + z_error) || z_hit > self.length + r_far + z_error {
            Robustness::Miss
        } else if z_hit >= near + z_error && z_hit <= self.length - r_far - near - z_error {
            Robustness::Hit
        } else {
            Robustness::Fragile
        }
    }
}

/// An upper bound on the tracer's δt (pbrt-v4 §6.8.4) for a triangle whose vertices lie within
/// `lateral` of the ray and `reach` of the origin. The shear maps a vector q across the ray to
/// (q_x − (d_x/d_z)·q_z, …), at most 2|q| since |d_x| ≤ |d_z|, and scales z by 1/|d_z| ≤ √3; it
/// maps the plane across the ray linearly with a Jacobian of at least 1, so the largest edge
/// function over their sum (`edge_ratio`) is the same as here, and δe over the sheared
/// determinant is at most δe over the determinant here (`det`).
fn distance_error_bound(edge_ratio: f64, det: f64, lateral: f64, reach: f64) -> f64 {
    let (max_xy, max_z) = (2.0 * lateral, 3f64.sqrt() * reach);
    let delta_z = gamma(3.0) * max_z;
    let delta_xy = gamma(5.0) * (max_xy + max_z);
    let delta_e = 2.0 * (gamma(2.0) * max_xy * max_xy + 2.0 * delta_xy * max_xy);
    3.0 * (gamma(3.0) * edge_ratio * max_z + delta_e / det * max_z + delta_z * edge_ratio)
}
