//! `tune`: the parameter values of one technique that minimise an objective, per scene and for
//! the whole suite, with the range around each optimum where the objective stays within
//! `SAFE_RANGE_SLACK` of it (docs/tune.md).
//!
//! - `options.rs` the command's options and their checks, before anything is traced;
//! - `search.rs` the search on log scales and the safe range (pure, on any function);
//! - `objective.rs` what is minimised;
//! - `views.rs` the views traced once, and one evaluation: a shading pass per view and resolution;
//! - `record.rs` tune.json (`shadowtruth/tune/v1`) and the gate rules that lock the result.

mod objective;
mod options;
mod record;
mod search;
mod views;

pub use objective::{Objective, SuiteAggregate};
pub use options::*;
pub use record::{TuneRecord, TunedRecord, gate_rules_toml};
pub use search::{LogRange, MAX_EVALUATIONS};
pub use views::TuneViews;

use search::{Point, minimise, safe_range};
use serde_json::{Map, Value};
use shadowtruth::metrics::Counts;
use shadowtruth::technique::TechniqueSpec;
use std::cell::RefCell;
use std::collections::HashMap;

/// The safe range keeps the objective at most this much (relative) above the optimum.
pub const SAFE_RANGE_SLACK: f64 = 0.1;

/// What to tune: the technique with its fixed parameters, and the parameters to search.
#[derive(Clone, Debug)]
pub struct TuneRequest {
    /// The technique as a plan names it (`{"technique": "constant", ...}`), fixed parameters set.
    pub base: Map<String, Value>,
    /// The tuned parameters with their ranges (one to three).
    pub params: Vec<(String, LogRange)>,
    pub objective: Objective,
    pub aggregate: SuiteAggregate,
}

impl TuneRequest {
    /// The suite's objective in words, for titles.
    pub fn aggregate_description(&self) -> String {
        let of = match self.aggregate {
            SuiteAggregate::Mean => "mean over scenes of",
            SuiteAggregate::Worst => "worst scene's",
        };
        format!("{of} {}", self.objective.describe())
    }

    /// The technique at these values of the tuned parameters.
    pub fn spec(&self, values: &[f64]) -> Result<TechniqueSpec, String> {
        let mut object = self.base.clone();
        for ((name, _), &v) in self.params.iter().zip(values) {
            object.insert(name.clone(), Value::from(v));
        }
        let spec: TechniqueSpec = serde_json::from_value(Value::Object(object)).map_err(|e| e.to_string())?;
        spec.validate().map_err(|e| e.to_string())?;
        // A technique that lets unknown fields pass (`none`) would tune nothing.
        let parameters = spec.parameters();
        if let Some((name, _)) = self.params.iter().find(|(name, _)| !parameters.contains_key(name)) {
            return Err(format!("{} has no parameter {name}", spec.name()));
        }
        if matches!(spec, TechniqueSpec::External(_)) {
            return Err(format!("{} reads another renderer's images: there is nothing to tune", spec.name()));
        }
        Ok(spec)
    }
}

/// The optimum of one scene or of the suite.
#[derive(Clone, Debug)]
pub struct Tuned {
    pub best: Point,
    pub safe: Vec<search::SafeRange>,
    /// Every point evaluated, in the order evaluated, with the rates behind its objective
    /// (for a scene; the suite's are the means over scenes).
    pub points: Vec<EvaluatedPoint>,
}

#[derive(Clone, Debug)]
pub struct EvaluatedPoint {
    pub params: Vec<f64>,
    pub objective: f64,
    pub false_shadow: f64,
    pub false_lit: f64,
}

/// The result: the suite's optimum, then each scene's, in scene order.
pub struct TuneResult {
    pub suite: Tuned,
    pub scenes: Vec<(String, Tuned)>,
    /// Settings shaded and scored on one scene (each at most once).
    pub scene_evaluations: usize,
}

/// The counts of a technique on one scene (by index), summed over its views and resolutions.
pub type Shade<'s> = dyn FnMut(usize, &TechniqueSpec) -> Counts + 's;

