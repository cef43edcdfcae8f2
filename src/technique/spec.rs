//! Every technique with its parameters, as plans name them and reports record them:
//! `{"technique": "constant", "bias_depth": 0.001}`.

use super::{
    AdaptiveBias, ConstantBias, DualDepth, EpsilonScale, Kernel, LayerNeeds, Midpoint, MultiDepthNeeds,
    NoBias, NormalOffset, OffsetFalloff, POISSON_SIZES, Pcf, Pcss, ReceiverPlane, SecondDepth,
    SlopeScaledBias, TapBias, TapThreshold, Technique,
};
use crate::raster::{Culling, DepthSelection};
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

/// PCF kernels (docs/formulas.md, "PCF kernels").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum KernelSpec {
    /// `size`×`size` point taps (default 3).
    #[default]
    Box,
    /// Hardware 2×2 bilinear compare.
    Bilinear,
    /// `taps` (16, 25, 32; default 16) Poisson-disk taps over `radius_texels` (default 1.5).
    Poisson,
    /// One jittered tap per cell of a 4×4 grid over ±`radius_texels` (default 2).
    Jitter4x4,
}

/// The bias applied to every PCF tap.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TapBiasSpec {
    /// `bias_depth` (default 0) subtracted from every tap.
    #[default]
    Constant,
    /// glPolygonOffset(`factor`, `units`) in the map.
    SlopeScaled,
    /// The receiver's plane at each tap texel's centre, minus `bias_depth`.
    ReceiverPlane,
    /// The potential occluder of every tap texel (`k`, `epsilon`).
    Adaptive,
    /// Ehm et al.'s Algorithm 1: three potential occluders and Δbias per receiver.
    AdaptiveDelta,
}

/// The depth-layer test under each PCF tap.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LayerSpec {
    #[default]
    Nearest,
    SecondDepth,
    Midpoint,
    Dual,
}

/// Which extra depths a multiple-depth map keeps.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SelectSpec {
    Min,
    Max,
    #[default]
    MinMax,
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
    /// Percentage-closer filtering with a per-tap bias over a depth-layer test.
    Pcf {
        #[serde(default)]
        kernel: KernelSpec,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        size: Option<u32>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        taps: Option<u32>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        radius_texels: Option<f64>,
        #[serde(default)]
        bias: TapBiasSpec,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        bias_depth: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        factor: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        units: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        k: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        epsilon: Option<EpsilonSpec>,
        #[serde(default, skip_serializing_if = "is_nearest")]
        layers: LayerSpec,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        z_offset: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        cull_back_faces: Option<bool>,
    },
    /// Multiple-depth shadow map (Pagot, Comba & Oliveira 2004): `depths` per texel, the n-shadow
    /// test, filtered like `pcf` (default a single tap: box of size 1).
    Mdsm {
        depths: u32,
        #[serde(default = "default_neighbourhood")]
        neighbourhood: u32,
        #[serde(default)]
        select: SelectSpec,
        #[serde(default)]
        kernel: KernelSpec,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        size: Option<u32>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        taps: Option<u32>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        radius_texels: Option<f64>,
        #[serde(default)]
        bias: TapBiasSpec,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        bias_depth: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        k: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        epsilon: Option<EpsilonSpec>,
    },
    /// Percentage-closer soft shadows (Fernando 2005): `search_taps` Poisson taps (16, 25, 32),
    /// `filter_taps` (16, 25, 32 Poisson; another square k² a regular k×k grid), per-tap `bias`.
    Pcss {
        #[serde(default = "default_pcss_taps")]
        search_taps: u32,
        #[serde(default = "default_pcss_taps")]
        filter_taps: u32,
        #[serde(default = "default_pcss_bias")]
        bias: TapBiasSpec,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        bias_depth: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        k: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        epsilon: Option<EpsilonSpec>,
    },
}

