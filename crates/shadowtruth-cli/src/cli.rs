//! The `shadowtruth` command: clap definitions and the glue from arguments to the crate's
//! modules; exit codes 0 success, 1 a gate failed, 2 a usage or input error.

use crate::plan::{
    DEFAULT_AREA_LIGHT_GRID, DEFAULT_COVERAGE_GRID, DEFAULT_MAX_RUNS, Event, MAX_FRAMES, MAX_REFERENCE_GRID,
    MAX_REPEATS, Plan, PlanError, Portion, Sink, execute_portion, read_plan,
};
use crate::report::{
    FigureSink, ReportWriter, load_report, write_mask_png, write_report_outputs, write_soft_exr,
    write_world_obj,
};
use anyhow::{Context, Result, bail};
use clap::{Args, Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use shadowtruth::atomic_file::write_atomic;
use shadowtruth::metrics::{Stopwatch, median_ms};
use shadowtruth::raster::MAX_SHADOW_MAP_RESOLUTION;
use shadowtruth::scene::{Scene, load_scene};
use shadowtruth::trace::{
    GBuffer, SceneBvh, SoftReference, trace_area_light_reference, trace_coverage_reference,
    trace_hard_reference, validate_area_light,
};
use shadowtruth::verify::{Adjudicator, PixelSelection, ViewVerification, verify_view};
use std::path::{Path, PathBuf};
use std::time::Instant;

mod score;
mod table;
use table::TableLayout;
mod trace_timing;
mod tune;

/// shadowtruth measures how wrong shadow maps are: an exact ray-traced reference decides, pixel
/// by pixel, what is lit; every shadow-map technique is scored against it (false shadow: acne,
/// self-shadowing; false lit: leaks, peter-panning) per resolution and bias setting.
#[derive(Parser)]
#[command(name = "shadowtruth", version, about, long_about)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run techniques over scenes and write OUT_DIR/report.json.
    ///
    /// With no arguments: every scene of `scenes/` with the default plan (plans/default.json:
    /// every technique at a few settings; shadow maps 512² to 4096² in f32 depth).
    Run(RunArgs),
    /// Write the exact hard shadow mask of one camera and light as a PNG, or a soft reference
    /// (pixel coverage, area light) as an EXR.
    ///
    /// Hard mask grey levels: 255 lit, 0 shadowed, 128 background, 64 facing away from the
    /// light, 192 outside the light. Soft references: channels V (visibility in [0, 1], 0 where
    /// not evaluated) and E (its standard error), f32, row 0 at the top.
    Reference(ReferenceArgs),
    /// Check the hard reference against exact predicates: the same visibility decided exactly
    /// on the f32 inputs, independent of the tracer (docs/reference.md).
    ///
    /// Checks every camera with every light unless --camera / --light name one. Prints, per
    /// view, the agreement with the exact answer, the disagreements at and away from shadow
    /// boundaries, and the worst cases with their pixel and triangles. Exit 1 when a
    /// disagreement lies outside the documented error band.
    Verify(VerifyArgs),
    /// Write the scene's world-space triangles as OBJ (one `o` group per object), with
    /// coordinates that read back as the same f32 values.
    ExportObj(ExportObjArgs),
    /// Check a report against rules: exit 0 when every rule holds, 1 on violations, 2 on bad input.
    ///
    /// Rules (TOML, `[[rule]]` tables) select runs by glob patterns and bound a metric absolutely
    /// (`max`) and/or against a baseline report (`max_increase`, `max_increase_ratio`). With
    /// --baseline every baseline run must pair with a run of the report (same view, resolution,
    /// depth format, reference and technique parameters); one that does not is a violation.
    Gate(GateArgs),
    /// Write one depth layer of a light as a one-channel f32 EXR, with a JSON sidecar holding
    /// clip_from_world and the near and far planes, to check the rasterizer against another.
    DepthMap(DepthMapArgs),
    /// Score another renderer's shadows: its visibility buffer of one view (and optionally its
    /// camera depth) against the exact reference, into a report folder like `run`'s.
    ///
    /// The buffer is one technique, `external`, with the same metrics, attribution (at
    /// --resolution), figures, CSV, plots and page as the built-in ones. Pixels where the
    /// renderer shows another surface (background where the reference has a surface, or a depth
    /// beyond the tolerance) are counted as surface_mismatch and left out of the rates. In a plan
    /// the same is a technique entry {"technique": "external", "name": ..., "visibility":
    /// "renders/{scene}.{camera}.{light}.exr"}.
    ///
    /// With --shadow-map and --technique instead of --visibility: the renderer's shadow map (as
    /// `depth-map` writes it) read by a built-in technique, to tell a wrong map from a wrong test.
    Score(score::ScoreArgs),
    /// Find the setting of one technique to ship: the values of one to three of its parameters
    /// that minimise an objective (total error by default) per scene and for the whole suite,
    /// each with its safe range (where the objective stays within 10 % of the optimum).
    ///
    /// One parameter is searched by a log grid and golden-section refinement, two or three by a
    /// coarse grid and coordinate refinement. The views are traced and the maps set up once;
    /// each evaluation is one shading pass per view and resolution. OUT gets tune.json
    /// (shadowtruth/tune/v1), plots/tune_<param>.png, the tuned settings run as a report
    /// (report.json, figures, page) and tune-gate.toml, gate rules that lock the suite setting's
    /// error on every view. docs/tune.md explains the search.
    Tune(tune::TuneArgs),
    /// Re-render report.csv, the plots and index.html of a report folder from its report.json,
    /// without running anything.
    Report(ReportArgs),
    /// Join the report folders of `run --shard K/N` (K = 1..N, any order) into one report
    /// folder, as the whole run would have written it apart from timings.
    ///
    /// OUT gets report.json (the runs in the whole run's order), the shards' figures, and
    /// report.csv, plots and index.html rendered from the merged report. Refused, naming the
    /// folder: a folder that is no shard, shards of different plans, scenes or options, a
    /// missing or repeated shard, a run in a view of another shard, an unfinished shard.
    /// docs/cluster.md runs shards as a Slurm job array or a CI matrix.
    Merge(MergeArgs),
    /// Reproduce the papers' results and judge each claim: Ehm et al.'s Figure 12 on the island
    /// (scenes/papers/island.json), Fig. 4 and Table 1 and Pagot et al.'s Table 1 and Fig. 6 on
    /// scenes/papers/casters.json, Weiskopf & Ertl's Fig. 5 on scenes/papers/l_above.json.
    ///
    /// Writes the usual report (the papers' set-ups) into OUT_DIR, plus claims.json (per claim:
    /// id, paper, statement, set-up, rule, our numbers, verdict holds / partly / does_not_hold,
    /// and the same rule over other set-ups: sensitivity, sensitivity_summary) and claims.html.
    Papers(PapersArgs),
    /// Generate the island of Ehm et al. (WSCG 2015, Figure 12) from a seed: DIR/island.json
    /// and DIR/meshes/island_terrain.obj.
    ///
    /// Noisy terrain rising from a sea plane, thin-trunked trees, a spot light `sun_spot`,
    /// a `front` camera on the lit side (the featured tree's trunk `tree00_trunk` in view) and
    /// a `back` camera where the light grazes the slopes. The same seed gives the same bytes;
    /// the default seed gives the committed scenes/papers/island.json.
    Island(IslandArgs),
    /// Write everything an engine needs to render the same pixels under the same light into
    /// DIR: view.json, the G-buffer as EXRs and the scene as glTF binary.
    ///
    /// view.json (format shadowtruth/view/v1): the camera's view and projection matrices and
    /// the light's shadow-map view (the CPU rasterizer's, at --resolution) in OpenGL, Vulkan and
    /// D3D form, each row-major and column-major, with the image size, near/far, the pixel-centre
    /// convention and the light's parameters. position.exr and normal.exr (f32 R, G, B = x, y,
    /// z) and ids.exr (u32 triangle, object, class: 0 background, 1 facing away, 2 outside the
    /// light, 3 evaluated), row 0 at the top. scene.glb: one mesh per object in world space,
    /// every camera and every light (KHR_lights_punctual).
    ViewExport(ViewExportArgs),
    /// Generate a procedural scene of a given size into DIR: DIR/scene.json and one mesh file
    /// per object, the same bytes for the same arguments.
    ///
    /// `city`: a gentle terrain and closed buildings of varied heights (low houses to towers),
    /// one per lot of a square grid, their walls tessellated to reach the size. `forest`: a
    /// hilly terrain and closed trees (trunk and ellipsoid crown) on a jittered grid. About 40 %
    /// of the triangles are terrain. The count is met within 2 % from 20K triangles up. Each
    /// scene has a camera `main` over the ground from one corner, a low directional `sun` and a
    /// spot light `lamp` above the centre, both casting long shadows into the view.
    Generate(GenerateArgs),
}

