//! A glTF file as a whole scene (docs/gltf.md): named after the file's stem, every placement of
//! every mesh an object, with the file's cameras and lights.

use super::budget::{Budget, Limits};
use super::format::MAX_SHAPE_TRIANGLES;
use super::gltf::{GltfProblem, GltfScene, ImportOptions, import_gltf, import_gltf_bytes};
use super::placement::{add_mesh_placements, number_instances};
use super::{Scene, SceneError};
use crate::json_input::Problems;
use std::path::Path;

/// Whether `path` names a glTF file (`.gltf` or `.glb`, in any case) rather than a scene file.
pub(super) fn is_gltf_path(path: &Path) -> bool {
    let extension = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    matches!(extension.as_deref(), Some("gltf" | "glb"))
}

/// Loads the glTF at `path` as a scene; problems name the file and the glTF JSON path.
pub(super) fn load_gltf_scene(path: &Path, limits: Limits) -> Result<Scene, SceneError> {
    let options = ImportOptions { max_triangles: limits.scene, views: true };
    scene_of(import_gltf(path, options), path, limits)
}

/// A glTF held in memory (`.gltf` JSON or `.glb`) as a scene, its buffer files inside `folder`,
/// with at most `max_triangles`: the same checks at a smaller size, for the fuzzer
/// (src/fuzzing/gltf_reader.rs). `source` names it in errors and gives the scene its name.
pub fn load_gltf_within(
    bytes: &[u8],
    source: &Path,
    folder: &Path,
    max_triangles: u64,
) -> Result<Scene, SceneError> {
    let limits = Limits { scene: max_triangles, shapes: max_triangles.min(MAX_SHAPE_TRIANGLES) };
    let options = ImportOptions { max_triangles, views: true };
    scene_of(import_gltf_bytes(bytes, folder, options), source, limits)
}

/// The scene of an imported glTF: every placement of every mesh an object, within `limits`.
fn scene_of(
    imported: Result<GltfScene, Vec<GltfProblem>>,
    path: &Path,
    limits: Limits,
) -> Result<Scene, SceneError> {
    let mut problems = Problems::new(path);
    let imported = match imported {
        Ok(imported) => imported,
        Err(list) => {
            list.into_iter().for_each(|p| problems.report(&p.path, p.message));
            return Err(SceneError { problems: problems.list });
        }
    };
    let name = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let mut scene = Scene::empty(name, path, imported.cameras, imported.lights);
    let mut budget = Budget::new(limits);
    for placed in imported.meshes {
        let count = placed.mesh.triangles.len() as u64;
        if budget.admit_mesh(&placed.path, count, placed.placements.len(), &mut problems) {
            add_mesh_placements(&mut scene, placed.mesh, &placed.placements, &mut problems);
        }
    }
    number_instances(&mut scene);
    if problems.list.is_empty() && scene.triangle_count() == 0 {
        problems.report("", "the glTF's scene has no triangles");
    }
    if problems.list.is_empty() { Ok(scene) } else { Err(SceneError { problems: problems.list }) }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fixture() -> std::path::PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/gltf/hierarchy.glb")
    }

    /// The fixture's quad mesh (2 triangles) is placed by two nodes and so held once, its
    /// triangle by one: 3 triangles held, 5 placed.
    #[test]
    fn scene_gltf_limits_count_each_mesh_once() {
        let load = |scene| load_gltf_scene(&fixture(), Limits { scene, shapes: scene });
        let scene = load(3).expect("3 triangles held");
        assert_eq!((scene.meshes.len(), scene.instances.len(), scene.flat_triangles.len()), (1, 2, 1));
        assert_eq!(scene.triangle_count(), 5);
        let found = load(2).expect_err("3 triangles over a limit of 2").problems;
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!(found[0].path, "meshes[1]");
        assert!(found[0].message.starts_with("its 1 triangles bring the file's meshes to 3"), "{found:?}");
    }

    #[test]
    fn scene_gltf_paths_are_recognized_by_extension() {
        assert!(is_gltf_path(Path::new("a/b.GLB")) && is_gltf_path(Path::new("x.gltf")));
        assert!(!is_gltf_path(Path::new("x.json")) && !is_gltf_path(Path::new("gltf")));
    }
}
