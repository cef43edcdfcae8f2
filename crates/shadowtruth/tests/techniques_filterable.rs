//! The filterable maps on analytic scenes under a sun straight down, where each occluder's shadow
//! is its own footprint: one occluder, where VSM is the exact depth test wherever its filter
//! region sees one depth; two stacked occluders, where VSM bleeds light through the lower one
//! next to the upper one's edge, by Chebyshev's bound, and its bleeding reduction removes it.
//! And the mipmapped maps' level of detail, worked by hand where camera and light look straight
//! down on a floor.

mod common;

use common::{scene_from_json, shade_technique, trace_first};
use shadowtruth::raster::{DepthFormat, LightView};
use shadowtruth::scene::Scene;
use shadowtruth::technique::TechniqueSpec;

const RESOLUTION: u32 = 256;

/// A 4×4 ground; a 2×2 slab at height 1 over x, z ∈ [−1, 1]; with `upper`, a second slab at
/// height 2 over x ∈ [−1, 0], z ∈ [−1, 1]. Sun straight down; the camera looks in below the slabs.
fn slabs(upper: bool) -> Scene {
    let mut objects = vec![
        serde_json::json!({ "name": "ground", "shape": { "type": "plane", "size": [4, 4] } }),
        serde_json::json!({ "name": "lower", "shape": { "type": "box", "size": [2, 0.02, 2] }, "closed": true,
                            "transform": { "translate": [0, 1, 0] } }),
    ];
    if upper {
        objects.push(serde_json::json!({ "name": "upper", "shape": { "type": "box", "size": [1, 0.02, 2] },
            "closed": true, "transform": { "translate": [-0.5, 2, 0] } }));
    }
    scene_from_json(&serde_json::json!({
        "format": "shadowtruth/scene/v1", "name": "slabs", "objects": objects,
        "cameras": [{ "name": "under", "position": [0.2, 0.5, 4], "look_at": [0, 0.1, 0],
                      "fov_y_deg": 50, "width": 384, "height": 256 }],
        "lights": [{ "name": "sun", "type": "directional", "direction": [0, -1, 0] }]
    }))
}

fn spec(json: serde_json::Value) -> TechniqueSpec {
    let spec: TechniqueSpec = serde_json::from_value(json).unwrap();
    spec.validate().unwrap();
    spec
}

/// (ground pixel's x, z, its visibility, its reference) for every evaluated ground pixel.
fn ground(scene: &Scene, technique: serde_json::Value) -> Vec<(f32, f32, f32, bool)> {
    let (g, reference) = trace_first(scene);
    let v = shade_technique(scene, &g, &spec(technique), RESOLUTION, DepthFormat::F32);
    g.evaluated
        .iter()
        .zip(v)
        .filter(|(i, _)| g.position[**i as usize].y < 0.5)
        .map(|(&i, v)| {
            let p = g.position[i as usize];
            (p.x, p.z, v, reference.lit[i as usize] != 0)
        })
        .collect()
}

/// One texel's world size of the sun's map over `scene`.
fn texel_world(scene: &Scene) -> f32 {
    let view = LightView::new(&scene.lights[0], scene.bounds(), RESOLUTION);
    view.texel_world_size(glam::Vec3::ZERO)
}

#[test]
fn one_occluder_vsm_is_the_exact_depth_test_where_its_filter_sees_one_depth() {
    let scene = slabs(false);
    let texel = texel_world(&scene);
    // A 3×3 box blur and the bilinear read reach 2.5 texels; 3 texels off the edge the region
    // holds one depth.
    let margin = 3.0 * texel;
    let (mut inside, mut outside) = (0, 0);
    for technique in [
        serde_json::json!({ "technique": "vsm", "min_variance": 0, "blur": "none" }),
        serde_json::json!({ "technique": "vsm", "min_variance": 0 }),
        serde_json::json!({ "technique": "msm" }),
        serde_json::json!({ "technique": "evsm4" }),
    ] {
        for (x, z, v, lit) in ground(&scene, technique.clone()) {
            let edge_distance = (x.abs() - 1.0).abs().min((z.abs() - 1.0).abs());
            let under = x.abs() < 1.0 && z.abs() < 1.0;
            if edge_distance > 1e-3 {
                assert_eq!(lit, !under, "the reference at ({x}, {z})");
            }
            if edge_distance < margin {
                continue;
            }
            let expected = if under { 0.0 } else { 1.0 };
            // Unblurred VSM is exact (the bilinear mix of equal moments is those moments); the box
            // blur's f32 sums leave a variance of a few ulps; MSM and EVSM are within their
            // biases' reach.
            let tolerance = match (technique["technique"].as_str(), technique.get("blur")) {
                (Some("vsm"), Some(_)) => 0.0,
                (Some("vsm"), None) => 1e-6,
                _ => 0.02,
            };
            assert!((v - expected).abs() <= tolerance, "{technique} at ({x}, {z}): {v}, not {expected}");
            if under { inside += 1 } else { outside += 1 }
        }
    }
    assert!(inside > 300 && outside > 300, "{inside} under, {outside} outside");
}

