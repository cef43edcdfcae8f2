//! JUnit XML of a gate for CI systems: one `<testsuite>` per rule, one `<testcase>` per run the
//! rule checked, a `<failure>` in each testcase that broke a bound; and, when baseline runs are
//! missing from the report, a `baseline` testsuite with one testcase per missing run (a failure,
//! or skipped with `--allow-missing`).

use crate::escape::escape_xml as escape;
use crate::gate::{BaselineComparison, Check, GateOutcome};

/// The outcome as JUnit XML (`testsuites` / `testsuite` / `testcase` / `failure`).
pub fn junit_xml(outcome: &GateOutcome) -> String {
    let mut suites: Vec<(usize, Vec<&Check>)> = Vec::new();
    for c in &outcome.checks {
        match suites.last_mut() {
            Some((rule, checks)) if *rule == c.rule => checks.push(c),
            _ => suites.push((c.rule, vec![c])),
        }
    }
    let missing = outcome.baseline.as_ref().map_or(0, |b| b.missing.len());
    let missing_failures = outcome.baseline.as_ref().map_or(0, BaselineComparison::violations);
    let mut x = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    x.push_str(&format!(
        "<testsuites name=\"shadowtruth gate\" tests=\"{}\" failures=\"{}\" errors=\"0\">\n",
        outcome.checks.len() + missing,
        outcome.failed_checks() + missing_failures
    ));
    for (rule, checks) in &suites {
        let failures = checks.iter().filter(|c| !c.passed()).count();
        x.push_str(&format!(
            "  <testsuite name=\"{}\" tests=\"{}\" failures=\"{failures}\" errors=\"0\" skipped=\"0\">\n",
            escape(&format!("rule[{rule}] {}", checks[0].rule_name)),
            checks.len()
        ));
        for c in checks {
            let name = escape(&c.run.to_string());
            let classname = escape(&format!("shadowtruth.gate.rule{rule}.{}", c.metric));
            if c.passed() {
                x.push_str(&format!("    <testcase name=\"{name}\" classname=\"{classname}\"/>\n"));
                continue;
            }
            let lines = c.violation_lines();
            x.push_str(&format!("    <testcase name=\"{name}\" classname=\"{classname}\">\n"));
            x.push_str(&format!(
                "      <failure message=\"{}\" type=\"{}\">{}</failure>\n",
                escape(&lines[0]),
                escape(&format!("{} bound", c.metric)),
                escape(&format!("{}\nlimits: {}", lines.join("\n"), c.limits()))
            ));
            x.push_str("    </testcase>\n");
        }
        x.push_str("  </testsuite>\n");
    }
    if let Some(b) = outcome.baseline.as_ref().filter(|b| !b.missing.is_empty()) {
        x.push_str(&missing_suite(b));
    }
    x.push_str("</testsuites>\n");
    x
}

/// One testcase per baseline run missing from the report.
fn missing_suite(b: &BaselineComparison) -> String {
    let (failures, skipped) = if b.allow_missing { (0, b.missing.len()) } else { (b.missing.len(), 0) };
    let tests = b.missing.len();
    let mut x = format!(
        "  <testsuite name=\"baseline: every run paired\" tests=\"{tests}\" failures=\"{failures}\" \
         errors=\"0\" skipped=\"{skipped}\">\n"
    );
    for run in &b.missing {
        let message = escape(&b.missing_line(run));
        let outcome = if b.allow_missing {
            format!("<skipped message=\"{message}\"/>")
        } else {
            format!("<failure message=\"{message}\" type=\"missing run\">{message}</failure>")
        };
        let name = escape(&run.to_string());
        x.push_str(&format!("    <testcase name=\"{name}\" classname=\"shadowtruth.gate.baseline\">\n"));
        x.push_str(&format!("      {outcome}\n    </testcase>\n"));
    }
    x.push_str("  </testsuite>\n");
    x
}
