//! Adaptive depth bias (Dou, Yan, Kerzner, Dai & Wyman, "Adaptive Depth Bias for Shadow Maps",
//! I3D 2014 / JCGT 3(4) 2014; formulas.md §5) and the enhanced epsilon of Ehm, Ederer, Klein &
//! Nischwitz ("Adaptive Depth Bias for Soft Shadows", WSCG 2015, Eq. 3–4).
//!
//! The potential occluder is where the light ray through the centre of the receiver's texel
//! meets the receiver's tangent plane; the receiver is compared at `min(d_occluder, d_receiver)`
//! minus an adaptive epsilon `K · sceneScale` converted to depth units at the occluder's depth:
//! `/(f − n)` for linear (orthographic) depth, `·(f − d(f − n))²/(f·n·(f − n))` for perspective
//! depth. The enhanced epsilon multiplies it by `min(1/(N·L)², 100)`.
//! The light ray is taken from the inverse light projection, so the same code serves both kinds.

use super::{LayerNeeds, Sample, ShadeContext, Technique, texel_at, texel_centre};
use crate::raster::Projection;
use glam::Vec4;

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
        let view = ctx.view;
        let (n, f) = (view.near, view.far);
        let world_tolerance = self.k * ctx.scene_scale;
        let mut epsilon = match view.projection {
            Projection::Orthographic { .. } => world_tolerance / (f - n),
            Projection::Perspective { .. } => {
                let s = f - depth * (f - n);
                world_tolerance * s * s / (f * n * (f - n))
            }
        };
        if self.epsilon == EpsilonScale::Ehm {
            let to_light = match (view.to_light, view.position) {
                (Some(l), _) => l,
                (None, Some(p)) => (p - s.position).normalize(),
                (None, None) => return None,
            };
            let n_dot_l = s.normal.dot(to_light);
            epsilon *= (1.0 / (n_dot_l * n_dot_l)).min(EHM_THRESHOLD);
        }
        Some(epsilon)
    }
}

impl Technique for AdaptiveBias {
    fn layer_needs(&self) -> LayerNeeds {
        LayerNeeds::default()
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

/// Light depth of the potential occluder: the light ray through texel centre (u_c, v_c) meets the
/// receiver's tangent plane. None when the ray is (nearly) parallel to the plane or meets it
/// behind the near plane; the receiver's own depth is used then.
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
