//! `shadowtruth gate`: exit 0 when every rule holds, 1 on violations, 2 on bad input; a one-pixel
//! regression is caught with zero slack; JUnit XML and the Markdown summary have their shape.

use serde_json::json;
use shadowtruth::metrics::Counts;
use shadowtruth::record::{Report, RunRecord, Timings};
use std::path::Path;
use std::process::Command;

/// Exit code, stdout, stderr.
fn gate(args: &[&str], dir: &Path) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_shadowtruth"))
        .arg("gate")
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!stderr.contains("panicked"), "panic on {args:?}: {stderr}");
    (out.status.code().unwrap_or(-1), stdout, stderr)
}

const EVALUATED: u64 = 786_432; // 1024 × 768: one pixel is 1.27e-6 of a rate

/// A run of `spec` (`{"technique": ..., parameters...}`, as plans write techniques) shown as
/// `label`.
fn run(
    scene: &str,
    spec: serde_json::Value,
    label: &str,
    resolution: u32,
    false_shadow: u64,
    false_lit: u64,
) -> RunRecord {
    let counts = Counts {
        pixels: EVALUATED + 1000,
        background: 1000,
        evaluated: EVALUATED,
        false_shadow,
        false_lit,
        ..Counts::default()
    };
    let mut parameters = spec.as_object().expect("a JSON object").clone();
    let technique = parameters.remove("technique").expect("a technique").as_str().unwrap().to_string();
    RunRecord {
        scene: scene.into(),
        camera: "main".into(),
        light: "sun".into(),
        technique,
        parameters,
        label: label.into(),
        resolution,
        depth_format: "f32".into(),
        counts,
        rates: counts.rates(),
        timings: Timings::default(),
        layer_memory_bytes: 0,
        reference: Default::default(),
        soft: None,
        pipeline: None,
        cascades: None,
        point_map: None,
        temporal: None,
    }
}

const SLOPE: &str = "slope_scaled(factor=2,units=4)";
const CONSTANT: &str = "constant(bias_depth=0.001)";

fn slope() -> serde_json::Value {
    json!({"technique": "slope_scaled", "factor": 2.0, "units": 4.0})
}

fn constant() -> serde_json::Value {
    json!({"technique": "constant", "bias_depth": 0.001})
}

/// A small report: two scenes, a slope-scaled bias and a constant bias at 1024² and 2048².
/// `acne_px` is the false-shadow count of plane_box's slope-scaled run at 2048².
fn report(acne_px: u64) -> Report {
    Report {
        runs: vec![
            run("plane_box", slope(), SLOPE, 2048, acne_px, 300),
            run("plane_box", slope(), SLOPE, 1024, 40, 900),
            run("plane_box", constant(), CONSTANT, 2048, 5000, 200),
            run("rocks", slope(), SLOPE, 2048, 10, 100),
        ],
        ..Report::new()
    }
}

/// Writes `report` as `dir/name/report.json` through serde_json and returns the folder name.
fn write_report(dir: &Path, name: &str, report: &Report) -> String {
    std::fs::create_dir_all(dir.join(name)).unwrap();
    std::fs::write(dir.join(name).join("report.json"), serde_json::to_string_pretty(report).unwrap())
        .unwrap();
    name.to_string()
}

fn write(dir: &Path, name: &str, text: &str) {
    std::fs::write(dir.join(name), text).unwrap();
}

const ABSOLUTE: &str = r#"
[[rule]]
name = "slope-scaled acne at 2048"
technique = "slope_*"
resolution = 2048
metric = "false_shadow"
max = 0.001
"#;

#[test]
fn a_violated_rule_exits_1_and_names_the_run() {
    let dir = tempfile::tempdir().unwrap();
    // 1000 false-shadow pixels of 786 432: 0.00127 > 0.001.
    write_report(dir.path(), "now", &report(1000));
    write(dir.path(), "rules.toml", ABSOLUTE);
    let (code, stdout, stderr) = gate(&["now", "--rules", "rules.toml"], dir.path());
    assert_eq!(code, 1, "stdout: {stdout}\nstderr: {stderr}");
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(lines.len(), 2, "one violation line and the summary: {stdout}");
    let v = lines[0];
    assert!(v.contains("slope-scaled acne at 2048"), "{v}");
    assert!(v.contains("plane_box/main/sun slope_scaled(factor=2,units=4) @2048 f32"), "{v}");
    assert!(v.contains("false_shadow") && v.contains("0.00127157") && v.contains("0.001"), "{v}");
    assert!(!stdout.contains("rocks/main/sun"), "the passing run is not a violation: {stdout}");
    assert_eq!(lines[1], "1 rules, 2 runs checked, 1 violations");
}

