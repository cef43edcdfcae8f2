//! Plans: which scenes, cameras, lights, techniques, resolutions and depth formats to run, and
//! the schedule that builds every shared intermediate once and sends what it produces to the
//! outputs (sinks).

mod area_light;
mod backend;
mod cascaded_map;
mod default_plan;
mod error;
mod events;
mod execute;
mod file;
mod frames;
mod identity;
mod layer_groups;
mod layers;
mod map_setting;
mod map_setup;
mod point_faces;
mod portion;
mod references;
mod run_record;
mod select;
mod shard;
mod size;
mod spec;
mod trace_shade_score;

pub(crate) use backend::command::{ExportedViews, run_setting};
pub use error::PlanError;
#[cfg(test)]
pub use events::Watch;
pub use events::{Event, Sink, TracedView, emit};
pub use execute::{execute, execute_portion};
pub use file::{PlanInputError, parse_plan, parse_plan_limited, read_plan};
pub use layers::{BinnedView, build_layers_timed};
pub(crate) use map_setup::MapSetup;
pub use portion::{MapKey, Portion};
pub(crate) use references::ViewReferences;
pub(crate) use select::{check_multi_map_lights, check_plan, load_selected};
pub use shard::Shard;
pub use spec::{
    DEFAULT_AREA_LIGHT_GRID, DEFAULT_COVERAGE_GRID, DEFAULT_MAX_RUNS, MAX_FRAMES, MAX_REFERENCE_GRID,
    MAX_REPEATS, Pipeline, Plan,
};
pub use trace_shade_score::{score_against, shade_through, trace_view};