fn is_nearest(l: &LayerSpec) -> bool {
    *l == LayerSpec::Nearest
}

fn default_neighbourhood() -> u32 {
    3
}

fn default_pcss_taps() -> u32 {
    25
}

fn default_pcss_bias() -> TapBiasSpec {
    TapBiasSpec::ReceiverPlane
}

/// Which reference a technique's output is scored against.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ReferenceKind {
    /// The exact hard visibility of each pixel's surface point.
    Hard,
    /// Hard visibility averaged over a pixel's sub-pixel grid (filtered techniques).
    Coverage,
    /// The fraction of an area light each point sees (soft shadows).
    AreaLight,
}

const MAX_KERNEL_SIZE: u32 = 31;

/// The kernel named by a spec's fields.
fn kernel_of(kernel: KernelSpec, size: Option<u32>, taps: Option<u32>, default_size: u32) -> Kernel {
    match kernel {
        KernelSpec::Box => Kernel::Box { size: size.unwrap_or(default_size) },
        KernelSpec::Bilinear => Kernel::Bilinear,
        KernelSpec::Poisson => Kernel::Poisson { taps: taps.unwrap_or(16) },
        KernelSpec::Jitter4x4 => Kernel::Jitter4x4,
    }
}

fn radius_of(kernel: KernelSpec, radius_texels: Option<f64>) -> f32 {
    radius_texels.unwrap_or(match kernel {
        KernelSpec::Jitter4x4 => 2.0,
        _ => 1.5,
    }) as f32
}

fn adaptive_of(k: Option<f64>, epsilon: Option<EpsilonSpec>) -> AdaptiveBias {
    AdaptiveBias {
        k: k.unwrap_or(default_k()) as f32,
        epsilon: match epsilon.unwrap_or_default() {
            EpsilonSpec::Original => EpsilonScale::Original,
            EpsilonSpec::Ehm => EpsilonScale::Ehm,
        },
    }
}

fn tap_bias_of(
    bias: TapBiasSpec,
    bias_depth: Option<f64>,
    k: Option<f64>,
    epsilon: Option<EpsilonSpec>,
) -> TapBias {
    let bias_depth = bias_depth.unwrap_or(0.0) as f32;
    match bias {
        TapBiasSpec::Constant => TapBias::Constant { bias_depth },
        TapBiasSpec::SlopeScaled => TapBias::SlopeScaled,
        TapBiasSpec::ReceiverPlane => TapBias::ReceiverPlane { bias_depth },
        TapBiasSpec::Adaptive => TapBias::Adaptive(adaptive_of(k, epsilon)),
        TapBiasSpec::AdaptiveDelta => TapBias::AdaptiveDelta(adaptive_of(k, epsilon)),
    }
}

/// The PCSS filter kernel for `taps`: a Poisson set, or a regular grid for another square.
fn pcss_filter(taps: u32) -> Kernel {
    if POISSON_SIZES.contains(&taps) {
        Kernel::Poisson { taps }
    } else {
        Kernel::Grid { size: (taps as f64).sqrt().round() as u32 }
    }
}

/// A parameter problem: the parameter at fault (when one is) and what is wrong.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{}{message}", field.map(|f| format!("{f}: ")).unwrap_or_default())]
pub struct TechniqueSpecError {
    pub field: Option<&'static str>,
    pub message: String,
}

fn err(field: &'static str, message: impl Into<String>) -> TechniqueSpecError {
    TechniqueSpecError { field: Some(field), message: message.into() }
}

/// Distances, offsets and scales that have no meaning below zero (a negative bias moves the
/// comparison towards more acne, never less).
fn non_negative(field: &'static str, x: f64) -> Result<(), TechniqueSpecError> {
    if x.is_finite() && x >= 0.0 {
        Ok(())
    } else {
        Err(err(field, format!("must be a finite number ≥ 0, found {x}")))
    }
}