#[derive(Args)]
struct GenerateArgs {
    /// city or forest.
    #[arg(value_enum)]
    kind: crate::generate::SceneKind,
    /// Triangles to generate: a count such as 500000, 250K or 10M (1000 to 16.7M; up to 2147M
    /// with --instanced).
    #[arg(long, value_parser = crate::generate::parse_triangle_count)]
    triangles: u64,
    /// Seed of the terrain and of the casters' placement and sizes.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// The camera's image width and height in pixels.
    #[arg(long, value_delimiter = ',', value_name = "W,H", default_value = "1920,1080",
          value_parser = clap::value_parser!(u32).range(1..=shadowtruth::scene::MAX_IMAGE_SIDE as i64))]
    image: Vec<u32>,
    /// Output folder (created if missing); files of the same names in it are replaced.
    #[arg(short, long, value_name = "DIR")]
    out: PathBuf,
    /// forest only: one finely tessellated tree placed at every tree by `instances`, stored
    /// once and traced through a two-level BVH (memory of one tree, however many are placed).
    #[arg(long)]
    instanced: bool,
    /// Worker threads for writing the meshes (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
}

#[derive(Args)]
struct PapersArgs {
    /// Output folder.
    #[arg(short, long, default_value = "reports/papers")]
    out: PathBuf,
    /// Folder holding papers/island.json, papers/casters.json and papers/l_above.json.
    #[arg(long, default_value = "scenes")]
    scenes: PathBuf,
    /// The papers' set-ups, but only one other set-up per claim in the sensitivity grid (for
    /// tests).
    #[arg(long)]
    quick: bool,
    /// Reference cache folder.
    #[arg(long, default_value = "references")]
    references: PathBuf,
    /// Trace every reference instead of reading or writing the cache.
    #[arg(long)]
    no_cache: bool,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// No progress bar and no table.
    #[arg(short, long)]
    quiet: bool,
}

#[derive(Args)]
struct IslandArgs {
    /// Seed of the terrain noise and the tree placement.
    #[arg(long, default_value_t = crate::papers::ISLAND_SEED)]
    seed: u64,
    /// Output folder (created if missing).
    #[arg(short, long, default_value = "scenes/papers")]
    out: PathBuf,
}

