//! Rules files: `[[rule]]` tables that select runs by glob patterns and bound one metric,
//! absolutely and/or against a baseline. The format is described in gates/README.md.

use super::GateError;
use super::fmt_value::fmt_value;
use serde::{Deserialize, Serialize};
use shadowtruth::metrics::SoftErrors;
use shadowtruth::record::RunRecord;
use shadowtruth::record::TemporalRecord;
use std::fmt;
use std::path::Path;

/// The metrics a rule may bound. The first three are rates of the evaluated pixels computed from
/// the run's counts; `reference_uncertain` is the fraction of the view's evaluated and uncertain
/// pixels that the reference cannot decide beyond doubt (`counts.uncertain`, left out of every
/// score) and `reference_uncertain_px` their number; the soft metrics (`mae`, `false_shadow_mass`, `false_lit_mass`) and the
/// metrics of a run over a path (`flicker_rate`, `worst_frame_error`, `mean_frame_error`: its
/// `temporal.flicker_rate`, `temporal.worst_frame_error` and `temporal.mean_error`) are read
/// from the run when its report carries them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Metric {
    FalseShadow,
    FalseLit,
    Error,
    Mae,
    FalseShadowMass,
    FalseLitMass,
    FlickerRate,
    WorstFrameError,
    MeanFrameError,
    ReferenceUncertain,
    ReferenceUncertainPx,
}

impl Metric {
    pub const ALL: [Metric; 11] = [
        Metric::FalseShadow,
        Metric::FalseLit,
        Metric::Error,
        Metric::Mae,
        Metric::FalseShadowMass,
        Metric::FalseLitMass,
        Metric::FlickerRate,
        Metric::WorstFrameError,
        Metric::MeanFrameError,
        Metric::ReferenceUncertain,
        Metric::ReferenceUncertainPx,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Metric::FalseShadow => "false_shadow",
            Metric::FalseLit => "false_lit",
            Metric::Error => "error",
            Metric::Mae => "mae",
            Metric::FalseShadowMass => "false_shadow_mass",
            Metric::FalseLitMass => "false_lit_mass",
            Metric::FlickerRate => "flicker_rate",
            Metric::WorstFrameError => "worst_frame_error",
            Metric::MeanFrameError => "mean_frame_error",
            Metric::ReferenceUncertain => "reference_uncertain",
            Metric::ReferenceUncertainPx => "reference_uncertain_px",
        }
    }

    /// A metric of a run over a path, read from its `temporal` record (`None` for the others,
    /// and for a run without one).
    pub(super) fn temporal(self, run: &RunRecord) -> Option<Option<f64>> {
        let field: fn(&TemporalRecord) -> f64 = match self {
            Metric::FlickerRate => |t| t.flicker_rate,
            Metric::WorstFrameError => |t| t.worst_frame_error,
            Metric::MeanFrameError => |t| t.mean_error,
            _ => return None,
        };
        Some(run.temporal.as_ref().map(field))
    }

    /// A soft metric, read from the run's `soft` errors (`None` for the others, and for a run
    /// without them).
    pub(super) fn soft(self, run: &RunRecord) -> Option<Option<f64>> {
        let field: fn(&SoftErrors) -> f64 = match self {
            Metric::Mae => |s| s.mae,
            Metric::FalseShadowMass => |s| s.false_shadow_mass,
            Metric::FalseLitMass => |s| s.false_lit_mass,
            _ => return None,
        };
        Some(run.soft.as_ref().map(field))
    }

    /// The pixel count behind a hard rate (`None` for the soft and path metrics).
    pub(super) fn count(self, run: &RunRecord) -> Option<u64> {
        let c = &run.counts;
        match self {
            Metric::FalseShadow => Some(c.false_shadow),
            Metric::FalseLit => Some(c.false_lit),
            Metric::Error => Some(c.false_shadow.saturating_add(c.false_lit)),
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
    pub(super) fn selector(&self) -> String {
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
    let spec = spec_from_value(value, i, origin)?;
    check_spec(&spec, i, origin)?;
    Ok(rule_from_spec(spec))
}

/// The table as a [`RuleSpec`], or a problem for each key that is unknown or has the wrong type.
fn spec_from_value(value: &toml::Value, i: usize, origin: &str) -> Result<RuleSpec, Vec<String>> {
    let Some(table) = value.as_table() else {
        return Err(vec![format!("{origin}: rule[{i}]: expected a table")]);
    };
    if let Ok(spec) = value.clone().try_into() {
        return Ok(spec);
    }
    // Every field is optional, so a table of one key fails exactly when that key is unknown or
    // has the wrong type: try them one by one to name each.
    let mut problems: Vec<String> = table
        .iter()
        .filter_map(|(k, v)| {
            let mut single = toml::Table::new();
            single.insert(k.clone(), v.clone());
            toml::Value::Table(single).try_into::<RuleSpec>().err().map(|e| {
                let first_line = e.to_string().lines().next().unwrap_or("invalid value").to_string();
                format!("{origin}: rule[{i}].{k}: {first_line}")
            })
        })
        .collect();
    if problems.is_empty() {
        problems.push(format!("{origin}: rule[{i}]: invalid rule"));
    }
    Err(problems)
}

/// A metric, at least one bound, and bounds that are finite and ≥ 0.
fn check_spec(spec: &RuleSpec, i: usize, origin: &str) -> Result<(), Vec<String>> {
    let at = |field: &str| format!("{origin}: rule[{i}].{field}");
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
    if problems.is_empty() { Ok(()) } else { Err(problems) }
}

/// The validated rule of a spec that passed [`check_spec`].
fn rule_from_spec(spec: RuleSpec) -> Rule {
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
        metric: spec.metric.expect("checked by check_spec"),
        max: spec.max,
        regression,
    };
    rule.name = spec.name.unwrap_or_else(|| rule.describe());
    rule
}

/// The text of a rules file holding `specs`: serialised from the type [`parse_rules`] reads, so
/// that what is written reads back as written whatever the names hold.
pub fn rules_toml(specs: &[RuleSpec]) -> String {
    #[derive(Serialize)]
    struct RulesFile<'a> {
        rule: &'a [RuleSpec],
    }
    toml::to_string(&RulesFile { rule: specs }).expect("rules serialise to TOML")
}

