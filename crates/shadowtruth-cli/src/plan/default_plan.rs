//! The default plan (`plans/default.json`: every single-depth technique at a few settings over
//! resolutions 512 to 4096), built into the binary so that `run` works from anywhere.

use super::{Plan, parse_plan};
use std::path::{Path, PathBuf};

const DEFAULT_PLAN_JSON: &str = include_str!("../../../../plans/default.json");

impl Plan {
    /// The default plan over `scenes`.
    pub fn default_for(scenes: Vec<PathBuf>) -> Self {
        let mut plan = parse_plan(DEFAULT_PLAN_JSON, Path::new("plans/default.json"))
            .expect("plans/default.json is valid");
        plan.source = None;
        plan.scenes = scenes;
        plan
    }
}
