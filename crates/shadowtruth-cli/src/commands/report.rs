//! `shadowtruth report`: report.csv, the plots and index.html of a report folder rendered again
//! from its report.json, without running anything.

use crate::outputs::write_report_outputs;
use anyhow::{Context, Result};
use clap::Args;
use shadowtruth::record::load_journaled_report;
use std::path::{Path, PathBuf};

#[derive(Args)]
pub(super) struct ReportArgs {
    /// A report folder (holding report.json).
    dir: PathBuf,
}

pub(super) fn report(a: ReportArgs) -> Result<u8> {
    // A killed run's folder: report.json and the runs its journal holds since.
    let (report, file) = load_journaled_report(&a.dir)?;
    let dir = file.parent().unwrap_or(Path::new(".")).to_path_buf();
    crate::sinks::remove_stray_report_temp_files(&dir)
        .with_context(|| format!("cleaning {}", dir.display()))?;
    write_report_outputs(&dir, &report).with_context(|| format!("writing into {}", dir.display()))?;
    println!("{}", dir.join("index.html").display());
    Ok(0)
}
