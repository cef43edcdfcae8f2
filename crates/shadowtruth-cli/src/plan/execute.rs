//! Runs a plan. The schedule follows the data: a scene's BVH once; per (camera, light) the
//! G-buffer and references once; per (resolution, depth format) each distinct depth layer once,
//! shared by every technique that reads it. What it produces goes to the sinks as events
//! (`events.rs`); the schedule itself writes nothing.

use super::cascaded_map::CascadedMap;
use super::events::{Event, Sink, TracedView, emit};
use super::identity::schedule_record;
use super::map_setup::MapSetup;
use super::portion::Portion;
use super::references::ViewReferences;
use super::select::{
    Selected, check_area_light_sizes, check_cascaded_lights, check_plan, check_run_count, load_selected,
};
use super::{BinnedView, Pipeline, Plan, PlanInputError, build_layers_timed};
use glam::Vec3;
use shadowtruth::import::evaluated_visibility;
use shadowtruth::metrics::{LightUv, Stopwatch, attribute, median_ms, score_hard, score_soft};
use shadowtruth::raster::{DepthFormat, LightView};
use shadowtruth::record::{PipelineUsed, RunRecord, SceneRecord, ScheduleRecord, Timings};
use shadowtruth::scene::{Camera, Light, Scene, SceneError, ViewKey};
use shadowtruth::technique::{
    BuiltLayers, ExternalParams, LayerNeeds, ShadeContext, ShadeOrder, Technique, TechniqueSpec,
    shade_evaluated,
};
use shadowtruth::trace::{GBuffer, ReferenceCache, SceneBvh};
use shadowtruth_gpu::{GpuDepthMap, GpuDevice, GpuTechnique, shade_visibility};
use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum PlanError {
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// What the plan asks for is wrong or does not exist: every problem with its file and path.
    #[error(transparent)]
    Input(#[from] PlanInputError),
    #[error("plan: {0}")]
    Invalid(String),
    /// An imported buffer (`external`) or shadow map that cannot be read or does not fit its view.
    #[error(transparent)]
    Import(shadowtruth::Error),
    #[error("writing {path}: {source}")]
    Io { path: PathBuf, source: std::io::Error },
}

/// Techniques grouped by the depth layers they read (in plan order): each group's layers are
/// rasterized once per (view, resolution, depth format).
type LayerGroups = Vec<(LayerNeeds, Vec<usize>)>;

/// What every step of one plan's schedule reads.
pub(super) struct Schedule<'p, 's, 'k> {
    pub(super) plan: &'p Plan,
    cache: Option<&'p ReferenceCache>,
    pub(super) groups: LayerGroups,
    pub(super) sinks: &'s mut [&'k mut dyn Sink],
    /// The device of a plan on the GPU pipeline.
    gpu: Option<GpuDevice>,
    pub(super) portion: &'p Portion,
    /// The schedule position of the next view (from 0).
    position: usize,
}

/// One shadow map's set-up within a view: the light view and what is built from it once.
pub(crate) struct MapSetting<'a> {
    /// The map (the first cascade's, for a light with cascades).
    pub view: &'a LightView,
    pub light_uv: &'a LightUv,
    /// The shading order of the one map (None for cascades, which hold their own).
    pub order: Option<&'a ShadeOrder>,
    pub cascaded: Option<&'a CascadedMap>,
    pub resolution: u32,
    pub format: DepthFormat,
    /// The scene's bounds, computed once per view.
    pub scene_bounds: (Vec3, Vec3),
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
    check_cascaded_lights(plan, &selected)?;
    check_frames(plan)?;
    // The limit holds for the whole plan, whatever share of it runs here.
    check_run_count(plan, selected.iter().map(|s| s.pairs.len()).sum())?;
    let groups = layer_groups(&plan.techniques);
    check_imported_map(plan, &groups)?;
    // Before anything is traced: a machine without a Vulkan adapter is told at once.
    let gpu = match plan.pipeline {
        Pipeline::Cpu => None,
        Pipeline::Gpu => Some(GpuDevice::new().map_err(|e| PlanError::Invalid(e.to_string()))?),
    };
    let schedule = schedule_record(plan, &selected);
    let runs = portion_runs(plan, &schedule, portion);
    emit(sinks, &Event::Planned { runs, schedule: &schedule })?;
    let mut schedule = Schedule { plan, cache, groups, sinks, gpu, portion, position: 0 };
    selected.iter().try_for_each(|sel| schedule.scene(sel))
}