#[derive(Args)]
struct DepthMapArgs {
    /// The scene file, or a glTF file (.gltf, .glb) as a scene.
    scene: PathBuf,
    /// Light name (default: the scene's first light).
    #[arg(long)]
    light: Option<String>,
    /// Shadow-map resolution (texels per side).
    #[arg(long)]
    resolution: u32,
    /// 1: the nearest surface; 2: the second-nearest distinct surface.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u8).range(1..=2))]
    layer: u8,
    /// Depth format: f32, unorm24 or unorm16.
    #[arg(long, default_value = "f32")]
    format: String,
    /// Faces of closed objects left out: none, back or front.
    #[arg(long, default_value = "none")]
    cull: String,
    #[arg(short, long)]
    out: PathBuf,
}

#[derive(Args)]
struct ViewExportArgs {
    /// The scene file (shadowtruth/scene/v1), or a glTF file (.gltf, .glb) as a scene.
    scene: PathBuf,
    /// Camera name (default: the scene's first camera).
    #[arg(long)]
    camera: Option<String>,
    /// Light name (default: the scene's first light).
    #[arg(long)]
    light: Option<String>,
    /// Shadow-map resolution (texels per side) of the light's exported view.
    #[arg(long, default_value_t = 2048,
          value_parser = clap::value_parser!(u32).range(1..=MAX_SHADOW_MAP_RESOLUTION as i64))]
    resolution: u32,
    /// Output folder (created if missing); files of the same names in it are replaced.
    #[arg(short, long, value_name = "DIR")]
    out: PathBuf,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// No progress messages and no list of files.
    #[arg(short, long)]
    quiet: bool,
}

#[derive(Args)]
struct MergeArgs {
    /// The shard folders (each written by `run --shard K/N`).
    #[arg(required = true, value_name = "DIR")]
    dirs: Vec<PathBuf>,
    /// Output folder (created if missing; an earlier report there is replaced).
    #[arg(short, long, value_name = "OUT")]
    out: PathBuf,
    /// No summary line.
    #[arg(short, long)]
    quiet: bool,
}

#[derive(Args)]
struct ReportArgs {
    /// A report folder (holding report.json).
    dir: PathBuf,
}

#[derive(Args)]
struct RunArgs {
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
    /// Worker threads (default: all cores).
    #[arg(long)]
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
    #[arg(long, value_delimiter = ',', value_name = "X,Y,W,H")]
    zoom: Option<Vec<u32>>,
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

/// Which reference `shadowtruth reference` writes.
#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum ReferenceKind {
    /// The hard shadow mask (PNG).
    Hard,
    /// Hard visibility averaged over an N×N sub-pixel grid (EXR: V, E).
    Coverage,
    /// Fraction of N×N light samples unoccluded; needs the light's size (EXR: V, E).
    Area,
}

#[derive(Args)]
struct ReferenceArgs {
    /// The scene file, or a glTF file (.gltf, .glb) as a scene.
    scene: PathBuf,
    /// Camera name (default: the scene's first camera).
    #[arg(long)]
    camera: Option<String>,
    /// Light name (default: the scene's first light).
    #[arg(long)]
    light: Option<String>,
    /// Output: a PNG mask for `hard`, a two-channel f32 EXR (V visibility, E standard error,
    /// row 0 at the top) for `coverage` and `area`.
    #[arg(short, long)]
    out: PathBuf,
    /// hard, coverage (sub-pixel grid) or area (light samples; the light needs
    /// `angular_diameter_deg` or `radius`).
    #[arg(long, value_enum, default_value_t = ReferenceKind::Hard)]
    kind: ReferenceKind,
    #[arg(long, help = format!(
        "N for an N×N grid of samples per pixel (default: {DEFAULT_COVERAGE_GRID} for coverage, \
         {DEFAULT_AREA_LIGHT_GRID} for area; 1 to {MAX_REFERENCE_GRID})"
    ))]
    samples: Option<u32>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Also time the tracer: primary rays per second (prepared before the clock, closest hits
    /// written, as Embree's tool times them), the G-buffer's pixels per second (those hits'
    /// surface points and classes too), and shadow rays per second (the whole hard
    /// reference), each the median of --repeats.
    #[arg(long)]
    timing: bool,
    /// How many times --timing runs each measurement.
    #[arg(long, default_value_t = 5)]
    repeats: usize,
    /// With --timing: the saved `--timing` output of the Embree reference tool on the same view
    /// (`embree-reference mask --timing`); prints our rate over Embree's at this thread count.
    #[arg(long, requires = "timing")]
    embree_timing: Option<PathBuf>,
}

#[derive(Args)]
struct VerifyArgs {
    /// The scene file, or a glTF file (.gltf, .glb) as a scene.
    scene: PathBuf,
    /// Camera name (default: every camera of the scene).
    #[arg(long)]
    camera: Option<String>,
    /// Light name (default: every light of the scene).
    #[arg(long)]
    light: Option<String>,
    /// Pixels to check per view: `all`, or N for about N evaluated pixels spread uniformly plus
    /// every pixel next to a shadow boundary.
    #[arg(long, default_value = "100000", value_parser = parse_pixel_selection)]
    pixels: PixelSelection,
    /// Also write the results as JSON.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
}

fn parse_pixel_selection(text: &str) -> std::result::Result<PixelSelection, String> {
    if text == "all" {
        return Ok(PixelSelection::All);
    }
    match text.parse::<usize>() {
        Ok(n) if n > 0 => Ok(PixelSelection::Sample(n)),
        _ => Err(format!("'{text}' is neither `all` nor a positive number of pixels")),
    }
}

