//! How a filter biases each tap's receiver depth: what the filters' parameters build
//! (filter_params.rs) and what their taps compare with (pcf.rs).

use super::adaptive::AdaptiveBias;

/// How each tap's receiver depth is biased.
pub enum TapBias {
    Constant {
        bias_depth: f32,
    },
    /// glPolygonOffset applied to the map (see `LayerNeeds`); the taps compare plainly.
    SlopeScaled,
    ReceiverPlane {
        bias_depth: f32,
    },
    Adaptive(AdaptiveBias),
    AdaptiveDelta(AdaptiveBias),
}

impl TapBias {
    /// Whether the bias reads light rays through texel centres (the adaptive ones do).
    pub fn needs_projective_map(&self) -> bool {
        matches!(self, TapBias::Adaptive(_) | TapBias::AdaptiveDelta(_))
    }
}
