//! three.js scored end to end: `view-export` of plane_box (its sun) and of spot (its lamp),
//! `engines/three/render.mjs` renders each
//! with three's own shadow maps in headless Chromium, `score` counts its errors against the exact
//! reference, and the counts agree with the CPU emulation of the same setting; the same inputs
//! give the same bytes. Needs node with `npm ci --prefix engines/three` run, and Chromium.

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

/// three.js stores its shadow map in a 24-bit unsigned-normalized depth texture
/// (DepthTexture with UnsignedIntType, DEPTH_COMPONENT24 in WebGL 2).
const THREE_DEPTH_FORMAT: &str = "unorm24";
/// The map the test renders and emulates at, the export's default resolution.
const RESOLUTION: u32 = 2048;
/// A three.js bias of −0.0005 moves the receiver's light depth 0.0005 towards the light; the
/// emulation moves the map's depth away by as much, as a raster bias of this many unorm24 steps.
const BIAS_DEPTH: f64 = 0.0005;
/// three.js's normalBias: world units along the surface normal, no falloff.
const NORMAL_BIAS_WORLD: f64 = 0.02;

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn binary() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_shadowtruth"));
    c.current_dir(workspace());
    c
}

/// Fails, naming what to install, when node, the engine's packages or Chromium are missing.
fn require_tools() {
    let node = Command::new("node").arg("--version").output();
    assert!(
        node.is_ok_and(|o| o.status.success()),
        "node is missing: install Node.js (`apt-get install nodejs npm`), then `npm ci --prefix engines/three`"
    );
    let modules = workspace().join("engines/three/node_modules");
    for package in ["three", "puppeteer-core"] {
        assert!(
            modules.join(package).join("package.json").is_file(),
            "engines/three/node_modules/{package} is missing: run `npm ci --prefix engines/three`"
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

fn run_ok(mut c: Command, what: &str) {
    let out = c.output().unwrap_or_else(|e| panic!("{what}: cannot start: {e}"));
    assert!(
        out.status.success(),
        "{what} failed ({}):\n{}{}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    eprint!("{}", String::from_utf8_lossy(&out.stderr));
}

/// Renders the exported view with three.js; returns (visibility, depth) paths.
fn render(view: &Path, out: &Path, name: &str, extra: &[&str]) -> (PathBuf, PathBuf) {
    let (visibility, depth) =
        (out.join(format!("{name}.visibility.exr")), out.join(format!("{name}.depth.exr")));
    let mut c = Command::new("node");
    c.current_dir(workspace()).arg("engines/three/render.mjs");
    c.args(["--view".as_ref(), view.as_os_str(), "--visibility".as_ref(), visibility.as_os_str()]);
    c.args(["--depth".as_ref(), depth.as_os_str()]).args(extra);
    run_ok(c, &format!("render.mjs {extra:?}"));
    (visibility, depth)
}

fn view_json(exported: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(exported.join("view.json")).unwrap()).unwrap()
}

fn counts(report_dir: &Path) -> Vec<(Value, Value)> {
    let text = std::fs::read_to_string(report_dir.join("report.json")).unwrap();
    let report: Value = serde_json::from_str(&text).unwrap();
    report["runs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| (r["parameters"].clone(), r["counts"].clone()))
        .collect()
}

/// One of the bundled scenes, with the light the test renders.
#[derive(Clone, Copy)]
struct View {
    scene: &'static str,
    light: &'static str,
}

fn score(view: View, dir: &Path, name: &str, (visibility, depth): &(PathBuf, PathBuf)) -> Value {
    let out = dir.join(format!("{name}.score"));
    let mut c = binary();
    c.args(["score", view.scene, "--camera", "main", "--light", view.light, "--quiet"]);
    c.args(["--visibility".as_ref(), visibility.as_os_str(), "--depth".as_ref(), depth.as_os_str()]);
    c.args(["-o".as_ref(), out.as_os_str()]);
    run_ok(c, &format!("score {name}"));
    counts(&out).remove(0).1
}

fn count(counts: &Value, key: &str) -> i64 {
    counts[key].as_i64().unwrap_or(0)
}

/// Bound on |three − emulation| for a count: 5 % of the emulation's count plus 100 pixels. At
/// bias 0 (acne: which pixels self-shadow hangs on depth differences far below a texel's) three's
/// 5-tap PCF and the emulation's single test differ by 2.3 % of about 250 000 false-shadow
/// pixels; at bias −0.0005 and with normalBias 0.02 the counts are tens of pixels apart, of
/// 514 645 evaluated; a bias of the wrong sign gives 503 955 false-shadow pixels.
fn assert_close(setting: &str, key: &str, three: &Value, emulation: &Value) {
    let (t, e) = (count(three, key), count(emulation, key));
    let bound = 0.05 * e as f64 + 100.0;
    assert!((t - e).abs() as f64 <= bound, "{setting}: {key} three.js {t}, emulation {e} (bound {bound})");
}

fn export(view: View, dir: &Path) -> PathBuf {
    let out = dir.join("view");
    let mut c = binary();
    c.args(["view-export", view.scene, "--camera", "main", "--light", view.light, "--quiet"]);
    c.args(["--resolution", &RESOLUTION.to_string(), "-o"]).arg(&out);
    run_ok(c, "view-export");
    out
}

/// The emulation's counts of each technique entry, in the plan's order (entries without lists
/// run once each).
fn emulate(view: View, dir: &Path, techniques: &[Value]) -> Vec<Value> {
    let plan = serde_json::json!({
        "format": "shadowtruth/plan/v1",
        "scenes": [workspace().join(view.scene)],
        "cameras": ["main"], "lights": [view.light],
        "techniques": techniques,
        "resolutions": [RESOLUTION], "depth_formats": [THREE_DEPTH_FORMAT], "repeats": 1,
    });
    let plan_path = dir.join("plan.json");
    std::fs::write(&plan_path, plan.to_string()).unwrap();
    let emulated = dir.join("emulated");
    let mut c = binary();
    c.args(["run", "--quiet", "--plan"]).arg(&plan_path).arg("-o").arg(&emulated);
    run_ok(c, "run (emulation)");
    let runs: Vec<Value> = counts(&emulated).into_iter().map(|(_, c)| c).collect();
    assert_eq!(runs.len(), techniques.len());
    runs
}

/// three.js's depth bias of −`depth`: a raster bias of that many unorm24 steps. three.js renders
/// the back faces of one-sided (closed) objects into its maps (its default shadowSide), so the
/// emulation culls their front faces.
fn three_bias(depth: f64) -> Value {
    let units = depth * ((1u64 << 24) - 1) as f64;
    serde_json::json!({ "technique": "slope_scaled", "factor": 0.0, "units": units, "cull": "front" })
}

fn assert_agrees(setting: &str, three: &Value, emulation: &Value) {
    eprintln!("{setting}: three.js {three}\n{setting}: emulation {emulation}");
    assert_eq!(count(three, "evaluated"), count(emulation, "evaluated"));
    // The same surface in nearly every pixel: camera, rows and depth convention agree.
    let mismatch = count(three, "surface_mismatch");
    assert!(mismatch as f64 <= 1e-4 * count(three, "evaluated") as f64, "{setting}: {mismatch} mismatches");
    for key in ["false_shadow", "false_lit"] {
        assert_close(setting, key, three, emulation);
    }
}

#[test]
fn three_js_directional_shadows_score_like_the_emulation_and_render_deterministically() {
    require_tools();
    let view = View { scene: "scenes/plane_box.json", light: "sun" };
    let dir = tempfile::tempdir().unwrap();
    let exported = export(view, dir.path());
    let defaults = render(&exported, dir.path(), "defaults", &[]);
    let biased = render(&exported, dir.path(), "biased", &["--bias", "-0.0005"]);
    let again = render(&exported, dir.path(), "biased.again", &["--bias", "-0.0005"]);
    for (a, b) in [(&biased.0, &again.0), (&biased.1, &again.1)] {
        assert!(
            std::fs::read(a).unwrap() == std::fs::read(b).unwrap(),
            "{} and {} differ",
            a.display(),
            b.display()
        );
    }
    // normalBias moves the receiver along its normal, which the glb's NORMAL attribute gives.
    let normal_bias =
        render(&exported, dir.path(), "normal_bias", &["--normal-bias", &NORMAL_BIAS_WORLD.to_string()]);

    // three.js's normalBias in the emulation's texels: the map's larger texel side.
    let map = &view_json(&exported)["light"]["shadow_map"];
    let side = |lo: &str, hi: &str| map[hi].as_f64().unwrap() - map[lo].as_f64().unwrap();
    let texel_world = side("left", "right").max(side("bottom", "top")) / RESOLUTION as f64;
    let normal_offset = serde_json::json!({
        "technique": "normal_offset", "scale_texels": NORMAL_BIAS_WORLD / texel_world, "falloff": "none",
    });
    let emulation = emulate(view, dir.path(), &[three_bias(0.0), three_bias(BIAS_DEPTH), normal_offset]);
    let cases = [("bias 0", &defaults), ("bias -0.0005", &biased), ("normalBias 0.02", &normal_bias)];
    for ((setting, buffers), emulated) in cases.into_iter().zip(&emulation) {
        assert_agrees(setting, &score(view, dir.path(), setting, buffers), emulated);
    }
}

/// The spot light's perspective map, with three's single-tap test (BasicShadowMap), which the
/// emulation's test is.
#[test]
fn three_js_spot_shadows_score_like_the_emulation() {
    require_tools();
    let view = View { scene: "scenes/spot.json", light: "lamp" };
    let dir = tempfile::tempdir().unwrap();
    let exported = export(view, dir.path());
    let biased = render(&exported, dir.path(), "basic", &["--shadow-type", "basic", "--bias", "-0.0005"]);
    let emulation = emulate(view, dir.path(), &[three_bias(BIAS_DEPTH)]);
    assert_agrees("spot, basic, bias -0.0005", &score(view, dir.path(), "basic", &biased), &emulation[0]);
}
