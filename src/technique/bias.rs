//! Single-depth techniques with a depth bias.
//!
//! - `none`: the plain depth test (Williams 1978), which shows acne.
//! - `constant`: a constant bias subtracted from the receiver depth (Williams 1978; Reeves,
//!   Salesin & Cook 1987), given in depth units or in world units along the light's axis.
//! - `slope_scaled`: glPolygonOffset's `factor·m + units·r`, added to the caster depths while the
//!   map is rasterized (OpenGL 4.6 §14.6.5; Vulkan "Depth Bias"); the test itself is plain.

use super::{LayerNeeds, Sample, ShadeContext, Technique, depth_test};
use crate::raster::Culling;

pub struct NoBias;

impl Technique for NoBias {
    fn layer_needs(&self) -> LayerNeeds {
        LayerNeeds::default()
    }

    fn visibility(&self, s: &Sample, ctx: &ShadeContext) -> f32 {
        let (view, nearest) = (ctx.view, ctx.layers.nearest());
        match view.project(s.position) {
            Some(uvd) => depth_test(nearest, uvd, 0.0),
            None => 1.0,
        }
    }
}

/// A constant bias, either in light-depth units or as a distance in world units along the
/// light's axis (converted at each receiver: exact for orthographic and perspective depth).
pub enum ConstantBias {
    Depth(f32),
    World(f32),
}

impl Technique for ConstantBias {
    fn layer_needs(&self) -> LayerNeeds {
        LayerNeeds::default()
    }

    fn visibility(&self, s: &Sample, ctx: &ShadeContext) -> f32 {
        let (view, nearest) = (ctx.view, ctx.layers.nearest());
        let Some(uvd) = view.project(s.position) else {
            return 1.0;
        };
        let bias_depth = match *self {
            ConstantBias::Depth(b) => b,
            ConstantBias::World(b_world) => {
                let d_view = view.view_depth(s.position) as f64;
                (view.depth_of_view_depth(d_view) - view.depth_of_view_depth(d_view - b_world as f64)) as f32
            }
        };
        depth_test(nearest, uvd, bias_depth)
    }
}

/// Rasterizer slope-scaled bias; `culling` is which faces of closed objects the map skips.
pub struct SlopeScaledBias {
    pub factor: f32,
    pub units: f32,
    pub culling: Culling,
}

impl Technique for SlopeScaledBias {
    fn layer_needs(&self) -> LayerNeeds {
        LayerNeeds {
            culling: self.culling,
            slope_factor: self.factor,
            slope_units: self.units,
            ..LayerNeeds::default()
        }
    }

    fn visibility(&self, s: &Sample, ctx: &ShadeContext) -> f32 {
        let (view, nearest) = (ctx.view, ctx.layers.nearest());
        match view.project(s.position) {
            Some(uvd) => depth_test(nearest, uvd, 0.0),
            None => 1.0,
        }
    }
}
