//! Everything a report folder holds besides report.json and the figures, rendered from the
//! report at the end of a command (`shadowtruth report DIR` renders them again): each output is
//! an [`Export`] in its own file — `report.csv` (`exports/csv_rows.rs`), `plots/`
//! (`drawing/plots.rs`, and the per-frame plots of runs over a path: `drawing/frame_plots.rs`)
//! and `index.html` (`drawing/html.rs`).

use crate::drawing::frame_plots::FramePlotsExport;
use crate::drawing::html::PageExport;
use crate::drawing::plots::PlotsExport;
use crate::export::Export;
use crate::exports::csv_rows::CsvExport;
use shadowtruth::record::Report;
use std::path::Path;

/// Every output, in the order written (the page links the plots and figures before it).
const EXPORTS: [&dyn Export; 4] = [&CsvExport, &PlotsExport, &FramePlotsExport, &PageExport];

/// Writes report.csv, the plots and index.html into `dir`.
pub fn write_report_outputs(dir: &Path, report: &Report) -> std::io::Result<()> {
    EXPORTS.iter().try_for_each(|export| export.write(dir, report))
}
