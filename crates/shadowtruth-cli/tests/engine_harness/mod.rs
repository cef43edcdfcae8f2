//! What the engine tests share: export a bundled view, render it with an engine's harness, score
//! the engine's buffers, run the emulation of the same setting, and compare the counts.

#![allow(dead_code)] // Each engine's test uses its own part of this.

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The map the tests render and emulate at, the export's default resolution.
pub const RESOLUTION: u32 = 2048;

pub fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

pub fn binary() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_shadowtruth"));
    c.current_dir(workspace());
    c
}

/// Fails, naming what to install, when node, the engine's packages (`engines/ENGINE/node_modules`)
/// or Chromium are missing.
pub fn require_browser_engine(engine: &str, packages: &[&str]) {
    let node = Command::new("node").arg("--version").output();
    assert!(
        node.is_ok_and(|o| o.status.success()),
        "node is missing: install Node.js (`apt-get install nodejs npm`), then `npm ci --prefix engines/{engine}`"
    );
    let modules = workspace().join("engines").join(engine).join("node_modules");
    for package in packages {
        assert!(
            modules.join(package).join("package.json").is_file(),
            "engines/{engine}/node_modules/{package} is missing: run `npm ci --prefix engines/{engine}`"
        );
    }
    let chromium = std::env::var_os("CHROMIUM").map(PathBuf::from).into_iter().chain(
        ["/usr/bin/chromium", "/usr/bin/chromium-browser", "/usr/bin/google-chrome"].map(PathBuf::from),
    );
    assert!(
        chromium.into_iter().any(|p| p.is_file()),
        "Chromium is missing: install it with `apt-get install chromium` (or set CHROMIUM to its path)"
    );
}

/// Runs `c`, failing with its output unless it succeeds; returns (and echoes) its stderr.
pub fn run_ok(mut c: Command, what: &str) -> String {
    let out = c.output().unwrap_or_else(|e| panic!("{what}: cannot start: {e}"));
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(
        out.status.success(),
        "{what} failed ({}):\n{}{stderr}",
        out.status,
        String::from_utf8_lossy(&out.stdout)
    );
    eprint!("{stderr}");
    stderr
}

/// A visibility and a depth buffer an engine wrote.
pub type Buffers = (PathBuf, PathBuf);

/// Renders the exported view with `program` (its first element the command, the rest leading
/// arguments, run from the workspace) into `out/NAME.{visibility,depth}.exr`.
pub fn render(program: &[&str], view: &Path, out: &Path, name: &str, extra: &[&str]) -> Buffers {
    render_logged(program, view, out, name, extra).0
}

/// `render`, and the renderer's stderr (its render line).
pub fn render_logged(
    program: &[&str],
    view: &Path,
    out: &Path,
    name: &str,
    extra: &[&str],
) -> (Buffers, String) {
    let (visibility, depth) =
        (out.join(format!("{name}.visibility.exr")), out.join(format!("{name}.depth.exr")));
    let mut c = Command::new(program[0]);
    c.current_dir(workspace()).args(&program[1..]);
    c.args(["--view".as_ref(), view.as_os_str(), "--visibility".as_ref(), visibility.as_os_str()]);
    c.args(["--depth".as_ref(), depth.as_os_str()]).args(extra);
    let stderr = run_ok(c, &format!("{program:?} {extra:?}"));
    ((visibility, depth), stderr)
}

/// Asserts that two renders of the same inputs wrote the same bytes.
pub fn assert_same_bytes(a: &Buffers, b: &Buffers) {
    for (a, b) in [(&a.0, &b.0), (&a.1, &b.1)] {
        assert!(
            std::fs::read(a).unwrap() == std::fs::read(b).unwrap(),
            "{} and {} differ",
            a.display(),
            b.display()
        );
    }
}

pub fn view_json(exported: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(exported.join("view.json")).unwrap()).unwrap()
}

/// Each run's counts in a report folder, in the report's order.
pub fn report_counts(report_dir: &Path) -> Vec<Value> {
    let text = std::fs::read_to_string(report_dir.join("report.json")).unwrap();
    let report: Value = serde_json::from_str(&text).unwrap();
    report["runs"].as_array().unwrap().iter().map(|r| r["counts"].clone()).collect()
}

