//! Reads a scene file, validates it and builds its world-space triangles.

use super::format::{Geometry, ObjectDesc, read_scene};
use super::format::{MAX_SCENE_TRIANGLES, MAX_SHAPE_TRIANGLES};
use super::obj::read_obj;
use super::shapes::IndexedMesh;
use super::{Object, Problem, Scene, SceneError};
use crate::json_input::{Problems, parse_json};
use glam::Vec3;
use rayon::prelude::*;
use std::path::Path;

/// Loads and validates the scene at `path`; mesh paths are relative to its folder.
pub fn load_scene(path: &Path) -> Result<Scene, SceneError> {
    let text = std::fs::read_to_string(path).map_err(|e| SceneError {
        problems: vec![Problem {
            file: path.to_path_buf(),
            path: String::new(),
            message: format!("cannot read scene file: {e}"),
        }],
    })?;
    load_scene_str(&text, path, path.parent().unwrap_or(Path::new("")))
}

/// Loads a scene from text; `source` names it in errors, `base_dir` resolves mesh paths.
/// Every problem (format, values, meshes) is collected; the scene is returned only without any.
pub fn load_scene_str(text: &str, source: &Path, base_dir: &Path) -> Result<Scene, SceneError> {
    let limits = Limits { scene: MAX_SCENE_TRIANGLES, shapes: MAX_SHAPE_TRIANGLES };
    load_with_limits(text, source, base_dir, limits)
}

/// As [`load_scene_str`], with at most `max_triangles` in the scene and in its shapes: the same
/// checks at a smaller size, so that the fuzzer spends its time on the reader, not on building
/// millions of triangles (src/fuzzing.rs).
pub(crate) fn load_scene_str_within(
    text: &str,
    source: &Path,
    base_dir: &Path,
    max_triangles: u64,
) -> Result<Scene, SceneError> {
    let limits = Limits { scene: max_triangles, shapes: max_triangles.min(MAX_SHAPE_TRIANGLES) };
    load_with_limits(text, source, base_dir, limits)
}

/// Most triangles of a scene, in all and made by its procedural shapes together.
#[derive(Clone, Copy)]
struct Limits {
    scene: u64,
    shapes: u64,
}

/// Triangles asked for so far (before degenerate ones are dropped), in all and by shapes:
/// checked before each mesh joins the scene and before each shape is built, so that a scene
/// over the limits fails with a message instead of exhausting memory. Each limit is named at the
/// first object over it only.
struct Budget {
    limits: Limits,
    total: u64,
    procedural: u64,
}

impl Budget {
    /// Whether a shape of `count` triangles may be built (reported before it is).
    fn admit_shape(&mut self, object_path: &str, count: u64, problems: &mut Problems) -> bool {
        self.procedural += count;
        if self.procedural > self.limits.shapes {
            if self.procedural - count <= self.limits.shapes {
                let message = format!(
                    "the procedural shapes up to this one have {} triangles; a scene's shapes may have at \
                     most {} together",
                    self.procedural, self.limits.shapes
                );
                problems.report(&format!("{object_path}.shape"), message);
            }
            return false;
        }
        if self.total + count > self.limits.scene {
            self.over_scene_limit(object_path, count, "shape", problems);
            return false;
        }
        true
    }

    /// Whether a mesh of `count` triangles may join the scene.
    fn admit_mesh(&mut self, object_path: &str, count: u64, problems: &mut Problems) -> bool {
        if self.total + count > self.limits.scene {
            self.over_scene_limit(object_path, count, "mesh", problems);
            return false;
        }
        self.total += count;
        true
    }

    fn over_scene_limit(&mut self, object_path: &str, count: u64, key: &str, problems: &mut Problems) {
        let before = self.total;
        self.total += count;
        if before <= self.limits.scene {
            let message = format!(
                "the objects up to this one have {} triangles; a scene may have at most {}",
                self.total, self.limits.scene
            );
            problems.report(&format!("{object_path}.{key}"), message);
        }
    }
}

