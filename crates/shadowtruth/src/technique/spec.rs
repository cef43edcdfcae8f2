//! Every technique with its parameters, as plans name them and reports record them:
//! `{"technique": "constant", "bias_depth": 0.001}`.
//!
//! The list below is the one place that names the techniques: each entry is the name plans use,
//! the variant and the parameter struct, which lives in the technique's own file and does the
//! rest through [`TechniqueParams`].

use super::canonical::CanonicalFields;
use super::{
    AdaptiveParams, CommandParams, ConstantParams, DualParams, EsmParams, Evsm2Params, Evsm4Params,
    ExternalParams, MdsmParams, MidpointParams, MsmParams, NoneParams, NormalOffsetParams, PcfParams,
    PcssParams, ReceiverPlaneParams, ReferenceKind, SecondDepthParams, SlopeScaledParams, Technique,
    TechniqueParams, TechniqueSpecError, VsmParams,
};
use serde::{Deserialize, Serialize};

/// The serialized enum and the one dispatch from a variant to its parameters.
macro_rules! techniques {
    ($($(#[$doc:meta])* $name:literal => $variant:ident($params:ty),)*) => {
        // Internally tagged newtype variants: the tag is taken out and the parameter struct reads
        // the rest of the object, so the JSON is that of struct variants. Unknown fields are
        // refused by each struct's own deny_unknown_fields: the enum's would not reach them.
        #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
        #[serde(tag = "technique")]
        pub enum TechniqueSpec {
            $($(#[$doc])* #[serde(rename = $name)] $variant($params),)*
        }

        impl TechniqueSpec {
            /// The technique's name as the report writes it.
            pub fn name(&self) -> &'static str {
                match self {
                    $(TechniqueSpec::$variant(_) => $name,)*
                }
            }

            /// The parameters, which know everything else about the technique.
            pub fn params(&self) -> &dyn TechniqueParams {
                match self {
                    $(TechniqueSpec::$variant(p) => p,)*
                }
            }
        }
    };
}

techniques! {
    /// The plain depth test.
    "none" => None(NoneParams),
    /// A constant bias: `bias_depth` in light-depth units, or `bias_world` in scene units.
    "constant" => Constant(ConstantParams),
    /// glPolygonOffset(factor, units) while rasterizing.
    "slope_scaled" => SlopeScaled(SlopeScaledParams),
    /// Receiver moved along its normal by `scale_texels` texels times g(θ).
    "normal_offset" => NormalOffset(NormalOffsetParams),
    /// Receiver depth tilted along its plane to the texel centre (Isidoro 2006).
    "receiver_plane" => ReceiverPlane(ReceiverPlaneParams),
    /// Back faces of closed objects only (Wang & Molnar 1994).
    "second_depth" => SecondDepth(SecondDepthParams),
    /// Halfway between the two nearest surfaces (Woo 1992).
    "midpoint" => Midpoint(MidpointParams),
    /// `z1 + min((z2 − z1)/2, z_offset)` (Weiskopf & Ertl 2003).
    "dual" => Dual(DualParams),
    /// Potential occluder on the tangent plane plus adaptive epsilon (Dou et al. 2014).
    "adaptive" => Adaptive(AdaptiveParams),
    /// Percentage-closer filtering with a per-tap bias over a depth-layer test.
    "pcf" => Pcf(PcfParams),
    /// Multiple-depth shadow map (Pagot, Comba & Oliveira 2004), filtered like `pcf`.
    "mdsm" => Mdsm(MdsmParams),
    /// Percentage-closer soft shadows (Fernando 2005).
    "pcss" => Pcss(PcssParams),
    /// Variance shadow map (Donnelly & Lauritzen 2006) with light-bleeding reduction.
    "vsm" => Vsm(VsmParams),
    /// Exponential shadow map (Annen et al. 2008).
    "esm" => Esm(EsmParams),
    /// Exponential variance shadow map, positive warp (Lauritzen & McCool 2008).
    "evsm2" => Evsm2(Evsm2Params),
    /// Exponential variance shadow map, positive and negative warps.
    "evsm4" => Evsm4(Evsm4Params),
    /// Four-moment Hamburger moment shadow map (Peters & Klein 2015).
    "msm" => Msm(MsmParams),
    /// Another renderer's visibility buffer, read from an image file and scored as it is.
    "external" => External(ExternalParams),
    /// Another renderer run once per setting through the command protocol (docs/engines.md).
    "command" => Command(CommandParams),
}

impl TechniqueSpec {
    /// The technique and its parameters with every default filled in, sorted, numbers printed
    /// from their f64 values: equal for two specs exactly when they are the same technique with
    /// the same parameters, however each was written.
    pub fn canonical(&self) -> String {
        let mut fields = CanonicalFields::default();
        self.params().canonical_fields(&mut fields);
        fields.render(self.name())
    }
}

impl TechniqueSpec {
    /// The reference the technique's output means the same thing as: pixel coverage for filtered
    /// maps, the area light for PCSS, the hard visibility otherwise.
    pub fn reference_kind(&self) -> ReferenceKind {
        self.params().reference_kind()
    }

    /// The parameters alone, as a JSON object (the record's `parameters`).
    pub fn parameters(&self) -> serde_json::Map<String, serde_json::Value> {
        self.params().parameters()
    }

    /// A short label: `constant(bias_depth=0.001)`.
    pub fn label(&self) -> String {
        let params = self.params().label_parameters();
        if params.is_empty() {
            return self.name().to_string();
        }
        let inner: Vec<String> = params
            .iter()
            .map(|(k, v)| format!("{k}={}", v.as_str().map(str::to_string).unwrap_or_else(|| v.to_string())))
            .collect();
        format!("{}({})", self.name(), inner.join(","))
    }

    /// Checks the parameters (see [`TechniqueParams::validate`]).
    pub fn validate(&self) -> Result<(), TechniqueSpecError> {
        self.params().validate()
    }

    /// The technique to run; `None` for `external` and `command`, whose visibility is read from
    /// files.
    pub fn build(&self) -> Option<Box<dyn Technique>> {
        self.params().build()
    }
}