fn non_negative_opt(field: &'static str, x: Option<f64>) -> Result<(), TechniqueSpecError> {
    x.map_or(Ok(()), |x| non_negative(field, x))
}

fn validate_kernel(
    kernel: KernelSpec,
    size: Option<u32>,
    taps: Option<u32>,
    radius_texels: Option<f64>,
) -> Result<(), TechniqueSpecError> {
    match (kernel, size) {
        (KernelSpec::Box, Some(k)) if !(1..=MAX_KERNEL_SIZE).contains(&k) => {
            return Err(err("size", format!("must be from 1 to {MAX_KERNEL_SIZE}, found {k}")));
        }
        (KernelSpec::Box, _) => {}
        (_, Some(_)) => return Err(err("size", "belongs to kernel \"box\"")),
        _ => {}
    }
    match (kernel, taps) {
        (KernelSpec::Poisson, Some(t)) if !POISSON_SIZES.contains(&t) => {
            return Err(err("taps", format!("must be 16, 25 or 32 (the Poisson sets), found {t}")));
        }
        (KernelSpec::Poisson, _) => {}
        (_, Some(_)) => return Err(err("taps", "belongs to kernel \"poisson\"")),
        _ => {}
    }
    match (kernel, radius_texels) {
        (KernelSpec::Poisson | KernelSpec::Jitter4x4, Some(r)) if !(r.is_finite() && r > 0.0) => {
            Err(err("radius_texels", format!("must be a number > 0, found {r}")))
        }
        (KernelSpec::Box | KernelSpec::Bilinear, Some(_)) => {
            Err(err("radius_texels", "belongs to kernels \"poisson\" and \"jitter4x4\""))
        }
        _ => Ok(()),
    }
}

fn validate_bias(
    bias: TapBiasSpec,
    bias_depth: Option<f64>,
    k: Option<f64>,
    epsilon: Option<EpsilonSpec>,
) -> Result<(), TechniqueSpecError> {
    let adaptive = matches!(bias, TapBiasSpec::Adaptive | TapBiasSpec::AdaptiveDelta);
    if !adaptive && k.is_some() {
        return Err(err("k", "belongs to bias \"adaptive\" and \"adaptive_delta\""));
    }
    if !adaptive && epsilon.is_some() {
        return Err(err("epsilon", "belongs to bias \"adaptive\" and \"adaptive_delta\""));
    }
    if adaptive && bias_depth.is_some() {
        return Err(err("bias_depth", "belongs to bias \"constant\" and \"receiver_plane\""));
    }
    non_negative_opt("k", k)?;
    non_negative_opt("bias_depth", bias_depth)
}

/// PCF's `factor`/`units` (with bias slope_scaled only) and `z_offset`/`cull_back_faces` (with
/// the layers that read two depths).
fn validate_pcf_layers(
    bias: TapBiasSpec,
    factor: Option<f64>,
    units: Option<f64>,
    layers: LayerSpec,
    z_offset: Option<f64>,
    cull_back_faces: Option<bool>,
) -> Result<(), TechniqueSpecError> {
    let slope = bias == TapBiasSpec::SlopeScaled;
    for (field, value) in [("factor", factor), ("units", units)] {
        if !slope && value.is_some() {
            return Err(err(field, "belongs to bias \"slope_scaled\""));
        }
        non_negative_opt(field, value)?;
    }
    match (layers, z_offset) {
        (LayerSpec::Dual, Some(z)) => non_negative("z_offset", z)?,
        (LayerSpec::Dual, None) => return Err(err("z_offset", "layers \"dual\" needs a z_offset ≥ 0")),
        (_, Some(_)) => return Err(err("z_offset", "belongs to layers \"dual\"")),
        _ => {}
    }
    if cull_back_faces.is_some() && !matches!(layers, LayerSpec::Midpoint | LayerSpec::Dual) {
        return Err(err("cull_back_faces", "belongs to layers \"midpoint\" and \"dual\""));
    }
    Ok(())
}

