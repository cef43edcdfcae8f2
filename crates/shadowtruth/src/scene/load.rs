//! Reads a scene file, validates it and builds its world-space triangles.

use super::budget::{Budget, Limits};
use super::format::{Geometry, ObjectDesc, read_scene};
use super::format::{MAX_SCENE_TRIANGLES, MAX_SHAPE_TRIANGLES};
use super::gltf::{ImportOptions, import_gltf};
use super::load_gltf::{is_gltf_path, load_gltf_scene};
use super::obj::read_obj;
use super::placement::{Placement, add_mesh_placements, number_instances};
use super::{Problem, Scene, SceneError};
use crate::json_input::{Problems, parse_json};
use std::path::Path;

/// Loads and validates the scene at `path`: a scene file (mesh paths relative to its folder), or
/// a glTF file (`.gltf`, `.glb`) as a whole scene (docs/gltf.md).
pub fn load_scene(path: &Path) -> Result<Scene, SceneError> {
    if is_gltf_path(path) {
        return load_gltf_scene(path, Limits { scene: MAX_SCENE_TRIANGLES, shapes: MAX_SHAPE_TRIANGLES });
    }
    let text = crate::input_file::read_named_text(path, MAX_SCENE_FILE_BYTES).map_err(|e| SceneError {
        problems: vec![Problem {
            file: path.to_path_buf(),
            path: String::new(),
            message: format!("cannot read scene file: {e}"),
        }],
    })?;
    load_scene_str(&text, path, path.parent().unwrap_or(Path::new("")))
}

/// The largest scene file read: a million instances (`MAX_INSTANCES`) with a full transform each
/// take about 200 MB of JSON.
const MAX_SCENE_FILE_BYTES: u64 = 512 << 20;

/// Loads a scene from text; `source` names it in errors, `base_dir` resolves mesh paths.
/// Every problem (format, values, meshes) is collected; the scene is returned only without any.
pub fn load_scene_str(text: &str, source: &Path, base_dir: &Path) -> Result<Scene, SceneError> {
    let limits = Limits { scene: MAX_SCENE_TRIANGLES, shapes: MAX_SHAPE_TRIANGLES };
    load_with_limits(text, source, base_dir, limits)
}

/// As [`load_scene_str`], with at most `max_triangles` in the scene and in its shapes: the same
/// checks at a smaller size, so that the fuzzer spends its time on the reader, not on building
/// millions of triangles (src/fuzzing/).
pub fn load_scene_str_within(
    text: &str,
    source: &Path,
    base_dir: &Path,
    max_triangles: u64,
) -> Result<Scene, SceneError> {
    let limits = Limits { scene: max_triangles, shapes: max_triangles.min(MAX_SHAPE_TRIANGLES) };
    load_with_limits(text, source, base_dir, limits)
}

fn load_with_limits(text: &str, source: &Path, base_dir: &Path, limits: Limits) -> Result<Scene, SceneError> {
    let mut problems = Problems::new(source);
    let Some(root) = parse_json(text, &mut problems) else {
        return Err(SceneError { problems: problems.list });
    };
    let desc = read_scene(&root, &mut problems);
    let mut scene = Scene::empty(desc.name, source, desc.cameras, desc.lights);
    let mut budget = Budget::new(limits);
    for object in &desc.objects {
        add_object(&mut scene, object, base_dir, &mut budget, &mut problems);
    }
    number_instances(&mut scene);
    if problems.list.is_empty() && scene.triangle_count() == 0 {
        problems.report("objects", "the scene has no triangles");
    }
    if problems.list.is_empty() { Ok(scene) } else { Err(SceneError { problems: problems.list }) }
}

