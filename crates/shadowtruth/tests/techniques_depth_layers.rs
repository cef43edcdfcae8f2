//! The depth-layer family and the adaptive bias against the reference.

mod common;

use common::{bundled, scene_from_json, score_technique, trace_first};
use glam::Vec3;
use serde_json::json;
use shadowtruth::raster::{DepthFormat, LightView};
use shadowtruth::technique::{
    AdaptiveParams, DualParams, EpsilonSpec, MidpointParams, NoneParams, SecondDepthParams, TechniqueSpec,
};
use std::collections::HashMap;

fn visibility(name: &str, spec: &TechniqueSpec, resolution: u32) -> Vec<f32> {
    let scene = bundled(name);
    let (g, r) = trace_first(&scene);
    score_technique(&scene, &g, &r, spec, resolution, DepthFormat::F32).1
}

#[test]
fn dual_with_infinite_offset_is_midpoint_and_with_zero_offset_is_none() {
    for name in ["l_shape", "spot"] {
        for resolution in [128, 1024] {
            for cull_back_faces in [false, true] {
                let dual_inf = visibility(
                    name,
                    &TechniqueSpec::Dual(DualParams { z_offset: 1.0, cull_back_faces }),
                    resolution,
                );
                let midpoint = visibility(
                    name,
                    &TechniqueSpec::Midpoint(MidpointParams { cull_back_faces }),
                    resolution,
                );
                assert!(dual_inf == midpoint, "{name} {resolution}: dual(∞) differs from midpoint");
            }
            let dual_zero = visibility(
                name,
                &TechniqueSpec::Dual(DualParams { z_offset: 0.0, cull_back_faces: false }),
                resolution,
            );
            let none = visibility(name, &TechniqueSpec::None(NoneParams {}), resolution);
            assert!(dual_zero == none, "{name} {resolution}: dual(0) differs from none");
            assert!(none.iter().any(|&v| v < 0.5) && none.iter().any(|&v| v >= 0.5));
        }
    }
}

/// Edges between a triangle facing the light and one facing away: the light-space silhouette.
fn silhouette_edges(scene: &shadowtruth::scene::Scene, to_light: Vec3) -> Vec<(Vec3, Vec3)> {
    let key = |v: Vec3| v.to_array().map(f32::to_bits);
    let mut faces: HashMap<([u32; 3], [u32; 3]), Vec<bool>> = HashMap::new();
    for t in &scene.flat_triangles {
        let lit = (t[1] - t[0]).cross(t[2] - t[0]).dot(to_light) > 0.0;
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let e = if key(a) < key(b) { (key(a), key(b)) } else { (key(b), key(a)) };
            faces.entry(e).or_default().push(lit);
        }
    }
    let from_bits = |k: [u32; 3]| Vec3::from_array(k.map(f32::from_bits));
    faces
        .into_iter()
        .filter(|(_, f)| f.len() == 2 && f[0] != f[1])
        .map(|((a, b), _)| (from_bits(a), from_bits(b)))
        .collect()
}

/// Distance from `p` to segment ab, measured across the light (in the plane normal to it).
fn distance_across_light(p: Vec3, (a, b): (Vec3, Vec3), to_light: Vec3) -> f32 {
    let flat = |x: Vec3| x - to_light * x.dot(to_light);
    let (p, a, b) = (flat(p), flat(a), flat(b));
    let t = ((p - a).dot(b - a) / (b - a).length_squared().max(f32::MIN_POSITIVE)).clamp(0.0, 1.0);
    (a + (b - a) * t - p).length()
}