pub fn count(counts: &Value, key: &str) -> i64 {
    counts[key].as_i64().unwrap_or(0)
}

/// One of the bundled scenes, with the light the test renders (camera `main`).
#[derive(Clone, Copy)]
pub struct View {
    pub scene: &'static str,
    pub light: &'static str,
}

pub const PLANE_BOX: View = View { scene: "scenes/plane_box.json", light: "sun" };
pub const SPOT: View = View { scene: "scenes/spot.json", light: "lamp" };
/// The room's point lamp with a cube map clamped at its seams (no guard band): the cube a
/// hardware `samplerCube` reads.
pub const ROOM_POINT: View = View { scene: "scenes/point/room.json", light: "lamp_clamped" };

/// `view-export` of the view at `RESOLUTION` into `dir/view`.
pub fn export(view: View, dir: &Path) -> PathBuf {
    let out = dir.join("view");
    let mut c = binary();
    c.args(["view-export", view.scene, "--camera", "main", "--light", view.light, "--quiet"]);
    c.args(["--resolution", &RESOLUTION.to_string(), "-o"]).arg(&out);
    run_ok(c, "view-export");
    out
}

/// `score` of an engine's buffers: the counts.
pub fn score(view: View, dir: &Path, name: &str, (visibility, depth): &Buffers) -> Value {
    let out = dir.join(format!("{name}.score"));
    let mut c = binary();
    c.args(["score", view.scene, "--camera", "main", "--light", view.light, "--quiet"]);
    c.args(["--visibility".as_ref(), visibility.as_os_str(), "--depth".as_ref(), depth.as_os_str()]);
    c.args(["-o".as_ref(), out.as_os_str()]);
    run_ok(c, &format!("score {name}"));
    report_counts(&out).remove(0)
}

/// The emulation's counts of the techniques' `runs` runs at `RESOLUTION` in `depth_format`, in
/// the plan's order.
pub fn emulate(view: View, dir: &Path, techniques: &[Value], depth_format: &str, runs: usize) -> Vec<Value> {
    let plan = serde_json::json!({
        "format": "shadowtruth/plan/v1",
        "scenes": [workspace().join(view.scene)],
        "cameras": ["main"], "lights": [view.light],
        "techniques": techniques,
        "resolutions": [RESOLUTION], "depth_formats": [depth_format], "repeats": 1,
    });
    let plan_path = dir.join(format!("plan.{depth_format}.json"));
    std::fs::write(&plan_path, plan.to_string()).unwrap();
    let emulated = dir.join(format!("emulated.{depth_format}"));
    let mut c = binary();
    c.args(["run", "--quiet", "--plan"]).arg(&plan_path).arg("-o").arg(&emulated);
    run_ok(c, "run (emulation)");
    let counts = report_counts(&emulated);
    assert_eq!(counts.len(), runs);
    counts
}

/// Asserts |engine − emulation| ≤ `relative`·emulation + 100 pixels for the false shadows and
/// false lits, the same surface in nearly every pixel (camera, rows and depth convention agree),
/// and the same pixels evaluated.
pub fn assert_agrees(engine: &str, setting: &str, rendered: &Value, emulation: &Value, relative: f64) {
    eprintln!("{setting}: {engine} {rendered}\n{setting}: emulation {emulation}");
    assert_eq!(count(rendered, "evaluated"), count(emulation, "evaluated"));
    let mismatch = count(rendered, "surface_mismatch");
    assert!(
        mismatch as f64 <= 1e-4 * count(rendered, "evaluated") as f64,
        "{setting}: {mismatch} mismatches"
    );
    for key in ["false_shadow", "false_lit"] {
        let (r, e) = (count(rendered, key), count(emulation, key));
        let bound = relative * e as f64 + 100.0;
        assert!(
            (r - e).abs() as f64 <= bound,
            "{setting}: {key} {engine} {r}, emulation {e} (bound {bound})"
        );
    }
}
