//! Everything a report folder holds besides report.json, rendered from it: `report.csv`,
//! `plots/` and `index.html`. `shadowtruth report DIR` calls this on an existing report.

use super::html::{PageAssets, index_html};
use super::{Report, charts, report_csv, write_chart};
use crate::atomic_file::write_atomic;
use rayon::prelude::*;
use std::path::Path;

/// Writes report.csv, the plots and index.html into `dir`; `figures` lists figure files already
/// written under `dir` (see `PageAssets`).
pub fn write_report_outputs(dir: &Path, report: &Report, mut assets: PageAssets) -> std::io::Result<()> {
    let csv = report_csv(report).map_err(std::io::Error::other)?;
    write_atomic(&dir.join("report.csv"), csv.as_bytes())?;
    let plots_dir = dir.join("plots");
    std::fs::create_dir_all(&plots_dir)?;
    let all = charts(report);
    all.par_iter().map(|c| write_chart(&plots_dir, c)).collect::<std::io::Result<Vec<()>>>()?;
    assets.plots = all.iter().map(|c| c.stem.clone()).collect();
    write_atomic(&dir.join("index.html"), index_html(report, &assets).as_bytes())
}
