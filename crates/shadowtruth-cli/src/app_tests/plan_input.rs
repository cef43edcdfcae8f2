//! Plans with problems: every problem names the plan file and its JSON path; the run limit
//! counts a sweep's settings before they are expanded.

use crate::plan::{PlanInputError, parse_plan, parse_plan_limited};
use std::path::Path;

/// A plan over `s.json` with these technique entries and extra top-level fields.
fn plan(techniques: &str, extra: &str) -> String {
    format!(
        r#"{{ "format": "shadowtruth/plan/v1", "scenes": ["s.json"], "techniques": [{techniques}], "resolutions": [64]{extra} }}"#
    )
}

fn problems(text: &str) -> PlanInputError {
    parse_plan(text, Path::new("dir/plan.json")).expect_err("a bad plan")
}

/// The one problem at `path`, or a panic listing them all.
fn message_at(e: &PlanInputError, path: &str) -> String {
    let found: Vec<&str> = e.problems.iter().filter(|p| p.path == path).map(|p| p.message.as_str()).collect();
    assert_eq!(found.len(), 1, "expected one problem at {path}: {e}");
    assert!(e.problems.iter().all(|p| p.file == Path::new("dir/plan.json")), "{e}");
    found[0].to_string()
}

#[test]
fn the_run_limit_counts_a_sweeps_settings_and_can_be_raised() {
    let values: Vec<String> = (1..=1000).map(|i| format!("{}", i as f64 * 1e-5)).collect();
    let text = format!(
        r#"{{ "format": "shadowtruth/plan/v1", "techniques": [{{ "technique": "constant", "bias_depth": [{}] }}],
             "resolutions": [64, 128], "cameras": ["a", "b"], "lights": ["x", "y", "z"] }}"#,
        values.join(", ")
    );
    // 1000 settings × 2 resolutions × 2 cameras × 3 lights.
    let e = parse_plan_limited(&text, Path::new("dir/plan.json"), 11_999).expect_err("12 000 runs");
    assert!(message_at(&e, "techniques[0]").contains("at least 12000 runs"), "{e}");
    let plan = parse_plan_limited(&text, Path::new("dir/plan.json"), 12_000).expect("at the limit");
    assert_eq!(plan.techniques.len(), 1000);
}

