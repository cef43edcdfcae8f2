//! `shadowtruth run`: a plan (the default one, or a plan file, with the options' overrides) run
//! into a report folder, whole, as one shard, or resuming an interrupted run.

use super::args::set_threads;
use super::plan_report::finish_plan_report;
use super::progress::Progress;
use super::scene_paths::expand_scenes;
use super::table::TableLayout;
use crate::option_values::threads_parser;
use crate::plan::{DEFAULT_MAX_RUNS, MAX_FRAMES, MAX_REPEATS, Plan, Portion, read_plan};
use crate::sinks::ReportWriter;
use anyhow::{Context, Result};
use clap::Args;
use shadowtruth::raster::MAX_SHADOW_MAP_RESOLUTION;
use std::path::PathBuf;

#[derive(Args)]
pub(super) struct RunArgs {
    /// Scene files (shadowtruth/scene/v1, or glTF .gltf/.glb as whole scenes) or folders of
    /// scene files (their *.json; default: scenes/).
    scenes: Vec<PathBuf>,
    /// A plan file (shadowtruth/plan/v1); its scenes are used when no scene is given.
    #[arg(long)]
    plan: Option<PathBuf>,
    /// Output folder for report.json.
    #[arg(short, long, default_value = "reports/latest")]
    out: PathBuf,
    /// Reference cache folder; masks whose inputs changed are traced again and stored.
    #[arg(long, default_value = "references")]
    references: PathBuf,
    /// Trace every reference instead of reading or writing the cache.
    #[arg(long)]
    no_cache: bool,
    #[arg(long, value_delimiter = ',', value_parser = clap::value_parser!(u32).range(1..=MAX_SHADOW_MAP_RESOLUTION as i64),
          help = format!("Override the plan's shadow-map resolutions, e.g. --resolutions 512,1024 \
                          (1 to {MAX_SHADOW_MAP_RESOLUTION})"))]
    resolutions: Option<Vec<u32>>,
    /// Refuse a plan that expands to more runs than this, before anything is built.
    #[arg(long, default_value_t = DEFAULT_MAX_RUNS, value_parser = clap::value_parser!(u64).range(1..))]
    max_runs: u64,
    /// Timings are medians of this many layer builds and shading passes (default: the plan's, 3).
    #[arg(long, value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..=MAX_REPEATS as u64))]
    repeats: Option<usize>,
    /// Evaluate this many frames spread over each view's camera and light paths (default: the
    /// plan's, 1): every frame traced and scored, then per run the mean and worst frame's
    /// error, the flicker rate, an animated error map and a flicker heat map (docs/temporal.md).
    #[arg(long, value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..=MAX_FRAMES as u64))]
    frames: Option<usize>,
    /// Worker threads, 1 to 1024 (default: all cores).
    #[arg(long, value_parser = threads_parser())]
    threads: Option<usize>,
    /// No progress bar and no table.
    #[arg(short, long)]
    quiet: bool,
    /// The tables printed at the end: one per scene, one per folder of scene files, or one over
    /// the whole suite; each followed by the best setting of each technique and the Pareto set.
    #[arg(long, value_enum, default_value_t = TableLayout::PerScene)]
    table: TableLayout,
    /// Print how long each stage took (loading, BVH build, G-buffer, references, each group's
    /// layers and shading) to stderr, as it ends.
    #[arg(long)]
    timing: bool,
    /// Skip the PNG figures (the report, CSV, plots and page are still written).
    #[arg(long)]
    no_figures: bool,
    /// Also write every run's error map enlarged 4× over this region of the camera image,
    /// given as x,y,width,height in pixels (the papers' enlarged panels).
    #[arg(long, value_name = "X,Y,W,H", value_parser = parse_zoom)]
    zoom: Option<[u32; 4]>,
    /// Draw the shadow maps and shade the techniques on a Vulkan GPU (`gpu`: none, constant,
    /// slope_scaled, normal_offset and pcf with a box or bilinear kernel; f32 maps) instead of
    /// the CPU (default: the plan's, cpu). Without a GPU, Mesa's lavapipe
    /// (`apt-get install mesa-vulkan-drivers libvulkan1`) is one.
    #[arg(long, value_enum)]
    pipeline: Option<crate::plan::Pipeline>,
    /// Run only shard K of N (1 ≤ K ≤ N): the plan's (scene, camera, light) views are dealt out
    /// round-robin in schedule order (view i, from 0, to shard i mod N + 1), so that what a view
    /// shares (G-buffer, references, shadow maps) is built in one shard. OUT_DIR is a report
    /// folder of its own, with the shard and the plan's identity in report.json; `shadowtruth
    /// merge` joins the N folders. A shard without views still writes its folder.
    #[arg(long, value_name = "K/N", value_parser = crate::plan::Shard::parse)]
    shard: Option<crate::plan::Shard>,
    /// Finish an interrupted run in OUT_DIR: the runs its report.json already holds are kept
    /// (a map — view, resolution, depth format — whose runs or grid figure are incomplete is run
    /// again whole) and only the rest are run; the result equals a fresh run apart from timings.
    /// The folder must hold a run of the same plan, scenes and options (and the same --shard);
    /// without a report.json the run starts afresh.
    #[arg(long)]
    resume: bool,
}

