//! Shadow-map techniques: what depth layers each needs, and the visibility of one receiver sample.
//!
//! `TechniqueSpec` names every technique with its parameters (the form plans and reports use);
//! `Technique` is the trait the shading loop calls. Each family lives in its own file with the
//! parameter structs of its techniques (`TechniqueParams`) and cites its source; the exact
//! formulas and our choices are in docs/formulas.md.

mod adaptive;
mod bias;
mod built_layers;
mod canonical;
mod cascaded;
mod command;
mod depth_layers;
mod external;
mod filter_params;
mod filterable;
mod kernel;
mod mdsm;
mod moment_tests;
mod normal_offset;
mod params;
mod pcf;
mod pcss;
mod receiver_plane;
mod shade;
mod spec;
mod tap_bias;

pub use adaptive::{
    AdaptiveBias, AdaptiveParams, AdaptiveTest, Epsilon, EpsilonScale, EpsilonSpec, TangentPlane,
};
pub use bias::{
    ConstantBias, ConstantParams, CullSpec, NoBias, NoneParams, SlopeScaledBias, SlopeScaledParams,
};
pub use built_layers::BuiltLayers;
pub use canonical::canonical_json;
pub use cascaded::CascadeOrders;
pub use command::{
    COMMAND_LIST_FIELDS, COMMAND_PLACEHOLDERS, CommandParams, CommandRun, DEFAULT_COMMAND_TIMEOUT_S,
    MAX_COMMAND_TIMEOUT_S, VisibilityFormat,
};
pub use depth_layers::{DualDepth, DualParams, Midpoint, MidpointParams, SecondDepth, SecondDepthParams};
pub use external::ExternalParams;
pub use filter_params::{KernelSpec, TapBiasSpec};
pub use filterable::{
    BlurSpec, EsmParams, Evsm2Params, Evsm4Params, EvsmParams, MomentNeeds, MsmParams, VsmParams,
    footprint_lod,
};
pub use kernel::{Kernel, POISSON_SIZES, poisson_set};
pub use mdsm::{MdsmParams, SelectSpec};
pub use moment_tests::{chebyshev_upper_bound, hamburger_shadow_intensity, reduce_bleeding};
pub use normal_offset::{FalloffSpec, NormalOffset, NormalOffsetParams, OffsetFalloff};
pub use params::{ReferenceKind, TechniqueParams, TechniqueSpecError};
pub use pcf::DEFAULT_BOX_SIZE as PCF_DEFAULT_BOX_SIZE;
pub use pcf::{AffineDepth, LayerSpec, Pcf, PcfParams, TapDepth, TapThreshold};
pub use pcss::{Pcss, PcssParams};
pub use receiver_plane::{ReceiverPlane, ReceiverPlaneParams, receiver_plane_slope, receiver_plane_slope_at};
pub use shade::{ShadeContext, ShadeOrder, shade_evaluated};
pub use spec::TechniqueSpec;
pub use tap_bias::TapBias;

use crate::raster::{Culling, DepthLayer, DepthPairLayer, DepthSelection, MomentLayer, MultiDepthLayer};
use glam::Vec3;

/// One receiver: the G-buffer's surface point, its geometric normal (which faces the light) and
/// the scene triangle it lies on.
#[derive(Clone, Copy, Debug)]
pub struct Sample {
    pub position: Vec3,
    pub normal: Vec3,
    pub triangle: u32,
}

/// How the technique's depth layers must be rasterized (the depth format is the run's).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LayerNeeds {
    pub culling: Culling,
    /// glPolygonOffset factor and units, applied while rasterizing.
    pub slope_factor: f32,
    pub slope_units: f32,
    /// Whether the second-nearest surface z2 is read as well as the nearest z1.
    pub second_layer: bool,
    /// A multiple-depth map derived from the nearest layer (Pagot et al. 2004).
    pub multi_depth: Option<MultiDepthNeeds>,
    /// The blurred moments of a filterable map, derived from the nearest layer.
    pub moments: Option<MomentNeeds>,
}

/// The n-SM a technique reads: `depths` per texel, selected over `neighbourhood`² texels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MultiDepthNeeds {
    pub depths: u32,
    pub neighbourhood: u32,
    pub selection: DepthSelection,
}

