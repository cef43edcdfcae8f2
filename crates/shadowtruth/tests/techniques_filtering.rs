//! Filtered techniques: PCF(k, n) takes at most n·k + 1 values and reaches the bound on a shadow
//! edge (Pagot et al., Table 1); Ehm et al.'s Δbias equals the per-tap adaptive bias on planar
//! receivers under a directional light; a bilinear 2×2 PCF of a straight edge is the ramp its
//! weights imply; PCSS widens its penumbra with the blocker distance.

mod common;

use common::{scene_from_json, trace_first};
use shadowtruth::raster::{DepthFormat, LightView};
use shadowtruth::scene::Scene;
use shadowtruth::technique::{ReceiverPlaneParams, TechniqueSpec};
use shadowtruth::trace::GBuffer;
use std::collections::BTreeSet;

/// A 4×4 ground with a thin 1.6×1.6 slab at height 1 and a rod (a shadow under a texel wide)
/// rotated `slab_yaw_deg` about y, under a slanted sun, seen from above and to the side so that
/// their shadows show.
fn edge_scene(slab_yaw_deg: f32) -> Scene {
    let light = serde_json::json!({ "name": "sun", "type": "directional", "direction": [0.3, -1, 0.4] });
    scene_from_json(&serde_json::json!({
        "format": "shadowtruth/scene/v1", "name": "edge",
        "objects": [
            { "name": "ground", "shape": { "type": "plane", "size": [4, 4] } },
            { "name": "slab", "shape": { "type": "box", "size": [1.6, 0.05, 1.6] }, "closed": true,
              "transform": { "rotate_deg": [0, slab_yaw_deg, 0], "translate": [0, 1, -0.8] } },
            { "name": "rod", "shape": { "type": "box", "size": [0.1, 0.05, 1.2] }, "closed": true,
              "transform": { "rotate_deg": [0, slab_yaw_deg, 0], "translate": [0.9, 0.5, 0.6] } }
        ],
        "cameras": [{ "name": "side", "position": [0, 6, 4], "look_at": [0, 0, 0],
                      "fov_y_deg": 40, "width": 512, "height": 512 }],
        "lights": [light]
    }))
}

/// Visibility of every evaluated pixel (in `g.evaluated` order) under `spec` at `resolution`.
fn shade(scene: &Scene, g: &GBuffer, spec: &TechniqueSpec, resolution: u32) -> Vec<f32> {
    common::shade_technique(scene, g, spec, resolution, DepthFormat::F32)
}

/// Indices (into `g.evaluated`) of the ground's pixels.
fn ground(g: &GBuffer) -> Vec<usize> {
    (0..g.evaluated.len()).filter(|&k| g.position[g.evaluated[k] as usize].y < 0.5).collect()
}

fn spec(json: serde_json::Value) -> TechniqueSpec {
    let spec: TechniqueSpec = serde_json::from_value(json).unwrap();
    spec.validate().unwrap();
    spec
}

#[test]
fn pcf_k_n_takes_at_most_n_k_plus_one_values_and_reaches_the_bound_on_an_edge() {
    // The slab at several yaws, so that its edge crosses the texel grid at many angles.
    let views: Vec<(Scene, GBuffer)> = [17.0, 31.0, 53.0, 71.0]
        .into_iter()
        .map(|yaw| {
            let scene = edge_scene(yaw);
            let (g, _) = trace_first(&scene);
            (scene, g)
        })
        .collect();
    for (size, depths) in [(1u32, 1u32), (1, 3), (2, 1), (2, 2), (3, 1), (2, 3), (3, 2)] {
        let k = size * size;
        let technique = spec(serde_json::json!({ "technique": "mdsm", "depths": depths, "neighbourhood": 3,
                                                 "select": "min_max", "kernel": "box", "size": size,
                                                 "bias": "constant", "bias_depth": 0.03 }));
        let mut distinct = BTreeSet::new();
        for (scene, g) in &views {
            let v = shade(scene, g, &technique, 24);
            for i in ground(g) {
                let steps = v[i] * (k * depths) as f32;
                assert!((steps - steps.round()).abs() < 1e-4, "{} is not a multiple of 1/(n·k)", v[i]);
                distinct.insert(steps.round() as u32);
            }
        }
        assert_eq!(
            distinct.len() as u32,
            depths * k + 1,
            "PCF({k}, {depths}) on slanted edges: {distinct:?}"
        );
    }
}

