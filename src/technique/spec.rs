//! Every technique with its parameters, as plans name them and reports record them:
//! `{"technique": "constant", "bias_depth": 0.001}`.

use super::{
    AdaptiveBias, ConstantBias, DualDepth, EpsilonScale, Midpoint, NoBias, NormalOffset, OffsetFalloff,
    ReceiverPlane, SecondDepth, SlopeScaledBias, Technique,
};
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

/// Which adaptive epsilon: Dou et al.'s, or Ehm et al.'s scaled by min(1/(N·L)², 100).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EpsilonSpec {
    #[default]
    Original,
    Ehm,
}

fn default_k() -> f64 {
    1e-4
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
    /// Receiver depth tilted along its plane to the texel centre (Isidoro 2006).
    ReceiverPlane {
        #[serde(default)]
        bias_depth: f64,
    },
    /// Back faces of closed objects only (Wang & Molnar 1994).
    SecondDepth {
        #[serde(default)]
        bias_depth: f64,
    },
    /// Halfway between the two nearest surfaces (Woo 1992).
    Midpoint {
        #[serde(default)]
        cull_back_faces: bool,
    },
    /// `z1 + min((z2 − z1)/2, z_offset)` (Weiskopf & Ertl 2003).
    Dual {
        z_offset: f64,
        #[serde(default)]
        cull_back_faces: bool,
    },
    /// Potential occluder on the tangent plane plus adaptive epsilon (Dou et al. 2014).
    Adaptive {
        #[serde(default = "default_k")]
        k: f64,
        #[serde(default)]
        epsilon: EpsilonSpec,
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
            TechniqueSpec::ReceiverPlane { .. } => "receiver_plane",
            TechniqueSpec::SecondDepth { .. } => "second_depth",
            TechniqueSpec::Midpoint { .. } => "midpoint",
            TechniqueSpec::Dual { .. } => "dual",
            TechniqueSpec::Adaptive { .. } => "adaptive",
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
            .map(|(k, v)| format!("{k}={}", v.as_str().map(str::to_string).unwrap_or_else(|| v.to_string())))
            .collect();
        format!("{}({})", self.name(), inner.join(","))
    }

    /// Checks the parameters: finite numbers, and the constant bias given one way.
    pub fn validate(&self) -> Result<(), TechniqueSpecError> {
        let finite = |name: &str, x: f64| {
            if x.is_finite() {
                Ok(())
            } else {
                Err(TechniqueSpecError(format!("{name} must be a finite number")))
            }
        };
        match *self {
            TechniqueSpec::None => Ok(()),
            TechniqueSpec::Constant { bias_depth, bias_world } => match (bias_depth, bias_world) {
                (Some(b), None) => finite("bias_depth", b),
                (None, Some(b)) => finite("bias_world", b),
                _ => {
                    Err(TechniqueSpecError("constant needs exactly one of bias_depth and bias_world".into()))
                }
            },
            TechniqueSpec::SlopeScaled { factor, units, .. } => {
                finite("factor", factor)?;
                finite("units", units)
            }
            TechniqueSpec::NormalOffset { scale_texels, .. } => finite("scale_texels", scale_texels),
            TechniqueSpec::ReceiverPlane { bias_depth } | TechniqueSpec::SecondDepth { bias_depth } => {
                finite("bias_depth", bias_depth)
            }
            TechniqueSpec::Midpoint { .. } => Ok(()),
            TechniqueSpec::Dual { z_offset, .. } if z_offset >= 0.0 && !z_offset.is_nan() => Ok(()),
            TechniqueSpec::Dual { .. } => Err(TechniqueSpecError("z_offset must be a number ≥ 0".into())),
            TechniqueSpec::Adaptive { k, .. } if k.is_finite() && k >= 0.0 => Ok(()),
            TechniqueSpec::Adaptive { .. } => Err(TechniqueSpecError("k must be a finite number ≥ 0".into())),
        }
    }

    /// The technique to run.
    pub fn build(&self) -> Box<dyn Technique> {
        match *self {
            TechniqueSpec::None => Box::new(NoBias),
            TechniqueSpec::Constant { bias_depth, bias_world } => Box::new(match (bias_depth, bias_world) {
                (_, Some(w)) => ConstantBias::World(w as f32),
                (d, None) => ConstantBias::Depth(d.unwrap_or(0.0) as f32),
            }),
            TechniqueSpec::SlopeScaled { factor, units, cull } => {
                Box::new(SlopeScaledBias { factor: factor as f32, units: units as f32, culling: cull.into() })
            }
            TechniqueSpec::NormalOffset { scale_texels, falloff } => Box::new(NormalOffset {
                scale_texels: scale_texels as f32,
                falloff: match falloff {
                    FalloffSpec::SinTheta => OffsetFalloff::SinTheta,
                    FalloffSpec::OneMinusNDotL => OffsetFalloff::OneMinusNDotL,
                },
            }),
            TechniqueSpec::ReceiverPlane { bias_depth } => {
                Box::new(ReceiverPlane { bias_depth: bias_depth as f32 })
            }
            TechniqueSpec::SecondDepth { bias_depth } => {
                Box::new(SecondDepth { bias_depth: bias_depth as f32 })
            }
            TechniqueSpec::Midpoint { cull_back_faces } => Box::new(Midpoint { cull_back_faces }),
            TechniqueSpec::Dual { z_offset, cull_back_faces } => {
                Box::new(DualDepth { z_offset: z_offset as f32, cull_back_faces })
            }
            TechniqueSpec::Adaptive { k, epsilon } => Box::new(AdaptiveBias {
                k: k as f32,
                epsilon: match epsilon {
                    EpsilonSpec::Original => EpsilonScale::Original,
                    EpsilonSpec::Ehm => EpsilonScale::Ehm,
                },
            }),
        }
    }
}
