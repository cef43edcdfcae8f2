//! `shadowtruth tune`: the setting of one technique to ship, per scene and for the suite, with
//! its safe range; tune.json, a plot of the search, gate rules, and the tuned settings run into
//! the usual report folder (docs/tune.md).

use super::{expand_scenes, load_report, set_threads, write_plan_report};
use crate::atomic_file::write_atomic;
use crate::plan::{Plan, check_plan};
use crate::raster::{DepthFormat, MAX_SHADOW_MAP_RESOLUTION};
use crate::report::tune_chart;
use crate::tune::{
    LogRange, Objective, SuiteAggregate, TuneRecord, TuneRequest, TuneResult, TuneViews, gate_rules_toml,
    tune,
};
use anyhow::{Context, Result, anyhow, bail};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use serde_json::{Map, Value};
use std::path::PathBuf;

#[derive(Args)]
pub(super) struct TuneArgs {
    /// Scene files or folders of scene files (default: scenes/).
    scenes: Vec<PathBuf>,
    /// The technique: its name (`constant`), or a JSON object with its fixed parameters
    /// (`{"technique": "pcf", "kernel": "box", "size": 3}`).
    #[arg(long)]
    technique: String,
    /// A parameter to tune, with its range searched on a log scale: NAME or NAME=LO:HI (both
    /// positive). One to three. Known names have a default range (bias_depth 1e-6:0.1,
    /// bias_world 1e-5:1, scale_texels 0.01:10, factor 0.01:16, units 0.01:64, k 1e-6:0.1,
    /// z_offset 1e-5:0.1, radius_texels 0.25:8).
    #[arg(long = "param", required = true, value_name = "NAME[=LO:HI]")]
    params: Vec<String>,
    /// What to minimise: `total` (false shadow + false lit), `weighted` (false shadow + W·false
    /// lit, with --weight W) or `false-lit-under` (the least false lit with false shadow at most
    /// --max-false-shadow X). Rates are fractions of each scene's scored pixels.
    #[arg(long, value_enum, default_value_t = ObjectiveKind::Total)]
    objective: ObjectiveKind,
    #[arg(long, value_name = "W", required_if_eq("objective", "weighted"))]
    weight: Option<f64>,
    #[arg(long, value_name = "X", required_if_eq("objective", "false-lit-under"))]
    max_false_shadow: Option<f64>,
    /// The suite's objective: the mean of the scenes' or the worst scene's.
    #[arg(long, value_enum, default_value_t = SuiteAggregate::Mean)]
    suite: SuiteAggregate,
    /// Shadow-map resolutions; every evaluation shades each of them.
    #[arg(long, value_delimiter = ',', default_value = "1024",
          value_parser = clap::value_parser!(u32).range(1..=MAX_SHADOW_MAP_RESOLUTION as i64))]
    resolutions: Vec<u32>,
    /// Depth format of the shadow maps: f32, unorm24 or unorm16.
    #[arg(long, default_value = "f32")]
    depth_format: String,
    /// Output folder: tune.json, tune-gate.toml, plots/tune.png and the tuned settings' report.
    #[arg(short, long, default_value = "reports/tune")]
    out: PathBuf,
    /// The slack of the gate rules written for the suite's setting (relative; one pixel more).
    #[arg(long, default_value_t = 0.1)]
    gate_slack: f64,
    /// Reference cache folder.
    #[arg(long, default_value = "references")]
    references: PathBuf,
    /// Trace every reference instead of reading or writing the cache.
    #[arg(long)]
    no_cache: bool,
    /// Write tune.json and the plot only, without running the tuned settings into a report.
    #[arg(long)]
    no_report: bool,
    /// Also run each scene's own best setting into the report, beside the suite's.
    #[arg(long, conflicts_with = "no_report")]
    report_scene_bests: bool,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// No progress bar and no table.
    #[arg(short, long)]
    quiet: bool,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum ObjectiveKind {
    Total,
    Weighted,
    FalseLitUnder,
}

/// Default search ranges of the parameters that have an obvious one.
const DEFAULT_RANGES: [(&str, f64, f64); 8] = [
    ("bias_depth", 1e-6, 0.1),
    ("bias_world", 1e-5, 1.0),
    ("scale_texels", 0.01, 10.0),
    ("factor", 0.01, 16.0),
    ("units", 0.01, 64.0),
    ("k", 1e-6, 0.1),
    ("z_offset", 1e-5, 0.1),
    ("radius_texels", 0.25, 8.0),
];

