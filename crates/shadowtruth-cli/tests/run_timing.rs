//! `run --timing`: each layer group's rasterization and its shading are timed apart, the group
//! named by its layers, culling and offset.

#[path = "../../shadowtruth/tests/common/mod.rs"]
mod common;

use std::process::Command;

#[test]
fn timing_names_each_layer_groups_rasterization_and_shading() {
    let dir = tempfile::tempdir().unwrap();
    let plan = serde_json::json!({
        "format": "shadowtruth/plan/v1", "scenes": [common::repo().join("scenes/plane_box.json")],
        "techniques": [
            { "technique": "constant", "bias_depth": [0.001, 0.002] },
            { "technique": "slope_scaled", "factor": 2, "units": 4, "cull": "back" }
        ],
        "resolutions": [256], "repeats": 1
    });
    let plan_path = dir.path().join("plan.json");
    std::fs::write(&plan_path, plan.to_string()).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_shadowtruth"))
        .args(["run", "--plan"])
        .arg(&plan_path)
        .args(["--no-cache", "--no-figures", "--quiet", "--timing", "-o"])
        .arg(dir.path().join("out"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // The timings go to stderr, beside the progress.
    let stderr = String::from_utf8_lossy(&out.stderr);
    let stages: Vec<&str> = stderr
        .lines()
        .filter_map(|l| l.split_once(" s  ").map(|(_, stage)| stage))
        .filter(|s| s.contains("layers"))
        .collect();
    assert_eq!(
        stages,
        [
            "plane_box/main/sun: 256² f32 layers, nearest: rasterizing",
            "plane_box/main/sun: 256² f32 layers, nearest: shading and scoring 2 techniques",
            "plane_box/main/sun: 256² f32 layers, nearest, back faces culled, offset (2, 4): rasterizing",
            "plane_box/main/sun: 256² f32 layers, nearest, back faces culled, offset (2, 4): shading and scoring 1 technique",
        ],
        "{stderr}"
    );
}
