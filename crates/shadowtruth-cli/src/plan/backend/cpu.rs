//! The CPU back-end: each layer group's depth layers rasterized once per map setting (or the
//! imported shadow map read in their place), then every member technique shaded through them,
//! each timed as the median of the plan's repeats.

use super::{MapBackend, ProducedRun, RunRecorder};
use crate::plan::events::TracedView;
use crate::plan::layer_groups::{LayerGroups, group_label};
use crate::plan::layers::{BinnedView, build_layers_timed};
use crate::plan::map_setting::MapSetting;
use crate::plan::{Plan, PlanError};
use shadowtruth::metrics::{RepeatTimes, timed_repeats};
use shadowtruth::scene::Scene;
use shadowtruth::technique::{BuiltLayers, LayerNeeds, TechniqueSpec};

pub(in crate::plan) struct CpuBackend<'p> {
    plan: &'p Plan,
    groups: &'p LayerGroups,
}

impl<'p> CpuBackend<'p> {
    pub fn new(plan: &'p Plan, groups: &'p LayerGroups) -> Self {
        CpuBackend { plan, groups }
    }
}

impl MapBackend for CpuBackend<'_> {
    fn produce(
        &mut self,
        traced: &TracedView,
        map: &MapSetting,
        recorder: &mut dyn RunRecorder,
    ) -> Result<(), PlanError> {
        let (scene, camera, light) = (traced.scene, traced.camera, traced.light);
        // Each map binned when the first group needs it, then shared by the others.
        let mut binned: Vec<BinnedView> = Vec::new();
        // The layers of the group before, their memory reused by the next group's.
        let mut spares: Vec<BuiltLayers> = Vec::new();
        for (needs, members) in self.groups {
            let (resolution, format) = (map.resolution, map.format.name());
            // Two stages a group, so that `--timing` names its rasterization and its shading apart.
            let group = format!(
                "{}/{}/{}: {resolution}² {format} layers, {}",
                scene.name,
                camera.name,
                light.name,
                group_label(needs)
            );
            recorder.stage(&format!("{group}: rasterizing"))?;
            let (layers, prepare_ms) = group_layers(self.plan, needs, scene, map, &mut binned, spares);
            let count = members.len();
            recorder.stage(&format!(
                "{group}: shading and scoring {count} technique{}",
                if count == 1 { "" } else { "s" }
            ))?;
            let layer_memory_bytes = layers.iter().map(|l| l.memory_bytes() as u64).sum();
            for &ti in members {
                let spec = &self.plan.techniques[ti];
                let (visibility, shade) = shade_timed(self.plan.repeats, spec, scene, map, &layers);
                let run = ProducedRun {
                    spec,
                    visibility: &visibility,
                    prepare_ms,
                    shade_ms: shade.median_ms,
                    shade_range_ms: Some([shade.min_ms, shade.max_ms]),
                    layer_memory_bytes,
                    pipeline: None,
                };
                recorder.record(run)?;
            }
            spares = layers;
        }
        Ok(())
    }
}

/// The layers `needs` asks for, one per map of `map` (each cascade's, or the one), built from
/// the maps' binned triangles (binned here on first use) into the memory of `spares` where it
/// fits, and the time they took (ms).
pub(in crate::plan) fn group_layers<'m>(
    plan: &Plan,
    needs: &LayerNeeds,
    scene: &'m Scene,
    map: &MapSetting<'m>,
    binned: &mut Vec<BinnedView<'m>>,
    spares: Vec<BuiltLayers>,
) -> (Vec<BuiltLayers>, f64) {
    if let Some(map_file) = &plan.shadow_map {
        return (vec![BuiltLayers::Nearest(map_file.layer.clone())], 0.0);
    }
    if binned.is_empty() {
        binned.extend(map.views().into_iter().map(|view| BinnedView::new(scene, view)));
    }
    let mut total_ms = 0.0;
    let mut spares = spares.into_iter();
    let layers = binned
        .iter()
        .map(|b| {
            let (layers, ms) = build_layers_timed(b, map.format, needs, plan.repeats, spares.next());
            total_ms += ms;
            layers
        })
        .collect();
    (layers, total_ms)
}

/// The technique's visibility of every evaluated sample through `layers` (one per map of
/// `map`), and the shading times of `repeats` (their median and range).
pub(in crate::plan) fn shade_timed(
    repeats: usize,
    spec: &TechniqueSpec,
    scene: &Scene,
    map: &MapSetting,
    layers: &[BuiltLayers],
) -> (Vec<f32>, RepeatTimes) {
    let technique = spec.build().expect("only shaded techniques are in a layer group");
    // The contexts are built once, outside the clock: only shading is timed.
    let contexts = map.contexts(scene, layers);
    timed_repeats(repeats, || map.shade(technique.as_ref(), &contexts))
}
