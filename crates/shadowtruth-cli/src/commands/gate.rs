//! `shadowtruth gate`: a report checked against rules (and a baseline report): exit 0 when every
//! rule holds, 1 on violations, 2 on bad input.

use anyhow::{Context, Result};
use clap::Args;
use shadowtruth::atomic_file::write_atomic;
use std::path::PathBuf;

#[derive(Args)]
pub(super) struct GateArgs {
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

/// Reads and checks everything first (any bad input exits 2 before anything is written),
/// evaluates, writes the optional JUnit and Markdown files, prints the violations, the missing and
/// new runs and the summary line.
pub(super) fn gate(a: GateArgs) -> Result<u8> {
    use crate::gate::{CheckedReport, GateOptions};
    let rules = crate::gate::load_rules(&a.rules)?;
    let report = CheckedReport::load(&a.report)?;
    let baseline = a.baseline.as_deref().map(CheckedReport::load).transpose()?;
    let options = GateOptions { allow_missing: a.allow_missing };
    let outcome = crate::gate::evaluate(&report, baseline.as_ref(), &rules, options)?;
    if let Some(path) = &a.junit {
        write_atomic(path, crate::exports::junit_xml(&outcome).as_bytes())
            .with_context(|| format!("writing {}", path.display()))?;
    }
    if let Some(path) = &a.summary {
        write_atomic(path, outcome.markdown().as_bytes())
            .with_context(|| format!("writing {}", path.display()))?;
    }
    print!("{}", outcome.text());
    Ok(if outcome.passed() { 0 } else { 1 })
}
