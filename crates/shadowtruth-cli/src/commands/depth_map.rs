//! `shadowtruth depth-map`: one depth layer of a light as a one-channel f32 EXR with a JSON
//! sidecar (clip_from_world, near, far), to check the rasterizer against another.

use super::named_item::pick;
use crate::option_values::depth_format_parser;
use anyhow::{Context, Result};
use clap::Args;
use shadowtruth::raster::{
    Culling, DepthFormat, LightView, MAX_SHADOW_MAP_RESOLUTION, RasterSettings, rasterize_nearest,
    rasterize_two_nearest,
};
use shadowtruth::scene::load_scene;
use std::path::PathBuf;

#[derive(Args)]
pub(super) struct DepthMapArgs {
    /// The scene file, or a glTF file (.gltf, .glb) as a scene.
    scene: PathBuf,
    /// Light name (default: the scene's first light).
    #[arg(long)]
    light: Option<String>,
    /// Shadow-map resolution (texels per side), 1 to 16384.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=MAX_SHADOW_MAP_RESOLUTION as i64))]
    resolution: u32,
    /// 1: the nearest surface; 2: the second-nearest distinct surface.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u8).range(1..=2))]
    layer: u8,
    /// Depth format.
    #[arg(long, default_value = "f32", value_parser = depth_format_parser())]
    format: DepthFormat,
    /// Faces of closed objects left out.
    #[arg(long, value_enum, default_value_t = Cull::None)]
    cull: Cull,
    /// The one-channel f32 EXR to write (*.exr); its JSON sidecar goes beside it.
    #[arg(short, long)]
    out: PathBuf,
}

pub(super) fn depth_map(a: DepthMapArgs) -> Result<u8> {
    super::args::check_output_extension(&a.out, "exr", "a one-channel f32 EXR")?;
    let format = a.format;
    let scene = load_scene(&a.scene)?;
    let light = pick(&scene.lights, a.light.as_deref(), |l| &l.name, "light", &a.scene)?;
    if light.is_point() {
        anyhow::bail!(
            "{}: light '{}' is a point light, whose shadow map is a cube of six faces; depth-map writes the one \
             map of a directional or spot light",
            a.scene.display(),
            light.name
        );
    }
    let view = LightView::new(light, scene.bounds(), a.resolution);
    let settings = RasterSettings { format, culling: a.cull.culling(), ..RasterSettings::default() };
    let layer = if a.layer == 1 {
        rasterize_nearest(&scene, &view, &settings)
    } else {
        let pairs = rasterize_two_nearest(&scene, &view, &settings);
        shadowtruth::raster::DepthLayer {
            resolution: pairs.resolution,
            depth: pairs.depth.iter().map(|p| p[1]).collect(),
        }
    };
    let description = serde_json::json!({ "index": a.layer, "format": format.name(), "cull": a.cull.name(), "light": light.name });
    crate::exports::write_depth_map(&a.out, &layer, &view, description)
        .with_context(|| format!("writing {}", a.out.display()))?;
    Ok(0)
}

/// The faces of closed objects `--cull` leaves out of the map.
#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(super) enum Cull {
    None,
    Back,
    Front,
}

impl Cull {
    fn culling(self) -> Culling {
        match self {
            Cull::None => Culling::None,
            Cull::Back => Culling::BackFacesOfClosed,
            Cull::Front => Culling::FrontFacesOfClosed,
        }
    }

    /// The name on the command line, as the sidecar records it.
    fn name(self) -> &'static str {
        match self {
            Cull::None => "none",
            Cull::Back => "back",
            Cull::Front => "front",
        }
    }
}