#[test]
fn second_depth_has_no_false_shadow_on_a_lit_closed_convex_object() {
    // Wang & Molnar's second depth holds the back faces: a lit face of a convex solid is never
    // behind them, except within a texel of the silhouette seen from the light, where the back
    // faces meet the front ones (z2 → z1) and the texel centre can read a back face nearer to
    // the light than the receiver. The test allows false shadow there and nowhere else.
    for shape in [
        json!({ "type": "sphere", "radius": 1.0, "segments": 48, "rings": 24 }),
        json!({ "type": "box", "size": [1.5, 1.0, 2.0] }),
    ] {
        for dir in [[0.3, -1.0, 0.2], [-1.0, -0.2, 0.4], [0.0, -1.0, 0.0]] {
            let scene = scene_from_json(&json!({
                "format": "shadowtruth/scene/v1", "name": "convex",
                "objects": [{ "name": "solid", "shape": shape, "closed": true, "transform": { "rotate_deg": [15, 30, 0] } }],
                "cameras": [{ "name": "c", "position": [2.5, 2.0, 3.0], "look_at": [0, 0, 0], "fov_y_deg": 50, "width": 320, "height": 240 }],
                "lights": [{ "name": "l", "type": "directional", "direction": dir }]
            }));
            let to_light = -Vec3::from_array(dir.map(|x| x as f32)).normalize();
            let silhouette = silhouette_edges(&scene, to_light);
            let (g, r) = trace_first(&scene);
            for resolution in [64, 512, 2048] {
                let spec = TechniqueSpec::SecondDepth(SecondDepthParams { bias_depth: 0.0 });
                let (c, v) = score_technique(&scene, &g, &r, &spec, resolution, DepthFormat::F32);
                assert!(c.evaluated > 1000);
                let view = LightView::new(&scene.lights[0], scene.bounds(), resolution);
                let mut at_silhouette = 0;
                for (k, &i) in g.evaluated.iter().enumerate() {
                    if v[k] >= 0.5 {
                        continue;
                    }
                    let p = g.position[i as usize];
                    let texel = view.texel_world_size(p);
                    let near =
                        silhouette.iter().any(|&e| distance_across_light(p, e, to_light) <= 1.5 * texel);
                    assert!(
                        near,
                        "{shape} from {dir:?} at {resolution}: false shadow at {p}, away from the silhouette"
                    );
                    at_silhouette += 1;
                }
                if at_silhouette > 0 {
                    eprintln!(
                        "{shape} from {dir:?} at {resolution}²: {at_silhouette} false-shadow pixels at the silhouette"
                    );
                }
                // The plain test on the same pixels has acne: the clean faces are the technique's.
                let (plain, _) = score_technique(
                    &scene,
                    &g,
                    &r,
                    &TechniqueSpec::None(NoneParams {}),
                    resolution,
                    DepthFormat::F32,
                );
                assert!(
                    plain.false_shadow > 10 * c.false_shadow.max(1),
                    "{shape} from {dir:?} at {resolution}: {plain:?} vs {c:?}"
                );
            }
        }
    }
}

#[test]
fn adaptive_bias_has_no_acne_on_planes_at_30_60_80_degrees() {
    // The default plan's resolutions.
    let plan: serde_json::Value =
        serde_json::from_slice(&std::fs::read(common::repo().join("plans/default.json")).unwrap()).unwrap();
    let resolutions: Vec<u32> =
        plan["resolutions"].as_array().unwrap().iter().map(|r| r.as_u64().unwrap() as u32).collect();
    let mut grazing = Vec::new();
    for theta in [30.0, 60.0, 80.0, 89.0] {
        let scene = scene_from_json(&json!({
            "format": "shadowtruth/scene/v1", "name": "tilted",
            "objects": [{ "name": "plane", "shape": { "type": "plane", "size": [6, 6], "subdivisions": 3 },
                          "transform": { "rotate_deg": [theta, 0, 0] } }],
            "cameras": [{ "name": "c", "position": [0.5, 6, 6], "look_at": [0, 0, 0], "fov_y_deg": 50, "width": 320, "height": 240 }],
            "lights": [{ "name": "sun", "type": "directional", "direction": [0, -1, 0] }]
        }));
        let (g, r) = trace_first(&scene);
        assert!(g.evaluated.len() > 1000, "θ = {theta}: the plane must be seen lit");
        for &resolution in &resolutions {
            for epsilon in [EpsilonSpec::Original, EpsilonSpec::Ehm] {
                let spec = TechniqueSpec::Adaptive(AdaptiveParams { k: 1e-4, epsilon });
                let (c, _) = score_technique(&scene, &g, &r, &spec, resolution, DepthFormat::F32);
                if theta <= 80.0 {
                    assert_eq!(c.false_shadow, 0, "θ = {theta}°, {resolution}², {epsilon:?}: {c:?}");
                } else {
                    grazing.push((resolution, epsilon, c.false_shadow, c.evaluated));
                }
            }
        }
    }
    // Past the claim: at 89° the report shows what happens; printed for the record.
    for (resolution, epsilon, false_shadow, evaluated) in grazing {
        eprintln!("adaptive at 89°: {resolution}² {epsilon:?}: false shadow {false_shadow} of {evaluated}");
    }
}

