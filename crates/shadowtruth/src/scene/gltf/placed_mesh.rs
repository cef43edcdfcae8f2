//! A glTF mesh as the reader hands it over: read once, placed by every node that names it.

use crate::scene::placement::Placement;
use crate::scene::shapes::IndexedMesh;

/// One glTF mesh (all its triangle primitives together) and every node that places it.
#[derive(Clone, Debug)]
pub(crate) struct PlacedMesh {
    pub mesh: IndexedMesh,
    /// `meshes[i]`.
    pub path: String,
    pub placements: Vec<Placement>,
}
