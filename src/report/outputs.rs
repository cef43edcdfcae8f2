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

/// Reads `dir/report.json`.
pub fn read_report(dir: &Path) -> Result<Report, String> {
    let path = if dir.is_dir() { dir.join("report.json") } else { dir.to_path_buf() };
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let report: Report = serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    if report.schema != super::REPORT_SCHEMA {
        return Err(format!(
            "{}: schema: expected \"{}\", found \"{}\"",
            path.display(),
            super::REPORT_SCHEMA,
            report.schema
        ));
    }
    Ok(report)
}