#[test]
fn l_shape_depth_layer_family_as_counts() {
    // Weiskopf & Ertl, Figure 5: the L-shape under a light from above, heavily undersampled map.
    let scene = bundled("l_shape");
    let (g, r) = trace_first(&scene);
    let family = [
        ("second_depth", TechniqueSpec::SecondDepth(SecondDepthParams { bias_depth: 0.0 })),
        ("midpoint", TechniqueSpec::Midpoint(MidpointParams { cull_back_faces: false })),
        ("midpoint+cull", TechniqueSpec::Midpoint(MidpointParams { cull_back_faces: true })),
        ("dual", TechniqueSpec::Dual(DualParams { z_offset: 0.005, cull_back_faces: false })),
        ("dual+cull", TechniqueSpec::Dual(DualParams { z_offset: 0.005, cull_back_faces: true })),
    ];
    for resolution in [64, 128] {
        let counts: Vec<_> = family
            .iter()
            .map(|(name, spec)| {
                (*name, score_technique(&scene, &g, &r, spec, resolution, DepthFormat::F32).0)
            })
            .collect();
        for (name, c) in &counts {
            eprintln!(
                "{resolution}² {name:14} false shadow {:6}  false lit {:6}",
                c.false_shadow, c.false_lit
            );
        }
        let errors = |n: &str| {
            counts.iter().find(|(m, _)| *m == n).map(|(_, c)| c.false_shadow + c.false_lit).unwrap()
        };
        let midpoint = counts[1].1;
        // Midpoint without culling: both kinds of error (self-unshadowing and self-shadowing).
        assert!(midpoint.false_lit > 0 && midpoint.false_shadow > 0, "{resolution}: {midpoint:?}");
        // Dual with back-face culling has the fewest errors of the family (ties allowed).
        for (name, _) in &family {
            assert!(errors("dual+cull") <= errors(name), "{resolution}: dual+cull vs {name}");
        }
    }
}

/// Layers rasterized into the memory of earlier ones (of another resolution, kind, culling,
/// offset or format, as the run reuses them from group to group) are the bits of fresh ones.
#[test]
fn layers_built_into_a_spare_are_the_bits_of_fresh_ones() {
    use shadowtruth::raster::Rasterizer;
    use shadowtruth::technique::BuiltLayers;
    let scene = bundled("rocks");
    let needs_of = |json: serde_json::Value| {
        let spec: TechniqueSpec = serde_json::from_value(json).unwrap();
        spec.build().expect("a shaded technique").layer_needs()
    };
    let needs = [
        needs_of(json!({ "technique": "constant", "bias_depth": 0.001 })),
        needs_of(json!({ "technique": "slope_scaled", "factor": 2.0, "units": 4.0 })),
        needs_of(json!({ "technique": "midpoint", "cull_back_faces": true })),
        needs_of(json!({ "technique": "second_depth" })),
        needs_of(json!({ "technique": "vsm", "min_variance": 0 })),
    ];
    let formats = [DepthFormat::F32, DepthFormat::Unorm16];
    let mut spare: Option<BuiltLayers> = None;
    let mut kinds = std::collections::HashSet::new();
    for resolution in [96, 64, 128] {
        let view = LightView::new(&scene.lights[0], scene.bounds(), resolution);
        let rasterizer = Rasterizer::new(&scene, &view);
        for (i, needs) in needs.iter().enumerate() {
            let format = formats[i % formats.len()];
            let fresh = BuiltLayers::rasterize(&rasterizer, format, needs);
            let reused = BuiltLayers::rasterize_reusing(&rasterizer, format, needs, spare.take());
            assert_eq!(reused, fresh, "{resolution}² {format:?} {needs:?}");
            kinds.insert(std::mem::discriminant(&reused));
            spare = Some(reused);
        }
    }
    assert_eq!(kinds.len(), 3, "nearest, two nearest and moments each reused");
}
