//! `shadowtruth papers`: the papers' results reproduced and each claim judged: the usual report
//! of their set-ups, claims.json and claims.html.

use super::args::set_threads;
use super::plan_report::sinks;
use super::progress::Progress;
use crate::option_values::threads_parser;
use crate::outputs::write_report_outputs;
use crate::sinks::{FigureSink, ReportWriter};
use anyhow::{Context, Result};
use clap::Args;
use std::path::PathBuf;
use std::time::Instant;

#[derive(Args)]
pub(super) struct PapersArgs {
    /// Output folder.
    #[arg(short, long, default_value = "reports/papers")]
    out: PathBuf,
    /// Folder holding papers/island.json, papers/casters.json, papers/curved.json and
    /// papers/l_above.json.
    #[arg(long, default_value = "scenes")]
    scenes: PathBuf,
    /// The papers' set-ups, but only one other set-up per claim in the sensitivity grid, one
    /// timing pass, Pagot's Table 1 on Fig. 6's four filters and Ehm's Table 1 at 3×3 and 11×11
    /// (for tests).
    #[arg(long)]
    quick: bool,
    /// Reference cache folder.
    #[arg(long, default_value = "references")]
    references: PathBuf,
    /// Trace every reference instead of reading or writing the cache.
    #[arg(long)]
    no_cache: bool,
    /// Worker threads, 1 to 1024 (default: all cores).
    #[arg(long, value_parser = threads_parser())]
    threads: Option<usize>,
    /// No progress bar and no table.
    #[arg(short, long)]
    quiet: bool,
}

pub(super) fn papers(a: PapersArgs) -> Result<u8> {
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
        let width = claims.iter().map(|c| c.id.chars().count()).max().unwrap_or(0);
        for c in &claims {
            println!("{:<width$} {:<14} {}", c.id, c.verdict.name(), c.sensitivity_summary);
            if !c.margin.is_empty() {
                println!("{:<width$} {:<14} margin: {}", "", "", c.margin);
            }
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
