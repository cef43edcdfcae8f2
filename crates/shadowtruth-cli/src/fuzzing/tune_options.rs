//! `tune`'s options (`tune::parse_tune_options`, then `TuneArgs::request`), and where they
//! validate, the whole search on a cheap synthetic objective, so that the fuzzer reaches the
//! search's bounds as well as the options' checks.

use crate::tune::{MAX_EVALUATIONS, TuneRecord, TuneRequest, parse_tune_options, tune_with};
use shadowtruth::metrics::Counts;
use shadowtruth::technique::TechniqueSpec;

/// Pixels scored per synthetic scene.
const SYNTHETIC_PIXELS: u64 = 10_000;

/// The bytes as `tune`'s options, one argument per line (so that a `--technique` JSON object
/// may hold spaces), without the command's name.
pub fn tune_options(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let args: Vec<&str> = text.lines().filter(|line| !line.is_empty()).collect();
    let Ok(options) = parse_tune_options(&args) else {
        return;
    };
    let Ok(request) = options.request() else {
        return;
    };
    check_search(&request);
}

/// The search over two synthetic scenes: each evaluation shaded once, every search within its
/// cap, every optimum inside its range and its safe range.
fn check_search(request: &TuneRequest) {
    let names = ["near".to_string(), "far".to_string()];
    let mut shaded = 0usize;
    let mut shade = |scene: usize, spec: &TechniqueSpec| {
        shaded += 1;
        synthetic_counts(scene, &tuned_values(request, spec))
    };
    let result = tune_with(request, &names, &mut shade);
    assert_eq!(result.scene_evaluations, shaded, "a setting shaded twice");
    // The suite's search shades every scene per call; each scene's, its own scene.
    assert!(shaded <= 2 * names.len() * MAX_EVALUATIONS, "{shaded} evaluations");
    for tuned in std::iter::once(&result.suite).chain(result.scenes.iter().map(|(_, t)| t)) {
        for (axis, (name, range)) in request.params.iter().enumerate() {
            let best = tuned.best.params[axis];
            let safe = tuned.safe[axis];
            // Values are rounded to three significant digits: an end may round past the range.
            // A range below zero holds the magnitudes of its values.
            let (slack, magnitude) = (1.0 + 5e-3, range.magnitude());
            assert!(
                (best < 0.0) == range.is_negative()
                    && magnitude.lo / slack <= best.abs()
                    && best.abs() <= magnitude.hi * slack,
                "{name} = {best} outside {range:?}"
            );
            assert!(safe.lo <= best && best <= safe.hi, "{name} = {best} outside its safe range {safe:?}");
        }
    }
    let record = TuneRecord::new(request, &result, &[64], "f32");
    serde_json::to_string(&record).expect("tune.json serializes");
}

/// The tuned parameters' values in `spec`, in the request's order.
fn tuned_values(request: &TuneRequest, spec: &TechniqueSpec) -> Vec<f64> {
    let parameters = spec.parameters();
    let value = |name: &String| parameters.get(name).and_then(|v| v.as_f64()).unwrap_or(f64::NAN);
    request.params.iter().map(|(name, _)| value(name)).collect()
}

/// A scene whose error curve is a bias's: false shadow (acne) falls and false lit (a leak)
/// grows with each parameter's magnitude, in whole pixels, crossing at a point that differs per
/// scene.
fn synthetic_counts(scene: usize, values: &[f64]) -> Counts {
    let crossing_log10 = -3.0 + scene as f64;
    let x: f64 =
        values.iter().map(|v| v.abs().log10() - crossing_log10).sum::<f64>() / values.len().max(1) as f64;
    let pixels = |rate: f64| (rate.clamp(0.0, 1.0) * SYNTHETIC_PIXELS as f64) as u64;
    Counts {
        evaluated: SYNTHETIC_PIXELS,
        false_shadow: pixels(0.05 * (-2.0 * x).exp()),
        false_lit: pixels(0.05 * (1.5 * x).exp()),
        ..Counts::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The seeds named `bad_*` are refused by the options' checks; every other seed passes them
    /// and so reaches the search.
    #[test]
    fn the_good_seeds_reach_the_search_and_the_bad_ones_do_not() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/corpus/tune_options");
        let mut seen = 0;
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            let text = std::fs::read_to_string(&path).unwrap();
            let args: Vec<&str> = text.lines().filter(|line| !line.is_empty()).collect();
            let checked = parse_tune_options(&args)
                .map_err(|e| e.to_string())
                .and_then(|o| o.request().map_err(|e| e.to_string()));
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            assert_eq!(checked.is_err(), name.starts_with("bad_"), "{name}: {:?}", checked.err());
            if let Ok(request) = checked {
                check_search(&request);
            }
            seen += 1;
        }
        assert!(seen >= 10, "{seen} seeds");
    }

    #[test]
    fn the_synthetic_scenes_have_an_interior_optimum() {
        // Acne below the crossing, a leak above: the objective is worst at both ends.
        let total = |x: f64| {
            let c = synthetic_counts(0, &[x]);
            c.false_shadow + c.false_lit
        };
        assert!(total(1e-3) < total(1e-6) && total(1e-3) < total(1.0));
    }
}
