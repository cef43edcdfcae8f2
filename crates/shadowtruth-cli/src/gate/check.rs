//! Evaluating rules: each rule against the runs it matches (an absolute bound, and a regression
//! bound against the paired baseline run), and every baseline run paired or listed missing.
//!
//! Exactness: the rates `false_shadow`, `false_lit` and `error` are recomputed from the integer
//! counts; a regression bound on them, when the run and its baseline evaluated the same number
//! of pixels, is an integer comparison of counts (the slack, in pixels, is rounded down), so a
//! regression of one pixel fails a rule with zero slack.

use super::GateError;
use super::identity::{Pairing, RunName};
use super::input::CheckedReport;
use super::rules::{Metric, Regression, Rule, Rules};
use shadowtruth::record::RunRecord;
use std::collections::{BTreeMap, BTreeSet};

/// A metric's value for one run, with the pixel counts behind it when it is a hard rate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measured {
    pub value: f64,
    /// Pixels counted (false shadow, false lit or both) for the hard rates.
    pub count: Option<u64>,
    /// The pixels a hard rate is over: the evaluated ones (and the uncertain ones too for
    /// `reference_uncertain`).
    pub evaluated: u64,
}

/// The value of `metric` for `run`, or `None` if the run does not carry it. Hard rates come from
/// the counts; the soft metrics from the run's `soft` errors and the metrics of a run over a
/// path from its `temporal` record (`Metric::soft` and `Metric::temporal` name their fields).
pub fn measure(run: &RunRecord, metric: Metric) -> Option<Measured> {
    let evaluated = run.counts.evaluated;
    let uncertain = run.counts.uncertain;
    match metric {
        // Over the pixels the reference was asked about: evaluated ones and uncertain ones.
        Metric::ReferenceUncertain => {
            let asked = evaluated.saturating_add(uncertain);
            let value = if asked == 0 { 0.0 } else { uncertain as f64 / asked as f64 };
            return Some(Measured { value, count: Some(uncertain), evaluated: asked });
        }
        Metric::ReferenceUncertainPx => {
            return Some(Measured { value: uncertain as f64, count: None, evaluated });
        }
        _ => {}
    }
    if let Some(count) = metric.count(run) {
        let value = if evaluated == 0 { 0.0 } else { count as f64 / evaluated as f64 };
        return Some(Measured { value, count: Some(count), evaluated });
    }
    let value = match metric.temporal(run) {
        Some(value) => value,
        // A report holds no soft value that is not finite (JSON has none): such a value in
        // memory is as absent.
        None => metric.soft(run)?.filter(|v| v.is_finite()),
    };
    value.map(|value| Measured { value, count: None, evaluated })
}

/// A bound a checked pair broke.
#[derive(Clone, Debug, PartialEq)]
pub enum Violation {
    /// value > max.
    Max { limit: f64 },
    /// value > baseline + slack. `limit_count` is the allowed pixel count when the comparison
    /// was made on counts.
    Regression { baseline: Measured, limit: f64, limit_count: Option<u64> },
}

/// How a regression bound was applied to a pair.
#[derive(Clone, Debug, PartialEq)]
pub enum BaselineStatus {
    /// The rule has no regression bound.
    NotChecked,
    /// The run is absent from the baseline: new, no regression check.
    New,
    /// Compared with this baseline value against this limit (and pixel count limit).
    Compared { baseline: Measured, limit: f64, limit_count: Option<u64> },
}

/// One (rule, run) pair.
#[derive(Clone, Debug, PartialEq)]
pub struct Check {
    /// Index of the rule in its file.
    pub rule: usize,
    pub rule_name: String,
    pub metric: Metric,
    /// Index of the run in the report.
    pub run_index: usize,
    pub run: RunName,
    pub measured: Measured,
    pub max: Option<f64>,
    pub baseline: BaselineStatus,
    pub violations: Vec<Violation>,
}

impl Check {
    pub fn passed(&self) -> bool {
        self.violations.is_empty()
    }
}

/// How a gate treats what the baseline and the report do not share.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GateOptions {
    /// Baseline runs missing from the report are warnings instead of violations (for a change
    /// that removes or renames runs on purpose).
    pub allow_missing: bool,
}

