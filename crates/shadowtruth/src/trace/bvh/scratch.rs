//! The traversal state a thread reuses across rays.

use super::walk::WalkState;
use super::wide_bvh::ChildRef;

/// Per-thread traversal state, reused across rays (no allocation per ray): one walk state for
/// the flat and top levels, one for an instance's mesh.
pub struct TraversalScratch {
    pub(in crate::trace) outer: WalkState,
    pub(in crate::trace) inner: WalkState,
    /// The stack of packet walks of the flat tree (packet.rs, x86_64 only).
    #[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
    pub(in crate::trace) packet: Box<[(ChildRef, u32, f32)]>,
}
