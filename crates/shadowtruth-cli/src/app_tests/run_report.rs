//! A plan run end to end through the library: the report's records and their invariants.

use super::common;

use crate::plan::{Plan, execute};
use crate::report::ReportWriter;
use common::repo;
use shadowtruth::raster::DepthFormat;
use shadowtruth::record::{REPORT_SCHEMA, Report};
use shadowtruth::technique::{ConstantParams, CullSpec, NoneParams, SlopeScaledParams, TechniqueSpec};

#[test]
fn a_plan_writes_one_record_per_run_with_consistent_counts() {
    let dir = tempfile::tempdir().unwrap();
    let techniques = vec![
        TechniqueSpec::None(NoneParams {}),
        TechniqueSpec::Constant(ConstantParams { bias_depth: Some(1e-3), bias_world: None }),
        TechniqueSpec::SlopeScaled(SlopeScaledParams { factor: 1.0, units: 1.0, cull: CullSpec::None }),
    ];
    let plan = Plan {
        source: None,
        scenes: vec![repo().join("scenes/plane_box.json"), repo().join("scenes/spot.json")],
        cameras: None,
        lights: None,
        techniques: techniques.clone(),
        resolutions: vec![256, 512],
        depth_formats: vec![DepthFormat::F32, DepthFormat::Unorm16],
        repeats: 1,
        figures: false,
        zoom: None,
        coverage_grid: crate::plan::DEFAULT_COVERAGE_GRID,
        area_light_grid: crate::plan::DEFAULT_AREA_LIGHT_GRID,
        max_runs: crate::plan::DEFAULT_MAX_RUNS,
        shadow_map: None,
        pipeline: crate::plan::Pipeline::Cpu,
        frames: 1,
    };
    let mut writer = ReportWriter::new(dir.path());
    let mut done = 0;
    let mut count = crate::plan::Watch(|e: &crate::plan::Event| {
        if let crate::plan::Event::RunDone { .. } = e {
            done += 1
        }
    });
    execute(&plan, None, &mut [&mut writer, &mut count]).unwrap();
    let text = std::fs::read_to_string(dir.path().join("report.json")).unwrap();
    let report: Report = serde_json::from_str(&text).unwrap();
    assert_eq!(report.schema, REPORT_SCHEMA);
    assert_eq!(report.runs.len(), 2 * 3 * 2 * 2);
    assert_eq!(done, report.runs.len());
    assert_eq!(report.scenes.len(), 2);
    for run in &report.runs {
        let c = run.counts;
        assert_eq!(c.pixels, c.background + c.facing_away + c.outside_light + c.evaluated, "{}", run.label);
        assert!(c.false_shadow + c.false_lit <= c.evaluated);
        assert!((run.rates.error - (c.false_shadow + c.false_lit) as f64 / c.evaluated as f64).abs() < 1e-12);
        assert!(run.timings.shade >= 0.0 && run.layer_memory_bytes == (run.resolution as u64).pow(2) * 4);
    }
    // none and constant read the same layer, built once: the same preparation time.
    for res in [256, 512] {
        let prep: Vec<f64> = report
            .runs
            .iter()
            .filter(|r| {
                r.scene == "spot"
                    && r.resolution == res
                    && r.depth_format == "f32"
                    && r.technique != "slope_scaled"
            })
            .map(|r| r.timings.prepare)
            .collect();
        assert_eq!(prep.len(), 2);
        assert_eq!(prep[0], prep[1], "the layer was rebuilt");
    }
    // The spot scene has pixels outside the cone; the plane_box scene none.
    let spot = report.runs.iter().find(|r| r.scene == "spot").unwrap();
    assert!(spot.counts.outside_light > 0);
}
