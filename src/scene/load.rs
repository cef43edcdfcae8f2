//! Reads a scene file, validates it and builds its world-space triangles.

use super::format::{Geometry, ObjectDesc, Problems, parse_json, read_scene};
use super::obj::read_obj;
use super::shapes::IndexedMesh;
use super::{Object, Problem, Scene, SceneError};
use glam::Vec3;
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
            Some(Geometry::Shape(shape)) => Some(shape.mesh()),
            None => None,
        };
        if let Some(mesh) = mesh {
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
    let world: Vec<Vec3> = mesh.positions.iter().map(|&p| affine.transform_point3(p).as_vec3()).collect();
    if world.iter().any(|v| !v.is_finite()) {
        problems.report(&path, "a vertex leaves the f32 range after the transform");
        return;
    }
    let first = scene.triangles.len();
    let index = scene.objects.len() as u32;
    let mirrored = transform.mirrors();
    let mut dropped = 0;
    for &[a, b, c] in &mesh.triangles {
        let (a, b, c) = (world[a as usize], world[b as usize], world[c as usize]);
        let tri = if mirrored { [a, c, b] } else { [a, b, c] };
        if is_degenerate(&tri) {
            dropped += 1;
        } else {
            scene.triangles.push(tri);
            scene.triangle_object.push(index);
        }
    }
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
