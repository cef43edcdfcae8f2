//! Point lights through the command: a plan over the bundled point-light techniques records each
//! run's cube, whose per-face counts add up to the run's; a renderer's `command` technique is
//! scored per face; what holds one map per light (`depth-map`, an imported shadow map) refuses a
//! point light, naming it.

#[path = "../../shadowtruth/tests/common/mod.rs"]
mod common;

use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_shadowtruth");

/// scenes/point/room.json seen by a 64×48 camera under two of its lamps, one with the default
/// guard band of 8 texels and one clamped at the seams, written into `dir`.
fn small_room(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(common::repo().join("scenes/point/room.json")).unwrap();
    let mut scene: Value = serde_json::from_str(&text).unwrap();
    scene["cameras"][0]["width"] = json!(64);
    scene["cameras"][0]["height"] = json!(48);
    let lamp = |name: &str, guard_texels: u32| {
        json!({ "name": name, "type": "point", "position": [0.1, 1.85, 0.05], "near": 0.05, "far": 12,
                "radius": 0.06, "cube_map": { "guard_texels": guard_texels } })
    };
    scene["lights"] = json!([lamp("lamp", 8), lamp("lamp_clamped", 0)]);
    let path = dir.join("room.json");
    std::fs::write(&path, serde_json::to_string_pretty(&scene).unwrap()).unwrap();
    path
}

