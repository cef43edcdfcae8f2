//! Ehm et al.'s Δbias (WSCG 2015, Algorithm 1) against the per-tap adaptive bias (Dou et al.
//! 2014) under PCF: they agree on every pixel under a directional light; a worked example of
//! Algorithm 1 (three potential occluders, the extrapolation and the per-tap epsilon) computed by
//! hand; and the one miss rule, for taps whose light line meets the tangent plane in front of the
//! near plane, behind the light, or not at all.

mod common;

use common::{scene_from_json, trace_first};
use glam::Vec3;
use serde_json::json;
use shadowtruth::raster::{DepthFormat, DepthLayer, LightView};
use shadowtruth::scene::{PixelFootprint, Scene};
use shadowtruth::technique::{
    AdaptiveBias, EpsilonScale, Layers, Sample, ShadeContext, TangentPlane, TapBias, TapDepth, TechniqueSpec,
};
use shadowtruth::trace::GBuffer;

/// Ground, a tilted plane and a floating slab; nothing touches, so no two surfaces meet within
/// rounding of a receiver's tangent plane. The slab's top corner towards the light is a corner of
/// the scene's bounds, so it lies next to the near plane of a directional light's fitted map:
/// taps around the top of its lit faces reach past it (the miss rule).
fn casters(light: serde_json::Value) -> Scene {
    scene_from_json(&json!({
        "format": "shadowtruth/scene/v1", "name": "casters",
        "objects": [
            { "name": "ground", "shape": { "type": "plane", "size": [8, 8] } },
            { "name": "tilted", "shape": { "type": "plane", "size": [3, 3] },
              "transform": { "rotate_deg": [35, 0, 0], "translate": [1.0, 1.0, 0.5] } },
            { "name": "slab", "shape": { "type": "box", "size": [1.2, 0.3, 1.0] }, "closed": true,
              "transform": { "translate": [-3.8, 1.8, -3.8] } }
        ],
        "cameras": [{ "name": "c", "position": [-6, 7, -6], "look_at": [-0.5, 0.5, -0.5], "fov_y_deg": 60,
                      "width": 320, "height": 240 }],
        "lights": [light]
    }))
}

fn sun() -> serde_json::Value {
    json!({ "name": "sun", "type": "directional", "direction": [0.35, -1, 0.25] })
}

fn pcf11(bias: &str, epsilon: &str) -> TechniqueSpec {
    let spec: TechniqueSpec =
        serde_json::from_value(json!({ "technique": "pcf", "kernel": "box", "size": 11,
        "bias": bias, "k": 1e-4, "epsilon": epsilon }))
        .unwrap();
    spec.validate().unwrap();
    spec
}

/// Visibility of every evaluated pixel (in `g.evaluated` order) under `spec` at `resolution`.
fn shade(scene: &Scene, g: &GBuffer, spec: &TechniqueSpec, resolution: u32) -> Vec<f32> {
    common::shade_technique(scene, g, spec, resolution, DepthFormat::F32)
}

/// Receivers with a tap of the 11×11 kernel whose potential occluder lies in front of the near
/// plane (d < 0).
fn receivers_with_taps_before_the_near_plane(scene: &Scene, g: &GBuffer, resolution: u32) -> usize {
    let view = LightView::new(&scene.lights[0], scene.bounds(), resolution);
    let map = DepthLayer::new_empty(resolution);
    let ctx = ShadeContext::new(scene, PixelFootprint::of(&scene.cameras[0]), &view, Layers::Nearest(&map));
    let r = resolution as f32;
    g.evaluated
        .iter()
        .filter(|&&i| {
            let s = sample(g, i as usize);
            let (Some(plane), Some(p)) = (TangentPlane::of(&s, &ctx), view.project(s.position)) else {
                return false;
            };
            let (x0, row0) = ((p.x * r).floor(), ((1.0 - p.y) * r).floor());
            (-5..=5).any(|j| {
                (-5..=5).any(|i| {
                    let centre = ((x0 + i as f32 + 0.5) / r, 1.0 - (row0 + j as f32 + 0.5) / r);
                    plane.depth_at(&ctx, centre) < 0.0
                })
            })
        })
        .count()
}

fn sample(g: &GBuffer, i: usize) -> Sample {
    Sample { position: g.position[i], normal: g.normal[i], triangle: g.triangle[i] }
}

