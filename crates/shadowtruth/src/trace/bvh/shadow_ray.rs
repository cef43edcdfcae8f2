//! Shadow rays as the definition states them (docs/reference.md): from the exact surface point
//! on its triangle (the hit's barycentrics on the triangle's f32 vertices, never rounded into a
//! neighbour) towards the light, with rigorous bounds on how far their f64 numbers lie from the
//! exact segment, so that the certified test (certified.rs) can say when it is sure. The
//! triangle the point lies on is never tested; no scene-dependent epsilon enters.

use super::watertight::barycentric_point;
use glam::{DVec3, Vec3};

/// A surface point as the shadow test needs it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// The exact point rounded to f32: what the techniques shade (the reference is about the
    /// exact point, `exact_point`).
    pub position: Vec3,
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

impl SurfacePoint {
    /// Per axis, a bound on |position − the exact point| (`position_error`), computed when a
    /// caller needs it rather than for every shadow ray.
    pub fn position_error(&self) -> Vec3 {
        position_error(self.position, &self.vertices)
    }
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

/// A shadow ray: the exact segment of the definition (docs/reference.md) from a surface point
/// towards the light, as the certified test (certified.rs) needs it. The exact point is only
/// known to within `origin_error` of `origin`; the direction and length likewise.
#[derive(Clone, Copy, Debug)]
pub struct ShadowRay {
    /// The exact surface point rounded to f64 (`barycentric_point`).
    pub origin: DVec3,
    /// Per axis, a bound on |origin − the exact point|.
    pub origin_error: f64,
    /// Unit direction towards the light, and per axis a bound on its distance from the exact
    /// segment's unit direction (0 towards a directional light, whose f32 direction is exact).
    pub direction: DVec3,
    pub direction_error: f64,
    /// The segment's length (∞ towards a directional light) and a bound on its error.
    pub length: f64,
    pub length_error: f64,
    /// The triangle the point lies on: never tested, and triangles exactly in its plane never
    /// occlude (the segment leaves the plane at the point).
    pub skip_triangle: u32,
    pub surface: [Vec3; 3],
}

impl ShadowRay {
    /// Towards the point `target` (a spot light's position, a sample of an area light): the
    /// segment ends there.
    pub fn to_point(point: &SurfacePoint, target: DVec3) -> ShadowRay {
        let (origin, origin_error) = exact_point(point);
        let to = target - origin;
        let length = to.length();
        // The difference rounds by 2⁻⁵³ of itself and inherits the origin's error; a unit
        // vector turns by at most 2·|δ|/|v| under a change δ of v (√3 from the max-norm), and
        // the normalization rounds a few times more.
        let to_error = origin_error + f64::EPSILON * to.abs().max_element();
        ShadowRay {
            origin,
            origin_error,
            direction: to / length,
            direction_error: 2.0 * 3f64.sqrt() * to_error / length * (1.0 + 1e-9) + 4.0 * f64::EPSILON,
            length,
            length_error: 3f64.sqrt() * to_error + 4.0 * f64::EPSILON * length,
            skip_triangle: point.triangle,
            surface: point.vertices,
        }
    }

    /// Along the direction `towards_light` (a directional light's reversed f32 direction,
    /// exact), without end.
    pub fn along(point: &SurfacePoint, towards_light: DVec3) -> ShadowRay {
        let (origin, origin_error) = exact_point(point);
        ShadowRay {
            origin,
            origin_error,
            direction: towards_light,
            direction_error: 0.0,
            length: f64::INFINITY,
            length_error: 0.0,
            skip_triangle: point.triangle,
            surface: point.vertices,
        }
    }
}

/// The exact point v0 + b1·(v1 − v0) + b2·(v2 − v0) rounded to f64, and a bound per axis on
/// that rounding: the two f64 differences, two products and two sums each round by at most
/// 2⁻⁵³ of terms no larger than (1 + |b1| + |b2|)·Σ|v|, so 2⁻⁴⁹·(1 + |b1| + |b2|)·Σ|v| holds
/// with room to spare (plus the smallest normal f64, for underflow).
pub fn exact_point(point: &SurfacePoint) -> (DVec3, f64) {
    let [b1, b2] = point.barycentric;
    let p = barycentric_point(&point.vertices, [0.0, b1, b2]);
    let sum_abs = point.vertices.iter().map(|v| v.abs().max_element() as f64).sum::<f64>();
    let error = 2f64.powi(-49) * (1.0 + b1.abs() as f64 + b2.abs() as f64) * sum_abs + f64::MIN_POSITIVE;
    (p, error)
}
