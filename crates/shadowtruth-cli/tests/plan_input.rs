//! Plans are refused before anything is built when they are too large or wrong, and every
//! problem names the plan file and its JSON path.

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
fn at_run_time_the_scenes_views_count_towards_the_run_limit() {
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
    let no_scene = plan(r#"{ "technique": "none" }"#, "").replace(r#"["s.json"]"#, "[]");
    let (code, stderr, _, _) = run_plan(&no_scene, SCENE, &[]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("plan.json: scenes: an empty list"), "{stderr}");
}
