//! Exact visibility by ray tracing: the only module that imports obvhs.
//!
//! A BVH per scene with a watertight triangle test and a robust traversal of obvhs's CWBVH;
//! the G-buffer of a camera (the surface point of every pixel, shared by the reference and
//! every technique); the hard reference; the reference cache.

mod bvh;
mod cache;
mod gbuffer;
mod offset;
mod reference;
mod simd4;
mod watertight;

pub use bvh::{Hit, SceneBvh, TraversalScratch};
pub use cache::{CachedReference, ReferenceCache, reference_digest};
pub use gbuffer::{GBuffer, PixelClass};
pub use offset::offset_ray_origin;
pub use reference::{HardReference, MaskCode, trace_hard_reference};
pub use watertight::{RayTriangleHit, WatertightRay};

/// Bumped whenever a change to the tracer could change a reference bit.
pub const TRACER_VERSION: &str = "shadowtruth-tracer/1";
