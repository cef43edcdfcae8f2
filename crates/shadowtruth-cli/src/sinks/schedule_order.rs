//! Puts a report's scenes and runs in the order of its schedule (`Report.schedule`), the order
//! a whole `run` writes them in: reports assembled from parts — merged shards, a resumed run's
//! earlier and new runs — end up as that run's would.

use shadowtruth::record::Report;
use shadowtruth::record::ViewName;
use std::collections::HashMap;

/// Sorts scenes by their first view and runs by (view, resolution, depth format), each sort
/// stable: the runs of one map keep the order they were written in, which the schedule sets.
/// A report without a schedule is left as it is; what the schedule does not name goes last.
pub fn put_in_schedule_order(report: &mut Report) {
    let Some(schedule) = &report.schedule else { return };
    let views: HashMap<&ViewName, usize> = schedule.views.iter().enumerate().map(|(i, v)| (v, i)).collect();
    let mut first_view_of_scene: HashMap<&str, usize> = HashMap::new();
    for (i, v) in schedule.views.iter().enumerate() {
        first_view_of_scene.entry(v.scene.as_str()).or_insert(i);
    }
    let mut runs = std::mem::take(&mut report.runs);
    runs.sort_by_cached_key(|r| {
        let view = views.get(&ViewName::of_run(r)).copied().unwrap_or(usize::MAX);
        let format = position(&schedule.depth_formats, &r.depth_format);
        (view, position(&schedule.resolutions, &r.resolution), format)
    });
    report.runs = runs;
    let mut scenes = std::mem::take(&mut report.scenes);
    scenes.sort_by_key(|s| first_view_of_scene.get(s.name.as_str()).copied().unwrap_or(usize::MAX));
    report.scenes = scenes;
}

/// Where `item` is in `list` (past the end when absent).
fn position<T: PartialEq>(list: &[T], item: &T) -> usize {
    list.iter().position(|x| x == item).unwrap_or(usize::MAX)
}
