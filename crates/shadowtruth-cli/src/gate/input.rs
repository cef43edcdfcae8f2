//! Reading reports, and the consistency a report must have before the gate trusts its numbers:
//! counts within the evaluated pixels, rates that are those of the counts, some pixels evaluated,
//! soft errors in [0, 1], each run once. Every problem names the file and the JSON path.
//!
//! Rates are compared exactly: a run's rates are written by `Counts::rates` and report.json
//! stores each f64 as the shortest decimal that reads back as the same bits (serde_json with
//! `float_roundtrip`), so recomputing them with `Counts::rates` gives the same bits again; any
//! difference is an edit.

use super::GateError;
use super::identity::{RunIdentity, RunName};
use shadowtruth::record::{Report, RunRecord};
use std::collections::HashMap;
use std::path::Path;

/// A report that passed the consistency checks, with the file it came from (named in messages)
/// and the identity of each run. The gate evaluates only these.
#[derive(Clone, Debug)]
pub struct CheckedReport {
    origin: String,
    report: Report,
    identities: Vec<RunIdentity>,
}

impl CheckedReport {
    /// Reads a report (see [`shadowtruth::record::load_report`]) and checks it.
    pub fn load(path: &Path) -> Result<Self, GateError> {
        let (report, file) = shadowtruth::record::load_report(path).map_err(|e| GateError::one(e.0))?;
        Self::new(report, file.display().to_string())
    }

    /// Checks a report; `origin` names it in messages. Every problem is listed.
    pub fn new(report: Report, origin: impl Into<String>) -> Result<Self, GateError> {
        let origin = origin.into();
        let identities: Vec<RunIdentity> = report.runs.iter().map(RunIdentity::of).collect();
        let mut problems: Vec<String> = report
            .runs
            .iter()
            .enumerate()
            .flat_map(|(i, run)| run_problems(run).into_iter().map(move |p| format!("runs[{i}]{p}")))
            .collect();
        problems.extend(empty_report_problem(&report));
        problems.extend(duplicate_problems(&report, &identities));
        if !problems.is_empty() {
            let problems = problems.into_iter().map(|p| format!("{origin}: {p}")).collect();
            return Err(GateError { problems });
        }
        Ok(CheckedReport { origin, report, identities })
    }

    pub fn origin(&self) -> &str {
        &self.origin
    }

    pub fn runs(&self) -> &[RunRecord] {
        &self.report.runs
    }

    /// The identity of each run, in report order.
    pub fn identities(&self) -> &[RunIdentity] {
        &self.identities
    }
}

/// Problems of one run, each starting with its JSON path below the run (`.counts.false_lit: ...`).
fn run_problems(run: &RunRecord) -> Vec<String> {
    let c = &run.counts;
    let mut problems = Vec::new();
    if c.evaluated > c.pixels {
        problems.push(format!(".counts.evaluated: {} > pixels {}", c.evaluated, c.pixels));
    } else {
        let classes = [c.background, c.facing_away, c.outside_light, c.evaluated, c.uncertain];
        let sum: u128 = classes.iter().map(|&n| n as u128).sum();
        if sum > c.pixels as u128 {
            problems.push(format!(
                ".counts: the classes add up to {sum} > pixels {} (background + facing_away + \
                 outside_light + evaluated + uncertain)",
                c.pixels
            ));
        }
    }
    let fields = [
        ("false_shadow", c.false_shadow),
        ("false_lit", c.false_lit),
        ("surface_mismatch", c.surface_mismatch),
    ];
    for (field, count) in fields {
        if count > c.evaluated {
            problems.push(format!(".counts.{field}: {count} > evaluated {}", c.evaluated));
        }
    }
    let both = c.false_shadow as u128 + c.false_lit as u128;
    if problems.is_empty() && both > c.scored() as u128 {
        let what = if c.surface_mismatch == 0 { "evaluated" } else { "evaluated - surface_mismatch" };
        problems.push(format!(".counts: false_shadow + false_lit = {both} > {what} {}", c.scored()));
    }
    if problems.is_empty() {
        problems.extend(rate_problems(run));
    }
    if let Some(soft) = &run.soft {
        for (field, v) in [
            ("mae", soft.mae),
            ("false_shadow_mass", soft.false_shadow_mass),
            ("false_lit_mass", soft.false_lit_mass),
        ] {
            if !(0.0..=1.0).contains(&v) {
                problems.push(format!(".soft.{field}: {v} is not a number in [0, 1]"));
            }
        }
    }
    if let Some(t) = &run.temporal {
        // The rates the gate bounds (`rules.rs`), so that NaN or a count mistaken for a rate
        // cannot pass a rule.
        for (field, v) in [
            ("mean_error", t.mean_error),
            ("worst_frame_error", t.worst_frame_error),
            ("flicker_rate", t.flicker_rate),
        ] {
            if !(0.0..=1.0).contains(&v) {
                problems.push(format!(".temporal.{field}: {v} is not a number in [0, 1]"));
            }
        }
    }
    problems
}

