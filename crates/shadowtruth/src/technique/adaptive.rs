//! Adaptive depth bias (Dou, Yan, Kerzner, Dai & Wyman, "Adaptive Depth Bias for Shadow Maps",
//! I3D 2014 / JCGT 3(4) 2014) and the enhanced epsilon of Ehm, Ederer, Klein & Nischwitz
//! ("Adaptive Depth Bias for Soft Shadows", WSCG 2015, Eq. 3–4); docs/formulas.md, "Adaptive
//! depth bias (Dou et al. 2014) and Δbias (Ehm et al. 2015)".
//!
//! The potential occluder is where the light's line through the centre of the receiver's texel
//! meets the receiver's tangent plane; the receiver is compared at `min(d_occluder, d_receiver)`
//! minus an adaptive epsilon, the world tolerance `K · sceneScale` converted to depth units at
//! the occluder's depth: `/(f − n)` for linear (orthographic) depth,
//! `·(f − d(f − n))²/(f·n·(f − n))` for perspective depth. The enhanced epsilon multiplies it by
//! `min(1/(N·L)², 100)`.
//!
//! The PCF biases `adaptive` and `adaptive_delta` (`pcf.rs`) take every tap's potential occluder
//! from `TangentPlane`, on the light's whole line through the tap texel (its one miss: a plane
//! the light sees edge-on), and subtract the epsilon at that occluder's depth. The single-tap
//! test keeps its guard (`potential_occluder_depth`).

use super::canonical::CanonicalFields;
use super::params::non_negative;
use super::{
    LayerNeeds, Sample, ShadeContext, Technique, TechniqueParams, TechniqueSpecError, texel_at, texel_centre,
};
use crate::raster::{LightView, Projection};
use glam::{DVec4, Vec3, Vec4};
use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EpsilonScale {
    /// Dou et al.: the epsilon alone.
    Original,
    /// Ehm et al.: times `min(1/(N·L)², threshold)` with threshold 100.
    Ehm,
}

pub struct AdaptiveBias {
    /// World-space tolerance as a fraction of the scene's size (the paper's K).
    pub k: f32,
    pub epsilon: EpsilonScale,
}

/// Ehm et al.'s cap on the 1/(N·L)² factor.
const EHM_THRESHOLD: f32 = 100.0;

/// |N·L| below which the light sees a tangent plane edge-on.
const EDGE_ON_COS: f32 = 1e-6;

/// One adaptive comparison: the texel read, the depth compared (`min(d_occluder, d_receiver)`)
/// and the epsilon subtracted from it. Lit when `compared − epsilon ≤ map(texel)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AdaptiveTest {
    pub texel: (u32, u32),
    pub occluder_depth: Option<f32>,
    pub compared_depth: f32,
    pub epsilon: f32,
}

impl AdaptiveBias {
    /// The comparison for `s`, or None when the receiver lies behind the light.
    pub fn test(&self, s: &Sample, ctx: &ShadeContext) -> Option<AdaptiveTest> {
        let uvd = ctx.view.project(s.position)?;
        let resolution = ctx.layers.resolution();
        let texel = texel_at(resolution, uvd.x, uvd.y);
        let occluder_depth = potential_occluder_depth(s, ctx, texel_centre(resolution, texel.0, texel.1));
        let epsilon = self.epsilon(s, ctx, occluder_depth.unwrap_or(uvd.z))?;
        let compared_depth = occluder_depth.map_or(uvd.z, |d| d.min(uvd.z));
        Some(AdaptiveTest { texel, occluder_depth, compared_depth, epsilon })
    }

    /// The adaptive epsilon in depth units at light depth `depth` for receiver `s` (None when the
    /// enhanced scale needs a direction to the light and there is none).
    pub fn epsilon(&self, s: &Sample, ctx: &ShadeContext, depth: f32) -> Option<f32> {
        Some(self.epsilon_of(s, ctx)?.at(depth))
    }

    /// Receiver `s`'s epsilon as a function of the potential occluder's depth.
    pub fn epsilon_of(&self, s: &Sample, ctx: &ShadeContext) -> Option<Epsilon> {
        let scale = match self.epsilon {
            EpsilonScale::Original => 1.0,
            EpsilonScale::Ehm => {
                let n_dot_l = s.normal.dot(to_light(ctx.view, s.position)?);
                (1.0 / (n_dot_l * n_dot_l)).min(EHM_THRESHOLD)
            }
        };
        Some(Epsilon::new(ctx.view, self.k * ctx.scene_scale * scale))
    }
}

