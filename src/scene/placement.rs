//! A mesh placed in the world: what an object of the scene is made of. An OBJ or a shape has one
//! placement (its object's transform); a glTF mesh has one per node that references it.

use super::Transform;
use glam::DAffine3;

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

    /// This placement moved by `outer` (applied after it): a glTF node inside a scene-file object.
    pub(crate) fn within(&self, outer: &Transform, name: String, path: String, closed: bool) -> Self {
        Placement {
            world_from_mesh: outer.affine() * self.world_from_mesh,
            mirrored: self.mirrored != outer.mirrors(),
            name,
            path,
            closed,
        }
    }
}
