//! A view over the frames of its camera's and light's paths (`run --frames N`,
//! docs/temporal.md). Frames run in order, each like a still view: G-buffer, references, then
//! every map and technique. What does not change between frames is shared: the BVH always; the
//! G-buffer and references while neither the camera nor the light moves; a map's depth layers
//! while its light views stay the same (a still light's single map, a stabilised cascade that
//! did not move). References are traced, not cached: the cache holds one mask per view.
//!
//! Flicker compares the same surface points in consecutive frames. With a still camera they
//! are the same pixels. With a moving camera, each point of the later frame is shaded again
//! through the earlier frame's maps (and its reference traced again under the earlier light
//! when the light moves too), so no point is ever compared with its neighbour.

use super::backend::cpu::{group_layers, shade_timed};
use super::events::{Event, TracedView, emit};
use super::execute::Schedule;
use super::map_setting::MapSetting;
use super::map_setup::MapSetup;
use super::references::ViewReferences;
use super::run_record::{run_record, timings};
use super::{BinnedView, PlanError};
use super::{shade_through, trace_view};
use glam::Vec3;
use shadowtruth::metrics::{Counts, FrameDecisions, count_flicker, reference_decisions, technique_decisions};
use shadowtruth::raster::{DepthFormat, LightView};
use shadowtruth::record::{RunRecord, TemporalRecord};
use shadowtruth::scene::{Camera, Light, Scene, frame_times, union_span};
use shadowtruth::technique::BuiltLayers;
use shadowtruth::trace::{GBuffer, SceneBvh, trace_scored_view};
use std::sync::Arc;

/// One run along the path, as its frames come.
struct RunTrack {
    counts: Counts,
    frame_errors: Vec<f64>,
    frame_flicker: Vec<u64>,
    compared: u64,
    heat: Vec<u16>,
    /// The technique's decisions in the frame before (its pixels).
    before: Vec<u8>,
    prepare_ms: f64,
    shade_ms: f64,
    /// The last frame's record and visibility.
    last: Option<(RunRecord, Vec<f32>)>,
}

/// A map's layers for one layer group, kept for the next frame with the views they were drawn
/// from.
struct KeptLayers {
    views: Vec<LightView>,
    layers: Arc<Vec<BuiltLayers>>,
}

/// What a frame leaves the next.
struct Frame {
    camera: Camera,
    light: Light,
    gbuffer: Arc<GBuffer>,
    references: Arc<ViewReferences>,
    reference: Vec<u8>,
    /// Per (map, layer group), in map-major order.
    layers: Vec<KeptLayers>,
}

/// The frame before, as the points of this frame see it: where those points are shaded from
/// through its maps, and their reference decisions under its light.
struct Before<'f> {
    frame: &'f Frame,
    points: Points,
    reference: Vec<u8>,
}

/// Which points of the frame before are compared with this frame's.
enum Points {
    /// The camera did not move: the same pixels, already shaded.
    SamePixels,
    /// The camera moved under a still light: this frame's G-buffer, shaded again.
    Here,
    /// Both moved: this frame's pixels traced again under the earlier light.
    Traced(Box<GBuffer>),
}

/// The span of a view's paths (the start of time when neither moves).
fn view_span(camera: &Camera, light: &Light) -> (f64, f64) {
    let spans =
        camera.path.iter().map(|p| p.position.span()).chain(light.path.iter().map(|p| p.direction.span()));
    union_span(spans).unwrap_or((0.0, 0.0))
}

/// What moves along the path, in words.
fn moving(camera: &Camera, light: &Light) -> &'static str {
    match (camera.path.is_some(), light.path.is_some()) {
        (true, true) => "both",
        (true, false) => "camera",
        (false, true) => "light",
        (false, false) => "none",
    }
}

