//! The gate: rules (glob patterns on the runs of a report, an absolute bound on a metric and/or a
//! bound on its regression against a baseline report) → checks and violations.
//!
//! Reading a rules file ([`parse_rules`], [`load_rules`]) and a report ([`load_report`]) are the
//! only I/O here; [`evaluate`] is a pure function of the report, the optional baseline and the
//! rules, and the text and Markdown outputs are pure too (the CLI writes them).
//!
//! Rules file (TOML), every key but `metric` and one bound optional:
//!
//! ```toml
//! [[rule]]
//! name = "no acne on the bundled suite"  # default: a description of the rule
//! scene = "*"                            # globs (`*`, `?`) on scene, camera, light, technique, label
//! technique = "slope_scaled"
//! resolution = 2048                      # exact match
//! depth_format = "f32"                   # exact match
//! metric = "false_shadow"                # false_shadow, false_lit, error, mae, false_shadow_mass, false_lit_mass
//! max = 0.001                            # value ≤ max
//! max_increase = 0.0                     # value ≤ baseline + max(max_increase, baseline · max_increase_ratio)
//! max_increase_ratio = 0.05
//! ```
//!
//! Exactness: the rates `false_shadow`, `false_lit` and `error` are recomputed from the integer
//! counts; a regression bound on them, when the run and its baseline evaluated the same number
//! of pixels, is an integer comparison of counts (the slack, in pixels, is rounded down), so a
//! regression of one pixel fails a rule with zero slack.

use super::record::{Report, RunRecord};
use serde::{Deserialize, Serialize};
use std::collections::{BTreeSet, HashMap};
use std::fmt;
use std::path::{Path, PathBuf};

/// The metrics a rule may bound. The first three are rates of the evaluated pixels computed from
/// the run's counts; the soft metrics are read from the run when its report carries them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Metric {
    FalseShadow,
    FalseLit,
    Error,
    Mae,
    FalseShadowMass,
    FalseLitMass,
}

impl Metric {
    pub const ALL: [Metric; 6] = [
        Metric::FalseShadow,
        Metric::FalseLit,
        Metric::Error,
        Metric::Mae,
        Metric::FalseShadowMass,
        Metric::FalseLitMass,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Metric::FalseShadow => "false_shadow",
            Metric::FalseLit => "false_lit",
            Metric::Error => "error",
            Metric::Mae => "mae",
            Metric::FalseShadowMass => "false_shadow_mass",
            Metric::FalseLitMass => "false_lit_mass",
        }
    }

    /// The pixel count behind a hard rate (`None` for the soft metrics).
    fn count(self, run: &RunRecord) -> Option<u64> {
        let c = &run.counts;
        match self {
            Metric::FalseShadow => Some(c.false_shadow),
            Metric::FalseLit => Some(c.false_lit),
            Metric::Error => Some(c.false_shadow + c.false_lit),
            _ => None,
        }
    }
}

impl fmt::Display for Metric {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// One `[[rule]]` table as written; every field optional so that each problem can be reported
/// with its field. [`Rule`] is the validated form.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RuleSpec {
    pub name: Option<String>,
    pub scene: Option<String>,
    pub camera: Option<String>,
    pub light: Option<String>,
    pub technique: Option<String>,
    pub label: Option<String>,
    pub resolution: Option<u32>,
    pub depth_format: Option<String>,
    pub metric: Option<Metric>,
    pub max: Option<f64>,
    pub max_increase: Option<f64>,
    pub max_increase_ratio: Option<f64>,
}

/// A validated rule: patterns default to `*`, the metric is known, at least one bound is given.
#[derive(Clone, Debug, PartialEq)]
pub struct Rule {
    pub name: String,
    pub scene: String,
    pub camera: String,
    pub light: String,
    pub technique: String,
    pub label: String,
    pub resolution: Option<u32>,
    pub depth_format: Option<String>,
    pub metric: Metric,
    /// Absolute bound: value ≤ max.
    pub max: Option<f64>,
    /// Regression bound against the baseline, see [`Regression`].
    pub regression: Option<Regression>,
}

/// value ≤ baseline + max(increase, baseline · ratio): with both slacks given the looser holds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Regression {
    pub increase: f64,
    pub ratio: f64,
}

