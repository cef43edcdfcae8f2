//! The scene's triangles as the device draws them, closed objects' and open objects' apart:
//! - flat triangles as world-space vertices, three per triangle, handed over in chunks of a
//!   bounded size;
//! - placed meshes as instanced draws: the mesh's vertices and indices once, one transform per
//!   placement (as engines draw a forest), in draws of a bounded number of placements.
//!
//! No buffer exceeds the adapter's `max_buffer_size` and memory stays at one chunk: 100 M
//! instanced triangles flattened would be 3.6 GB of vertices. A depth-only pass keeps the
//! minimum of its fragments' depths whatever their order, so the order of draws is free.

use super::GpuError;
use shadowtruth::scene::{Scene, SharedMesh};

/// Bytes of one buffer at most: 1 M placements, or a little more than 1 M flat triangles.
pub(crate) const CHUNK_BYTES: u64 = 48 << 20;

const TRIANGLE_BYTES: u64 = 3 * 12;
/// A placement's transform: three rows of an affine map (world = row · (p, 1)).
pub(crate) type Placement = [[f32; 4]; 3];
const PLACEMENT_BYTES: u64 = std::mem::size_of::<Placement>() as u64;

/// Items per buffer (flat triangles, placements, or triangles of indices: at most 48 bytes each)
/// for an adapter whose buffers go up to `max_buffer_size` bytes.
pub(crate) fn chunk_items(max_buffer_size: u64) -> usize {
    (CHUNK_BYTES.min(max_buffer_size) / PLACEMENT_BYTES.max(TRIANGLE_BYTES)).max(1) as usize
}

/// Calls `draw` with the world-space vertices of the flat triangles of the closed (or the open)
/// objects, in triangle id order, at most `chunk_triangles` triangles at a time; stops at its
/// first error.
pub(crate) fn for_each_flat_chunk(
    scene: &Scene,
    closed: bool,
    chunk_triangles: usize,
    mut draw: impl FnMut(&[[f32; 3]]) -> Result<(), GpuError>,
) -> Result<(), GpuError> {
    let capacity = 3 * chunk_triangles.max(1);
    let mut chunk: Vec<[f32; 3]> = Vec::with_capacity(capacity.min(1 << 20));
    let is_closed = |object: u32| scene.objects.get(object as usize).is_some_and(|o| o.closed);
    for (tri, &object) in scene.flat_triangles.iter().zip(&scene.flat_triangle_object) {
        if is_closed(object) != closed {
            continue;
        }
        chunk.extend(tri.iter().map(|p| p.to_array()));
        if chunk.len() == capacity {
            draw(&chunk)?;
            chunk.clear();
        }
    }
    if !chunk.is_empty() {
        draw(&chunk)?;
    }
    Ok(())
}

/// Consecutive placements of one mesh with one winding, drawn by instanced draws.
pub(crate) struct InstanceRun<'a> {
    pub mesh: &'a SharedMesh,
    /// A mirroring transform: the indices are read with the second and third corners swapped,
    /// as `Instance::triangle` does, so that closed meshes stay counter-clockwise from outside.
    pub mirrored: bool,
    pub placements: Vec<Placement>,
}

impl InstanceRun<'_> {
    /// The mesh's vertices in f32, as the device reads them.
    pub fn positions(&self) -> Vec<[f32; 3]> {
        self.mesh.positions.iter().map(|p| p.as_vec3().to_array()).collect()
    }

    /// The mesh's corner indices, in the run's winding.
    pub fn indices(&self) -> Vec<u32> {
        let wind = |[a, b, c]: [u32; 3]| if self.mirrored { [a, c, b] } else { [a, b, c] };
        self.mesh.triangles.iter().flat_map(|&t| wind(t)).collect()
    }
}

/// The placements of the closed (or the open) objects' instanced meshes, in runs of one mesh
/// and winding, in instance order.
pub(crate) fn instance_runs(scene: &Scene, closed: bool) -> Vec<InstanceRun<'_>> {
    let mut runs: Vec<InstanceRun> = Vec::new();
    for instance in &scene.instances {
        if scene.objects.get(instance.object as usize).is_some_and(|o| o.closed) != closed {
            continue;
        }
        let mesh = &scene.meshes[instance.mesh as usize];
        let m = instance.world_from_local;
        let (x, y, z, t) = (m.matrix3.x_axis, m.matrix3.y_axis, m.matrix3.z_axis, m.translation);
        let placement = [
            [x.x as f32, y.x as f32, z.x as f32, t.x as f32],
            [x.y as f32, y.y as f32, z.y as f32, t.y as f32],
            [x.z as f32, y.z as f32, z.z as f32, t.z as f32],
        ];
        match runs.last_mut() {
            Some(run) if std::ptr::eq(run.mesh, mesh) && run.mirrored == instance.mirrored => {
                run.placements.push(placement)
            }
            _ => runs.push(InstanceRun { mesh, mirrored: instance.mirrored, placements: vec![placement] }),
        }
    }
    runs
}

/// Refuses a mesh whose vertices do not fit one buffer (its draws index them all at once).
pub(crate) fn check_mesh_fits(mesh: &SharedMesh, max_buffer_size: u64) -> Result<(), GpuError> {
    let bytes = mesh.positions.len() as u64 * 12;
    if bytes > max_buffer_size {
        return Err(GpuError(format!(
            "an instanced mesh of {} vertices ({bytes} bytes) does not fit one GPU buffer: the \
             adapter's max_buffer_size is {max_buffer_size} bytes",
            mesh.positions.len()
        )));
    }
    Ok(())
}