#[test]
fn two_stacked_occluders_bleed_next_to_the_upper_edge_by_chebyshevs_bound() {
    let scene = slabs(true);
    let texel = texel_world(&scene);
    let pixels = ground(&scene, serde_json::json!({ "technique": "vsm", "min_variance": 0 }));
    // Under the lower slab's far half (x ∈ (0, 1)) the ground is in shadow of the lower slab
    // alone; next to x = 0 the filter region also sees the upper slab, one unit nearer the sun.
    // The filter region holds a fraction a of the upper slab's depth z_u and 1 − a of the
    // lower's z_l, and the receiver sits Δ_r behind the lower: Chebyshev's bound
    // a(1 − a)Δ² / (a(1 − a)Δ² + (Δ_r + aΔ)²), Δ = z_l − z_u, is at most its maximum over a.
    // In light depth the slabs and the ground are 1 world unit apart (depth is linear).
    let view = LightView::new(&scene.lights[0], scene.bounds(), RESOLUTION);
    let depth = |y: f32| view.project(glam::Vec3::new(0.5, y, 0.0)).unwrap().z;
    let (zu, zl, zr) = (depth(1.99), depth(0.99), depth(0.0));
    let (delta, behind) = (zl - zu, zr - zl);
    let bound = (0..=1000)
        .map(|k| {
            let a = k as f32 / 1000.0;
            let var = a * (1.0 - a) * delta * delta;
            var / (var + (behind + a * delta).powi(2))
        })
        .fold(0.0f32, f32::max);
    let mut bled = 0;
    for &(x, z, v, lit) in &pixels {
        if !(x > 0.0 && x < 1.0 - 3.0 * texel && z.abs() < 1.0 - 3.0 * texel) {
            continue;
        }
        assert!(!lit);
        if x > 3.0 * texel {
            assert_eq!(v, 0.0, "at ({x}, {z}) the region sees the lower slab alone");
            continue;
        }
        assert!(v <= bound * 1.0001, "at ({x}, {z}): {v} above Chebyshev's bound {bound}");
        if v > 0.01 {
            bled += 1;
        }
    }
    assert!(bled > 20, "light bleeding next to the upper edge: {bled} pixels");
    // A bleeding reduction above the bound removes it everywhere.
    let reduced = ground(
        &scene,
        serde_json::json!({ "technique": "vsm", "min_variance": 0, "bleeding_reduction": 0.25 }),
    );
    for (x, z, v, lit) in reduced {
        if !lit && x > 0.0 && x < 1.0 - 3.0 * texel && z.abs() < 1.0 - 3.0 * texel {
            assert_eq!(v, 0.0, "at ({x}, {z})");
        }
    }
}