impl Regression {
    /// The allowed increase over a baseline value.
    pub fn slack(&self, baseline: f64) -> f64 {
        self.increase.max(baseline * self.ratio)
    }
}

impl Rule {
    pub fn matches(&self, run: &RunRecord) -> bool {
        glob_match(&self.scene, &run.scene)
            && glob_match(&self.camera, &run.camera)
            && glob_match(&self.light, &run.light)
            && glob_match(&self.technique, &run.technique)
            && glob_match(&self.label, &run.label)
            && self.resolution.is_none_or(|r| r == run.resolution)
            && self.depth_format.as_ref().is_none_or(|f| *f == run.depth_format)
    }

    /// The patterns that are not `*`, e.g. `technique=slope_scaled resolution=2048`.
    fn selector(&self) -> String {
        let mut parts: Vec<String> = [
            ("scene", &self.scene),
            ("camera", &self.camera),
            ("light", &self.light),
            ("technique", &self.technique),
            ("label", &self.label),
        ]
        .into_iter()
        .filter(|(_, p)| p.as_str() != "*")
        .map(|(k, p)| format!("{k}={p}"))
        .collect();
        if let Some(r) = self.resolution {
            parts.push(format!("resolution={r}"));
        }
        if let Some(f) = &self.depth_format {
            parts.push(format!("depth_format={f}"));
        }
        if parts.is_empty() { "all runs".into() } else { parts.join(" ") }
    }

    fn describe(&self) -> String {
        let mut bounds = Vec::new();
        if let Some(m) = self.max {
            bounds.push(format!("{} ≤ {}", self.metric, fmt_value(m)));
        }
        if let Some(r) = &self.regression {
            bounds.push(format!("{} regression ≤ {}", self.metric, describe_slack(r)));
        }
        format!("{}: {}", self.selector(), bounds.join(", "))
    }
}

fn describe_slack(r: &Regression) -> String {
    let (i, q) = (r.increase, r.ratio);
    if q == 0.0 {
        fmt_value(i)
    } else if i == 0.0 {
        format!("{}·baseline", fmt_value(q))
    } else {
        format!("max({}, {}·baseline)", fmt_value(i), fmt_value(q))
    }
}

/// The rules of one file; `origin` (the file as named on the command line) prefixes messages.
#[derive(Clone, Debug, PartialEq)]
pub struct Rules {
    pub origin: String,
    pub rules: Vec<Rule>,
}

/// Bad input: every problem found, each naming its file and field.
#[derive(Clone, Debug, PartialEq)]
pub struct GateError {
    pub problems: Vec<String>,
}

impl GateError {
    fn one(message: String) -> Self {
        GateError { problems: vec![message] }
    }
}

impl fmt::Display for GateError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.problems.join("\n"))
    }
}

impl std::error::Error for GateError {}

/// `*` matches any run of characters (also none), `?` exactly one; all else matches itself.
pub fn glob_match(pattern: &str, text: &str) -> bool {
    let p: Vec<char> = pattern.chars().collect();
    let t: Vec<char> = text.chars().collect();
    let (mut pi, mut ti) = (0, 0);
    let mut star: Option<(usize, usize)> = None;
    while ti < t.len() {
        if pi < p.len() && (p[pi] == '?' || (p[pi] != '*' && p[pi] == t[ti])) {
            pi += 1;
            ti += 1;
        } else if pi < p.len() && p[pi] == '*' {
            star = Some((pi, ti));
            pi += 1;
        } else if let Some((sp, st)) = star {
            pi = sp + 1;
            ti = st + 1;
            star = Some((sp, st + 1));
        } else {
            return false;
        }
    }
    p[pi..].iter().all(|&c| c == '*')
}

