//! A plan run into a report folder: report.json and the figures as the runs come, then the
//! CSV, plots and page, and the tables and summary line on the terminal.

use super::progress::Progress;
use super::table::{TableLayout, print_tables};
use crate::outputs::write_report_outputs;
use crate::plan::{Plan, Portion, Sink, execute_portion};
use crate::sinks::{FigureSink, ReportWriter};
use anyhow::{Context, Result};
use shadowtruth::trace::ReferenceCache;
use std::path::Path;
use std::time::Instant;

/// The sinks of `run` and `papers`: report.json, figures unless `figures` is off, progress.
pub(super) fn sinks<'a>(
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

/// Runs `plan` into the report folder `out` (report.json, figures unless the plan has none, then
/// the CSV, plots and page) and prints the tables and summary unless `quiet`.
pub(super) fn write_plan_report(
    plan: &Plan,
    out: &Path,
    cache: Option<&ReferenceCache>,
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
pub(super) fn finish_plan_report(
    plan: &Plan,
    mut writer: ReportWriter,
    portion: &Portion,
    cache: Option<&ReferenceCache>,
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
        print_tables(writer.report(), layout);
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
