//! Exact visibility by ray tracing: the only module that imports obvhs.
//!
//! Two folders, the lower one never importing the upper: `bvh/`, the engine (a BVH per scene,
//! obvhs building its shape, our own 8-wide tree with exact f32 boxes walked one ray or eight at
//! a time, a watertight triangle test and a conservative node test), and `reference/`, what is
//! traced with it (the G-buffer of a camera, the hard reference, the soft references — pixel
//! coverage, area light — and the reference cache).

mod bvh;
mod reference;
pub mod splitmix;

pub use bvh::{
    Hit, RayTriangleHit, SceneBvh, ShadowAnswer, ShadowBits, ShadowRay, SurfacePoint, TraversalScratch,
    WatertightRay, exact_point, node_test_name, position_error,
};
pub use reference::{
    AreaLightError, CachedReference, DEFAULT_AREA_LIGHT_GRID, DEFAULT_COVERAGE_GRID, EXR_ENCODING, GBuffer,
    HardReference, MAX_REFERENCE_GRID, MaskCode, PixelClass, PrimaryHit, ReferenceCache, ShadowOverlap,
    SoftKind, SoftReference, area_light_shadow_rays, hard_shadow_ray, hard_shadow_rays, primary_directions,
    primary_hits, reference_digest, soft_reference_digest, trace_area_light_reference,
    trace_coverage_reference, trace_hard_reference, trace_scored_view, trace_shadow_overlap,
    trace_shadow_rays, validate_area_light,
};

/// Bumped whenever a change to the tracer could change a reference bit.
pub const TRACER_VERSION: &str = "shadowtruth-tracer/4";