/// Rates that are not those of the run's counts (see the module comment), each naming the field
/// and the run.
fn rate_problems(run: &RunRecord) -> Vec<String> {
    let (written, counted) = (run.rates, run.counts.rates());
    let fields = [
        ("false_shadow", written.false_shadow, counted.false_shadow),
        ("false_lit", written.false_lit, counted.false_lit),
        ("error", written.error, counted.error),
    ];
    fields
        .into_iter()
        .filter(|(_, written, counted)| written != counted)
        .map(|(field, written, counted)| {
            format!(
                ".rates.{field}: {written} is not the rate of the counts ({counted}) of {}",
                RunName::of(run)
            )
        })
        .collect()
}

/// A report with no run, or none that evaluated a pixel, has nothing to gate.
fn empty_report_problem(report: &Report) -> Option<String> {
    if report.runs.is_empty() {
        Some("runs: no run".into())
    } else if report.runs.iter().all(|r| r.counts.evaluated == 0) {
        Some(format!("runs: none of the {} runs evaluated a pixel (counts.evaluated = 0)", report.runs.len()))
    } else {
        None
    }
}

/// Two runs with one identity could not be told apart when pairing with a baseline.
fn duplicate_problems(report: &Report, identities: &[RunIdentity]) -> Vec<String> {
    let mut first: HashMap<&RunIdentity, usize> = HashMap::new();
    let mut problems = Vec::new();
    for (i, id) in identities.iter().enumerate() {
        if let Some(&j) = first.get(id) {
            problems.push(format!(
                "runs[{i}]: the same run as runs[{j}] ({}): same view, map, reference and parameters",
                RunName::of(&report.runs[j])
            ));
        } else {
            first.insert(id, i);
        }
    }
    problems
}

#[cfg(test)]
mod tests {
    use super::*;
    use shadowtruth::metrics::{Counts, SoftErrors};

    fn run(scene: &str, evaluated: u64, false_shadow: u64, false_lit: u64) -> RunRecord {
        let counts =
            Counts { pixels: evaluated + 10, evaluated, false_shadow, false_lit, ..Counts::default() };
        crate::gate::test_run(scene, "none", serde_json::json!({}), "none", counts)
    }

    fn problems(runs: Vec<RunRecord>) -> Vec<String> {
        CheckedReport::new(Report { runs, ..Report::new() }, "r.json").expect_err("inconsistent").problems
    }

    #[test]
    fn a_consistent_report_passes() {
        let ok = CheckedReport::new(Report { runs: vec![run("a", 100, 60, 40)], ..Report::new() }, "r.json");
        assert_eq!(ok.unwrap().identities().len(), 1);
    }

    #[test]
    fn counts_above_evaluated_are_named_with_their_path() {
        let p = problems(vec![run("a", 100, 0, 0), run("b", 700, 812, 0)]);
        assert_eq!(p, vec!["r.json: runs[1].counts.false_shadow: 812 > evaluated 700"]);
        let p = problems(vec![run("a", 100, 60, 41)]);
        assert_eq!(p, vec!["r.json: runs[0].counts: false_shadow + false_lit = 101 > evaluated 100"]);
        let mut over = run("a", 100, 0, 0);
        over.counts.pixels = 99;
        assert_eq!(problems(vec![over]), vec!["r.json: runs[0].counts.evaluated: 100 > pixels 99"]);
    }

    #[test]
    fn rates_that_are_not_those_of_the_counts_are_rejected() {
        let mut edited = run("b", 700, 70, 7);
        edited.rates.error = 0.01;
        let p = problems(vec![run("a", 100, 0, 0), edited]);
        assert_eq!(p.len(), 1, "{p:?}");
        let expected =
            format!("r.json: runs[1].rates.error: 0.01 is not the rate of the counts ({})", 77.0 / 700.0);
        assert!(p[0].starts_with(&expected), "{p:?}");
        assert!(p[0].contains("b/main/sun"), "{p:?}");
        // A third that does not round-trip exactly still passes when written by `Counts::rates`.
        let third = run("c", 3, 1, 0);
        let text = serde_json::to_string(&Report { runs: vec![third], ..Report::new() }).unwrap();
        let read: Report = serde_json::from_str(&text).unwrap();
        assert!(CheckedReport::new(read, "r.json").is_ok());
    }

    #[test]
    fn soft_errors_outside_zero_one_are_rejected() {
        let mut r = run("a", 100, 0, 0);
        r.soft = Some(SoftErrors { mae: 1.5, false_shadow_mass: 0.5, false_lit_mass: -0.1 });
        let p = problems(vec![r]);
        assert_eq!(p.len(), 2, "{p:?}");
        assert!(p[0].starts_with("r.json: runs[0].soft.mae: 1.5"), "{p:?}");
        assert!(p[1].starts_with("r.json: runs[0].soft.false_lit_mass"), "{p:?}");
    }

    #[test]
    fn empty_reports_and_duplicates_are_rejected() {
        assert_eq!(problems(vec![]), vec!["r.json: runs: no run"]);
        let p = problems(vec![run("a", 0, 0, 0), run("b", 0, 0, 0)]);
        assert!(p[0].contains("runs: none of the 2 runs evaluated a pixel"), "{p:?}");
        let mut relabelled = run("a", 100, 0, 0);
        relabelled.label = "none()".into();
        let p = problems(vec![run("a", 100, 0, 0), run("b", 100, 0, 0), relabelled]);
        assert_eq!(p.len(), 1, "{p:?}");
        assert!(p[0].starts_with("r.json: runs[2]: the same run as runs[0] (a/main/sun none @1024"), "{p:?}");
    }
}