fn validate_mdsm(depths: u32, neighbourhood: u32, bias: TapBiasSpec) -> Result<(), TechniqueSpecError> {
    if !(1..=4).contains(&depths) {
        return Err(err("depths", format!("must be 1, 2, 3 or 4, found {depths}")));
    }
    if neighbourhood % 2 == 0 || !(1..=15).contains(&neighbourhood) {
        return Err(err("neighbourhood", "must be an odd number of texels from 1 to 15"));
    }
    if bias == TapBiasSpec::SlopeScaled {
        return Err(err("bias", "mdsm takes bias constant, receiver_plane, adaptive or adaptive_delta"));
    }
    Ok(())
}

fn validate_pcss(search_taps: u32, filter_taps: u32, bias: TapBiasSpec) -> Result<(), TechniqueSpecError> {
    if !POISSON_SIZES.contains(&search_taps) {
        return Err(err("search_taps", "must be 16, 25 or 32 (the Poisson sets)"));
    }
    let root = (filter_taps as f64).sqrt().round() as u32;
    if !POISSON_SIZES.contains(&filter_taps) && (root * root != filter_taps || !(2..=16).contains(&root)) {
        return Err(err("filter_taps", "must be 16, 25, 32 (Poisson) or a square from 4 to 256 (grid)"));
    }
    if matches!(bias, TapBiasSpec::SlopeScaled | TapBiasSpec::Adaptive) {
        return Err(err("bias", "pcss takes bias constant, receiver_plane or adaptive_delta"));
    }
    Ok(())
}

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
            TechniqueSpec::Pcf { .. } => "pcf",
            TechniqueSpec::Mdsm { .. } => "mdsm",
            TechniqueSpec::Pcss { .. } => "pcss",
        }
    }

    /// The reference the technique's output means the same thing as: pixel coverage for filtered
    /// maps, the area light for PCSS, the hard visibility otherwise.
    pub fn reference_kind(&self) -> ReferenceKind {
        match self {
            TechniqueSpec::Pcf { .. } | TechniqueSpec::Mdsm { .. } => ReferenceKind::Coverage,
            TechniqueSpec::Pcss { .. } => ReferenceKind::AreaLight,
            _ => ReferenceKind::Hard,
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

    /// Checks the parameters: numbers finite and, where below zero means nothing, not negative;
    /// each parameter used only where it belongs.
    pub fn validate(&self) -> Result<(), TechniqueSpecError> {
        match *self {
            TechniqueSpec::None | TechniqueSpec::Midpoint { .. } => Ok(()),
            TechniqueSpec::Constant { bias_depth, bias_world } => match (bias_depth, bias_world) {
                (Some(b), None) => non_negative("bias_depth", b),
                (None, Some(b)) => non_negative("bias_world", b),
                _ => Err(TechniqueSpecError {
                    field: None,
                    message: "constant needs exactly one of bias_depth and bias_world".into(),
                }),
            },
            TechniqueSpec::SlopeScaled { factor, units, .. } => {
                non_negative("factor", factor)?;
                non_negative("units", units)
            }
            TechniqueSpec::NormalOffset { scale_texels, .. } => non_negative("scale_texels", scale_texels),
            TechniqueSpec::ReceiverPlane { bias_depth } | TechniqueSpec::SecondDepth { bias_depth } => {
                non_negative("bias_depth", bias_depth)
            }
            TechniqueSpec::Dual { z_offset, .. } => non_negative("z_offset", z_offset),
            TechniqueSpec::Adaptive { k, .. } => non_negative("k", k),
            TechniqueSpec::Pcf {
                kernel,
                size,
                taps,
                radius_texels,
                bias,
                bias_depth,
                factor,
                units,
                k,
                epsilon,
                layers,
                z_offset,
                cull_back_faces,
            } => {
                validate_kernel(kernel, size, taps, radius_texels)?;
                validate_bias(bias, bias_depth, k, epsilon)?;
                validate_pcf_layers(bias, factor, units, layers, z_offset, cull_back_faces)
            }
            TechniqueSpec::Mdsm {
                depths,
                neighbourhood,
                kernel,
                size,
                taps,
                radius_texels,
                bias,
                bias_depth,
                k,
                epsilon,
                ..
            } => {
                validate_mdsm(depths, neighbourhood, bias)?;
                validate_kernel(kernel, size, taps, radius_texels)?;
                validate_bias(bias, bias_depth, k, epsilon)
            }
            TechniqueSpec::Pcss { search_taps, filter_taps, bias, bias_depth, k, epsilon } => {
                validate_pcss(search_taps, filter_taps, bias)?;
                validate_bias(bias, bias_depth, k, epsilon)
            }
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
            TechniqueSpec::Adaptive { k, epsilon } => Box::new(adaptive_of(Some(k), Some(epsilon))),
            TechniqueSpec::Pcf {
                kernel,
                size,
                taps,
                radius_texels,
                bias,
                bias_depth,
                factor,
                units,
                k,
                epsilon,
                layers,
                z_offset,
                cull_back_faces,
            } => {
                // The layers of the depth-layer technique underneath, as it asks for them.
                let cull = cull_back_faces.unwrap_or(false);
                let (threshold, mut needs) = match layers {
                    LayerSpec::Nearest => (TapThreshold::Nearest, LayerNeeds::default()),
                    LayerSpec::SecondDepth => {
                        (TapThreshold::Nearest, SecondDepth { bias_depth: 0.0 }.layer_needs())
                    }
                    LayerSpec::Midpoint => (
                        TapThreshold::TwoLayers { z_offset: f32::INFINITY },
                        Midpoint { cull_back_faces: cull }.layer_needs(),
                    ),
                    LayerSpec::Dual => {
                        let z_offset = z_offset.unwrap_or(0.0) as f32;
                        (
                            TapThreshold::TwoLayers { z_offset },
                            DualDepth { z_offset, cull_back_faces: cull }.layer_needs(),
                        )
                    }
                };
                if bias == TapBiasSpec::SlopeScaled {
                    needs.slope_factor = factor.unwrap_or(0.0) as f32;
                    needs.slope_units = units.unwrap_or(0.0) as f32;
                }
                Box::new(Pcf {
                    kernel: kernel_of(kernel, size, taps, 3),
                    radius_texels: radius_of(kernel, radius_texels),
                    bias: tap_bias_of(bias, bias_depth, k, epsilon),
                    threshold,
                    needs,
                })
            }
            TechniqueSpec::Mdsm {
                depths,
                neighbourhood,
                select,
                kernel,
                size,
                taps,
                radius_texels,
                bias,
                bias_depth,
                k,
                epsilon,
            } => Box::new(Pcf {
                kernel: kernel_of(kernel, size, taps, 1),
                radius_texels: radius_of(kernel, radius_texels),
                bias: tap_bias_of(bias, bias_depth, k, epsilon),
                threshold: TapThreshold::MultiDepth,
                needs: LayerNeeds {
                    multi_depth: Some(MultiDepthNeeds {
                        depths,
                        neighbourhood,
                        selection: match select {
                            SelectSpec::Min => DepthSelection::Min,
                            SelectSpec::Max => DepthSelection::Max,
                            SelectSpec::MinMax => DepthSelection::MinMax,
                        },
                    }),
                    ..LayerNeeds::default()
                },
            }),
            TechniqueSpec::Pcss { search_taps, filter_taps, bias, bias_depth, k, epsilon } => {
                Box::new(Pcss {
                    search: Kernel::Poisson { taps: search_taps },
                    filter: pcss_filter(filter_taps),
                    bias: tap_bias_of(bias, bias_depth, k, epsilon),
                })
            }
        }
    }
}
