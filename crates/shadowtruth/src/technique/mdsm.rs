//! Multiple-depth shadow maps (Pagot, Comba & Oliveira 2004): `depths` depths per texel, selected
//! over `neighbourhood`² texels of the nearest layer (raster's `multi_depth.rs`), read by PCF's
//! n-shadow test (`TapThreshold::MultiDepth`, pcf.rs) and filtered like `pcf`, by default with
//! a single tap (a box of size 1).

use super::canonical::CanonicalFields;
use super::filter_params::{KernelFields, TapBiasFields};
use super::params::err;
use super::{
    EpsilonSpec, KernelSpec, LayerNeeds, MultiDepthNeeds, Pcf, ReferenceKind, TapBiasSpec, TapThreshold,
    Technique, TechniqueParams, TechniqueSpecError,
};
use crate::raster::{DepthSelection, MAX_DEPTHS_PER_TEXEL};
use serde::{Deserialize, Serialize};

/// Which extra depths a multiple-depth map keeps.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SelectSpec {
    Min,
    Max,
    #[default]
    MinMax,
}

impl From<SelectSpec> for DepthSelection {
    fn from(s: SelectSpec) -> DepthSelection {
        match s {
            SelectSpec::Min => DepthSelection::Min,
            SelectSpec::Max => DepthSelection::Max,
            SelectSpec::MinMax => DepthSelection::MinMax,
        }
    }
}

fn default_neighbourhood() -> u32 {
    3
}

/// A box of this side (in texels) when `mdsm` names no size: the paper's single n-shadow test.
const DEFAULT_BOX_SIZE: u32 = 1;

/// `mdsm`: the map (`depths`, `neighbourhood` in texels, `select`), then the kernel and the
/// per-tap bias as `pcf` names them (no slope-scaled bias: the map has no polygon offset).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MdsmParams {
    pub depths: u32,
    #[serde(default = "default_neighbourhood")]
    pub neighbourhood: u32,
    #[serde(default)]
    pub select: SelectSpec,
    #[serde(default)]
    pub kernel: KernelSpec,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub size: Option<u32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub taps: Option<u32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius_texels: Option<f64>,
    #[serde(default)]
    pub bias: TapBiasSpec,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bias_depth: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub epsilon: Option<EpsilonSpec>,
}

impl MdsmParams {
    fn kernel_fields(&self) -> KernelFields {
        KernelFields {
            kernel: self.kernel,
            size: self.size,
            taps: self.taps,
            radius_texels: self.radius_texels,
        }
    }

    fn tap_bias_fields(&self) -> TapBiasFields {
        TapBiasFields { bias: self.bias, bias_depth: self.bias_depth, k: self.k, epsilon: self.epsilon }
    }

    fn validate_map(&self) -> Result<(), TechniqueSpecError> {
        if !(1..=MAX_DEPTHS_PER_TEXEL).contains(&self.depths) {
            let message = format!("must be between 1 and {MAX_DEPTHS_PER_TEXEL}, found {}", self.depths);
            return Err(err("depths", message));
        }
        if self.neighbourhood.is_multiple_of(2) || !(1..=15).contains(&self.neighbourhood) {
            return Err(err("neighbourhood", "must be an odd number of texels from 1 to 15"));
        }
        if self.bias == TapBiasSpec::SlopeScaled {
            return Err(err("bias", "mdsm takes bias constant, receiver_plane, adaptive or adaptive_delta"));
        }
        Ok(())
    }

    /// The multiple-depth map, derived from the nearest layer.
    fn layer_needs(&self) -> LayerNeeds {
        LayerNeeds {
            multi_depth: Some(MultiDepthNeeds {
                depths: self.depths,
                neighbourhood: self.neighbourhood,
                selection: self.select.into(),
            }),
            ..LayerNeeds::default()
        }
    }
}

impl TechniqueParams for MdsmParams {
    fn validate(&self) -> Result<(), TechniqueSpecError> {
        self.validate_map()?;
        self.kernel_fields().validate()?;
        self.tap_bias_fields().validate()
    }

    fn build(&self) -> Option<Box<dyn Technique>> {
        let kernel = self.kernel_fields();
        Some(Box::new(Pcf {
            kernel: kernel.kernel(DEFAULT_BOX_SIZE),
            radius_texels: kernel.radius_texels(),
            bias: self.tap_bias_fields().tap_bias(),
            threshold: TapThreshold::MultiDepth,
            needs: self.layer_needs(),
        }))
    }

    fn reference_kind(&self) -> ReferenceKind {
        ReferenceKind::Coverage
    }

    fn canonical_fields(&self, f: &mut CanonicalFields) {
        f.count("depths", self.depths);
        f.count("neighbourhood", self.neighbourhood);
        f.named("select", self.select);
        self.kernel_fields().canonical_fields(f, DEFAULT_BOX_SIZE);
        self.tap_bias_fields().canonical_fields(f);
    }
}
