//! `shadowtruth score`: another renderer's visibility buffer of one view, scored like a technique
//! through the plan's schedule (one `external` technique), into a report folder like `run`'s.

use super::{set_threads, write_plan_report};
use crate::import::{ReadOptions, read_depth, read_visibility};
use crate::plan::{DEFAULT_AREA_LIGHT_GRID, DEFAULT_COVERAGE_GRID, DEFAULT_MAX_RUNS, Plan};
use crate::raster::{DepthFormat, MAX_SHADOW_MAP_RESOLUTION};
use crate::technique::{ExternalParams, TechniqueSpec};
use anyhow::{Result, anyhow};
use clap::Args;
use std::path::PathBuf;

#[derive(Args)]
pub(super) struct ScoreArgs {
    /// The scene the buffer was rendered from.
    scene: PathBuf,
    /// The camera it was rendered with (its size is the buffer's).
    #[arg(long)]
    camera: String,
    /// The light whose shadows it holds.
    #[arg(long)]
    light: String,
    /// The visibility buffer: EXR (f16 or f32) or PNG (8 or 16 bit; grey, or the first channel of
    /// RGB(A)), 1 lit and 0 shadowed, row 0 at the top; NaN or negative where the renderer drew
    /// background.
    #[arg(long)]
    visibility: PathBuf,
    /// The renderer's camera depth (EXR): per pixel the distance from the camera's position to
    /// the surface along the primary ray, in world units; 0 or +inf for background. Pixels whose
    /// surface differs from the reference's are counted as surface_mismatch, not scored.
    #[arg(long)]
    depth: Option<PathBuf>,
    /// Relative depth tolerance: a depth d matches the reference's distance t when
    /// |d − t| ≤ X·t + 1e-4 (world units).
    #[arg(long, value_name = "X", requires = "depth", default_value_t = crate::import::DEFAULT_DEPTH_TOLERANCE)]
    depth_tolerance: f64,
    /// The renderer's name, recorded as the technique's `name`.
    #[arg(long, default_value = "external")]
    name: String,
    /// Row 0 of the files is the bottom row.
    #[arg(long)]
    flip_y: bool,
    /// The EXR channel of the visibility file (needed when it has more than one).
    #[arg(long)]
    channel: Option<String>,
    /// The shadow-map resolution the attribution's texel footprint is taken at (aliasing: a false
    /// pixel within one texel of a reference shadow boundary).
    #[arg(long, default_value_t = 2048,
          value_parser = clap::value_parser!(u32).range(1..=MAX_SHADOW_MAP_RESOLUTION as i64))]
    resolution: u32,
    /// Output folder.
    #[arg(short, long, default_value = "reports/score")]
    out: PathBuf,
    /// Reference cache folder.
    #[arg(long, default_value = "references")]
    references: PathBuf,
    /// Trace the reference instead of reading or writing the cache.
    #[arg(long)]
    no_cache: bool,
    /// Skip the PNG figures.
    #[arg(long)]
    no_figures: bool,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// No progress bar and no table.
    #[arg(short, long)]
    quiet: bool,
}

pub(super) fn score(a: ScoreArgs) -> Result<u8> {
    set_threads(a.threads)?;
    let path = |p: &PathBuf| p.to_string_lossy().into_owned();
    let params = ExternalParams {
        name: a.name.clone(),
        visibility: path(&a.visibility),
        depth: a.depth.as_ref().map(path),
        depth_tolerance: a.depth.is_some().then_some(a.depth_tolerance),
        channel: a.channel.clone(),
        flip_y: a.flip_y,
    };
    let spec = TechniqueSpec::External(params);
    spec.validate().map_err(|e| anyhow!("{e}"))?;
    // The files are checked before the reference is traced: bad input fails at once.
    read_visibility(&a.visibility, &ReadOptions { channel: a.channel.clone(), flip_y: a.flip_y })?;
    if let Some(depth) = &a.depth {
        read_depth(depth, &ReadOptions { channel: None, flip_y: a.flip_y })?;
    }
    if !a.scene.is_file() {
        return Err(anyhow!("{}: no such scene file", a.scene.display()));
    }
    let plan = Plan {
        source: None,
        scenes: vec![a.scene.clone()],
        cameras: Some(vec![a.camera.clone()]),
        lights: Some(vec![a.light.clone()]),
        techniques: vec![spec],
        resolutions: vec![a.resolution],
        depth_formats: vec![DepthFormat::F32],
        repeats: 1,
        figures: !a.no_figures,
        zoom: None,
        coverage_grid: DEFAULT_COVERAGE_GRID,
        area_light_grid: DEFAULT_AREA_LIGHT_GRID,
        max_runs: DEFAULT_MAX_RUNS,
    };
    let cache = (!a.no_cache).then(|| crate::trace::ReferenceCache::new(&a.references));
    write_plan_report(&plan, &a.out, cache.as_ref(), a.quiet)?;
    Ok(0)
}
