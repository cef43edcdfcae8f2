//! Normal-offset shadows (Holbert, "Normal Offset Shadows", GDC 2011 poster; RTR4 §7.4): the
//! receiver moves along its geometric normal by `scale · texel_world · g(θ)` before it is
//! projected, so both its map position and its depth change. g = sin θ follows RTR4's account of
//! Holbert; `1 − N·L` is the variant of MJP's sample and Unity (docs/formulas.md, "Normal
//! offset").

use super::canonical::CanonicalFields;
use super::params::non_negative;
use super::{LayerNeeds, Sample, ShadeContext, Technique, TechniqueParams, TechniqueSpecError, depth_test};
use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OffsetFalloff {
    /// g = sin θ = √(1 − (N·L)²).
    SinTheta,
    /// g = 1 − N·L.
    OneMinusNDotL,
}

pub struct NormalOffset {
    /// Offset in shadow-map texels (world size of one texel at the receiver).
    pub scale_texels: f32,
    pub falloff: OffsetFalloff,
}

impl Technique for NormalOffset {
    fn layer_needs(&self) -> LayerNeeds {
        LayerNeeds::default()
    }

    fn visibility(&self, s: &Sample, ctx: &ShadeContext) -> f32 {
        let (view, nearest) = (ctx.view, ctx.layers.nearest());
        let to_light = match (view.to_light, view.position) {
            (Some(l), _) => l,
            (None, Some(pos)) => (pos - s.position).normalize(),
            (None, None) => return 1.0,
        };
        let n_dot_l = s.normal.dot(to_light).clamp(0.0, 1.0);
        let g = match self.falloff {
            OffsetFalloff::SinTheta => (1.0 - n_dot_l * n_dot_l).max(0.0).sqrt(),
            OffsetFalloff::OneMinusNDotL => 1.0 - n_dot_l,
        };
        let moved = s.position + s.normal * (self.scale_texels * view.texel_world_size(s.position) * g);
        match view.project(moved) {
            Some(uvd) => depth_test(nearest, uvd, 0.0),
            None => 1.0,
        }
    }
}

/// The falloff g(θ) a spec names.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FalloffSpec {
    #[default]
    SinTheta,
    OneMinusNDotL,
}

impl From<FalloffSpec> for OffsetFalloff {
    fn from(f: FalloffSpec) -> OffsetFalloff {
        match f {
            FalloffSpec::SinTheta => OffsetFalloff::SinTheta,
            FalloffSpec::OneMinusNDotL => OffsetFalloff::OneMinusNDotL,
        }
    }
}

/// `normal_offset`: the receiver moved by `scale_texels` texels times g(θ).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NormalOffsetParams {
    pub scale_texels: f64,
    #[serde(default)]
    pub falloff: FalloffSpec,
}

impl TechniqueParams for NormalOffsetParams {
    fn validate(&self) -> Result<(), TechniqueSpecError> {
        non_negative("scale_texels", self.scale_texels)
    }

    fn build(&self) -> Option<Box<dyn Technique>> {
        Some(Box::new(NormalOffset { scale_texels: self.scale_texels as f32, falloff: self.falloff.into() }))
    }

    fn canonical_fields(&self, f: &mut CanonicalFields) {
        f.number("scale_texels", self.scale_texels);
        f.named("falloff", self.falloff);
    }
}
