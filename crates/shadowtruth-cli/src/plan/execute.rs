//! Runs a plan. The schedule follows the data: a scene's BVH once; per (camera, light) the
//! G-buffer and references once; per (resolution, depth format) the runs of every technique from
//! its back-end (`backend/`), each group's depth layers built once and shared by every
//! technique that reads them. What it produces goes to the sinks as events (`events.rs`); the
//! schedule itself writes nothing.

use super::backend::command::CommandBackend;
use super::backend::cpu::CpuBackend;
#[cfg(feature = "gpu")]
use super::backend::gpu::GpuBackend;
use super::backend::imported::ImportedBackend;
use super::backend::{MapBackend, ProducedRun, RunRecorder};
use super::events::{Event, Sink, TracedView, emit};
use super::identity::schedule_record;
use super::layer_groups::{LayerGroups, layer_groups};
use super::map_setting::MapSetting;
use super::map_setup::MapSetup;
use super::portion::Portion;
use super::references::ViewReferences;
use super::run_record::{run_record, timings};
use super::select::{
    Selected, check_area_light_sizes, check_multi_map_lights, check_plan, check_run_count, load_selected,
};
use super::trace_view;
use super::{Pipeline, Plan, PlanError};
use glam::Vec3;
use shadowtruth::metrics::Stopwatch;
use shadowtruth::raster::DepthFormat;
use shadowtruth::record::{SceneRecord, ScheduleRecord};
use shadowtruth::scene::{Camera, Light, Scene, ViewKey};
use shadowtruth::technique::{LayerNeeds, TechniqueSpec};
use shadowtruth::trace::{GBuffer, ReferenceCache, SceneBvh};

/// What every step of one plan's schedule reads.
pub(super) struct Schedule<'p, 's, 'k> {
    pub(super) plan: &'p Plan,
    cache: Option<&'p ReferenceCache>,
    pub(super) groups: &'p LayerGroups,
    pub(super) sinks: &'s mut [&'k mut dyn Sink],
    /// Where the shaded techniques' maps are drawn and shaded: the CPU, or the GPU pipeline.
    shaded: Box<dyn MapBackend + 'p>,
    pub(super) portion: &'p Portion,
    /// The schedule position of the next view (from 0).
    position: usize,
}

/// Runs `plan`, sending what it produces to `sinks` in order. References come from `cache`
/// when given (and are stored there), else they are traced.
pub fn execute(
    plan: &Plan,
    cache: Option<&ReferenceCache>,
    sinks: &mut [&mut dyn Sink],
) -> Result<(), PlanError> {
    execute_portion(plan, cache, sinks, &Portion::default())
}

/// Runs the `portion` of `plan` (a shard's views, less the maps already done), as `execute`.
pub fn execute_portion(
    plan: &Plan,
    cache: Option<&ReferenceCache>,
    sinks: &mut [&mut dyn Sink],
    portion: &Portion,
) -> Result<(), PlanError> {
    check_plan(plan)?;
    let selected = load_selected(plan)?;
    check_area_light_sizes(plan, &selected)?;
    check_multi_map_lights(plan, &selected)?;
    check_frames(plan)?;
    // The limit holds for the whole plan, whatever share of it runs here.
    check_run_count(plan, selected.iter().map(|s| s.pairs.len()).sum())?;
    let groups = layer_groups(&plan.techniques);
    check_imported_map(plan, &groups)?;
    let shaded = shaded_backend(plan, &groups)?;
    let schedule = schedule_record(plan, &selected);
    let runs = portion_runs(plan, &schedule, portion);
    emit(sinks, &Event::Planned { runs, schedule: &schedule })?;
    let mut schedule = Schedule { plan, cache, groups: &groups, sinks, shaded, portion, position: 0 };
    selected.iter().try_for_each(|sel| schedule.scene(sel))
}

/// The back-end of the plan's shaded techniques. The GPU's device is opened here, before
/// anything is traced: a machine without a Vulkan adapter is told at once.
fn shaded_backend<'p>(
    plan: &'p Plan,
    groups: &'p LayerGroups,
) -> Result<Box<dyn MapBackend + 'p>, PlanError> {
    match plan.pipeline {
        Pipeline::Cpu => Ok(Box::new(CpuBackend::new(plan, groups))),
        #[cfg(feature = "gpu")]
        Pipeline::Gpu => Ok(Box::new(GpuBackend::new(plan, groups)?)),
        #[cfg(not(feature = "gpu"))]
        Pipeline::Gpu => Err(PlanError::Invalid(super::select::WITHOUT_GPU.into())),
    }
}

