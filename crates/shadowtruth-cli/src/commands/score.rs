//! `shadowtruth score`: another renderer's visibility buffer of one view, scored like a technique
//! through the plan's schedule (one `external` technique), into a report folder like `run`'s; or
//! its shadow map, read by a built-in technique in place of the layers rasterized here.

use super::args::set_threads;
use super::plan_report::write_plan_report;
use crate::option_values::threads_parser;
use crate::plan::Plan;
use anyhow::{Result, anyhow};
use clap::Args;
use shadowtruth::import::{ImportedShadowMap, read_shadow_map};
use shadowtruth::metrics::DEFAULT_ATTRIBUTION_RESOLUTION;
use shadowtruth::raster::MAX_SHADOW_MAP_RESOLUTION;
use shadowtruth::scene::{Camera, Scene};
use shadowtruth::technique::{ExternalParams, LayerNeeds, TechniqueSpec};
use std::path::{Path, PathBuf};

#[derive(Args)]
pub(super) struct ScoreArgs {
    /// The scene the buffer was rendered from (a scene file, or a glTF file as a scene).
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
    #[arg(long, required_unless_present = "shadow_map", conflicts_with = "shadow_map")]
    visibility: Option<PathBuf>,
    /// The renderer's camera depth (EXR, the only channel or `Z`): per pixel the distance from the camera's position to
    /// the surface along the primary ray, in world units; 0 or +inf for background. Pixels whose
    /// surface differs from the reference's are counted as surface_mismatch, not scored.
    #[arg(long, conflicts_with = "shadow_map")]
    depth: Option<PathBuf>,
    /// Relative depth tolerance: a depth d matches the reference's distance t when
    /// |d − t| ≤ X·t + 1e-4 (world units).
    #[arg(long, value_name = "X", requires = "depth", default_value_t = shadowtruth::import::DEFAULT_DEPTH_TOLERANCE)]
    depth_tolerance: f64,
    /// The renderer's name, recorded as the technique's `name`.
    #[arg(long, default_value = "external")]
    name: String,
    /// Row 0 of the files is the bottom row.
    #[arg(long, conflicts_with = "shadow_map")]
    flip_y: bool,
    /// The EXR channel of the visibility file (needed when it has more than one).
    #[arg(long, conflicts_with = "shadow_map")]
    channel: Option<String>,
    /// The shadow-map resolution the attribution's texel footprint is taken at (aliasing: a false
    /// pixel within one texel of a reference shadow boundary).
    #[arg(long, default_value_t = DEFAULT_ATTRIBUTION_RESOLUTION, conflicts_with = "shadow_map",
          value_parser = clap::value_parser!(u32).range(1..=MAX_SHADOW_MAP_RESOLUTION as i64))]
    resolution: u32,
    /// Instead of a visibility buffer, the renderer's shadow map: one depth layer as an EXR (row
    /// 0 at the top, depth in [0, 1], smaller closer), as `shadowtruth depth-map` writes it. The
    /// reference's surface points are shaded with it by --technique, which tells a wrong map
    /// from a wrong shadow test.
    #[arg(long, requires = "technique")]
    shadow_map: Option<PathBuf>,
    /// The map's sidecar: JSON with `clip_from_world` (4 rows of 4), `near` and `far`
    /// (default: the map's file name with extension .json).
    #[arg(long, requires = "shadow_map")]
    clip_from_world: Option<PathBuf>,
    /// The built-in technique that reads the shadow map, as JSON:
    /// '{"technique": "constant", "bias_depth": 0.001}'. Single-layer techniques only.
    #[arg(long, value_name = "JSON", requires = "shadow_map", value_parser = parse_map_technique)]
    technique: Option<TechniqueSpec>,
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
    /// Worker threads, 1 to 1024 (default: all cores).
    #[arg(long, value_parser = threads_parser())]
    threads: Option<usize>,
    /// No progress bar and no table.
    #[arg(short, long)]
    quiet: bool,
}

pub(super) fn score(a: ScoreArgs) -> Result<u8> {
    set_threads(a.threads)?;
    if !a.scene.is_file() {
        return Err(anyhow!("{}: no such scene file", a.scene.display()));
    }
    // The scene for the camera's size and the light, so that bad files fail before anything is
    // traced; a scene that does not load, or lacks the camera or light, fails in the plan.
    let scene = shadowtruth::scene::load_scene(&a.scene).ok();
    let (technique, resolution, shadow_map) = match (&a.visibility, &a.shadow_map) {
        (Some(visibility), _) => {
            let camera = scene.as_ref().and_then(|s| s.camera(&a.camera));
            (imported_technique(&a, visibility, camera)?, a.resolution, None)
        }
        (None, Some(map)) => {
            let sidecar = a.clip_from_world.clone().unwrap_or_else(|| map.with_extension("json"));
            let shadow_map = read_shadow_map(map, &sidecar)?;
            let technique = a.technique.clone().ok_or_else(|| anyhow!("--shadow-map needs --technique"))?;
            check_map_light(&shadow_map, scene.as_ref(), &a.light)?;
            (technique, shadow_map.layer.resolution, Some(shadow_map))
        }
        (None, None) => return Err(anyhow!("give --visibility or --shadow-map")),
    };
    drop(scene);
    let plan = Plan {
        cameras: Some(vec![a.camera.clone()]),
        lights: Some(vec![a.light.clone()]),
        repeats: 1,
        figures: !a.no_figures,
        shadow_map,
        ..Plan::new(vec![a.scene.clone()], vec![technique], vec![resolution])
    };
    let cache = (!a.no_cache).then(|| shadowtruth::trace::ReferenceCache::new(&a.references));
    write_plan_report(&plan, &a.out, cache.as_ref(), a.quiet, false)?;
    if let (Some(TechniqueSpec::External(params)), false) = (plan.techniques.first(), a.quiet) {
        let (report, _) = shadowtruth::record::load_report(&a.out)?;
        if let Some(hint) = flip_hint(&a.scene, &a.camera, &a.light, params, &report.runs[0].counts)? {
            eprintln!("{hint}");
        }
    }
    Ok(0)
}

