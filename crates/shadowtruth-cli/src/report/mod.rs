//! The versioned output types (the only serialized outputs) and the files written from them:
//! report.json, report.csv, figures (PNG), plots, the HTML index, the gate, OBJ exports, masks and
//! soft reference EXRs.

mod cascades_section;
pub mod csv_rows;
mod depth_map;
mod exports;
mod figure_sink;
pub mod figures;
pub mod flicker_map;
pub mod font;
pub mod frame_movie;
pub mod frame_plots;
pub mod gate;
pub mod html;
pub mod indexed_image;
mod junit;
mod merge;
mod outputs;
mod path_section;
pub mod plots;
mod resume;
mod schedule_order;
mod soft_exr;
pub mod summary;
mod tune_plot;
mod writer;

pub use depth_map::write_depth_map;
pub use exports::{write_mask_png, write_world_obj};
pub use figure_sink::FigureSink;
pub use gate::{CheckedReport, GateOptions, evaluate, load_rules, parse_rules};
pub use html::{escape, write_page};
pub use junit::junit_xml;
pub use merge::merge_shards;
pub use outputs::write_report_outputs;
pub use plots::write_chart;
pub use resume::open_resumed;
pub use shadowtruth::record::load_report;
pub use shadowtruth::record::{ReferenceUsed, Report, RunRecord, SceneRecord, Timings};
pub use soft_exr::write_soft_exr;
pub use tune_plot::tune_chart;
pub use writer::{ReportWriter, remove_stray_report_temp_files};
