//! The outcome as text (what `gate` prints) and as a Markdown table for CI job summaries.

use super::check::{BaselineComparison, BaselineStatus, Check, GateOutcome, Measured, Violation};
use super::fmt_value::fmt_value;
use super::identity::RunName;

impl Measured {
    /// `0.00127157 (1000 of 786432 px)`, or the value alone for the soft metrics.
    pub fn show(&self) -> String {
        match self.count {
            Some(c) => format!("{} ({c} of {} px)", fmt_value(self.value), self.evaluated),
            None => fmt_value(self.value),
        }
    }
}

fn show_limit(limit: f64, limit_count: Option<u64>) -> String {
    match limit_count {
        Some(c) => format!("{} ({c} px)", fmt_value(limit)),
        None => fmt_value(limit),
    }
}

impl Check {
    /// The limits applied, e.g. `≤ 0.001; ≤ baseline 0.0012 + 0 = 0.0012 (24 px)`.
    pub fn limits(&self) -> String {
        let mut parts = Vec::new();
        if let Some(m) = self.max {
            parts.push(format!("≤ {}", fmt_value(m)));
        }
        match &self.baseline {
            BaselineStatus::NotChecked => {}
            BaselineStatus::New => parts.push("new: not in the baseline".into()),
            BaselineStatus::Compared { baseline, limit, limit_count } => {
                parts.push(format!("≤ baseline {} → {}", baseline.show(), show_limit(*limit, *limit_count)))
            }
        }
        parts.join("; ")
    }

    /// `pass`, `pass (new)` or `FAIL`.
    pub fn status(&self) -> &'static str {
        match (self.passed(), &self.baseline) {
            (false, _) => "FAIL",
            (true, BaselineStatus::New) => "pass (new)",
            (true, _) => "pass",
        }
    }

    /// One line per violation: rule, run, metric value and limit (and baseline).
    pub fn violation_lines(&self) -> Vec<String> {
        let head = format!(
            "FAIL rule[{}] \"{}\": {}: {} = {}",
            self.rule,
            self.rule_name,
            self.run,
            self.metric,
            self.measured.show()
        );
        self.violations
            .iter()
            .map(|v| match v {
                Violation::Max { limit } => format!("{head} > max {}", fmt_value(*limit)),
                Violation::Regression { baseline, limit, limit_count } => format!(
                    "{head} > limit {} (baseline {})",
                    show_limit(*limit, *limit_count),
                    baseline.show()
                ),
            })
            .collect()
    }
}

impl BaselineComparison {
    /// `missing: RUN: in the baseline, not in the report`, a warning when missing runs are allowed.
    pub fn missing_line(&self, run: &RunName) -> String {
        let line = format!("missing: {run}: in the baseline, not in the report");
        if self.allow_missing { format!("warning: {line} (allowed by --allow-missing)") } else { line }
    }

    /// `new: RUN: not in the baseline, no regression check`
    pub fn new_line(&self, run: &RunName) -> String {
        format!("new: {run}: not in the baseline, no regression check")
    }

    /// `P paired, Q missing, R new` (`Q missing (allowed)` with `--allow-missing`).
    pub fn summary(&self) -> String {
        let allowed = if self.allow_missing && !self.missing.is_empty() { " (allowed)" } else { "" };
        format!(
            "{} paired, {} missing{allowed}, {} new",
            self.paired,
            self.missing.len(),
            self.new_runs.len()
        )
    }
}

impl GateOutcome {
    /// `N rules, M runs checked, K violations`, then `; baseline: P paired, Q missing, R new`
    /// with a baseline.
    pub fn summary_line(&self) -> String {
        let mut line = format!(
            "{} rules, {} runs checked, {} violations",
            self.rules,
            self.runs_checked,
            self.violations()
        );
        if let Some(b) = &self.baseline {
            line.push_str(&format!("; baseline: {}", b.summary()));
        }
        line
    }

    /// What `gate` prints: one line per violation, the missing and the new runs, the summary line.
    pub fn text(&self) -> String {
        let mut lines: Vec<String> = self.checks.iter().flat_map(Check::violation_lines).collect();
        if let Some(b) = &self.baseline {
            lines.extend(b.missing.iter().map(|run| b.missing_line(run)));
            lines.extend(b.new_runs.iter().map(|run| b.new_line(run)));
        }
        lines.push(self.summary_line());
        lines.iter().map(|l| format!("{l}\n")).collect()
    }

