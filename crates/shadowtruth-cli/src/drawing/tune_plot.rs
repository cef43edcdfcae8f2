//! The plot of a `tune` search along one parameter: the suite's false shadow, false lit and
//! objective at every value the search evaluated with the other parameters at the optimum, the
//! optimum marked and its safe range shaded.

use super::plots::{Chart, Marks};
use crate::tune::{TuneRequest, TuneResult};

/// The chart of parameter `axis` of the suite's search.
pub fn tune_chart(result: &TuneResult, request: &TuneRequest, axis: usize) -> Chart {
    let tuned = &result.suite;
    let best = &tuned.best.params;
    let on_axis =
        |p: &[f64]| p.iter().enumerate().all(|(k, &v)| k == axis || v.to_bits() == best[k].to_bits());
    let mut points: Vec<_> = tuned.points.iter().filter(|p| on_axis(&p.params)).collect();
    points.sort_by(|a, b| a.params[axis].total_cmp(&b.params[axis]));
    let percent = |v: f64| super::plots::percent_on_log_axis(v);
    let series = |f: fn(&crate::tune::EvaluatedPoint) -> f64| -> Vec<(f64, f64)> {
        points.iter().map(|p| (p.params[axis], percent(f(p)))).collect()
    };
    let name = &request.params[axis].0;
    let safe = tuned.safe[axis];
    let spec = request.spec(best).map(|s| s.label()).unwrap_or_default();
    Chart {
        stem: format!("tune_{}", name.replace(|c: char| !c.is_ascii_alphanumeric(), "_")),
        title: format!("tune {spec}: {}", request.aggregate_description()),
        x_label: name.clone(),
        y_label: "% of scored pixels (mean over scenes)".into(),
        log_x: true,
        series: vec![
            ("false shadow".into(), series(|p| p.false_shadow)),
            ("false lit".into(), series(|p| p.false_lit)),
            (objective_series_name(&request.objective), series(|p| p.objective)),
        ],
        panel_size: 3,
        marks: vec![Some(Marks {
            point: (best[axis], percent(tuned.best.value)),
            point_label: format!("optimum {name} = {}", best[axis]),
            band: (safe.lo, safe.hi),
            band_label: format!("safe range (≤ {:.0} % above)", 100.0 * crate::tune::SAFE_RANGE_SLACK),
        })],
        ..Chart::default()
    }
}

/// The objective's series: the total error, drawn in its colour, when that is what is
/// minimised; otherwise named for what it weighs.
fn objective_series_name(objective: &crate::tune::Objective) -> String {
    match objective {
        crate::tune::Objective::Total => "error (the objective)".into(),
        other => format!("objective: {}", other.describe()),
    }
}
