//! The engine: one BVH per scene and the rays walked through it. obvhs builds the tree's shape
//! (a CWBVH, converted by cwbvh_convert.rs); the walks run over our own 8-wide tree with exact
//! f32 child boxes (wide_bvh.rs, walk.rs; eight or sixteen rays at once in packet.rs, their
//! closest hits kept in best_hits.rs), a conservative node test (node_test.rs, simd4.rs) and a
//! watertight triangle test (watertight.rs); instanced meshes sit behind a second level
//! (instances.rs). Shadow rays (shadow_ray.rs) are answered one at a time or a batch at once
//! (shadow_batch.rs), each with a certificate (certified.rs, shadow_search.rs); primary hits are
//! certified too (primary_certificate.rs, with each hit's own crossing in f64, own_crossing.rs).

pub(in crate::trace) mod best_hits;
pub(in crate::trace) mod certified;
pub(in crate::trace) mod cwbvh_convert;
pub(in crate::trace) mod flat_tree;
pub(in crate::trace) mod hit;
pub(in crate::trace) mod instances;
pub(in crate::trace) mod lane_vector;
pub(in crate::trace) mod node_test;
pub(in crate::trace) mod own_crossing;
pub(in crate::trace) mod packet;
#[cfg(target_arch = "x86_64")]
pub(in crate::trace) mod packet_isa;
pub(in crate::trace) mod primary_certificate;
pub(in crate::trace) mod scene_bvh;
pub(in crate::trace) mod scratch;
pub(in crate::trace) mod shadow_batch;
pub(in crate::trace) mod shadow_ray;
pub(in crate::trace) mod shadow_search;
pub(in crate::trace) mod simd4;
pub(in crate::trace) mod walk;
pub(in crate::trace) mod watertight;
pub(in crate::trace) mod wide_bvh;

pub use hit::Hit;
pub use node_test::node_test_name;
pub use scene_bvh::{SceneBvh, ShadowBits};
pub use scratch::TraversalScratch;
pub use shadow_ray::{ShadowRay, SurfacePoint, exact_point, position_error};
pub use shadow_search::ShadowAnswer;
pub use watertight::{RayTriangleHit, WatertightRay};

/// Runs `work` compiled for the packet walk's instruction set where the processor has one
/// (`packet_isa::in_packet_isa`), portable otherwise: loops of f64 arithmetic beside the walks
/// (a tile's surface points, a block of light samples) then take its vector registers too.
/// Everything `work` calls must be `#[inline(always)]` for that.
#[inline(always)]
pub(in crate::trace) fn in_packet_isa_where_available<R>(work: impl FnOnce() -> R) -> R {
    #[cfg(target_arch = "x86_64")]
    if let Some(isa) = packet_isa::packet_isa() {
        return packet_isa::in_packet_isa(isa, work);
    }
    work()
}
