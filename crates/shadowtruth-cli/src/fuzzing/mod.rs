//! Entry points for fuzzing the input readers: scene files, OBJ meshes, plans and gate rules.
//!
//! Each function takes arbitrary bytes and must return without panicking, whatever they are:
//! rejecting them with an error is the expected outcome. They live in the library rather than
//! in the fuzz targets (fuzz/fuzz_targets/) so that the very same code runs under `cargo fuzz`
//! and, in the ordinary test suite, over every file of the committed corpus (tests/fuzz_corpus.rs),
//! which needs no nightly toolchain. Not a stable API.

mod image_reader;
pub use image_reader::*;

use shadowtruth::scene::{Scene, load_scene_str_within, parse_obj};
use std::path::{Component, Path, PathBuf};

mod tune_options;
pub use tune_options::*;
mod gltf_reader;
pub use gltf_reader::*;

/// The folder that fuzzed scenes resolve their mesh paths in: a few small OBJ files under
/// `meshes/`, named like the bundled scenes' meshes (fuzz/scene_dir/).
pub fn scene_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz").join("scene_dir")
}

/// Triangles a fuzzed scene may make: the limits are checked by the same code as the real ones
/// (tests/scene_load.rs tests those), at a size that keeps each input fast.
const FUZZ_MAX_TRIANGLES: u64 = 1 << 16;

/// Runs a fuzzed plan may expand to, for the same reason.
const FUZZ_MAX_RUNS: u64 = 1000;

/// A scene file (`shadowtruth::scene::load_scene_str`), meshes resolved in `scene_dir()`.
pub fn scene_reader(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    // A mesh path may name any file of the machine (`/dev/zero`, `../../x`); the fuzzer stays
    // inside `scene_dir()`, whose files are all small.
    if !strings_stay_inside(&text) {
        return;
    }
    match load_scene_str_within(&text, Path::new("fuzz.json"), &scene_dir(), FUZZ_MAX_TRIANGLES) {
        Ok(scene) => check_scene(&scene),
        Err(error) => {
            assert!(!error.problems.is_empty(), "an error without problems");
            let _ = error.to_string();
        }
    }
}

/// An OBJ mesh, parsed from memory by the same code that reads mesh files.
pub fn obj_reader(data: &[u8]) {
    if let Ok(mesh) = parse_obj(data, "fuzz.obj") {
        assert!(mesh.positions.iter().all(|p| p.is_finite()), "a non-finite vertex");
        let n = mesh.positions.len();
        assert!(mesh.triangles.iter().flatten().all(|&i| (i as usize) < n), "an index out of range");
    }
}

/// A plan file (`crate::plan::parse_plan`).
pub fn plan_reader(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let _ = crate::plan::parse_plan_limited(&text, Path::new("fuzz.json"), FUZZ_MAX_RUNS);
}

/// A gate rules file (`crate::gate::parse_rules`); rules that parse are evaluated
/// against a small report and their outcome rendered. The input's length picks the options
/// (with or without the baseline, missing runs allowed or not): each input is evaluated once,
/// and every combination is reached across inputs.
pub fn gate_rules(data: &[u8]) {
    use crate::exports::junit_xml;
    use crate::gate::{GateOptions, evaluate, parse_rules};
    let text = String::from_utf8_lossy(data);
    let Ok(rules) = parse_rules(&text, "fuzz.toml") else {
        return;
    };
    let (report, baseline) = gate_reports();
    let baseline = data.len().is_multiple_of(2).then_some(baseline);
    let options = GateOptions { allow_missing: data.len() % 4 >= 2 };
    if let Ok(outcome) = evaluate(report, baseline, &rules, options) {
        let _ = (outcome.text(), outcome.markdown(), junit_xml(&outcome));
    }
}

