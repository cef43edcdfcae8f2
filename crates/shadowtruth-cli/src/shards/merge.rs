//! `shadowtruth merge`: joins the report folders of `run --shard K/N`, K = 1..N, into the folder
//! the whole run would have written — report.json in schedule order (`schedule_order.rs`), the
//! shards' figures copied, report.csv, plots and index.html rendered from the merged report —
//! equal to it apart from timings. Shards of different schedules, a missing or repeated shard, a
//! folder that is no shard, a run in a view of another shard, an unfinished shard and a shard
//! missing a figure of its runs are refused before anything is written.

use crate::drawing::figures::{run_stem, view_stem};
use crate::outputs::write_report_outputs;
use crate::plan::Shard;
use crate::sinks::ReportWriter;
use crate::sinks::figure_sink::grid_file_name;
use crate::sinks::schedule_order::put_in_schedule_order;
use anyhow::{Context, Result, anyhow, bail};
use shadowtruth::atomic_file::write_atomic;
use shadowtruth::raster::DepthFormat;
use shadowtruth::record::{Report, RunRecord, load_report};
use shadowtruth::record::{ScheduleRecord, ShardRecord, ViewName};
use shadowtruth::scene::ViewKey;
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

/// One shard folder, read.
struct ShardFolder {
    dir: PathBuf,
    /// Its report.json, as messages name it.
    file: String,
    report: Report,
    schedule: ScheduleRecord,
    shard: ShardRecord,
}

/// Merges the shard folders `dirs` into `out` and returns the merged report.
pub fn merge_shards(dirs: &[PathBuf], out: &Path) -> Result<Report> {
    let shards = dirs.iter().map(|d| read_shard(d)).collect::<Result<Vec<_>>>()?;
    check_complete_set(&shards)?;
    for shard in &shards {
        check_runs(shard)?;
        if same_folder(&shard.dir, out) {
            bail!("-o {}: the output folder is one of the shards; choose another", out.display());
        }
    }
    check_figures(&shards)?;
    let report = merged_report(&shards);
    let mut writer = ReportWriter::create(out).with_context(|| format!("opening {}", out.display()))?;
    writer.replace_report(report.clone());
    writer.flush().with_context(|| format!("writing {}", writer.path().display()))?;
    for shard in &shards {
        copy_figures(&shard.dir, out)?;
    }
    write_report_outputs(out, &report).with_context(|| format!("writing into {}", out.display()))?;
    Ok(report)
}

fn read_shard(dir: &Path) -> Result<ShardFolder> {
    let (report, file) = load_report(dir).map_err(|e| anyhow!("{e}"))?;
    let file = file.display().to_string();
    let not_a_shard = |field: &str| {
        anyhow!("{file}: {field}: missing: not a shard folder (`shadowtruth run --shard K/N` writes one)")
    };
    let shard = report.shard.ok_or_else(|| not_a_shard("shard"))?;
    let schedule = report.schedule.clone().ok_or_else(|| not_a_shard("schedule"))?;
    if Shard::new(shard.index, shard.count).is_err() {
        bail!("{file}: shard: {shard} is not shard K of N with 1 ≤ K ≤ N");
    }
    Ok(ShardFolder { dir: dir.to_path_buf(), file, report, schedule, shard })
}

/// Every shard of one schedule, each once.
fn check_complete_set(shards: &[ShardFolder]) -> Result<()> {
    let first = &shards[0];
    let mut by_index: BTreeMap<u32, &str> = BTreeMap::new();
    for s in shards {
        if s.schedule != first.schedule {
            bail!(
                "{}: schedule.identity: a shard of another plan, other scenes or other options than {} ({} ≠ {})",
                s.file,
                first.file,
                s.schedule.identity,
                first.schedule.identity
            );
        }
        if s.shard.count != first.shard.count {
            bail!(
                "{}: shard.count: shard {} of {}, but {} is of {}",
                s.file,
                s.shard,
                s.shard.count,
                first.file,
                first.shard.count
            );
        }
        if let Some(other) = by_index.insert(s.shard.index, &s.file) {
            bail!("{}: shard: shard {} given twice (also {other})", s.file, s.shard);
        }
    }
    let count = first.shard.count;
    if let Some(missing) = (1..=count).find(|k| !by_index.contains_key(k)) {
        let given: Vec<String> = by_index.iter().map(|(k, f)| format!("{k}/{count} in {f}")).collect();
        bail!("shard: shard {missing}/{count} is missing (given: {})", given.join(", "));
    }
    Ok(())
}