#[test]
fn adaptive_delta_equals_adaptive_per_tap_on_planar_receivers_under_a_directional_light() {
    let scene = scene_from_json(&serde_json::json!({
        "format": "shadowtruth/scene/v1", "name": "tilted_with_box",
        "objects": [
            { "name": "plane", "shape": { "type": "plane", "size": [6, 6] }, "transform": { "rotate_deg": [30, 0, 0] } },
            { "name": "box", "shape": { "type": "box", "size": [0.8, 0.8, 0.8] }, "closed": true,
              "transform": { "rotate_deg": [0, 25, 0], "translate": [0.3, 1.6, 0.2] } }
        ],
        "cameras": [{ "name": "c", "position": [0.5, 6, 6], "look_at": [0, 0, 0], "fov_y_deg": 50, "width": 320, "height": 240 }],
        "lights": [{ "name": "sun", "type": "directional", "direction": [0.2, -1, -0.3] }]
    }));
    let (g, _) = trace_first(&scene);
    for (size, epsilon) in [(5u32, "original"), (11, "original"), (5, "ehm")] {
        let per_tap = |bias: &str| {
            spec(serde_json::json!({ "technique": "pcf", "kernel": "box", "size": size, "bias": bias,
                                     "k": 1e-4, "epsilon": epsilon }))
        };
        for resolution in [256, 1024] {
            let a = shade(&scene, &g, &per_tap("adaptive"), resolution);
            let d = shade(&scene, &g, &per_tap("adaptive_delta"), resolution);
            // Every pixel, the box's faces too: with the epsilon per tap and one rule for taps
            // past the near plane, Δbias is the per-tap bias up to rounding (tests/adaptive_delta.rs).
            let worst = (0..a.len()).map(|k| (a[k] - d[k]).abs()).fold(0.0f32, f32::max);
            assert!(worst <= 1e-6, "{size}×{size} {epsilon} at {resolution}²: differs by {worst}");
            // Not a vacuous comparison: the box casts a filtered shadow on the plane.
            assert!(a.contains(&0.0) && a.iter().any(|&x| x > 0.0 && x < 1.0));
        }
    }
}

#[test]
fn bilinear_pcf_of_a_shadow_edge_is_the_ramp_of_its_weights() {
    // Bilinear PCF at texel-space (x_s, y_s) weights the four texels around (x_s − ½, y_s − ½)
    // by (1 − f)(1 − g), f(1 − g), (1 − f)g, fg; along a straight edge that is a linear ramp one
    // texel wide. Recomputed here from the map itself, independently of the kernel code.
    let scene = edge_scene(0.0);
    let (g, _) = trace_first(&scene);
    let n = 32u32;
    let view = LightView::new(&scene.lights[0], scene.bounds(), n);
    let needs = shadowtruth::technique::LayerNeeds::default();
    let layers = shadowtruth::technique::BuiltLayers::build(&scene, &view, DepthFormat::F32, &needs);
    let map = layers.as_layers().nearest();
    // Large enough that the sloped ground has no acne: the fractional values are the edge's.
    let bias = 0.03;
    let v = shade(
        &scene,
        &g,
        &spec(
            serde_json::json!({ "technique": "pcf", "kernel": "bilinear", "bias": "constant", "bias_depth": bias }),
        ),
        n,
    );
    let last = n as i64 - 1;
    let (mut ramp, mut checked) = (0, 0);
    for k in ground(&g) {
        let uvd = view.project(g.position[g.evaluated[k] as usize]).unwrap();
        let (s, t) = (uvd.x * n as f32 - 0.5, (1.0 - uvd.y) * n as f32 - 0.5);
        let (i, j) = (s.floor() as i64, t.floor() as i64);
        let (f, gw) = (s - s.floor(), t - t.floor());
        let lit = |x: i64, y: i64| {
            (uvd.z - bias <= map.at(x.clamp(0, last) as u32, y.clamp(0, last) as u32)) as u8 as f32
        };
        let expected = (1.0 - f) * (1.0 - gw) * lit(i, j)
            + f * (1.0 - gw) * lit(i + 1, j)
            + (1.0 - f) * gw * lit(i, j + 1)
            + f * gw * lit(i + 1, j + 1);
        assert!((v[k] - expected).abs() < 1e-5, "at ({s}, {t}): {} instead of {expected}", v[k]);
        ramp += (expected > 0.05 && expected < 0.95) as usize;
        checked += 1;
    }
    assert!(ramp > 200 && checked > 10 * ramp, "the ramp is sampled: {ramp} of {checked} pixels");
}