#[test]
fn per_tap_adaptive_and_delta_agree_on_every_pixel_under_a_directional_light() {
    let scene = casters(sun());
    let (g, _) = trace_first(&scene);
    for resolution in [256, 1024] {
        // Not vacuous: taps beyond the near plane, where a per-tap fallback to the receiver's
        // depth would part from Δbias's extrapolation (on 289 pixels of the slab at 256²).
        let beyond = receivers_with_taps_before_the_near_plane(&scene, &g, resolution);
        assert!(beyond > 50, "{resolution}²: {beyond} receivers reach past the near plane");
        for epsilon in ["original", "ehm"] {
            let a = shade(&scene, &g, &pcf11("adaptive", epsilon), resolution);
            let d = shade(&scene, &g, &pcf11("adaptive_delta", epsilon), resolution);
            let differing: Vec<usize> = (0..a.len()).filter(|&k| (a[k] - d[k]).abs() > 1e-6).collect();
            assert!(
                differing.is_empty(),
                "{epsilon} at {resolution}²: {} of {} pixels differ, e.g. object {} by {}",
                differing.len(),
                a.len(),
                g.object(&scene, g.evaluated[differing[0]] as usize),
                (a[differing[0]] - d[differing[0]]).abs()
            );
            // Not vacuous: filtered cast shadows.
            assert!(a.contains(&0.0) && a.iter().filter(|&&x| x > 0.0 && x < 1.0).count() > 100);
        }
    }
}

#[test]
fn per_tap_adaptive_and_delta_agree_under_a_spot_light_where_the_epsilon_decides() {
    // A perspective map: the epsilon varies with each tap's occluder depth, so only a per-tap
    // epsilon in Δbias agrees with the per-tap adaptive bias. A sheet hovers over the ground at
    // about the world tolerance K·sceneScale (≈ 1.2·10⁻³), so under it the epsilon decides taps.
    let scene = scene_from_json(&json!({
        "format": "shadowtruth/scene/v1", "name": "sheet",
        "objects": [
            { "name": "ground", "shape": { "type": "plane", "size": [8, 8] } },
            { "name": "sheet", "shape": { "type": "plane", "size": [3, 3] },
              "transform": { "rotate_deg": [0.03, 0, 0], "translate": [-0.5, 0.0012, 0.5] } },
            { "name": "slab", "shape": { "type": "box", "size": [1.2, 0.3, 1.0] }, "closed": true,
              "transform": { "rotate_deg": [0, 20, 0], "translate": [1.5, 1.8, -1.0] } }
        ],
        "cameras": [{ "name": "c", "position": [-5, 6, 6], "look_at": [0, 0, 0], "fov_y_deg": 50,
                      "width": 320, "height": 240 }],
        "lights": [{ "name": "lamp", "type": "spot", "position": [-4, 6, 3], "direction": [0.6, -1, -0.45],
                     "cone_deg": 80, "near": 2, "far": 14 }]
    }));
    let (g, _) = trace_first(&scene);
    for resolution in [128, 512] {
        let a = shade(&scene, &g, &pcf11("adaptive", "original"), resolution);
        let d = shade(&scene, &g, &pcf11("adaptive_delta", "original"), resolution);
        let differing = (0..a.len()).filter(|&k| (a[k] - d[k]).abs() > 1e-6).count();
        // Where a tap's gap to the sheet equals its epsilon to an ulp, the rounding of the
        // extrapolation decides it: a few pixels. An epsilon per receiver parts on 555 at 128².
        assert!(differing <= a.len() / 2000, "{resolution}²: {differing} of {} pixels differ", a.len());
        // Not vacuous: the epsilon decides a band of taps under the sheet.
        let partial = a.iter().filter(|&&x| x > 0.0 && x < 1.0).count();
        assert!(partial > 500, "{resolution}²: {partial} partly lit pixels");
    }
}

