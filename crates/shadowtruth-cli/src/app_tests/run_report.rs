//! A plan run end to end through the library: the report's records and their invariants.

use super::common;

use crate::plan::{Event, Plan, PlanError, Portion, Sink, Watch, execute, execute_portion};
use crate::sinks::ReportWriter;
use common::repo;
use shadowtruth::raster::DepthFormat;
use shadowtruth::record::{REPORT_SCHEMA, Report};
use shadowtruth::technique::{ConstantParams, CullSpec, NoneParams, SlopeScaledParams, TechniqueSpec};

/// Three techniques over `scenes` at `resolutions`, in f32 and unorm16, without figures.
fn plan_of(scenes: &[&str], resolutions: Vec<u32>) -> Plan {
    let techniques = vec![
        TechniqueSpec::None(NoneParams {}),
        TechniqueSpec::Constant(ConstantParams { bias_depth: Some(1e-3), bias_world: None }),
        TechniqueSpec::SlopeScaled(SlopeScaledParams { factor: 1.0, units: 1.0, cull: CullSpec::None }),
    ];
    Plan {
        depth_formats: vec![DepthFormat::F32, DepthFormat::Unorm16],
        repeats: 1,
        figures: false,
        ..Plan::new(scenes.iter().map(|s| repo().join(s)).collect(), techniques, resolutions)
    }
}

#[test]
fn a_plan_writes_one_record_per_run_with_consistent_counts() {
    let dir = tempfile::tempdir().unwrap();
    let plan = plan_of(&["scenes/plane_box.json", "scenes/spot.json"], vec![256, 512]);
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
        let classes = c.background + c.facing_away + c.outside_light + c.evaluated + c.uncertain;
        assert_eq!(c.pixels, classes, "{}", run.label);
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

/// A sink that stops the plan after `runs` runs, as a kill would (the writer before it has
/// journaled the last one).
struct KillAfter {
    runs: usize,
}

impl Sink for KillAfter {
    fn on_event(&mut self, event: &Event) -> Result<(), PlanError> {
        if let Event::RunDone { .. } = event {
            self.runs -= 1;
            if self.runs == 0 {
                return Err(PlanError::Invalid("killed".into()));
            }
        }
        Ok(())
    }
}

fn without_timings(mut report: Report) -> serde_json::Value {
    report.created = String::new();
    report.scenes.iter_mut().for_each(|s| s.bvh_build_ms = 0.0);
    report.runs.iter_mut().for_each(|r| r.timings = Default::default());
    serde_json::to_value(report).unwrap()
}

#[test]
fn a_run_killed_midway_resumes_from_report_json_and_its_journal() {
    let plan = plan_of(&["scenes/plane_box.json"], vec![64, 128]);
    let whole = tempfile::tempdir().unwrap();
    let mut writer = ReportWriter::create(whole.path()).unwrap();
    writer.track_schedule(None);
    execute(&plan, None, &mut [&mut writer]).unwrap();
    let whole = writer.into_report();
    let runs_per_map = whole.schedule.as_ref().unwrap().runs_per_map;
    assert!(whole.runs.len() >= 3 * runs_per_map, "{} runs", whole.runs.len());

    let dir = tempfile::tempdir().unwrap();
    let mut writer = ReportWriter::create(dir.path()).unwrap();
    writer.track_schedule(None);
    // Killed one run into the third map: nothing more is written, as after SIGKILL.
    let killed = 2 * runs_per_map + 1;
    assert!(execute(&plan, None, &mut [&mut writer, &mut KillAfter { runs: killed }]).is_err());
    std::mem::forget(writer);
    let on_disk: Report =
        serde_json::from_slice(&std::fs::read(dir.path().join("report.json")).unwrap()).unwrap();
    assert!(on_disk.runs.len() < killed, "report.json is not rewritten after every run");
    let journal = std::fs::read_to_string(dir.path().join("report.journal")).unwrap();
    assert_eq!(journal.lines().filter(|l| l.starts_with("{\"run\":")).count(), killed);

    let resumed = crate::shards::open_resumed(dir.path(), false, None).unwrap().unwrap();
    assert_eq!((resumed.report.runs.len(), resumed.dropped_runs), (2 * runs_per_map, 1));
    let portion = Portion { done: resumed.done, ..Portion::default() };
    let mut writer = ReportWriter::resume(dir.path(), resumed.report).unwrap();
    writer.track_schedule(None);
    let mut run_again = 0;
    let mut count = Watch(|e: &Event| run_again += matches!(e, Event::RunDone { .. }) as usize);
    execute_portion(&plan, None, &mut [&mut writer, &mut count], &portion).unwrap();
    assert_eq!(run_again, whole.runs.len() - 2 * runs_per_map, "the recorded maps are not run again");
    assert!(!dir.path().join("report.journal").exists(), "folded into report.json at the end");
    let (read, _) = shadowtruth::record::load_report(dir.path()).unwrap();
    assert_eq!(without_timings(read), without_timings(whole));
}
