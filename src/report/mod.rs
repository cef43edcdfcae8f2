//! The versioned output types (the only serialized outputs) and the files written from them:
//! report.json, report.csv, plots, the HTML index, OBJ exports and masks.

mod csv_rows;
mod exports;
mod html;
mod outputs;
mod plots;
mod record;
mod writer;

pub use csv_rows::report_csv;
pub use exports::{world_obj, write_mask_png, write_world_obj};
pub use html::{PageAssets, escape, index_html};
pub use outputs::{read_report, write_report_outputs};
pub use plots::{Chart, charts, pareto_front, write_chart};
pub use record::{Machine, REPORT_SCHEMA, Report, RunRecord, SceneRecord, Timings, Tool};
pub use writer::ReportWriter;
