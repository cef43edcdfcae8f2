//! `shadowtruth tune`: the setting of one technique to ship, per scene and for the suite, with
//! its safe range; tune.json, a plot of the search, gate rules, and the tuned settings run into
//! the usual report folder (docs/tune.md).

use super::args::set_threads;
use super::plan_report::write_plan_report;
use super::scene_paths::expand_scenes_or_default;
use crate::drawing::tune_chart;
use crate::plan::{Plan, check_plan};
use crate::tune::{TuneRecord, TuneRequest, TuneResult, TuneViews, gate_rules_toml, tune};
use anyhow::{Context, Result, anyhow};
use indicatif::{ProgressBar, ProgressStyle};
use shadowtruth::atomic_file::write_atomic;
use shadowtruth::record::load_report;

/// The options and their checks live beside the search (`src/tune/options.rs`), where the
/// fuzz entry reaches them too.
pub(super) use crate::tune::TuneArgs;

pub(super) fn run_tune(a: TuneArgs) -> Result<u8> {
    set_threads(a.threads)?;
    let request = a.request()?;
    let format = a.depth_format;
    let scenes = expand_scenes_or_default(&a.scenes)?;
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
    let cache = (!a.no_cache).then(|| shadowtruth::trace::ReferenceCache::new(&a.references));
    let bar = progress_bar(a.quiet);
    let mut views = TuneViews::build(&plan, cache.as_ref(), &mut |s| bar.set_message(s.to_string()))?;
    bar.set_message("searching");
    let result = tune(&mut views, &request, &mut || bar.inc(1))?;
    bar.finish_and_clear();
    drop(views);
    let record = TuneRecord::new(&request, &result, &plan.resolutions, format.name());
    // The report folder's earlier outputs are cleared by the run: tune's own files come after.
    let report =
        if a.no_report { None } else { Some(run_tuned(&a, &plan, &request, &result, cache.as_ref())?) };
    write_outputs(&a, &record, &result, &request)?;
    if let Some(report) = &report {
        // The page again, now with the tuning section.
        crate::drawing::write_page(&a.out, report)
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
        crate::drawing::write_chart(&a.out.join("plots"), &chart)
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
    cache: Option<&shadowtruth::trace::ReferenceCache>,
) -> Result<shadowtruth::record::Report> {
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