/// Frames are shaded here, from buffers traced here: a plan over several frames cannot run on
/// the GPU pipeline, read an imported shadow map, score imported buffers (one per view) or run
/// renderers' commands.
fn check_frames(plan: &Plan) -> Result<(), PlanError> {
    if plan.frames <= 1 {
        return Ok(());
    }
    let refused = if plan.pipeline == Pipeline::Gpu {
        Some("the GPU pipeline")
    } else if plan.shadow_map.is_some() {
        Some("an imported shadow map")
    } else if plan.techniques.iter().any(|t| matches!(t, TechniqueSpec::External(_))) {
        Some("`external` techniques (one imported buffer per view)")
    } else if plan.techniques.iter().any(|t| matches!(t, TechniqueSpec::Command(_))) {
        Some("`command` techniques (one export of the view per resolution)")
    } else {
        None
    };
    match refused {
        Some(what) => {
            Err(PlanError::Invalid(format!("{} frames: a plan over frames cannot use {what}", plan.frames)))
        }
        None => Ok(()),
    }
}

/// The number of runs of `portion`.
fn portion_runs(plan: &Plan, schedule: &ScheduleRecord, portion: &Portion) -> usize {
    let mut maps = 0;
    let owned = schedule.views.iter().enumerate().filter(|(position, _)| portion.owns_view(*position));
    for v in owned.map(|(_, view)| view) {
        let key = ViewKey::new(&v.scene, &v.camera, &v.light);
        for &resolution in &plan.resolutions {
            maps += plan.depth_formats.iter().filter(|f| portion.runs_map(key, resolution, f.name())).count();
        }
    }
    maps * plan.techniques.len()
}

/// An imported shadow map is one nearest layer at one resolution: every technique must read just
/// that (no culling, raster bias, second layer or multiple depths), at that resolution.
fn check_imported_map(plan: &Plan, groups: &LayerGroups) -> Result<(), PlanError> {
    let Some(imported) = &plan.shadow_map else { return Ok(()) };
    if plan.resolutions != [imported.layer.resolution] {
        return Err(PlanError::Invalid(format!(
            "the imported shadow map is {0}²: the plan's resolutions must be [{0}]",
            imported.layer.resolution
        )));
    }
    for (needs, members) in groups {
        if *needs != LayerNeeds::default() {
            let label = plan.techniques[members[0]].label();
            return Err(PlanError::Invalid(format!(
                "technique {label} reads layers an imported shadow map does not hold (culling, raster bias, a \
                 second layer, multiple depths or moments): only single-layer techniques read one"
            )));
        }
    }
    Ok(())
}