/// A spot light at (0, 10, 0) looking straight down, 90° cone (tan ½ = 1), near 1, far 21, over
/// the plane y = 0.5·x + 0.25·z: view x is world z and view y is world x, so the light's line
/// through the texel centre at NDC (x_n, y_n) is (D·y_n, 10 − D, D·x_n) and meets the plane at
/// view depth D = 10/(1 + 0.5·y_n + 0.25·x_n). With d = f(D − n)/(D(f − n)) = 1.05·(1 − 1/D):
///
///   d_o(x, row) = 1.05·(0.9 − 0.05·y_n − 0.025·x_n)
///               = 0.91875 + (0.105·(row + ½) − 0.0525·(x + ½))/R
///
/// (x_n = 2(x + ½)/R − 1, y_n = 1 − 2(row + ½)/R), and the adaptive epsilon at d_o is
/// `K·sceneScale·(f − d_o(f − n))²/(f·n·(f − n)) = K·sceneScale·(21 − 20·d_o)²/420`.
fn overhead_lamp(plane_size: f32) -> Scene {
    scene_from_json(&json!({
        "format": "shadowtruth/scene/v1", "name": "overhead",
        "objects": [{ "name": "p", "shape": { "type": "plane", "size": [plane_size, plane_size] } }],
        "cameras": [{ "name": "c", "position": [0, 5, 5], "look_at": [0, 0, 0], "fov_y_deg": 45, "width": 8, "height": 8 }],
        "lights": [{ "name": "lamp", "type": "spot", "position": [0, 10, 0], "direction": [0, -1, 0],
                     "cone_deg": 90, "near": 1, "far": 21 }]
    }))
}

/// The prepared tap depths of `bias` for receiver `s` (and the receiver's texel).
fn prepare(bias: &TapBias, s: &Sample, ctx: &ShadeContext) -> (TapDepth, (i64, i64)) {
    let uvd = ctx.view.project(s.position).unwrap();
    let r = ctx.layers.resolution() as f32;
    let (x0, row0) = ((uvd.x * r).floor() as i64, ((1.0 - uvd.y) * r).floor() as i64);
    (bias.prepare(s, ctx, uvd, x0, row0), (x0, row0))
}

#[test]
fn algorithm_1_worked_by_hand_for_one_receiver_and_six_taps() {
    const R: u32 = 64;
    let scene = overhead_lamp(4.0);
    let view = LightView::new(&scene.lights[0], scene.bounds(), R);
    let map = DepthLayer::new_empty(R);
    let ctx = ShadeContext::new(&scene, PixelFootprint::of(&scene.cameras[0]), &view, Layers::Nearest(&map));
    // The receiver (0.3, 0.2, 0.2) on the plane: D = 9.8, NDC (0.2/9.8, 0.3/9.8), so
    // u = 0.5102 and v = 0.5153: texel (32, 31).
    let s = Sample {
        position: Vec3::new(0.3, 0.2, 0.2),
        normal: Vec3::new(-0.5, 1.0, -0.25).normalize(),
        triangle: 0,
    };
    let k = 1e-4;
    let tolerance = k as f64 * ctx.scene_scale as f64;
    let adaptive = AdaptiveBias { k, epsilon: EpsilonScale::Original };
    let (TapDepth::Delta { occluders, epsilon }, texel) =
        prepare(&TapBias::AdaptiveDelta(adaptive), &s, &ctx)
    else {
        panic!("a plane facing the light has potential occluders");
    };
    assert_eq!(texel, (32, 31));

    // The potential occluders of the receiver's texel and of one texel over in x and in y, and
    // their differences Δx = −0.0525/64, Δy = 0.105/64.
    let d_o = |x: f64, row: f64| 0.91875 + (0.105 * (row + 0.5) - 0.0525 * (x + 0.5)) / R as f64;
    assert!((occluders.d0 as f64 - d_o(32.0, 31.0)).abs() < 1e-6, "{} vs 0.94376953", occluders.d0);
    assert!((occluders.du as f64 + 0.0525 / 64.0).abs() < 1e-7, "Δx = {}", occluders.du);
    assert!((occluders.dv as f64 - 0.105 / 64.0).abs() < 1e-7, "Δy = {}", occluders.dv);

    // Per tap: the extrapolated occluder, the epsilon of that occluder (the algorithm's line 11),
    // the depth compared.
    let per_tap = TapBias::Adaptive(AdaptiveBias { k, epsilon: EpsilonScale::Original });
    let (prepared_per_tap, _) = prepare(&per_tap, &s, &ctx);
    let eps_at = |d: f64| tolerance * (21.0 - 20.0 * d).powi(2) / 420.0;
    let receiver_eps = eps_at(d_o(32.0, 31.0));
    for (i, j) in [(0i64, 0i64), (-5, -5), (5, -5), (-5, 5), (5, 5), (3, -2)] {
        let (x, row) = (32 + i, 31 + j);
        let hand = d_o(x as f64, row as f64);
        let code = occluders.at(x, row) as f64;
        assert!((code - hand).abs() < 2e-6, "tap ({i}, {j}): occluder {code} vs {hand}");
        let eps = epsilon.at(code as f32) as f64;
        assert!(
            (eps - eps_at(hand)).abs() < 1e-4 * eps_at(hand),
            "tap ({i}, {j}): ε {eps} vs {}",
            eps_at(hand)
        );
        let compared = TapDepth::Delta { occluders, epsilon }.at(&ctx, x, row) as f64;
        assert!((compared - (hand - eps_at(hand))).abs() < 2e-6, "tap ({i}, {j}): {compared}");
        // The per-tap adaptive bias intersects the plane at this tap itself: the same depth.
        let direct = prepared_per_tap.at(&ctx, x, row) as f64;
        assert!((direct - compared).abs() < 3e-7, "tap ({i}, {j}): per tap {direct} vs Δbias {compared}");
        // Five rows away the epsilon is 8 to 15 % off the receiver's: the per-tap epsilon matters.
        if j.abs() == 5 {
            assert!((eps_at(hand) - receiver_eps).abs() > 0.05 * receiver_eps);
        }
    }
}

