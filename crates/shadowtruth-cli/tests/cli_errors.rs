//! Bad input gets a clear error naming the file and the field, exit code 2, and never a panic.

use std::path::Path;
use std::process::Command;

fn shadowtruth(args: &[&str], dir: &Path) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_shadowtruth")).args(args).current_dir(dir).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!stderr.contains("panicked"), "panic on {args:?}: {stderr}");
    (out.status.code().unwrap_or(-1), stderr)
}

const GOOD_CAMERA: &str = r#"{ "name": "c", "position": [0, 3, 5], "look_at": [0, 0, 0], "fov_y_deg": 45, "width": 64, "height": 48 }"#;
const GOOD_LIGHT: &str = r#"{ "name": "l", "type": "directional", "direction": [0, -1, 0.2] }"#;
const GOOD_OBJECT: &str = r#"{ "name": "g", "shape": { "type": "plane", "size": [4, 4] } }"#;

fn scene(objects: &str, cameras: &str, lights: &str) -> String {
    format!(
        r#"{{ "format": "shadowtruth/scene/v1", "name": "t", "objects": [{objects}], "cameras": [{cameras}], "lights": [{lights}] }}"#
    )
}

/// (description, scene text, strings the error must contain)
fn bad_scenes() -> Vec<(&'static str, String, Vec<&'static str>)> {
    vec![
        ("malformed JSON", "{ \"format\": ".to_string(), vec!["bad.json", "line"]),
        (
            "missing mesh",
            scene(r#"{ "name": "m", "mesh": "nowhere.obj" }"#, GOOD_CAMERA, GOOD_LIGHT),
            vec!["bad.json", "objects[0].mesh", "nowhere.obj"],
        ),
        (
            "infinite number",
            scene(GOOD_OBJECT, &GOOD_CAMERA.replace("45", "1e999"), GOOD_LIGHT),
            vec!["bad.json", "cameras[0].fov_y_deg"],
        ),
        (
            "zero-length direction",
            scene(
                GOOD_OBJECT,
                GOOD_CAMERA,
                r#"{ "name": "l", "type": "directional", "direction": [0, 0, 0] }"#,
            ),
            vec!["bad.json", "lights[0].direction"],
        ),
        (
            "degenerate camera",
            scene(GOOD_OBJECT, &GOOD_CAMERA.replace("[0, 3, 5]", "[0, 0, 0]"), GOOD_LIGHT),
            vec!["bad.json", "cameras[0]"],
        ),
        ("empty scene", scene("", GOOD_CAMERA, GOOD_LIGHT), vec!["bad.json", "objects"]),
        (
            "absurd image size",
            scene(GOOD_OBJECT, &GOOD_CAMERA.replace("\"width\": 64", "\"width\": 1000000"), GOOD_LIGHT),
            vec!["bad.json", "cameras[0].width"],
        ),
        (
            "unknown field",
            scene(
                r#"{ "name": "g", "shape": { "type": "plane", "size": [4, 4] }, "colour": "red" }"#,
                GOOD_CAMERA,
                GOOD_LIGHT,
            ),
            vec!["bad.json", "objects[0]", "colour"],
        ),
    ]
}

#[test]
fn bad_scenes_exit_2_naming_file_and_field() {
    let dir = tempfile::tempdir().unwrap();
    for (what, text, needles) in bad_scenes() {
        std::fs::write(dir.path().join("bad.json"), &text).unwrap();
        for args in [
            vec!["run", "bad.json", "-o", "out", "--quiet", "--no-cache"],
            vec!["reference", "bad.json", "-o", "mask.png"],
            vec!["export-obj", "bad.json", "-o", "world.obj"],
        ] {
            let (code, stderr) = shadowtruth(&args, dir.path());
            assert_eq!(code, 2, "{what} with {args:?}: exit code {code}, stderr: {stderr}");
            for n in &needles {
                assert!(stderr.contains(n), "{what} with {args:?}: error lacks '{n}': {stderr}");
            }
        }
        assert!(!dir.path().join("out/report.json").exists(), "{what}: a report was written for bad input");
    }
}

#[test]
fn usage_errors_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.json"), scene(GOOD_OBJECT, GOOD_CAMERA, GOOD_LIGHT)).unwrap();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["frobnicate"], "frobnicate"),
        (vec!["run", "missing.json"], "missing.json"),
        (vec!["reference", "s.json", "--camera", "nope", "-o", "m.png"], "nope"),
        (vec!["reference", "s.json", "--light", "nope", "-o", "m.png"], "nope"),
        (vec!["run", "s.json", "--plan", "missing-plan.json"], "missing-plan.json"),
        (vec!["run", "s.json", "--resolutions", "0", "--quiet", "--no-cache"], "resolution"),
        (vec!["run", "s.json", "--threads", "0"], "threads"),
        // An output named for another format than the one written.
        (vec!["reference", "s.json", "-o", "m.jpg"], "must end in .png (it has '.jpg')"),
        (vec!["reference", "s.json", "--kind", "coverage", "-o", "c.png"], "must end in .exr"),
        (vec!["depth-map", "s.json", "--resolution", "64", "-o", "d.png"], "must end in .exr"),
        (vec!["export-obj", "s.json", "-o", "w"], "must end in .obj (it has no extension)"),
    ];
    for (args, needle) in cases {
        let (code, stderr) = shadowtruth(&args, dir.path());
        assert_eq!(code, 2, "{args:?}: exit code {code}, stderr: {stderr}");
        assert!(stderr.contains(needle), "{args:?}: error lacks '{needle}': {stderr}");
    }
    for wrong in ["m.jpg", "c.png", "d.png", "w"] {
        assert!(!dir.path().join(wrong).exists(), "{wrong} was written");
    }
}

