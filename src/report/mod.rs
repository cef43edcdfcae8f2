//! The versioned output types (the only serialized outputs) and the files written from them.

mod exports;
mod record;
mod writer;

pub use exports::{world_obj, write_mask_png, write_world_obj};
pub use record::{Machine, REPORT_SCHEMA, Report, RunRecord, SceneRecord, Timings, Tool};
pub use writer::ReportWriter;
