//! Plan files (`shadowtruth/plan/v1`): JSON naming scenes, cameras, lights, techniques,
//! resolutions and depth formats. Scene paths are relative to the plan file.

use super::Plan;
use crate::raster::DepthFormat;
use crate::technique::TechniqueSpec;
use serde::Deserialize;
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
    techniques: Vec<TechniqueSpec>,
    resolutions: Vec<u32>,
    #[serde(default = "default_formats")]
    depth_formats: Vec<String>,
}

fn default_formats() -> Vec<String> {
    vec!["f32".into()]
}

/// Reads a plan file; errors name the file and, for JSON errors, the line and column.
pub fn read_plan(path: &Path) -> Result<Plan, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let file: PlanFile =
        serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
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
    for (i, t) in file.techniques.iter().enumerate() {
        t.validate()
            .map_err(|e| format!("{}: techniques[{i}]: {e}", path.display()))?;
    }
    Ok(Plan {
        scenes: file.scenes.iter().map(|s| base.join(s)).collect(),
        cameras: file.cameras,
        lights: file.lights,
        techniques: file.techniques,
        resolutions: file.resolutions,
        depth_formats,
    })
}