pub(super) fn run_tune(a: TuneArgs) -> Result<u8> {
    set_threads(a.threads)?;
    let request = request(&a)?;
    let format = DepthFormat::parse(&a.depth_format)
        .ok_or_else(|| anyhow!("--depth-format {}: expected f32, unorm24 or unorm16", a.depth_format))?;
    let default_scenes = [PathBuf::from("scenes")];
    let scenes = expand_scenes(if a.scenes.is_empty() { &default_scenes } else { &a.scenes })?;
    let mut plan = Plan::default_for(scenes);
    plan.techniques = vec![
        request
            .spec(&request.params.iter().map(|(_, r)| r.lo).collect::<Vec<_>>())
            .map_err(|e| anyhow!("--technique: {e}"))?,
    ];
    plan.resolutions = a.resolutions.clone();
    plan.depth_formats = vec![format];
    plan.repeats = 1;
    check_plan(&plan)?;
    let cache = (!a.no_cache).then(|| crate::trace::ReferenceCache::new(&a.references));
    let bar = progress_bar(a.quiet);
    let mut views = TuneViews::build(&plan, cache.as_ref(), &mut |s| bar.set_message(s.to_string()))?;
    bar.set_message("searching");
    let result = tune(&mut views, &request, &mut || bar.inc(1));
    bar.finish_and_clear();
    drop(views);
    let record = TuneRecord::new(&request, &result, &plan.resolutions, format.name());
    // The report folder's earlier outputs are cleared by the run: tune's own files come after.
    let report =
        if a.no_report { None } else { Some(run_tuned(&a, &plan, &request, &result, cache.as_ref())?) };
    write_outputs(&a, &record, &result, &request)?;
    if let Some(report) = &report {
        // The page again, now with the tuning section.
        crate::report::write_page(&a.out, report)
            .with_context(|| format!("writing {}", a.out.join("index.html").display()))?;
    }
    if !a.quiet {
        print_summary(&record);
        println!("{} settings shaded and scored on one scene each", result.scene_evaluations);
        println!("tune: {}", a.out.join("tune.json").display());
    }
    Ok(0)
}

fn progress_bar(quiet: bool) -> ProgressBar {
    let bar = if quiet { ProgressBar::hidden() } else { ProgressBar::new_spinner() };
    bar.set_style(
        ProgressStyle::with_template("{elapsed_precise} {spinner} {pos} scene evaluations  {msg}")
            .expect("valid template"),
    );
    bar.enable_steady_tick(std::time::Duration::from_millis(200));
    bar
}

/// The request from the arguments, every problem named by its option.
fn request(a: &TuneArgs) -> Result<TuneRequest> {
    let base = technique_object(&a.technique)?;
    if a.params.len() > 3 {
        bail!("--param: at most three parameters are tuned together ({} given)", a.params.len());
    }
    let params = a.params.iter().map(|p| param_range(p)).collect::<Result<Vec<_>>>()?;
    let objective = match a.objective {
        ObjectiveKind::Total => Objective::Total,
        ObjectiveKind::Weighted => Objective::Weighted { weight: a.weight.expect("required by clap") },
        ObjectiveKind::FalseLitUnder => {
            Objective::FalseLitUnder { max_false_shadow: a.max_false_shadow.expect("required by clap") }
        }
    };
    let request = TuneRequest { base, params, objective, aggregate: a.suite };
    // Both ends of every range must make a valid technique before anything is traced.
    for corner in [true, false] {
        let values: Vec<f64> = request.params.iter().map(|(_, r)| if corner { r.lo } else { r.hi }).collect();
        request
            .spec(&values)
            .map_err(|e| anyhow!("--technique {} with --param {:?}: {e}", a.technique, a.params))?;
    }
    Ok(request)
}

fn technique_object(text: &str) -> Result<Map<String, Value>> {
    if !text.trim_start().starts_with('{') {
        let mut m = Map::new();
        m.insert("technique".into(), Value::from(text));
        return Ok(m);
    }
    match serde_json::from_str(text) {
        Ok(Value::Object(m)) => Ok(m),
        Ok(_) => bail!("--technique: expected a technique name or a JSON object"),
        Err(e) => bail!("--technique: {e} (in {text})"),
    }
}

