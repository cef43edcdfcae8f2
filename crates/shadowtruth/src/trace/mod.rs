//! Exact visibility by ray tracing: the only module that imports obvhs.
//!
//! A BVH per scene (obvhs builds its shape; our own 8-wide tree with exact f32 boxes is walked,
//! one ray or eight at a time) with a watertight triangle test and a conservative node test;
//! the G-buffer of a camera (the surface point of every pixel, shared by the reference and
//! every technique); the hard reference; the soft references (pixel coverage, area light); the
//! reference cache.

mod area_light;
mod bvh;
mod cache;
mod coverage;
mod cwbvh_convert;
mod gbuffer;
mod instances;
mod node_test;
mod packet;
mod reference;
mod sampling;
mod shadow_batch;
mod shadow_ray;
mod simd4;
mod soft_reference;
pub mod splitmix;
mod walk;
mod watertight;
mod wide_bvh;

pub use area_light::{AreaLightError, trace_area_light_reference, validate_area_light};

pub use bvh::{Hit, SceneBvh, TraversalScratch};
pub use cache::{CachedReference, ReferenceCache, reference_digest, soft_reference_digest};
pub use coverage::trace_coverage_reference;
pub use gbuffer::{GBuffer, PixelClass, PrimaryHit, primary_directions, primary_hits};
pub use node_test::node_test_name;
pub use reference::{HardReference, MaskCode, hard_shadow_ray, trace_hard_reference};
pub use shadow_ray::{ShadowRay, SurfacePoint, offset_ray_origin, position_error};
pub use soft_reference::EXR_ENCODING;
pub use soft_reference::{SoftKind, SoftReference};
pub use watertight::{RayTriangleHit, WatertightRay};

/// Bumped whenever a change to the tracer could change a reference bit.
pub const TRACER_VERSION: &str = "shadowtruth-tracer/2";