/// Every run of a shard is in one of its own views, and each of its views has all of its runs.
fn check_runs(s: &ShardFolder) -> Result<()> {
    let positions: HashMap<&ViewName, usize> =
        s.schedule.views.iter().enumerate().map(|(i, v)| (v, i)).collect();
    let mut runs_of_view = vec![0usize; s.schedule.views.len()];
    for (i, run) in s.report.runs.iter().enumerate() {
        let view = ViewName::of_run(run);
        let Some(&position) = positions.get(&view) else {
            bail!("{}: runs[{i}]: view {view} is not in the schedule (schedule.views)", s.file);
        };
        let owner = Shard::owner_of(position, s.shard.count);
        if owner != s.shard.index {
            bail!(
                "{}: runs[{i}]: view {view} belongs to shard {owner}/{}, not to this shard {}: the shards overlap",
                s.file,
                s.shard.count,
                s.shard
            );
        }
        runs_of_view[position] += 1;
    }
    let per_view = s.schedule.runs_per_map * s.schedule.resolutions.len() * s.schedule.depth_formats.len();
    for (position, view) in s.schedule.views.iter().enumerate() {
        let owned = Shard::owner_of(position, s.shard.count) == s.shard.index;
        if owned && runs_of_view[position] != per_view {
            bail!(
                "{}: runs: view {view} has {} of its {per_view} runs: the shard did not finish (finish it with \
                 `shadowtruth run --resume --shard {}` and the same plan and -o)",
                s.file,
                runs_of_view[position],
                s.shard
            );
        }
    }
    Ok(())
}

/// Every figure that each shard's report says it wrote is there. The figures option is part of
/// the schedule identity that every shard shares, so when one shard holds figures every shard
/// wrote them: each view's reference, each run's technique and error figures, each map's grid
/// (`figure_sink.rs`).
fn check_figures(shards: &[ShardFolder]) -> Result<()> {
    if !shards.iter().any(|s| holds_figures(&s.dir)) {
        return Ok(()); // run with --no-figures
    }
    for s in shards {
        for (i, run) in s.report.runs.iter().enumerate() {
            let Some(format) = DepthFormat::parse(&run.depth_format) else {
                bail!("{}: runs[{i}].depth_format: {:?} is not a depth format", s.file, run.depth_format);
            };
            for name in figures_of_run(run, format) {
                if !s.dir.join("figures").join(&name).is_file() {
                    bail!(
                        "{}: runs[{i}]: figures/{name} is missing from {}: the shard's figures are not whole \
                         (run the shard again)",
                        s.file,
                        s.dir.display()
                    );
                }
            }
        }
    }
    Ok(())
}

/// The figures written for `run` and its view and map.
fn figures_of_run(run: &RunRecord, format: DepthFormat) -> [String; 4] {
    let view = ViewKey::new(&run.scene, &run.camera, &run.light);
    let stem = run_stem(run);
    [
        format!("{}.reference.png", view_stem(view)),
        format!("{stem}.technique.png"),
        format!("{stem}.error.png"),
        grid_file_name(view, run.resolution, format),
    ]
}

/// Whether `dir/figures` holds a figure.
fn holds_figures(dir: &Path) -> bool {
    std::fs::read_dir(dir.join("figures"))
        .is_ok_and(|entries| entries.flatten().any(|e| e.path().extension().is_some_and(|x| x == "png")))
}

/// The first given shard's header, every shard's scenes (each scene once) and runs, in schedule order.
fn merged_report(shards: &[ShardFolder]) -> Report {
    let mut report = shards[0].report.clone();
    report.shard = None;
    report.scenes.clear();
    report.runs.clear();
    for s in shards {
        for scene in &s.report.scenes {
            if !report.scenes.iter().any(|kept| kept.name == scene.name) {
                report.scenes.push(scene.clone());
            }
        }
        report.runs.extend(s.report.runs.iter().cloned());
    }
    put_in_schedule_order(&mut report);
    report
}

/// Copies the shard's figures (PNG) into `out/figures/`, each written atomically.
/// The largest figure copied: a figure, or a run's animation over its frames, is a compressed
/// indexed PNG; a gigabyte is sixteen frames of the largest camera stored raw.
const MAX_FIGURE_BYTES: u64 = 1 << 30;

fn copy_figures(dir: &Path, out: &Path) -> Result<()> {
    let from = dir.join("figures");
    let entries = match std::fs::read_dir(&from) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        entries => entries.with_context(|| format!("reading {}", from.display()))?,
    };
    let to = out.join("figures");
    std::fs::create_dir_all(&to).with_context(|| format!("creating {}", to.display()))?;
    for entry in entries {
        let entry = entry.with_context(|| format!("reading {}", from.display()))?;
        let path = entry.path();
        // A shard's own figures only: regular files, never followed links, of a figure's size.
        let is_file = entry.file_type().is_ok_and(|t| t.is_file());
        if is_file && path.extension().is_some_and(|x| x == "png") {
            let bytes =
                shadowtruth::input_file::read_named(&path, MAX_FIGURE_BYTES).map_err(anyhow::Error::msg)?;
            let target = to.join(path.file_name().expect("a file has a name"));
            write_atomic(&target, &bytes).with_context(|| format!("writing {}", target.display()))?;
        }
    }
    Ok(())
}

fn same_folder(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}
