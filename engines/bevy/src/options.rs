//! The command line.

use clap::{Parser, ValueEnum};
use std::path::PathBuf;

use bevy::pbr::{DirectionalLight, SpotLight};

/// Renders a `shadowtruth view-export` folder with Bevy 0.16's own shadow maps, headless, and
/// writes the shadow factor (and optionally the camera distance) per pixel as one-channel f32
/// EXRs for `shadowtruth score`.
#[derive(Parser, Debug)]
#[command(
    name = "shadowtruth-bevy",
    version,
    after_help = "Example:\n  shadowtruth view-export scenes/plane_box.json -o view\n  \
        shadowtruth-bevy --view view --visibility vis.exr --depth depth.exr --fit export\n  \
        shadowtruth score scenes/plane_box.json --camera main --light sun \
        --visibility vis.exr --depth depth.exr"
)]
pub struct Args {
    /// The exported view's folder (view.json, scene.glb).
    #[arg(long)]
    pub view: PathBuf,
    /// Where to write the shadow factor: 1 lit, 0 shadowed, NaN on background.
    #[arg(long)]
    pub visibility: PathBuf,
    /// Where to write the distance from the camera to the surface (world units, +inf on
    /// background).
    #[arg(long)]
    pub depth: Option<PathBuf>,
    /// The shadow map's size in texels (Bevy's `DirectionalLightShadowMap`, which spot lights
    /// use too); default: view.json's light.shadow_map.resolution.
    #[arg(long)]
    pub map_size: Option<u32>,
    /// The light's `shadow_depth_bias`, world units towards the light [Bevy: 0.02].
    #[arg(long, allow_negative_numbers = true)]
    pub depth_bias: Option<f32>,
    /// The light's `shadow_normal_bias`, texels along the normal [Bevy: 1.8].
    #[arg(long, allow_negative_numbers = true)]
    pub normal_bias: Option<f32>,
    /// The camera's `ShadowFilteringMethod` [Bevy: gaussian].
    #[arg(long, value_enum, default_value_t = Filter::Gaussian)]
    pub filter: Filter,
    /// A directional light's map: `cascade`, one cascade that Bevy fits to the camera's view (what
    /// Bevy ships), or `export`, the exported box and texel grid. Spot lights ignore it.
    #[arg(long, value_enum, default_value_t = Fit::Cascade)]
    pub fit: Fit,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Filter {
    Hardware2x2,
    Gaussian,
    Temporal,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Fit {
    Cascade,
    Export,
}

/// The settings of one render, defaults filled in.
#[derive(Clone, Copy, Debug)]
pub struct Settings {
    pub map_size_texels: u32,
    pub depth_bias: f32,
    pub normal_bias: f32,
    pub filter: Filter,
    pub fit: Fit,
}

impl Args {
    pub fn settings(&self, exported_resolution: u32, spot: bool) -> Result<Settings, String> {
        let map_size_texels = self.map_size.unwrap_or(exported_resolution);
        if map_size_texels == 0 || map_size_texels > 16384 {
            return Err(format!("--map-size {map_size_texels}: expected 1 to 16384 texels"));
        }
        // bevy_pbr light/directional_light.rs and spot_light.rs: 0.02 world units towards the
        // light, 1.8 texels along the normal (times √2 in render/light.rs).
        let (default_depth, default_normal) = if spot {
            (SpotLight::DEFAULT_SHADOW_DEPTH_BIAS, SpotLight::DEFAULT_SHADOW_NORMAL_BIAS)
        } else {
            (DirectionalLight::DEFAULT_SHADOW_DEPTH_BIAS, DirectionalLight::DEFAULT_SHADOW_NORMAL_BIAS)
        };
        let settings = Settings {
            map_size_texels,
            depth_bias: self.depth_bias.unwrap_or(default_depth),
            normal_bias: self.normal_bias.unwrap_or(default_normal),
            filter: self.filter,
            fit: self.fit,
        };
        for (name, v) in [("--depth-bias", settings.depth_bias), ("--normal-bias", settings.normal_bias)] {
            if !v.is_finite() {
                return Err(format!("{name} {v}: not a finite number"));
            }
        }
        Ok(settings)
    }
}