#[test]
fn a_passing_report_exits_0() {
    let dir = tempfile::tempdir().unwrap();
    // A report.json path works as well as its folder.
    write_report(dir.path(), "now", &report(786));
    write(dir.path(), "rules.toml", ABSOLUTE);
    let (code, stdout, stderr) = gate(&["now/report.json", "--rules", "rules.toml"], dir.path());
    assert_eq!(code, 0, "stdout: {stdout}\nstderr: {stderr}");
    assert_eq!(stdout, "1 rules, 2 runs checked, 0 violations\n");
}

fn regression_rules(max_increase: f64) -> String {
    format!(
        r#"
[[rule]]
name = "no acne regression"
scene = "plane_*"
label = "slope_scaled(*)"
metric = "false_shadow"
max_increase = {max_increase:e}

[[rule]]
name = "no error regression"
metric = "error"
max_increase = {max_increase:e}
"#
    )
}

#[test]
fn a_one_pixel_regression_fails_with_zero_slack() {
    let dir = tempfile::tempdir().unwrap();
    write_report(dir.path(), "base", &report(500));
    write_report(dir.path(), "now", &report(501));
    write(dir.path(), "rules.toml", &regression_rules(0.0));
    let (code, stdout, stderr) = gate(&["now", "--rules", "rules.toml", "--baseline", "base"], dir.path());
    assert_eq!(code, 1, "stdout: {stdout}\nstderr: {stderr}");
    let fails: Vec<&str> = stdout.lines().filter(|l| l.starts_with("FAIL")).collect();
    assert_eq!(fails.len(), 2, "the false-shadow rule and the error rule: {stdout}");
    for f in &fails {
        assert!(f.contains("plane_box/main/sun slope_scaled(factor=2,units=4) @2048 f32"), "{f}");
        assert!(f.contains("baseline"), "{f}");
    }
    assert!(fails[0].contains("501 of 786432 px") && fails[0].contains("500 px"), "{}", fails[0]);
    assert!(
        stdout.ends_with("2 rules, 4 runs checked, 2 violations; baseline: 4 paired, 0 missing, 0 new\n"),
        "{stdout}"
    );

    // Identical reports pass with zero slack.
    let (code, stdout, _) = gate(&["base", "--rules", "rules.toml", "--baseline", "base"], dir.path());
    assert_eq!(code, 0, "{stdout}");
}

#[test]
fn a_one_pixel_regression_passes_with_one_pixel_of_slack() {
    let dir = tempfile::tempdir().unwrap();
    write_report(dir.path(), "base", &report(500));
    write_report(dir.path(), "now", &report(501));
    for slack_px in [1.0, 1.5] {
        write(dir.path(), "rules.toml", &regression_rules(slack_px / EVALUATED as f64));
        let (code, stdout, stderr) =
            gate(&["now", "--rules", "rules.toml", "--baseline", "base"], dir.path());
        assert_eq!(code, 0, "slack {slack_px} px: stdout: {stdout}\nstderr: {stderr}");
    }
    // Two pixels over one pixel of slack fail again.
    write_report(dir.path(), "now", &report(502));
    write(dir.path(), "rules.toml", &regression_rules(1.0 / EVALUATED as f64));
    let (code, stdout, _) = gate(&["now", "--rules", "rules.toml", "--baseline", "base"], dir.path());
    assert_eq!(code, 1, "{stdout}");
}

#[test]
fn runs_missing_from_the_baseline_are_listed_as_new() {
    let dir = tempfile::tempdir().unwrap();
    let mut base = report(500);
    base.runs.retain(|r| r.scene != "rocks");
    write_report(dir.path(), "base", &base);
    write_report(dir.path(), "now", &report(500));
    write(dir.path(), "rules.toml", &regression_rules(0.0));
    let (code, stdout, stderr) = gate(&["now", "--rules", "rules.toml", "--baseline", "base"], dir.path());
    assert_eq!(code, 0, "stdout: {stdout}\nstderr: {stderr}");
    assert!(
        stdout.contains("new: rocks/main/sun slope_scaled(factor=2,units=4) @2048 f32 [hard×1]"),
        "{stdout}"
    );
    assert!(stdout.ends_with("; baseline: 3 paired, 0 missing, 1 new\n"), "{stdout}");
}