/// Reads an object's geometry and adds it. Meshes are read even when other fields are wrong, so
/// that their problems show too.
fn add_object(
    scene: &mut Scene,
    object: &ObjectDesc,
    base_dir: &Path,
    budget: &mut Budget,
    problems: &mut Problems,
) {
    let (key, mesh) = match &object.geometry {
        Some(Geometry::Mesh(relative)) => ("mesh", read_obj(base_dir, relative)),
        Some(Geometry::Shape(shape)) => {
            if !budget.admit_shape(&object.path, shape.triangle_count(), problems) {
                return;
            }
            ("shape", Ok(shape.mesh()))
        }
        Some(Geometry::Gltf(relative)) => match crate::input_file::open_inside(base_dir, relative) {
            Ok(inside) => return add_gltf_object(scene, object, &inside.path, budget, problems),
            Err(message) => return problems.report(&format!("{}.gltf", object.path), message),
        },
        None => return,
    };
    let at = format!("{}.{key}", object.path);
    match mesh {
        Ok(mesh) => {
            let Some(placements) = object_placements(object, &at) else { return };
            if budget.admit_mesh(&at, mesh.triangles.len() as u64, placements.len(), problems) {
                add_mesh_placements(scene, mesh, &placements, problems);
            }
        }
        Err(messages) => messages.into_iter().for_each(|m| problems.report(&at, m)),
    }
}

/// The placements of an OBJ or shape object: its transform, or one per entry of `instances`
/// (objects `NAME#k`); `None` when they failed to read (reported).
fn object_placements(object: &ObjectDesc, at: &str) -> Option<Vec<Placement>> {
    let transform = object.transform.as_ref()?;
    if object.instances.is_empty() {
        return Some(vec![Placement::from_transform(transform, &object.name, at.to_string(), object.closed)]);
    }
    let placement = |(k, t)| {
        let (name, path) = (format!("{}#{k}", object.name), format!("{}.instances[{k}]", object.path));
        Placement::from_transform(t, &name, path, object.closed)
    };
    Some(object.instances.iter().enumerate().map(placement).collect())
}

/// A scene-file object naming a glTF: every placement of every mesh becomes an object
/// `OBJECT/NODE` (`OBJECT#k/NODE` with `instances`), moved by the object's transform (each of its
/// instances) and closed when the object or the node says so.
fn add_gltf_object(
    scene: &mut Scene,
    object: &ObjectDesc,
    file: &Path,
    budget: &mut Budget,
    problems: &mut Problems,
) {
    let at = format!("{}.gltf", object.path);
    let options = ImportOptions { max_triangles: budget.remaining(), views: false };
    let imported = match import_gltf(file, options) {
        Ok(imported) => imported,
        Err(list) => {
            for p in list {
                let inner = if p.path.is_empty() { String::new() } else { format!("{}: ", p.path) };
                problems.report(&at, format!("{}: {inner}{}", file.display(), p.message));
            }
            return;
        }
    };
    let Some(outer) = object_placements(object, &at) else { return };
    for placed in imported.meshes {
        let placements: Vec<Placement> = (outer.iter())
            .flat_map(|o| placed.placements.iter().map(|p| p.within(o, format!("{at} ({})", p.path))))
            .collect();
        if budget.admit_mesh(&at, placed.mesh.triangles.len() as u64, placements.len(), problems) {
            add_mesh_placements(scene, placed.mesh, &placements, problems);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn problems(text: &str, limits: Limits) -> Vec<Problem> {
        let dir = std::env::temp_dir();
        load_with_limits(text, Path::new("s.json"), &dir, limits).expect_err(text).problems
    }

    /// Objects of 12 triangles each (boxes) against a limit of 30 triangles.
    fn boxes(n: usize) -> String {
        let object = |i| format!(r#"{{"name": "b{i}", "shape": {{"type": "box", "size": [1, 1, 1]}}}}"#);
        let objects = (0..n).map(object).collect::<Vec<_>>().join(", ");
        format!(
            r#"{{"format": "shadowtruth/scene/v1", "name": "n", "objects": [{objects}], "cameras": [], "lights": []}}"#
        )
    }

    #[test]
    fn scene_load_limits_name_the_first_object_over_them() {
        let text = boxes(4);
        let scene =
            load_with_limits(&boxes(2), Path::new("s.json"), Path::new(""), Limits { scene: 24, shapes: 24 });
        assert_eq!(scene.map(|s| s.flat_triangles.len()).ok(), Some(24));
        let found = problems(&text, Limits { scene: 30, shapes: 1000 });
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!(found[0].path, "objects[2].shape");
        assert_eq!(
            found[0].message,
            "the objects up to this one have 36 triangles; a scene may have at most 30"
        );
        let found = problems(&text, Limits { scene: 1000, shapes: 30 });
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!(found[0].path, "objects[2].shape");
        assert_eq!(
            found[0].message,
            "the procedural shapes up to this one have 36 triangles; a scene's shapes may have at most 30 together"
        );
    }
}
