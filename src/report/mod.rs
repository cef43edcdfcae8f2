//! The versioned output types (the only serialized outputs) and the files written from them.

mod exports;
mod gate;
mod junit;
mod record;
mod writer;

pub use exports::{world_obj, write_mask_png, write_world_obj};
pub use gate::{
    BaselineStatus, Check, GateError, GateOutcome, Measured, Metric, Regression, Rule, RuleSpec, Rules,
    RunKey, Violation, evaluate, fmt_value, glob_match, load_report, load_rules, measure, parse_rules,
};
pub use junit::junit_xml;
pub use record::{Machine, REPORT_SCHEMA, Report, RunRecord, SceneRecord, Timings, Tool};
pub use writer::ReportWriter;