/// One receiver's adaptive epsilon as a function of light depth d: its world tolerance times
/// ∂d/∂D at d, i.e. `c` (orthographic) or `c·(f − d(f − n))²` (perspective), with c folded once
/// per receiver.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Epsilon {
    c: f32,
    /// (f, f − n) of a perspective map.
    perspective: Option<(f32, f32)>,
}

impl Epsilon {
    /// No epsilon at all.
    pub const ZERO: Epsilon = Epsilon { c: 0.0, perspective: None };

    /// The epsilon of world tolerance `tolerance` (K · sceneScale, times Ehm's factor).
    pub fn new(view: &LightView, tolerance: f32) -> Self {
        let (n, f) = (view.near, view.far);
        match view.projection {
            // A paraboloid's depth is linear in the distance (its techniques are refused at plan
            // time: `Technique::needs_projective_map`).
            Projection::Orthographic { .. } | Projection::Paraboloid => {
                Epsilon { c: tolerance / (f - n), perspective: None }
            }
            Projection::Perspective { .. } => {
                Epsilon { c: tolerance / (f * n * (f - n)), perspective: Some((f, f - n)) }
            }
        }
    }

    /// `d` minus the epsilon at `d`: the depth a tap with potential occluder `d` compares.
    #[inline]
    pub fn below(&self, d: f32) -> f32 {
        d - self.at(d)
    }

    /// The epsilon at light depth `d`.
    #[inline]
    pub fn at(&self, d: f32) -> f32 {
        match self.perspective {
            None => self.c,
            Some((f, f_minus_n)) => {
                let s = f - d * f_minus_n;
                self.c * s * s
            }
        }
    }
}

/// The unit direction from `p` towards the light.
fn to_light(view: &LightView, p: Vec3) -> Option<Vec3> {
    match (view.to_light, view.position) {
        (Some(l), _) => Some(l),
        (None, Some(e)) => Some((e - p).normalize()),
        (None, None) => None,
    }
}

impl Technique for AdaptiveBias {
    fn layer_needs(&self) -> LayerNeeds {
        LayerNeeds::default()
    }

    /// The potential occluder lies on the light ray through a texel centre.
    fn needs_projective_map(&self) -> bool {
        true
    }

    fn visibility(&self, s: &Sample, ctx: &ShadeContext) -> f32 {
        match self.test(s, ctx) {
            Some(t) => {
                (t.compared_depth - t.epsilon <= ctx.layers.nearest().at(t.texel.0, t.texel.1)) as u8 as f32
            }
            None => 1.0,
        }
    }
}

/// Which adaptive epsilon a spec names: Dou et al.'s, or Ehm et al.'s scaled by
/// min(1/(N·L)², 100).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EpsilonSpec {
    #[default]
    Original,
    Ehm,
}

impl From<EpsilonSpec> for EpsilonScale {
    fn from(e: EpsilonSpec) -> EpsilonScale {
        match e {
            EpsilonSpec::Original => EpsilonScale::Original,
            EpsilonSpec::Ehm => EpsilonScale::Ehm,
        }
    }
}

/// The paper's K when a spec leaves it out (as a fraction of the scene's size).
pub(super) const DEFAULT_K: f64 = 1e-4;

fn default_k() -> f64 {
    DEFAULT_K
}

/// `adaptive`: the tolerance `k` (a fraction of the scene's size) and the epsilon's scale.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AdaptiveParams {
    #[serde(default = "default_k")]
    pub k: f64,
    #[serde(default)]
    pub epsilon: EpsilonSpec,
}

impl TechniqueParams for AdaptiveParams {
    fn validate(&self) -> Result<(), TechniqueSpecError> {
        non_negative("k", self.k)
    }

    fn build(&self) -> Option<Box<dyn Technique>> {
        Some(Box::new(AdaptiveBias { k: self.k as f32, epsilon: self.epsilon.into() }))
    }

    fn canonical_fields(&self, f: &mut CanonicalFields) {
        f.number("k", self.k);
        f.named("epsilon", self.epsilon);
    }
}

/// A receiver's tangent plane (its point and geometric normal), where potential occluders lie.
#[derive(Clone, Copy, Debug)]
pub struct TangentPlane {
    point: Vec3,
    normal: Vec3,
}

