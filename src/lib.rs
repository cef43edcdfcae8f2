//! shadowtruth: measures how wrong shadow maps are against an exact ray-traced reference.
//!
//! Data flows one way: `scene` → `trace` (BVH, G-buffer, reference) and `raster` (light
//! projection, depth layers) → `technique` (visibility per G-buffer sample) → `metrics` →
//! `report`. `verify` checks the reference against exact predicates. `plan` expands a sweep into runs and schedules the shared work; `cli` parses
//! arguments only.

pub mod atomic_file;
#[doc(hidden)]
pub mod fuzzing;
mod json_input;
pub mod metrics;
pub mod papers;
pub mod plan;
pub mod raster;
pub mod record;
pub mod report;
pub mod scene;
pub mod technique;
pub mod trace;
pub mod verify;
