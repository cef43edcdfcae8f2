//! Everything a report folder holds besides report.json and the figures, rendered from the
//! report at the end of a command (`shadowtruth report DIR` renders them again): each output is
//! an `Export` in its own file — `report.csv` (`csv_rows.rs`), `plots/` (`plots.rs`, and the
//! per-frame plots of runs over a path: `frame_plots.rs`) and `index.html` (`html.rs`).

use super::Report;
use super::csv_rows::CsvExport;
use super::frame_plots::FramePlotsExport;
use super::html::PageExport;
use super::plots::PlotsExport;
use std::path::Path;

/// One output of a report folder, written from the whole report.
pub trait Export: Sync {
    /// Writes the output into the report folder `dir`.
    fn write(&self, dir: &Path, report: &Report) -> std::io::Result<()>;
}

/// Every output, in the order written (the page links the plots and figures before it).
const EXPORTS: [&dyn Export; 4] = [&CsvExport, &PlotsExport, &FramePlotsExport, &PageExport];

/// Writes report.csv, the plots and index.html into `dir`.
pub fn write_report_outputs(dir: &Path, report: &Report) -> std::io::Result<()> {
    EXPORTS.iter().try_for_each(|export| export.write(dir, report))
}
