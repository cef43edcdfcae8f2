//! Plan files (`shadowtruth/plan/v1`): JSON naming scenes, cameras, lights, techniques,
//! resolutions and depth formats. A technique parameter given as a list sweeps its values: an
//! entry expands to the product of its lists, in the order written. Scene paths are relative to
//! the plan file.

use super::Plan;
use crate::raster::DepthFormat;
use crate::technique::TechniqueSpec;
use serde::Deserialize;
use serde_json::{Map, Value};
use std::path::Path;

pub const PLAN_FORMAT: &str = "shadowtruth/plan/v1";

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PlanFile {
    format: String,
    #[serde(default)]
    scenes: Vec<String>,
    #[serde(default)]
    cameras: Option<Vec<String>>,
    #[serde(default)]
    lights: Option<Vec<String>>,
    techniques: Vec<Map<String, Value>>,
    resolutions: Vec<u32>,
    #[serde(default = "default_formats")]
    depth_formats: Vec<String>,
    #[serde(default = "default_repeats")]
    repeats: usize,
    #[serde(default = "default_coverage_grid")]
    coverage_grid: u32,
    #[serde(default = "default_area_light_grid")]
    area_light_grid: u32,
}

fn default_coverage_grid() -> u32 {
    super::DEFAULT_COVERAGE_GRID
}

fn default_area_light_grid() -> u32 {
    super::DEFAULT_AREA_LIGHT_GRID
}

fn default_formats() -> Vec<String> {
    vec!["f32".into()]
}

fn default_repeats() -> usize {
    3
}

/// The techniques of one plan entry: the product of its list-valued parameters.
pub fn expand_technique(entry: &Map<String, Value>) -> Result<Vec<TechniqueSpec>, String> {
    let mut variants: Vec<Map<String, Value>> = vec![Map::new()];
    for (key, value) in entry {
        let values = match value {
            Value::Array(list) if list.is_empty() => return Err(format!("{key}: an empty list of values")),
            Value::Array(list) => list.clone(),
            other => vec![other.clone()],
        };
        variants = variants
            .into_iter()
            .flat_map(|v| {
                values.iter().map(move |x| {
                    let mut v = v.clone();
                    v.insert(key.clone(), x.clone());
                    v
                })
            })
            .collect();
    }
    variants
        .into_iter()
        .map(|v| {
            let spec: TechniqueSpec = serde_json::from_value(Value::Object(v)).map_err(|e| e.to_string())?;
            spec.validate().map_err(|e| e.to_string())?;
            Ok(spec)
        })
        .collect()
}

/// Reads a plan file; errors name the file and the field.
pub fn read_plan(path: &Path) -> Result<Plan, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    parse_plan(&text, path)
}

/// Parses plan text; `path` names it in errors and anchors its scene paths.
pub fn parse_plan(text: &str, path: &Path) -> Result<Plan, String> {
    let file: PlanFile = serde_json::from_str(text).map_err(|e| format!("{}: {e}", path.display()))?;
    if file.format != PLAN_FORMAT {
        return Err(format!(
            "{}: format: expected \"{PLAN_FORMAT}\", found \"{}\"",
            path.display(),
            file.format
        ));
    }
    let base = path.parent().unwrap_or(Path::new(""));
    let mut depth_formats = Vec::new();
    for (i, name) in file.depth_formats.iter().enumerate() {
        depth_formats.push(DepthFormat::parse(name).ok_or_else(|| {
            format!(
                "{}: depth_formats[{i}]: unknown format \"{name}\" (f32, unorm24, unorm16)",
                path.display()
            )
        })?);
    }
    let mut techniques = Vec::new();
    for (i, entry) in file.techniques.iter().enumerate() {
        techniques.extend(
            expand_technique(entry).map_err(|e| format!("{}: techniques[{i}]: {e}", path.display()))?,
        );
    }
    if file.repeats == 0 {
        return Err(format!("{}: repeats: must be at least 1", path.display()));
    }
    for (name, grid) in [("coverage_grid", file.coverage_grid), ("area_light_grid", file.area_light_grid)] {
        if !(1..=64).contains(&grid) {
            return Err(format!(
                "{}: {name}: must be from 1 to 64 (samples per pixel: its square)",
                path.display()
            ));
        }
    }
    Ok(Plan {
        scenes: file.scenes.iter().map(|s| base.join(s)).collect(),
        cameras: file.cameras,
        lights: file.lights,
        techniques,
        resolutions: file.resolutions,
        depth_formats,
        repeats: file.repeats,
        figures: true,
        zoom: None,
        coverage_grid: file.coverage_grid,
        area_light_grid: file.area_light_grid,
    })
}
