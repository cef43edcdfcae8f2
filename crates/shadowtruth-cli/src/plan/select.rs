//! Choosing what a plan runs: the plan's own checks, the scenes loaded and their (camera, light)
//! views selected, every problem reported at once; and the run count held to its limit before
//! anything is built.

use super::{Plan, PlanError, PlanInputError};
use shadowtruth::raster::MAX_SHADOW_MAP_RESOLUTION;
use shadowtruth::scene::{LightKind, PointMap, Problem, Scene, SceneError, load_scene};
use shadowtruth::technique::ReferenceKind;
use std::collections::HashMap;
use std::collections::hash_map::Entry;
use std::path::{Path, PathBuf};

/// Why a plan on the GPU pipeline cannot run in a binary without the device code.
#[cfg(not(feature = "gpu"))]
pub(super) const WITHOUT_GPU: &str = "the GPU pipeline is not available: this shadowtruth was built without the `gpu` feature \
     (build it with `--features gpu`, or run on the CPU pipeline)";

/// A loaded scene and the (camera, light) index pairs the plan runs on it.
pub(crate) struct Selected {
    pub scene: Scene,
    pub pairs: Vec<(usize, usize)>,
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
            let message = shadowtruth::scene::missing_view_item(&scene.source, &field[..field.len() - 1]);
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
pub(crate) fn check_plan(plan: &Plan) -> Result<(), PlanError> {
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
    if plan.pipeline == super::Pipeline::Gpu {
        #[cfg(not(feature = "gpu"))]
        problem("pipeline".into(), WITHOUT_GPU.into());
        // Imported techniques are read, not drawn or shaded: they run on either pipeline.
        #[cfg(feature = "gpu")]
        for (i, t) in plan.techniques.iter().enumerate().filter(|(_, t)| t.build().is_some()) {
            if let Err(e) = shadowtruth_gpu::GpuTechnique::from_spec(t) {
                problem(format!("techniques[{i}]"), e.to_string());
            }
        }
        for (i, f) in plan.depth_formats.iter().enumerate() {
            if *f != shadowtruth::raster::DepthFormat::F32 {
                problem(
                    format!("depth_formats[{i}]"),
                    format!("the GPU pipeline draws f32 maps only, not {}", f.name()),
                );
            }
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
pub(super) fn check_run_count(plan: &Plan, views: usize) -> Result<usize, PlanError> {
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
pub(crate) fn load_selected(plan: &Plan) -> Result<Vec<Selected>, PlanError> {
    let mut selected = Vec::new();
    let (mut scene_problems, mut problems) = (Vec::new(), Vec::new());
    for path in &plan.scenes {
        match load_scene(path) {
            Ok(scene) => selected.push(select(plan, scene, &mut problems)),
            Err(e) => scene_problems.extend(e.problems),
        }
    }
    scene_problems.extend(name_problems(&selected));
    if !scene_problems.is_empty() {
        return Err(SceneError { problems: scene_problems }.into());
    }
    if !problems.is_empty() {
        return Err(PlanInputError { problems }.into());
    }
    Ok(selected)
}

/// A scene's name is its identity in the report, the cache and every file name: each scene
/// needs one, and no two the same (the report could not tell their runs apart). Each problem is
/// at the later file's `name`, naming the earlier file.
fn name_problems(selected: &[Selected]) -> Vec<Problem> {
    let mut first_with: HashMap<&str, &Path> = HashMap::new();
    let mut problems = Vec::new();
    for scene in selected.iter().map(|s| &s.scene) {
        let problem = |message: String| Problem { file: scene.source.clone(), path: "name".into(), message };
        if scene.name.trim().is_empty() {
            problems.push(problem("must not be empty: a scene's name tells its runs apart".into()));
            continue;
        }
        match first_with.entry(&scene.name) {
            Entry::Vacant(slot) => {
                slot.insert(&scene.source);
            }
            Entry::Occupied(first) => problems.push(problem(format!(
                "{:?} is also the name of {}: each scene of a plan needs its own name",
                scene.name,
                first.get().display()
            ))),
        }
    }
    problems
}

/// PCSS is scored against the area light: every light it runs under needs a size.
pub(crate) fn check_area_light_sizes(plan: &Plan, selected: &[Selected]) -> Result<(), PlanError> {
    if plan.techniques.iter().any(|t| t.reference_kind() == ReferenceKind::AreaLight) {
        for sel in selected {
            super::area_light::check_area_light_sizes(&sel.scene, sel.pairs.iter().map(|&(_, li)| li))?;
        }
    }
    Ok(())
}

/// Cascades are drawn and shaded on the CPU pipeline only, a point light's cube on either, its
/// dual paraboloids on the CPU only: a cascaded light or dual paraboloids cannot run on the GPU
/// pipeline, and neither a cascaded light nor a point light can read an imported shadow map (one
/// map). Each is refused at its path in the scene file; a technique that needs a projective map
/// is refused on dual paraboloids by name. (A renderer's `command` reads a view export, which
/// holds a point light's faces or hemispheres.)
pub(crate) fn check_multi_map_lights(plan: &Plan, selected: &[Selected]) -> Result<(), PlanError> {
    check_paraboloid_lights(plan, selected)?;
    let gpu = (plan.pipeline == super::Pipeline::Gpu)
        .then_some("the GPU pipeline draws a cube's faces but no cascades");
    let imported = plan.shadow_map.is_some().then_some("an imported shadow map is one map");
    for sel in selected {
        for &(_, li) in &sel.pairs {
            let light = &sel.scene.lights[li];
            let (path, message) = match (imported, gpu.or(imported)) {
                (Some(why), _) if light.is_point() => (
                    format!("lights[{li}].type"),
                    format!(
                        "is a point light, whose six-face cube map only the CPU and GPU pipelines draw: {why}"
                    ),
                ),
                (_, Some(why)) if light.cascades.is_some() => (
                    format!("lights[{li}].cascades"),
                    format!("has cascades, which run on the CPU pipeline only: {why}"),
                ),
                _ => continue,
            };
            return Err(PlanInputError::one(&sel.scene.source, &path, message).into());
        }
    }
    Ok(())
}

/// Dual-paraboloid maps are not projective: the GPU pipeline (whose shaders apply one matrix)
/// and the techniques that read the projection as a matrix (`Technique::needs_projective_map`)
/// cannot run on them.
fn check_paraboloid_lights(plan: &Plan, selected: &[Selected]) -> Result<(), PlanError> {
    let projective =
        plan.techniques.iter().find(|t| t.build().is_some_and(|technique| technique.needs_projective_map()));
    for sel in selected {
        for &(_, li) in &sel.pairs {
            let light = &sel.scene.lights[li];
            if !matches!(light.kind, LightKind::Point { map: PointMap::DualParaboloid, .. }) {
                continue;
            }
            let message = match (plan.pipeline, projective) {
                (super::Pipeline::Gpu, _) => {
                    "is a dual-paraboloid map, which the GPU pipeline does not draw: its shaders apply one \
                     projective matrix"
                        .to_string()
                }
                (_, Some(t)) => format!(
                    "is a dual-paraboloid map, which is not projective: technique {} reads the light's projection \
                     as a matrix (an adaptive bias's light rays, PCSS's frustum)",
                    t.label()
                ),
                _ => continue,
            };
            let path = format!("lights[{li}].shadow_map");
            return Err(PlanInputError::one(&sel.scene.source, &path, message).into());
        }
    }
    Ok(())
}
