//! Procedural shapes.

/// A procedural shape, in object space before its transform.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {}
