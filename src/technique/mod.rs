//! Shadow-map techniques: what depth layers each needs, and the visibility of one receiver sample.
//!
//! `TechniqueSpec` names every technique with its parameters (the form plans and reports use);
//! `Technique` is the trait the shading loop calls. Each family lives in its own file and cites
//! its source; the exact formulas and our choices are in formulas.md.

mod bias;
mod normal_offset;
mod shade;
mod spec;

pub use bias::{ConstantBias, NoBias, SlopeScaledBias};
pub use normal_offset::{NormalOffset, OffsetFalloff};
pub use shade::{ShadeContext, shade_evaluated};
pub use spec::{CullSpec, FalloffSpec, TechniqueSpec, TechniqueSpecError};

use crate::raster::{Culling, DepthLayer, LightView};
use glam::Vec3;

/// One receiver: the G-buffer's surface point and its geometric normal, which faces the light.
#[derive(Clone, Copy, Debug)]
pub struct Sample {
    pub position: Vec3,
    pub normal: Vec3,
}

/// How the technique's nearest depth layer must be rasterized (the depth format is the run's).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LayerNeeds {
    pub culling: Culling,
    /// glPolygonOffset factor and units, applied while rasterizing.
    pub slope_factor: f32,
    pub slope_units: f32,
}

impl Default for LayerNeeds {
    fn default() -> Self {
        LayerNeeds {
            culling: Culling::None,
            slope_factor: 0.0,
            slope_units: 0.0,
        }
    }
}

/// A shadow test. Implementations do no I/O and hold only their parameters.
pub trait Technique: Sync {
    /// The depth layer this technique reads.
    fn layer_needs(&self) -> LayerNeeds;
    /// Visibility of `sample` in [0, 1] (1 = lit).
    fn visibility(&self, sample: &Sample, view: &LightView, nearest: &DepthLayer) -> f32;
}

/// The classic depth comparison: lit when `d_receiver − bias ≤ d_map` at the texel holding
/// (u, v); a receiver outside the map is clamped to the border texel, as a clamp-to-edge
/// sampler would.
#[inline]
pub fn depth_test(layer: &DepthLayer, uvd: Vec3, bias_depth: f32) -> f32 {
    let n = layer.resolution;
    let x = ((uvd.x * n as f32).floor().max(0.0) as u32).min(n - 1);
    let row = (((1.0 - uvd.y) * n as f32).floor().max(0.0) as u32).min(n - 1);
    (uvd.z - bias_depth <= layer.at(x, row)) as u8 as f32
}