    /// A Markdown table (rule, run, value, limit, status) for CI job summaries: one row per check
    /// and per missing baseline run, then the new runs.
    pub fn markdown(&self) -> String {
        let mut out = format!(
            "## shadowtruth gate: {}\n\n{}\n\n| rule | run | value | limit | status |\n| --- | --- | --- | --- | --- |\n",
            if self.passed() { "passed" } else { "FAILED" },
            self.summary_line()
        );
        for c in &self.checks {
            let status = if c.passed() { c.status().to_string() } else { "**FAIL**".to_string() };
            out.push_str(&md_row([
                &format!("rule[{}] {}", c.rule, c.rule_name),
                &c.run.to_string(),
                &format!("{} = {}", c.metric, c.measured.show()),
                &c.limits(),
                &status,
            ]));
        }
        if let Some(b) = &self.baseline {
            out.push_str(&baseline_markdown(b));
        }
        out
    }
}

/// The rows of missing baseline runs, and the new runs as a list under the table.
fn baseline_markdown(b: &BaselineComparison) -> String {
    let status = if b.allow_missing { "missing (allowed)" } else { "**FAIL** (missing)" };
    let mut out: String = b
        .missing
        .iter()
        .map(|run| md_row(["baseline", &run.to_string(), "not in the report", "in the report", status]))
        .collect();
    if !b.new_runs.is_empty() {
        out.push_str("\nNew runs (not in the baseline, no regression check):\n\n");
        for run in &b.new_runs {
            out.push_str(&format!("- {}\n", md_cell(&run.to_string())));
        }
    }
    out
}

fn md_row(cells: [&str; 5]) -> String {
    let cells: Vec<String> = cells.iter().map(|c| md_cell(c)).collect();
    format!("| {} |\n", cells.join(" | "))
}

fn md_cell(s: &str) -> String {
    s.replace('\\', "\\\\").replace('|', "\\|").replace(['\n', '\r'], " ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gate::{CheckedReport, GateOptions, evaluate, parse_rules};
    use shadowtruth::metrics::Counts;
    use shadowtruth::record::{Report, RunRecord};

    fn run(scene: &str, false_shadow: u64) -> RunRecord {
        let counts = Counts { pixels: 100, evaluated: 100, false_shadow, ..Counts::default() };
        crate::gate::test_run(scene, "none", serde_json::json!({}), "none", counts)
    }

    fn outcome(now: Vec<RunRecord>, base: Option<Vec<RunRecord>>, allow_missing: bool) -> GateOutcome {
        let checked = |runs| CheckedReport::new(Report { runs, ..Report::new() }, "r.json").unwrap();
        let rules = parse_rules("[[rule]]\nmetric = \"error\"\nmax = 0\n", "rules.toml").unwrap();
        let base = base.map(checked);
        evaluate(&checked(now), base.as_ref(), &rules, GateOptions { allow_missing }).unwrap()
    }

    #[test]
    fn markdown_has_one_row_per_check_and_escapes_pipes() {
        let md = outcome(vec![run("a|b", 1), run("c", 0)], None, false).markdown();
        let rows: Vec<&str> = md.lines().filter(|l| l.starts_with('|')).collect();
        assert_eq!(rows.len(), 2 + 2);
        assert!(rows[2].contains("a\\|b") && rows[2].contains("FAIL"), "{md}");
        assert!(rows[3].ends_with("| pass |"), "{md}");
    }

    #[test]
    fn markdown_lists_missing_runs_as_failures_and_new_runs_below() {
        let out = outcome(vec![run("a", 0), run("new", 0)], Some(vec![run("a", 0), run("gone", 0)]), false);
        let md = out.markdown();
        assert!(md.starts_with("## shadowtruth gate: FAILED"), "{md}");
        let missing: Vec<&str> = md.lines().filter(|l| l.starts_with("| baseline |")).collect();
        assert_eq!(missing.len(), 1, "{md}");
        assert!(missing[0].contains("gone/main/sun") && missing[0].contains("**FAIL** (missing)"), "{md}");
        assert!(md.contains("\n- new/main/sun none @1024 f32 [hard×1]\n"), "{md}");
        assert!(md.contains("1 paired, 1 missing, 1 new"), "{md}");
        let allowed = outcome(vec![run("a", 0)], Some(vec![run("a", 0), run("gone", 0)]), true).markdown();
        assert!(
            allowed.starts_with("## shadowtruth gate: passed") && allowed.contains("| missing (allowed) |")
        );
    }
}
