//! Every technique with its parameters, as plans name them and reports record them:
//! `{"technique": "constant", "bias_depth": 0.001}`.

use super::{ConstantBias, NoBias, NormalOffset, OffsetFalloff, SlopeScaledBias, Technique};
use crate::raster::Culling;
use serde::{Deserialize, Serialize};

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

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FalloffSpec {
    #[default]
    SinTheta,
    OneMinusNDotL,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "technique", rename_all = "snake_case", deny_unknown_fields)]
pub enum TechniqueSpec {
    /// The plain depth test.
    None,
    /// A constant bias: `bias_depth` in light-depth units, or `bias_world` in scene units.
    Constant {
        #[serde(default, skip_serializing_if = "Option::is_none")]
        bias_depth: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        bias_world: Option<f64>,
    },
    /// glPolygonOffset(factor, units) while rasterizing.
    SlopeScaled {
        factor: f64,
        units: f64,
        #[serde(default)]
        cull: CullSpec,
    },
    /// Receiver moved along its normal by `scale_texels` texels times g(θ).
    NormalOffset {
        scale_texels: f64,
        #[serde(default)]
        falloff: FalloffSpec,
    },
}

#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct TechniqueSpecError(pub String);

impl TechniqueSpec {
    /// The technique's name as the report writes it.
    pub fn name(&self) -> &'static str {
        match self {
            TechniqueSpec::None => "none",
            TechniqueSpec::Constant { .. } => "constant",
            TechniqueSpec::SlopeScaled { .. } => "slope_scaled",
            TechniqueSpec::NormalOffset { .. } => "normal_offset",
        }
    }

    /// The parameters alone, as a JSON object (the record's `parameters`).
    pub fn parameters(&self) -> serde_json::Map<String, serde_json::Value> {
        let mut v = match serde_json::to_value(self) {
            Ok(serde_json::Value::Object(m)) => m,
            _ => serde_json::Map::new(),
        };
        v.remove("technique");
        v
    }

    /// A short label: `constant(bias_depth=0.001)`.
    pub fn label(&self) -> String {
        let params = self.parameters();
        if params.is_empty() {
            return self.name().to_string();
        }
        let inner: Vec<String> = params
            .iter()
            .map(|(k, v)| {
                format!(
                    "{k}={}",
                    v.as_str()
                        .map(str::to_string)
                        .unwrap_or_else(|| v.to_string())
                )
            })
            .collect();
        format!("{}({})", self.name(), inner.join(","))
    }

    /// Checks the parameters: finite numbers, and the constant bias given one way.
    pub fn validate(&self) -> Result<(), TechniqueSpecError> {
        let finite = |name: &str, x: f64| {
            if x.is_finite() {
                Ok(())
            } else {
                Err(TechniqueSpecError(format!(
                    "{name} must be a finite number"
                )))
            }
        };
        match *self {
            TechniqueSpec::None => Ok(()),
            TechniqueSpec::Constant {
                bias_depth,
                bias_world,
            } => match (bias_depth, bias_world) {
                (Some(b), None) => finite("bias_depth", b),
                (None, Some(b)) => finite("bias_world", b),
                _ => Err(TechniqueSpecError(
                    "constant needs exactly one of bias_depth and bias_world".into(),
                )),
            },
            TechniqueSpec::SlopeScaled { factor, units, .. } => {
                finite("factor", factor)?;
                finite("units", units)
            }
            TechniqueSpec::NormalOffset { scale_texels, .. } => {
                finite("scale_texels", scale_texels)
            }
        }
    }

    /// The technique to run.
    pub fn build(&self) -> Box<dyn Technique> {
        match *self {
            TechniqueSpec::None => Box::new(NoBias),
            TechniqueSpec::Constant {
                bias_depth,
                bias_world,
            } => Box::new(match (bias_depth, bias_world) {
                (_, Some(w)) => ConstantBias::World(w as f32),
                (d, None) => ConstantBias::Depth(d.unwrap_or(0.0) as f32),
            }),
            TechniqueSpec::SlopeScaled {
                factor,
                units,
                cull,
            } => Box::new(SlopeScaledBias {
                factor: factor as f32,
                units: units as f32,
                culling: cull.into(),
            }),
            TechniqueSpec::NormalOffset {
                scale_texels,
                falloff,
            } => Box::new(NormalOffset {
                scale_texels: scale_texels as f32,
                falloff: match falloff {
                    FalloffSpec::SinTheta => OffsetFalloff::SinTheta,
                    FalloffSpec::OneMinusNDotL => OffsetFalloff::OneMinusNDotL,
                },
            }),
        }
    }
}