fn load_with_limits(text: &str, source: &Path, base_dir: &Path, limits: Limits) -> Result<Scene, SceneError> {
    let mut problems = Problems::new(source);
    let Some(root) = parse_json(text, &mut problems) else {
        return Err(SceneError { problems: problems.list });
    };
    let desc = read_scene(&root, &mut problems);
    let mut scene = Scene {
        name: desc.name,
        source: source.to_path_buf(),
        objects: Vec::new(),
        triangles: Vec::new(),
        triangle_object: Vec::new(),
        cameras: desc.cameras,
        lights: desc.lights,
        dropped_degenerate: 0,
    };
    let mut budget = Budget { limits, total: 0, procedural: 0 };
    for object in &desc.objects {
        // Meshes are read even when other fields are wrong, so that their problems show too.
        let mesh = match &object.geometry {
            Some(Geometry::Mesh(relative)) => match read_obj(&base_dir.join(relative)) {
                Ok(mesh) => Some(mesh),
                Err(messages) => {
                    let path = format!("{}.mesh", object.path);
                    messages.into_iter().for_each(|m| problems.report(&path, m));
                    None
                }
            },
            Some(Geometry::Shape(shape)) => {
                budget.admit_shape(&object.path, shape.triangle_count(), &mut problems).then(|| shape.mesh())
            }
            None => None,
        };
        if let Some(mesh) = mesh
            && budget.admit_mesh(&object.path, mesh.triangles.len() as u64, &mut problems)
        {
            add_object(&mut scene, object, &mesh, &mut problems);
        }
    }
    if problems.list.is_empty() && scene.triangles.is_empty() {
        problems.report("objects", "the scene has no triangles");
    }
    if problems.list.is_empty() { Ok(scene) } else { Err(SceneError { problems: problems.list }) }
}

/// Transforms `mesh` to world space (each vertex rounded to f32 once, so shared vertices stay
/// shared), keeps closed objects counter-clockwise from outside under a mirroring scale, drops
/// zero-area triangles and appends the rest as one contiguous object.
fn add_object(scene: &mut Scene, object: &ObjectDesc, mesh: &IndexedMesh, problems: &mut Problems) {
    let Some(transform) = &object.transform else {
        return;
    };
    let key = match object.geometry {
        Some(Geometry::Mesh(_)) => "mesh",
        _ => "shape",
    };
    let path = format!("{}.{key}", object.path);
    let affine = transform.affine();
    // Per vertex and per triangle in parallel (rayon), appended in mesh order.
    let world: Vec<Vec3> = mesh.positions.par_iter().map(|&p| affine.transform_point3(p).as_vec3()).collect();
    if world.par_iter().any(|v| !v.is_finite()) {
        problems.report(&path, "a vertex leaves the f32 range after the transform");
        return;
    }
    let first = scene.triangles.len();
    let index = scene.objects.len() as u32;
    let mirrored = transform.mirrors();
    let corners = |&[a, b, c]: &[u32; 3]| {
        let (a, b, c) = (world[a as usize], world[b as usize], world[c as usize]);
        if mirrored { [a, c, b] } else { [a, b, c] }
    };
    let degenerate: Vec<bool> = mesh.triangles.par_iter().map(|t| is_degenerate(&corners(t))).collect();
    let dropped = degenerate.iter().filter(|&&d| d).count();
    scene.triangles.reserve(mesh.triangles.len() - dropped);
    scene
        .triangles
        .extend(mesh.triangles.iter().zip(&degenerate).filter(|(_, d)| !**d).map(|(t, _)| corners(t)));
    scene.triangle_object.resize(scene.triangles.len(), index);
    let count = scene.triangles.len() - first;
    scene.dropped_degenerate += dropped;
    if count == 0 {
        problems.report(&path, format!("has no triangles ({dropped} degenerate dropped)"));
    }
    match (u32::try_from(first), u32::try_from(count)) {
        (Ok(first_triangle), Ok(triangle_count)) => scene.objects.push(Object {
            name: object.name.clone(),
            closed: object.closed,
            first_triangle,
            triangle_count,
        }),
        _ => problems.report(&path, "too many triangles in the scene"),
    }
}

/// Zero area in f32 world space: two vertices equal or the edges parallel. The cross product is
/// taken in f64, where the differences and products of f32 coordinates are (nearly) exact, so
/// tiny but valid triangles are kept.
fn is_degenerate([a, b, c]: &[Vec3; 3]) -> bool {
    if a == b || b == c || a == c {
        return true;
    }
    let (a, b, c) = (a.as_dvec3(), b.as_dvec3(), c.as_dvec3());
    (b - a).cross(c - a) == glam::DVec3::ZERO
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
        assert_eq!(scene.map(|s| s.triangles.len()).ok(), Some(24));
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
