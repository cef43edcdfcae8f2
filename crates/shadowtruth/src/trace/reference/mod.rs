//! The references, traced over the engine (`super::bvh`): the G-buffer of a camera (the surface
//! point of every pixel, shared by the reference and every technique), the hard reference, the
//! soft references (pixel coverage, area light) with their sampling, and the reference cache.

pub(in crate::trace) mod area_light;
pub(in crate::trace) mod cache;
pub(in crate::trace) mod coverage;
pub(in crate::trace) mod facing;
pub(in crate::trace) mod gbuffer;
pub(in crate::trace) mod hard;
pub(in crate::trace) mod overlap;
mod pixel_buffer;
pub(in crate::trace) mod sampling;
pub(in crate::trace) mod soft_reference;

pub use area_light::{
    AreaLightError, area_light_shadow_rays, trace_area_light_reference, validate_area_light,
};
pub use cache::{CachedReference, ReferenceCache, reference_digest, soft_reference_digest};
pub use coverage::trace_coverage_reference;
pub use gbuffer::{GBuffer, PixelClass, PrimaryHit, primary_directions, primary_hits};
pub use hard::{
    HardReference, MaskCode, hard_shadow_ray, hard_shadow_rays, trace_hard_reference, trace_scored_view,
    trace_shadow_rays,
};
pub use overlap::{ShadowOverlap, trace_shadow_overlap};
pub use soft_reference::EXR_ENCODING;
pub use soft_reference::{
    DEFAULT_AREA_LIGHT_GRID, DEFAULT_COVERAGE_GRID, MAX_REFERENCE_GRID, SoftKind, SoftReference,
};