/// Reads and parses a rules file.
pub fn load_rules(path: &Path) -> Result<Rules, GateError> {
    let origin = path.display().to_string();
    // Rules are a few lines each; 16 MiB holds more rules than any report has runs to check.
    let text = shadowtruth::input_file::read_named_text(path, 16 << 20).map_err(GateError::one)?;
    parse_rules(&text, &origin)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rules(text: &str) -> Rules {
        parse_rules(text, "rules.toml").unwrap_or_else(|e| panic!("{e}"))
    }

    fn problems(text: &str) -> String {
        parse_rules(text, "rules.toml").expect_err("bad rules").to_string()
    }

    #[test]
    fn written_rules_read_back_as_written() {
        let spec = RuleSpec {
            name: Some("tuned \"x\" on a/b\\c".into()),
            scene: Some("s*".into()),
            resolution: Some(512),
            metric: Some(Metric::Error),
            max: Some(1.0 / 3.0),
            ..RuleSpec::default()
        };
        let read = rules(&rules_toml(&[spec.clone(), RuleSpec { name: None, ..spec.clone() }]));
        assert_eq!(read.rules.len(), 2);
        assert_eq!(read.rules[0].name, "tuned \"x\" on a/b\\c");
        assert_eq!((read.rules[0].max, read.rules[0].resolution), (Some(1.0 / 3.0), Some(512)));
        assert_eq!(read.rules[1].scene, "s*");
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
}
