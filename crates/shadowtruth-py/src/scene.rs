//! `shadowtruth.Scene`: a loaded scene and its BVH, built on first use and kept, so that every
//! reference, verification and score of the scene shares one.

use crate::error::library_error;
use pyo3::prelude::*;
use shadowtruth::SceneBvh;
use std::path::PathBuf;
use std::sync::OnceLock;

/// A scene loaded from a `shadowtruth/scene/v1` JSON file (or a glTF file as a scene), with its
/// cameras and lights. Its BVH is built once, on the first call that traces.
#[pyclass(frozen, module = "shadowtruth")]
pub struct Scene {
    pub scene: shadowtruth::Scene,
    bvh: OnceLock<SceneBvh>,
}

impl Scene {
    /// The scene's BVH, built by the first caller (outside the GIL: callers hold none).
    pub fn bvh(&self) -> &SceneBvh {
        self.bvh.get_or_init(|| SceneBvh::build(&self.scene))
    }
}

#[pymethods]
impl Scene {
    /// The scene's name.
    #[getter]
    fn name(&self) -> &str {
        &self.scene.name
    }

    /// The file the scene was read from.
    #[getter]
    fn path(&self) -> PathBuf {
        self.scene.source.clone()
    }

    /// The cameras' names, in the file's order (the first is the default).
    #[getter]
    fn cameras(&self) -> Vec<String> {
        self.scene.cameras.iter().map(|c| c.name.clone()).collect()
    }

    /// The lights' names, in the file's order (the first is the default).
    #[getter]
    fn lights(&self) -> Vec<String> {
        self.scene.lights.iter().map(|l| l.name.clone()).collect()
    }

    /// Triangles of the scene, instanced ones included.
    #[getter]
    fn triangle_count(&self) -> usize {
        self.scene.triangle_count()
    }

    /// The image size `(width, height)` in pixels of camera `name` (default: the first): the
    /// shape of its arrays is `(height, width)`.
    #[pyo3(signature = (camera=None))]
    fn image_size(&self, camera: Option<&str>) -> PyResult<(u32, u32)> {
        let camera = crate::view::camera(&self.scene, camera)?;
        Ok((camera.width, camera.height))
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        // Python's quoting of the names, as the list and str reprs write them.
        let repr = |value: Bound<'_, PyAny>| value.repr().map(|r| r.to_string());
        Ok(format!(
            "Scene(name={}, cameras={}, lights={}, triangle_count={})",
            repr(self.scene.name.as_str().into_pyobject(py)?.into_any())?,
            repr(self.cameras().into_pyobject(py)?.into_any())?,
            repr(self.lights().into_pyobject(py)?.into_any())?,
            self.scene.triangle_count()
        ))
    }
}

/// Loads a scene file (`shadowtruth/scene/v1` JSON with its meshes, or a glTF file as a scene).
///
/// Returns a `Scene`. Raises `shadowtruth.Error` for a file that cannot be read or is not a valid
/// scene, its message naming the file and the JSON path at fault.
#[pyfunction]
pub fn load_scene(py: Python<'_>, path: PathBuf) -> PyResult<Scene> {
    let scene = py.detach(|| shadowtruth::load_scene(&path)).map_err(library_error)?;
    Ok(Scene { scene, bvh: OnceLock::new() })
}
