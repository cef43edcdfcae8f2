//! `run --pipeline gpu` against `run --pipeline cpu` on the same plan: the command's GPU
//! back-end (crate shadowtruth-gpu, cross-checked pixel by pixel in its own tests) records its
//! adapter and scores within 0.1 % of the CPU emulation, on a bundled scene and on one whose
//! flattened triangles are past the adapter's largest buffer.

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
    let (gpu_runs, cpu_runs) = (runs(dir.path(), &plan, "gpu"), runs(dir.path(), &plan, "cpu"));
    assert_eq!(gpu_runs.len(), 3);
    assert_eq!(cpu_runs.len(), 3);
    for (g, c) in gpu_runs.iter().zip(&cpu_runs) {
        assert!(c.get("pipeline").is_none(), "a CPU run records no pipeline");
        let used = &g["pipeline"];
        assert_eq!(used["name"], "gpu");
        assert_eq!(used["backend"], "vulkan");
        assert!(!used["adapter"].as_str().unwrap().is_empty());
        scores_within_a_hair(g, c);
    }
}

/// The runs of `plan` on `pipeline` (its report's `runs`), written under `dir`.
fn runs(dir: &std::path::Path, plan: &serde_json::Value, pipeline: &str) -> Vec<serde_json::Value> {
    let plan_path = dir.join("plan.json");
    std::fs::write(&plan_path, plan.to_string()).unwrap();
    let out = dir.join(pipeline);
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
}

/// The GPU run `g` and the CPU run `c` of one setting: false shadow and false lit within 0.1 % of
/// the evaluated pixels.
fn scores_within_a_hair(g: &serde_json::Value, c: &serde_json::Value) {
    assert_eq!(g["label"], c["label"]);
    let evaluated = c["counts"]["evaluated"].as_u64().unwrap() as f64;
    assert!(evaluated > 0.0, "{}: no pixel evaluated", c["label"]);
    for field in ["false_shadow", "false_lit"] {
        let (gv, cv) = (g["counts"][field].as_u64().unwrap(), c["counts"][field].as_u64().unwrap());
        assert!((gv as f64 - cv as f64).abs() <= 0.001 * evaluated, "{} {field}: {gv} vs {cv}", g["label"]);
    }
}

/// A scene whose triangles, flattened, are past the adapter's largest buffer: 100 M instanced
/// triangles (3.6 GB of vertices). The GPU pipeline draws its placements instanced, each buffer
/// within the limit, and scores it as the CPU does.
#[cfg(feature = "gpu")]
#[test]
fn a_scene_past_the_adapters_buffer_limit_runs_on_the_gpu() {
    let dir = tempfile::tempdir().unwrap();
    let forest = dir.path().join("forest");
    let generate = std::process::Command::new(env!("CARGO_BIN_EXE_shadowtruth"))
        .args(["generate", "forest", "--instanced", "--triangles", "100M", "--image", "480,270", "-o"])
        .arg(&forest)
        .output()
        .unwrap();
    assert!(generate.status.success(), "{}", String::from_utf8_lossy(&generate.stderr));
    let scene = shadowtruth::scene::load_scene(&forest.join("scene.json")).unwrap();
    let gpu = shadowtruth_gpu::GpuDevice::new().unwrap_or_else(|e| panic!("{e}"));
    let flattened_bytes = scene.triangle_count() as u64 * 36;
    println!(
        "flattened: {flattened_bytes} bytes; the adapter's largest buffer: {} bytes",
        gpu.max_buffer_size()
    );
    assert!(
        flattened_bytes > gpu.max_buffer_size(),
        "{flattened_bytes} bytes of vertices fit the adapter's {} byte buffers: the scene proves nothing",
        gpu.max_buffer_size()
    );
    drop((scene, gpu));
    let plan = serde_json::json!({
        "format": "shadowtruth/plan/v1",
        "scenes": [forest.join("scene.json")],
        "lights": ["sun"],
        "techniques": [{"technique": "constant", "bias_depth": 0.0005}],
        "resolutions": [2048],
        "repeats": 1
    });
    let (gpu_runs, cpu_runs) = (runs(dir.path(), &plan, "gpu"), runs(dir.path(), &plan, "cpu"));
    assert_eq!((gpu_runs.len(), cpu_runs.len()), (1, 1));
    assert_eq!(gpu_runs[0]["pipeline"]["name"], "gpu");
    scores_within_a_hair(&gpu_runs[0], &cpu_runs[0]);
}
