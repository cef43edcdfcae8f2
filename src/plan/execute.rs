//! Runs a plan. The schedule follows the data: a scene's BVH once; per (camera, light) the
//! G-buffer and reference once; per (resolution, depth format) each distinct depth layer once,
//! shared by every technique that reads it.

use super::Plan;
use super::PlanInputError;
use super::build_layers;
use super::references::ViewReferences;
use crate::metrics::{LightUv, Stopwatch, attribute, median_ms, score_hard, score_soft};
use crate::raster::LightView;
use crate::raster::MAX_SHADOW_MAP_RESOLUTION;
use crate::report::{
    GridCell, IndexedImage, ReportWriter, RunRecord, SceneRecord, Timings, ViewCanvas, downscale, grid,
    run_stem, view_stem, write_reference_figure, write_run_figures, zoom,
};
use crate::scene::{Problem, Scene, SceneError, load_scene};
use crate::technique::{LayerNeeds, ReferenceKind, ShadeContext, ShadeOrder, shade_evaluated};
use crate::trace::{GBuffer, ReferenceCache, SceneBvh};
use rayon::prelude::*;
use std::path::PathBuf;

/// Progress of a plan, for progress bars and logs.
pub enum Event<'a> {
    /// The number of runs the plan expands to.
    Planned { runs: usize },
    /// A stage began (a short description).
    Stage(String),
    /// A run finished: its record, and its visibility per evaluated pixel (in the order of the
    /// G-buffer's `evaluated`), for callers that measure more than the report holds.
    RunDone { record: &'a RunRecord, visibility: &'a [f32] },
    /// Figures were drawn and written, taking this many milliseconds of wall time (the runs wait
    /// for them, so a batch's figure cost is the sum of these).
    FiguresDone { ms: f64 },
}

