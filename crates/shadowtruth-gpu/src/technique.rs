//! The techniques the GPU's fragment shader implements (`visibility.wgsl`), taken from a
//! `TechniqueSpec`; any other is refused by name.

use super::GpuError;
use shadowtruth::raster::{DepthFormat, RasterSettings};
pub use shadowtruth::technique::{
    ConstantParams, FalloffSpec, KernelSpec, LayerNeeds, LayerSpec, PCF_DEFAULT_BOX_SIZE, TapBiasSpec,
    TechniqueSpec,
};

/// One shadow test of `visibility.wgsl`, with its parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GpuTechnique {
    /// `none` and `slope_scaled` (whose offset is in the map): the plain depth test.
    Plain,
    /// `constant` with `bias_depth`.
    ConstantDepth { bias_depth: f32 },
    /// `constant` with `bias_world`, converted at each receiver.
    ConstantWorld { bias_world: f32 },
    /// `normal_offset`; `one_minus_n_dot_l` picks g = 1 − N·L over sin θ.
    NormalOffset { scale_texels: f32, one_minus_n_dot_l: bool },
    /// `pcf` over the nearest layer with a box kernel and a flat per-tap bias (`bias_depth` for
    /// bias constant, 0 for slope_scaled).
    PcfBox { size: u32, bias_depth: f32 },
    /// `pcf` with the bilinear kernel: the hardware comparison sampler.
    PcfBilinear { bias_depth: f32 },
}

/// Which techniques the GPU runs, for error messages.
pub const GPU_TECHNIQUES: &str = "none, constant, slope_scaled, normal_offset, and pcf with layers \
\"nearest\", kernel \"box\" or \"bilinear\" and bias \"constant\" or \"slope_scaled\"";

impl GpuTechnique {
    /// The GPU form of `spec`, or an error naming the technique when the shader has none.
    pub fn from_spec(spec: &TechniqueSpec) -> Result<Self, GpuError> {
        let unsupported = || {
            GpuError(format!(
                "technique {} has no GPU implementation (the GPU runs {GPU_TECHNIQUES})",
                spec.label()
            ))
        };
        let units = Self::raster_settings(spec).slope_units;
        if units.fract() != 0.0 {
            return Err(GpuError(format!(
                "technique {}: the GPU's depth bias takes whole units, not {units}",
                spec.label()
            )));
        }
        Ok(match spec {
            TechniqueSpec::None(_) | TechniqueSpec::SlopeScaled(_) => GpuTechnique::Plain,
            TechniqueSpec::Constant(ConstantParams { bias_world: Some(w), .. }) => {
                GpuTechnique::ConstantWorld { bias_world: *w as f32 }
            }
            TechniqueSpec::Constant(p) => {
                GpuTechnique::ConstantDepth { bias_depth: p.bias_depth.unwrap_or(0.0) as f32 }
            }
            // The device's normal offset has the two falloffs of the papers and no depth bias.
            TechniqueSpec::NormalOffset(p)
                if p.falloff == FalloffSpec::None
                    || [p.bias_world, p.bias_texels, p.factor, p.units]
                        .iter()
                        .any(|v| v.is_some_and(|v| v != 0.0)) =>
            {
                return Err(unsupported());
            }
            TechniqueSpec::NormalOffset(p) => GpuTechnique::NormalOffset {
                scale_texels: p.scale_texels as f32,
                one_minus_n_dot_l: p.falloff == FalloffSpec::OneMinusNDotL,
            },
            TechniqueSpec::Pcf(p) => {
                if p.layers != LayerSpec::Nearest {
                    return Err(unsupported());
                }
                let bias_depth = match p.bias {
                    TapBiasSpec::Constant => p.bias_depth.unwrap_or(0.0) as f32,
                    TapBiasSpec::SlopeScaled => 0.0,
                    _ => return Err(unsupported()),
                };
                match p.kernel {
                    KernelSpec::Box => {
                        GpuTechnique::PcfBox { size: p.size.unwrap_or(PCF_DEFAULT_BOX_SIZE), bias_depth }
                    }
                    KernelSpec::Bilinear => GpuTechnique::PcfBilinear { bias_depth },
                    _ => return Err(unsupported()),
                }
            }
            _ => return Err(unsupported()),
        })
    }

    /// How the map of `spec` is rasterized: its culling and polygon offset, in f32 depth.
    pub fn raster_settings(spec: &TechniqueSpec) -> RasterSettings {
        // An imported technique draws no map: it has the default needs.
        Self::raster_settings_of(&spec.build().map(|t| t.layer_needs()).unwrap_or_default())
    }

    /// The map that techniques with these layer needs read (one map serves them all).
    pub fn raster_settings_of(needs: &LayerNeeds) -> RasterSettings {
        RasterSettings {
            format: DepthFormat::F32,
            culling: needs.culling,
            slope_factor: needs.slope_factor,
            slope_units: needs.slope_units,
            ..RasterSettings::default()
        }
    }
}
