//! What stops a plan: its input (scenes, the plan, imported files) or writing an output.

use super::PlanInputError;
use shadowtruth::scene::SceneError;
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
