//! Plans: which scenes, cameras, lights, techniques, resolutions and depth formats to run, and
//! the schedule that builds every shared intermediate once.

mod execute;
mod file;
mod spec;

pub use execute::{Event, PlanError, execute};
pub use file::{PLAN_FORMAT, read_plan};
pub use spec::{Plan, default_techniques};
