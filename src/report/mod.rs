//! The versioned output types (the only serialized outputs) and the files written from them:
//! report.json, report.csv, figures (PNG), plots, the HTML index, the gate, OBJ exports, masks and
//! soft reference EXRs.

mod csv_rows;
mod depth_map;
mod exports;
mod figure_sink;
pub mod figures;
pub mod font;
mod gate;
mod html;
mod indexed_image;
mod junit;
mod outputs;
mod plots;
mod soft_exr;
mod writer;

pub use crate::record::{
    Machine, REPORT_SCHEMA, ReferenceUsed, Report, RunRecord, SceneRecord, Timings, Tool,
};
pub use csv_rows::report_csv;
pub use depth_map::write_depth_map;
pub use exports::{world_obj, write_mask_png, write_world_obj};
pub use figure_sink::FigureSink;
pub use figures::{
    GridCell, RunFigures, ViewCanvas, downscale, error_map, grid, run_images, run_stem, shaded_base,
    view_stem, visibility_image, write_reference_figure, write_run_figures, zoom,
};
pub use gate::{
    BaselineComparison, BaselineStatus, Check, CheckedReport, GateError, GateOptions, GateOutcome, Measured,
    Metric, Pairing, Regression, Rule, RuleSpec, Rules, RunIdentity, RunName, TechniqueIdentity, Violation,
    evaluate, fmt_value, glob_match, load_report, load_rules, measure, parse_rules,
};
pub use html::{PageAssets, escape, index_html};
pub use indexed_image::IndexedImage;
pub use junit::junit_xml;
pub use outputs::write_report_outputs;
pub use plots::{Chart, charts, pareto_front, write_chart};
pub use soft_exr::{read_soft_exr, write_soft_exr};
pub use writer::{ReportWriter, remove_stray_report_temp_files};
