//! glTF point lights (KHR_lights_punctual, docs/gltf.md): a point light imports at its node's
//! world position with its `range` as far and the node's extras as near, sphere radius and cube
//! guard band; without a range, far reaches past the farthest corner of the placed meshes'
//! bounds, as for a spot light; bad extras name their own JSON path.

use glam::Vec3;
use serde_json::{Value, json};
use shadowtruth::scene::{LightKind, SceneError, load_scene};
use std::path::Path;

/// The triangle (0,0,0), (1,0,0), (0,0,−1) as f32 VEC3s, 36 bytes.
fn triangle_bytes() -> Vec<u8> {
    [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -1.0].iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// A glTF whose triangle is placed at x = 0 and x = 10, with `light` at node 4: translated by
/// (2, 1, −3) under node 3, which is translated by (0, 4, 0) and turned 90° about y (a point
/// light's direction does not matter; its position does), with the node `extras`.
fn gltf(light: Value, extras: Value) -> Value {
    json!({
        "asset": { "version": "2.0" },
        "buffers": [{ "uri": "triangle.bin", "byteLength": 36 }],
        "bufferViews": [{ "buffer": 0, "byteLength": 36 }],
        "accessors": [{ "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                        "min": [0, 0, -1], "max": [1, 0, 0] }],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 } }] }],
        "cameras": [{ "type": "perspective", "perspective": { "yfov": 0.8, "znear": 0.1, "aspectRatio": 1.5 },
                       "extras": { "width": 48, "height": 32 } }],
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": { "KHR_lights_punctual": { "lights": [light] } },
        "nodes": [
            { "mesh": 0 }, { "mesh": 0, "translation": [10, 0, 0] }, { "camera": 0, "translation": [0, 1, 5] },
            { "translation": [0, 4, 0], "rotation": [0, std::f64::consts::FRAC_1_SQRT_2, 0, std::f64::consts::FRAC_1_SQRT_2],
              "children": [4] },
            { "translation": [2, 1, -3], "extras": extras, "extensions": { "KHR_lights_punctual": { "light": 0 } } }
        ],
        "scenes": [{ "nodes": [0, 1, 2, 3] }],
        "scene": 0
    })
}

fn load(dir: &Path, doc: &Value) -> Result<shadowtruth::Scene, SceneError> {
    std::fs::write(dir.join("triangle.bin"), triangle_bytes()).unwrap();
    let path = dir.join("point.gltf");
    std::fs::write(&path, doc.to_string()).unwrap();
    load_scene(&path)
}

/// The light's world position: node 3 turns node 4's offset (2, 1, −3) by 90° about y, x ↦ −z
/// and z ↦ x, to (−3, 1, −2), then adds (0, 4, 0).
const POSITION: Vec3 = Vec3::new(-3.0, 5.0, -2.0);

#[test]
fn a_point_light_imports_its_range_and_extras() {
    let dir = tempfile::tempdir().unwrap();
    let doc = gltf(
        json!({ "type": "point", "range": 15, "name": "bulb" }),
        json!({ "near": 0.05, "radius": 0.2, "guard_texels": 3 }),
    );
    let scene = load(dir.path(), &doc).expect("a point light");
    assert_eq!(scene.lights.len(), 1);
    let light = &scene.lights[0];
    assert!(light.is_point());
    let LightKind::Point { position, near, far, radius, .. } = light.kind else { panic!("{:?}", light.kind) };
    assert!((position - POSITION).abs().max_element() < 1e-6, "{position}");
    assert_eq!((near, far, radius), (0.05, 15.0, Some(0.2)));
    let cube = shadowtruth::cube_map(light, 32).unwrap();
    assert_eq!(cube.guard_texels, 3);
    assert_eq!(cube.faces[0].resolution, 32 + 2 * 3);
    assert_eq!((light.path.as_ref(), light.cascades.as_ref()), (None, None));
}

/// Without `range` (and no extras) far is 1.01 × the distance from the light to the farthest
/// corner of the placed meshes' box (x 0..11, y 0, z −1..0): from (−3, 5, −2) that is (11, 0, 0),
/// √(14² + 5² + 2²) = √225 = 15 away; near is far/1000, the guard band the default 8 texels, and
/// the light has no sphere. (The node's f32 quaternion turns by 90° to within 1e-7, so the
/// position, and far with it, may differ from the exact values by that much.)
#[test]
fn a_point_light_without_range_reaches_past_the_scene_bounds() {
    let dir = tempfile::tempdir().unwrap();
    let scene = load(dir.path(), &gltf(json!({ "type": "point" }), json!({}))).expect("a point light");
    let light = &scene.lights[0];
    let LightKind::Point { position, near, far, radius, .. } = light.kind else { panic!("{:?}", light.kind) };
    assert!((position - POSITION).abs().max_element() < 1e-6, "{position}");
    assert!((far as f64 - 15.15).abs() < 2e-6, "{far}");
    assert!((near as f64 - 0.01515).abs() < 2e-9, "{near}");
    assert_eq!(radius, None);
    assert_eq!(shadowtruth::cube_map(light, 16).unwrap().guard_texels, 8);
}

#[test]
fn bad_point_light_values_name_their_json_paths() {
    let dir = tempfile::tempdir().unwrap();
    for (light, extras, field) in [
        (
            json!({ "type": "point", "range": 10 }),
            json!({ "guard_texels": 65 }),
            "nodes[4].extras.guard_texels",
        ),
        (
            json!({ "type": "point", "range": 10 }),
            json!({ "guard_texels": -1 }),
            "nodes[4].extras.guard_texels",
        ),
        (json!({ "type": "point", "range": 10 }), json!({ "radius": 0 }), "nodes[4].extras.radius"),
        (
            json!({ "type": "point", "range": -2 }),
            json!({}),
            "extensions.KHR_lights_punctual.lights[0].range",
        ),
        (
            json!({ "type": "point", "range": 10 }),
            json!({ "near": 12 }),
            "extensions.KHR_lights_punctual.lights[0].range",
        ),
        (json!({ "type": "point" }), json!({ "near": 1, "far": 0.5 }), "nodes[4].extras.far"),
    ] {
        let found = load(dir.path(), &gltf(light, extras.clone())).expect_err(field).problems;
        let paths: Vec<&str> = found.iter().map(|p| p.path.as_str()).collect();
        assert_eq!(paths, [field], "{extras}: {found:?}");
        assert!(found[0].file.ends_with("point.gltf"), "{:?}", found[0].file);
    }
}