/// A receiver just under one occluder and far under a second one: the mixture of the two
/// occluders' depths in VSM's filter then lets through more than half the light (Chebyshev's
/// bound a(1 − a)Δ²/(a(1 − a)Δ² + (Δ_r + aΔ)²) reaches 0.65 with Δ = 5.6, Δ_r = 0.4), so the
/// ground next to the upper slab's edge is false lit. Where the slabs overlap in the sun's view
/// (x < 0) every shadowed ground pixel is marked overlapped, where only the lower one shades
/// (x > 0) none is; the attribution calls the false lit pixels light bleeding, and without the
/// overlap map calls them leaks.
#[test]
fn false_lit_next_to_overlapping_occluders_is_light_bleeding() {
    use shadowtruth::metrics::{LightUv, attribute};
    use shadowtruth::trace::trace_shadow_overlap;
    let scene = scene_from_json(&serde_json::json!({
        "format": "shadowtruth/scene/v1", "name": "far_slabs",
        "objects": [
            { "name": "ground", "shape": { "type": "plane", "size": [4, 4] } },
            { "name": "lower", "shape": { "type": "box", "size": [2, 0.02, 2] }, "closed": true,
              "transform": { "translate": [0, 0.4, 0] } },
            { "name": "upper", "shape": { "type": "box", "size": [1, 0.02, 2] }, "closed": true,
              "transform": { "translate": [-0.5, 6, 0] } }
        ],
        "cameras": [{ "name": "under", "position": [0.2, 0.3, 4], "look_at": [0, 0.05, 0],
                      "fov_y_deg": 50, "width": 384, "height": 256 }],
        "lights": [{ "name": "sun", "type": "directional", "direction": [0, -1, 0] }]
    }));
    let (g, r) = trace_first(&scene);
    let bvh = shadowtruth::SceneBvh::build(&scene);
    let overlap = trace_shadow_overlap(&scene, &bvh, &g, &scene.lights[0], |i| r.lit[i] == 0);
    let texel = texel_world(&scene);
    let (mut both, mut one) = (0, 0);
    for &i in &g.evaluated {
        let (i, p) = (i as usize, g.position[i as usize]);
        if p.y > 0.1 || r.lit[i] != 0 || p.z.abs() > 1.0 - texel {
            continue;
        }
        if p.x < -texel && p.x > -1.0 + texel {
            assert!(overlap.at(i), "({}, {}) lies under both slabs", p.x, p.z);
            both += 1;
        } else if p.x > texel && p.x < 1.0 - texel {
            assert!(!overlap.at(i), "({}, {}) lies under the lower slab alone", p.x, p.z);
            one += 1;
        }
    }
    assert!(both > 100 && one > 100, "{both} under both, {one} under one");

    let vsm = spec(serde_json::json!({ "technique": "vsm", "min_variance": 0 }));
    let v = shade_technique(&scene, &g, &vsm, RESOLUTION, DepthFormat::F32);
    let view = LightView::new(&scene.lights[0], scene.bounds(), RESOLUTION);
    let uv = LightUv::new(&g, &view);
    let with = attribute(&scene, &g, &r, &v, &uv, Some(&overlap));
    let without = attribute(&scene, &g, &r, &v, &uv, None);
    println!("with the overlap map: {with:?}; without: {without:?}");
    assert!(with.light_bleeding > 10 && with.light_bleeding > 4 * with.leak, "{with:?}");
    assert_eq!(without.light_bleeding, 0);
    assert_eq!(with.leak + with.light_bleeding, without.leak);
    assert_eq!((with.aliasing, with.acne), (without.aliasing, without.acne));
    // Every false lit ground pixel under the lower slab alone (away from its own outline) lies
    // next to the upper's edge.
    for (&i, &vi) in g.evaluated.iter().zip(&v) {
        let p = g.position[i as usize];
        let inside = p.x > 0.0 && p.x < 1.0 - 2.0 * texel && p.z.abs() < 1.0 - 2.0 * texel;
        if p.y < 0.1 && r.lit[i as usize] == 0 && vi >= 0.5 && inside {
            assert!(
                p.x < 4.0 * texel,
                "false lit at ({}, {}), {} texels from the edge",
                p.x,
                p.z,
                p.x / texel
            );
        }
    }
}

#[test]
fn the_level_of_detail_is_the_camera_pixel_over_the_map_texel() {
    // The floor y = 0 seen from 20 up through 90° over 128 rows: a pixel is 2·20/128 = 0.3125
    // wide everywhere on it. A spot 10 up with a 90° cone over 256 texels: a texel is
    // 2·10/256 = 0.078125 wide on it. Both project the floor linearly, so every pixel's
    // footprint is 4 texels: λ = 2.
    use shadowtruth::raster::DepthLayer;
    use shadowtruth::technique::{Layers, Sample, ShadeContext, footprint_lod};
    let scene = scene_from_json(&serde_json::json!({
        "format": "shadowtruth/scene/v1", "name": "floor",
        "objects": [{ "name": "floor", "shape": { "type": "plane", "size": [8, 8] } }],
        "cameras": [{ "name": "down", "position": [0.3, 20, 0.1], "look_at": [0.3, 0, 0.1], "up": [0, 0, -1],
                      "fov_y_deg": 90, "width": 128, "height": 128 }],
        "lights": [{ "name": "lamp", "type": "spot", "position": [0, 10, 0], "direction": [0, -1, 0],
                     "cone_deg": 90, "near": 1, "far": 20 }]
    }));
    let (g, _) = trace_first(&scene);
    let view = LightView::new(&scene.lights[0], scene.bounds(), 256);
    let map = DepthLayer::new_empty(256);
    let ctx = ShadeContext::new(&scene, g.footprint, &view, Layers::Nearest(&map));
    assert!(g.evaluated.len() > 500, "{}", g.evaluated.len());
    for &i in &g.evaluated {
        let i = i as usize;
        let s = Sample { position: g.position[i], normal: g.normal[i], triangle: g.triangle[i] };
        let lod = footprint_lod(&s, &ctx, view.project(s.position).unwrap(), 256);
        assert!((lod - 2.0).abs() < 1e-4, "pixel {i}: λ = {lod}");
    }
}