impl Schedule<'_, '_, '_> {
    pub(super) fn stage(&mut self, what: &str) -> Result<(), PlanError> {
        emit(self.sinks, &Event::Stage(what))
    }

    fn scene(&mut self, sel: &Selected) -> Result<(), PlanError> {
        let scene = &sel.scene;
        // The views of this portion with something left to run; a scene without one is not built.
        let first = self.position;
        self.position += sel.pairs.len();
        let pairs: Vec<(usize, usize)> = (first..)
            .zip(&sel.pairs)
            .filter(|&(position, &(ci, li))| {
                let key = ViewKey::from_view(scene, &scene.cameras[ci], &scene.lights[li]);
                self.portion.owns_view(position) && self.any_map_left(key)
            })
            .map(|(_, &pair)| pair)
            .collect();
        if pairs.is_empty() {
            return Ok(());
        }
        self.stage(&format!("{}: building the BVH", scene.name))?;
        let sw = Stopwatch::start();
        let bvh = SceneBvh::build(scene);
        let record = SceneRecord {
            name: scene.name.clone(),
            file: scene.source.display().to_string(),
            triangles: scene.triangle_count() as u64,
            dropped_degenerate: scene.dropped_degenerate as u64,
            bvh_build_ms: sw.ms(),
        };
        emit(self.sinks, &Event::SceneBuilt(&record))?;
        // The scene's bounds, computed with the BVH (every instanced triangle walked once): the
        // tree is dropped before the last view's maps.
        let bounds = bvh.scene_bounds();
        let mut bvh = Some(bvh);
        let last = pairs.len() - 1;
        for (k, (ci, li)) in pairs.into_iter().enumerate() {
            let (camera, light) = (&scene.cameras[ci], &scene.lights[li]);
            if self.plan.frames > 1 {
                self.view_over_frames(scene, bvh.as_ref().expect("kept for every frame"), camera, light)?;
                continue;
            }
            let (gbuffer, references) =
                self.trace(scene, bvh.as_ref().expect("kept until the last view"), camera, light)?;
            if k == last {
                // The shadow maps trace no rays: at millions of triangles the tree is a third
                // of the memory, given back before the maps take theirs (docs/scale.md).
                bvh = None;
            }
            let traced = TracedView { scene, camera, light, gbuffer: &gbuffer, references: &references };
            self.view(&traced, bounds)?;
        }
        Ok(())
    }

    /// Whether any map of the view is still to be run.
    fn any_map_left(&self, key: ViewKey) -> bool {
        let plan = self.plan;
        plan.resolutions
            .iter()
            .any(|&r| plan.depth_formats.iter().any(|f| self.portion.runs_map(key, r, f.name())))
    }

    /// The G-buffer of a view and the references its techniques are scored against.
    fn trace(
        &mut self,
        scene: &Scene,
        bvh: &SceneBvh,
        camera: &Camera,
        light: &Light,
    ) -> Result<(GBuffer, ViewReferences), PlanError> {
        let (plan, cache) = (self.plan, self.cache);
        let mut stage =
            |step: &str| self.stage(&format!("{}/{}/{}: {step}", scene.name, camera.name, light.name));
        trace_view(plan, cache, scene, bvh, (camera, light), &mut stage)
    }

    /// Every map of a traced view (its scene's `bounds`): the runs of its shaded and its imported
    /// techniques.
    fn view(&mut self, traced: &TracedView, bounds: (Vec3, Vec3)) -> Result<(), PlanError> {
        let light = traced.light;
        emit(self.sinks, &Event::ViewTraced(traced))?;
        let mut imported = ImportedBackend::load(self.plan, traced)?;
        let mut commands = CommandBackend::new(self.plan);
        let key = traced.key();
        for &resolution in &self.plan.resolutions {
            let left = |f: &&DepthFormat| self.portion.runs_map(key, resolution, f.name());
            let formats: Vec<DepthFormat> = self.plan.depth_formats.iter().filter(left).copied().collect();
            if formats.is_empty() {
                continue;
            }
            let views = (traced.gbuffer, traced.camera, traced.camera);
            let setup = MapSetup::new(self.plan, views, light, bounds, resolution)?;
            for format in formats {
                let map = setup.setting(format, bounds);
                let recorder = &mut Recorder { sinks: &mut *self.sinks, traced, map: &map };
                self.shaded.produce(traced, &map, recorder)?;
                imported.produce(traced, &map, recorder)?;
                commands.produce(traced, &map, recorder)?;
                emit(self.sinks, &Event::MapsDone { view: traced, resolution, format })?;
            }
        }
        Ok(())
    }
}

/// The one place a run from any back-end becomes a record: scored, timed and sent to the sinks.
struct Recorder<'r, 'k, 'v> {
    sinks: &'r mut [&'k mut dyn Sink],
    traced: &'r TracedView<'v>,
    map: &'r MapSetting<'r>,
}

impl RunRecorder for Recorder<'_, '_, '_> {
    fn stage(&mut self, what: &str) -> Result<(), PlanError> {
        emit(self.sinks, &Event::Stage(what))
    }

    fn record(&mut self, run: ProducedRun) -> Result<(), PlanError> {
        let mut record = run_record(self.traced, self.map, run.spec, run.visibility);
        record.timings = timings(run.prepare_ms, run.shade_ms, run.shade_range_ms, record.counts.evaluated);
        record.layer_memory_bytes = run.layer_memory_bytes;
        record.pipeline = run.pipeline.cloned();
        emit(self.sinks, &Event::RunDone { record: &record, visibility: run.visibility })
    }
}
