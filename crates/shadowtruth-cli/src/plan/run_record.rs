//! A run's record: its technique's visibility scored against the reference it is judged by, at
//! one map setting of a traced view, with its timings.

use super::events::TracedView;
use super::map_setting::MapSetting;
use super::score_against;
use shadowtruth::metrics::score_soft;
use shadowtruth::record::{RunRecord, Timings};
use shadowtruth::technique::TechniqueSpec;

/// The record of `spec`'s `visibility` (timings and layer memory are the caller's).
pub(super) fn run_record(
    traced: &TracedView,
    map: &MapSetting,
    spec: &TechniqueSpec,
    visibility: &[f32],
) -> RunRecord {
    let gbuffer = traced.gbuffer;
    let (scored_against, soft_reference, reference_used) = traced.references.for_kind(spec.reference_kind());
    let counts = score_against(
        traced.scene,
        gbuffer,
        scored_against,
        visibility,
        map.light_uv,
        Some(&traced.references.overlap),
    );
    RunRecord {
        scene: traced.scene.name.clone(),
        camera: traced.camera.name.clone(),
        light: traced.light.name.clone(),
        technique: spec.name().into(),
        parameters: spec.parameters(),
        label: spec.label(),
        resolution: map.resolution,
        depth_format: map.format.name().into(),
        rates: counts.rates(),
        counts,
        timings: Timings::default(),
        layer_memory_bytes: 0,
        reference: reference_used,
        soft: soft_reference.map(|r| score_soft(gbuffer, &r.visibility, visibility)),
        pipeline: None,
        cascades: map.cascaded.map(|c| c.record(gbuffer, scored_against, visibility)),
        point_map: map.cube.map(|c| c.record(gbuffer, scored_against, visibility)),
        temporal: None,
    }
}

/// A run's timings: building its layers, shading (both ms, shading the median of repeats whose
/// least and greatest time are `shade_range_ms` where it was timed over repeats) and shading per
/// evaluated pixel.
pub(super) fn timings(
    prepare_ms: f64,
    shade_ms: f64,
    shade_range_ms: Option<[f64; 2]>,
    evaluated: u64,
) -> Timings {
    let ns_per_pixel = |ms: f64| ms * 1e6 / evaluated.max(1) as f64;
    Timings {
        prepare: prepare_ms,
        shade: shade_ms,
        ns_per_pixel: ns_per_pixel(shade_ms),
        ns_per_pixel_min: shade_range_ms.map(|r| ns_per_pixel(r[0])),
        ns_per_pixel_max: shade_range_ms.map(|r| ns_per_pixel(r[1])),
    }
}