#[test]
fn a_tap_whose_line_misses_the_tangent_plane_gets_the_same_depth_from_both() {
    // The plane y = 8 + 4x under the same lamp (an 8² map, so that 5 texels span 1.25 in NDC):
    // D = 2/(1 + 4·y_n). Rows with y_n > 0.25 meet it before the near plane (D < 1, d < 0); rows
    // with y_n < −0.25 behind the light (D < 0, d > f/(f − n)); y_n = −0.25 would be parallel.
    const R: u32 = 8;
    let scene = overhead_lamp(4.0);
    let view = LightView::new(&scene.lights[0], scene.bounds(), R);
    let map = DepthLayer::new_empty(R);
    let ctx = ShadeContext::new(&scene, PixelFootprint::of(&scene.cameras[0]), &view, Layers::Nearest(&map));
    // The receiver (0.025, 8.1, 0): D = 1.9, NDC (0, 0.0132), texel (4, 3), whose centre has
    // y_n = 0.125; the kernel's rows run from y_n = 1.375 down to −1.125.
    let s = Sample {
        position: Vec3::new(0.025, 8.1, 0.0),
        normal: Vec3::new(-4.0, 1.0, 0.0).normalize(),
        triangle: 0,
    };
    let adaptive = || AdaptiveBias { k: 1e-4, epsilon: EpsilonScale::Original };
    let (per_tap, delta) = (TapBias::Adaptive(adaptive()), TapBias::AdaptiveDelta(adaptive()));
    let ((pa, texel), (pd, _)) = (prepare(&per_tap, &s, &ctx), prepare(&delta, &s, &ctx));
    let eps = adaptive().epsilon_of(&s, &ctx).unwrap();
    let (mut before_near, mut behind_light) = (0, 0);
    for row in texel.1 - 5..=texel.1 + 5 {
        let y_n = 1.0 - 2.0 * (row as f64 + 0.5) / R as f64;
        let hand = 1.05 * (1.0 - (1.0 + 4.0 * y_n) / 2.0);
        before_near += (hand < 0.0) as u32;
        behind_light += (hand > 1.05) as u32;
        for x in texel.0 - 5..=texel.0 + 5 {
            let a = pa.at(&ctx, x, row) as f64;
            let d = pd.at(&ctx, x, row) as f64;
            let expected = hand - eps.at(hand as f32) as f64;
            assert!((a - expected).abs() < 1e-5, "({x}, {row}): per tap {a} vs {expected}");
            assert!((d - a).abs() < 1e-5, "({x}, {row}): Δbias {d} vs per tap {a}");
        }
    }
    assert!(
        before_near > 0 && behind_light > 0,
        "{before_near} rows before the near plane, {behind_light} behind"
    );

    // Seen edge-on (the plane holds the light's position), the plane has no depth at any texel:
    // every tap of both compares the receiver's own depth, minus the epsilon there.
    let edge_on = Sample { position: Vec3::new(0.0, 5.0, 0.5), normal: Vec3::X, triangle: 0 };
    let d = view.project(edge_on.position).unwrap().z;
    for bias in [&per_tap, &delta] {
        let (prepared, _) = prepare(bias, &edge_on, &ctx);
        let TapDepth::Flat(z) = prepared else { panic!("edge-on: {prepared:?}") };
        assert_eq!(z, eps.below(d));
    }
}
