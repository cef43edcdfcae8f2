//! Plan files (`shadowtruth/plan/v1`): JSON naming scenes, cameras, lights, techniques,
//! resolutions and depth formats. A technique parameter given as a list sweeps its values: an
//! entry expands to the product of its lists (keys in alphabetical order, the last varying
//! fastest). Scene paths are relative to
//! the plan file.
//!
//! Every problem is reported at once with the plan file and its JSON path, and the number of
//! runs is counted from the lists' lengths before anything is expanded, so that a plan of 10⁸
//! runs is refused in microseconds instead of filling memory.

use super::Plan;
use super::size::{PlanSize, TechniqueEntry};
use super::spec::{DEFAULT_MAX_RUNS, DEFAULT_REPEATS, MAX_REPEATS};
use serde_json::{Map, Value};
use shadowtruth::json_input::{Problem, Problems, Reader, as_name, as_string, count, describe, parse_json};
use shadowtruth::raster::{DepthFormat, MAX_SHADOW_MAP_RESOLUTION};
use shadowtruth::technique::TechniqueSpec;
use std::fmt;
use std::path::Path;

pub const PLAN_FORMAT: &str = "shadowtruth/plan/v1";

/// Every problem of a plan, each with its file and JSON path.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub struct PlanInputError {
    pub problems: Vec<Problem>,
}

impl fmt::Display for PlanInputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        shadowtruth::json_input::write_problems(f, "plan", &self.problems)
    }
}

impl PlanInputError {
    pub(crate) fn one(file: &Path, path: &str, message: impl Into<String>) -> Self {
        let problem = Problem { file: file.to_path_buf(), path: path.into(), message: message.into() };
        PlanInputError { problems: vec![problem] }
    }
}

/// The largest plan file read: plans list techniques and settings, a few kilobytes each.
const MAX_PLAN_FILE_BYTES: u64 = 64 << 20;

/// Reads a plan file, refusing plans of more than `max_runs` runs and naming scene files that
/// do not exist (folders are expanded later).
pub fn read_plan(path: &Path, max_runs: u64) -> Result<Plan, PlanInputError> {
    let text = shadowtruth::input_file::read_named_text(path, MAX_PLAN_FILE_BYTES)
        .map_err(|e| PlanInputError::one(path, "", format!("cannot read plan file: {e}")))?;
    let plan = parse_plan_limited(&text, path, max_runs)?;
    let missing: Vec<Problem> = (plan.scenes.iter().enumerate())
        .filter(|(_, scene)| !scene.exists())
        .map(|(i, scene)| Problem {
            file: path.to_path_buf(),
            path: format!("scenes[{i}]"),
            message: format!("no such scene file or folder: {}", scene.display()),
        })
        .collect();
    if missing.is_empty() { Ok(plan) } else { Err(PlanInputError { problems: missing }) }
}

/// Parses plan text with the default run limit; `path` names it in errors and anchors its
/// scene paths.
pub fn parse_plan(text: &str, path: &Path) -> Result<Plan, PlanInputError> {
    parse_plan_limited(text, path, DEFAULT_MAX_RUNS)
}

/// Parses plan text, refusing plans of more than `max_runs` runs.
pub fn parse_plan_limited(text: &str, path: &Path, max_runs: u64) -> Result<Plan, PlanInputError> {
    let mut problems = Problems::new(path);
    let plan = parse_json(text, &mut problems)
        .and_then(|root| read_plan_value(&root, path, max_runs, &mut problems));
    match plan {
        Some(plan) if problems.list.is_empty() => Ok(plan),
        _ => Err(PlanInputError { problems: problems.list }),
    }
}

/// The plan's fields as read; `None` where a field was invalid (reported).
fn read_plan_value(root: &Value, path: &Path, max_runs: u64, problems: &mut Problems) -> Option<Plan> {
    let mut top = Reader::new(root, String::new(), problems)?;
    if let Some(format) = top.required("format", as_string)
        && format != PLAN_FORMAT
    {
        top.problem("format", format!("unsupported format \"{format}\"; expected \"{PLAN_FORMAT}\""));
    }
    let base = path.parent().unwrap_or(Path::new(""));
    let scenes = top.optional_list("scenes", as_name).unwrap_or(Some(Vec::new()));
    let cameras = absent_means_all(top.optional_list("cameras", as_name));
    let lights = absent_means_all(top.optional_list("lights", as_name));
    let resolutions = top.required_list("resolutions", count(1, MAX_SHADOW_MAP_RESOLUTION as u64));
    let depth_formats =
        top.optional_list("depth_formats", as_depth_format).unwrap_or(Some(vec![DepthFormat::F32]));
    let repeats = top.optional_or("repeats", count(1, MAX_REPEATS as u64), DEFAULT_REPEATS as _);
    let frames = top.optional_or("frames", count(1, super::MAX_FRAMES as u64), 1);
    let max_grid = super::MAX_REFERENCE_GRID as u64;
    let coverage_grid = top.optional_or("coverage_grid", count(1, max_grid), super::DEFAULT_COVERAGE_GRID);
    let area_light_grid =
        top.optional_or("area_light_grid", count(1, max_grid), super::DEFAULT_AREA_LIGHT_GRID);
    let pipeline = top.optional_or("pipeline", as_pipeline, super::Pipeline::Cpu);
    let entries = read_technique_entries(&mut top);
    top.finish();
    let entries = entries?;
    // Counted from the lists as written, so that a plan too large is refused whatever else is
    // wrong with it; 1 for a list that is absent (all of the scene's) or not a list.
    let written = |key: &str| root.get(key).and_then(Value::as_array).map_or(1, |l| l.len().max(1) as u64);
    let size = PlanSize {
        entries: &entries,
        resolutions: written("resolutions"),
        depth_formats: written("depth_formats"),
        scenes: written("scenes"),
        cameras: written("cameras"),
        lights: written("lights"),
    };
    if let Some((at, message)) = size.refusal(max_runs) {
        problems.report(&at, message);
        return None;
    }
    let techniques =
        expand_entries(&entries, problems).into_iter().map(|t| files_relative_to(t, base)).collect();
    let scenes = scenes?.iter().map(|s| base.join(s)).collect();
    Some(Plan {
        source: Some(path.to_path_buf()),
        cameras: cameras?,
        lights: lights?,
        depth_formats: depth_formats?,
        repeats: repeats? as usize,
        coverage_grid: coverage_grid?,
        area_light_grid: area_light_grid?,
        max_runs,
        pipeline: pipeline?,
        frames: frames? as usize,
        ..Plan::new(scenes, techniques, resolutions?)
    })
}