/// `NAME` or `NAME=LO:HI`.
fn param_range(text: &str) -> Result<(String, LogRange)> {
    let (name, range) = match text.split_once('=') {
        Some((name, range)) => {
            let (lo, hi) =
                range.split_once(':').ok_or_else(|| anyhow!("--param {text}: expected NAME=LO:HI"))?;
            let parse = |s: &str| s.trim().parse::<f64>().map_err(|e| anyhow!("--param {text}: {s}: {e}"));
            (name.trim(), LogRange { lo: parse(lo)?, hi: parse(hi)? })
        }
        None => {
            let (_, lo, hi) = DEFAULT_RANGES.iter().find(|(n, _, _)| *n == text.trim()).ok_or_else(|| {
                anyhow!("--param {text}: no default range for this parameter; give one as {text}=LO:HI")
            })?;
            (text.trim(), LogRange { lo: *lo, hi: *hi })
        }
    };
    if !(range.lo > 0.0 && range.hi > range.lo && range.hi.is_finite()) {
        bail!("--param {text}: the range must satisfy 0 < LO < HI (it is searched on a log scale)");
    }
    Ok((name.to_string(), range))
}

fn write_outputs(
    a: &TuneArgs,
    record: &TuneRecord,
    result: &TuneResult,
    request: &TuneRequest,
) -> Result<()> {
    std::fs::create_dir_all(a.out.join("plots")).with_context(|| format!("creating {}", a.out.display()))?;
    let mut text = serde_json::to_string_pretty(record)?;
    text.push('\n');
    let path = a.out.join("tune.json");
    write_atomic(&path, text.as_bytes()).with_context(|| format!("writing {}", path.display()))?;
    for (axis, (name, _)) in request.params.iter().enumerate() {
        let chart = tune_chart(result, request, axis);
        crate::report::write_chart(&a.out.join("plots"), &chart)
            .with_context(|| format!("writing the plot of {name} into {}", a.out.join("plots").display()))?;
    }
    Ok(())
}

fn print_summary(record: &TuneRecord) {
    let rows: Vec<(&str, &crate::tune::TunedRecord)> = std::iter::once(("suite", &record.suite))
        .chain(record.per_scene.iter().map(|s| (s.scene.as_str(), &s.tuned)))
        .collect();
    let scene_width = rows.iter().map(|(s, _)| s.len()).max().unwrap_or(5).max(5);
    let label_width = rows.iter().map(|(_, t)| t.best.label.len()).max().unwrap_or(4).max(4);
    println!("{:<scene_width$}  {:<label_width$}  {:>10}  safe range", "scene", "best", "objective");
    for (scene, t) in rows {
        let safe: Vec<String> =
            t.safe_range.iter().map(|(n, r)| format!("{n} {}..{}", r["lo"], r["hi"])).collect();
        if !t.best.feasible {
            println!(
                "{scene:<scene_width$}  no setting meets the bound; the least false shadow is {:.4}% ({})",
                100.0 * (t.best.objective - 1.0),
                t.best.label
            );
            continue;
        }
        println!(
            "{scene:<scene_width$}  {:<label_width$}  {:>9.4}%  {}",
            t.best.label,
            100.0 * t.best.objective,
            safe.join(", ")
        );
    }
}

/// Runs the suite's setting (and with --report-scene-bests each scene's) into the report
/// folder, writes the gate rules that lock the suite setting's error on every view, and
/// returns the report.
fn run_tuned(
    a: &TuneArgs,
    plan: &Plan,
    request: &TuneRequest,
    result: &TuneResult,
    cache: Option<&crate::trace::ReferenceCache>,
) -> Result<crate::report::Report> {
    let suite_spec = request.spec(&result.suite.best.params).map_err(|e| anyhow!(e))?;
    let mut plan = plan.clone();
    plan.techniques = vec![suite_spec.clone()];
    if a.report_scene_bests {
        for (_, t) in &result.scenes {
            let spec = request.spec(&t.best.params).map_err(|e| anyhow!(e))?;
            if !plan.techniques.iter().any(|s| s.label() == spec.label()) {
                plan.techniques.push(spec);
            }
        }
    }
    write_plan_report(&plan, &a.out, cache, a.quiet, false)?;
    let (report, _) = load_report(&a.out)?;
    let rules = gate_rules_toml(&report.runs, &suite_spec.label(), a.gate_slack);
    let path = a.out.join("tune-gate.toml");
    write_atomic(&path, rules.as_bytes()).with_context(|| format!("writing {}", path.display()))?;
    if !a.quiet {
        println!("gate rules for {}: {}", suite_spec.label(), path.display());
    }
    Ok(report)
}