/// Frames are shaded here, from buffers traced here: a plan over several frames cannot run on
/// the GPU pipeline, read an imported shadow map or score imported buffers (one per view).
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
                 second layer or multiple depths): only single-layer techniques read one"
            )));
        }
    }
    Ok(())
}

/// Imported techniques (`external`) build no technique and read no layers: they are in no group.
fn layer_groups(techniques: &[TechniqueSpec]) -> LayerGroups {
    let mut groups: LayerGroups = Vec::new();
    for (ti, t) in techniques.iter().enumerate() {
        let Some(technique) = t.build() else { continue };
        let needs = technique.layer_needs();
        match groups.iter_mut().find(|(n, _)| *n == needs) {
            Some((_, members)) => members.push(ti),
            None => groups.push((needs, vec![ti])),
        }
    }
    groups
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
            self.view(&traced)?;
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
        self.stage(&format!("{}/{}/{}: G-buffer", scene.name, camera.name, light.name))?;
        let gbuffer = GBuffer::trace(scene, bvh, camera, light);
        self.stage(&format!("{}/{}/{}: reference", scene.name, camera.name, light.name))?;
        let references = ViewReferences::new(self.plan, self.cache, scene, bvh, &gbuffer, camera, light)?;
        Ok((gbuffer, references))
    }

    /// Every map of a traced view: its layers, techniques and imported runs.
    fn view(&mut self, traced: &TracedView) -> Result<(), PlanError> {
        let (scene, light) = (traced.scene, traced.light);
        emit(self.sinks, &Event::ViewTraced(traced))?;
        let external = load_imported(self.plan, traced)?;
        let bounds = scene.bounds();
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
                self.map(traced, &map)?;
                self.imported_runs(traced, &map, &external)?;
                emit(self.sinks, &Event::MapsDone { view: traced, resolution, format })?;
            }
        }
        Ok(())
    }

    /// Every technique at one (resolution, depth format): each group's layers built once.
    fn map(&mut self, traced: &TracedView, map: &MapSetting) -> Result<(), PlanError> {
        if let Some(gpu) = self.gpu.take() {
            let done = self.map_on_gpu(&gpu, traced, map);
            self.gpu = Some(gpu);
            return done;
        }
        // Each map binned when the first group needs it, then shared by the others.
        let mut binned: Vec<BinnedView> = Vec::new();
        for gi in 0..self.groups.len() {
            let (scene, camera, light) = (traced.scene, traced.camera, traced.light);
            let (resolution, format) = (map.resolution, map.format.name());
            self.stage(&format!(
                "{}/{}/{}: {resolution}² {format} layers",
                scene.name, camera.name, light.name
            ))?;
            let (layers, prepare_ms) = self.group_layers(scene, map, gi, &mut binned);
            let layer_memory_bytes = layers.iter().map(|l| l.memory_bytes() as u64).sum();
            for mi in 0..self.groups[gi].1.len() {
                let spec = &self.plan.techniques[self.groups[gi].1[mi]];
                let (visibility, shade_ms) = self.shade(spec, scene, map, &layers);
                let mut record = run_record(traced, map, spec, &visibility);
                record.timings = timings(prepare_ms, shade_ms, record.counts.evaluated);
                record.layer_memory_bytes = layer_memory_bytes;
                emit(self.sinks, &Event::RunDone { record: &record, visibility: &visibility })?;
            }
        }
        Ok(())
    }

    /// The layers group `gi` reads, one per map (each cascade's, or the one), built from the
    /// maps' binned triangles (binned here on first use), and the time they took (ms).
    pub(super) fn group_layers<'m>(
        &self,
        scene: &'m Scene,
        map: &MapSetting<'m>,
        gi: usize,
        binned: &mut Vec<BinnedView<'m>>,
    ) -> (Vec<BuiltLayers>, f64) {
        if let Some(map_file) = &self.plan.shadow_map {
            return (vec![BuiltLayers::Nearest(map_file.layer.clone())], 0.0);
        }
        if binned.is_empty() {
            binned.extend(map.views().into_iter().map(|view| BinnedView::new(scene, view)));
        }
        let mut total_ms = 0.0;
        let layers = binned
            .iter()
            .map(|b| {
                let (layers, ms) = build_layers_timed(b, map.format, &self.groups[gi].0, self.plan.repeats);
                total_ms += ms;
                layers
            })
            .collect();
        (layers, total_ms)
    }

    /// The technique's visibility of every evaluated sample through `layers` (one per map of
    /// `map`), and the median shading time (ms).
    pub(super) fn shade(
        &self,
        spec: &TechniqueSpec,
        scene: &Scene,
        map: &MapSetting,
        layers: &[BuiltLayers],
    ) -> (Vec<f32>, f64) {
        let technique = spec.build().expect("only shaded techniques are in a layer group");
        let contexts = map.contexts(scene, layers);
        let mut shade_ms = Vec::with_capacity(self.plan.repeats);
        let mut visibility = Vec::new();
        for _ in 0..self.plan.repeats.max(1) {
            let sw = Stopwatch::start();
            visibility = map.shade(technique.as_ref(), &contexts);
            shade_ms.push(sw.ms());
        }
        (visibility, median_ms(&shade_ms))
    }
}