#[test]
fn pcf_box_1_with_receiver_plane_is_the_receiver_plane_technique() {
    let scene = common::tilted_plane();
    let (g, _) = trace_first(&scene);
    for resolution in [128, 1024] {
        let single = shade(
            &scene,
            &g,
            &TechniqueSpec::ReceiverPlane(ReceiverPlaneParams { bias_depth: 1e-5 }),
            resolution,
        );
        let pcf = shade(
            &scene,
            &g,
            &spec(serde_json::json!({ "technique": "pcf", "kernel": "box", "size": 1,
                                      "bias": "receiver_plane", "bias_depth": 1e-5 })),
            resolution,
        );
        let differing = single.iter().zip(&pcf).filter(|(a, b)| a != b).count();
        // The two evaluate the same plane in f64 at the same texel centre; rounding may differ
        // in the last bit of the compared depth.
        assert!(differing * 1000 <= single.len(), "{differing} of {} differ at {resolution}²", single.len());
    }
}

#[test]
fn pcss_penumbra_widens_with_the_distance_to_the_blocker() {
    // Two slabs at heights 0.5 and 2 over the ground: the higher one's penumbra is wider.
    let scene = scene_from_json(&serde_json::json!({
        "format": "shadowtruth/scene/v1", "name": "two_slabs",
        "objects": [
            { "name": "ground", "shape": { "type": "plane", "size": [8, 8] } },
            { "name": "low", "shape": { "type": "box", "size": [2, 0.05, 2] }, "closed": true,
              "transform": { "translate": [-2, 0.5, 0] } },
            { "name": "high", "shape": { "type": "box", "size": [2, 0.05, 2] }, "closed": true,
              "transform": { "translate": [2, 2, 0] } }
        ],
        "cameras": [{ "name": "top", "position": [0, 10, 0.0001], "look_at": [0, 0, 0], "up": [0, 0, -1],
                      "fov_y_deg": 45, "width": 400, "height": 400 }],
        "lights": [{ "name": "sun", "type": "directional", "direction": [0, -1, 0], "angular_diameter_deg": 6 }]
    }));
    let (g, _) = trace_first(&scene);
    let v = shade(
        &scene,
        &g,
        &spec(
            serde_json::json!({ "technique": "pcss", "search_taps": 32, "filter_taps": 64, "bias": "receiver_plane" }),
        ),
        1024,
    );
    // Width (in world x) of the partly lit band next to each slab.
    let band = |x_min: f32, x_max: f32| {
        let xs: Vec<f32> = ground(&g)
            .into_iter()
            .filter(|&k| v[k] > 0.02 && v[k] < 0.98)
            .map(|k| g.position[g.evaluated[k] as usize])
            .filter(|p| p.x > x_min && p.x < x_max && p.z.abs() < 0.5)
            .map(|p| p.x)
            .collect();
        xs.iter().copied().fold(f32::MIN, f32::max) - xs.iter().copied().fold(f32::MAX, f32::min)
    };
    // The inner edges (the camera above the gap sees under them): low slab x ∈ [−3, −1], edge
    // at −1; high slab x ∈ [1, 3], edge at 1.
    let (low, high) = (band(-1.3, -0.7), band(0.7, 1.3));
    // The true penumbra is 2·h·tan(3°): 0.052 under the low slab and 0.21 under the high one.
    assert!(high > 2.5 * low, "penumbra widths: low {low}, high {high}");
    assert!((high - 0.21).abs() < 0.08, "high slab penumbra {high}");
}

#[test]
fn the_soft_plan_parses_and_covers_every_filtered_family() {
    let path = common::repo().join("plans/soft.json");
    let plan: serde_json::Value = serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
    let names: BTreeSet<&str> =
        plan["techniques"].as_array().unwrap().iter().map(|t| t["technique"].as_str().unwrap()).collect();
    assert_eq!(names, BTreeSet::from(["mdsm", "pcf", "pcss"]));
    // Every bundled light has an area size, so PCSS can run on the whole suite.
    for entry in std::fs::read_dir(common::repo().join("scenes")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "json") {
            let scene = shadowtruth::scene::load_scene(&path).unwrap();
            for light in &scene.lights {
                assert!(light.size().is_ok(), "{}: {}", path.display(), light.name);
            }
        }
    }
}