pub(super) fn run(a: RunArgs) -> Result<u8> {
    set_threads(a.threads)?;
    let mut plan = match &a.plan {
        Some(p) => read_plan(p, a.max_runs)?,
        None => Plan::default_for(Vec::new()),
    };
    plan.max_runs = a.max_runs;
    if !a.scenes.is_empty() {
        plan.scenes = a.scenes.clone();
    } else if plan.scenes.is_empty() {
        plan.scenes = vec![PathBuf::from("scenes")];
    }
    plan.scenes = expand_scenes(&plan.scenes)?;
    if let Some(r) = &a.resolutions {
        plan.resolutions = r.clone();
    }
    if let Some(p) = a.pipeline {
        plan.pipeline = p;
    }
    plan.figures = !a.no_figures;
    if let Some(zoom) = a.zoom {
        plan.zoom = Some(zoom);
    }
    if let Some(n) = a.repeats {
        plan.repeats = n;
    }
    if let Some(n) = a.frames {
        plan.frames = n;
    }
    let cache = (!a.no_cache).then(|| shadowtruth::trace::ReferenceCache::new(&a.references));
    let (writer, portion) = open_run_folder(&a, &plan)?;
    let progress = Progress::timed(a.quiet, a.timing);
    finish_plan_report(&plan, writer, &portion, cache.as_ref(), (!a.quiet).then_some(a.table), progress)?;
    Ok(0)
}

/// Opens `run`'s report folder: afresh, or with `--resume` the interrupted run there, whose
/// finished maps the schedule then skips.
fn open_run_folder(a: &RunArgs, plan: &Plan) -> Result<(ReportWriter, Portion)> {
    let shard = a.shard.map(|s| s.record());
    let resumed = if a.resume { crate::shards::open_resumed(&a.out, plan.figures, shard)? } else { None };
    let mut portion = Portion { shard: a.shard, ..Portion::default() };
    let mut writer = match resumed {
        Some(r) => {
            if !a.quiet {
                println!(
                    "resuming {}: {} finished runs kept, {} runs of unfinished maps run again",
                    a.out.display(),
                    r.report.runs.len(),
                    r.dropped_runs
                );
            }
            portion.done = r.done;
            ReportWriter::resume(&a.out, r.report)
        }
        None => ReportWriter::create(&a.out),
    }
    .with_context(|| format!("opening {}", a.out.display()))?;
    writer.track_schedule(shard);
    Ok((writer, portion))
}

/// `--zoom X,Y,W,H`: a region of the camera image, in pixels, with a non-zero width and height.
fn parse_zoom(text: &str) -> Result<[u32; 4], String> {
    let numbers: Result<Vec<u32>, _> = text.split(',').map(|n| n.trim().parse::<u32>()).collect();
    match numbers.as_deref() {
        Ok(&[x, y, w, h]) if w > 0 && h > 0 => Ok([x, y, w, h]),
        _ => Err("expected x,y,width,height in pixels with a non-zero width and height".into()),
    }
}