fn assert_bad_input(args: &[&str], dir: &Path, needles: &[&str]) {
    let (code, stdout, stderr) = gate(args, dir);
    assert_eq!(code, 2, "{args:?}: stdout: {stdout}\nstderr: {stderr}");
    for n in needles {
        assert!(stderr.contains(n), "{args:?}: stderr lacks {n:?}: {stderr}");
    }
}

#[test]
fn a_rule_matching_no_run_exits_2() {
    let dir = tempfile::tempdir().unwrap();
    write_report(dir.path(), "now", &report(0));
    write(dir.path(), "rules.toml", "[[rule]]\ntechnique = \"pcss\"\nmetric = \"error\"\nmax = 0.1\n");
    assert_bad_input(
        &["now", "--rules", "rules.toml"],
        dir.path(),
        &["rules.toml", "rule[0]", "matches no run"],
    );
    // A typo in an exact match is caught the same way.
    write(dir.path(), "rules.toml", "[[rule]]\ndepth_format = \"F32\"\nmetric = \"error\"\nmax = 0.1\n");
    assert_bad_input(&["now", "--rules", "rules.toml"], dir.path(), &["rule[0]", "matches no run"]);
}

#[test]
fn a_regression_rule_without_a_baseline_exits_2() {
    let dir = tempfile::tempdir().unwrap();
    write_report(dir.path(), "now", &report(0));
    write(dir.path(), "rules.toml", &regression_rules(0.0));
    assert_bad_input(&["now", "--rules", "rules.toml"], dir.path(), &["rules.toml", "rule[0]", "--baseline"]);
}

#[test]
fn a_missing_or_invalid_baseline_or_report_exits_2() {
    let dir = tempfile::tempdir().unwrap();
    write_report(dir.path(), "now", &report(0));
    write(dir.path(), "rules.toml", &regression_rules(0.0));
    let rules = ["--rules", "rules.toml"];
    assert_bad_input(&["now", rules[0], rules[1], "--baseline", "nowhere"], dir.path(), &["nowhere"]);
    std::fs::create_dir(dir.path().join("empty")).unwrap();
    assert_bad_input(&["now", rules[0], rules[1], "--baseline", "empty"], dir.path(), &["report.json"]);
    write(dir.path(), "broken.json", "{ \"schema\": ");
    assert_bad_input(&["now", rules[0], rules[1], "--baseline", "broken.json"], dir.path(), &["broken.json"]);
    assert_bad_input(&["nowhere", rules[0], rules[1], "--baseline", "now"], dir.path(), &["nowhere"]);
    let mut other = serde_json::to_value(report(0)).unwrap();
    other["schema"] = "something/else".into();
    write(dir.path(), "other.json", &other.to_string());
    assert_bad_input(
        &["other.json", rules[0], rules[1], "--baseline", "now"],
        dir.path(),
        &["other.json", "schema"],
    );
}

#[test]
fn malformed_rules_exit_2_naming_the_file_and_field() {
    let dir = tempfile::tempdir().unwrap();
    write_report(dir.path(), "now", &report(0));
    let cases: &[(&str, &[&str])] = &[
        ("[[rule]\nmetric = \"error\"", &["bad.toml", "TOML", "line"]),
        (
            "[[rule]]\nmetric = \"error\"\nmax = 0.1\nmaximum = 0.2\n",
            &["bad.toml", "rule[0].maximum", "unknown"],
        ),
        (
            "[[rule]]\nmetric = \"error\"\nmax = 0.1\n[[rule]]\nmetric = \"acne\"\nmax = 0.1\n",
            &["rule[1].metric", "acne"],
        ),
        ("[[rule]]\nmetric = \"error\"\nmax = \"one percent\"\n", &["bad.toml", "rule[0].max"]),
        ("[[rule]]\nmetric = \"error\"\n", &["bad.toml", "rule[0]", "max"]),
    ];
    for (text, needles) in cases {
        write(dir.path(), "bad.toml", text);
        assert_bad_input(&["now", "--rules", "bad.toml"], dir.path(), needles);
    }
    assert_bad_input(&["now", "--rules", "missing.toml"], dir.path(), &["missing.toml"]);
}

