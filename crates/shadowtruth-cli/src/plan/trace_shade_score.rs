//! The three steps every measurement of a technique takes, wherever it is assembled (the
//! schedule, frames, `tune`, the papers' experiments): a view traced (G-buffer and the
//! references its techniques are judged by), a technique shaded through one map setting, and
//! its visibility scored against a reference with the attribution of every false pixel.

use super::map_setting::MapSetting;
use super::references::ViewReferences;
use super::{Plan, PlanError};
use shadowtruth::metrics::{Counts, LightUv, attribute, score_hard};
use shadowtruth::scene::{Camera, Light, Scene};
use shadowtruth::technique::{BuiltLayers, Technique};
use shadowtruth::trace::{GBuffer, HardReference, ReferenceCache, SceneBvh, ShadowOverlap};

/// The G-buffer of the (camera, light) view and the references `plan`'s techniques are scored
/// against (read from `cache` when given), the pixels the hard reference cannot decide left out
/// of the G-buffer and its barycentrics released (`GBuffer::release_barycentrics`); `stage` is
/// told each step (`G-buffer`, `reference`) as it begins.
pub fn trace_view(
    plan: &Plan,
    cache: Option<&ReferenceCache>,
    scene: &Scene,
    bvh: &SceneBvh,
    (camera, light): (&Camera, &Light),
    stage: &mut dyn FnMut(&str) -> Result<(), PlanError>,
) -> Result<(GBuffer, ViewReferences), PlanError> {
    stage("G-buffer")?;
    let mut gbuffer = GBuffer::trace(bvh, camera, light);
    stage("reference")?;
    let references = ViewReferences::new(plan, cache, scene, bvh, &mut gbuffer, camera, light)?;
    // Every ray from the view's surface points is traced: the maps take the room.
    gbuffer.release_barycentrics();
    Ok((gbuffer, references))
}

/// The technique's visibility of every evaluated pixel through `map`, whose maps hold `layers`
/// (one per map, in `map.views()` order).
pub fn shade_through(
    technique: &dyn Technique,
    scene: &Scene,
    map: &MapSetting,
    layers: &[BuiltLayers],
) -> Vec<f32> {
    map.shade(technique, &map.contexts(scene, layers))
}

/// The counts of `visibility` against `reference`, with the attribution of every false pixel
/// (acne, leak, light bleeding where `overlap` says occluders overlap, aliasing) through the
/// light-map positions `light_uv`.
pub fn score_against(
    scene: &Scene,
    gbuffer: &GBuffer,
    reference: &HardReference,
    visibility: &[f32],
    light_uv: &LightUv,
    overlap: Option<&ShadowOverlap>,
) -> Counts {
    score_hard(gbuffer, reference, visibility)
        .with_attribution(attribute(scene, gbuffer, reference, visibility, light_uv, overlap))
}
