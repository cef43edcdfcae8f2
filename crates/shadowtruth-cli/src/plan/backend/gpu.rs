//! The GPU back-end: each layer group's map (or a point light's six faces) drawn on a Vulkan
//! device once per map setting (timed as `prepare`), then every member technique shaded there
//! (`shade`), each the median of the plan's repeats.

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
        // The maps drawn: the one, or a point light's six faces, each evaluated pixel shaded
        // through its own face (as on the CPU).
        let views = map.views();
        let view_of = |k: usize| map.cube.map_or(0, |cube| cube.face(k));
        let layer_memory_bytes = views.iter().map(|v| v.resolution as u64 * v.resolution as u64 * 4).sum();
        // One map per layer group and view, as on the CPU: drawn once, read by every technique of
        // the group. Imported techniques are in no group (`imported.rs`).
        for (needs, members) in self.groups {
            recorder.stage(&format!(
                "{}/{}/{}: {}² on the GPU",
                scene.name, camera.name, light.name, map.resolution
            ))?;
            let settings = GpuTechnique::raster_settings_of(needs);
            let mut depth_maps = Vec::with_capacity(views.len());
            let mut prepare_ms = 0.0;
            for view in &views {
                let (depth_map, ms) = try_timed_median(self.plan.repeats, || {
                    let drawn = gpu.checked(|| GpuDepthMap::render(gpu, scene, view, &settings))?;
                    gpu.wait()?;
                    Ok(drawn)
                })
                .map_err(failed)?;
                depth_maps.push(depth_map);
                prepare_ms += ms;
            }
            for &ti in members {
                let spec = &self.plan.techniques[ti];
                let technique = GpuTechnique::from_spec(spec).map_err(failed)?;
                let mut images = Vec::with_capacity(views.len());
                let mut shade_ms = 0.0;
                for (view, depth_map) in views.iter().zip(&depth_maps) {
                    let (image, ms) = try_timed_median(self.plan.repeats, || {
                        gpu.checked(|| shade_visibility(gpu, traced.gbuffer, view, depth_map, technique))
                    })
                    .map_err(failed)?;
                    images.push(image);
                    shade_ms += ms;
                }
                let evaluated = traced.gbuffer.evaluated.iter().enumerate();
                let visibility: Vec<f32> = evaluated.map(|(k, &i)| images[view_of(k)][i as usize]).collect();
                let run = ProducedRun {
                    spec,
                    visibility: &visibility,
                    prepare_ms,
                    shade_ms,
                    shade_range_ms: None,
                    layer_memory_bytes,
                    pipeline: Some(&self.used),
                };
                recorder.record(run)?;
            }
        }
        Ok(())
    }
}
