//! One output of a report folder written from the whole report: the trait both the exports
//! (`exports/`) and the drawing (`drawing/`) implement, and `outputs.rs` lists.

use shadowtruth::record::Report;
use std::path::Path;

/// One output of a report folder, written from the whole report.
pub trait Export: Sync {
    /// Writes the output into the report folder `dir`.
    fn write(&self, dir: &Path, report: &Report) -> std::io::Result<()>;
}