#[derive(Args)]
struct ExportObjArgs {
    /// The scene file, or a glTF file (.gltf, .glb) as a scene.
    scene: PathBuf,
    #[arg(short, long)]
    out: PathBuf,
}

#[derive(Args)]
struct GateArgs {
    /// The report to check: a report.json file or a folder holding one.
    report: PathBuf,
    /// The rules file (TOML).
    #[arg(long)]
    rules: PathBuf,
    /// The report to compare with (a report.json file or its folder): every one of its runs must
    /// pair with a run of the report, and regression bounds compare with it.
    #[arg(long)]
    baseline: Option<PathBuf>,
    /// Also write JUnit XML: one testcase per (rule, run) checked and per baseline run missing
    /// from the report.
    #[arg(long)]
    junit: Option<PathBuf>,
    /// Also write a Markdown table (rule, run, value, limit, status; missing baseline runs) and
    /// the new runs, for CI job summaries.
    #[arg(long)]
    summary: Option<PathBuf>,
    /// Let baseline runs that the report lacks pass with a warning (for a change that removes or
    /// renames runs on purpose); without it each one is a violation.
    #[arg(long, requires = "baseline")]
    allow_missing: bool,
}

/// Parses the arguments and runs the command: 0 success, 1 a gate failed, 2 a usage or input
/// error.
pub fn main() -> std::process::ExitCode {
    use clap::{CommandFactory, FromArgMatches};
    use std::process::ExitCode;
    let parsed = Cli::command().try_get_matches().and_then(|m| Ok((Cli::from_arg_matches(&m)?, m)));
    let (args, matches) = match parsed {
        Ok(parsed) => parsed,
        Err(e) => {
            let code = if e.use_stderr() { 2 } else { 0 };
            let _ = e.print();
            return ExitCode::from(code);
        }
    };
    let result = lock_output_folder(&matches).and_then(|()| run(args));
    shadowtruth::output_lock::release_output_folders();
    match result {
        Ok(code) => ExitCode::from(code),
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}

/// The commands that write into a folder, and the argument that names it: each locks its folder
/// before it reads its inputs (`output_lock.rs`), so that a second process writing there is
/// refused at once.
const FOLDER_WRITING_COMMANDS: [(&str, &str); 9] = [
    ("run", "out"),
    ("papers", "out"),
    ("tune", "out"),
    ("score", "out"),
    ("merge", "out"),
    ("island", "out"),
    ("view-export", "out"),
    ("generate", "out"),
    ("report", "dir"),
];

/// Locks the output folder of the command in `matches`, if it writes one.
fn lock_output_folder(matches: &clap::ArgMatches) -> Result<()> {
    let Some((command, sub)) = matches.subcommand() else { return Ok(()) };
    let Some((_, arg)) = FOLDER_WRITING_COMMANDS.iter().find(|(name, _)| *name == command) else {
        return Ok(());
    };
    let Some(path) = sub.try_get_one::<PathBuf>(arg).ok().flatten() else { return Ok(()) };
    // `report` takes a folder or the report.json in it.
    let dir = match (command == "report" && path.is_file()).then(|| path.parent()).flatten() {
        Some(parent) if parent.as_os_str().is_empty() => Path::new("."),
        Some(parent) => parent,
        None => path.as_path(),
    };
    match shadowtruth::output_lock::lock_output_folder(dir) {
        Err(held) if held.kind() == std::io::ErrorKind::WouldBlock => Err(held.into()),
        // Any other failure (the path is a file, or under one) is the command's to report,
        // naming its option, when it writes there.
        _ => Ok(()),
    }
}

fn run(cli: Cli) -> Result<u8> {
    match cli.command {
        Command::Run(a) => run_plan(a),
        Command::Reference(a) => reference(a),
        Command::Verify(a) => verify(a),
        Command::DepthMap(a) => depth_map(a),
        Command::Score(a) => score::score(a),
        Command::Tune(a) => tune::run_tune(a),
        Command::Merge(a) => {
            let report = crate::report::merge_shards(&a.dirs, &a.out)?;
            if !a.quiet {
                println!(
                    "merged {} shards: {} runs; report: {} (open {})",
                    a.dirs.len(),
                    report.runs.len(),
                    a.out.join("report.json").display(),
                    a.out.join("index.html").display()
                );
            }
            Ok(0)
        }
        Command::Report(a) => {
            let (report, file) = load_report(&a.dir)?;
            let dir = file.parent().unwrap_or(Path::new(".")).to_path_buf();
            crate::report::remove_stray_report_temp_files(&dir)
                .with_context(|| format!("cleaning {}", dir.display()))?;
            write_report_outputs(&dir, &report).with_context(|| format!("writing into {}", dir.display()))?;
            println!("{}", dir.join("index.html").display());
            Ok(0)
        }
        Command::ExportObj(a) => {
            let scene = load_scene(&a.scene)?;
            write_world_obj(&scene, &a.out).with_context(|| format!("writing {}", a.out.display()))?;
            Ok(0)
        }
        Command::Gate(a) => gate(a),
        Command::Papers(a) => papers(a),
        Command::ViewExport(a) => view_export(a),
        Command::Generate(a) => generate(a),
        Command::Island(a) => {
            crate::papers::write_island(&a.out, a.seed)
                .with_context(|| format!("writing the island into {}", a.out.display()))?;
            println!("{}", a.out.join(crate::papers::ISLAND_SCENE_FILE).display());
            Ok(0)
        }
    }
}

/// Reads and checks everything first (any bad input exits 2 before anything is written),
/// evaluates, writes the optional JUnit and Markdown files, prints the violations, the missing and
/// new runs and the summary line.
fn gate(a: GateArgs) -> Result<u8> {
    use crate::report::{CheckedReport, GateOptions};
    let rules = crate::report::load_rules(&a.rules)?;
    let report = CheckedReport::load(&a.report)?;
    let baseline = a.baseline.as_deref().map(CheckedReport::load).transpose()?;
    let options = GateOptions { allow_missing: a.allow_missing };
    let outcome = crate::report::evaluate(&report, baseline.as_ref(), &rules, options)?;
    if let Some(path) = &a.junit {
        write_atomic(path, crate::report::junit_xml(&outcome).as_bytes())
            .with_context(|| format!("writing {}", path.display()))?;
    }
    if let Some(path) = &a.summary {
        write_atomic(path, outcome.markdown().as_bytes())
            .with_context(|| format!("writing {}", path.display()))?;
    }
    print!("{}", outcome.text());
    Ok(if outcome.passed() { 0 } else { 1 })
}

fn set_threads(threads: Option<usize>) -> Result<()> {
    if let Some(n) = threads {
        if n == 0 {
            bail!("--threads must be at least 1");
        }
        rayon::ThreadPoolBuilder::new().num_threads(n).build_global().context("setting up worker threads")?;
    }
    Ok(())
}

/// Scene files named on the command line: files as given (a glTF file is a scene of its own),
/// folders expanded to their `*.json` files in name order (a glTF in a folder is usually a
/// scene file's mesh, so it is not a scene there).
fn expand_scenes(paths: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for p in paths {
        if p.is_dir() {
            let mut found: Vec<PathBuf> = std::fs::read_dir(p)
                .with_context(|| format!("reading folder {}", p.display()))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|f| f.is_file() && f.extension().is_some_and(|x| x == "json"))
                .collect();
            found.sort();
            if found.is_empty() {
                bail!("{}: no scene files (*.json) in this folder", p.display());
            }
            out.extend(found);
        } else if p.is_file() {
            out.push(p.clone());
        } else {
            bail!("{}: no such scene file or folder", p.display());
        }
    }
    Ok(out)
}