/// The report and baseline that fuzzed gate rules are evaluated against, built once: a
/// hard-reference and a soft run that both hold, a run only in the report, one only in the
/// baseline, and one that regressed.
fn gate_reports() -> &'static (crate::gate::CheckedReport, crate::gate::CheckedReport) {
    use crate::gate::CheckedReport;
    use shadowtruth::metrics::{Counts, SoftErrors};
    use shadowtruth::record::{ReferenceUsed, Report, RunRecord, Timings};
    use shadowtruth::technique::ReferenceKind;
    static REPORTS: std::sync::OnceLock<(CheckedReport, CheckedReport)> = std::sync::OnceLock::new();
    let run = |scene: &str, spec: serde_json::Value, label: &str, resolution, false_shadow, false_lit| {
        let counts = Counts {
            pixels: 1000,
            background: 100,
            evaluated: 900,
            false_shadow,
            false_lit,
            ..Counts::default()
        };
        let mut parameters = spec.as_object().cloned().unwrap_or_default();
        let technique = parameters.remove("technique").and_then(|t| t.as_str().map(String::from));
        RunRecord {
            scene: scene.into(),
            camera: "main".into(),
            light: "sun".into(),
            technique: technique.unwrap_or_default(),
            parameters,
            label: label.into(),
            resolution,
            depth_format: "f32".into(),
            counts,
            rates: counts.rates(),
            timings: Timings::default(),
            layer_memory_bytes: 0,
            reference: ReferenceUsed::default(),
            soft: None,
            pipeline: None,
            cascades: None,
            point_map: None,
            temporal: None,
        }
    };
    REPORTS.get_or_init(|| {
        let slope = serde_json::json!({"technique": "slope_scaled", "factor": 2.0, "units": 4.0});
        let constant = serde_json::json!({"technique": "constant", "bias_depth": 0.001});
        let pcf = serde_json::json!({"technique": "pcf", "kernel": "box", "size": 3});
        let (slope_label, constant_label) =
            ("slope_scaled(factor=2.0,units=4.0)", "constant(bias_depth=0.001)");
        let mut soft = run("spot", pcf, "pcf(kernel=box,size=3)", 1024, 3, 4);
        soft.reference = ReferenceUsed { kind: ReferenceKind::Coverage, samples: 16 };
        soft.soft = Some(SoftErrors { mae: 0.01, false_shadow_mass: 0.004, false_lit_mass: 0.006 });
        let mut worse_soft = soft.clone();
        worse_soft.soft = Some(SoftErrors { mae: 0.02, false_shadow_mass: 0.01, false_lit_mass: 0.01 });
        let report = Report {
            runs: vec![
                run("plane_box", slope.clone(), slope_label, 2048, 1, 2),
                run("plane_box", slope.clone(), slope_label, 1024, 9, 30),
                run("plane_box", constant.clone(), constant_label, 2048, 50, 0),
                worse_soft,
            ],
            ..Report::default()
        };
        let baseline = Report {
            runs: vec![
                run("plane_box", slope.clone(), slope_label, 2048, 1, 2),
                run("plane_box", slope, slope_label, 1024, 5, 30),
                run("rocks", constant, constant_label, 2048, 10, 10),
                soft,
            ],
            ..Report::default()
        };
        let check = |report, origin| CheckedReport::new(report, origin).expect("a consistent report");
        (check(report, "report.json"), check(baseline, "baseline.json"))
    })
}

/// What a loaded scene promises every later stage.
fn check_scene(scene: &Scene) {
    assert!(scene.triangle_count() > 0, "a scene without triangles");
    assert_eq!(scene.flat_triangles.len(), scene.flat_triangle_object.len());
    assert!(scene.triangles().flat_map(|(_, t)| t).all(|v| v.is_finite()), "a non-finite vertex");
    // Flat objects are contiguous in file order, and instanced ones follow them in theirs.
    let mut objects: Vec<usize> = (0..scene.objects.len()).collect();
    objects.sort_by_key(|&i| scene.objects[i].first_triangle);
    let mut next = 0u32;
    for i in objects {
        let object = &scene.objects[i];
        assert_eq!(object.first_triangle, next, "objects are not contiguous");
        next += object.triangle_count;
        assert!((object.first_triangle..next).all(|id| scene.object_of(id) as usize == i));
    }
    assert_eq!(next as usize, scene.triangle_count());
    let (lo, hi) = scene.bounds();
    // Empty exactly when no triangle has an area where it is placed: an instanced triangle whose
    // world form rounds to a degenerate one is skipped, here as by the tracer.
    assert_eq!(lo.cmple(hi).all(), scene.triangles().next().is_some(), "bounds and triangles disagree");
    let _ = scene.geometry_digest();
}

/// False when a JSON string literal of `text` is a path that leaves the folder it is joined to
/// (absolute, or with a `..` component). Every value the scene reader sees, mesh paths included,
/// is one of these literals: the loader only ever rewrites number tokens.
fn strings_stay_inside(text: &str) -> bool {
    let bytes = text.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'"' {
            let start = i;
            i += 1;
            while i < bytes.len() && bytes[i] != b'"' {
                i += if bytes[i] == b'\\' { 2 } else { 1 };
            }
            // Both ends lie on a quote or at the end of the text: character boundaries.
            let end = (i + 1).min(bytes.len());
            if let Ok(s) = serde_json::from_str::<String>(&text[start..end])
                && !Path::new(&s).components().all(|c| matches!(c, Component::Normal(_) | Component::CurDir))
            {
                return false;
            }
        }
        i += 1;
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fuzzing_paths_outside_the_scene_dir_are_skipped() {
        assert!(strings_stay_inside(r#"{"mesh": "meshes/rocks.obj", "a": "x\"y", "b": 1e999}"#));
        assert!(!strings_stay_inside(r#"{"mesh": "/dev/zero"}"#));
        assert!(!strings_stay_inside(r#"{"mesh": "\/dev\/zero"}"#));
        assert!(!strings_stay_inside(r#"{"mesh": "\u002fdev/zero"}"#));
        assert!(!strings_stay_inside(r#"{"mesh": "meshes/../../Cargo.toml"}"#));
        assert!(strings_stay_inside("\"unterminated \\"));
    }
}