impl TangentPlane {
    /// The plane of `s`; None when the light sees it edge-on (|N·L| < 10⁻⁶: it contains the
    /// light's direction or position), where it has no depth at any texel. That is the one miss
    /// of the potential occluder: every tap then compares the receiver's own depth.
    pub fn of(s: &Sample, ctx: &ShadeContext) -> Option<Self> {
        let l = to_light(ctx.view, s.position)?;
        (s.normal.dot(l).abs() >= EDGE_ON_COS).then_some(TangentPlane { point: s.position, normal: s.normal })
    }

    /// Light depth of the potential occluder of texel centre (u_c, v_c): where the light's whole
    /// line through the centre meets the plane, in front of the near plane, past the far plane or
    /// behind the light alike. That is the plane's d = z/w continued over the map, affine in
    /// (u, v) for both projections, so Δbias's linear extrapolation is the same function.
    /// Computed in f64 from the f32 inputs (and rounded once by the caller).
    pub fn depth_at(&self, ctx: &ShadeContext, (u_c, v_c): (f32, f32)) -> f64 {
        let (x_ndc, y_ndc) = (2.0 * u_c as f64 - 1.0, 2.0 * v_c as f64 - 1.0);
        // A point of the line at light depth d, and its clip w (D for a spot light, 1 otherwise).
        let unproject = |d: f64| {
            let h = ctx.world_from_clip_f64 * DVec4::new(x_ndc, y_ndc, d, 1.0);
            (h.truncate() / h.w, 1.0 / h.w)
        };
        let ((near_point, w0), (far_point, w1)) = (unproject(0.0), unproject(1.0));
        // The plane meets the line at t = num/den from its d = 0 point to its d = 1 point; z and w
        // are affine along it, so d = t·w1/((1 − t)·w0 + t·w1), here multiplied through by den:
        // finite for a line parallel to the plane (d = w1/(w1 − w0), f/(f − n) for a spot light)
        // and for a meeting point behind the light (d > 1).
        let normal = self.normal.as_dvec3();
        let num = normal.dot(self.point.as_dvec3() - near_point);
        let den = normal.dot(far_point - near_point);
        num * w1 / ((den - num) * w0 + num * w1)
    }
}

