//! `shadowtruth tune` on a scene whose error curve in the constant bias is known: a box resting
//! on a plane under a slanted sun shows acne (false shadow) on the plane below some bias and a
//! leak at the contact (false lit) above another. The tuned bias must beat or tie every value
//! of an independent 20-point sweep run by `shadowtruth run`, lie in its own safe range, and
//! the gate rules written for it must hold on the report it wrote.

use serde_json::{Value, json};
use std::path::Path;
use std::process::Command;

const RANGE: (f64, f64) = (1e-6, 0.1);
const RESOLUTION: &str = "256";

fn shadowtruth(dir: &Path, args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_shadowtruth")).args(args).current_dir(dir).output().unwrap();
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn read_json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn write_contact_scene(path: &Path) {
    let scene = json!({
        "format": "shadowtruth/scene/v1", "name": "contact",
        "objects": [
            { "name": "ground", "shape": { "type": "plane", "size": [10, 10] } },
            { "name": "box", "shape": { "type": "box", "size": [1, 1, 1] }, "closed": true,
              "transform": { "rotate_deg": [0, 20, 0], "translate": [0, 0.5, 0] } }
        ],
        "cameras": [{ "name": "c", "position": [-3, 4, 5], "look_at": [0.5, 0, 0], "fov_y_deg": 45,
                      "width": 200, "height": 150 }],
        "lights": [{ "name": "sun", "type": "directional", "direction": [0.6, -1, 0.3] }]
    });
    std::fs::write(path, scene.to_string()).unwrap();
}

/// The 20 biases of the sweep, evenly spaced in log over the tuned range.
fn sweep_biases() -> Vec<f64> {
    let (a, b) = (RANGE.0.ln(), RANGE.1.ln());
    (0..20).map(|i| (a + (b - a) * i as f64 / 19.0).exp()).collect()
}

#[test]
fn the_tuned_bias_beats_a_20_point_sweep_and_sits_in_its_safe_range() {
    let dir = tempfile::tempdir().unwrap();
    write_contact_scene(&dir.path().join("contact.json"));
    let range = format!("bias_depth={}:{}", RANGE.0, RANGE.1);
    shadowtruth(
        dir.path(),
        &[
            "tune",
            "contact.json",
            "--technique",
            "constant",
            "--param",
            &range,
            "--resolutions",
            RESOLUTION,
            "-o",
            "tuned",
            "--no-cache",
            "-q",
        ],
    );
    let tuned = read_json(&dir.path().join("tuned/tune.json"));
    assert_eq!(tuned["format"], "shadowtruth/tune/v1");
    let best = &tuned["suite"]["best"];
    let bias = best["params"]["bias_depth"].as_f64().unwrap();
    let objective = best["objective"].as_f64().unwrap();
    let safe = &tuned["suite"]["safe_range"]["bias_depth"];
    let (lo, hi) = (safe["lo"].as_f64().unwrap(), safe["hi"].as_f64().unwrap());
    assert!(lo <= bias && bias <= hi, "{bias} outside its safe range [{lo}, {hi}]");
    // One scene: its own optimum is the suite's.
    assert_eq!(tuned["per_scene"][0]["best"]["objective"], best["objective"]);

    // The sweep, run independently of the search.
    let plan = json!({
        "format": "shadowtruth/plan/v1",
        "techniques": [{ "technique": "constant", "bias_depth": sweep_biases() }],
        "resolutions": [256], "depth_formats": ["f32"], "repeats": 1
    });
    std::fs::write(dir.path().join("sweep.json"), plan.to_string()).unwrap();
    shadowtruth(
        dir.path(),
        &["run", "contact.json", "--plan", "sweep.json", "-o", "sweep", "--no-cache", "--no-figures", "-q"],
    );
    let report = read_json(&dir.path().join("sweep/report.json"));
    let runs = report["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 20);
    let rate = |r: &Value, k: &str| r["rates"][k].as_f64().unwrap();
    // The known shape: acne at the smallest bias, a leak at the largest, a minimum between.
    let (first, last) = (&runs[0], &runs[19]);
    assert!(
        rate(first, "false_shadow") > 10.0 * rate(first, "false_lit"),
        "no acne at {}",
        sweep_biases()[0]
    );
    assert!(rate(last, "false_lit") > rate(first, "false_lit"), "no leak at {}", sweep_biases()[19]);
    for r in runs {
        assert!(
            objective <= rate(r, "error"),
            "the sweep's {} ({}) beats the tuned {bias} ({objective})",
            r["label"],
            rate(r, "error")
        );
    }
    let best_sweep = runs.iter().map(|r| rate(r, "error")).fold(f64::INFINITY, f64::min);
    assert!(objective < rate(first, "error") && objective < rate(last, "error"));
    assert!(best_sweep >= objective);

    // The report holds the tuned setting, and the rules written for it hold there.
    let tuned_report = read_json(&dir.path().join("tuned/report.json"));
    let label = best["label"].as_str().unwrap();
    let run =
        tuned_report["runs"].as_array().unwrap().iter().find(|r| r["label"] == label).expect("the tuned run");
    assert_eq!(rate(run, "error"), objective, "the report scores the tuned setting as the search did");
    let out = shadowtruth(dir.path(), &["gate", "tuned", "--rules", "tuned/tune-gate.toml"]);
    assert!(out.contains("0 violations"), "{out}");
    assert!(dir.path().join("tuned/plots/tune_bias_depth.png").is_file());
}

/// The error of a `tune` that must fail (exit 2) before writing anything into `t`.
fn tune_refused(dir: &Path, options: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_shadowtruth"))
        .args(["tune", "contact.json", "--technique", "constant", "-o", "t", "--no-cache", "-q"])
        .args(options)
        .current_dir(dir)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2), "{options:?} was not refused");
    assert!(!dir.join("t").exists(), "nothing is written");
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn tune_error(dir: &Path, param: &str) -> String {
    tune_refused(dir, &["--param", param])
}

#[test]
fn a_parameter_the_technique_does_not_have_is_named_before_anything_is_traced() {
    let dir = tempfile::tempdir().unwrap();
    write_contact_scene(&dir.path().join("contact.json"));
    let err = tune_error(dir.path(), "scale_texels");
    assert!(err.contains("scale_texels"), "{err}");
    let err = tune_error(dir.path(), "bias_depth=0:1");
    assert!(err.contains("0 < LO < HI"), "{err}");
}

#[test]
fn every_number_out_of_its_range_is_refused_by_its_option_before_anything_is_written() {
    let dir = tempfile::tempdir().unwrap();
    write_contact_scene(&dir.path().join("contact.json"));
    let weighted = ["--param", "bias_depth", "--objective", "weighted"];
    for (options, named) in [
        (&[&weighted[..], &["--weight", "NaN"]].concat(), "--weight NaN"),
        (&[&weighted[..], &["--weight", "inf"]].concat(), "--weight inf"),
        (&[&weighted[..], &["--weight=-1"]].concat(), "--weight -1"),
        (&vec!["--param", "bias_depth=1e-200:1e200"], "invalid value 'bias_depth=1e-200:1e200' for '--param"),
        (&vec!["--param", "bias_depth", "--param", "bias_depth=1e-3:1e-2"], "bias_depth is given twice"),
        (&vec!["--param", "bias_depth", "--gate-slack", "NaN"], "--gate-slack NaN"),
        (&vec!["--param", "bias_depth", "--gate-slack=-1"], "--gate-slack -1"),
    ] {
        let err = tune_refused(dir.path(), options);
        assert!(err.contains(named), "{options:?}: {err}");
    }
}

/// A renderer whose shadows are right only for a bias from -0.002 to -0.0005 (towards the
/// light, as three.js's): inside, it writes the exact mask of the light asked for (by
/// `shadowtruth reference`); outside, the mask of the scene's other light. (Its awk braces are
/// doubled: single braces are the protocol's placeholders.)
fn switching_renderer(scene: &Path) -> Value {
    let script = format!(
        "if awk -v b=\"$1\" 'BEGIN {{{{ exit !(b >= -0.002 && b <= -0.0005) }}}}'; then L=\"$3\"; \
         elif [ \"$3\" = a ]; then L=b; else L=a; fi; \
         exec '{}' reference '{}' --light \"$L\" -o \"$2\"",
        env!("CARGO_BIN_EXE_shadowtruth"),
        scene.display()
    );
    json!({"technique": "command", "name": "switch", "visibility_format": "png",
           "run": ["sh", "-c", script, "renderer", "{bias}", "{visibility}", "{light}"]})
}

#[test]
fn tune_runs_a_renderers_command_and_finds_its_bias_below_zero() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("two_suns.json");
    let mut json: Value = {
        write_contact_scene(&scene);
        read_json(&scene)
    };
    json["lights"] = json!([{ "name": "a", "type": "directional", "direction": [0.6, -1, 0.3] },
                            { "name": "b", "type": "directional", "direction": [-0.5, -1, -0.2] }]);
    std::fs::write(&scene, json.to_string()).unwrap();
    let technique = switching_renderer(&scene).to_string();
    shadowtruth(
        dir.path(),
        &[
            "tune",
            "two_suns.json",
            "--technique",
            &technique,
            "--param",
            "bias=-0.01:-0.00001",
            "-o",
            "t",
            "-q",
        ],
    );
    let tuned = read_json(&dir.path().join("t/tune.json"));
    let best = &tuned["suite"]["best"];
    let bias = best["params"]["bias"].as_f64().unwrap();
    assert!((-0.002..=-0.0005).contains(&bias), "{best}");
    assert_eq!(best["objective"].as_f64(), Some(0.0), "the exact masks: {best}");
    let safe = &tuned["suite"]["safe_range"]["bias"];
    let (lo, hi) = (safe["lo"].as_f64().unwrap(), safe["hi"].as_f64().unwrap());
    // The ends are placed to 0.02 decades (docs/tune.md): within 5 % of the switch's edges.
    assert!((lo / -0.002 - 1.0).abs() < 0.05 && (hi / -0.0005 - 1.0).abs() < 0.05, "{safe}");
    // The tuned setting's report: its runs are the renderer's, each exact.
    let report = read_json(&dir.path().join("t/report.json"));
    for run in report["runs"].as_array().unwrap() {
        assert_eq!(run["technique"], "command");
        assert_eq!(
            (run["counts"]["false_shadow"].as_u64(), run["counts"]["false_lit"].as_u64()),
            (Some(0), Some(0))
        );
    }
}