#[test]
fn plan_errors_name_the_file_and_the_json_path() {
    let e = problems(&plan(r#"{ "technique": "none" }"#, "").replace("[64]", "[64, 0, 20000]"));
    assert!(message_at(&e, "resolutions[1]").contains("between 1 and 16384"), "{e}");
    assert!(message_at(&e, "resolutions[2]").contains("found 20000"), "{e}");
    let e = problems(&plan("", ""));
    assert!(message_at(&e, "techniques").contains("at least one technique"), "{e}");
    let e = problems(&plan(r#"{ "technique": "none" }"#, r#", "repeats": 0, "coverage_grid": 65"#));
    assert!(message_at(&e, "repeats").contains("between 1 and 1000"), "{e}");
    assert!(message_at(&e, "coverage_grid").contains("between 1 and 64"), "{e}");
    let e = problems(&plan(r#"{ "technique": "none" }"#, r#", "depth_formats": ["f32", "f64"], "lamps": 1"#));
    assert!(message_at(&e, "depth_formats[1]").contains("f64"), "{e}");
    assert!(message_at(&e, "lamps").contains("unknown field"), "{e}");
    let e = problems(&plan(r#"{ "technique": "none" }"#, r#", "cameras": []"#));
    assert!(message_at(&e, "cameras").contains("empty list"), "{e}");
}

#[test]
fn technique_errors_name_the_entry_the_parameter_and_the_swept_value() {
    let e = problems(&plan(
        r#"{ "technique": "none" }, { "technique": "constant", "bias_depth": [0.001, -0.001] }"#,
        "",
    ));
    assert!(message_at(&e, "techniques[1].bias_depth[1]").contains("≥ 0, found -0.001"), "{e}");
    let e = problems(&plan(r#"{ "technique": "sorcery" }"#, ""));
    assert!(message_at(&e, "techniques[0].technique").contains("sorcery"), "{e}");
    let e = problems(&plan(r#"{ "technique": "slope_scaled", "factor": "steep", "units": 1 }"#, ""));
    assert!(message_at(&e, "techniques[0].factor").contains("invalid type"), "{e}");
    let e = problems(&plan(r#"{ "technique": "slope_scaled", "factor": 1 }"#, ""));
    assert!(message_at(&e, "techniques[0].units").contains("missing field"), "{e}");
    let e = problems(&plan(
        r#"{ "technique": "slope_scaled", "factor": 1, "units": 1, "cull": "sideways" }"#,
        "",
    ));
    assert!(message_at(&e, "techniques[0].cull").contains("sideways"), "{e}");
    let e = problems(&plan(r#"{ "technique": "pcf", "kernel": "gaussian" }"#, ""));
    assert!(message_at(&e, "techniques[0].kernel").contains("gaussian"), "{e}");
    let e = problems(&plan(r#"{ "technique": "pcf", "kernel": "box", "colour": 1 }"#, ""));
    assert!(message_at(&e, "techniques[0].colour").contains("unknown field"), "{e}");
    let e = problems(&plan(r#"{ "technique": "dual", "z_offset": [] }"#, ""));
    assert!(message_at(&e, "techniques[0].z_offset").contains("empty list"), "{e}");
    let e = problems(&plan(r#"{ "bias_depth": 0.1 }"#, ""));
    assert!(message_at(&e, "techniques[0]").contains("technique"), "{e}");
}

#[test]
fn parameters_without_meaning_below_zero_are_refused() {
    for (entry, field) in [
        (r#"{ "technique": "constant", "bias_depth": -0.001 }"#, "bias_depth"),
        (r#"{ "technique": "constant", "bias_world": -0.01 }"#, "bias_world"),
        (r#"{ "technique": "normal_offset", "scale_texels": -1 }"#, "scale_texels"),
        (r#"{ "technique": "slope_scaled", "factor": -1, "units": 1 }"#, "factor"),
        (r#"{ "technique": "slope_scaled", "factor": 1, "units": -1 }"#, "units"),
        (r#"{ "technique": "receiver_plane", "bias_depth": -1e-5 }"#, "bias_depth"),
        (r#"{ "technique": "second_depth", "bias_depth": -1e-5 }"#, "bias_depth"),
        (r#"{ "technique": "pcf", "bias": "constant", "bias_depth": -1e-5 }"#, "bias_depth"),
        (r#"{ "technique": "pcf", "bias": "slope_scaled", "factor": -2 }"#, "factor"),
    ] {
        let e = problems(&plan(entry, ""));
        assert!(message_at(&e, &format!("techniques[0].{field}")).contains("≥ 0"), "{entry}: {e}");
        // Zero stays valid: it is the plain depth test.
        let zero = entry.replace("-0.001", "0").replace("-0.01", "0").replace("-1e-5", "0");
        let zero = zero.replace(": -1,", ": 0,").replace(": -1 ", ": 0 ").replace(": -2", ": 0");
        parse_plan(&plan(&zero, ""), Path::new("plan.json")).unwrap_or_else(|e| panic!("{zero}: {e}"));
    }
}

#[test]
fn every_bundled_plan_reads_and_every_technique_builds_or_names_a_bundled_engine() {
    let dir = super::common::repo().join("plans");
    let mut read = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|x| x != "json") {
            continue;
        }
        let plan = crate::plan::read_plan(&path, crate::plan::DEFAULT_MAX_RUNS)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        for t in &plan.techniques {
            // A renderer's command is not built here: its program must exist instead.
            if let shadowtruth::technique::TechniqueSpec::Command(c) = t {
                let script =
                    c.run.iter().find(|a| a.starts_with("engines/")).expect("a bundled engine's script");
                assert!(super::common::repo().join(script).is_file(), "{}: {script}", path.display());
                continue;
            }
            assert!(t.build().is_some(), "{}: {} builds", path.display(), t.label());
        }
        read += 1;
    }
    assert!(read >= 5, "the plans folder holds the bundled plans");
}

/// A binary built without the device code refuses the GPU pipeline at the plan's `pipeline`,
/// before any scene is loaded, saying why.
#[cfg(not(feature = "gpu"))]
#[test]
fn the_gpu_pipeline_without_the_gpu_feature_is_refused_at_pipeline() {
    let text = plan(r#"{ "technique": "none" }"#, r#", "pipeline": "gpu""#);
    let plan = parse_plan(&text, Path::new("dir/plan.json")).expect("a valid plan file");
    let e = match crate::plan::check_plan(&plan) {
        Err(crate::plan::PlanError::Input(e)) => e,
        other => panic!("expected a plan input error, got {:?}", other.err()),
    };
    assert!(message_at(&e, "pipeline").contains("built without the `gpu` feature"), "{e}");
}
