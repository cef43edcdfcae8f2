//! three.js scored end to end: `view-export` of plane_box (its sun), of spot (its lamp) and of
//! the point-light room (its lamp's cube), `engines/three/render.mjs` renders each
//! with three's own shadow maps in headless Chromium, `score` counts its errors against the exact
//! reference, and the counts agree with the CPU emulation of the same setting; the same inputs
//! give the same bytes. Needs node with `npm ci --prefix engines/three` run, and Chromium.

mod engine_harness;

use engine_harness::{
    Buffers, PLANE_BOX, RESOLUTION, ROOM_POINT, SPOT, View, emulate, export, render, score, view_json,
};
use serde_json::Value;
use std::path::Path;

/// three.js stores its shadow map in a 24-bit unsigned-normalized depth texture
/// (DepthTexture with UnsignedIntType, DEPTH_COMPONENT24 in WebGL 2).
const THREE_DEPTH_FORMAT: &str = "unorm24";
/// A three.js bias of −0.0005 moves the receiver's light depth 0.0005 towards the light; the
/// emulation moves the map's depth away by as much, as a raster bias of this many unorm24 steps.
const BIAS_DEPTH: f64 = 0.0005;
/// three.js's normalBias: world units along the surface normal, no falloff.
const NORMAL_BIAS_WORLD: f64 = 0.02;

fn require_tools() {
    engine_harness::require_browser_engine("three", &["three", "puppeteer-core"]);
}

/// Renders the exported view with three.js.
fn render_three(view: &Path, out: &Path, name: &str, extra: &[&str]) -> Buffers {
    render(&["node", "engines/three/render.mjs"], view, out, name, extra)
}

/// Bound on |three − emulation| for a count: 5 % of the emulation's count plus 100 pixels. At
/// bias 0 (acne: which pixels self-shadow hangs on depth differences far below a texel's) three's
/// 5-tap PCF and the emulation's single test differ by 2.3 % of about 250 000 false-shadow
/// pixels; at bias −0.0005 and with normalBias 0.02 the counts are tens of pixels apart, of
/// 514 645 evaluated; a bias of the wrong sign gives 503 955 false-shadow pixels.
const RELATIVE_BOUND: f64 = 0.05;

fn emulate_three(view: View, dir: &Path, techniques: &[Value]) -> Vec<Value> {
    emulate(view, dir, techniques, THREE_DEPTH_FORMAT, techniques.len())
}

/// three.js's depth bias of −`depth`: a raster bias of that many unorm24 steps. three.js renders
/// the back faces of one-sided (closed) objects into its maps (its default shadowSide), so the
/// emulation culls their front faces.
fn three_bias(depth: f64) -> Value {
    let units = depth * ((1u64 << 24) - 1) as f64;
    serde_json::json!({ "technique": "slope_scaled", "factor": 0.0, "units": units, "cull": "front" })
}

fn assert_agrees(setting: &str, three: &Value, emulation: &Value) {
    engine_harness::assert_agrees("three.js", setting, three, emulation, RELATIVE_BOUND);
}

#[test]
fn three_js_directional_shadows_score_like_the_emulation_and_render_deterministically() {
    require_tools();
    let view = PLANE_BOX;
    let dir = tempfile::tempdir().unwrap();
    let exported = export(view, dir.path());
    let defaults = render_three(&exported, dir.path(), "defaults", &[]);
    let biased = render_three(&exported, dir.path(), "biased", &["--bias", "-0.0005"]);
    let again = render_three(&exported, dir.path(), "biased.again", &["--bias", "-0.0005"]);
    engine_harness::assert_same_bytes(&biased, &again);
    // normalBias moves the receiver along its normal, which the glb's NORMAL attribute gives.
    let normal_bias = render_three(
        &exported,
        dir.path(),
        "normal_bias",
        &["--normal-bias", &NORMAL_BIAS_WORLD.to_string()],
    );

    // three.js's normalBias in the emulation's texels: the map's larger texel side.
    let map = &view_json(&exported)["light"]["shadow_map"];
    let side = |lo: &str, hi: &str| map[hi].as_f64().unwrap() - map[lo].as_f64().unwrap();
    let texel_world = side("left", "right").max(side("bottom", "top")) / RESOLUTION as f64;
    let normal_offset = serde_json::json!({
        "technique": "normal_offset", "scale_texels": NORMAL_BIAS_WORLD / texel_world, "falloff": "none",
    });
    let emulation =
        emulate_three(view, dir.path(), &[three_bias(0.0), three_bias(BIAS_DEPTH), normal_offset]);
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
    let view = SPOT;
    let dir = tempfile::tempdir().unwrap();
    let exported = export(view, dir.path());
    let biased =
        render_three(&exported, dir.path(), "basic", &["--shadow-type", "basic", "--bias", "-0.0005"]);
    let emulation = emulate_three(view, dir.path(), &[three_bias(BIAS_DEPTH)]);
    assert_agrees("spot, basic, bias -0.0005", &score(view, dir.path(), "basic", &biased), &emulation[0]);
}

/// The point light's cube: three draws six faces into a cube texture and its BasicShadowMap reads
/// it through a `samplerCube` (the hardware picks the face; no guard band), which is the
/// emulation's cube with its seams clamped and the single-tap test.
#[test]
fn three_js_point_light_shadows_score_like_the_emulations_clamped_cube() {
    require_tools();
    let view = ROOM_POINT;
    let dir = tempfile::tempdir().unwrap();
    let exported = export(view, dir.path());
    let map = &view_json(&exported)["light"]["shadow_map"];
    assert_eq!((map["projection"].as_str(), map["guard_texels"].as_u64()), (Some("cube"), Some(0)));
    let biased =
        render_three(&exported, dir.path(), "basic", &["--shadow-type", "basic", "--bias", "-0.0005"]);
    let emulation = emulate_three(view, dir.path(), &[three_bias(BIAS_DEPTH)]);
    assert_agrees("point, basic, bias -0.0005", &score(view, dir.path(), "basic", &biased), &emulation[0]);
}

/// Every shadow type reaches three.js: BasicShadowMap, PCFShadowMap and VSMShadowMap each draw
/// other pixels, and PCFSoftShadowMap, which r187 removed, renders PCF (three warns) — the same
/// bytes. A type the page dropped would render three's default, PCF.
#[test]
fn every_three_js_shadow_type_changes_the_image() {
    require_tools();
    let dir = tempfile::tempdir().unwrap();
    let exported = export(PLANE_BOX, dir.path());
    let image = |shadow_type: &str| {
        let args = ["--shadow-type", shadow_type, "--map-size", "512", "--bias", "-0.0005"];
        std::fs::read(render_three(&exported, dir.path(), shadow_type, &args).0).unwrap()
    };
    let (basic, pcf, pcfsoft, vsm) = (image("basic"), image("pcf"), image("pcfsoft"), image("vsm"));
    assert!(pcfsoft == pcf, "r187 renders PCFSoftShadowMap as PCFShadowMap");
    assert!(basic != pcf && basic != vsm && pcf != vsm, "two shadow types rendered the same image");
}
