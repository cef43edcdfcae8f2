//! A swept plan entry runs exactly what its settings run one by one.

use super::common;
use crate::plan::{execute, parse_plan};
use crate::sinks::ReportWriter;
use serde_json::json;
use std::path::Path;

#[test]
fn a_sweep_of_20_biases_equals_20_separate_runs() {
    let biases: Vec<f64> = (0..20).map(|k| 1e-5 * 1.5f64.powi(k)).collect();
    let sweep_text = json!({
        "format": "shadowtruth/plan/v1",
        "techniques": [{ "technique": "constant", "bias_depth": biases }],
        "resolutions": [512], "repeats": 1
    })
    .to_string();
    let scene = common::repo().join("scenes/plane_box.json");
    let run = |plan_text: &str| {
        let mut plan = parse_plan(plan_text, Path::new("plan.json")).unwrap();
        plan.scenes = vec![scene.clone()];
        plan.figures = false;
        let dir = tempfile::tempdir().unwrap();
        let mut writer = ReportWriter::new(dir.path());
        execute(&plan, None, &mut [&mut writer]).unwrap();
        writer.into_report().runs
    };
    let swept = run(&sweep_text);
    assert_eq!(swept.len(), 20);
    for (k, b) in biases.iter().enumerate() {
        let single = run(&json!({
            "format": "shadowtruth/plan/v1",
            "techniques": [{ "technique": "constant", "bias_depth": b }],
            "resolutions": [512], "repeats": 1
        })
        .to_string());
        assert_eq!(single.len(), 1);
        assert_eq!(single[0].counts, swept[k].counts, "bias {b}");
        assert_eq!(single[0].parameters, swept[k].parameters);
    }
    assert!(swept.first().unwrap().counts.false_shadow > swept.last().unwrap().counts.false_shadow);
}