#[test]
fn junit_xml_has_the_testsuite_testcase_failure_shape() {
    let dir = tempfile::tempdir().unwrap();
    write_report(dir.path(), "now", &report(1000));
    // Two rules: the first fails on one of its two runs; the second checks every run and holds.
    let rules = format!(
        "{ABSOLUTE}\n[[rule]]\nname = \"errors < 5 % & no <leaks>\"\nmetric = \"error\"\nmax = 0.05\n"
    );
    write(dir.path(), "rules.toml", &rules);
    let (code, stdout, stderr) =
        gate(&["now", "--rules", "rules.toml", "--junit", "out/junit.xml"], dir.path());
    assert_eq!(code, 1, "stdout: {stdout}\nstderr: {stderr}");
    let xml = std::fs::read_to_string(dir.path().join("out/junit.xml")).unwrap();
    let doc = roxmltree::Document::parse(&xml).unwrap_or_else(|e| panic!("invalid XML: {e}\n{xml}"));
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "testsuites");
    assert_eq!(root.attribute("tests"), Some("6"));
    assert_eq!(root.attribute("failures"), Some("1"));
    let suites: Vec<_> = root.children().filter(|n| n.is_element()).collect();
    assert_eq!(suites.len(), 2);
    assert!(suites.iter().all(|s| s.tag_name().name() == "testsuite"));
    assert_eq!(suites[0].attribute("tests"), Some("2"));
    assert_eq!(suites[0].attribute("failures"), Some("1"));
    assert_eq!(suites[1].attribute("tests"), Some("4"));
    assert_eq!(suites[1].attribute("failures"), Some("0"));
    assert!(
        suites[1].attribute("name").unwrap().contains("errors < 5 % & no <leaks>"),
        "escaped and read back"
    );
    let cases: Vec<_> = suites[0].children().filter(|n| n.is_element()).collect();
    assert!(cases.iter().all(|c| c.tag_name().name() == "testcase"));
    let failing: Vec<_> = cases.iter().filter(|c| c.children().any(|f| f.has_tag_name("failure"))).collect();
    assert_eq!(failing.len(), 1);
    assert_eq!(
        failing[0].attribute("name"),
        Some("plane_box/main/sun slope_scaled(factor=2,units=4) @2048 f32 [hard×1]")
    );
    let failure = failing[0].children().find(|f| f.has_tag_name("failure")).unwrap();
    assert!(failure.attribute("message").unwrap().contains("0.00127157"));
    let all_cases = suites.iter().flat_map(|s| s.children().filter(|n| n.is_element())).count();
    assert_eq!(all_cases, 6);
    let all_failures = doc.descendants().filter(|n| n.has_tag_name("failure")).count();
    assert_eq!(all_failures, 1);
}

#[test]
fn the_markdown_summary_has_a_header_and_one_row_per_checked_pair() {
    let dir = tempfile::tempdir().unwrap();
    write_report(dir.path(), "now", &report(1000));
    let rules = format!("{ABSOLUTE}\n[[rule]]\nmetric = \"error\"\nmax = 0.05\n");
    write(dir.path(), "rules.toml", &rules);
    let (code, stdout, _) = gate(&["now", "--rules", "rules.toml", "--summary", "summary.md"], dir.path());
    assert_eq!(code, 1, "{stdout}");
    let md = std::fs::read_to_string(dir.path().join("summary.md")).unwrap();
    let rows: Vec<&str> = md.lines().filter(|l| l.starts_with('|')).collect();
    assert_eq!(rows[0], "| rule | run | value | limit | status |");
    assert!(rows[1].starts_with("| ---"), "{md}");
    assert_eq!(rows.len(), 2 + 6, "{md}");
    assert_eq!(rows.iter().filter(|r| r.contains("FAIL")).count(), 1, "{md}");
    assert!(md.contains("2 rules, 4 runs checked, 1 violations"), "{md}");
}