impl Schedule<'_, '_, '_> {
    /// Every frame of the (camera, light) view, then each run's record over them.
    pub(super) fn view_over_frames(
        &mut self,
        scene: &Scene,
        bvh: &SceneBvh,
        camera: &Camera,
        light: &Light,
    ) -> Result<(), PlanError> {
        let times = frame_times(view_span(camera, light), self.plan.frames);
        let key = shadowtruth::scene::ViewKey::from_view(scene, camera, light);
        let maps = self.maps_left(key);
        let first_camera = camera.at_time(times[0]);
        // Computed once, when the BVH was built: not per view, frame or map.
        let bounds = bvh.scene_bounds();
        let runs = maps.len() * self.plan.techniques.len();
        let pixels = camera.pixel_count();
        let mut tracks: Vec<RunTrack> = (0..runs).map(|_| RunTrack::new(pixels, times.len())).collect();
        let mut previous: Option<Frame> = None;
        for (f, &t) in times.iter().enumerate() {
            let (cam, lit) = (camera.at_time(t), light.at_time(t));
            self.stage(&format!(
                "{}/{}/{}: frame {}/{}",
                scene.name,
                camera.name,
                light.name,
                f + 1,
                times.len()
            ))?;
            let (gbuffer, references) = self.frame_traced(scene, bvh, &cam, &lit, previous.as_ref())?;
            let traced =
                TracedView { scene, camera: &cam, light: &lit, gbuffer: &gbuffer, references: &references };
            let reference = reference_decisions(&gbuffer, &references.hard);
            let before = previous.as_ref().map(|p| before_frame(scene, bvh, p, (&cam, &lit), &reference));
            let frame = (f, times.len(), &first_camera, bounds);
            let layers = self.frame_maps(&traced, frame, &maps, before.as_ref(), &reference, &mut tracks)?;
            drop(before);
            if f + 1 == times.len() {
                self.finish_runs(&traced, &maps, &mut tracks, moving(camera, light))?;
            }
            previous = Some(Frame { camera: cam, light: lit, gbuffer, references, reference, layers });
        }
        Ok(())
    }

    /// The (resolution, depth format) maps of the view still to run, in schedule order.
    fn maps_left(&self, key: shadowtruth::scene::ViewKey) -> Vec<(u32, DepthFormat)> {
        let plan = self.plan;
        let all = plan.resolutions.iter().flat_map(|&r| plan.depth_formats.iter().map(move |&f| (r, f)));
        all.filter(|(r, f)| self.portion.runs_map(key, *r, f.name())).collect()
    }

    /// The frame's G-buffer and references: the frame before's when nothing moved.
    fn frame_traced(
        &mut self,
        scene: &Scene,
        bvh: &SceneBvh,
        camera: &Camera,
        light: &Light,
        previous: Option<&Frame>,
    ) -> Result<(Arc<GBuffer>, Arc<ViewReferences>), PlanError> {
        if let Some(p) = previous.filter(|p| p.camera == *camera && p.light == *light) {
            return Ok((p.gbuffer.clone(), p.references.clone()));
        }
        // The frame's stage is already under way.
        let (gbuffer, references) =
            trace_view(self.plan, None, scene, bvh, (camera, light), &mut |_| Ok(()))?;
        Ok((Arc::new(gbuffer), Arc::new(references)))
    }
}

/// The frame before, seen from this frame's points (`camera`, `light`, `reference`).
fn before_frame<'f>(
    scene: &Scene,
    bvh: &SceneBvh,
    previous: &'f Frame,
    (camera, light): (&Camera, &Light),
    reference: &[u8],
) -> Before<'f> {
    if previous.camera == *camera {
        return Before { frame: previous, points: Points::SamePixels, reference: previous.reference.clone() };
    }
    if previous.light == *light {
        return Before { frame: previous, points: Points::Here, reference: reference.to_vec() };
    }
    // The points the earlier light's reference cannot decide are left out, as in any frame.
    let (earlier, earlier_reference) = trace_scored_view(scene, bvh, camera, &previous.light);
    let reference = reference_decisions(&earlier, &earlier_reference);
    Before { frame: previous, points: Points::Traced(Box::new(earlier)), reference }
}

