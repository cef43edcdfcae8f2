//! The versioned output types (the only serialized outputs) and the files written from them:
//! report.json, report.csv, plots, the HTML index, OBJ exports and masks.

mod csv_rows;
mod exports;
mod gate;
mod html;
mod junit;
mod outputs;
mod plots;
mod record;
mod writer;

pub use csv_rows::report_csv;
pub use exports::{world_obj, write_mask_png, write_world_obj};
pub use gate::{
    BaselineStatus, Check, GateError, GateOutcome, Measured, Metric, Regression, Rule, RuleSpec, Rules,
    RunKey, Violation, evaluate, fmt_value, glob_match, load_report, load_rules, measure, parse_rules,
};
pub use html::{PageAssets, escape, index_html};
pub use junit::junit_xml;
pub use outputs::write_report_outputs;
pub use plots::{Chart, charts, pareto_front, write_chart};
pub use record::{Machine, REPORT_SCHEMA, Report, RunRecord, SceneRecord, Timings, Tool};
pub use writer::ReportWriter;