#[test]
fn nothing_is_written_on_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    write_report(dir.path(), "now", &report(0));
    write(dir.path(), "rules.toml", &regression_rules(0.0));
    let (code, _, _) = gate(
        &["now", "--rules", "rules.toml", "--junit", "junit.xml", "--summary", "summary.md"],
        dir.path(),
    );
    assert_eq!(code, 2);
    assert!(!dir.path().join("junit.xml").exists() && !dir.path().join("summary.md").exists());
}

#[test]
fn the_example_gate_runs_on_a_report_with_the_shipped_setting() {
    let dir = tempfile::tempdir().unwrap();
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../gates/shadow-settings.toml");
    let shipped = "slope_scaled(cull=none,factor=2.0,units=4.0)";
    let spec = json!({"technique": "slope_scaled", "factor": 2.0, "units": 4.0, "cull": "none"});
    let mut now = report(0);
    now.runs.push(run("terrain", spec.clone(), shipped, 2048, 90, 177));
    now.runs.push(run("terrain", spec, shipped, 1024, 88, 52));
    write_report(dir.path(), "base", &now);
    write_report(dir.path(), "now", &now);
    let example = example.to_str().unwrap();
    let (code, stdout, stderr) = gate(&["now", "--rules", example, "--baseline", "base"], dir.path());
    assert_eq!(code, 0, "stdout: {stdout}\nstderr: {stderr}");
    assert!(stdout.starts_with("5 rules, 6 runs checked, 0 violations"), "{stdout}");
    // One more false-shadow pixel of the shipped setting at 1024² breaks the no-regression rule.
    let last = now.runs.last_mut().unwrap();
    last.counts.false_shadow += 1;
    last.rates = last.counts.rates();
    write_report(dir.path(), "now", &now);
    let (code, stdout, _) = gate(&["now", "--rules", example, "--baseline", "base"], dir.path());
    assert_eq!(code, 1, "{stdout}");
    assert!(
        stdout.contains("shipped bias: no regression") && stdout.contains(&format!("{shipped} @1024 f32"))
    );
}

/// The line a baseline run missing from the report gets.
fn missing_line(scene: &str, label: &str, resolution: u32) -> String {
    format!(
        "missing: {scene}/main/sun {label} @{resolution} f32 [hard×1]: in the baseline, not in the report"
    )
}

#[test]
fn a_removed_run_fails_unless_allowed() {
    let dir = tempfile::tempdir().unwrap();
    let mut now = report(500);
    write_report(dir.path(), "base", &now);
    now.runs.retain(|r| r.scene != "rocks");
    write_report(dir.path(), "now", &now);
    write(dir.path(), "rules.toml", &regression_rules(0.0));
    let args = ["now", "--rules", "rules.toml", "--baseline", "base"];
    let (code, stdout, stderr) = gate(&[&args[..], &["--junit", "junit.xml"]].concat(), dir.path());
    assert_eq!(code, 1, "stdout: {stdout}\nstderr: {stderr}");
    let missing = missing_line("rocks", SLOPE, 2048);
    assert!(stdout.lines().any(|l| l == missing), "{stdout}");
    assert!(
        stdout.ends_with("2 rules, 3 runs checked, 1 violations; baseline: 3 paired, 1 missing, 0 new\n")
    );
    let xml = std::fs::read_to_string(dir.path().join("junit.xml")).unwrap();
    let doc = roxmltree::Document::parse(&xml).unwrap();
    assert_eq!(doc.root_element().attribute("failures"), Some("1"), "{xml}");
    let failure = doc.descendants().find(|n| n.has_tag_name("failure")).expect("a failure");
    assert_eq!(failure.attribute("message"), Some(missing.as_str()));

    let (code, stdout, stderr) = gate(&[&args[..], &["--allow-missing"]].concat(), dir.path());
    assert_eq!(code, 0, "stdout: {stdout}\nstderr: {stderr}");
    assert!(
        stdout.lines().any(|l| l == format!("warning: {missing} (allowed by --allow-missing)")),
        "{stdout}"
    );
    assert!(stdout.ends_with("0 violations; baseline: 3 paired, 1 missing (allowed), 0 new\n"), "{stdout}");
}

