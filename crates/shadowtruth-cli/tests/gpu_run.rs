//! `run --pipeline gpu` against `run --pipeline cpu` on the same plan: the command's GPU
//! back-end (crate shadowtruth-gpu, cross-checked pixel by pixel in its own tests) records its
//! adapter and scores within 0.1 % of the CPU emulation.

#[path = "../../shadowtruth/tests/common/mod.rs"]
mod common;

/// `run --pipeline gpu`: every run of the report records the device, and scores within a
/// hair of the same plan on the CPU (the maps differ as the tests above bound); the CPU's
/// report has no `pipeline` field.
#[test]
fn run_on_the_gpu_pipeline_records_the_adapter() {
    let dir = tempfile::tempdir().unwrap();
    let plan = serde_json::json!({
        "format": "shadowtruth/plan/v1",
        "scenes": [common::repo().join("scenes/plane_box.json")],
        "techniques": [
            {"technique": "constant", "bias_depth": 0.0005},
            {"technique": "normal_offset", "scale_texels": 1.0},
            {"technique": "pcf", "kernel": "bilinear", "bias_depth": 0.0005}
        ],
        "resolutions": [1024],
        "repeats": 1
    });
    let plan_path = dir.path().join("plan.json");
    std::fs::write(&plan_path, plan.to_string()).unwrap();
    let report = |pipeline: &str| {
        let out = dir.path().join(pipeline);
        let run = std::process::Command::new(env!("CARGO_BIN_EXE_shadowtruth"))
            .args(["run", "--plan"])
            .arg(&plan_path)
            .args(["--pipeline", pipeline, "--no-cache", "--no-figures", "--quiet", "-o"])
            .arg(&out)
            .output()
            .unwrap();
        // Without a Vulkan adapter the command's message says what to install.
        assert!(
            run.status.success(),
            "run --pipeline {pipeline}: {}(`bash scripts/test.sh` installs lavapipe)",
            String::from_utf8_lossy(&run.stderr)
        );
        let text = std::fs::read_to_string(out.join("report.json")).unwrap();
        serde_json::from_str::<serde_json::Value>(&text).unwrap()["runs"].as_array().unwrap().clone()
    };
    let (gpu_runs, cpu_runs) = (report("gpu"), report("cpu"));
    assert_eq!(gpu_runs.len(), 3);
    assert_eq!(cpu_runs.len(), 3);
    for (g, c) in gpu_runs.iter().zip(&cpu_runs) {
        assert!(c.get("pipeline").is_none(), "a CPU run records no pipeline");
        let used = &g["pipeline"];
        assert_eq!(used["name"], "gpu");
        assert_eq!(used["backend"], "vulkan");
        assert!(!used["adapter"].as_str().unwrap().is_empty());
        assert_eq!(g["label"], c["label"]);
        let evaluated = c["counts"]["evaluated"].as_u64().unwrap() as f64;
        for field in ["false_shadow", "false_lit"] {
            let (gv, cv) = (g["counts"][field].as_u64().unwrap(), c["counts"][field].as_u64().unwrap());
            assert!(
                (gv as f64 - cv as f64).abs() <= 0.001 * evaluated,
                "{} {field}: {gv} vs {cv}",
                g["label"]
            );
        }
    }
}
