//! The scene's triangles as the device draws them: world-space vertices, three per triangle,
//! closed objects' and open objects' apart, handed over in chunks of a bounded size, so that a
//! scene of any size (100 M instanced triangles flatten to 3.6 GB of vertices) is streamed
//! through one buffer's worth of memory and no buffer exceeds the adapter's `max_buffer_size`.

use super::GpuError;
use shadowtruth::scene::Scene;

/// Bytes of vertices per chunk at most: 4 M triangles.
pub(crate) const CHUNK_BYTES: u64 = 48 << 20;

const TRIANGLE_BYTES: u64 = 3 * 12;

/// Triangles per chunk for an adapter whose buffers go up to `max_buffer_size` bytes.
pub(crate) fn chunk_triangles(max_buffer_size: u64) -> usize {
    (CHUNK_BYTES.min(max_buffer_size) / TRIANGLE_BYTES).max(1) as usize
}

/// Calls `draw` with the vertices of the triangles of the closed (or the open) objects, in
/// triangle id order, at most `chunk_triangles` triangles at a time; stops at its first error.
pub(crate) fn for_each_chunk(
    scene: &Scene,
    closed: bool,
    chunk_triangles: usize,
    mut draw: impl FnMut(&[[f32; 3]]) -> Result<(), GpuError>,
) -> Result<(), GpuError> {
    let capacity = 3 * chunk_triangles.max(1);
    let mut chunk: Vec<[f32; 3]> = Vec::with_capacity(capacity.min(1 << 20));
    // An object's triangles are one id range, and objects come in id order.
    let objects = scene.objects.iter().enumerate().filter(|(_, o)| o.closed == closed);
    for (index, _) in objects {
        for tri in scene.object_triangles(index) {
            chunk.extend(tri.iter().map(|p| p.to_array()));
            if chunk.len() == capacity {
                draw(&chunk)?;
                chunk.clear();
            }
        }
    }
    if !chunk.is_empty() {
        draw(&chunk)?;
    }
    Ok(())
}