/// The runs progress bar (hidden when `quiet`), as a sink of the plan's events: its length grows
/// with every plan (the papers suite runs several). With `timing` it also prints each stage's
/// wall-clock time.
struct Progress(ProgressBar, Option<StageClock>);

/// The stage under way and when it (or, before the first, the run) started.
struct StageClock {
    stage: String,
    started: Instant,
}

impl StageClock {
    fn new() -> Self {
        StageClock { stage: "loading and checking the scenes".into(), started: Instant::now() }
    }

    /// Prints the stage that ends and starts `next`.
    fn next(&mut self, bar: &ProgressBar, next: &str) {
        bar.suspend(|| eprintln!("{:>9.3} s  {}", self.started.elapsed().as_secs_f64(), self.stage));
        *self = StageClock { stage: next.to_string(), started: Instant::now() };
    }
}

impl Progress {
    fn timed(quiet: bool, timing: bool) -> Self {
        let mut progress = Progress::new(quiet);
        progress.1 = timing.then(StageClock::new);
        progress
    }

    /// Prints the last stage's time, if timed.
    fn finish_timing(&mut self, next: &str) {
        if let Some(clock) = &mut self.1 {
            clock.next(&self.0, next);
        }
    }

    fn new(quiet: bool) -> Self {
        let bar = if quiet { ProgressBar::hidden() } else { ProgressBar::new(0) };
        bar.set_style(
            ProgressStyle::with_template("{elapsed_precise} [{bar:30}] {pos}/{len} runs  {msg}")
                .expect("valid template")
                .progress_chars("=> "),
        );
        Progress(bar, None)
    }
}

impl Sink for Progress {
    fn on_event(&mut self, event: &Event) -> Result<(), PlanError> {
        match event {
            Event::Planned { runs, .. } => self.0.inc_length(*runs as u64),
            Event::Stage(s) => {
                self.finish_timing(s);
                self.0.set_message(s.to_string())
            }
            Event::RunDone { .. } => self.0.inc(1),
            _ => {}
        }
        Ok(())
    }
}

/// The sinks of `run` and `papers`: report.json, figures unless `figures` is off, progress.
fn sinks<'a>(
    writer: &'a mut ReportWriter,
    figures: Option<&'a mut FigureSink>,
    progress: &'a mut Progress,
) -> Vec<&'a mut dyn Sink> {
    let mut sinks: Vec<&mut dyn Sink> = vec![writer];
    if let Some(f) = figures {
        sinks.push(f);
    }
    sinks.push(progress);
    sinks
}

