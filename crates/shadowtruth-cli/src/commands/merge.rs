//! `shadowtruth merge`: the report folders of `run --shard K/N` joined into one, as the whole run
//! would have written it apart from timings.

use anyhow::Result;
use clap::Args;
use std::path::PathBuf;

#[derive(Args)]
pub(super) struct MergeArgs {
    /// The shard folders (each written by `run --shard K/N`).
    #[arg(required = true, value_name = "DIR")]
    dirs: Vec<PathBuf>,
    /// Output folder (created if missing; an earlier report there is replaced).
    #[arg(short, long, value_name = "OUT")]
    out: PathBuf,
    /// No summary line.
    #[arg(short, long)]
    quiet: bool,
}

pub(super) fn merge(a: MergeArgs) -> Result<u8> {
    let report = crate::shards::merge_shards(&a.dirs, &a.out)?;
    if !a.quiet {
        println!(
            "merged {} shards: {} runs; report: {} (open {})",
            a.dirs.len(),
            report.runs.len(),
            a.out.join("report.json").display(),
            a.out.join("index.html").display()
        );
    }
    Ok(0)
}
