//! A plan's schedule as `run` records it in report.json (`ScheduleRecord`): the identity that
//! shards must share to be merged and a folder must carry to be resumed, and the order of views
//! and maps that merged and resumed reports are put back in.

use super::Plan;
use super::select::Selected;
use sha2::{Digest, Sha256};
use shadowtruth::record::{ScheduleRecord, ViewName};
use shadowtruth::trace::reference_digest;

/// The views of `selected` in schedule order (scene by scene, then its (camera, light) pairs).
pub(super) fn scheduled_views(selected: &[Selected]) -> Vec<ViewName> {
    selected
        .iter()
        .flat_map(|sel| {
            sel.pairs.iter().map(|&(ci, li)| ViewName {
                scene: sel.scene.name.clone(),
                camera: sel.scene.cameras[ci].name.clone(),
                light: sel.scene.lights[li].name.clone(),
            })
        })
        .collect()
}

/// The schedule of `plan` over `selected`. The identity hashes what decides a run's numbers and
/// files: each view's geometry, camera and light (through the reference cache's digest, plus the
/// light's every field for soft references), the techniques in canonical form, the maps, the
/// reference grids, repeats, figures, zoom, pipeline and an imported shadow map's matrix — not
/// file paths, so that shards run from other folders still merge.
pub(super) fn schedule_record(plan: &Plan, selected: &[Selected]) -> ScheduleRecord {
    let mut h = Sha256::new();
    let mut field = |name: &str, value: String| {
        h.update(name.as_bytes());
        h.update(b"\0");
        h.update(value.as_bytes());
        h.update(b"\0");
    };
    for sel in selected {
        for &(ci, li) in &sel.pairs {
            let (camera, light) = (&sel.scene.cameras[ci], &sel.scene.lights[li]);
            let names = format!("{}/{}/{}", sel.scene.name, camera.name, light.name);
            let digest = reference_digest(&sel.scene, camera, light);
            field("view", format!("{names} {digest} {light:?} {:?}", camera.path));
        }
    }
    for t in &plan.techniques {
        field("technique", t.canonical());
    }
    let formats: Vec<String> = plan.depth_formats.iter().map(|f| f.name().to_string()).collect();
    field("resolutions", format!("{:?}", plan.resolutions));
    field("depth_formats", format!("{formats:?}"));
    field("grids", format!("{} {}", plan.coverage_grid, plan.area_light_grid));
    field("repeats", plan.repeats.to_string());
    field("frames", plan.frames.to_string());
    field("figures", format!("{} {:?}", plan.figures, plan.zoom));
    field("pipeline", format!("{:?}", plan.pipeline));
    if let Some(map) = &plan.shadow_map {
        field("shadow_map", format!("{} {:?}", map.layer.resolution, map.clip_from_world));
    }
    ScheduleRecord {
        identity: shadowtruth::scene::hex(&h.finalize()),
        views: scheduled_views(selected),
        resolutions: plan.resolutions.clone(),
        depth_formats: formats,
        runs_per_map: plan.techniques.len(),
    }
}