/// Above this fraction of wrong pixels a buffer is also scored upside down, in case it was.
const FLIP_CHECK_WRONG_FRACTION: f64 = 0.01;

/// False shadow, false lit and surface mismatches (a flipped image's background lands on
/// surfaces), as a fraction of the evaluated pixels.
fn wrong_fraction(c: &shadowtruth::metrics::Counts) -> f64 {
    (c.false_shadow + c.false_lit + c.surface_mismatch) as f64 / c.evaluated.max(1) as f64
}

/// A hint to (un)set `--flip-y` when the buffer read the other way up has less than half the
/// wrong pixels it had as read (`counts`): the usual sign of an OpenGL read-back, whose row 0 is
/// the bottom.
fn flip_hint(
    scene: &Path,
    camera: &str,
    light: &str,
    params: &ExternalParams,
    counts: &shadowtruth::metrics::Counts,
) -> Result<Option<String>> {
    let wrong = wrong_fraction(counts);
    if wrong <= FLIP_CHECK_WRONG_FRACTION {
        return Ok(None);
    }
    let scene = shadowtruth::scene::load_scene(scene)?;
    let (Some(camera), Some(light)) = (scene.camera(camera), scene.light(light)) else { return Ok(None) };
    let flipped = ExternalParams { flip_y: !params.flip_y, ..params.clone() };
    let (visibility, depth) = flipped.read_buffers(camera)?;
    let bvh = shadowtruth::SceneBvh::build(&scene);
    let (gbuffer, reference) = shadowtruth::trace_scored_view(&scene, &bvh, camera, light);
    let tolerance = flipped.depth_tolerance();
    let other =
        shadowtruth::score_imported(&gbuffer, camera, &reference, &visibility, depth.as_ref(), tolerance)?;
    let wrong_flipped = wrong_fraction(&other);
    if wrong_flipped >= 0.5 * wrong {
        return Ok(None);
    }
    let option = if params.flip_y { "without --flip-y" } else { "with --flip-y" };
    Ok(Some(format!(
        "hint: read {option}, {:.3}% of the pixels are wrong (false or another surface) instead of {:.3}%: the \
         buffer looks upside down (an OpenGL or WebGL read-back has row 0 at the bottom)",
        100.0 * wrong_flipped,
        100.0 * wrong
    )))
}

/// The `external` technique of the visibility (and depth) files, checked (against `camera`'s
/// size) before the reference is traced so that bad input fails at once.
fn imported_technique(a: &ScoreArgs, visibility: &Path, camera: Option<&Camera>) -> Result<TechniqueSpec> {
    let path = |p: &Path| p.to_string_lossy().into_owned();
    let params = ExternalParams {
        name: a.name.clone(),
        visibility: path(visibility),
        depth: a.depth.as_deref().map(path),
        depth_tolerance: a.depth.is_some().then_some(a.depth_tolerance),
        channel: a.channel.clone(),
        flip_y: a.flip_y,
    };
    let spec = TechniqueSpec::External(params.clone());
    spec.validate().map_err(|e| anyhow!("{e}"))?;
    if let Some(camera) = camera {
        params.read_buffers(camera)?;
    }
    Ok(spec)
}

/// The imported map checked against the scene's light (the plan checks it again), so that a
/// map of another light fails before anything is traced.
fn check_map_light(map: &ImportedShadowMap, scene: Option<&Scene>, light: &str) -> Result<()> {
    if let Some(scene) = scene
        && let Some(light) = scene.light(light)
    {
        map.light_view(light, scene.bounds())?;
    }
    Ok(())
}

/// `--technique JSON`: the built-in technique that shades with an imported map, which holds one
/// nearest layer: a technique that reads no map, or more than that layer, is refused.
fn parse_map_technique(json: &str) -> Result<TechniqueSpec, String> {
    let spec: TechniqueSpec = serde_json::from_str(json).map_err(|e| e.to_string())?;
    spec.validate().map_err(|e| format!("{}: {e}", spec.name()))?;
    match spec.build() {
        None => Err(format!("{} reads no shadow map", spec.name())),
        Some(t) if t.layer_needs() != LayerNeeds::default() => Err(format!(
            "{} reads layers an imported shadow map does not hold (culling, raster bias, a second layer, \
             multiple depths or moments): only single-layer techniques read one",
            spec.label()
        )),
        Some(_) => Ok(spec),
    }
}
