//! glTF 2.0 scenes (docs/gltf.md), read through the `gltf` crate's document model with our own
//! buffer loading, so that every problem names the glTF JSON path at fault (`buffers[0].uri`,
//! `meshes[0].primitives[1].mode`).
//!
//! The result is neutral: each glTF mesh once, as an `IndexedMesh` in mesh space, with the list
//! of its placements (one per node that references it); cameras and lights already converted.
//! `load.rs` decides how placements become objects.

mod buffers;
mod data_uri;
mod document;
mod extras;
mod mesh;
mod names;
mod nodes;
mod placed_mesh;
mod problem;
mod views;

pub(crate) use placed_mesh::PlacedMesh;
pub(crate) use problem::GltfProblem;

use super::{Camera, Light, box_corners};
use glam::DVec3;
use std::cell::OnceCell;
use std::path::Path;

/// What a glTF file holds for shadowtruth.
#[derive(Clone, Debug, Default)]
pub(crate) struct GltfScene {
    /// In glTF mesh order; meshes no node of the scene references are left out.
    pub meshes: Vec<PlacedMesh>,
    pub cameras: Vec<Camera>,
    pub lights: Vec<Light>,
}

/// How much of the file to read.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ImportOptions {
    /// Most triangles the meshes may have together, each counted once; checked before any mesh
    /// is read.
    pub max_triangles: u64,
    /// Whether cameras and lights are read (a glTF named by a scene-file object ignores them).
    pub views: bool,
}

/// Reads the glTF (`.gltf` or `.glb`) at `path`, its buffer files inside its folder; every
/// problem found is returned.
pub(crate) fn import_gltf(path: &Path, options: ImportOptions) -> Result<GltfScene, Vec<GltfProblem>> {
    let bytes = document::read(path)?;
    import_gltf_bytes(&bytes, path.parent().unwrap_or(Path::new("")), options)
}

/// Reads a glTF held in memory (`.gltf` JSON or `.glb`), its buffer files inside `folder`.
pub(crate) fn import_gltf_bytes(
    bytes: &[u8],
    folder: &Path,
    options: ImportOptions,
) -> Result<GltfScene, Vec<GltfProblem>> {
    let mut gltf = document::parse(bytes)?;
    let buffers = buffers::load(&mut gltf, folder)?;
    let mut problems = Vec::new();
    let tree = nodes::walk(&gltf.document, &mut problems);
    let meshes =
        mesh::read_placed(&gltf.document, &buffers, tree.meshes, options.max_triangles, &mut problems);
    let mut scene = GltfScene { meshes, ..GltfScene::default() };
    if options.views {
        scene.cameras = views::cameras(&gltf.document, &tree.cameras, &mut problems);
        // Computed once, and only when a spot light needs it.
        let bounds = OnceCell::new();
        let bounds = || *bounds.get_or_init(|| world_bounds(&scene.meshes));
        scene.lights = views::lights(&gltf.document, &tree.lights, bounds, &mut problems);
    }
    if problems.is_empty() { Ok(scene) } else { Err(problems) }
}

/// A box (min, max) around every placed vertex, for the defaults of spot lights: each mesh's own
/// box, from one pass over its vertices, with its corners moved by each placement. The cost is
/// the vertices plus the placements, not their product; the box may be larger than the tightest
/// one around the placed vertices (a rotated mesh), never smaller.
fn world_bounds(meshes: &[PlacedMesh]) -> (DVec3, DVec3) {
    let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    for placed in meshes {
        let positions = &placed.mesh.positions;
        if positions.is_empty() {
            continue;
        }
        let mesh_lo = positions.iter().fold(DVec3::INFINITY, |a, &p| a.min(p));
        let mesh_hi = positions.iter().fold(DVec3::NEG_INFINITY, |a, &p| a.max(p));
        for placement in &placed.placements {
            for corner in box_corners(mesh_lo, mesh_hi) {
                let w = placement.world_from_mesh.transform_point3(corner);
                (lo, hi) = (lo.min(w), hi.max(w));
            }
        }
    }
    (lo, hi)
}