/// How the runs of the report paired with those of the baseline.
#[derive(Clone, Debug, PartialEq)]
pub struct BaselineComparison {
    /// Runs of the report paired with a baseline run.
    pub paired: usize,
    /// Baseline runs absent from the report, in baseline order.
    pub missing: Vec<RunName>,
    /// Runs of the report absent from the baseline, in report order.
    pub new_runs: Vec<RunName>,
    /// Whether missing runs are warnings rather than violations.
    pub allow_missing: bool,
}

impl BaselineComparison {
    /// Missing runs that count as violations.
    pub fn violations(&self) -> usize {
        if self.allow_missing { 0 } else { self.missing.len() }
    }
}

/// The result of a gate.
#[derive(Clone, Debug, PartialEq)]
pub struct GateOutcome {
    pub rules: usize,
    /// Distinct runs of the report matched by at least one rule.
    pub runs_checked: usize,
    /// Every (rule, run) pair, in rule order then report order.
    pub checks: Vec<Check>,
    /// The pairing with the baseline, when there is one.
    pub baseline: Option<BaselineComparison>,
}

impl GateOutcome {
    /// Broken bounds, plus baseline runs missing from the report unless they are allowed.
    pub fn violations(&self) -> usize {
        let bounds: usize = self.checks.iter().map(|c| c.violations.len()).sum();
        bounds + self.baseline.as_ref().map_or(0, BaselineComparison::violations)
    }

    pub fn failed_checks(&self) -> usize {
        self.checks.iter().filter(|c| !c.passed()).count()
    }

    pub fn passed(&self) -> bool {
        self.violations() == 0
    }
}

/// The baseline with the pairing of its runs to the report's.
struct Baseline<'a> {
    report: &'a CheckedReport,
    pairing: Pairing,
}

impl<'a> Baseline<'a> {
    fn new(report: &CheckedReport, baseline: &'a CheckedReport) -> Self {
        Baseline { report: baseline, pairing: Pairing::new(report.identities(), baseline.identities()) }
    }

    /// The baseline run paired with run `i` of the report, with its index.
    fn partner(&self, i: usize) -> Option<(usize, &'a RunRecord)> {
        self.pairing.partner[i].map(|b| (b, &self.report.runs()[b]))
    }

    fn comparison(&self, report: &CheckedReport, options: GateOptions) -> BaselineComparison {
        BaselineComparison {
            paired: self.pairing.paired(),
            missing: self.pairing.missing.iter().map(|&b| RunName::of(&self.report.runs()[b])).collect(),
            new_runs: self.pairing.new_runs().map(|i| RunName::of(&report.runs()[i])).collect(),
            allow_missing: options.allow_missing,
        }
    }
}

/// Checks every rule against the runs it matches and pairs every run with the baseline. Bad
/// input is an error listing every problem: a rule that matches no run, a regression rule
/// without a baseline or that pairs none of its runs with it, a metric a run lacks, a matched run
/// that evaluated no pixel. Violations (and missing baseline runs) are part of the outcome.
pub fn evaluate(
    report: &CheckedReport,
    baseline: Option<&CheckedReport>,
    rules: &Rules,
    options: GateOptions,
) -> Result<GateOutcome, GateError> {
    let baseline = baseline.map(|b| Baseline::new(report, b));
    let mut problems = Vec::new();
    let mut checks = Vec::new();
    for (index, rule) in rules.rules.iter().enumerate() {
        match check_rule(index, rule, report, baseline.as_ref()) {
            Ok(mut c) => checks.append(&mut c),
            Err(p) => problems.extend(p.into_iter().map(|p| format!("{}: {p}", rule_at(rules, index)))),
        }
    }
    if !problems.is_empty() {
        return Err(GateError { problems });
    }
    let runs_checked = checks.iter().map(|c| c.run_index).collect::<BTreeSet<_>>().len();
    Ok(GateOutcome {
        rules: rules.rules.len(),
        runs_checked,
        checks,
        baseline: baseline.map(|b| b.comparison(report, options)),
    })
}

