//! Normal-offset shadows (Holbert, "Normal Offset Shadows", GDC 2011 poster; RTR4 §7.4): the
//! receiver moves along its geometric normal by `scale · texel_world · g(θ)` before it is
//! projected, so both its map position and its depth change. g = sin θ follows RTR4's account of
//! Holbert; `1 − N·L` is the variant of MJP's sample and Unity; `none` (g = 1) is Bevy's.
//! Engines pair the offset with a depth bias: an optional move towards the light (`bias_world`
//! world units or `bias_texels` texels) and an optional raster bias of the map (`factor`,
//! `units`, as `slope_scaled`), so that an engine's shipped setting is one technique here
//! (docs/formulas.md, "Normal offset"; docs/engine-defaults.md).

use super::canonical::CanonicalFields;
use super::params::{non_negative, non_negative_opt};
use super::{LayerNeeds, Sample, ShadeContext, Technique, TechniqueParams, TechniqueSpecError, depth_test};
use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OffsetFalloff {
    /// g = sin θ = √(1 − (N·L)²).
    SinTheta,
    /// g = 1 − N·L.
    OneMinusNDotL,
    /// g = 1.
    None,
}

pub struct NormalOffset {
    /// Offset in shadow-map texels (world size of one texel at the receiver).
    pub scale_texels: f32,
    pub falloff: OffsetFalloff,
    /// Then this far towards the light: world units plus texels at the receiver.
    pub bias_world: f32,
    pub bias_texels: f32,
    /// glPolygonOffset(factor, units) of the map.
    pub factor: f32,
    pub units: f32,
}

impl Technique for NormalOffset {
    fn layer_needs(&self) -> LayerNeeds {
        LayerNeeds { slope_factor: self.factor, slope_units: self.units, ..LayerNeeds::default() }
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
            OffsetFalloff::None => 1.0,
        };
        let texel = view.texel_world_size(s.position);
        let moved = s.position
            + s.normal * (self.scale_texels * texel * g)
            + to_light * (self.bias_world + self.bias_texels * texel);
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
    None,
}

impl From<FalloffSpec> for OffsetFalloff {
    fn from(f: FalloffSpec) -> OffsetFalloff {
        match f {
            FalloffSpec::SinTheta => OffsetFalloff::SinTheta,
            FalloffSpec::OneMinusNDotL => OffsetFalloff::OneMinusNDotL,
            FalloffSpec::None => OffsetFalloff::None,
        }
    }
}

/// `normal_offset`: the receiver moved by `scale_texels` texels times g(θ), then `bias_world`
/// plus `bias_texels` towards the light; the map drawn with glPolygonOffset(`factor`, `units`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NormalOffsetParams {
    pub scale_texels: f64,
    #[serde(default)]
    pub falloff: FalloffSpec,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bias_world: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bias_texels: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub factor: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub units: Option<f64>,
}

impl NormalOffsetParams {
    /// The optional parts, by name: each absent one is 0 and moves nothing.
    fn extras(&self) -> [(&'static str, Option<f64>); 4] {
        [
            ("bias_world", self.bias_world),
            ("bias_texels", self.bias_texels),
            ("factor", self.factor),
            ("units", self.units),
        ]
    }
}

impl TechniqueParams for NormalOffsetParams {
    fn validate(&self) -> Result<(), TechniqueSpecError> {
        non_negative("scale_texels", self.scale_texels)?;
        self.extras().into_iter().try_for_each(|(name, v)| non_negative_opt(name, v))
    }

    fn build(&self) -> Option<Box<dyn Technique>> {
        let f = |v: Option<f64>| v.unwrap_or(0.0) as f32;
        Some(Box::new(NormalOffset {
            scale_texels: self.scale_texels as f32,
            falloff: self.falloff.into(),
            bias_world: f(self.bias_world),
            bias_texels: f(self.bias_texels),
            factor: f(self.factor),
            units: f(self.units),
        }))
    }

    fn canonical_fields(&self, f: &mut CanonicalFields) {
        f.number("scale_texels", self.scale_texels);
        f.named("falloff", self.falloff);
        // Absent and 0 are the same technique: only a part that moves something is named, so
        // that the plain offset keeps its identity.
        for (name, v) in self.extras() {
            if let Some(v) = v.filter(|&v| v != 0.0) {
                f.number(name, v);
            }
        }
    }
}