/// Imported buffers' files, like scenes, are relative to the plan file.
fn files_relative_to(technique: TechniqueSpec, base: &Path) -> TechniqueSpec {
    match technique {
        TechniqueSpec::External(p) => TechniqueSpec::External(p.relative_to(base)),
        other => other,
    }
}

fn as_pipeline(v: &Value) -> Result<super::Pipeline, String> {
    let name = as_string(v)?;
    // The names `--pipeline` takes, from the same `ValueEnum`.
    <super::Pipeline as clap::ValueEnum>::from_str(&name, false)
        .map_err(|_| format!("unknown pipeline \"{name}\" (cpu, gpu)"))
}

/// A list that selects (cameras, lights): absent means all (`Some(None)`); `None` when invalid.
fn absent_means_all(field: Option<Option<Vec<String>>>) -> Option<Option<Vec<String>>> {
    match field {
        None => Some(None),
        Some(list) => list.map(Some),
    }
}

fn as_depth_format(v: &Value) -> Result<DepthFormat, String> {
    let name = as_string(v)?;
    DepthFormat::parse(&name).ok_or_else(|| {
        let names: Vec<&str> = DepthFormat::ALL.map(DepthFormat::name).to_vec();
        format!("unknown depth format \"{name}\" ({})", names.join(", "))
    })
}

/// The `techniques` array: each entry an object, its list-valued parameters non-empty.
fn read_technique_entries(top: &mut Reader) -> Option<Vec<TechniqueEntry>> {
    let items = top.array("techniques")?;
    if items.is_empty() {
        top.problem("techniques", "an empty list: a plan needs at least one technique");
        return None;
    }
    let mut entries = Vec::with_capacity(items.len());
    let mut valid = true;
    for (i, item) in items.iter().enumerate() {
        let path = format!("techniques[{i}]");
        let Some(map) = item.as_object() else {
            top.problem(&path, format!("expected an object, found {}", describe(item)));
            valid = false;
            continue;
        };
        for (key, value) in map {
            if value.as_array().is_some_and(Vec::is_empty) {
                top.problem(&format!("{path}.{key}"), "an empty list of values");
                valid = false;
            }
        }
        if !map.contains_key("technique") {
            top.problem(&path, "missing required field `technique`");
            valid = false;
        }
        entries.push(TechniqueEntry { path, map: map.clone() });
    }
    valid.then_some(entries)
}

/// Every entry's techniques, in order; problems are reported once per distinct path and message.
fn expand_entries(entries: &[TechniqueEntry], problems: &mut Problems) -> Vec<TechniqueSpec> {
    let mut techniques = Vec::new();
    for entry in entries {
        let mut seen = std::collections::BTreeSet::new();
        for variant in entry.variants() {
            match technique_of(&variant.map) {
                Ok(spec) => techniques.push(spec),
                Err((key, message)) => {
                    let at = variant.path_of(&entry.path, key.as_deref());
                    if seen.insert((at.clone(), message.clone())) {
                        problems.report(&at, message);
                    }
                }
            }
        }
    }
    techniques
}

/// One technique from its parameters, or the parameter at fault (when known) and the message.
fn technique_of(map: &Map<String, Value>) -> Result<TechniqueSpec, (Option<String>, String)> {
    let spec: TechniqueSpec = serde_json::from_value(Value::Object(map.clone()))
        .map_err(|e| (culprit(map, &e.to_string()), serde_message(&e.to_string())))?;
    spec.validate().map_err(|e| (e.field.map(str::to_string), e.message))?;
    Ok(spec)
}

/// serde's message without its trailing position (a `Value` has none worth showing).
fn serde_message(message: &str) -> String {
    message.lines().next().unwrap_or(message).to_string()
}

/// The parameter a deserialization error is about: named by serde for unknown and missing
/// fields, otherwise the one whose removal makes the error go away or turn into its absence.
fn culprit(map: &Map<String, Value>, message: &str) -> Option<String> {
    for prefix in ["unknown field `", "missing field `"] {
        if let Some(rest) = message.split(prefix).nth(1) {
            return rest.split('`').next().map(str::to_string);
        }
    }
    // The technique's name alone tells whether the tag itself is unknown.
    let tag = Map::from_iter(map.get("technique").map(|t| ("technique".to_string(), t.clone())));
    let tag_error = serde_json::from_value::<TechniqueSpec>(Value::Object(tag)).err();
    if tag_error.is_some_and(|e| e.to_string().contains("unknown variant")) {
        return Some("technique".into());
    }
    map.keys().filter(|k| k.as_str() != "technique").find_map(|key| {
        let mut without = map.clone();
        without.remove(key);
        match serde_json::from_value::<TechniqueSpec>(Value::Object(without)) {
            Ok(_) => Some(key.clone()),
            Err(e) if e.to_string().contains(&format!("missing field `{key}`")) => Some(key.clone()),
            Err(_) => None,
        }
    })
}