/// Parses a rules file's text; `origin` names it in messages.
pub fn parse_rules(text: &str, origin: &str) -> Result<Rules, GateError> {
    let table: toml::Table = text.parse().map_err(|e: toml::de::Error| {
        GateError::one(format!("{origin}: not valid TOML: {}", e.to_string().trim_end()))
    })?;
    let mut problems = Vec::new();
    for key in table.keys().filter(|k| k.as_str() != "rule") {
        problems.push(format!("{origin}: {key}: unknown key (the file holds [[rule]] tables only)"));
    }
    let entries: &[toml::Value] = match table.get("rule") {
        None => &[],
        Some(toml::Value::Array(a)) => a,
        Some(_) => {
            problems.push(format!("{origin}: rule: expected an array of [[rule]] tables"));
            &[]
        }
    };
    if entries.is_empty() && problems.is_empty() {
        problems.push(format!("{origin}: no [[rule]] in the file"));
    }
    let mut rules = Vec::new();
    for (i, entry) in entries.iter().enumerate() {
        match rule_from_value(entry, i, origin) {
            Ok(r) => rules.push(r),
            Err(mut p) => problems.append(&mut p),
        }
    }
    if problems.is_empty() { Ok(Rules { origin: origin.into(), rules }) } else { Err(GateError { problems }) }
}

fn rule_from_value(value: &toml::Value, i: usize, origin: &str) -> Result<Rule, Vec<String>> {
    let at = |field: &str| format!("{origin}: rule[{i}].{field}");
    let Some(table) = value.as_table() else {
        return Err(vec![format!("{origin}: rule[{i}]: expected a table")]);
    };
    let spec: RuleSpec = match value.clone().try_into() {
        Ok(s) => s,
        Err(_) => {
            // Find the offending fields one by one: every field is optional, so a table of one
            // key fails exactly when that key is unknown or has the wrong type.
            let mut problems: Vec<String> = table
                .iter()
                .filter_map(|(k, v)| {
                    let mut single = toml::Table::new();
                    single.insert(k.clone(), v.clone());
                    toml::Value::Table(single).try_into::<RuleSpec>().err().map(|e| {
                        format!("{}: {}", at(k), e.to_string().lines().next().unwrap_or("invalid value"))
                    })
                })
                .collect();
            if problems.is_empty() {
                problems.push(format!("{origin}: rule[{i}]: invalid rule"));
            }
            return Err(problems);
        }
    };
    let mut problems = Vec::new();
    if spec.metric.is_none() {
        let names: Vec<&str> = Metric::ALL.iter().map(|m| m.name()).collect();
        problems.push(format!("{}: missing (one of {})", at("metric"), names.join(", ")));
    }
    for (field, v) in [
        ("max", spec.max),
        ("max_increase", spec.max_increase),
        ("max_increase_ratio", spec.max_increase_ratio),
    ] {
        if let Some(v) = v
            && !(v.is_finite() && v >= 0.0)
        {
            problems.push(format!("{}: must be a finite number ≥ 0, got {v}", at(field)));
        }
    }
    if spec.max.is_none() && spec.max_increase.is_none() && spec.max_increase_ratio.is_none() {
        problems.push(format!(
            "{origin}: rule[{i}]: no bound: give `max` and/or `max_increase` / `max_increase_ratio`"
        ));
    }
    if !problems.is_empty() {
        return Err(problems);
    }
    let regression = (spec.max_increase.is_some() || spec.max_increase_ratio.is_some()).then(|| Regression {
        increase: spec.max_increase.unwrap_or(0.0),
        ratio: spec.max_increase_ratio.unwrap_or(0.0),
    });
    let pattern = |p: Option<String>| p.unwrap_or_else(|| "*".into());
    let mut rule = Rule {
        name: String::new(),
        scene: pattern(spec.scene),
        camera: pattern(spec.camera),
        light: pattern(spec.light),
        technique: pattern(spec.technique),
        label: pattern(spec.label),
        resolution: spec.resolution,
        depth_format: spec.depth_format,
        metric: spec.metric.expect("checked above"),
        max: spec.max,
        regression,
    };
    rule.name = spec.name.unwrap_or_else(|| rule.describe());
    Ok(rule)
}

/// Reads and parses a rules file.
pub fn load_rules(path: &Path) -> Result<Rules, GateError> {
    let origin = path.display().to_string();
    let text =
        std::fs::read_to_string(path).map_err(|e| GateError::one(format!("{origin}: cannot read: {e}")))?;
    parse_rules(&text, &origin)
}

