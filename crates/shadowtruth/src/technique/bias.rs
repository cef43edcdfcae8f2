//! Single-depth techniques with a depth bias.
//!
//! - `none`: the plain depth test (Williams 1978), which shows acne.
//! - `constant`: a constant bias subtracted from the receiver depth (Williams 1978; Reeves,
//!   Salesin & Cook 1987), given in depth units or in world units along the light's axis.
//! - `slope_scaled`: glPolygonOffset's `factor·m + units·r`, added to the caster depths while the
//!   map is rasterized (OpenGL 4.6 §14.6.5; Vulkan "Depth Bias"); the test itself is plain.

use super::canonical::CanonicalFields;
use super::params::non_negative;
use super::{LayerNeeds, Sample, ShadeContext, Technique, TechniqueParams, TechniqueSpecError, depth_test};
use crate::raster::Culling;
use serde::{Deserialize, Serialize};

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

/// `none` takes no parameters.
// No deny_unknown_fields: `none` was a unit variant, whose other fields serde lets pass, and
// plans that give it some still read.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct NoneParams {}

impl TechniqueParams for NoneParams {
    fn validate(&self) -> Result<(), TechniqueSpecError> {
        Ok(())
    }

    fn build(&self) -> Option<Box<dyn Technique>> {
        Some(Box::new(NoBias))
    }

    fn canonical_fields(&self, _: &mut CanonicalFields) {}
}

/// `constant`: exactly one of `bias_depth` (light-depth units) and `bias_world` (scene units).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConstantParams {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bias_depth: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bias_world: Option<f64>,
}

impl TechniqueParams for ConstantParams {
    fn validate(&self) -> Result<(), TechniqueSpecError> {
        match (self.bias_depth, self.bias_world) {
            (Some(b), None) => non_negative("bias_depth", b),
            (None, Some(b)) => non_negative("bias_world", b),
            _ => Err(TechniqueSpecError {
                field: None,
                message: "constant needs exactly one of bias_depth and bias_world".into(),
            }),
        }
    }

    fn build(&self) -> Option<Box<dyn Technique>> {
        Some(Box::new(match (self.bias_depth, self.bias_world) {
            (_, Some(w)) => ConstantBias::World(w as f32),
            (d, None) => ConstantBias::Depth(d.unwrap_or(0.0) as f32),
        }))
    }

    fn canonical_fields(&self, f: &mut CanonicalFields) {
        // A world-space bias wins when both are given (`build`).
        match self.bias_world {
            None => f.number("bias_depth", self.bias_depth.unwrap_or(0.0)),
            Some(w) => {
                f.number("bias_world", w);
                f.number_if_given("bias_depth", self.bias_depth);
            }
        }
    }
}

/// Faces of closed objects left out of the map.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CullSpec {
    #[default]
    None,
    Back,
    Front,
}

impl From<CullSpec> for Culling {
    fn from(c: CullSpec) -> Culling {
        match c {
            CullSpec::None => Culling::None,
            CullSpec::Back => Culling::BackFacesOfClosed,
            CullSpec::Front => Culling::FrontFacesOfClosed,
        }
    }
}

/// `slope_scaled`: glPolygonOffset(`factor`, `units`) while rasterizing, with `cull`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SlopeScaledParams {
    pub factor: f64,
    pub units: f64,
    #[serde(default)]
    pub cull: CullSpec,
}

impl TechniqueParams for SlopeScaledParams {
    fn validate(&self) -> Result<(), TechniqueSpecError> {
        non_negative("factor", self.factor)?;
        non_negative("units", self.units)
    }

    fn build(&self) -> Option<Box<dyn Technique>> {
        Some(Box::new(SlopeScaledBias {
            factor: self.factor as f32,
            units: self.units as f32,
            culling: self.cull.into(),
        }))
    }

    fn canonical_fields(&self, f: &mut CanonicalFields) {
        f.number("factor", self.factor);
        f.number("units", self.units);
        f.named("cull", self.cull);
    }
}
