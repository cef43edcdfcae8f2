//! Reads a scene file, validates it and builds its world-space triangles.

use super::{Scene, SceneError};
use std::path::Path;

/// Loads and validates the scene at `path`; mesh paths are relative to its folder.
pub fn load_scene(path: &Path) -> Result<Scene, SceneError> {
    let _ = path;
    todo!()
}

/// Loads a scene from text; `source` names it in errors, `base_dir` resolves mesh paths.
pub fn load_scene_str(text: &str, source: &Path, base_dir: &Path) -> Result<Scene, SceneError> {
    let _ = (text, source, base_dir);
    todo!()
}