impl Schedule<'_, '_, '_> {
    /// Every map, layer group and technique of one frame; returns the layers kept for the next.
    fn frame_maps(
        &mut self,
        traced: &TracedView,
        (frame, frames, first_camera, bounds): (usize, usize, &Camera, (Vec3, Vec3)),
        maps: &[(u32, DepthFormat)],
        before: Option<&Before>,
        reference: &[u8],
        tracks: &mut [RunTrack],
    ) -> Result<Vec<KeptLayers>, PlanError> {
        let scene = traced.scene;
        let mut kept = Vec::new();
        // Built once per resolution (maps come resolution by resolution), shared by its formats.
        let mut setups: Option<(u32, MapSetup, Option<EarlierSetup>)> = None;
        for (m, &(resolution, format)) in maps.iter().enumerate() {
            if setups.as_ref().is_none_or(|(r, _, _)| *r != resolution) {
                let cameras = (traced.gbuffer, traced.camera, first_camera);
                let setup = MapSetup::new(self.plan, cameras, traced.light, bounds, resolution)?;
                let earlier = before
                    .map(|b| earlier_setup(self.plan, b, traced, (first_camera, bounds), resolution))
                    .transpose()?
                    .flatten();
                setups = Some((resolution, setup, earlier));
            }
            let (_, setup, earlier) = setups.as_ref().expect("set up above");
            let setting = setup.setting(format, bounds);
            let views = setup.views();
            let mut binned: Vec<BinnedView> = Vec::new();
            for gi in 0..self.groups.len() {
                let index = m * self.groups.len() + gi;
                let reused = before.and_then(|b| b.frame.layers.get(index)).filter(|k| k.views == views);
                let (layers, prepare_ms) = match reused {
                    Some(k) => (k.layers.clone(), 0.0),
                    None => {
                        let (layers, ms) = group_layers(
                            self.plan,
                            &self.groups[gi].0,
                            scene,
                            &setting,
                            &mut binned,
                            Vec::new(),
                        );
                        (Arc::new(layers), ms)
                    }
                };
                let run = RunInFrame { setting: &setting, layers: &layers, prepare_ms, frame, frames };
                for mi in 0..self.groups[gi].1.len() {
                    let ti = self.groups[gi].1[mi];
                    let track = &mut tracks[m * self.plan.techniques.len() + ti];
                    let visibility = self.frame_run(traced, &run, ti, track)?;
                    let earlier = earlier.as_ref().map(|(s, g)| (s.setting(format, bounds), *g, index));
                    self.flicker(traced, before, earlier, (ti, &visibility), reference, track);
                }
                kept.push(KeptLayers { views: views.clone(), layers });
            }
        }
        Ok(kept)
    }

    /// One technique in one frame: shaded, scored, sent as `FrameDone` and added to its track.
    fn frame_run(
        &mut self,
        traced: &TracedView,
        run: &RunInFrame,
        ti: usize,
        track: &mut RunTrack,
    ) -> Result<Vec<f32>, PlanError> {
        let spec = &self.plan.techniques[ti];
        let (visibility, shade) = shade_timed(self.plan.repeats, spec, traced.scene, run.setting, run.layers);
        let shade_ms = shade.median_ms;
        let mut record = run_record(traced, run.setting, spec, &visibility);
        record.timings =
            timings(run.prepare_ms, shade_ms, Some([shade.min_ms, shade.max_ms]), record.counts.evaluated);
        record.layer_memory_bytes = run.layers.iter().map(|l| l.memory_bytes() as u64).sum();
        let (frame, frames) = (run.frame as u32, run.frames as u32);
        emit(
            self.sinks,
            &Event::FrameDone { view: traced, record: &record, visibility: &visibility, frame, frames },
        )?;
        track.add_frame(&record, run.prepare_ms, shade_ms);
        track.last = Some((record, visibility.clone()));
        Ok(visibility)
    }

    /// The flicker of technique `ti` between the frame before and this one.
    fn flicker(
        &self,
        traced: &TracedView,
        before: Option<&Before>,
        earlier: Option<(MapSetting, &GBuffer, usize)>,
        (ti, visibility): (usize, &[f32]),
        reference: &[u8],
        track: &mut RunTrack,
    ) {
        let now = technique_decisions(traced.gbuffer, visibility);
        if let Some(before) = before {
            let technique_before = match earlier {
                None => std::mem::take(&mut track.before),
                Some((setting, points, index)) => {
                    let layers = &before.frame.layers[index].layers;
                    // Shaded once: the earlier frame's maps are read for the comparison, not timed.
                    let technique = self.plan.techniques[ti].build().expect("a shaded technique");
                    technique_decisions(
                        points,
                        &shade_through(technique.as_ref(), traced.scene, &setting, layers),
                    )
                }
            };
            let earlier = FrameDecisions { technique: &technique_before, reference: &before.reference };
            let later = FrameDecisions { technique: &now, reference };
            let (flicker, compared) = count_flicker(&earlier, &later, &mut track.heat);
            track.frame_flicker.push(flicker);
            track.compared += compared;
        }
        track.before = now;
    }

    /// After the last frame: the view, then each run's record over the path and its flicker
    /// map, map by map.
    fn finish_runs(
        &mut self,
        traced: &TracedView,
        maps: &[(u32, DepthFormat)],
        tracks: &mut [RunTrack],
        moving: &str,
    ) -> Result<(), PlanError> {
        emit(self.sinks, &Event::ViewTraced(traced))?;
        let (width, height) = (traced.camera.width, traced.camera.height);
        let per_map = self.plan.techniques.len();
        // In the order a still view sends its runs: group by group.
        let order: Vec<usize> = self.groups.iter().flat_map(|(_, members)| members.iter().copied()).collect();
        for (m, &(resolution, format)) in maps.iter().enumerate() {
            for &ti in &order {
                let track = &mut tracks[m * per_map + ti];
                let (record, visibility) = track.finish(moving);
                emit(self.sinks, &Event::FlickerDone { record: &record, heat: &track.heat, width, height })?;
                emit(self.sinks, &Event::RunDone { record: &record, visibility: &visibility })?;
            }
            emit(self.sinks, &Event::MapsDone { view: traced, resolution, format })?;
        }
        Ok(())
    }
}

