//! The schedule's sinks that write a report folder as the plan runs: report.json
//! ([`ReportWriter`], with its journal) and the figures ([`FigureSink`]). The schedule knows
//! them only as `plan::Sink`s; the progress bar and timing clock are the command's own.

pub mod figure_sink;
pub mod schedule_order;
mod writer;

pub use figure_sink::FigureSink;
pub use writer::{ReportWriter, remove_stray_report_temp_files};