/// `rules.toml: rule[2] "name"`
fn rule_at(rules: &Rules, index: usize) -> String {
    format!("{}: rule[{index}] \"{}\"", rules.origin, rules.rules[index].name)
}

/// Why a matched run cannot be checked (bad input, not a violation).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Unusable {
    NoValue,
    NoBaselineValue,
    NothingEvaluated,
    NothingEvaluatedInBaseline,
}

/// The checks of one rule, or its problems (without the rule's name).
fn check_rule(
    index: usize,
    rule: &Rule,
    report: &CheckedReport,
    baseline: Option<&Baseline>,
) -> Result<Vec<Check>, Vec<String>> {
    if rule.regression.is_some() && baseline.is_none() {
        return Err(vec!["a regression bound (max_increase, max_increase_ratio) needs --baseline".into()]);
    }
    let matched: Vec<usize> = (0..report.runs().len()).filter(|&i| rule.matches(&report.runs()[i])).collect();
    if matched.is_empty() {
        let runs = report.runs().len();
        return Err(vec![format!("matches no run of the report ({runs} runs; selects {})", rule.selector())]);
    }
    let mut checks = Vec::new();
    let mut unusable: BTreeMap<Unusable, Vec<usize>> = BTreeMap::new();
    for &i in &matched {
        match check_run(index, rule, i, report, baseline) {
            Ok(c) => checks.push(c),
            Err(why) => unusable.entry(why).or_default().push(i),
        }
    }
    let mut problems: Vec<String> = unusable
        .iter()
        .map(|(&why, runs)| unusable_problem(why, runs, matched.len(), rule.metric, report, baseline))
        .collect();
    let compared_none = checks.iter().all(|c| c.baseline == BaselineStatus::New);
    if let Some(b) = baseline
        && rule.regression.is_some()
        && problems.is_empty()
        && compared_none
    {
        problems.push(format!(
            "none of its {} matched runs is in the baseline {}: its regression bound compares nothing",
            matched.len(),
            b.report.origin()
        ));
    }
    if problems.is_empty() { Ok(checks) } else { Err(problems) }
}

/// `n of m matched runs ...`, naming the first such run with its file and JSON path.
fn unusable_problem(
    why: Unusable,
    runs: &[usize],
    matched: usize,
    metric: Metric,
    report: &CheckedReport,
    baseline: Option<&Baseline>,
) -> String {
    let n = runs.len();
    let first = runs[0];
    let what = match why {
        Unusable::NoValue => format!("metric: {n} of {matched} matched runs have no {metric} value"),
        Unusable::NoBaselineValue => {
            format!(
                "metric: {n} of {matched} matched runs pair with a baseline run that has no {metric} value"
            )
        }
        Unusable::NothingEvaluated => {
            format!("{n} of {matched} matched runs evaluated no pixel, nothing to check")
        }
        Unusable::NothingEvaluatedInBaseline => format!(
            "{n} of {matched} matched runs pair with a baseline run that evaluated no pixel, nothing to compare"
        ),
    };
    let in_baseline = matches!(why, Unusable::NoBaselineValue | Unusable::NothingEvaluatedInBaseline);
    let from_baseline = baseline
        .filter(|_| in_baseline)
        .and_then(|b| b.partner(first).map(|(j, run)| (b.report.origin(), j, run)));
    let (origin, index, run) = from_baseline.unwrap_or((report.origin(), first, &report.runs()[first]));
    let field = match why {
        Unusable::NothingEvaluated | Unusable::NothingEvaluatedInBaseline => ".counts.evaluated = 0",
        Unusable::NoValue | Unusable::NoBaselineValue => "",
    };
    format!("{what} (first: {origin}: runs[{index}]{field}, {})", RunName::of(run))
}

