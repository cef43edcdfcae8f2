//! The imported back-end: the buffers of the plan's `external` techniques, read once per view
//! (visibility, and depth to find surface mismatches); at every map setting the same buffers
//! are scored again, the resolution giving the attribution its texel footprint.

use super::{MapBackend, ProducedRun, RunRecorder};
use crate::plan::events::TracedView;
use crate::plan::map_setting::MapSetting;
use crate::plan::{Plan, PlanError};
use shadowtruth::import::evaluated_visibility;
use shadowtruth::metrics::Stopwatch;
use shadowtruth::technique::{ExternalParams, TechniqueSpec};

/// An imported technique of one view: its spec with the view's files, the visibility of every
/// evaluated pixel (NaN for a surface mismatch) and the time spent reading it.
struct Imported {
    spec: TechniqueSpec,
    visibility: Vec<f32>,
    read_ms: f64,
}

/// The imported techniques of one view.
pub(in crate::plan) struct ImportedBackend {
    imported: Vec<Imported>,
}

impl ImportedBackend {
    /// Reads the buffers of `plan`'s `external` techniques for the view.
    pub fn load(plan: &Plan, traced: &TracedView) -> Result<Self, PlanError> {
        let mut imported = Vec::new();
        for spec in &plan.techniques {
            let TechniqueSpec::External(params) = spec else { continue };
            let params = params
                .for_view(&traced.scene.name, &traced.camera.name, &traced.light.name)
                .map_err(|e| PlanError::Invalid(format!("{}: {e}", traced.scene.source.display())))?;
            let sw = Stopwatch::start();
            let visibility = read_external(&params, traced).map_err(PlanError::Import)?;
            imported.push(Imported { spec: TechniqueSpec::External(params), visibility, read_ms: sw.ms() });
        }
        Ok(ImportedBackend { imported })
    }
}

impl MapBackend for ImportedBackend {
    fn produce(
        &mut self,
        _traced: &TracedView,
        _map: &MapSetting,
        recorder: &mut dyn RunRecorder,
    ) -> Result<(), PlanError> {
        for run in &self.imported {
            let produced = ProducedRun {
                spec: &run.spec,
                visibility: &run.visibility,
                prepare_ms: run.read_ms,
                shade_ms: 0.0,
                shade_range_ms: None,
                layer_memory_bytes: 0,
                pipeline: None,
            };
            recorder.record(produced)?;
        }
        Ok(())
    }
}

/// The visibility of every evaluated pixel of `params`' files (NaN for a surface mismatch).
pub(super) fn read_external(
    params: &ExternalParams,
    traced: &TracedView,
) -> Result<Vec<f32>, shadowtruth::Error> {
    // Both checked against the camera's size before a pixel is decoded.
    let (visibility, depth) = params.read_buffers(traced.camera)?;
    Ok(evaluated_visibility(
        traced.gbuffer,
        traced.camera,
        &visibility,
        depth.as_ref(),
        params.depth_tolerance(),
    )?)
}
