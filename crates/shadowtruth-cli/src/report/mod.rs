//! The paths the outputs had before they moved to modules of their own — `sinks` (report.json
//! and figures as the schedule runs), `exports` (single-file writers), `drawing` (figures,
//! plots, page), `gate`, `shards` (merge, resume) and `outputs` — re-exported while their
//! callers move.

pub use crate::drawing::{figures, summary, tune_chart, write_chart, write_page};
pub use crate::escape::escape_html as escape;
pub use crate::exports::{junit_xml, write_depth_map, write_mask_png, write_soft_exr, write_world_obj};
pub use crate::gate::{CheckedReport, GateOptions, evaluate, load_rules, parse_rules};
pub use crate::outputs::write_report_outputs;
pub use crate::shards::{merge_shards, open_resumed};
pub use crate::sinks::{FigureSink, ReportWriter, remove_stray_report_temp_files};
pub use shadowtruth::record::{ReferenceUsed, Report, RunRecord, Timings, load_report};
