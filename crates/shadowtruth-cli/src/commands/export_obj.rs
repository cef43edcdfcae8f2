//! `shadowtruth export-obj`: a scene's world-space triangles as OBJ, one group per object.

use crate::exports::write_world_obj;
use anyhow::{Context, Result};
use clap::Args;
use shadowtruth::scene::load_scene;
use std::path::PathBuf;

#[derive(Args)]
pub(super) struct ExportObjArgs {
    /// The scene file, or a glTF file (.gltf, .glb) as a scene.
    scene: PathBuf,
    /// The OBJ file to write (*.obj).
    #[arg(short, long)]
    out: PathBuf,
}

pub(super) fn export_obj(a: ExportObjArgs) -> Result<u8> {
    super::args::check_output_extension(&a.out, "obj", "the world-space triangles as OBJ")?;
    let scene = load_scene(&a.scene)?;
    write_world_obj(&scene, &a.out).with_context(|| format!("writing {}", a.out.display()))?;
    Ok(0)
}