/// Evaluations of settings on scenes, each computed once.
struct Evaluations<'v> {
    shade: &'v mut Shade<'v>,
    scene_count: usize,
    request: &'v TuneRequest,
    memo: HashMap<(usize, Vec<u64>), Counts>,
}

impl Evaluations<'_> {
    fn counts(&mut self, scene: usize, values: &[f64]) -> Counts {
        let key = (scene, values.iter().map(|v| v.to_bits()).collect());
        if let Some(c) = self.memo.get(&key) {
            return *c;
        }
        let spec = self.request.spec(values).expect("checked before the search");
        let counts = (self.shade)(scene, &spec);
        self.memo.insert(key, counts);
        counts
    }

    fn scene_point(&mut self, scene: usize, values: &[f64]) -> EvaluatedPoint {
        let c = self.counts(scene, values);
        let r = c.rates();
        EvaluatedPoint {
            params: values.to_vec(),
            objective: self.request.objective.of(&c),
            false_shadow: r.false_shadow,
            false_lit: r.false_lit,
        }
    }

    fn suite_point(&mut self, values: &[f64]) -> EvaluatedPoint {
        let n = self.scene_count;
        let points: Vec<EvaluatedPoint> = (0..n).map(|s| self.scene_point(s, values)).collect();
        let mean = |f: fn(&EvaluatedPoint) -> f64| points.iter().map(f).sum::<f64>() / n.max(1) as f64;
        let objectives: Vec<f64> = points.iter().map(|p| p.objective).collect();
        EvaluatedPoint {
            params: values.to_vec(),
            objective: self.request.aggregate.of(&objectives),
            false_shadow: mean(|p| p.false_shadow),
            false_lit: mean(|p| p.false_lit),
        }
    }
}

/// Searches the suite's optimum, then each scene's (reusing every evaluation already made).
/// `on_evaluation` is called after each new shading of a scene. The first evaluation that fails
/// (a renderer's command) ends the search with its error: every later one counts as the worst.
pub fn tune(
    views: &mut TuneViews,
    request: &TuneRequest,
    on_evaluation: &mut dyn FnMut(),
) -> Result<TuneResult, crate::plan::PlanError> {
    let names: Vec<String> = views.scenes.iter().map(|s| s.name.clone()).collect();
    let mut failure = None;
    let mut shade = |scene: usize, spec: &TechniqueSpec| {
        if failure.is_some() {
            return Counts::default();
        }
        let counts = views.counts(scene, spec).unwrap_or_else(|e| {
            failure = Some(e);
            Counts::default()
        });
        on_evaluation();
        counts
    };
    let result = tune_with(request, &names, &mut shade);
    match failure {
        Some(e) => Err(e),
        None => Ok(result),
    }
}

/// `tune` on any scenes: `shade` gives the counts of a setting on the scene of that index in
/// `names` (a synthetic objective, for the fuzz entry and tests). Each (scene, setting) is
/// shaded once; each search calls its objective at most `MAX_EVALUATIONS` times.
pub fn tune_with(request: &TuneRequest, names: &[String], shade: &mut Shade<'_>) -> TuneResult {
    let ranges: Vec<LogRange> = request.params.iter().map(|(_, r)| *r).collect();
    let mut ev = Evaluations { shade, scene_count: names.len(), request, memo: HashMap::new() };
    let suite = optimise(&ranges, &mut |p| ev.suite_point(p));
    let scenes = (0..names.len())
        .map(|s| (names[s].clone(), optimise(&ranges, &mut |p| ev.scene_point(s, p))))
        .collect();
    TuneResult { suite, scenes, scene_evaluations: ev.memo.len() }
}