/// One map's layers in one frame, as every technique of its group reads them.
struct RunInFrame<'a> {
    setting: &'a MapSetting<'a>,
    layers: &'a [BuiltLayers],
    prepare_ms: f64,
    frame: usize,
    frames: usize,
}

/// The earlier frame's maps set up over this frame's points, and the G-buffer of those points.
type EarlierSetup<'b> = (MapSetup, &'b GBuffer);

/// The earlier frame's maps over this frame's points, when the camera moved (None for a still
/// camera: its pixels were shaded in that frame): the set-up and the G-buffer shaded.
fn earlier_setup<'b>(
    plan: &super::Plan,
    before: &'b Before,
    traced: &'b TracedView,
    (first_camera, bounds): (&Camera, (Vec3, Vec3)),
    resolution: u32,
) -> Result<Option<EarlierSetup<'b>>, PlanError> {
    let points = match &before.points {
        Points::SamePixels => return Ok(None),
        Points::Here => traced.gbuffer,
        Points::Traced(gbuffer) => gbuffer,
    };
    let frame = before.frame;
    let setup = MapSetup::new(plan, (points, &frame.camera, first_camera), &frame.light, bounds, resolution)?;
    Ok(Some((setup, points)))
}

impl RunTrack {
    fn new(pixels: usize, frames: usize) -> Self {
        RunTrack {
            counts: Counts::default(),
            frame_errors: Vec::with_capacity(frames),
            frame_flicker: vec![0],
            compared: 0,
            heat: vec![0; pixels],
            before: Vec::new(),
            prepare_ms: 0.0,
            shade_ms: 0.0,
            last: None,
        }
    }

    fn add_frame(&mut self, record: &RunRecord, prepare_ms: f64, shade_ms: f64) {
        self.counts.add(&record.counts);
        self.frame_errors.push(record.rates.error);
        self.prepare_ms += prepare_ms;
        self.shade_ms += shade_ms;
    }

    /// The run's record over the path (its last frame's, with the counts of every frame) and
    /// the last frame's visibility.
    fn finish(&mut self, moving: &str) -> (RunRecord, Vec<f32>) {
        let (mut record, visibility) = self.last.take().expect("every run has a frame");
        let frames = self.frame_errors.len();
        let (worst_frame, worst_frame_error) = self
            .frame_errors
            .iter()
            .copied()
            .enumerate()
            .fold((0, f64::NEG_INFINITY), |best, (f, e)| if e > best.1 { (f, e) } else { best });
        let flicker_pixels: u64 = self.frame_flicker.iter().sum();
        record.counts = self.counts;
        record.rates = self.counts.rates();
        let n = frames.max(1) as f64;
        record.timings = timings(
            self.prepare_ms / n,
            self.shade_ms / n,
            None,
            self.counts.evaluated / frames.max(1) as u64,
        );
        record.temporal = Some(TemporalRecord {
            frames: frames as u32,
            moving: moving.into(),
            frame_errors: self.frame_errors.clone(),
            frame_flicker: self.frame_flicker.clone(),
            mean_error: self.frame_errors.iter().sum::<f64>() / n,
            worst_frame: worst_frame as u32,
            worst_frame_error,
            flicker_rate: flicker_pixels as f64 / self.compared.max(1) as f64,
            flicker_pixels,
            compared_pixels: self.compared,
        });
        (record, visibility)
    }
}