#[test]
fn a_renamed_parameter_is_a_different_run() {
    let dir = tempfile::tempdir().unwrap();
    let mut now = report(500);
    write_report(dir.path(), "base", &now);
    // Same label, same value, but a world-space bias instead of a depth bias.
    let renamed = &mut now.runs[2].parameters;
    let value = renamed.remove("bias_depth").unwrap();
    renamed.insert("bias_world".into(), value);
    write_report(dir.path(), "now", &now);
    write(dir.path(), "rules.toml", &regression_rules(0.0));
    let (code, stdout, stderr) = gate(&["now", "--rules", "rules.toml", "--baseline", "base"], dir.path());
    assert_eq!(code, 1, "stdout: {stdout}\nstderr: {stderr}");
    assert!(stdout.lines().any(|l| l == missing_line("plane_box", CONSTANT, 2048)), "{stdout}");
    assert!(stdout.contains(&format!("new: plane_box/main/sun {CONSTANT} @2048 f32 [hard×1]")), "{stdout}");
    assert!(stdout.ends_with("; baseline: 3 paired, 1 missing, 1 new\n"), "{stdout}");
}

#[test]
fn a_disjoint_baseline_fails_and_a_regression_rule_pairing_nothing_exits_2() {
    let dir = tempfile::tempdir().unwrap();
    let mut base = report(786);
    for r in &mut base.runs {
        r.scene = format!("old_{}", r.scene);
    }
    write_report(dir.path(), "base", &base);
    write_report(dir.path(), "now", &report(786));
    write(dir.path(), "rules.toml", ABSOLUTE);
    let (code, stdout, stderr) = gate(&["now", "--rules", "rules.toml", "--baseline", "base"], dir.path());
    assert_eq!(code, 1, "stdout: {stdout}\nstderr: {stderr}");
    assert!(stdout.lines().any(|l| l == missing_line("old_rocks", SLOPE, 2048)), "{stdout}");
    assert_eq!(stdout.lines().filter(|l| l.starts_with("missing: ")).count(), 4, "{stdout}");
    assert!(
        stdout.ends_with("1 rules, 2 runs checked, 4 violations; baseline: 0 paired, 4 missing, 4 new\n")
    );

    write(dir.path(), "rules.toml", &regression_rules(0.0));
    assert_bad_input(
        &["now", "--rules", "rules.toml", "--baseline", "base"],
        dir.path(),
        &[
            "rules.toml: rule[0] \"no acne regression\"",
            "none of its 2 matched runs is in the baseline base/report.json",
        ],
    );
}

/// `report` as compact JSON with `from` replaced by `to` (which must occur).
fn write_edited(dir: &Path, name: &str, report: &Report, edits: &[(&str, &str)]) {
    let mut text = serde_json::to_string(report).unwrap();
    for (from, to) in edits {
        assert!(text.contains(from), "{from} not in {text}");
        text = text.replace(from, to);
    }
    std::fs::create_dir_all(dir.join(name)).unwrap();
    std::fs::write(dir.join(name).join("report.json"), text).unwrap();
}

