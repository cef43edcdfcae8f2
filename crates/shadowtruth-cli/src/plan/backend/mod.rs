//! What produces the visibility of every technique at one map setting of a traced view: the
//! CPU rasterizer and techniques (`cpu.rs`), a Vulkan device (`gpu.rs`, with the `gpu` feature),
//! another renderer's buffers read once per view (`imported.rs`), or another renderer run by its
//! command line per setting (`command.rs`). The schedule records the runs of any of them the
//! same way (`execute.rs`).

pub(super) mod command;
mod command_process;
pub(super) mod cpu;
#[cfg(feature = "gpu")]
pub(super) mod gpu;
pub(super) mod imported;

use super::PlanError;
use super::events::TracedView;
use super::map_setting::MapSetting;
use shadowtruth::record::PipelineUsed;
use shadowtruth::technique::TechniqueSpec;

/// One technique's run at one map setting, as a back-end produced it.
pub(in crate::plan) struct ProducedRun<'a> {
    pub spec: &'a TechniqueSpec,
    /// Per evaluated pixel, in the G-buffer's `evaluated` order.
    pub visibility: &'a [f32],
    /// Building (or reading) what the technique reads, ms.
    pub prepare_ms: f64,
    /// Shading, ms (0 where not timed here).
    pub shade_ms: f64,
    /// The least and greatest shading time of the repeats, where shading was repeated, ms.
    pub shade_range_ms: Option<[f64; 2]>,
    pub layer_memory_bytes: u64,
    /// The device, when not the CPU.
    pub pipeline: Option<&'a PipelineUsed>,
}

/// Where a back-end sends the stage under way and each run it produces.
pub(in crate::plan) trait RunRecorder {
    fn stage(&mut self, what: &str) -> Result<(), PlanError>;
    fn record(&mut self, run: ProducedRun) -> Result<(), PlanError>;
}

/// A producer of the runs of its techniques at one map setting, in the order they are reported.
pub(in crate::plan) trait MapBackend {
    fn produce(
        &mut self,
        traced: &TracedView,
        map: &MapSetting,
        recorder: &mut dyn RunRecorder,
    ) -> Result<(), PlanError>;
}