#[derive(Debug, thiserror::Error)]
pub enum PlanError {
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// What the plan asks for is wrong or does not exist: every problem with its file and path.
    #[error(transparent)]
    Input(#[from] PlanInputError),
    #[error("plan: {0}")]
    Invalid(String),
    #[error("writing {path}: {source}")]
    Io { path: PathBuf, source: std::io::Error },
}

/// Widest cell of the per-(view, resolution, depth format) grid figures, in pixels.
const GRID_CELL_WIDTH: u32 = 512;

/// A loaded scene and the (camera, light) index pairs the plan runs on it.
struct Selected {
    scene: Scene,
    pairs: Vec<(usize, usize)>,
}

/// Where the plan's problems are reported: its file, or `plan` for a plan built in code.
fn plan_file(plan: &Plan) -> PathBuf {
    plan.source.clone().unwrap_or_else(|| PathBuf::from("plan"))
}

/// Indices of the items named in `wanted` (all items when None); each name the scene lacks is a
/// problem at the plan's `field[i]`.
fn indices_of(
    plan: &Plan,
    scene: &Scene,
    (field, kind): (&str, &str),
    wanted: &Option<Vec<String>>,
    names: &[&str],
    problems: &mut Vec<Problem>,
) -> Vec<usize> {
    let Some(wanted) = wanted else { return (0..names.len()).collect() };
    let mut found = Vec::new();
    for (i, w) in wanted.iter().enumerate() {
        match names.iter().position(|n| n == w) {
            Some(index) => found.push(index),
            None => problems.push(Problem {
                file: plan_file(plan),
                path: format!("{field}[{i}]"),
                message: format!(
                    "no {kind} named '{w}' in {} (it has: {})",
                    scene.source.display(),
                    if names.is_empty() { "none".to_string() } else { names.join(", ") }
                ),
            }),
        }
    }
    found
}

/// The (camera, light) pairs the plan runs on `scene`; a scene without a camera or a light has
/// nothing to score and is a problem of its own.
fn select(plan: &Plan, scene: Scene, problems: &mut Vec<Problem>) -> Selected {
    let camera_names: Vec<&str> = scene.cameras.iter().map(|c| c.name.as_str()).collect();
    let light_names: Vec<&str> = scene.lights.iter().map(|l| l.name.as_str()).collect();
    for (field, names) in [("cameras", &camera_names), ("lights", &light_names)] {
        if names.is_empty() {
            let message =
                format!("the scene has no {}: there is nothing to score", &field[..field.len() - 1]);
            problems.push(Problem { file: scene.source.clone(), path: field.into(), message });
        }
    }
    let cams = indices_of(plan, &scene, ("cameras", "camera"), &plan.cameras, &camera_names, problems);
    let lights = indices_of(plan, &scene, ("lights", "light"), &plan.lights, &light_names, problems);
    let pairs = cams.iter().flat_map(|&c| lights.iter().map(move |&l| (c, l))).collect();
    Selected { scene, pairs }
}

/// Checks what `parse_plan` checks for a plan built in code or changed after reading
/// (`--resolutions`), before any scene is loaded.
fn check_plan(plan: &Plan) -> Result<(), PlanError> {
    let file = plan_file(plan);
    let mut problems = Vec::new();
    let mut problem =
        |path: String, message: String| problems.push(Problem { file: file.clone(), path, message });
    for (field, empty) in [
        ("techniques", plan.techniques.is_empty()),
        ("resolutions", plan.resolutions.is_empty()),
        ("depth_formats", plan.depth_formats.is_empty()),
        ("scenes", plan.scenes.is_empty()),
    ] {
        if empty {
            problem(field.into(), "an empty list: the plan selects no run".into());
        }
    }
    for (i, t) in plan.techniques.iter().enumerate() {
        if let Err(e) = t.validate() {
            problem(format!("techniques[{i}]"), format!("{}: {e}", t.label()));
        }
    }
    for (i, &r) in plan.resolutions.iter().enumerate() {
        if !(1..=MAX_SHADOW_MAP_RESOLUTION).contains(&r) {
            problem(
                format!("resolutions[{i}]"),
                format!("must be between 1 and {MAX_SHADOW_MAP_RESOLUTION}, found {r}"),
            );
        }
    }
    if problems.is_empty() { Ok(()) } else { Err(PlanInputError { problems }.into()) }
}

/// Refuses a plan of more than `plan.max_runs` runs, now that every view is known.
fn check_run_count(plan: &Plan, views: usize) -> Result<usize, PlanError> {
    let per_view =
        plan.techniques.len() as u128 * plan.resolutions.len() as u128 * plan.depth_formats.len() as u128;
    let runs = per_view.saturating_mul(views as u128);
    if runs > plan.max_runs as u128 {
        let message = format!(
            "the plan expands to {runs} runs, more than the limit of {} (raise it with --max-runs): {} techniques × \
             {} resolutions × {} depth formats × {views} (scene, camera, light) views",
            plan.max_runs,
            plan.techniques.len(),
            plan.resolutions.len(),
            plan.depth_formats.len()
        );
        return Err(PlanInputError::one(&plan_file(plan), "", message).into());
    }
    Ok(runs as usize)
}

/// Loads every scene and selects its views, reporting every problem at once.
fn load_selected(plan: &Plan) -> Result<Vec<Selected>, PlanError> {
    let mut selected = Vec::new();
    let (mut scene_problems, mut problems) = (Vec::new(), Vec::new());
    for path in &plan.scenes {
        match load_scene(path) {
            Ok(scene) => selected.push(select(plan, scene, &mut problems)),
            Err(e) => scene_problems.extend(e.problems),
        }
    }
    if !scene_problems.is_empty() {
        return Err(SceneError { problems: scene_problems }.into());
    }
    if !problems.is_empty() {
        return Err(PlanInputError { problems }.into());
    }
    Ok(selected)
}

/// Runs `plan`, adding each finished run to `writer` (which rewrites report.json). References
/// come from `cache` when given (and are stored there), else they are traced.
pub fn execute(
    plan: &Plan,
    writer: &mut ReportWriter,
    cache: Option<&ReferenceCache>,
    on_event: &mut dyn FnMut(Event),
) -> Result<(), PlanError> {
    check_plan(plan)?;
    let selected = load_selected(plan)?;
    // PCSS is scored against the area light: every light it runs under needs a size.
    if plan.techniques.iter().any(|t| t.reference_kind() == ReferenceKind::AreaLight) {
        for sel in &selected {
            super::area_light::check_area_light_sizes(&sel.scene, sel.pairs.iter().map(|&(_, li)| li))?;
        }
    }
    let runs = check_run_count(plan, selected.iter().map(|s| s.pairs.len()).sum())?;
    on_event(Event::Planned { runs });
    let io = |path: &std::path::Path| {
        let path = path.to_path_buf();
        move |source| PlanError::Io { path, source }
    };

    for sel in &selected {
        let scene = &sel.scene;
        on_event(Event::Stage(format!("{}: building the BVH", scene.name)));
        let sw = Stopwatch::start();
        let bvh = SceneBvh::build(scene);
        writer
            .add_scene(SceneRecord {
                name: scene.name.clone(),
                file: scene.source.display().to_string(),
                triangles: scene.triangles.len() as u64,
                dropped_degenerate: scene.dropped_degenerate as u64,
                bvh_build_ms: sw.ms(),
            })
            .map_err(io(writer.path()))?;
        let bounds = scene.bounds();
        for &(ci, li) in &sel.pairs {
            let (camera, light) = (&scene.cameras[ci], &scene.lights[li]);
            on_event(Event::Stage(format!("{}/{}/{}: reference", scene.name, camera.name, light.name)));
            let gbuffer = GBuffer::trace(scene, &bvh, camera, light);
            let figures_dir = writer.dir().join("figures");
            let cache_dir = cache.map_or_else(|| writer.dir().to_path_buf(), |c| c.dir().to_path_buf());
            let references = ViewReferences::new(plan, cache, scene, &bvh, &gbuffer, camera, light)
                .map_err(io(&cache_dir))?;
            let reference = &references.hard;
            let sw = Stopwatch::start();
            let canvas = plan.figures.then(|| ViewCanvas::new(&gbuffer, reference, light));
            if let Some(canvas) = &canvas {
                let stem = view_stem(&scene.name, &camera.name, &light.name);
                write_reference_figure(&figures_dir, &stem, &gbuffer, reference, canvas)
                    .map_err(io(&figures_dir))?;
                on_event(Event::FiguresDone { ms: sw.ms() });
            }
            for &resolution in &plan.resolutions {
                let view = LightView::new(light, bounds, resolution);
                let light_uv = LightUv::new(&gbuffer, &view);
                let order = ShadeOrder::new(&gbuffer, &view);
                for &format in &plan.depth_formats {
                    // Figures of this (resolution, format): (stem, caption, visibility), drawn
                    // and encoded together in parallel once its runs are scored.
                    let mut pending: Vec<(String, String, Vec<f32>, ReferenceKind)> = Vec::new();
                    // Techniques grouped by the layers they read: each set is rasterized once.
                    let mut groups: Vec<(LayerNeeds, Vec<usize>)> = Vec::new();
                    for (ti, t) in plan.techniques.iter().enumerate() {
                        let needs = t.build().layer_needs();
                        match groups.iter_mut().find(|(n, _)| *n == needs) {
                            Some((_, members)) => members.push(ti),
                            None => groups.push((needs, vec![ti])),
                        }
                    }
                    for (needs, members) in groups {
                        on_event(Event::Stage(format!(
                            "{}/{}/{}: {resolution}² {} layers",
                            scene.name,
                            camera.name,
                            light.name,
                            format.name()
                        )));
                        let (layers, prepare_ms) = build_layers(scene, &view, format, &needs, plan.repeats);
                        let ctx = ShadeContext::new(scene, &view, layers.as_layers());
                        for ti in members {
                            let spec = &plan.techniques[ti];
                            let technique = spec.build();
                            let mut shade_ms = Vec::with_capacity(plan.repeats);
                            let mut visibility = Vec::new();
                            for _ in 0..plan.repeats.max(1) {
                                let sw = Stopwatch::start();
                                visibility = shade_evaluated(technique.as_ref(), &order, &ctx);
                                shade_ms.push(sw.ms());
                            }
                            let shade_ms = median_ms(&shade_ms);
                            let (scored_against, soft_reference, reference_used) =
                                references.for_kind(spec.reference_kind());
                            let counts = score_hard(&gbuffer, scored_against, &visibility).with_attribution(
                                attribute(&gbuffer, scored_against, &visibility, &light_uv),
                            );
                            let soft =
                                soft_reference.map(|r| score_soft(&gbuffer, &r.visibility, &visibility));
                            let record = RunRecord {
                                scene: scene.name.clone(),
                                camera: camera.name.clone(),
                                light: light.name.clone(),
                                technique: spec.name().into(),
                                parameters: spec.parameters(),
                                label: spec.label(),
                                resolution,
                                depth_format: format.name().into(),
                                rates: counts.rates(),
                                counts,
                                timings: Timings {
                                    prepare: prepare_ms,
                                    shade: shade_ms,
                                    ns_per_pixel: shade_ms * 1e6 / counts.evaluated.max(1) as f64,
                                },
                                layer_memory_bytes: layers.memory_bytes() as u64,
                                reference: reference_used,
                                soft,
                            };
                            let figure = canvas.is_some().then(|| {
                                let caption =
                                    format!("{}  error {:.3}%", record.label, 100.0 * record.rates.error);
                                (run_stem(&record), caption)
                            });
                            writer.add_run(record).map_err(io(writer.path()))?;
                            on_event(Event::RunDone {
                                record: writer.report().runs.last().expect("just added"),
                                visibility: &visibility,
                            });
                            if let Some((stem, caption)) = figure {
                                pending.push((stem, caption, visibility, spec.reference_kind()));
                            }
                        }
                    }
                    if let Some(canvas) = &canvas {
                        let sw = Stopwatch::start();
                        // Each run's grid cell is shrunk beside its figures, in parallel, so that
                        // only the small cells are kept for the grid.
                        let shrink = gbuffer.width.div_ceil(GRID_CELL_WIDTH).max(1);
                        let cells: Vec<(String, IndexedImage)> = pending
                            .par_iter()
                            .map(|(stem, caption, visibility, kind)| {
                                let figures = write_run_figures(
                                    &figures_dir,
                                    stem,
                                    &gbuffer,
                                    references.for_kind(*kind).0,
                                    visibility,
                                    canvas,
                                )?;
                                if let Some([x, y, w, h]) = plan.zoom {
                                    zoom(&figures.error_image, (x, y, w, h), 4)
                                        .write_png(&figures_dir.join(format!("{stem}.error.zoom.png")))?;
                                }
                                Ok((caption.clone(), downscale(&figures.error_image, shrink)))
                            })
                            .collect::<std::io::Result<_>>()
                            .map_err(io(&figures_dir))?;
                        let cells: Vec<GridCell> = cells
                            .iter()
                            .map(|(caption, image)| GridCell { image, caption: caption.clone() })
                            .collect();
                        let stem = view_stem(&scene.name, &camera.name, &light.name);
                        let path =
                            figures_dir.join(format!("{stem}.r{resolution}.{}.grid.png", format.name()));
                        grid(&cells, 4, GRID_CELL_WIDTH).write_png(&path).map_err(io(&figures_dir))?;
                        on_event(Event::FiguresDone { ms: sw.ms() });
                    }
                }
            }
        }
    }
    Ok(())
}
