//! `shadowtruth island`: the island of Ehm et al. (WSCG 2015, Figure 12) generated from a seed.

use anyhow::{Context, Result};
use clap::Args;
use std::path::PathBuf;

#[derive(Args)]
pub(super) struct IslandArgs {
    /// Seed of the terrain noise and the tree placement.
    #[arg(long, default_value_t = crate::papers::ISLAND_SEED)]
    seed: u64,
    /// Output folder (created if missing).
    #[arg(short, long, default_value = "scenes/papers")]
    out: PathBuf,
}

pub(super) fn island(a: IslandArgs) -> Result<u8> {
    crate::papers::write_island(&a.out, a.seed)
        .with_context(|| format!("writing the island into {}", a.out.display()))?;
    println!("{}", a.out.join(crate::papers::ISLAND_SCENE_FILE).display());
    Ok(0)
}