/// One (rule, run) pair: the absolute bound, and the regression bound against its partner.
fn check_run(
    index: usize,
    rule: &Rule,
    i: usize,
    report: &CheckedReport,
    baseline: Option<&Baseline>,
) -> Result<Check, Unusable> {
    let run = &report.runs()[i];
    if run.counts.evaluated == 0 {
        return Err(Unusable::NothingEvaluated);
    }
    let measured = measure(run, rule.metric).ok_or(Unusable::NoValue)?;
    let mut violations = Vec::new();
    if let Some(limit) = rule.max
        && measured.value > limit
    {
        violations.push(Violation::Max { limit });
    }
    let mut status = BaselineStatus::NotChecked;
    if let (Some(reg), Some(b)) = (&rule.regression, baseline) {
        let (s, violation) = regression(reg, rule.metric, &measured, b.partner(i).map(|(_, r)| r))?;
        status = s;
        violations.extend(violation);
    }
    Ok(Check {
        rule: index,
        rule_name: rule.name.clone(),
        metric: rule.metric,
        run_index: i,
        run: RunName::of(run),
        measured,
        max: rule.max,
        baseline: status,
        violations,
    })
}

/// The regression bound against the partner: new without one.
fn regression(
    reg: &Regression,
    metric: Metric,
    measured: &Measured,
    partner: Option<&RunRecord>,
) -> Result<(BaselineStatus, Option<Violation>), Unusable> {
    let Some(base_run) = partner else {
        return Ok((BaselineStatus::New, None));
    };
    if base_run.counts.evaluated == 0 {
        return Err(Unusable::NothingEvaluatedInBaseline);
    }
    let base = measure(base_run, metric).ok_or(Unusable::NoBaselineValue)?;
    let (limit, limit_count, violated) = regression_check(measured, &base, reg);
    let violation = violated.then_some(Violation::Regression { baseline: base, limit, limit_count });
    Ok((BaselineStatus::Compared { baseline: base, limit, limit_count }, violation))
}