impl Default for LayerNeeds {
    fn default() -> Self {
        LayerNeeds {
            culling: Culling::None,
            slope_factor: 0.0,
            slope_units: 0.0,
            second_layer: false,
            multi_depth: None,
            moments: None,
        }
    }
}

/// The depth layers a technique reads: the nearest surface, the two nearest (z1, z2), the n
/// depths of a multiple-depth map, or the filtered moments of a filterable map.
#[derive(Clone, Copy)]
pub enum Layers<'a> {
    Nearest(&'a DepthLayer),
    TwoNearest(&'a DepthPairLayer),
    MultiDepth(&'a MultiDepthLayer),
    Moments(&'a MomentLayer),
}

impl<'a> Layers<'a> {
    /// The nearest layer; only techniques that asked for it (`second_layer == false`) call this.
    pub fn nearest(&self) -> &'a DepthLayer {
        match self {
            Layers::Nearest(l) => l,
            _ => panic!("the technique did not ask for the nearest layer alone"),
        }
    }

    /// The two nearest layers; only techniques that asked for them call this.
    pub fn two_nearest(&self) -> &'a DepthPairLayer {
        match self {
            Layers::TwoNearest(l) => l,
            _ => panic!("the technique did not ask for two layers"),
        }
    }

    /// The filtered moments; only filterable techniques (which asked for them) call this.
    pub fn moments(&self) -> &'a MomentLayer {
        match self {
            Layers::Moments(l) => l,
            _ => panic!("the technique did not ask for moments"),
        }
    }

    pub fn resolution(&self) -> u32 {
        match self {
            Layers::Moments(l) => l.resolution(),
            Layers::Nearest(l) => l.resolution,
            Layers::TwoNearest(l) => l.resolution,
            Layers::MultiDepth(l) => l.resolution,
        }
    }
}

/// A shadow test. Implementations do no I/O and hold only their parameters.
pub trait Technique: Sync {
    /// The depth layers this technique reads.
    fn layer_needs(&self) -> LayerNeeds;
    /// Visibility of `sample` in [0, 1] (1 = lit).
    fn visibility(&self, sample: &Sample, ctx: &ShadeContext) -> f32;
    /// The visibility of each of `samples`, in order, into `out` (as long): `visibility`'s
    /// answers. The shading order puts the samples of one texel, and of one triangle, next to
    /// each other, so a technique may override this to reuse work between neighbours. Compiled
    /// per technique, so `visibility` is called directly here, not through the trait object.
    fn visibility_of_run(&self, samples: &[Sample], ctx: &ShadeContext, out: &mut [f32]) {
        for (s, v) in samples.iter().zip(out) {
            *v = self.visibility(s, ctx);
        }
    }
    /// Whether the technique reads the light's projection as a matrix (rays through texel
    /// centres, a frustum's size): it cannot run on a dual-paraboloid map, whose map is not one.
    fn needs_projective_map(&self) -> bool {
        false
    }
}

/// The texel (x, row) holding map coordinates (u, v); a receiver outside the map is clamped to
/// the border texel, as a clamp-to-edge sampler would.
#[inline]
pub fn texel_at(resolution: u32, u: f32, v: f32) -> (u32, u32) {
    let n = resolution as f32;
    // Clamped to ≥ 0 first, so that the truncating cast is the floor (and NaN goes to 0).
    let x = ((u * n).max(0.0) as u32).min(resolution - 1);
    let row = (((1.0 - v) * n).max(0.0) as u32).min(resolution - 1);
    (x, row)
}

/// The map coordinates (u, v) of the centre of texel (x, row).
#[inline]
pub fn texel_centre(resolution: u32, x: u32, row: u32) -> (f32, f32) {
    let n = resolution as f32;
    ((x as f32 + 0.5) / n, 1.0 - (row as f32 + 0.5) / n)
}

/// The classic depth comparison: lit when `d_receiver − bias ≤ d_map` at the texel holding
/// (u, v).
#[inline]
pub fn depth_test(layer: &DepthLayer, uvd: Vec3, bias_depth: f32) -> f32 {
    let (x, row) = texel_at(layer.resolution, uvd.x, uvd.y);
    (uvd.z - bias_depth <= layer.at(x, row)) as u8 as f32
}
