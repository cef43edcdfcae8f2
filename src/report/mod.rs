//! The versioned output types (the only serialized outputs) and the files written from them:
//! report.json, masks, OBJ and figures (PNG).

mod exports;
pub mod figures;
pub mod font;
mod record;
mod writer;

pub use exports::{world_obj, write_mask_png, write_world_obj};
pub use figures::{
    GridCell, RunFigures, error_map, grid, run_stem, shaded_base, view_stem, visibility_image, write_grid,
    write_reference_figure, write_run_figures, zoom,
};
pub use record::{Machine, REPORT_SCHEMA, Report, RunRecord, SceneRecord, Timings, Tool};
pub use writer::ReportWriter;
