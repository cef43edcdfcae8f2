//! The closest hit of a ray, and the order that makes it independent of the tree's shape.

use glam::Vec3;

/// A closest hit: the scene triangle, the distance along the unit direction, barycentrics.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub triangle: u32,
    pub t: f32,
    pub barycentric: [f32; 3],
    /// The triangle's world vertices as the test took them (`Scene::triangle`), carried so that
    /// the surface point is computed from the copy the walk just read rather than from another
    /// random read of the scene's.
    pub vertices: [Vec3; 3],
}

impl Hit {
    /// Whether this hit replaces `best`: nearer, or as near with a lower scene triangle id, so
    /// that the closest hit does not depend on the tree's shape.
    #[inline]
    pub(in crate::trace) fn beats(&self, best: &Option<Hit>) -> bool {
        match best {
            Some(b) => self.t < b.t || (self.t == b.t && self.triangle < b.triangle),
            None => true,
        }
    }
}