#[test]
fn a_parameter_key_renamed_in_the_report_format_unpairs_the_run() {
    let dir = tempfile::tempdir().unwrap();
    write_report(dir.path(), "base", &report(786));
    // As if another version wrote the slope factor under another key: its runs no longer read as
    // the same technique, so each baseline run of it is missing.
    let edit =
        (r#""parameters":{"factor":2.0,"units":4.0}"#, r#""parameters":{"slope_factor":2.0,"units":4.0}"#);
    write_edited(dir.path(), "now", &report(786), &[edit]);
    write(dir.path(), "rules.toml", ABSOLUTE);
    let (code, stdout, stderr) = gate(&["now", "--rules", "rules.toml", "--baseline", "base"], dir.path());
    assert_eq!(code, 1, "stdout: {stdout}\nstderr: {stderr}");
    assert!(stdout.lines().any(|l| l == missing_line("plane_box", SLOPE, 1024)), "{stdout}");
    assert!(stdout.ends_with("; baseline: 1 paired, 3 missing, 3 new\n"), "{stdout}");
}

#[test]
fn printing_changes_still_pair() {
    let dir = tempfile::tempdir().unwrap();
    write_report(dir.path(), "base", &report(500));
    let edits = [
        // Keys reordered, integers for floats, a default (cull = none) written out.
        (
            r#""parameters":{"factor":2.0,"units":4.0}"#,
            r#""parameters":{"units":4,"cull":"none","factor":2e0}"#,
        ),
        (r#""bias_depth":0.001"#, r#""bias_depth":1e-3"#),
        (SLOPE, "slope_scaled(cull=none,factor=2.0,units=4.0)"),
        (CONSTANT, "constant(bias_depth=1e-3)"),
    ];
    write_edited(dir.path(), "now", &report(500), &edits);
    write(dir.path(), "rules.toml", &regression_rules(0.0));
    let (code, stdout, stderr) = gate(&["now", "--rules", "rules.toml", "--baseline", "base"], dir.path());
    assert_eq!(code, 0, "stdout: {stdout}\nstderr: {stderr}");
    assert_eq!(stdout, "2 rules, 4 runs checked, 0 violations; baseline: 4 paired, 0 missing, 0 new\n");
    // And still compares: one more pixel fails.
    write_edited(dir.path(), "now", &report(501), &edits);
    let (code, stdout, _) = gate(&["now", "--rules", "rules.toml", "--baseline", "base"], dir.path());
    assert_eq!(code, 1, "{stdout}");
}

#[test]
fn inconsistent_reports_exit_2_naming_the_file_and_path() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "rules.toml", &regression_rules(0.0));
    write_report(dir.path(), "good", &report(0));
    let check = |name: &str, needles: &[&str]| {
        assert_bad_input(&[name, "--rules", "rules.toml", "--baseline", "good"], dir.path(), needles);
        // The baseline is checked the same way.
        assert_bad_input(&["good", "--rules", "rules.toml", "--baseline", name], dir.path(), needles);
    };

    let mut over = report(0);
    over.runs[2].counts.false_shadow = EVALUATED + 1;
    write_report(dir.path(), "over", &over);
    check(
        "over",
        &[&format!(
            "over/report.json: runs[2].counts.false_shadow: {} > evaluated {EVALUATED}",
            EVALUATED + 1
        )],
    );

    let mut negative = serde_json::to_value(report(0)).unwrap();
    negative["runs"][1]["counts"]["false_lit"] = json!(-1);
    std::fs::create_dir_all(dir.path().join("negative")).unwrap();
    write(dir.path(), "negative/report.json", &negative.to_string());
    check("negative", &["negative/report.json: runs[1].counts.false_lit: invalid value: integer `-1`"]);

    let mut future = serde_json::to_value(report(0)).unwrap();
    future["schema"] = json!("shadowtruth/report/v2");
    future["runs"] = json!({"renamed": "in v2"});
    std::fs::create_dir_all(dir.path().join("future")).unwrap();
    write(dir.path(), "future/report.json", &future.to_string());
    check(
        "future",
        &["future/report.json: schema: expected \"shadowtruth/report/v1\", got \"shadowtruth/report/v2\""],
    );

    let mut empty = report(0);
    for r in &mut empty.runs {
        r.counts = Counts { pixels: 10, background: 10, ..Counts::default() };
        r.rates = r.counts.rates();
    }
    write_report(dir.path(), "empty", &empty);
    check("empty", &["empty/report.json: runs: none of the 4 runs evaluated a pixel"]);

    let mut twice = report(0);
    let mut again = twice.runs[0].clone();
    again.label = "slope_scaled(cull=none,factor=2.0,units=4.0)".into();
    twice.runs.push(again);
    write_report(dir.path(), "twice", &twice);
    check("twice", &["twice/report.json: runs[4]: the same run as runs[0]"]);
}

#[test]
fn a_rule_matching_a_run_that_evaluated_nothing_exits_2() {
    let dir = tempfile::tempdir().unwrap();
    let mut now = report(0);
    now.runs[3].counts = Counts { pixels: 10, background: 10, ..Counts::default() };
    now.runs[3].rates = now.runs[3].counts.rates();
    write_report(dir.path(), "now", &now);
    write(dir.path(), "rules.toml", ABSOLUTE);
    assert_bad_input(
        &["now", "--rules", "rules.toml"],
        dir.path(),
        &["rules.toml: rule[0]", "evaluated no pixel", "now/report.json: runs[3].counts.evaluated = 0"],
    );
}

#[test]
fn allow_missing_is_explained_in_help() {
    let dir = tempfile::tempdir().unwrap();
    let (code, stdout, _) = gate(&["--help"], dir.path());
    assert_eq!(code, 0);
    assert!(stdout.contains("--allow-missing") && stdout.contains("warning"), "{stdout}");
}
