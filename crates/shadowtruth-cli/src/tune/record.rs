//! tune.json (`shadowtruth/tune/v1`, docs/tune.md) and the gate rules that lock a tuned
//! setting's error.

use super::search::SafeRange;
use super::{EvaluatedPoint, Objective, SuiteAggregate, TuneRequest, TuneResult, Tuned};
use crate::gate::{Metric, RuleSpec, rules_toml};
use serde::Serialize;
use serde_json::{Map, Value};
use shadowtruth::record::RunRecord;

#[derive(Serialize)]
pub struct TuneRecord {
    pub format: &'static str,
    /// The technique with its fixed parameters, as a plan names it.
    pub technique: Map<String, Value>,
    pub parameters: Vec<ParameterRecord>,
    pub objective: Objective,
    pub suite_aggregate: SuiteAggregate,
    /// The safe range keeps the objective at most this much (relative) above the optimum.
    pub safe_range_slack: f64,
    pub scenes: Vec<String>,
    pub resolutions: Vec<u32>,
    pub depth_format: String,
    pub suite: TunedRecord,
    pub per_scene: Vec<SceneTunedRecord>,
}

#[derive(Serialize)]
pub struct ParameterRecord {
    pub name: String,
    /// The searched range, on a log scale.
    pub range: [f64; 2],
}

#[derive(Serialize)]
pub struct SceneTunedRecord {
    pub scene: String,
    #[serde(flatten)]
    pub tuned: TunedRecord,
}

#[derive(Serialize)]
pub struct TunedRecord {
    pub best: BestRecord,
    /// Per parameter, the others held at the optimum.
    pub safe_range: Map<String, Value>,
    pub points: Vec<PointRecord>,
}

#[derive(Serialize)]
pub struct BestRecord {
    pub params: Map<String, Value>,
    pub objective: f64,
    /// False when no setting meets the objective's constraint (`false_lit_under`): the best
    /// is then the one with the least false shadow, and its objective is 1 + that.
    pub feasible: bool,
    /// The run label of the tuned technique (what report.json and gate rules name).
    pub label: String,
}

#[derive(Serialize)]
pub struct PointRecord {
    pub params: Map<String, Value>,
    pub objective: f64,
    pub false_shadow: f64,
    pub false_lit: f64,
}

impl TuneRecord {
    pub fn new(request: &TuneRequest, result: &TuneResult, resolutions: &[u32], depth_format: &str) -> Self {
        let names: Vec<&str> = request.params.iter().map(|(n, _)| n.as_str()).collect();
        TuneRecord {
            format: "shadowtruth/tune/v1",
            technique: request.base.clone(),
            parameters: request
                .params
                .iter()
                .map(|(name, r)| ParameterRecord { name: name.clone(), range: [r.lo, r.hi] })
                .collect(),
            objective: request.objective,
            suite_aggregate: request.aggregate,
            safe_range_slack: super::SAFE_RANGE_SLACK,
            scenes: result.scenes.iter().map(|(n, _)| n.clone()).collect(),
            resolutions: resolutions.to_vec(),
            depth_format: depth_format.into(),
            suite: tuned_record(request, &names, &result.suite),
            per_scene: result
                .scenes
                .iter()
                .map(|(scene, t)| SceneTunedRecord {
                    scene: scene.clone(),
                    tuned: tuned_record(request, &names, t),
                })
                .collect(),
        }
    }
}

fn named(names: &[&str], values: &[f64]) -> Map<String, Value> {
    names.iter().zip(values).map(|(n, &v)| (n.to_string(), Value::from(v))).collect()
}

fn tuned_record(request: &TuneRequest, names: &[&str], t: &Tuned) -> TunedRecord {
    let safe = |s: &SafeRange| {
        serde_json::json!({
            "lo": s.lo, "hi": s.hi,
            "lo_at_range_end": s.lo_at_range_end, "hi_at_range_end": s.hi_at_range_end,
        })
    };
    let point = |p: &EvaluatedPoint| PointRecord {
        params: named(names, &p.params),
        objective: p.objective,
        false_shadow: p.false_shadow,
        false_lit: p.false_lit,
    };
    TunedRecord {
        best: BestRecord {
            params: named(names, &t.best.params),
            objective: t.best.value,
            feasible: request.objective.feasible(t.best.value),
            label: request.spec(&t.best.params).map(|s| s.label()).unwrap_or_default(),
        },
        safe_range: names.iter().zip(&t.safe).map(|(n, s)| (n.to_string(), safe(s))).collect(),
        points: t.points.iter().map(point).collect(),
    }
}

/// Gate rules (gates/README.md) bounding the error of every run labelled `label` at its value
/// in `runs` plus `slack` of it and one scored pixel: a later change that makes the tuned
/// setting worse on any view fails the gate.
pub fn gate_rules_toml(runs: &[RunRecord], label: &str, slack: f64) -> String {
    let header = format!(
        "# The error of the tuned setting {label} on each view, with {}% slack and one pixel.\n\n",
        slack * 100.0
    );
    let rule = |r: &RunRecord| RuleSpec {
        name: Some(format!("tuned {label} on {}/{}/{} at {}", r.scene, r.camera, r.light, r.resolution)),
        scene: Some(r.scene.clone()),
        camera: Some(r.camera.clone()),
        light: Some(r.light.clone()),
        resolution: Some(r.resolution),
        depth_format: Some(r.depth_format.clone()),
        label: Some(label.into()),
        metric: Some(Metric::Error),
        max: Some(r.rates.error * (1.0 + slack) + 1.0 / r.counts.scored().max(1) as f64),
        ..RuleSpec::default()
    };
    let rules: Vec<RuleSpec> = runs.iter().filter(|r| r.label == label).map(rule).collect();
    header + &rules_toml(&rules)
}