/// The single-tap test's potential occluder at its own texel centre (u_c, v_c), in f32: on the
/// light's ray ahead of the near plane only. None when the ray is (nearly) parallel to the plane
/// or meets it before the near plane or behind the light; the receiver's own depth is used then.
/// (The PCF taps take theirs from `TangentPlane`, on the whole line.)
pub fn potential_occluder_depth(s: &Sample, ctx: &ShadeContext, (u_c, v_c): (f32, f32)) -> Option<f32> {
    let (x_ndc, y_ndc) = (2.0 * u_c - 1.0, 2.0 * v_c - 1.0);
    let unproject = |d: f32| {
        let h = ctx.world_from_clip * Vec4::new(x_ndc, y_ndc, d, 1.0);
        h.truncate() / h.w
    };
    let (near_point, far_point) = (unproject(0.0), unproject(1.0));
    let dir = far_point - near_point;
    let denom = s.normal.dot(dir);
    if denom.abs() < 1e-6 * dir.length() {
        return None;
    }
    let t = s.normal.dot(s.position - near_point) / denom;
    if t <= 0.0 {
        return None;
    }
    ctx.view.project(near_point + dir * t).map(|p| p.z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::raster::DepthLayer;
    use crate::scene::{PixelFootprint, Scene, load_scene_str};
    use crate::technique::Layers;
    use std::path::Path;

    /// A 4×4 plane under `light` (JSON).
    fn scene(light: &str) -> Scene {
        let text = format!(
            r#"{{ "format": "shadowtruth/scene/v1", "name": "t",
                 "objects": [{{ "name": "p", "shape": {{ "type": "plane", "size": [4, 4] }} }}],
                 "cameras": [{{ "name": "c", "position": [0, 5, 5], "look_at": [0, 0, 0], "fov_y_deg": 45,
                                "width": 8, "height": 8 }}],
                 "lights": [{light}] }}"#
        );
        load_scene_str(&text, Path::new("t.json"), Path::new(".")).unwrap()
    }

    const SUN: &str = r#"{ "name": "sun", "type": "directional", "direction": [0.3, -1, 0.2] }"#;
    const LAMP: &str = r#"{ "name": "lamp", "type": "spot", "position": [0, 10, 0], "direction": [0, -1, 0],
                           "cone_deg": 90, "near": 1, "far": 21 }"#;

    fn with_context(light: &str, f: impl FnOnce(&ShadeContext)) {
        let scene = scene(light);
        let view = LightView::new(&scene.lights[0], scene.bounds(), 16);
        let map = DepthLayer::new_empty(16);
        f(&ShadeContext::new(&scene, PixelFootprint::of(&scene.cameras[0]), &view, Layers::Nearest(&map)));
    }

    fn steep_receiver() -> Sample {
        Sample {
            position: Vec3::new(0.2, 1.5, -0.1),
            normal: Vec3::new(-3.0, 1.0, 0.5).normalize(),
            triangle: 0,
        }
    }

    #[test]
    fn the_potential_occluder_depth_is_affine_in_the_map_under_both_projections() {
        // d = z/w over a plane is affine in (u, v), ahead of the near plane, past the far plane
        // and behind the light alike: four centres spanning the map, the fourth from the others.
        for light in [SUN, LAMP] {
            with_context(light, |ctx| {
                let plane = TangentPlane::of(&steep_receiver(), ctx).unwrap();
                let at = |u: f32, v: f32| plane.depth_at(ctx, (u, v));
                for (u, v) in [(0.9, 0.1), (-0.5, 1.5), (2.0, -1.0)] {
                    let affine = at(0.5, 0.5)
                        + (at(0.75, 0.5) - at(0.5, 0.5)) * ((u as f64 - 0.5) / 0.25)
                        + (at(0.5, 0.75) - at(0.5, 0.5)) * ((v as f64 - 0.5) / 0.25);
                    let d = at(u, v);
                    assert!((d - affine).abs() < 1e-9 * d.abs().max(1.0), "({u}, {v}): {d} vs {affine}");
                }
                // Not vacuous: the plane's depth leaves [0, 1] over that span.
                assert!(at(-0.5, 1.5).min(at(2.0, -1.0)) < 0.0 || at(-0.5, 1.5).max(at(2.0, -1.0)) > 1.0);
            });
        }
    }

    #[test]
    fn a_line_parallel_to_the_plane_meets_it_at_the_depth_of_infinity() {
        // Under the lamp the line through centre (0.5, 0.75) runs along (0.5, −1, 0); the plane
        // through (1, 0, 0) with normal (2, 1, 0) holds that direction: D → ∞, d → f/(f − n).
        with_context(LAMP, |ctx| {
            let s = Sample { position: Vec3::X, normal: Vec3::new(2.0, 1.0, 0.0).normalize(), triangle: 0 };
            let d = TangentPlane::of(&s, ctx).unwrap().depth_at(ctx, (0.5, 0.75));
            assert!((d - 21.0 / 20.0).abs() < 1e-6, "{d}");
        });
    }

    #[test]
    fn a_plane_seen_edge_on_has_no_potential_occluder() {
        let holding = |l: Vec3| Sample {
            position: Vec3::new(0.0, 2.0, 0.0),
            normal: l.any_orthonormal_vector(),
            triangle: 0,
        };
        with_context(SUN, |ctx| {
            assert!(TangentPlane::of(&holding(ctx.view.to_light.unwrap()), ctx).is_none())
        });
        with_context(LAMP, |ctx| assert!(TangentPlane::of(&holding(Vec3::Y), ctx).is_none()));
    }

    #[test]
    fn the_epsilon_is_the_tolerance_times_the_depth_slope_at_the_occluder() {
        with_context(SUN, |ctx| {
            let (n, f) = (ctx.view.near, ctx.view.far);
            assert!((Epsilon::new(ctx.view, 0.01).at(0.7) - 0.01 / (f - n)).abs() < 1e-9);
        });
        with_context(LAMP, |ctx| {
            for big_d in [1.5f64, 4.0, 12.0] {
                // ∂d/∂D = f·n/((f − n)·D²) at d(D) = f(D − n)/(D(f − n)).
                let d = 21.0 * (big_d - 1.0) / (big_d * 20.0);
                let expected = 0.01 * 21.0 / (20.0 * big_d * big_d);
                let eps = Epsilon::new(ctx.view, 0.01).at(d as f32) as f64;
                assert!((eps - expected).abs() < 1e-5 * expected, "D = {big_d}: {eps} vs {expected}");
            }
        });
    }
}
