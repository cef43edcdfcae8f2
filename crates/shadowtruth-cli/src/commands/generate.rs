//! `shadowtruth generate`: a procedural city or forest of a given size, the same bytes for the
//! same arguments.

use super::args::set_threads;
use crate::option_values::threads_parser;
use anyhow::{Context, Result};
use clap::Args;
use shadowtruth::scene::MAX_IMAGE_SIDE;
use std::path::PathBuf;

#[derive(Args)]
pub(super) struct GenerateArgs {
    /// city or forest.
    #[arg(value_enum)]
    kind: crate::generate::SceneKind,
    /// Triangles to generate: a count such as 500000, 250K or 10M (1000 to 16.7M; 200K to 2147M
    /// with --instanced).
    #[arg(long, value_parser = crate::generate::parse_triangle_count)]
    triangles: u64,
    /// Seed of the terrain and of the casters' placement and sizes.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// The camera's image width and height in pixels.
    #[arg(long, value_name = "W,H", default_value = "1920,1080", value_parser = parse_image_size)]
    image: (u32, u32),
    /// Output folder (created if missing); files of the same names in it are replaced.
    #[arg(short, long, value_name = "DIR")]
    out: PathBuf,
    /// forest only: one finely tessellated tree placed at every tree by `instances`, stored
    /// once and traced through a two-level BVH (memory of one tree, however many are placed).
    #[arg(long)]
    instanced: bool,
    /// Worker threads for writing the meshes, 1 to 1024 (default: all cores).
    #[arg(long, value_parser = threads_parser())]
    threads: Option<usize>,
}

pub(super) fn generate(a: GenerateArgs) -> Result<u8> {
    set_threads(a.threads)?;
    let (width_px, height_px) = a.image;
    let options = crate::generate::GenerateOptions {
        kind: a.kind,
        triangles: a.triangles,
        seed: a.seed,
        width_px,
        height_px,
        instanced: a.instanced,
    };
    // Checked against the loader's own limits before the folder is touched.
    crate::generate::check_options(&options).map_err(anyhow::Error::msg)?;
    let (path, triangles) = crate::generate::write_generated(&a.out, &options)
        .with_context(|| format!("writing the scene into {}", a.out.display()))?;
    println!("{} ({triangles} triangles)", path.display());
    Ok(0)
}

/// `--image W,H`: the camera's width and height in pixels, each 1 to the scene format's limit.
fn parse_image_size(text: &str) -> Result<(u32, u32), String> {
    let side =
        |n: &str| n.trim().parse::<u32>().ok().filter(|&s| (1..=MAX_IMAGE_SIDE).contains(&u64::from(s)));
    match text.split(',').map(side).collect::<Vec<_>>()[..] {
        [Some(width_px), Some(height_px)] => Ok((width_px, height_px)),
        [_, _] => Err(format!("each side must be a number from 1 to {MAX_IMAGE_SIDE}")),
        _ => Err("expected the width and height: W,H".into()),
    }
}
