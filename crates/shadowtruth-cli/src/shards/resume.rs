//! `run --resume`: what an interrupted report folder already holds. report.json and its journal
//! hold every finished run of a killed run (`writer.rs`); a
//! map (view, resolution, depth format) counts as done when all of its runs are there and, with
//! figures, its grid figure too (written after the map's other figures, `figure_sink.rs`).
//! Runs of unfinished maps are dropped and run again with their map.

use crate::plan::MapKey;
use crate::sinks::figure_sink::grid_file_name;
use anyhow::{Result, anyhow, bail};
use shadowtruth::raster::DepthFormat;
use shadowtruth::record::ShardRecord;
use shadowtruth::record::{Report, RunRecord};
use shadowtruth::scene::ViewKey;
use std::collections::{HashMap, HashSet};
use std::path::Path;

/// An interrupted run's report, reduced to its finished maps.
pub struct Resumed {
    pub report: Report,
    pub done: HashSet<MapKey>,
    /// Runs of unfinished maps, dropped to be run again.
    pub dropped_runs: usize,
}

/// The map a run belongs to.
pub fn map_key(run: &RunRecord) -> MapKey {
    MapKey::new(ViewKey::new(&run.scene, &run.camera, &run.light), run.resolution, &run.depth_format)
}

/// Reads `dir/report.json` to resume it (None when there is none: the run starts afresh). A report
/// that `run` did not write, or of another shard, is an error; whether it is of the same plan
/// is checked once the plan is expanded (`ReportWriter::resume`).
pub fn open_resumed(dir: &Path, figures: bool, shard: Option<ShardRecord>) -> Result<Option<Resumed>> {
    let file = dir.join("report.json");
    if !file.exists() {
        return Ok(None);
    }
    let (mut report, _) = shadowtruth::record::load_journaled_report(dir).map_err(|e| anyhow!("{e}"))?;
    let Some(schedule) = &report.schedule else {
        bail!(
            "{}: schedule: missing: the folder holds no `run` to resume (a report of `papers`, `score` or of \
             an earlier version); run without --resume to replace it",
            file.display()
        );
    };
    if report.shard != shard {
        let name = |s: Option<ShardRecord>| s.map_or("the whole plan".to_string(), |s| format!("shard {s}"));
        bail!(
            "{}: shard: the folder holds {}, this run is {}",
            file.display(),
            name(report.shard),
            name(shard)
        );
    }
    let mut runs_per_map: HashMap<MapKey, usize> = HashMap::new();
    for run in &report.runs {
        *runs_per_map.entry(map_key(run)).or_default() += 1;
    }
    let done: HashSet<MapKey> = runs_per_map
        .into_iter()
        .filter(|(key, runs)| *runs == schedule.runs_per_map && (!figures || grid_written(dir, key)))
        .map(|(key, _)| key)
        .collect();
    let before = report.runs.len();
    report.runs.retain(|run| done.contains(&map_key(run)));
    let dropped_runs = before - report.runs.len();
    Ok(Some(Resumed { report, done, dropped_runs }))
}

/// Whether the map's grid figure is there. A depth format the tool does not know (an edited
/// report) never had a grid written: its map is run again.
fn grid_written(dir: &Path, key: &MapKey) -> bool {
    let view = ViewKey::new(&key.scene, &key.camera, &key.light);
    DepthFormat::parse(&key.depth_format).is_some_and(|format| {
        dir.join("figures").join(grid_file_name(view, key.resolution, format)).is_file()
    })
}
