//! Scene errors: every problem found, each with its file and JSON path (`Problem`).

pub use crate::json_input::Problem;
use std::fmt;

/// All the problems of a scene, reported at once.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub struct SceneError {
    pub problems: Vec<Problem>,
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        crate::json_input::write_problems(f, "scene", &self.problems)
    }
}
