//! The parameters the filtered techniques share (`pcf`, `mdsm`, `pcss`): the kernel and the bias
//! of every tap (docs/formulas.md, "PCF kernels" and "PCF per-tap biases and layer tests").
//!
//! Serde cannot flatten them into the parameter structs and still refuse unknown fields, so each
//! struct holds these fields itself and hands copies to [`KernelFields`] and [`TapBiasFields`].

use super::adaptive::DEFAULT_K;
use super::canonical::CanonicalFields;
use super::params::{err, non_negative_opt};
use super::tap_bias::TapBias;
use super::{AdaptiveBias, EpsilonSpec, Kernel, POISSON_SIZES, TechniqueSpecError};
use serde::{Deserialize, Serialize};

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

const MAX_KERNEL_SIZE: u32 = 31;

/// The kernel a spec names: `kernel`, the side of a box (`size`), the count of Poisson taps
/// (`taps`) and the extent of Poisson and jitter kernels (`radius_texels`).
#[derive(Clone, Copy, Debug)]
pub(super) struct KernelFields {
    pub kernel: KernelSpec,
    pub size: Option<u32>,
    pub taps: Option<u32>,
    pub radius_texels: Option<f64>,
}

impl KernelFields {
    /// The kernel, a box of `default_size` when its size is not given.
    pub fn kernel(&self, default_size: u32) -> Kernel {
        match self.kernel {
            KernelSpec::Box => Kernel::Box { size: self.size.unwrap_or(default_size) },
            KernelSpec::Bilinear => Kernel::Bilinear,
            KernelSpec::Poisson => Kernel::Poisson { taps: self.taps.unwrap_or(16) },
            KernelSpec::Jitter4x4 => Kernel::Jitter4x4,
        }
    }

    pub fn radius_texels(&self) -> f32 {
        self.radius_texels.unwrap_or(match self.kernel {
            KernelSpec::Jitter4x4 => 2.0,
            _ => 1.5,
        }) as f32
    }

    /// Each field in range and given only with the kernel that reads it.
    pub fn validate(&self) -> Result<(), TechniqueSpecError> {
        match (self.kernel, self.size) {
            (KernelSpec::Box, Some(k)) if !(1..=MAX_KERNEL_SIZE).contains(&k) => {
                return Err(err("size", format!("must be from 1 to {MAX_KERNEL_SIZE}, found {k}")));
            }
            (KernelSpec::Box, _) => {}
            (_, Some(_)) => return Err(err("size", "belongs to kernel \"box\"")),
            _ => {}
        }
        match (self.kernel, self.taps) {
            (KernelSpec::Poisson, Some(t)) if !POISSON_SIZES.contains(&t) => {
                return Err(err("taps", format!("must be 16, 25 or 32 (the Poisson sets), found {t}")));
            }
            (KernelSpec::Poisson, _) => {}
            (_, Some(_)) => return Err(err("taps", "belongs to kernel \"poisson\"")),
            _ => {}
        }
        match (self.kernel, self.radius_texels) {
            (KernelSpec::Poisson | KernelSpec::Jitter4x4, Some(r)) if !(r.is_finite() && r > 0.0) => {
                Err(err("radius_texels", format!("must be a number > 0, found {r}")))
            }
            (KernelSpec::Box | KernelSpec::Bilinear, Some(_)) => {
                Err(err("radius_texels", "belongs to kernels \"poisson\" and \"jitter4x4\""))
            }
            _ => Ok(()),
        }
    }

    /// The size of a box (`default_size` when omitted), the taps of a Poisson kernel (16) and the
    /// radius of Poisson (1.5) and jitter (2.0) kernels.
    pub fn canonical_fields(&self, f: &mut CanonicalFields, default_size: u32) {
        f.named("kernel", self.kernel);
        match self.kernel {
            KernelSpec::Box => f.count("size", self.size.unwrap_or(default_size)),
            _ => f.count_if_given("size", self.size),
        }
        match self.kernel {
            KernelSpec::Poisson => f.count("taps", self.taps.unwrap_or(16)),
            _ => f.count_if_given("taps", self.taps),
        }
        match self.kernel {
            KernelSpec::Poisson => f.number("radius_texels", self.radius_texels.unwrap_or(1.5)),
            KernelSpec::Jitter4x4 => f.number("radius_texels", self.radius_texels.unwrap_or(2.0)),
            _ => f.number_if_given("radius_texels", self.radius_texels),
        }
    }
}

/// The per-tap bias a spec names: `bias`, its `bias_depth` (constant and receiver-plane biases)
/// or its `k` and `epsilon` (adaptive biases).
#[derive(Clone, Copy, Debug)]
pub(super) struct TapBiasFields {
    pub bias: TapBiasSpec,
    pub bias_depth: Option<f64>,
    pub k: Option<f64>,
    pub epsilon: Option<EpsilonSpec>,
}

impl TapBiasFields {
    fn adaptive(&self) -> AdaptiveBias {
        AdaptiveBias {
            k: self.k.unwrap_or(DEFAULT_K) as f32,
            epsilon: self.epsilon.unwrap_or_default().into(),
        }
    }

    pub fn tap_bias(&self) -> TapBias {
        let bias_depth = self.bias_depth.unwrap_or(0.0) as f32;
        match self.bias {
            TapBiasSpec::Constant => TapBias::Constant { bias_depth },
            TapBiasSpec::SlopeScaled => TapBias::SlopeScaled,
            TapBiasSpec::ReceiverPlane => TapBias::ReceiverPlane { bias_depth },
            TapBiasSpec::Adaptive => TapBias::Adaptive(self.adaptive()),
            TapBiasSpec::AdaptiveDelta => TapBias::AdaptiveDelta(self.adaptive()),
        }
    }

    fn is_adaptive(&self) -> bool {
        matches!(self.bias, TapBiasSpec::Adaptive | TapBiasSpec::AdaptiveDelta)
    }

    /// `k` and `epsilon` only with the adaptive biases, `bias_depth` only without; not negative.
    pub fn validate(&self) -> Result<(), TechniqueSpecError> {
        let adaptive = self.is_adaptive();
        if !adaptive && self.k.is_some() {
            return Err(err("k", "belongs to bias \"adaptive\" and \"adaptive_delta\""));
        }
        if !adaptive && self.epsilon.is_some() {
            return Err(err("epsilon", "belongs to bias \"adaptive\" and \"adaptive_delta\""));
        }
        if adaptive && self.bias_depth.is_some() {
            return Err(err("bias_depth", "belongs to bias \"constant\" and \"receiver_plane\""));
        }
        non_negative_opt("k", self.k)?;
        non_negative_opt("bias_depth", self.bias_depth)
    }

    /// `bias_depth` (0) for the constant and receiver-plane biases, `k` (1e-4) and `epsilon`
    /// (original) for the adaptive ones.
    pub fn canonical_fields(&self, f: &mut CanonicalFields) {
        f.named("bias", self.bias);
        match self.bias {
            TapBiasSpec::Constant | TapBiasSpec::ReceiverPlane => {
                f.number("bias_depth", self.bias_depth.unwrap_or(0.0))
            }
            _ => f.number_if_given("bias_depth", self.bias_depth),
        }
        if self.is_adaptive() {
            f.number("k", self.k.unwrap_or(DEFAULT_K));
            f.named("epsilon", self.epsilon.unwrap_or_default());
        } else {
            f.number_if_given("k", self.k);
            if let Some(e) = self.epsilon {
                f.named("epsilon", e);
            }
        }
    }
}
