//! The CPU depth rasterizer: texel centres, top-left fill rule, depth linear in screen space,
//! f32 arithmetic, near-plane clipping, per-object back-face culling of closed objects.

use super::{DepthFormat, DepthLayer, LightView};
use crate::scene::Scene;

/// Which faces of closed objects are not rasterized (open objects are never culled).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Culling {
    None,
    BackFacesOfClosed,
    FrontFacesOfClosed,
}

/// Everything a depth layer depends on besides the scene and the light view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RasterSettings {
    pub format: DepthFormat,
    pub culling: Culling,
    /// glPolygonOffset `factor` (multiplies the depth slope m, in depth units per texel).
    pub slope_factor: f32,
    /// glPolygonOffset `units` (multiplies the format's minimum resolvable difference r).
    pub slope_units: f32,
}

impl Default for RasterSettings {
    fn default() -> Self {
        RasterSettings {
            format: DepthFormat::F32,
            culling: Culling::None,
            slope_factor: 0.0,
            slope_units: 0.0,
        }
    }
}

/// The nearest depth per texel of every (non-culled) triangle.
pub fn rasterize_nearest(scene: &Scene, view: &LightView, settings: &RasterSettings) -> DepthLayer {
    let _ = (scene, view, settings);
    todo!()
}