/// Reads a report: a `report.json` file, or a folder holding one. Returns the report and the
/// file it was read from.
pub fn load_report(path: &Path) -> Result<(Report, PathBuf), GateError> {
    let file = if path.is_dir() { path.join("report.json") } else { path.to_path_buf() };
    let origin = file.display().to_string();
    let text = std::fs::read_to_string(&file).map_err(|e| {
        if e.kind() == std::io::ErrorKind::NotFound {
            GateError::one(format!("{origin}: no such report"))
        } else {
            GateError::one(format!("{origin}: cannot read: {e}"))
        }
    })?;
    let report: Report = serde_json::from_str(&text)
        .map_err(|e| GateError::one(format!("{origin}: not a valid report: {e}")))?;
    if report.schema != super::REPORT_SCHEMA {
        return Err(GateError::one(format!(
            "{origin}: schema: expected \"{}\", got \"{}\"",
            super::REPORT_SCHEMA,
            report.schema
        )));
    }
    Ok((report, file))
}

/// What pairs a run with its baseline run.
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct RunKey {
    pub scene: String,
    pub camera: String,
    pub light: String,
    pub label: String,
    pub resolution: u32,
    pub depth_format: String,
}

impl RunKey {
    pub fn of(run: &RunRecord) -> Self {
        RunKey {
            scene: run.scene.clone(),
            camera: run.camera.clone(),
            light: run.light.clone(),
            label: run.label.clone(),
            resolution: run.resolution,
            depth_format: run.depth_format.clone(),
        }
    }
}

impl fmt::Display for RunKey {
    /// `scene/camera/light label @resolution format`
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}/{}/{} {} @{} {}",
            self.scene, self.camera, self.light, self.label, self.resolution, self.depth_format
        )
    }
}

/// A metric's value for one run, with the pixel counts behind it when it is a hard rate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measured {
    pub value: f64,
    /// Pixels counted (false shadow, false lit or both) for the hard rates.
    pub count: Option<u64>,
    pub evaluated: u64,
}

impl Measured {
    fn show(&self) -> String {
        match self.count {
            Some(c) => format!("{} ({c} of {} px)", fmt_value(self.value), self.evaluated),
            None => fmt_value(self.value),
        }
    }
}

/// The value of `metric` for `run`, or `None` if the run does not carry it. Hard rates come from
/// the counts; soft metrics from the run's `soft` (or `rates`) object when the report has one.
pub fn measure(run: &RunRecord, metric: Metric) -> Option<Measured> {
    let evaluated = run.counts.evaluated;
    if let Some(count) = metric.count(run) {
        let value = if evaluated == 0 { 0.0 } else { count as f64 / evaluated as f64 };
        return Some(Measured { value, count: Some(count), evaluated });
    }
    let json = serde_json::to_value(run).ok()?;
    let name = metric.name();
    ["soft", "soft_errors", "rates"]
        .iter()
        .find_map(|k| json.get(k).and_then(|o| o.get(name)))
        .or_else(|| json.get(name))
        .and_then(|v| v.as_f64())
        .map(|value| Measured { value, count: None, evaluated })
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
    pub run: RunKey,
    pub technique: String,
    pub measured: Measured,
    pub max: Option<f64>,
    pub baseline: BaselineStatus,
    pub violations: Vec<Violation>,
}

impl Check {
    pub fn passed(&self) -> bool {
        self.violations.is_empty()
    }

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
        self.violations
            .iter()
            .map(|v| {
                let head = format!(
                    "FAIL rule[{}] \"{}\": {}: {} = {}",
                    self.rule,
                    self.rule_name,
                    self.run,
                    self.metric,
                    self.measured.show()
                );
                match v {
                    Violation::Max { limit } => format!("{head} > max {}", fmt_value(*limit)),
                    Violation::Regression { baseline, limit, limit_count } => format!(
                        "{head} > limit {} (baseline {})",
                        show_limit(*limit, *limit_count),
                        baseline.show()
                    ),
                }
            })
            .collect()
    }
}

