//! `shadowtruth view-export`: everything an engine needs to render the same pixels under the
//! same light (view.json, the G-buffer as EXRs, the scene as glTF binary).

use super::args::set_threads;
use super::named_item::pick;
use crate::option_values::threads_parser;
use anyhow::Result;
use clap::Args;
use indicatif::ProgressBar;
use shadowtruth::raster::MAX_SHADOW_MAP_RESOLUTION;
use shadowtruth::scene::load_scene;
use std::path::PathBuf;

#[derive(Args)]
pub(super) struct ViewExportArgs {
    /// The scene file (shadowtruth/scene/v1), or a glTF file (.gltf, .glb) as a scene.
    scene: PathBuf,
    /// Camera name (default: the scene's first camera).
    #[arg(long)]
    camera: Option<String>,
    /// Light name (default: the scene's first light).
    #[arg(long)]
    light: Option<String>,
    /// Shadow-map resolution (texels per side) of the light's exported view.
    #[arg(long, default_value_t = 2048,
          value_parser = clap::value_parser!(u32).range(1..=MAX_SHADOW_MAP_RESOLUTION as i64))]
    resolution: u32,
    /// Output folder (created if missing); files of the same names in it are replaced.
    #[arg(short, long, value_name = "DIR")]
    out: PathBuf,
    /// Worker threads, 1 to 1024 (default: all cores).
    #[arg(long, value_parser = threads_parser())]
    threads: Option<usize>,
    /// No progress messages and no list of files.
    #[arg(short, long)]
    quiet: bool,
}

pub(super) fn view_export(a: ViewExportArgs) -> Result<u8> {
    set_threads(a.threads)?;
    let scene = load_scene(&a.scene)?;
    let camera = pick(&scene.cameras, a.camera.as_deref(), |c| &c.name, "camera", &a.scene)?;
    let light = pick(&scene.lights, a.light.as_deref(), |l| &l.name, "light", &a.scene)?;
    let bar = if a.quiet { ProgressBar::hidden() } else { ProgressBar::new_spinner() };
    bar.enable_steady_tick(std::time::Duration::from_millis(120));
    let files = crate::view_export::write_view_export(&scene, camera, light, a.resolution, &a.out, |step| {
        bar.set_message(step.to_string())
    })?;
    bar.finish_and_clear();
    if !a.quiet {
        for f in files {
            println!("{}", f.display());
        }
    }
    Ok(0)
}
