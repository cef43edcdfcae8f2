//! `shadowtruth reference`: the exact hard mask of one view as a PNG, or a soft reference (pixel
//! coverage, area light) as an EXR; with `--timing`, the tracer's rates beside another tracer's.

use super::args::set_threads;
use super::named_item::pick;
use super::trace_timing;
use crate::exports::{write_mask_png, write_soft_exr};
use crate::option_values::threads_parser;
use crate::plan::{DEFAULT_AREA_LIGHT_GRID, DEFAULT_COVERAGE_GRID, MAX_REFERENCE_GRID, MAX_REPEATS};
use anyhow::{Context, Result, bail};
use clap::Args;
use shadowtruth::metrics::try_timed_median;
use shadowtruth::scene::{Scene, load_scene};
use shadowtruth::trace::{
    GBuffer, SceneBvh, SoftReference, area_light_shadow_rays, trace_area_light_reference,
    trace_coverage_reference, trace_scored_view, validate_area_light,
};
use std::path::PathBuf;

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
pub(super) struct ReferenceArgs {
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
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=MAX_REFERENCE_GRID as i64), help = format!(
        "N for an N×N grid of samples per pixel (default: {DEFAULT_COVERAGE_GRID} for coverage, \
         {DEFAULT_AREA_LIGHT_GRID} for area; 1 to {MAX_REFERENCE_GRID})"
    ))]
    samples: Option<u32>,
    /// Worker threads, 1 to 1024 (default: all cores).
    #[arg(long, value_parser = threads_parser())]
    threads: Option<usize>,
    /// Also time the tracer: primary rays per second (prepared before the clock, closest hits
    /// written, as Embree's tool times them), the G-buffer's pixels per second (those hits'
    /// surface points, classes and certificates too, with its time over the rays' alone),
    /// shadow rays per second (prepared from the G-buffer before the clock, as the primary rays
    /// are), and the hard reference's pixels per second (the shadow rays built and traced, with
    /// its time over the rays' alone), each the median of --repeats; with --kind area, the
    /// area-light reference's rate and its time over its shadow rays' alone too.
    #[arg(long)]
    timing: bool,
    /// How many times --timing runs each measurement, 1 to 1000.
    #[arg(long, default_value_t = 5,
          value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..=MAX_REPEATS as u64))]
    repeats: usize,
    /// With --timing: Embree's timing on the same view, saved (the Embree reference tool's
    /// `mask --timing` output, or a native Embree benchmark's lines per mode); prints our rate
    /// over Embree's best at this thread count. Repeat it to take the best over several files.
    #[arg(long, requires = "timing")]
    embree_timing: Vec<PathBuf>,
}

pub(super) fn reference(a: ReferenceArgs) -> Result<u8> {
    let grid = match (a.kind, a.samples) {
        (ReferenceKind::Hard, Some(_)) => bail!("--samples applies to --kind coverage and --kind area only"),
        (ReferenceKind::Hard, None) => 1,
        (ReferenceKind::Coverage, n) => n.unwrap_or(DEFAULT_COVERAGE_GRID),
        (ReferenceKind::Area, n) => n.unwrap_or(DEFAULT_AREA_LIGHT_GRID),
    };
    match a.kind {
        ReferenceKind::Hard => super::args::check_output_extension(&a.out, "png", "the hard mask as a PNG")?,
        _ => super::args::check_output_extension(&a.out, "exr", "a soft reference as a two-channel EXR")?,
    }
    set_threads(a.threads)?;
    // Read before tracing, so that a wrong file fails at once.
    let embree = (!a.embree_timing.is_empty())
        .then(|| trace_timing::read_other_timing(&a.embree_timing, rayon::current_num_threads()))
        .transpose()?;
    let scene: Scene = load_scene(&a.scene)?;
    let camera = pick(&scene.cameras, a.camera.as_deref(), |c| &c.name, "camera", &a.scene)?;
    let light = pick(&scene.lights, a.light.as_deref(), |l| &l.name, "light", &a.scene)?;
    if a.kind == ReferenceKind::Area {
        validate_area_light(light, grid).with_context(|| format!("{}: --kind area", a.scene.display()))?;
    }
    let bvh = SceneBvh::build(&scene);
    // The soft references are traced as every score reads them: over the pixels the hard
    // reference decides (the mask marks the others `Uncertain` either way).
    let (gbuffer, hard) = trace_scored_view(&scene, &bvh, camera, light);
    let trace_soft = |g: &GBuffer| -> Result<SoftReference> {
        Ok(match a.kind {
            ReferenceKind::Coverage => trace_coverage_reference(&scene, &bvh, g, camera, light, grid),
            _ => trace_area_light_reference(&scene, &bvh, g, light, grid)?,
        })
    };
    let what = if a.kind == ReferenceKind::Hard {
        write_mask_png(&a.out, gbuffer.width, gbuffer.height, &hard.mask_codes(&gbuffer))
            .with_context(|| format!("writing {}", a.out.display()))?;
        "hard shadow mask"
    } else {
        write_soft_exr(&a.out, &trace_soft(&gbuffer)?)
            .with_context(|| format!("writing {}", a.out.display()))?;
        if a.kind == ReferenceKind::Coverage { "pixel-coverage reference" } else { "area-light reference" }
    };
    println!(
        "wrote {}: the {what} of camera '{}' under light '{}', {}×{} pixels",
        a.out.display(),
        camera.name,
        light.name,
        gbuffer.width,
        gbuffer.height
    );
    if a.timing {
        let ours = trace_timing::time_tracer(&scene, &bvh, camera, light, a.repeats);
        println!("node test: {}", shadowtruth::trace::node_test_name());
        println!("{}", trace_timing::timing_line(&ours, a.repeats));
        if let Some(theirs) = &embree {
            println!("{}", trace_timing::ratio_line(&ours, theirs));
        }
        if a.kind != ReferenceKind::Hard {
            let (_, soft_ms) =
                try_timed_median(a.repeats, || trace_soft(&gbuffer).map(std::hint::black_box))?;
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
                samples as f64 / soft_ms / 1e3,
                a.repeats
            );
            if a.kind == ReferenceKind::Area {
                let mut prepared = Ok(());
                let (rays_ms, rays) = trace_timing::time_prepared_rays(&bvh, a.repeats, |each_group| {
                    prepared = area_light_shadow_rays(
                        &scene,
                        &gbuffer,
                        light,
                        grid,
                        trace_timing::SHADOW_RAYS_HELD,
                        each_group,
                    )
                });
                prepared?;
                println!(
                    "shadowtruth {} threads  area light {grid}×{grid} shadow rays alone {:.3} Mrays/s ({rays} rays, \
                     those facing the surface): the reference takes {:.2}× their time",
                    rayon::current_num_threads(),
                    rays as f64 / rays_ms / 1e3,
                    soft_ms / rays_ms
                );
            }
        }
    }
    Ok(0)
}