fn show_limit(limit: f64, limit_count: Option<u64>) -> String {
    match limit_count {
        Some(c) => format!("{} ({c} px)", fmt_value(limit)),
        None => fmt_value(limit),
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
    /// Runs checked by a regression rule but absent from the baseline.
    pub new_runs: Vec<RunKey>,
}

impl GateOutcome {
    pub fn violations(&self) -> usize {
        self.checks.iter().map(|c| c.violations.len()).sum()
    }

    pub fn failed_checks(&self) -> usize {
        self.checks.iter().filter(|c| !c.passed()).count()
    }

    pub fn passed(&self) -> bool {
        self.violations() == 0
    }

    /// `N rules, M runs checked, K violations`
    pub fn summary_line(&self) -> String {
        format!("{} rules, {} runs checked, {} violations", self.rules, self.runs_checked, self.violations())
    }

    /// What `gate` prints: one line per violation, the new runs, the summary line.
    pub fn text(&self) -> String {
        let mut out = String::new();
        for c in &self.checks {
            for line in c.violation_lines() {
                out.push_str(&line);
                out.push('\n');
            }
        }
        for run in &self.new_runs {
            out.push_str(&format!("new: {run}: not in the baseline, no regression check\n"));
        }
        out.push_str(&self.summary_line());
        out.push('\n');
        out
    }

    /// A Markdown table (rule, run, value, limit, status) for CI job summaries.
    pub fn markdown(&self) -> String {
        let mut out = format!(
            "## shadowtruth gate: {}\n\n{}\n\n| rule | run | value | limit | status |\n| --- | --- | --- | --- | --- |\n",
            if self.passed() { "passed" } else { "FAILED" },
            self.summary_line()
        );
        for c in &self.checks {
            out.push_str(&format!(
                "| {} | {} | {} | {} | {} |\n",
                md_cell(&format!("rule[{}] {}", c.rule, c.rule_name)),
                md_cell(&c.run.to_string()),
                md_cell(&format!("{} = {}", c.metric, c.measured.show())),
                md_cell(&c.limits()),
                if c.passed() { c.status().to_string() } else { "**FAIL**".to_string() },
            ));
        }
        out
    }
}

fn md_cell(s: &str) -> String {
    s.replace('\\', "\\\\").replace('|', "\\|").replace(['\n', '\r'], " ")
}

/// Six significant digits, no trailing zeros: `0.00123457`, `0`, `1.5e-9`.
pub fn fmt_value(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let exp = v.abs().log10().floor() as i32;
    if (-6..=6).contains(&exp) {
        let decimals = (5 - exp).max(0) as usize;
        let s = format!("{v:.decimals$}");
        if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s }
    } else {
        format!("{v:.5e}")
    }
}

