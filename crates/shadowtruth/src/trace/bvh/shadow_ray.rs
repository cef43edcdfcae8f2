//! Shadow rays that cannot hit the surface they leave (docs/reference.md, "Why a surface cannot
//! shadow itself"): the ray starts from the surface point moved along the normal just past a
//! rigorous bound on the point's rounding error (Pharr, Jakob & Humphreys, *Physically Based
//! Rendering*, 4th ed., §6.8.5–6), it never tests the triangle the point was interpolated from,
//! and the triangle test accepts only hits certainly in front of the origin
//! (`WatertightRay::intersect_beyond_error`). No scene-dependent epsilon enters.

use glam::{DVec3, Vec3};

/// A surface point as the shadow test needs it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// The f32 point interpolated from the triangle's vertices: what the reference is about.
    pub position: Vec3,
    /// Per axis, a bound on |position − the exact interpolated point| (`position_error`).
    pub error: Vec3,
    /// Unit geometric normal, on the side the shadow ray leaves towards.
    pub normal: Vec3,
    /// Scene id of the triangle the point lies on; shadow rays skip it.
    pub triangle: u32,
    /// The hit's barycentrics (b1, b2) on `vertices`: the exact point is
    /// v0 + b1·(v1 − v0) + b2·(v2 − v0) (docs/reference.md, "The definition").
    pub barycentric: [f32; 2],
    /// The f32 world vertices of `triangle`.
    pub vertices: [Vec3; 3],
}

/// A bound, per axis, on the distance between `p` (the f32 rounding of `barycentric_point`,
/// v0 + b1·(v1 − v0) + b2·(v2 − v0) evaluated in f64) and the exact value of that expression.
///
/// Rounding to f32 moves a value by at most 2⁻²⁴·|p|(1 + 2⁻²⁴) (and by at most 2⁻¹⁵⁰ below the
/// normal range); the f64 evaluation adds at most γ₆₄(4)·(|v0| + |v1| + |v2|) < 2⁻⁵¹·Σ|v| (two
/// differences, two products, two sums, each rounding once). Each term is doubled, and the
/// factor 1 + 2⁻²⁰ covers the few f32 roundings of the bound itself.
#[inline]
pub fn position_error(p: Vec3, triangle: &[Vec3; 3]) -> Vec3 {
    let sum_abs = triangle[0].abs() + triangle[1].abs() + triangle[2].abs();
    let bound = p.abs() * 2f32.powi(-23) + sum_abs * 2f32.powi(-50) + Vec3::splat(2f32.powi(-148));
    bound * (1.0 + 2f32.powi(-20))
}

/// The origin of a ray leaving the surface at `point` along its normal: moved by
/// d = |n|·error along the normal, then each coordinate rounded one more step away from the
/// surface. Every point of the box `position ± error` lies on the other side of the plane
/// through the origin with normal n (pbrt-v4's `OffsetRayOrigin`).
pub fn offset_ray_origin(point: &SurfacePoint) -> Vec3 {
    let n = point.normal;
    let d = n.abs().dot(point.error);
    let offset = n * d;
    let moved = point.position + offset;
    Vec3::from_array(std::array::from_fn(|k| {
        if offset[k] > 0.0 {
            moved[k].next_up()
        } else if offset[k] < 0.0 {
            moved[k].next_down()
        } else {
            moved[k]
        }
    }))
}

/// A shadow ray: from an offset origin, along a unit direction, up to `tmax`, never testing
/// `skip_triangle`.
#[derive(Clone, Copy, Debug)]
pub struct ShadowRay {
    pub origin: Vec3,
    pub direction: Vec3,
    pub tmax: f32,
    pub skip_triangle: u32,
}

impl ShadowRay {
    /// Towards the point `target` (a spot light's position, a sample of an area light): the
    /// segment ends there.
    pub fn to_point(point: &SurfacePoint, target: DVec3) -> ShadowRay {
        let origin = offset_ray_origin(point);
        let to = target - origin.as_dvec3();
        ShadowRay {
            origin,
            direction: to.normalize().as_vec3(),
            tmax: to.length() as f32,
            skip_triangle: point.triangle,
        }
    }

    /// Along the unit direction `towards_light` (a directional light), without end.
    pub fn along(point: &SurfacePoint, towards_light: DVec3) -> ShadowRay {
        ShadowRay {
            origin: offset_ray_origin(point),
            direction: towards_light.as_vec3(),
            tmax: f32::INFINITY,
            skip_triangle: point.triangle,
        }
    }
}
