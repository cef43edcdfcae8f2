//! What the schedule tells its outputs. The executor (`execute.rs`) decides only what to build
//! and in what order; every output — report.json, figures, a progress bar — is a `Sink` that
//! receives these events in order and writes its own file.

use super::PlanError;
use super::references::ViewReferences;
use shadowtruth::raster::DepthFormat;
use shadowtruth::record::{RunRecord, SceneRecord, ScheduleRecord};
use shadowtruth::scene::{Camera, Light, Scene, ViewKey};
use shadowtruth::trace::GBuffer;

/// One (scene, camera, light) view, traced: what every run of the view is scored against.
pub struct TracedView<'a> {
    pub scene: &'a Scene,
    pub camera: &'a Camera,
    pub light: &'a Light,
    pub gbuffer: &'a GBuffer,
    pub references: &'a ViewReferences,
}

impl TracedView<'_> {
    /// The view's names.
    pub fn key(&self) -> ViewKey<'_> {
        ViewKey::from_view(self.scene, self.camera, self.light)
    }
}

/// Progress of a plan, in schedule order.
pub enum Event<'a> {
    /// The number of runs to do (the plan's, or its portion's: `portion.rs`), and the whole
    /// plan's schedule.
    Planned { runs: usize, schedule: &'a ScheduleRecord },
    /// A stage began (a short description, for progress bars and logs).
    Stage(&'a str),
    /// A scene was loaded and its BVH built.
    SceneBuilt(&'a SceneRecord),
    /// A view's G-buffer and references are ready; its runs follow.
    ViewTraced(&'a TracedView<'a>),
    /// A run finished: its record, and its visibility per evaluated pixel (in the order of the
    /// G-buffer's `evaluated`), for outputs that need more than the record.
    RunDone { record: &'a RunRecord, visibility: &'a [f32] },
    /// One frame of a run over a path (`run --frames`), before the run's `RunDone`: the frame's
    /// view, the run's record for this frame alone, its visibility, and the frame's index of
    /// `frames`.
    FrameDone {
        view: &'a TracedView<'a>,
        record: &'a RunRecord,
        visibility: &'a [f32],
        frame: u32,
        frames: u32,
    },
    /// A run over a path ended (just before its `RunDone`, with the same record): how many times
    /// each pixel of the camera image flickered, row-major, `width` × `height`.
    FlickerDone { record: &'a RunRecord, heat: &'a [u16], width: u32, height: u32 },
    /// Every run of the view at this shadow-map resolution and depth format has finished.
    MapsDone { view: &'a TracedView<'a>, resolution: u32, format: DepthFormat },
}

/// An output of the schedule (in the style of hyperfine's exporters: one trait, each output
/// its own type and file).
pub trait Sink {
    /// Receives every event in schedule order; an error stops the plan.
    fn on_event(&mut self, event: &Event) -> Result<(), PlanError>;
}

#[cfg(test)]
/// A sink made of a closure, for callers that only watch (progress, tests).
pub struct Watch<F: FnMut(&Event)>(pub F);

#[cfg(test)]
impl<F: FnMut(&Event)> Sink for Watch<F> {
    fn on_event(&mut self, event: &Event) -> Result<(), PlanError> {
        (self.0)(event);
        Ok(())
    }
}

/// Sends `event` to every sink in order.
pub fn emit(sinks: &mut [&mut dyn Sink], event: &Event) -> Result<(), PlanError> {
    sinks.iter_mut().try_for_each(|sink| sink.on_event(event))
}