/// Checks every rule against the runs it matches. Bad input (a rule that matches no run, a
/// regression rule without a baseline, a metric a run lacks, an ambiguous baseline pairing) is
/// an error listing every such problem; violations are part of the outcome.
pub fn evaluate(report: &Report, baseline: Option<&Report>, rules: &Rules) -> Result<GateOutcome, GateError> {
    let origin = &rules.origin;
    let mut problems = Vec::new();
    let mut by_key: HashMap<RunKey, Vec<usize>> = HashMap::new();
    if let Some(b) = baseline {
        for (i, run) in b.runs.iter().enumerate() {
            by_key.entry(RunKey::of(run)).or_default().push(i);
        }
    }
    let mut checks = Vec::new();
    let mut checked_runs = BTreeSet::new();
    let mut new_runs = BTreeSet::new();
    for (ri, rule) in rules.rules.iter().enumerate() {
        let at = format!("{origin}: rule[{ri}] \"{}\"", rule.name);
        if rule.regression.is_some() && baseline.is_none() {
            problems.push(format!(
                "{at}: a regression bound (max_increase, max_increase_ratio) needs --baseline"
            ));
            continue;
        }
        let matched: Vec<usize> = (0..report.runs.len()).filter(|&i| rule.matches(&report.runs[i])).collect();
        if matched.is_empty() {
            problems.push(format!(
                "{at}: matches no run of the report ({} runs; selects {})",
                report.runs.len(),
                rule.selector()
            ));
            continue;
        }
        let (mut lacking, mut lacking_in_baseline) = (Vec::new(), Vec::new());
        for &i in &matched {
            let run = &report.runs[i];
            let key = RunKey::of(run);
            let Some(measured) = measure(run, rule.metric) else {
                lacking.push(key);
                continue;
            };
            let mut violations = Vec::new();
            if let Some(limit) = rule.max
                && measured.value > limit
            {
                violations.push(Violation::Max { limit });
            }
            let mut status = BaselineStatus::NotChecked;
            if let (Some(reg), Some(base_report)) = (&rule.regression, baseline) {
                match by_key.get(&key).map(|v| v.as_slice()) {
                    None | Some([]) => {
                        status = BaselineStatus::New;
                        new_runs.insert(key.clone());
                    }
                    Some([b]) => match measure(&base_report.runs[*b], rule.metric) {
                        None => lacking_in_baseline.push(key.clone()),
                        Some(base) => {
                            let (limit, limit_count, violated) = regression_check(&measured, &base, reg);
                            if violated {
                                violations.push(Violation::Regression { baseline: base, limit, limit_count });
                            }
                            status = BaselineStatus::Compared { baseline: base, limit, limit_count };
                        }
                    },
                    Some(many) => problems.push(format!(
                        "{at}: the baseline has {} runs for {key}; cannot pair them",
                        many.len()
                    )),
                }
            }
            checked_runs.insert(i);
            checks.push(Check {
                rule: ri,
                rule_name: rule.name.clone(),
                metric: rule.metric,
                run_index: i,
                run: key,
                technique: run.technique.clone(),
                measured,
                max: rule.max,
                baseline: status,
                violations,
            });
        }
        for (runs, whose) in [(&lacking, "runs"), (&lacking_in_baseline, "baseline runs")] {
            if let Some(first) = runs.first() {
                problems.push(format!(
                    "{at}: metric: {} of {} matched {whose} have no {} value (first: {first})",
                    runs.len(),
                    matched.len(),
                    rule.metric
                ));
            }
        }
    }
    if !problems.is_empty() {
        return Err(GateError { problems });
    }
    Ok(GateOutcome {
        rules: rules.rules.len(),
        runs_checked: checked_runs.len(),
        checks,
        new_runs: new_runs.into_iter().collect(),
    })
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
    use crate::metrics::Counts;
    use crate::report::Timings;

    fn run(scene: &str, technique: &str, label: &str, evaluated: u64, fs: u64, fl: u64) -> RunRecord {
        let counts =
            Counts { pixels: evaluated, evaluated, false_shadow: fs, false_lit: fl, ..Counts::default() };
        RunRecord {
            scene: scene.into(),
            camera: "main".into(),
            light: "sun".into(),
            technique: technique.into(),
            parameters: Default::default(),
            label: label.into(),
            resolution: 1024,
            depth_format: "f32".into(),
            counts,
            rates: counts.rates(),
            timings: Timings::default(),
            layer_memory_bytes: 0,
            reference: Default::default(),
            soft: None,
        }
    }

    fn report(runs: Vec<RunRecord>) -> Report {
        Report { runs, ..Report::new() }
    }

    fn rules(text: &str) -> Rules {
        parse_rules(text, "rules.toml").unwrap_or_else(|e| panic!("{e}"))
    }

    fn problems(text: &str) -> String {
        parse_rules(text, "rules.toml").expect_err("bad rules").to_string()
    }

    #[test]
    fn globs() {
        assert!(glob_match("*", ""));
        assert!(glob_match("*", "anything"));
        assert!(glob_match("slope_*", "slope_scaled"));
        assert!(glob_match("?one", "none"));
        assert!(!glob_match("?one", "one"));
        assert!(glob_match("constant(bias_depth=0.00?)", "constant(bias_depth=0.001)"));
        assert!(glob_match("*a*b*c", "xxaxxbxxbc"));
        assert!(!glob_match("*a*b*c", "xxaxxbxxb"));
        assert!(!glob_match("plane", "plane_box"));
        assert!(glob_match("plane*", "plane_box"));
        assert!(glob_match("**x", "x"));
    }

    #[test]
    fn rules_parse_with_defaults() {
        let r = rules(
            r#"
            [[rule]]
            technique = "slope_*"
            metric = "false_shadow"
            max = 0.001
            [[rule]]
            name = "no regression"
            metric = "error"
            max_increase = 0
            max_increase_ratio = 0.05
            resolution = 2048
            "#,
        );
        assert_eq!(r.rules.len(), 2);
        let a = &r.rules[0];
        assert_eq!((a.scene.as_str(), a.label.as_str(), a.technique.as_str()), ("*", "*", "slope_*"));
        assert_eq!(a.max, Some(0.001));
        assert!(a.regression.is_none());
        assert!(a.name.contains("technique=slope_*"), "{}", a.name);
        let b = &r.rules[1];
        assert_eq!(b.name, "no regression");
        assert_eq!(b.regression, Some(Regression { increase: 0.0, ratio: 0.05 }));
        assert_eq!(b.resolution, Some(2048));
    }

    #[test]
    fn bad_rules_name_the_file_and_field() {
        let e = problems("[[rule]]\nmetric = \"false_shadow\"\nmax = 0.1\ncolour = \"red\"\n");
        assert!(e.contains("rules.toml: rule[0].colour") && e.contains("unknown field"), "{e}");
        let e = problems(
            "[[rule]]\nmetric = \"false_shadow\"\nmax = 0.1\n[[rule]]\nmetric = \"acne\"\nmax = 0.1\n",
        );
        assert!(e.contains("rule[1].metric") && e.contains("acne"), "{e}");
        let e = problems("[[rule]]\nmetric = \"error\"\nmax = \"small\"\n");
        assert!(e.contains("rule[0].max"), "{e}");
        let e = problems("[[rule]]\nmetric = \"error\"\nresolution = -1\nmax = 0\n");
        assert!(e.contains("rule[0].resolution"), "{e}");
        let e = problems("[[rule]]\nmetric = \"error\"\n");
        assert!(e.contains("rule[0]") && e.contains("no bound"), "{e}");
        let e = problems("[[rule]]\nmax = 0.1\n");
        assert!(e.contains("rule[0].metric") && e.contains("missing"), "{e}");
        let e = problems("[[rule]]\nmetric = \"error\"\nmax = -0.5\n");
        assert!(e.contains("rule[0].max") && e.contains("≥ 0"), "{e}");
        let e = problems("[[rule]\nmetric = ");
        assert!(e.contains("rules.toml") && e.contains("TOML"), "{e}");
        let e = problems("");
        assert!(e.contains("no [[rule]]"), "{e}");
        let e = problems("threshold = 3\n[[rule]]\nmetric = \"error\"\nmax = 0\n");
        assert!(e.contains("rules.toml: threshold"), "{e}");
    }

    #[test]
    fn soft_metric_names_are_accepted_but_a_run_without_them_is_bad_input() {
        let r = rules("[[rule]]\nmetric = \"mae\"\nmax = 0.1\n");
        let e = evaluate(&report(vec![run("s", "none", "none", 100, 0, 0)]), None, &r).unwrap_err();
        assert!(
            e.to_string().contains("rules.toml: rule[0]")
                && e.to_string().contains("1 of 1 matched runs have no mae value"),
            "{e}"
        );
    }

    #[test]
    fn absolute_bound_is_inclusive_and_exact() {
        let rep = report(vec![
            run("a", "constant", "constant(bias_depth=0.001)", 1000, 1, 0),
            run("b", "constant", "constant(bias_depth=0.001)", 1000, 2, 0),
        ]);
        let out = evaluate(&rep, None, &rules("[[rule]]\nmetric = \"false_shadow\"\nmax = 0.001\n")).unwrap();
        assert_eq!(out.checks.len(), 2);
        assert!(out.checks[0].passed(), "1 of 1000 is exactly 0.001");
        assert!(!out.checks[1].passed());
        assert_eq!(out.violations(), 1);
        assert_eq!(out.runs_checked, 2);
        assert!(out.text().contains("b/main/sun constant(bias_depth=0.001) @1024 f32"), "{}", out.text());
        assert!(out.text().ends_with("1 rules, 2 runs checked, 1 violations\n"), "{}", out.text());
    }

    #[test]
    fn one_pixel_regression_is_caught_with_zero_slack_only() {
        let n = 786_432; // 1024 × 768: one pixel is 1.3e-6 of the rate
        let base = report(vec![run("s", "none", "none", n, 1000, 500)]);
        let now = report(vec![run("s", "none", "none", n, 1001, 500)]);
        for (metric, fails) in [("false_shadow", true), ("false_lit", false), ("error", true)] {
            let zero = rules(&format!("[[rule]]\nmetric = \"{metric}\"\nmax_increase = 0\n"));
            let out = evaluate(&now, Some(&base), &zero).unwrap();
            assert_eq!(!out.passed(), fails, "{metric}: {}", out.text());
            let one_px =
                rules(&format!("[[rule]]\nmetric = \"{metric}\"\nmax_increase = {}\n", 1.0 / n as f64));
            assert!(
                evaluate(&now, Some(&base), &one_px).unwrap().passed(),
                "{metric} with one pixel of slack"
            );
        }
        // Relative slack: 0.1 % of 1000 pixels is one pixel.
        let ratio = rules("[[rule]]\nmetric = \"false_shadow\"\nmax_increase_ratio = 0.001\n");
        assert!(evaluate(&now, Some(&base), &ratio).unwrap().passed());
        let both =
            rules("[[rule]]\nmetric = \"false_shadow\"\nmax_increase = 0\nmax_increase_ratio = 0.0005\n");
        assert!(!evaluate(&now, Some(&base), &both).unwrap().passed());
    }

    #[test]
    fn different_evaluated_counts_fall_back_to_rates() {
        let base = report(vec![run("s", "none", "none", 1000, 10, 0)]);
        let better = report(vec![run("s", "none", "none", 2000, 19, 0)]);
        let worse = report(vec![run("s", "none", "none", 2000, 21, 0)]);
        let r = rules("[[rule]]\nmetric = \"false_shadow\"\nmax_increase = 0\n");
        assert!(evaluate(&better, Some(&base), &r).unwrap().passed());
        let out = evaluate(&worse, Some(&base), &r).unwrap();
        assert!(matches!(out.checks[0].violations[0], Violation::Regression { limit_count: None, .. }));
    }

    #[test]
    fn runs_absent_from_the_baseline_are_new() {
        let base = report(vec![run("s", "none", "none", 100, 1, 0)]);
        let now = report(vec![run("s", "none", "none", 100, 1, 0), run("t", "none", "none", 100, 50, 0)]);
        let r = rules("[[rule]]\nmetric = \"false_shadow\"\nmax_increase = 0\n");
        let out = evaluate(&now, Some(&base), &r).unwrap();
        assert!(out.passed());
        assert_eq!(out.new_runs.len(), 1);
        assert_eq!(out.new_runs[0].scene, "t");
        assert_eq!(out.checks[1].status(), "pass (new)");
        assert!(out.text().contains("new: t/main/sun none @1024 f32"));
    }

    #[test]
    fn bad_input_is_collected() {
        let now = report(vec![run("s", "none", "none", 100, 1, 0)]);
        let r = rules(
            "[[rule]]\nscene = \"nowhere\"\nmetric = \"error\"\nmax = 0\n[[rule]]\nmetric = \"error\"\nmax_increase = 0\n",
        );
        let e = evaluate(&now, None, &r).unwrap_err();
        assert_eq!(e.problems.len(), 2, "{e}");
        assert!(e.problems[0].contains("rules.toml: rule[0]") && e.problems[0].contains("matches no run"));
        assert!(e.problems[1].contains("rule[1]") && e.problems[1].contains("--baseline"));
        let twice = report(vec![run("s", "none", "none", 100, 1, 0), run("s", "none", "none", 100, 1, 0)]);
        let e = evaluate(&now, Some(&twice), &rules("[[rule]]\nmetric = \"error\"\nmax_increase = 0\n"))
            .unwrap_err();
        assert!(e.to_string().contains("cannot pair"), "{e}");
    }

    #[test]
    fn markdown_has_one_row_per_check_and_escapes_pipes() {
        let now = report(vec![run("a|b", "none", "none", 100, 1, 0), run("c", "none", "none", 100, 0, 0)]);
        let out = evaluate(&now, None, &rules("[[rule]]\nmetric = \"error\"\nmax = 0\n")).unwrap();
        let md = out.markdown();
        let rows: Vec<&str> = md.lines().filter(|l| l.starts_with('|')).collect();
        assert_eq!(rows.len(), 2 + 2);
        assert!(rows[2].contains("a\\|b") && rows[2].contains("FAIL"), "{md}");
        assert!(rows[3].ends_with("| pass |"), "{md}");
    }

    #[test]
    fn values_print_with_six_significant_digits() {
        assert_eq!(fmt_value(0.0), "0");
        assert_eq!(fmt_value(0.001), "0.001");
        assert_eq!(fmt_value(1.0 / 3.0), "0.333333");
        assert_eq!(fmt_value(0.0012715657552083333), "0.00127157");
        assert_eq!(fmt_value(2.0), "2");
        assert_eq!(fmt_value(1.5e-9), "1.50000e-9");
    }
}
