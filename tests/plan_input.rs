//! Plans are refused before anything is built when they are too large or wrong, and every
//! problem names the plan file and its JSON path.

use shadowtruth::plan::{PlanInputError, parse_plan, parse_plan_limited};
use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

const SCENE: &str = r#"{ "format": "shadowtruth/scene/v1", "name": "t",
  "objects": [ { "name": "g", "shape": { "type": "plane", "size": [4, 4] } } ],
  "cameras": [ { "name": "c", "position": [0, 3, 5], "look_at": [0, 0, 0], "fov_y_deg": 45, "width": 32, "height": 24 } ],
  "lights": [ { "name": "l", "type": "directional", "direction": [0, -1, 0.2] } ] }"#;

/// A plan over `s.json` with these technique entries and extra top-level fields.
fn plan(techniques: &str, extra: &str) -> String {
    format!(
        r#"{{ "format": "shadowtruth/plan/v1", "scenes": ["s.json"], "techniques": [{techniques}], "resolutions": [64]{extra} }}"#
    )
}

/// Runs `shadowtruth run --plan plan.json` in a folder holding `s.json` (`scene`) and the plan;
/// returns (exit code, stderr, wall time, peak resident memory in bytes).
// The child is reaped by `wait4`, which clippy does not know.
#[allow(clippy::zombie_processes)]
fn run_plan(plan: &str, scene: &str, args: &[&str]) -> (i32, String, Duration, u64) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.json"), scene).unwrap();
    std::fs::write(dir.path().join("plan.json"), plan).unwrap();
    let started = Instant::now();
    let mut child = Command::new(env!("CARGO_BIN_EXE_shadowtruth"))
        .args(["run", "--plan", "plan.json", "--quiet", "--no-cache", "--no-figures", "-o", "out"])
        .args(args)
        .current_dir(dir.path())
        .stderr(std::process::Stdio::piped())
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let mut stderr = String::new();
    std::io::Read::read_to_string(child.stderr.as_mut().unwrap(), &mut stderr).unwrap();
    // wait4 gives this child's own peak memory, whatever other tests run meanwhile.
    let (mut status, mut usage) = (0, unsafe { std::mem::zeroed::<libc::rusage>() });
    let pid = unsafe { libc::wait4(child.id() as i32, &mut status, 0, &mut usage) };
    assert_eq!(pid, child.id() as i32);
    let wall = started.elapsed();
    assert!(!stderr.contains("panicked"), "{stderr}");
    let code = if libc::WIFEXITED(status) { libc::WEXITSTATUS(status) } else { -1 };
    (code, stderr, wall, usage.ru_maxrss as u64 * 1024)
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
fn a_plan_of_1e8_runs_exits_2_within_a_second_in_little_memory() {
    let values: Vec<String> = (0..10_000).map(|i| format!("{}", i as f64 * 1e-6)).collect();
    let list = values.join(", ");
    let text =
        plan(&format!(r#"{{ "technique": "slope_scaled", "factor": [{list}], "units": [{list}] }}"#), "");
    let (code, stderr, wall, peak_bytes) = run_plan(&text, SCENE, &[]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("plan.json: techniques[0]: the plan expands to at least 100000000 runs")
            && stderr.contains("limit of 100000")
            && stderr.contains("--max-runs")
            && stderr.contains("factor: 10000 values × units: 10000 values"),
        "{stderr}"
    );
    assert!(wall < Duration::from_secs(1), "took {wall:?}");
    assert!(peak_bytes < 100 << 20, "peak memory {} MB", peak_bytes >> 20);
}

#[test]
fn the_run_limit_counts_views_and_can_be_raised() {
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
    // At run time the scene's views count too: one view of 2 000 runs over a limit of 1 999.
    let text = plan_text_sweep(1000);
    let (code, stderr, _, _) = run_plan(&text, SCENE, &["--max-runs", "1999"]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("plan.json") && stderr.contains("2000 runs"), "{stderr}");
}

fn plan_text_sweep(n: usize) -> String {
    let values: Vec<String> = (1..=n).map(|i| format!("{}", i as f64 * 1e-5)).collect();
    format!(
        r#"{{ "format": "shadowtruth/plan/v1", "scenes": ["s.json"],
             "techniques": [{{ "technique": "constant", "bias_depth": [{}] }}], "resolutions": [64, 128] }}"#,
        values.join(", ")
    )
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
    let e = problems(&plan(r#"{ "technique": "none" }"#, r#", "depth_formats": ["f32", "f16"], "lamps": 1"#));
    assert!(message_at(&e, "depth_formats[1]").contains("f16"), "{e}");
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
fn a_missing_scene_file_names_the_plan_path() {
    let text =
        plan(r#"{ "technique": "none" }"#, "").replace(r#"["s.json"]"#, r#"["s.json", "nowhere.json"]"#);
    let (code, stderr, _, _) = run_plan(&text, SCENE, &[]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("plan.json: scenes[1]: no such scene file or folder")
            && stderr.contains("nowhere.json"),
        "{stderr}"
    );
}

#[test]
fn a_camera_or_light_the_scene_lacks_names_the_plan_path_and_the_scene() {
    for (key, kind) in [("cameras", "camera"), ("lights", "light")] {
        let present = &kind[..1]; // the scene's camera is `c`, its light `l`
        let text = plan(r#"{ "technique": "none" }"#, &format!(r#", "{key}": ["{present}", "nope"]"#));
        let (code, stderr, _, _) = run_plan(&text, SCENE, &[]);
        assert_eq!(code, 2, "{stderr}");
        assert!(
            stderr.contains(&format!("plan.json: {key}[1]: no {kind} named 'nope' in s.json")),
            "{stderr}"
        );
    }
}

#[test]
fn a_scene_without_a_light_or_a_plan_without_runs_is_bad_input() {
    let no_light = SCENE.replace(r#"{ "name": "l", "type": "directional", "direction": [0, -1, 0.2] }"#, "");
    let (code, stderr, _, _) = run_plan(&plan(r#"{ "technique": "none" }"#, ""), &no_light, &[]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("s.json: lights: the scene has no light"), "{stderr}");
    let e = problems(&plan(r#"{ "technique": "none" }"#, "").replace(r#"["s.json"]"#, "[]"));
    assert!(message_at(&e, "scenes").contains("empty list"), "{e}");
}
