//! What a plan names. The default plan is every single-depth technique at a few settings over
//! resolutions 512 to 4096.

use crate::raster::DepthFormat;
use crate::technique::{CullSpec, FalloffSpec, TechniqueSpec};
use std::path::PathBuf;

#[derive(Clone, Debug)]
pub struct Plan {
    pub scenes: Vec<PathBuf>,
    /// Camera names to run (None: every camera of each scene).
    pub cameras: Option<Vec<String>>,
    /// Light names to run (None: every light of each scene).
    pub lights: Option<Vec<String>>,
    pub techniques: Vec<TechniqueSpec>,
    pub resolutions: Vec<u32>,
    pub depth_formats: Vec<DepthFormat>,
}

impl Plan {
    /// The default matrix over `scenes`.
    pub fn default_for(scenes: Vec<PathBuf>) -> Self {
        Plan {
            scenes,
            cameras: None,
            lights: None,
            techniques: default_techniques(),
            resolutions: vec![512, 1024, 2048, 4096],
            depth_formats: vec![DepthFormat::F32],
        }
    }
}

/// The techniques of the default plan.
pub fn default_techniques() -> Vec<TechniqueSpec> {
    let mut t = vec![TechniqueSpec::None];
    for b in [1e-4, 1e-3, 5e-3] {
        t.push(TechniqueSpec::Constant {
            bias_depth: Some(b),
            bias_world: None,
        });
    }
    for b in [0.01, 0.05] {
        t.push(TechniqueSpec::Constant {
            bias_depth: None,
            bias_world: Some(b),
        });
    }
    for (factor, units) in [(1.0, 1.0), (2.0, 4.0), (4.0, 16.0)] {
        t.push(TechniqueSpec::SlopeScaled {
            factor,
            units,
            cull: CullSpec::None,
        });
    }
    for scale_texels in [0.5, 1.0, 2.0] {
        t.push(TechniqueSpec::NormalOffset {
            scale_texels,
            falloff: FalloffSpec::SinTheta,
        });
    }
    t
}