fn shadowtruth(args: &[&str]) -> Output {
    Command::new(BIN).args(args).output().unwrap()
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

fn count(value: &Value, key: &str) -> u64 {
    value[key].as_u64().unwrap_or_else(|| panic!("no count {key} in {value}"))
}

#[test]
fn each_run_under_a_point_light_records_its_six_faces_whose_counts_add_up() {
    let dir = tempfile::tempdir().unwrap();
    let scene = small_room(dir.path());
    let plan = common::repo().join("plans/point-lights.json");
    let out = dir.path().join("out");
    let output = shadowtruth(&[
        "run",
        scene.to_str().unwrap(),
        "--plan",
        plan.to_str().unwrap(),
        "--resolutions",
        "64",
        "--no-cache",
        "--no-figures",
        "--quiet",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let report: Value = serde_json::from_slice(&std::fs::read(out.join("report.json")).unwrap()).unwrap();
    let runs = report["runs"].as_array().unwrap();
    // Twelve techniques, nineteen settings once swept, under each of the two lamps.
    assert_eq!(runs.len(), 2 * 19, "{} runs", runs.len());
    let (mut near_seam_anywhere, mut seam_anywhere) = (0, 0);
    for run in runs {
        let what = format!("{} {}", run["light"], run["label"]);
        assert_eq!(run["resolution"], 64, "{what}");
        let guard = match run["light"].as_str().unwrap() {
            "lamp" => 8,
            "lamp_clamped" => 0,
            other => panic!("light {other}"),
        };
        let cube = &run["point_map"];
        assert_eq!(cube["layout"], "cube", "{what}");
        assert_eq!(cube["guard_texels"], guard, "{what}");
        assert_eq!(cube["face_texels"], 64 + 2 * guard, "{what}");
        let faces = cube["faces"].as_array().unwrap_or_else(|| panic!("{what}: no point map in {run}"));
        let names: Vec<&str> = faces.iter().map(|f| f["face"].as_str().unwrap()).collect();
        assert_eq!(names, ["+x", "-x", "+y", "-y", "+z", "-z"], "{what}");
        for key in ["evaluated", "false_shadow", "false_lit"] {
            let sum: u64 = faces.iter().map(|f| count(&f["counts"], key)).sum();
            assert_eq!(sum, count(&run["counts"], key), "{what}: {key} over the faces");
        }
        // Every false pixel has one class; a seam one lies near a seam of its face.
        let counts = &run["counts"];
        let classes: u64 =
            ["aliasing", "seam", "acne", "leak", "light_bleeding"].iter().map(|k| count(counts, k)).sum();
        assert_eq!(classes, count(counts, "false_shadow") + count(counts, "false_lit"), "{what}");
        let false_near_seams: u64 = faces
            .iter()
            .map(|f| count(&f["near_seam"], "false_shadow") + count(&f["near_seam"], "false_lit"))
            .sum();
        assert!(count(counts, "seam") <= false_near_seams, "{what}: seam class beyond the near-seam pixels");
        seam_anywhere += count(counts, "seam");
        for face in faces {
            let (all, seam) = (&face["counts"], &face["near_seam"]);
            for key in ["evaluated", "false_shadow", "false_lit"] {
                assert!(
                    count(seam, key) <= count(all, key),
                    "{what}: {key} near the seams of {}",
                    face["face"]
                );
            }
            near_seam_anywhere += count(seam, "evaluated");
        }
        // The camera sees the floor, the walls and the table: four faces at least.
        let seen = faces.iter().filter(|f| count(&f["counts"], "evaluated") > 0).count();
        assert!(seen >= 4, "{what}: {seen} faces shade pixels");
        assert!(count(&run["counts"], "evaluated") > 1000, "{what}");
    }
    assert!(near_seam_anywhere > 0, "some pixels lie near a seam");
    assert!(seam_anywhere > 0, "some false pixels near a seam are the seam class");
}

#[test]
fn an_exact_renderer_under_a_point_light_is_scored_per_face_without_error() {
    // The `command` protocol exports each view (the cube's faces in view.json) and scores what
    // the command writes: here the hard reference itself, which must score no error on any face.
    let dir = tempfile::tempdir().unwrap();
    let scene = small_room(dir.path());
    let run = [BIN, "reference", scene.to_str().unwrap(), "--camera", "{camera}", "--light", "{light}"];
    let run: Vec<&str> = run.into_iter().chain(["-o", "{visibility}"]).collect();
    let plan = json!({
        "format": "shadowtruth/plan/v1", "scenes": [scene],
        "techniques": [{ "technique": "command", "name": "renderer", "visibility_format": "png", "run": run }],
        "resolutions": [64], "repeats": 1
    });
    let plan_path = dir.path().join("plan.json");
    std::fs::write(&plan_path, plan.to_string()).unwrap();
    let out = dir.path().join("out");
    let args = ["run", "--plan", plan_path.to_str().unwrap(), "--no-cache", "--no-figures", "--quiet", "-o"];
    let output = shadowtruth(&[&args[..], &[out.to_str().unwrap()]].concat());
    assert!(output.status.success(), "{}", stderr(&output));
    let report: Value = serde_json::from_slice(&std::fs::read(out.join("report.json")).unwrap()).unwrap();
    let runs = report["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 2, "one run per lamp");
    for run in runs {
        let counts = &run["counts"];
        assert!(count(counts, "evaluated") > 1000, "{run}");
        assert_eq!((count(counts, "false_shadow"), count(counts, "false_lit")), (0, 0), "{run}");
        let faces = run["point_map"]["faces"].as_array().unwrap();
        let evaluated: u64 = faces.iter().map(|f| count(&f["counts"], "evaluated")).sum();
        assert_eq!(evaluated, count(counts, "evaluated"), "{run}");
    }
}

#[test]
fn depth_map_and_an_imported_map_refuse_a_point_light() {
    let dir = tempfile::tempdir().unwrap();
    let scene = small_room(dir.path());
    let bundled = common::repo().join("scenes/point/room.json");
    let map = dir.path().join("x.exr");
    let output = shadowtruth(&[
        "depth-map",
        bundled.to_str().unwrap(),
        "--resolution",
        "64",
        "-o",
        map.to_str().unwrap(),
    ]);
    let message = stderr(&output);
    assert_eq!(output.status.code(), Some(2), "{message}");
    assert!(
        message.contains("room.json") && message.contains("'lamp'") && message.contains("point light"),
        "{message}"
    );
    assert!(!map.exists(), "no map written");

    // An imported shadow map is one map: `score` refuses it for a point light.
    let renders = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad_inputs/renders");
    let technique = r#"{"technique": "none"}"#;
    let output = Command::new(BIN)
        .args(["score", scene.to_str().unwrap(), "--camera", "main", "--light", "lamp", "--shadow-map"])
        .arg(renders.join("map.exr"))
        .arg("--clip-from-world")
        .arg(renders.join("map.json"))
        .args(["--technique", technique, "--no-cache", "--no-figures", "--quiet", "-o"])
        .arg(dir.path().join("score"))
        .output()
        .unwrap();
    let message = stderr(&output);
    assert_eq!(output.status.code(), Some(2), "{message}");
    assert!(
        message.contains("map.json") && message.contains("'lamp'") && message.contains("point light"),
        "{message}"
    );
}