/// The optimum of `point`'s objective over `ranges`, the safe range of each parameter, and the
/// points evaluated. A range below zero (an engine's bias towards the light) is searched on the
/// log scale of its magnitude: `magnitude` holds the searched ranges, `signed` turns a searched
/// point back into the parameters' values.
fn optimise(ranges: &[LogRange], point: &mut dyn FnMut(&[f64]) -> EvaluatedPoint) -> Tuned {
    let negative: Vec<bool> = ranges.iter().map(LogRange::is_negative).collect();
    let magnitude: Vec<LogRange> = ranges.iter().map(LogRange::magnitude).collect();
    let signed = |p: &[f64]| -> Vec<f64> {
        p.iter().zip(&negative).map(|(&x, &neg)| if neg { -x } else { x }).collect()
    };
    // Shared by the objective (which records each point) and the safe ranges (which read them).
    let points: RefCell<Vec<EvaluatedPoint>> = RefCell::new(Vec::new());
    let mut f = |p: &[f64]| {
        let e = point(&round_all(&signed(p)));
        let value = e.objective;
        let mut points = points.borrow_mut();
        if !points.iter().any(|q| q.params == e.params) {
            points.push(e);
        }
        value
    };
    let mut best = minimise(&magnitude, &mut f);
    best.params = round_all(&best.params);
    let bound = best.value * (1.0 + SAFE_RANGE_SLACK);
    let safe = (0..ranges.len())
        .map(|axis| {
            let known: Vec<f64> =
                on_axis(&points.borrow(), &signed(&best.params), axis).iter().map(|x| x.abs()).collect();
            let s = safe_range(&best, axis, magnitude[axis], &known, bound, &mut f);
            let s = search::SafeRange { lo: round_significant(s.lo), hi: round_significant(s.hi), ..s };
            if negative[axis] { s.negated() } else { s }
        })
        .collect();
    best.params = signed(&best.params);
    Tuned { best, safe, points: points.into_inner() }
}

/// The values of parameter `axis` at the points evaluated with every other parameter at `at`.
fn on_axis(points: &[EvaluatedPoint], at: &[f64], axis: usize) -> Vec<f64> {
    let others_equal = |p: &[f64]| p.iter().zip(at).enumerate().all(|(k, (a, b))| k == axis || a == b);
    points.iter().filter(|p| others_equal(&p.params)).map(|p| p.params[axis]).collect()
}

/// Significant digits of every evaluated value: settings read as a person would write them
/// (0.00575, not 0.005748397828674646), well below the search's tolerance.
const SIGNIFICANT_DIGITS: i32 = 3;

fn round_significant(x: f64) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let scale = 10f64.powi(SIGNIFICANT_DIGITS - 1 - x.abs().log10().floor() as i32);
    // Through the decimal text, so that the value is the f64 nearest to what is printed.
    format!("{}", (x * scale).round() / scale).parse().unwrap_or(x)
}

fn round_all(values: &[f64]) -> Vec<f64> {
    values.iter().map(|&v| round_significant(v)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A renderer whose bias is below zero (towards the light): false shadow falls and false lit
    /// rises as the bias grows in magnitude, crossing at 0.0005.
    fn engine_counts(spec: &TechniqueSpec) -> Counts {
        let bias = spec.parameters()["bias"].as_f64().unwrap();
        assert!(bias < 0.0, "only negative values are asked for: {bias}");
        let magnitude = -bias;
        let evaluated = 1_000_000;
        Counts {
            evaluated,
            false_shadow: (evaluated as f64 * (0.0005 / magnitude).powi(2) * 0.01) as u64,
            false_lit: (evaluated as f64 * (magnitude / 0.0005).powi(2) * 0.01) as u64,
            ..Counts::default()
        }
    }

    #[test]
    fn a_range_below_zero_is_searched_on_its_magnitude_and_reported_in_its_own_sign() {
        let base = serde_json::json!({"technique": "command", "name": "engine",
            "run": ["render", "{visibility}", "{bias}"]});
        let request = TuneRequest {
            base: base.as_object().unwrap().clone(),
            params: vec![("bias".into(), LogRange { lo: -0.01, hi: -1e-5 })],
            objective: Objective::Total,
            aggregate: SuiteAggregate::Mean,
        };
        let result = tune_with(&request, &["s".to_string()], &mut |_, spec| engine_counts(spec));
        let best = result.suite.best.params[0];
        assert!((-0.00055..=-0.00045).contains(&best), "{best}");
        let safe = result.suite.safe[0];
        assert!(safe.lo < best && best < safe.hi && safe.hi < 0.0, "{safe:?}");
        assert!(result.suite.points.iter().all(|p| p.params[0] < 0.0));
        assert_eq!(request.spec(&[best]).unwrap().label(), format!("command(bias={best},name=engine)"));
    }
}
