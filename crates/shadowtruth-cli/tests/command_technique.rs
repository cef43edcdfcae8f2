//! The renderer-command protocol (plan technique `command`, docs/engines.md), with a renderer
//! whose answer is known: `shadowtruth reference` itself, writing the exact hard mask where the
//! protocol asks. Its runs score no error; flipped rows score exactly what the library scores
//! for the flipped mask; settings sweep and fill the command line; a command that fails, hangs
//! or writes the wrong size is an error naming the command and what it said.

#[path = "../../shadowtruth/tests/common/mod.rs"]
mod common;

use serde_json::{Value, json};
use shadowtruth::{GBuffer, ReadOptions, SceneBvh, read_visibility, score_imported, trace_hard_reference};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_shadowtruth");

/// A box on a plane under the sun, seen by a `width`×`height` camera; written into `dir`.
fn scene_file(dir: &Path, name: &str, width: u32, height: u32) -> PathBuf {
    let json = json!({
        "format": "shadowtruth/scene/v1", "name": name,
        "objects": [
            { "name": "ground", "shape": { "type": "plane", "size": [8, 8] } },
            { "name": "box", "shape": { "type": "box", "size": [1, 1, 1] }, "closed": true,
              "transform": { "translate": [0, 0.5, 0], "rotate_deg": [0, 30, 0] } }
        ],
        "cameras": [{ "name": "c", "position": [-4, 3, 4], "look_at": [0, 0.4, 0], "fov_y_deg": 45,
                      "width": width, "height": height }],
        "lights": [{ "name": "sun", "type": "directional", "direction": [-0.4, -1, -0.3] }]
    });
    let path = dir.join(format!("{name}.json"));
    std::fs::write(&path, serde_json::to_string_pretty(&json).unwrap()).unwrap();
    path
}

/// `shadowtruth reference SCENE` writing its mask to the protocol's `{visibility}`, with extra
/// arguments.
fn mask_command(scene: &Path, extra: &[&str]) -> Value {
    let mut run = vec![BIN.to_string(), "reference".into(), scene.display().to_string()];
    run.extend(["--camera", "{camera}", "--light", "{light}", "-o", "{visibility}"].map(String::from));
    run.extend(extra.iter().map(|s| s.to_string()));
    Value::from(run)
}

