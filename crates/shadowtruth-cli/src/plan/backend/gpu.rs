//! The GPU back-end: each layer group's map drawn on a Vulkan device once per map setting
//! (timed as `prepare`), then every member technique shaded there (`shade`), each the median of
//! the plan's repeats.

use super::{MapBackend, ProducedRun, RunRecorder};
use crate::plan::events::TracedView;
use crate::plan::layer_groups::LayerGroups;
use crate::plan::map_setting::MapSetting;
use crate::plan::{Plan, PlanError};
use shadowtruth::metrics::try_timed_median;
use shadowtruth::record::PipelineUsed;
use shadowtruth_gpu::{GpuDepthMap, GpuDevice, GpuError, GpuTechnique, shade_visibility};

pub(in crate::plan) struct GpuBackend<'p> {
    plan: &'p Plan,
    groups: &'p LayerGroups,
    device: GpuDevice,
    /// The device as each run's record names it.
    used: PipelineUsed,
}

impl<'p> GpuBackend<'p> {
    /// Opens the device: a machine without a Vulkan adapter is told before anything is traced.
    pub fn new(plan: &'p Plan, groups: &'p LayerGroups) -> Result<Self, PlanError> {
        let device = GpuDevice::new().map_err(|e| PlanError::Invalid(e.to_string()))?;
        let adapter = device.adapter();
        let used = PipelineUsed {
            name: "gpu".into(),
            adapter: adapter.name,
            driver: adapter.driver,
            backend: adapter.backend,
        };
        Ok(GpuBackend { plan, groups, device, used })
    }
}

impl MapBackend for GpuBackend<'_> {
    fn produce(
        &mut self,
        traced: &TracedView,
        map: &MapSetting,
        recorder: &mut dyn RunRecorder,
    ) -> Result<(), PlanError> {
        let (scene, camera, light) = (traced.scene, traced.camera, traced.light);
        let gpu = &self.device;
        let failed =
            |e: GpuError| PlanError::Invalid(format!("{}/{}/{}: {e}", scene.name, camera.name, light.name));
        // One map per layer group, as on the CPU: drawn once, read by every technique of the
        // group. Imported techniques are in no group (`imported.rs`).
        for (needs, members) in self.groups {
            recorder.stage(&format!(
                "{}/{}/{}: {}² on the GPU",
                scene.name, camera.name, light.name, map.resolution
            ))?;
            let settings = GpuTechnique::raster_settings_of(needs);
            let (depth_map, prepare_ms) = try_timed_median(self.plan.repeats, || {
                let drawn = gpu.checked(|| GpuDepthMap::render(gpu, scene, map.view, &settings))?;
                gpu.wait()?;
                Ok(drawn)
            })
            .map_err(failed)?;
            for &ti in members {
                let spec = &self.plan.techniques[ti];
                let technique = GpuTechnique::from_spec(spec).map_err(failed)?;
                let (image, shade_ms) = try_timed_median(self.plan.repeats, || {
                    gpu.checked(|| shade_visibility(gpu, traced.gbuffer, map.view, &depth_map, technique))
                })
                .map_err(failed)?;
                let visibility: Vec<f32> =
                    traced.gbuffer.evaluated.iter().map(|&i| image[i as usize]).collect();
                let run = ProducedRun {
                    spec,
                    visibility: &visibility,
                    prepare_ms,
                    shade_ms,
                    layer_memory_bytes: map.resolution as u64 * map.resolution as u64 * 4,
                    pipeline: Some(&self.used),
                };
                recorder.record(run)?;
            }
        }
        Ok(())
    }
}