fn papers(a: PapersArgs) -> Result<u8> {
    set_threads(a.threads)?;
    let cache = (!a.no_cache).then(|| shadowtruth::trace::ReferenceCache::new(&a.references));
    let mut writer = ReportWriter::create(&a.out).with_context(|| format!("opening {}", a.out.display()))?;
    let started = Instant::now();
    let mut progress = Progress::new(a.quiet);
    let mut figures = FigureSink::new(&a.out.join("figures"), None);
    let options = crate::papers::PapersOptions { quick: a.quick };
    let claims = crate::papers::run_papers(
        &a.scenes,
        &a.out,
        cache.as_ref(),
        &mut sinks(&mut writer, Some(&mut figures), &mut progress),
        options,
    )?;
    let bar = progress.0;
    bar.set_message("figures, plots and pages");
    write_report_outputs(&a.out, writer.report())
        .with_context(|| format!("writing into {}", a.out.display()))?;
    let document = serde_json::json!({ "format": "shadowtruth/claims/v1", "claims": claims });
    let mut text = serde_json::to_string_pretty(&document)?;
    text.push('\n');
    shadowtruth::atomic_file::write_atomic(&a.out.join("claims.json"), text.as_bytes())
        .with_context(|| format!("writing {}", a.out.join("claims.json").display()))?;
    shadowtruth::atomic_file::write_atomic(
        &a.out.join("claims.html"),
        crate::papers::claims_html(&claims).as_bytes(),
    )
    .with_context(|| format!("writing {}", a.out.join("claims.html").display()))?;
    bar.finish_and_clear();
    if !a.quiet {
        for c in &claims {
            println!("{:<28} {:<14} {}", c.id, c.verdict.name(), c.sensitivity_summary);
        }
        println!(
            "{} claims from {} runs in {:.1} s; open {}",
            claims.len(),
            writer.report().runs.len(),
            started.elapsed().as_secs_f64(),
            a.out.join("claims.html").display()
        );
    }
    Ok(0)
}

fn run_plan(a: RunArgs) -> Result<u8> {
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
    if let Some(z) = &a.zoom {
        if z.len() != 4 || z[2] == 0 || z[3] == 0 {
            bail!("--zoom takes x,y,width,height with a non-zero width and height");
        }
        plan.zoom = Some([z[0], z[1], z[2], z[3]]);
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
    let resumed = if a.resume { crate::report::open_resumed(&a.out, plan.figures, shard)? } else { None };
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

/// Runs `plan` into the report folder `out` (report.json, figures unless the plan has none, then
/// the CSV, plots and page) and prints the tables and summary unless `quiet`.
fn write_plan_report(
    plan: &Plan,
    out: &Path,
    cache: Option<&shadowtruth::trace::ReferenceCache>,
    quiet: bool,
    timing: bool,
) -> Result<()> {
    let writer = ReportWriter::create(out).with_context(|| format!("opening {}", out.display()))?;
    let tables = (!quiet).then_some(TableLayout::PerScene);
    finish_plan_report(plan, writer, &Portion::default(), cache, tables, Progress::timed(quiet, timing))
}

/// Runs the `portion` of `plan` through `writer`, the figures and `progress`, then writes the
/// CSV, plots and page of the whole report, and prints the tables (in `tables`' layout) and
/// summary unless `tables` is None.
fn finish_plan_report(
    plan: &Plan,
    mut writer: ReportWriter,
    portion: &Portion,
    cache: Option<&shadowtruth::trace::ReferenceCache>,
    tables: Option<TableLayout>,
    mut progress: Progress,
) -> Result<()> {
    let out = writer.dir().to_path_buf();
    let runs_before = writer.report().runs.len();
    let started = Instant::now();
    let mut figures = plan.figures.then(|| FigureSink::new(&out.join("figures"), plan.zoom));
    execute_portion(plan, cache, &mut sinks(&mut writer, figures.as_mut(), &mut progress), portion)?;
    progress.finish_timing("figures, plots and index.html");
    let figures_ms = figures.as_ref().map_or(0.0, FigureSink::spent_ms);
    let bar = progress.0;
    let outputs_started = Instant::now();
    bar.set_message("figures, plots and index.html");
    write_report_outputs(&out, writer.report()).with_context(|| format!("writing into {}", out.display()))?;
    bar.finish_and_clear();
    progress.1 = progress.1.take().map(|mut clock| {
        clock.next(&bar, "");
        clock
    });
    // What the figures, plots, CSV and page cost beside the runs themselves.
    let outputs_s = (figures_ms / 1e3) + outputs_started.elapsed().as_secs_f64();
    let total_s = started.elapsed().as_secs_f64();
    let runs_s = total_s - outputs_s;
    if let Some(layout) = tables {
        table::print_tables(writer.report(), layout);
        println!(
            "{} runs in {runs_s:.1} s ({} of them run now), then figures, plots and page in {outputs_s:.1} s \
             ({:.1} % of the runs' time); report: {} (open {})",
            writer.report().runs.len(),
            writer.report().runs.len() - runs_before,
            100.0 * outputs_s / runs_s.max(1e-9),
            writer.path().display(),
            out.join("index.html").display()
        );
    }
    Ok(())
}

/// Error rate (%) per technique setting and resolution, averaged over scenes, cameras and lights.
fn pick<'a, T>(
    items: &'a [T],
    name: Option<&str>,
    get: impl Fn(&T) -> &str,
    what: &str,
    file: &Path,
) -> Result<&'a T> {
    let have = || items.iter().map(&get).collect::<Vec<_>>().join(", ");
    match name {
        Some(n) => items
            .iter()
            .find(|i| get(i) == n)
            .with_context(|| format!("{}: no {what} named '{n}' (have: {})", file.display(), have())),
        None => items.first().with_context(|| format!("{}: the scene has no {what}", file.display())),
    }
}

