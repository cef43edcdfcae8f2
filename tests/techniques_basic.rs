//! The single-depth techniques against the reference: acne without bias, leaks with too much.
//! Every count comes from comparing with the ray-traced reference.

mod common;

use common::{scene_from_json, trace_first};
use serde_json::json;
use shadowtruth::metrics::Counts;
use shadowtruth::raster::DepthFormat;
use shadowtruth::scene::Scene;
use shadowtruth::technique::{CullSpec, TechniqueSpec};
use shadowtruth::trace::{GBuffer, HardReference};

fn score(
    scene: &Scene,
    g: &GBuffer,
    r: &HardReference,
    spec: &TechniqueSpec,
    resolution: u32,
) -> (Counts, Vec<f32>) {
    common::score_technique(scene, g, r, spec, resolution, DepthFormat::F32)
}

fn tilted_plane() -> Scene {
    scene_from_json(&json!({
        "format": "shadowtruth/scene/v1", "name": "tilted",
        "objects": [{ "name": "plane", "shape": { "type": "plane", "size": [6, 6] },
                      "transform": { "rotate_deg": [45, 0, 0] } }],
        "cameras": [{ "name": "c", "position": [0.5, 6, 6], "look_at": [0, 0, 0], "fov_y_deg": 50, "width": 400, "height": 300 }],
        "lights": [{ "name": "sun", "type": "directional", "direction": [0, -1, 0] }]
    }))
}

#[test]
fn no_bias_has_acne_on_a_plane_at_45_degrees() {
    let scene = tilted_plane();
    let (g, r) = trace_first(&scene);
    assert_eq!(
        g.evaluated.iter().filter(|&&i| r.lit[i as usize] == 0).count(),
        0,
        "the lone plane is lit in truth"
    );
    for resolution in [256, 1024] {
        let (none, _) = score(&scene, &g, &r, &TechniqueSpec::None, resolution);
        assert!(none.false_shadow > 0, "{resolution}: a plain depth test at 45° must show acne");
        assert_eq!(none.false_lit, 0, "nothing is shadowed in truth");
        // A slope-scaled bias removes it: the count above is the technique's, not the scene's.
        let slope = TechniqueSpec::SlopeScaled { factor: 1.5, units: 2.0, cull: CullSpec::None };
        let (biased, _) = score(&scene, &g, &r, &slope, resolution);
        assert!(biased.false_shadow * 100 < none.false_shadow, "{resolution}: {biased:?} vs {none:?}");
    }
}

#[test]
fn a_large_constant_bias_leaks_light_at_the_contact_shadow() {
    let scene = scene_from_json(&json!({
        "format": "shadowtruth/scene/v1", "name": "contact",
        "objects": [
            { "name": "ground", "shape": { "type": "plane", "size": [10, 10] } },
            { "name": "box", "shape": { "type": "box", "size": [1, 1, 1] }, "closed": true,
              "transform": { "rotate_deg": [0, 20, 0], "translate": [0, 0.5, 0] } }
        ],
        "cameras": [{ "name": "c", "position": [-3, 4, 5], "look_at": [0.5, 0, 0], "fov_y_deg": 45, "width": 480, "height": 360 }],
        "lights": [{ "name": "sun", "type": "directional", "direction": [0.6, -1, 0.3] }]
    }));
    let (g, r) = trace_first(&scene);
    let small = TechniqueSpec::Constant { bias_depth: None, bias_world: Some(0.002) };
    let large = TechniqueSpec::Constant { bias_depth: None, bias_world: Some(0.4) };
    let (c_small, _) = score(&scene, &g, &r, &small, 2048);
    let (c_large, v) = score(&scene, &g, &r, &large, 2048);
    assert!(c_large.false_lit > 0, "a 0.4-unit bias must detach the shadow from the box: {c_large:?}");
    assert!(c_large.false_lit > 10 * c_small.false_lit.max(1), "{c_large:?} vs {c_small:?}");
    // The leak is at the contact: every false-lit ground pixel lies within the bias (as a
    // horizontal run along the light) of the box's footprint.
    for (k, &i) in g.evaluated.iter().enumerate() {
        let i = i as usize;
        if r.lit[i] == 0 && v[k] >= 0.5 {
            let p = g.position[i];
            assert!(p.y.abs() < 1e-6 || g.object[i] == 1, "leak away from the ground and box at {p}");
            assert!(p.x.abs() < 1.5 && p.z.abs() < 1.5, "false-lit pixel at {p} is far from the contact");
        }
    }
}
