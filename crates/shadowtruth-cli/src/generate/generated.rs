//! A generated scene in memory, before it is written.

use shadowtruth::scene::{IndexedMesh, Transform};

/// One object of a generated scene: its name, mesh, whether it is a closed solid, and its
/// placements when it is instanced (none: the mesh stands where it is).
pub(crate) struct GeneratedObject {
    pub name: &'static str,
    pub mesh: IndexedMesh,
    pub closed: bool,
    pub instances: Vec<Transform>,
}

/// A generated scene before it is written: objects, the side of the square ground in metres,
/// and the height of its tallest caster.
pub(crate) struct GeneratedScene {
    pub objects: Vec<GeneratedObject>,
    pub ground_size_m: f64,
    pub top_m: f64,
}

impl GeneratedScene {
    /// Triangles numbered: every placement of an instanced mesh counts.
    pub fn triangle_count(&self) -> u64 {
        self.objects.iter().map(|o| o.mesh.triangles.len() as u64 * o.instances.len().max(1) as u64).sum()
    }
}