fn reference(a: ReferenceArgs) -> Result<u8> {
    let grid = match (a.kind, a.samples) {
        (ReferenceKind::Hard, Some(_)) => bail!("--samples applies to --kind coverage and --kind area only"),
        (ReferenceKind::Hard, None) => 1,
        (ReferenceKind::Coverage, n) => n.unwrap_or(DEFAULT_COVERAGE_GRID),
        (ReferenceKind::Area, n) => n.unwrap_or(DEFAULT_AREA_LIGHT_GRID),
    };
    if !(1..=MAX_REFERENCE_GRID).contains(&grid) {
        bail!("--samples {grid} is outside 1..={MAX_REFERENCE_GRID} (N for an N×N grid per pixel)");
    }
    set_threads(a.threads)?;
    // Read before tracing, so that a wrong file fails at once.
    let embree = (a.embree_timing.as_deref())
        .map(|path| trace_timing::read_other_timing(path, rayon::current_num_threads()))
        .transpose()?;
    let scene: Scene = load_scene(&a.scene)?;
    let camera = pick(&scene.cameras, a.camera.as_deref(), |c| &c.name, "camera", &a.scene)?;
    let light = pick(&scene.lights, a.light.as_deref(), |l| &l.name, "light", &a.scene)?;
    if a.kind == ReferenceKind::Area {
        validate_area_light(light, grid).with_context(|| format!("{}: --kind area", a.scene.display()))?;
    }
    let bvh = SceneBvh::build(&scene);
    let gbuffer = GBuffer::trace(&scene, &bvh, camera, light);
    let trace_soft = |g: &GBuffer| -> Result<SoftReference> {
        Ok(match a.kind {
            ReferenceKind::Coverage => trace_coverage_reference(&scene, &bvh, g, camera, light, grid),
            _ => trace_area_light_reference(&scene, &bvh, g, light, grid)?,
        })
    };
    if a.kind == ReferenceKind::Hard {
        let reference = trace_hard_reference(&scene, &bvh, &gbuffer, light);
        write_mask_png(&a.out, gbuffer.width, gbuffer.height, &reference.mask_codes(&gbuffer))
            .with_context(|| format!("writing {}", a.out.display()))?;
    } else {
        write_soft_exr(&a.out, &trace_soft(&gbuffer)?)
            .with_context(|| format!("writing {}", a.out.display()))?;
    }
    if a.timing {
        let ours = trace_timing::time_tracer(&scene, &bvh, camera, light, a.repeats);
        println!("node test: {}", shadowtruth::trace::node_test_name());
        println!("{}", trace_timing::timing_line(&ours, a.repeats));
        if let Some(theirs) = &embree {
            println!("{}", trace_timing::ratio_line(&ours, theirs));
        }
        if a.kind != ReferenceKind::Hard {
            let mut ms = Vec::new();
            for _ in 0..a.repeats.max(1) {
                let sw = Stopwatch::start();
                std::hint::black_box(trace_soft(&gbuffer)?);
                ms.push(sw.ms());
            }
            let samples = gbuffer.evaluated.len() * (grid * grid) as usize;
            let what = match a.kind {
                ReferenceKind::Coverage => {
                    "sub-pixel samples (a primary ray and at most one shadow ray each)"
                }
                _ => "shadow rays",
            };
            println!(
                "shadowtruth {} threads  {} {grid}×{grid}  {:.3} M/s ({samples} {what})   (median of {})",
                rayon::current_num_threads(),
                if a.kind == ReferenceKind::Coverage { "coverage" } else { "area light" },
                samples as f64 / median_ms(&ms) / 1e3,
                ms.len()
            );
        }
    }
    Ok(0)
}

fn verify(a: VerifyArgs) -> Result<u8> {
    set_threads(a.threads)?;
    let scene: Scene = load_scene(&a.scene)?;
    let select = |name: &Option<String>, names: Vec<&str>, what: &str| -> Result<Vec<String>> {
        match name {
            Some(n) if names.contains(&n.as_str()) => Ok(vec![n.clone()]),
            Some(n) => bail!("{}: no {what} named '{n}' (have: {})", a.scene.display(), names.join(", ")),
            None if names.is_empty() => bail!("{}: the scene has no {what}", a.scene.display()),
            None => Ok(names.iter().map(|s| s.to_string()).collect()),
        }
    };
    let cameras = select(&a.camera, scene.cameras.iter().map(|c| c.name.as_str()).collect(), "camera")?;
    let lights = select(&a.light, scene.lights.iter().map(|l| l.name.as_str()).collect(), "light")?;
    let bvh = SceneBvh::build(&scene);
    let adjudicator = Adjudicator::new(&scene);
    let mut views = Vec::new();
    for camera in &cameras {
        for light in &lights {
            let (c, l) = (scene.camera(camera).expect("selected"), scene.light(light).expect("selected"));
            let v = verify_view(&scene, &bvh, &adjudicator, c, l, a.pixels);
            print_verification(&a.scene, &v);
            views.push(v);
        }
    }
    if let Some(path) = &a.json {
        let text = serde_json::to_string_pretty(&serde_json::json!({ "scene": a.scene, "views": views }))?;
        write_atomic(path, text.as_bytes()).with_context(|| format!("writing {}", path.display()))?;
    }
    let failed = views.iter().filter(|v| !v.passed()).count();
    if failed == 0 {
        println!("verify: {} views, no disagreement outside the error band", views.len());
        Ok(0)
    } else {
        println!("verify: {failed} of {} views have disagreements outside the error band", views.len());
        Ok(1)
    }
}

