//! Plans: which scenes, cameras, lights, techniques, resolutions and depth formats to run, and
//! the schedule that builds every shared intermediate once.

mod area_light;
mod execute;
mod file;
mod layers;
mod references;
mod size;
mod spec;

pub use execute::{Event, PlanError, execute};
pub use file::{DEFAULT_MAX_RUNS, PLAN_FORMAT, PlanInputError, parse_plan, parse_plan_limited, read_plan};
pub use layers::{BuiltLayers, build_layers};
pub use spec::{DEFAULT_AREA_LIGHT_GRID, DEFAULT_COVERAGE_GRID, DEFAULT_PLAN_JSON, MAX_REFERENCE_GRID, Plan};
