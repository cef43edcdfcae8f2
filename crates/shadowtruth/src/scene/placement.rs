//! A mesh placed in the world: what an object of the scene is made of. An OBJ or a shape has one
//! placement (its object's transform) or one per entry of its `instances`; a glTF mesh has one
//! per node that references it. A mesh with one placement is flattened into world triangles; a
//! mesh with several is stored once and instanced.

use super::instance::{Instance, SharedMesh, box_corners, is_degenerate, world_vertex};
use super::shapes::IndexedMesh;
use super::{Object, Scene, Transform};
use crate::json_input::Problems;
use glam::{DAffine3, DVec3, Vec3};
use rayon::prelude::*;

/// The refusal of a placement that carries a vertex of its mesh out of f32: flattened or
/// instanced, the same words.
const VERTEX_OUT_OF_RANGE: &str = "a vertex leaves the f32 range after the transform";

/// One placement of a mesh: its world transform and the object it becomes.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Placement {
    /// Mesh space to world space, composed in f64 (each vertex is rounded to f32 once).
    pub world_from_mesh: DAffine3,
    /// Whether the transform mirrors (negative determinant): triangles are then flipped so that
    /// closed objects stay counter-clockwise seen from outside.
    pub mirrored: bool,
    /// The object's name.
    pub name: String,
    /// Where the placement comes from, for problems: a scene-file JSON path (`objects[2].mesh`)
    /// or a glTF one (`nodes[3]`).
    pub path: String,
    /// A solid whose back faces may be culled; open objects are two-sided.
    pub closed: bool,
}

impl Placement {
    /// The single placement of an OBJ mesh or a shape.
    pub(crate) fn from_transform(transform: &Transform, name: &str, path: String, closed: bool) -> Self {
        Placement {
            world_from_mesh: transform.affine(),
            mirrored: transform.mirrors(),
            name: name.to_string(),
            path,
            closed,
        }
    }

    /// This placement moved by `outer` (applied after it), named `OUTER/THIS` and closed when
    /// either is: a glTF node inside a scene-file object.
    pub(crate) fn within(&self, outer: &Placement, path: String) -> Self {
        Placement {
            world_from_mesh: outer.world_from_mesh * self.world_from_mesh,
            mirrored: self.mirrored != outer.mirrored,
            name: format!("{}/{}", outer.name, self.name),
            path,
            closed: outer.closed || self.closed,
        }
    }
}

/// Adds `mesh` at its placements: flattened into world triangles when it has one, stored once
/// and instanced when it has several (src/scene/instance.rs: both give the same triangles).
pub(crate) fn add_mesh_placements(
    scene: &mut Scene,
    mesh: IndexedMesh,
    placements: &[Placement],
    problems: &mut Problems,
) {
    match placements {
        [placement] => flatten(scene, &mesh, placement, problems),
        _ => instance(scene, mesh, placements, problems),
    }
}

/// Adds `mesh` at `placement` as one contiguous object of flat triangles. Each vertex is
/// transformed once (`world_vertex`), so shared vertices stay shared; a mirroring placement
/// flips the triangles (closed objects stay counter-clockwise from outside); zero-area
/// triangles are dropped and counted.
fn flatten(scene: &mut Scene, mesh: &IndexedMesh, placement: &Placement, problems: &mut Problems) {
    // Per vertex and per triangle in parallel (rayon), appended in mesh order.
    let world: Vec<Vec3> =
        mesh.positions.par_iter().map(|&p| world_vertex(&placement.world_from_mesh, p)).collect();
    if world.par_iter().any(|v| !v.is_finite()) {
        problems.report(&placement.path, VERTEX_OUT_OF_RANGE);
        return;
    }
    let first = scene.flat_triangles.len();
    let index = scene.objects.len() as u32;
    let corners = |&[a, b, c]: &[u32; 3]| {
        let (a, b, c) = (world[a as usize], world[b as usize], world[c as usize]);
        if placement.mirrored { [a, c, b] } else { [a, b, c] }
    };
    let degenerate: Vec<bool> = mesh.triangles.par_iter().map(|t| is_degenerate(&corners(t))).collect();
    let dropped = degenerate.iter().filter(|&&d| d).count();
    scene.flat_triangles.reserve(mesh.triangles.len() - dropped);
    let kept = mesh.triangles.iter().zip(&degenerate).filter(|(_, d)| !**d).map(|(t, _)| corners(t));
    scene.flat_triangles.extend(kept);
    scene.flat_triangle_object.resize(scene.flat_triangles.len(), index);
    let count = scene.flat_triangles.len() - first;
    scene.dropped_degenerate += dropped;
    if count == 0 {
        problems.report(&placement.path, format!("has no triangles ({dropped} degenerate dropped)"));
    }
    match (u32::try_from(first), u32::try_from(count)) {
        (Ok(first_triangle), Ok(triangle_count)) => scene.objects.push(Object {
            name: placement.name.clone(),
            closed: placement.closed,
            first_triangle,
            triangle_count,
        }),
        _ => problems.report(&placement.path, "too many triangles in the scene"),
    }
}

/// Stores `mesh` once, without the triangles degenerate in its own space, and adds one object
/// per placement, each an instance of it. Their triangle ids are given once every object is
/// read (`number_instances`): instanced ids follow the flat ones.
fn instance(scene: &mut Scene, mesh: IndexedMesh, placements: &[Placement], problems: &mut Problems) {
    let local = |t: &[u32; 3]| t.map(|i| mesh.positions[i as usize]);
    let triangles: Vec<[u32; 3]> =
        mesh.triangles.iter().copied().filter(|t| !is_local_degenerate(local(t))).collect();
    scene.dropped_degenerate += mesh.triangles.len() - triangles.len();
    let triangle_count = triangles.len() as u32;
    let mesh_index = scene.meshes.len() as u32;
    scene.meshes.push(SharedMesh { positions: mesh.positions, triangles });
    let (lo, hi) = scene.meshes[mesh_index as usize].bounds();
    for placement in placements {
        if triangle_count == 0 {
            problems.report(&placement.path, "has no triangles (all degenerate)");
            continue;
        }
        // Every vertex lies in the box of the mesh's bounds, and rounding is monotonic.
        if !box_corners(lo, hi).iter().all(|&p| world_vertex(&placement.world_from_mesh, p).is_finite()) {
            problems.report(&placement.path, VERTEX_OUT_OF_RANGE);
            continue;
        }
        let object = scene.objects.len() as u32;
        scene.instances.push(Instance::new(
            mesh_index,
            object,
            placement.world_from_mesh,
            placement.mirrored,
        ));
        let name = placement.name.clone();
        scene.objects.push(Object { name, closed: placement.closed, first_triangle: 0, triangle_count });
    }
}

/// Gives each instance, and its object, the triangle ids after the flat triangles.
pub(crate) fn number_instances(scene: &mut Scene) {
    let mut next = scene.flat_triangles.len() as u32;
    for instance in &mut scene.instances {
        instance.first_triangle = next;
        scene.objects[instance.object as usize].first_triangle = next;
        next += scene.meshes[instance.mesh as usize].triangles.len() as u32;
    }
}

/// A triangle with a repeated vertex or parallel edges in the mesh's own (f64) space.
fn is_local_degenerate([a, b, c]: [DVec3; 3]) -> bool {
    a == b || b == c || a == c || (b - a).cross(c - a) == DVec3::ZERO
}