#[test]
fn bad_plan_files_exit_2_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.json"), scene(GOOD_OBJECT, GOOD_CAMERA, GOOD_LIGHT)).unwrap();
    let plans = [
        (
            r#"{ "format": "shadowtruth/plan/v1", "techniques": [{ "technique": "sorcery" }], "resolutions": [64] }"#,
            "sorcery",
        ),
        (
            r#"{ "format": "shadowtruth/plan/v1", "techniques": [{ "technique": "constant" }], "resolutions": [64] }"#,
            "bias",
        ),
        (r#"{ "format": "shadowtruth/plan/v2", "techniques": [], "resolutions": [64] }"#, "format"),
        (
            r#"{ "format": "shadowtruth/plan/v1", "techniques": [{ "technique": "none" }], "resolutions": [64], "depth_formats": ["f64"] }"#,
            "depth_formats[0]",
        ),
    ];
    for (text, needle) in plans {
        std::fs::write(dir.path().join("plan.json"), text).unwrap();
        let (code, stderr) =
            shadowtruth(&["run", "s.json", "--plan", "plan.json", "--quiet", "--no-cache"], dir.path());
        assert_eq!(code, 2, "{text}: {stderr}");
        assert!(stderr.contains("plan.json") && stderr.contains(needle), "{text}: {stderr}");
    }
}

#[test]
fn a_plan_naming_a_missing_camera_or_light_exits_2() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.json"), scene(GOOD_OBJECT, GOOD_CAMERA, GOOD_LIGHT)).unwrap();
    for (key, needle) in [
        ("cameras", "plan.json: cameras[0]: no camera named 'nope' in s.json (it has: c)"),
        ("lights", "plan.json: lights[0]: no light named 'nope' in s.json (it has: l)"),
    ] {
        let plan = format!(
            r#"{{ "format": "shadowtruth/plan/v1", "{key}": ["nope"], "techniques": [{{ "technique": "none" }}], "resolutions": [64] }}"#
        );
        std::fs::write(dir.path().join("plan.json"), plan).unwrap();
        let (code, stderr) =
            shadowtruth(&["run", "s.json", "--plan", "plan.json", "--quiet", "--no-cache"], dir.path());
        assert_eq!(code, 2, "{stderr}");
        assert!(stderr.contains(needle), "{stderr}");
    }
}