fn print_verification(scene: &Path, v: &ViewVerification) {
    let pct = |n: usize| 100.0 * n as f64 / v.checked.max(1) as f64;
    println!(
        "{}  camera {}  light {}: {} evaluated pixels, {} checked ({} next to a shadow boundary) in {:.1} s",
        scene.display(),
        v.camera,
        v.light,
        v.evaluated,
        v.checked,
        v.checked_at_boundary,
        v.seconds
    );
    println!("  agree with the exact answer   {:>9} ({:.4} %)", v.agree, pct(v.agree));
    println!(
        "  disagree                      {:>9} ({} at a shadow boundary, {} away)",
        v.disagree_at_boundary + v.disagree_away_from_boundary,
        v.disagree_at_boundary,
        v.disagree_away_from_boundary
    );
    println!("    inside the error band       {:>9}", v.disagree_in_band);
    println!("    outside the error band      {:>9}", v.disagree_outside_band);
    println!("  exact answer inside the band  {:>9} ({:.4} %)", v.in_band, pct(v.in_band));
    if v.inconsistent > 0 {
        println!(
            "  ADJUDICATOR INCONSISTENT on {} pixels: the exact test and the band disagree",
            v.inconsistent
        );
    }
    for c in &v.cases {
        let verdict = |shadowed: bool| if shadowed { "shadowed" } else { "lit" };
        println!(
            "    pixel ({}, {}) on triangle {}: traced {}, exact {}{}{}{}",
            c.x,
            c.y,
            c.surface_triangle,
            verdict(c.traced_shadowed),
            verdict(c.exact_shadowed),
            c.triangle.map(|t| format!(", triangle {t}")).unwrap_or_default(),
            if c.outside_band() { "  OUTSIDE THE BAND" } else { "  (inside the band)" },
            if c.at_boundary { ", at a shadow boundary" } else { "" },
        );
    }
}

/// The figures already written under `dir/figures/`: scene grids and references (in name
/// order), and each run's visibility and error figures.
fn depth_map(a: DepthMapArgs) -> Result<u8> {
    use shadowtruth::raster::{
        Culling, DepthFormat, LightView, RasterSettings, rasterize_nearest, rasterize_two_nearest,
    };
    let format = DepthFormat::parse(&a.format)
        .with_context(|| format!("--format: unknown depth format '{}' (f32, unorm24, unorm16)", a.format))?;
    let culling = match a.cull.as_str() {
        "none" => Culling::None,
        "back" => Culling::BackFacesOfClosed,
        "front" => Culling::FrontFacesOfClosed,
        other => bail!("--cull: unknown value '{other}' (none, back, front)"),
    };
    if !(1..=MAX_SHADOW_MAP_RESOLUTION).contains(&a.resolution) {
        bail!("--resolution {} is outside 1..={MAX_SHADOW_MAP_RESOLUTION}", a.resolution);
    }
    let scene = load_scene(&a.scene)?;
    let light = pick(&scene.lights, a.light.as_deref(), |l| &l.name, "light", &a.scene)?;
    let view = LightView::new(light, scene.bounds(), a.resolution);
    let settings = RasterSettings { format, culling, ..RasterSettings::default() };
    let layer = if a.layer == 1 {
        rasterize_nearest(&scene, &view, &settings)
    } else {
        let pairs = rasterize_two_nearest(&scene, &view, &settings);
        shadowtruth::raster::DepthLayer {
            resolution: pairs.resolution,
            depth: pairs.depth.iter().map(|p| p[1]).collect(),
        }
    };
    let description =
        serde_json::json!({ "index": a.layer, "format": format.name(), "cull": a.cull, "light": light.name });
    crate::report::write_depth_map(&a.out, &layer, &view, description)
        .with_context(|| format!("writing {}", a.out.display()))?;
    Ok(0)
}

fn generate(a: GenerateArgs) -> Result<u8> {
    set_threads(a.threads)?;
    let [width_px, height_px] = a.image[..] else {
        bail!("--image takes the width and height: W,H");
    };
    let options = crate::generate::GenerateOptions {
        kind: a.kind,
        triangles: a.triangles,
        seed: a.seed,
        width_px,
        height_px,
        instanced: a.instanced,
    };
    // Checked against the loader's own limits before the folder is touched.
    crate::generate::check_options(&options).map_err(anyhow::Error::msg)?;
    let (path, triangles) = crate::generate::write_generated(&a.out, &options)
        .with_context(|| format!("writing the scene into {}", a.out.display()))?;
    println!("{} ({triangles} triangles)", path.display());
    Ok(0)
}

fn view_export(a: ViewExportArgs) -> Result<u8> {
    set_threads(a.threads)?;
    let scene = load_scene(&a.scene)?;
    let camera = pick(&scene.cameras, a.camera.as_deref(), |c| &c.name, "camera", &a.scene)?;
    let light = pick(&scene.lights, a.light.as_deref(), |l| &l.name, "light", &a.scene)?;
    let bar = if a.quiet { ProgressBar::hidden() } else { ProgressBar::new_spinner() };
    bar.enable_steady_tick(std::time::Duration::from_millis(120));
    let files = crate::view_export::write_view_export(&scene, camera, light, a.resolution, &a.out, |step| {
        bar.set_message(step.to_string())
    })?;
    bar.finish_and_clear();
    if !a.quiet {
        for f in files {
            println!("{}", f.display());
        }
    }
    Ok(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_folder_writing_command_names_its_folder_argument() {
        let cli = <Cli as clap::CommandFactory>::command();
        for (name, arg) in FOLDER_WRITING_COMMANDS {
            let command = cli.find_subcommand(name).unwrap_or_else(|| panic!("no command {name}"));
            assert!(command.get_arguments().any(|a| a.get_id() == arg), "{name} has no argument {arg}");
        }
    }
}