impl Schedule<'_, '_, '_> {
    /// The runs of the imported techniques at one (resolution, depth format): their buffers were
    /// read once per view; the resolution gives the attribution its texel footprint.
    fn imported_runs(
        &mut self,
        traced: &TracedView,
        map: &MapSetting,
        imported: &[Imported],
    ) -> Result<(), PlanError> {
        for run in imported {
            let mut record = run_record(traced, map, &run.spec, &run.visibility);
            record.timings = timings(run.read_ms, 0.0, record.counts.evaluated);
            emit(self.sinks, &Event::RunDone { record: &record, visibility: &run.visibility })?;
        }
        Ok(())
    }

    /// Every technique at one resolution on the device: its map drawn there (timed as
    /// `prepare`), then shaded there (`shade`), each the median of the plan's repeats.
    fn map_on_gpu(
        &mut self,
        gpu: &GpuDevice,
        traced: &TracedView,
        map: &MapSetting,
    ) -> Result<(), PlanError> {
        let (scene, camera, light) = (traced.scene, traced.camera, traced.light);
        let adapter = gpu.adapter();
        let used = PipelineUsed {
            name: "gpu".into(),
            adapter: adapter.name,
            driver: adapter.driver,
            backend: adapter.backend,
        };
        let failed = |e: shadowtruth_gpu::GpuError| {
            PlanError::Invalid(format!("{}/{}/{}: {e}", scene.name, camera.name, light.name))
        };
        // One map per layer group, as on the CPU: drawn once, read by every technique of the
        // group. Imported techniques are in no group (`imported_runs`).
        for gi in 0..self.groups.len() {
            self.stage(&format!(
                "{}/{}/{}: {}² on the GPU",
                scene.name, camera.name, light.name, map.resolution
            ))?;
            let settings = GpuTechnique::raster_settings_of(&self.groups[gi].0);
            let mut prepare_ms = Vec::new();
            let mut depth_map = None;
            for _ in 0..self.plan.repeats.max(1) {
                let sw = Stopwatch::start();
                let drawn =
                    gpu.checked(|| GpuDepthMap::render(gpu, scene, map.view, &settings)).map_err(failed)?;
                gpu.wait().map_err(failed)?;
                prepare_ms.push(sw.ms());
                depth_map = Some(drawn);
            }
            let depth_map = depth_map.expect("at least one draw");
            for mi in 0..self.groups[gi].1.len() {
                let spec = &self.plan.techniques[self.groups[gi].1[mi]];
                let technique = GpuTechnique::from_spec(spec).map_err(failed)?;
                let mut shade_ms = Vec::new();
                let mut image = Vec::new();
                for _ in 0..self.plan.repeats.max(1) {
                    let sw = Stopwatch::start();
                    image = gpu
                        .checked(|| shade_visibility(gpu, traced.gbuffer, map.view, &depth_map, technique))
                        .map_err(failed)?;
                    shade_ms.push(sw.ms());
                }
                let visibility: Vec<f32> =
                    traced.gbuffer.evaluated.iter().map(|&i| image[i as usize]).collect();
                let mut record = run_record(traced, map, spec, &visibility);
                record.timings =
                    timings(median_ms(&prepare_ms), median_ms(&shade_ms), record.counts.evaluated);
                record.layer_memory_bytes = map.resolution as u64 * map.resolution as u64 * 4;
                record.pipeline = Some(used.clone());
                emit(self.sinks, &Event::RunDone { record: &record, visibility: &visibility })?;
            }
        }
        Ok(())
    }
}