/// Runs a plan of `techniques` over `scene` into `dir/out`; the report's runs, or the command's
/// output when it fails.
fn run_plan(dir: &Path, scene: &Path, techniques: Value) -> Result<Vec<Value>, Output> {
    let plan = json!({
        "format": "shadowtruth/plan/v1", "scenes": [scene], "techniques": techniques,
        "resolutions": [256], "repeats": 1
    });
    let plan_path = dir.join("plan.json");
    std::fs::write(&plan_path, plan.to_string()).unwrap();
    let out = dir.join("out");
    let output = Command::new(BIN)
        .args(["run", "--plan"])
        .arg(&plan_path)
        .args(["--no-cache", "--no-figures", "--quiet", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    if !output.status.success() {
        return Err(output);
    }
    let report: Value = serde_json::from_slice(&std::fs::read(out.join("report.json")).unwrap()).unwrap();
    Ok(report["runs"].as_array().unwrap().clone())
}

fn count(run: &Value, key: &str) -> u64 {
    run["counts"][key].as_u64().unwrap_or(0)
}

#[test]
fn an_exact_renderer_scores_no_error_and_its_settings_sweep() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_file(dir.path(), "boxes", 160, 120);
    let technique = json!({
        "technique": "command", "name": "mask", "visibility_format": "png",
        "run": mask_command(&scene, &["--threads", "{threads}"]), "threads": [1, 2]
    });
    let runs = run_plan(dir.path(), &scene, json!([technique])).unwrap();
    let labels: Vec<&str> = runs.iter().map(|r| r["label"].as_str().unwrap()).collect();
    assert_eq!(labels, ["command(name=mask,threads=1)", "command(name=mask,threads=2)"]);
    for run in &runs {
        assert!(count(run, "evaluated") > 10_000, "{run}");
        assert_eq!((count(run, "false_shadow"), count(run, "false_lit")), (0, 0), "{run}");
        assert_eq!(run["parameters"]["run"][1], "reference", "the record keeps the command line");
    }
}

#[test]
fn flipped_rows_score_what_the_library_scores_for_the_flipped_mask() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_file(dir.path(), "boxes", 160, 120);
    let technique = json!({
        "technique": "command", "name": "mask", "visibility_format": "png", "flip_y": true,
        "run": mask_command(&scene, &[])
    });
    let runs = run_plan(dir.path(), &scene, json!([technique])).unwrap();
    // The same mask, written here and read flipped by the library.
    let mask = dir.path().join("mask.png");
    let written = Command::new(BIN).args(["reference"]).arg(&scene).arg("-o").arg(&mask).output().unwrap();
    assert!(written.status.success());
    let loaded = shadowtruth::load_scene(&scene).unwrap();
    let bvh = SceneBvh::build(&loaded);
    let (camera, light) = (&loaded.cameras[0], &loaded.lights[0]);
    let gbuffer = GBuffer::trace(&bvh, camera, light);
    let reference = trace_hard_reference(&loaded, &bvh, &gbuffer, light);
    let flipped = read_visibility(&mask, &ReadOptions { channel: None, flip_y: true }).unwrap();
    let expected = score_imported(&gbuffer, camera, &reference, &flipped, None, 1e-3).unwrap();
    assert!(expected.false_shadow + expected.false_lit > 100, "the flip is visible: {expected:?}");
    assert_eq!(count(&runs[0], "false_shadow"), expected.false_shadow);
    assert_eq!(count(&runs[0], "false_lit"), expected.false_lit);
}

/// The plan's error output for a command technique that goes wrong.
fn failure(technique: Value) -> String {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_file(dir.path(), "boxes", 160, 120);
    let mut technique = technique;
    if technique["run"] == "mask of another size" {
        let other = scene_file(dir.path(), "wide", 200, 100);
        technique["run"] = mask_command(&other, &[]);
    }
    let output = run_plan(dir.path(), &scene, json!([technique])).expect_err("the plan fails");
    assert_eq!(output.status.code(), Some(2), "an input error");
    String::from_utf8_lossy(&output.stderr).into_owned()
}

#[test]
fn a_command_that_fails_hangs_or_writes_the_wrong_size_is_an_error_naming_it() {
    let sh = |script: &str| json!(["sh", "-c", script, "renderer", "{visibility}"]);
    let failed = failure(json!({"technique": "command", "name": "broken",
        "run": sh("echo 'loading scene.glb' >&2; echo 'WebGL context lost' >&2; exit 3")}));
    assert!(failed.contains("technique command(name=broken)"), "{failed}");
    assert!(failed.contains("`sh -c"), "names the command: {failed}");
    assert!(failed.contains("exit status: 3") && failed.contains("WebGL context lost"), "{failed}");

    let hung =
        failure(json!({"technique": "command", "name": "hung", "timeout_s": 0.5, "run": sh("sleep 60")}));
    assert!(hung.contains("timeout of 0.5 s"), "{hung}");

    let silent = failure(json!({"technique": "command", "name": "silent", "run": sh("true")}));
    assert!(silent.contains("ran, but what it wrote cannot be scored"), "{silent}");

    let wide = failure(json!({"technique": "command", "name": "wide", "visibility_format": "png",
        "run": "mask of another size"}));
    assert!(wide.contains("200×100") && wide.contains("160×120"), "{wide}");
}

#[test]
fn a_command_entry_that_cannot_run_is_refused_before_anything_is_traced() {
    let refused = failure(json!({"technique": "command", "name": "x", "bias": 0.1,
        "run": ["node", "render.mjs", "{visibility}"]}));
    assert!(
        refused.contains("techniques[0]") && refused.contains("setting `bias` is never named"),
        "{refused}"
    );
}