/// (limit as a value, limit as a pixel count when counts are compared, violated?)
///
/// With pixel counts on both sides over the same number of evaluated pixels the bound is
/// `count ≤ base_count + ⌊slack · evaluated⌋` (slack = max(increase, base · ratio) as a rate;
/// a 1e-6-pixel allowance absorbs the rounding of `slack · evaluated`), so one pixel over a zero
/// slack fails. Otherwise the rates are compared: `value ≤ base + slack`.
fn regression_check(value: &Measured, base: &Measured, reg: &Regression) -> (f64, Option<u64>, bool) {
    let limit = base.value + reg.slack(base.value);
    match (value.count, base.count) {
        (Some(c), Some(b)) if value.evaluated == base.evaluated && value.evaluated > 0 => {
            let n = value.evaluated as f64;
            let slack_px = (reg.increase * n).max(b as f64 * reg.ratio);
            let allowed = b.saturating_add((slack_px + 1e-6).floor().min(u64::MAX as f64) as u64);
            (limit, Some(allowed), c > allowed)
        }
        _ => (limit, None, value.value > limit),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gate::rules::parse_rules;
    use shadowtruth::metrics::Counts;
    use shadowtruth::record::Report;

    fn run(scene: &str, evaluated: u64, fs: u64, fl: u64) -> RunRecord {
        let counts =
            Counts { pixels: evaluated, evaluated, false_shadow: fs, false_lit: fl, ..Counts::default() };
        crate::gate::test_run(
            scene,
            "constant",
            serde_json::json!({"bias_depth": 0.001}),
            "constant(bias_depth=0.001)",
            counts,
        )
    }

    fn report(runs: Vec<RunRecord>) -> CheckedReport {
        CheckedReport::new(Report { runs, ..Report::new() }, "report.json").unwrap_or_else(|e| panic!("{e}"))
    }

    fn rules(text: &str) -> Rules {
        parse_rules(text, "rules.toml").unwrap_or_else(|e| panic!("{e}"))
    }

    fn gate(now: &CheckedReport, base: Option<&CheckedReport>, text: &str) -> Result<GateOutcome, GateError> {
        evaluate(now, base, &rules(text), GateOptions::default())
    }

    const ZERO_SLACK: &str = "[[rule]]\nmetric = \"false_shadow\"\nmax_increase = 0\n";

    #[test]
    fn soft_metric_names_are_accepted_but_a_run_without_them_is_bad_input() {
        let e = gate(&report(vec![run("s", 100, 0, 0)]), None, "[[rule]]\nmetric = \"mae\"\nmax = 0.1\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("rules.toml: rule[0]") && e.contains("1 of 1 matched runs have no mae value"),
            "{e}"
        );
    }

    #[test]
    fn temporal_metrics_are_read_from_the_path_and_a_run_without_one_is_bad_input() {
        let mut over_path = run("path", 100, 1, 0);
        over_path.temporal = Some(shadowtruth::record::TemporalRecord {
            frames: 3,
            moving: "light".into(),
            frame_errors: vec![0.0, 0.03, 0.0],
            frame_flicker: vec![0, 4, 2],
            mean_error: 0.01,
            worst_frame: 1,
            worst_frame_error: 0.03,
            flicker_rate: 0.03,
            flicker_pixels: 6,
            compared_pixels: 200,
        });
        let now = report(vec![over_path, run("still", 100, 1, 0)]);
        let on_path = |metric: &str, max: f64| {
            let text = format!("[[rule]]\nscene = \"path\"\nmetric = \"{metric}\"\nmax = {max}\n");
            gate(&now, None, &text).unwrap()
        };
        assert!(on_path("flicker_rate", 0.03).passed(), "the bound is inclusive");
        let out = on_path("flicker_rate", 0.029);
        assert!(!out.passed());
        assert_eq!(out.checks[0].measured, Measured { value: 0.03, count: None, evaluated: 100 });
        assert!(on_path("worst_frame_error", 0.03).passed() && !on_path("worst_frame_error", 0.02).passed());
        assert!(on_path("mean_frame_error", 0.01).passed() && !on_path("mean_frame_error", 0.009).passed());
        let e = gate(&now, None, "[[rule]]\nmetric = \"flicker_rate\"\nmax = 1\n").unwrap_err().to_string();
        assert!(e.contains("1 of 2 matched runs have no flicker_rate value") && e.contains("runs[1]"), "{e}");
    }

    /// A run of a view whose reference left `uncertain` of its 1000 pixels undecided.
    fn run_uncertain(scene: &str, uncertain: u64) -> RunRecord {
        let mut r = run(scene, 1000 - uncertain, 2, 1);
        r.counts.pixels = 1000;
        r.counts.uncertain = uncertain;
        r
    }

    #[test]
    fn reference_uncertain_bounds_the_undecided_pixels_of_the_view() {
        let now = report(vec![run_uncertain("rocks", 3), run_uncertain("plane_box", 0)]);
        let rule = |metric: &str, max: f64| format!("[[rule]]\nmetric = \"{metric}\"\nmax = {max}\n");
        // As a count: 3 pixels pass a bound of 3 (inclusive) and fail one of 2.
        let out = gate(&now, None, &rule("reference_uncertain_px", 3.0)).unwrap();
        assert!(out.passed(), "{}", out.text());
        let out = gate(&now, None, &rule("reference_uncertain_px", 2.0)).unwrap();
        assert_eq!(out.violations(), 1, "{}", out.text());
        assert!(out.text().contains("rocks/main/sun"), "{}", out.text());
        // As a fraction of the evaluated and uncertain pixels: 3 of 1000.
        let out = gate(&now, None, &rule("reference_uncertain", 0.003)).unwrap();
        assert!(out.passed(), "{}", out.text());
        assert_eq!(out.checks[0].measured, Measured { value: 0.003, count: Some(3), evaluated: 1000 });
        assert_eq!(out.checks[0].measured.show(), "0.003 (3 of 1000 px)");
        let out = gate(&now, None, &rule("reference_uncertain", 0.0029)).unwrap();
        assert!(!out.passed() && out.violations() == 1, "{}", out.text());
        // Against a baseline: one more undecided pixel fails a zero slack, as a count or a rate.
        let base = report(vec![run_uncertain("rocks", 3), run_uncertain("plane_box", 0)]);
        let worse = report(vec![run_uncertain("rocks", 4), run_uncertain("plane_box", 0)]);
        for metric in ["reference_uncertain", "reference_uncertain_px"] {
            let zero = format!("[[rule]]\nmetric = \"{metric}\"\nmax_increase = 0\n");
            assert!(gate(&base, Some(&base), &zero).unwrap().passed(), "{metric}");
            let out = gate(&worse, Some(&base), &zero).unwrap();
            assert_eq!(out.violations(), 1, "{metric}: {}", out.text());
        }
    }

    #[test]
    fn a_report_written_before_uncertain_pixels_were_counted_reads_none() {
        let mut json = serde_json::to_value(run("s", 100, 1, 0)).unwrap();
        json["counts"].as_object_mut().unwrap().remove("uncertain");
        let old: RunRecord = serde_json::from_value(json).unwrap();
        let out = gate(&report(vec![old]), None, "[[rule]]\nmetric = \"reference_uncertain_px\"\nmax = 0\n")
            .unwrap();
        assert!(out.passed(), "{}", out.text());
    }

    #[test]
    fn absolute_bound_is_inclusive_and_exact() {
        let rep = report(vec![run("a", 1000, 1, 0), run("b", 1000, 2, 0)]);
        let out = gate(&rep, None, "[[rule]]\nmetric = \"false_shadow\"\nmax = 0.001\n").unwrap();
        assert_eq!(out.checks.len(), 2);
        assert!(out.checks[0].passed(), "1 of 1000 is exactly 0.001");
        assert!(!out.checks[1].passed());
        assert_eq!(out.violations(), 1);
        assert_eq!(out.runs_checked, 2);
        let text = out.text();
        assert!(text.contains("b/main/sun constant(bias_depth=0.001) @1024 f32 [hard×1]"), "{text}");
        assert!(text.ends_with("1 rules, 2 runs checked, 1 violations\n"), "{text}");
    }

    #[test]
    fn one_pixel_regression_is_caught_with_zero_slack_only() {
        let n = 786_432; // 1024 × 768: one pixel is 1.3e-6 of the rate
        let base = report(vec![run("s", n, 1000, 500)]);
        let now = report(vec![run("s", n, 1001, 500)]);
        for (metric, fails) in [("false_shadow", true), ("false_lit", false), ("error", true)] {
            let zero = format!("[[rule]]\nmetric = \"{metric}\"\nmax_increase = 0\n");
            let out = gate(&now, Some(&base), &zero).unwrap();
            assert_eq!(!out.passed(), fails, "{metric}: {}", out.text());
            let one_px = format!("[[rule]]\nmetric = \"{metric}\"\nmax_increase = {}\n", 1.0 / n as f64);
            assert!(gate(&now, Some(&base), &one_px).unwrap().passed(), "{metric} with one pixel of slack");
        }
        // Relative slack: 0.1 % of 1000 pixels is one pixel.
        let ratio = "[[rule]]\nmetric = \"false_shadow\"\nmax_increase_ratio = 0.001\n";
        assert!(gate(&now, Some(&base), ratio).unwrap().passed());
        let both = "[[rule]]\nmetric = \"false_shadow\"\nmax_increase = 0\nmax_increase_ratio = 0.0005\n";
        assert!(!gate(&now, Some(&base), both).unwrap().passed());
    }

    #[test]
    fn different_evaluated_counts_fall_back_to_rates() {
        let base = report(vec![run("s", 1000, 10, 0)]);
        let better = report(vec![run("s", 2000, 19, 0)]);
        let worse = report(vec![run("s", 2000, 21, 0)]);
        assert!(gate(&better, Some(&base), ZERO_SLACK).unwrap().passed());
        let out = gate(&worse, Some(&base), ZERO_SLACK).unwrap();
        assert!(matches!(out.checks[0].violations[0], Violation::Regression { limit_count: None, .. }));
    }

    #[test]
    fn runs_absent_from_the_baseline_are_new_and_all_listed() {
        let base = report(vec![run("s", 100, 1, 0)]);
        let now = report(vec![run("s", 100, 1, 0), run("t", 100, 50, 0), run("uu", 100, 0, 0)]);
        // The rule checks s and t only; uu is new all the same.
        let one_letter = "[[rule]]\nscene = \"?\"\nmetric = \"false_shadow\"\nmax_increase = 0\n";
        let out = gate(&now, Some(&base), one_letter).unwrap();
        assert_eq!(out.runs_checked, 2);
        assert!(out.passed(), "{}", out.text());
        let b = out.baseline.as_ref().unwrap();
        assert_eq!((b.paired, b.missing.len()), (1, 0));
        let new: Vec<&str> = b.new_runs.iter().map(|r| r.scene.as_str()).collect();
        assert_eq!(new, ["t", "uu"]);
        assert_eq!(out.checks[1].status(), "pass (new)");
        assert!(out.text().contains("new: t/main/sun constant(bias_depth=0.001) @1024 f32 [hard×1]"));
        assert!(out.text().ends_with("; baseline: 1 paired, 0 missing, 2 new\n"), "{}", out.text());
    }

    #[test]
    fn baseline_runs_missing_from_the_report_are_violations_whatever_the_rules() {
        let base = report(vec![run("s", 100, 1, 0), run("gone", 100, 1, 0)]);
        let now = report(vec![run("s", 100, 1, 0)]);
        let absolute = "[[rule]]\nmetric = \"error\"\nmax = 0.5\n";
        let out = gate(&now, Some(&base), absolute).unwrap();
        assert!(!out.passed());
        assert_eq!(out.violations(), 1);
        let text = out.text();
        let gone = "gone/main/sun constant(bias_depth=0.001) @1024 f32 [hard×1]";
        assert!(text.contains(&format!("missing: {gone}: in the baseline, not in the report\n")), "{text}");
        assert!(
            text.ends_with("1 rules, 1 runs checked, 1 violations; baseline: 1 paired, 1 missing, 0 new\n"),
            "{text}"
        );

        let allowed =
            evaluate(&now, Some(&base), &rules(absolute), GateOptions { allow_missing: true }).unwrap();
        assert!(allowed.passed());
        let text = allowed.text();
        assert!(text.starts_with("warning: missing: gone/main/sun"), "{text}");
        assert!(text.ends_with("0 violations; baseline: 1 paired, 1 missing (allowed), 0 new\n"), "{text}");
    }

    #[test]
    fn a_regression_rule_pairing_nothing_is_bad_input() {
        let base = report(vec![run("old", 100, 1, 0)]);
        let now = report(vec![run("new", 100, 1, 0)]);
        let e = gate(&now, Some(&base), ZERO_SLACK).unwrap_err().to_string();
        assert!(
            e.contains("rules.toml: rule[0]")
                && e.contains("none of its 1 matched runs is in the baseline report.json"),
            "{e}"
        );
        // An absolute rule still runs, and the missing run fails the gate.
        let out = gate(&now, Some(&base), "[[rule]]\nmetric = \"error\"\nmax = 1\n").unwrap();
        assert!(!out.passed());
    }

    #[test]
    fn a_matched_run_that_evaluated_nothing_is_bad_input() {
        let now = report(vec![run("s", 100, 1, 0), run("empty", 0, 0, 0)]);
        let e = gate(&now, None, "[[rule]]\nmetric = \"error\"\nmax = 1\n").unwrap_err().to_string();
        assert!(
            e.contains("rule[0]")
                && e.contains("1 of 2 matched runs evaluated no pixel")
                && e.contains("report.json: runs[1].counts.evaluated = 0"),
            "{e}"
        );
        assert!(gate(&now, None, "[[rule]]\nscene = \"s\"\nmetric = \"error\"\nmax = 1\n").is_ok());
        let base = report(vec![run("s", 0, 0, 0), run("t", 10, 0, 0)]);
        let e = gate(&report(vec![run("s", 100, 1, 0)]), Some(&base), ZERO_SLACK).unwrap_err().to_string();
        assert!(e.contains("baseline run that evaluated no pixel") && e.contains("runs[0]"), "{e}");
    }

    #[test]
    fn bad_input_is_collected() {
        let now = report(vec![run("s", 100, 1, 0)]);
        let two = "[[rule]]\nscene = \"nowhere\"\nmetric = \"error\"\nmax = 0\n\
                   [[rule]]\nmetric = \"error\"\nmax_increase = 0\n";
        let e = gate(&now, None, two).unwrap_err();
        assert_eq!(e.problems.len(), 2, "{e}");
        assert!(e.problems[0].contains("rules.toml: rule[0]") && e.problems[0].contains("matches no run"));
        assert!(e.problems[1].contains("rule[1]") && e.problems[1].contains("--baseline"));
    }
}