/// An imported technique of one view: its spec with the view's files, the visibility of every
/// evaluated pixel (NaN for a surface mismatch) and the time spent reading it.
struct Imported {
    spec: TechniqueSpec,
    visibility: Vec<f32>,
    read_ms: f64,
}

/// Reads the buffers of the plan's `external` techniques for one view.
fn load_imported(plan: &Plan, traced: &TracedView) -> Result<Vec<Imported>, PlanError> {
    let mut out = Vec::new();
    for spec in &plan.techniques {
        let TechniqueSpec::External(params) = spec else { continue };
        let params = params
            .for_view(&traced.scene.name, &traced.camera.name, &traced.light.name)
            .map_err(|e| PlanError::Invalid(format!("{}: {e}", traced.scene.source.display())))?;
        let sw = Stopwatch::start();
        let visibility = read_external(&params, traced).map_err(PlanError::Import)?;
        out.push(Imported { spec: TechniqueSpec::External(params), visibility, read_ms: sw.ms() });
    }
    Ok(out)
}

fn read_external(params: &ExternalParams, traced: &TracedView) -> Result<Vec<f32>, shadowtruth::Error> {
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

/// A run's record scored against the reference its technique is judged by (timings and layer
/// memory are the caller's).
pub(super) fn run_record(
    traced: &TracedView,
    map: &MapSetting,
    spec: &TechniqueSpec,
    visibility: &[f32],
) -> RunRecord {
    let gbuffer = traced.gbuffer;
    let (scored_against, soft_reference, reference_used) = traced.references.for_kind(spec.reference_kind());
    let counts = score_hard(gbuffer, scored_against, visibility).with_attribution(attribute(
        gbuffer,
        scored_against,
        visibility,
        map.light_uv,
    ));
    RunRecord {
        scene: traced.scene.name.clone(),
        camera: traced.camera.name.clone(),
        light: traced.light.name.clone(),
        technique: spec.name().into(),
        parameters: spec.parameters(),
        label: spec.label(),
        resolution: map.resolution,
        depth_format: map.format.name().into(),
        rates: counts.rates(),
        counts,
        timings: Timings::default(),
        layer_memory_bytes: 0,
        reference: reference_used,
        soft: soft_reference.map(|r| score_soft(gbuffer, &r.visibility, visibility)),
        pipeline: None,
        cascades: map.cascaded.map(|c| c.record(gbuffer, scored_against, visibility)),
        temporal: None,
    }
}

impl<'a> MapSetting<'a> {
    /// The light views of the map: each cascade's, or the one.
    pub(crate) fn views(&self) -> Vec<&'a LightView> {
        match self.cascaded {
            Some(c) => c.cascades.views.iter().collect(),
            None => vec![self.view],
        }
    }

    /// What the technique reads of each map, with `layers` (one per map, in `views` order).
    pub(crate) fn contexts<'s>(&self, scene: &'s Scene, layers: &'s [BuiltLayers]) -> Vec<ShadeContext<'s>>
    where
        'a: 's,
    {
        let views = self.views().into_iter().zip(layers);
        views
            .map(|(view, l)| ShadeContext::with_bounds(scene, view, l.as_layers(), self.scene_bounds))
            .collect()
    }

    /// The technique's visibility of every evaluated pixel through `contexts` (`contexts`).
    pub(crate) fn shade(&self, technique: &dyn Technique, contexts: &[ShadeContext]) -> Vec<f32> {
        match (self.cascaded, self.order) {
            (Some(cascaded), _) => cascaded.orders.shade(technique, contexts),
            (None, Some(order)) => shade_evaluated(technique, order, &contexts[0]),
            (None, None) => unreachable!("one map has its shading order"),
        }
    }
}

pub(super) fn timings(prepare_ms: f64, shade_ms: f64, evaluated: u64) -> Timings {
    Timings { prepare: prepare_ms, shade: shade_ms, ns_per_pixel: shade_ms * 1e6 / evaluated.max(1) as f64 }
}
