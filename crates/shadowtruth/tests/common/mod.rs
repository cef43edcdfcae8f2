//! Helpers shared by the integration tests.
#![allow(dead_code)]

use shadowtruth::scene::{Scene, load_scene, load_scene_str};
use shadowtruth::trace::{GBuffer, HardReference, SceneBvh, trace_scored_view};
use std::path::{Path, PathBuf};

/// The workspace's root, where the bundled scenes, plans and gates are.
pub fn repo() -> PathBuf {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    crate_dir.parent().and_then(Path::parent).expect("crates/<name>/ inside the workspace").to_path_buf()
}

pub fn bundled(name: &str) -> Scene {
    load_scene(&repo().join("scenes").join(format!("{name}.json"))).expect("bundled scene loads")
}

pub fn scene_from_json(json: &serde_json::Value) -> Scene {
    let text = serde_json::to_string(json).unwrap();
    load_scene_str(&text, Path::new("test.json"), &repo().join("scenes")).unwrap_or_else(|e| panic!("{e}"))
}

/// G-buffer and hard reference of the scene's first camera and light, as every score takes them:
/// the pixels the reference cannot decide left out of the G-buffer (`trace_scored_view`).
pub fn trace_first(scene: &Scene) -> (GBuffer, HardReference) {
    let bvh = SceneBvh::build(scene);
    trace_scored_view(scene, &bvh, &scene.cameras[0], &scene.lights[0])
}

/// Pixels whose 3×3 neighbourhood in `codes` holds more than one value (boundaries of shadows,
/// silhouettes and light edges).
pub fn near_boundary(width: u32, height: u32, codes: &[u8]) -> Vec<bool> {
    let (w, h) = (width as i64, height as i64);
    let mut out = vec![false; codes.len()];
    for y in 0..h {
        for x in 0..w {
            let c = codes[(y * w + x) as usize];
            'n: for dy in -1..=1 {
                for dx in -1..=1 {
                    let (nx, ny) = (x + dx, y + dy);
                    if nx >= 0 && ny >= 0 && nx < w && ny < h && codes[(ny * w + nx) as usize] != c {
                        out[(y * w + x) as usize] = true;
                        break 'n;
                    }
                }
            }
        }
    }
    out
}

/// Visibility of every evaluated pixel (in `g.evaluated` order) under `spec`, on the map of the
/// scene's first light at `resolution` in `format`.
pub fn shade_technique(
    scene: &Scene,
    g: &GBuffer,
    spec: &shadowtruth::technique::TechniqueSpec,
    resolution: u32,
    format: shadowtruth::raster::DepthFormat,
) -> Vec<f32> {
    use shadowtruth::technique::{ShadeContext, ShadeOrder, shade_evaluated};
    let technique = spec.build().expect("a shaded technique");
    let view = shadowtruth::raster::LightView::new(&scene.lights[0], scene.bounds(), resolution);
    let layers = shadowtruth::technique::BuiltLayers::build(scene, &view, format, &technique.layer_needs());
    let ctx = ShadeContext::new(scene, g.footprint, &view, layers.as_layers());
    shade_evaluated(technique.as_ref(), &ShadeOrder::new(g, &view), &ctx)
}

/// Runs one technique on a traced G-buffer and scores it: (counts, visibility per evaluated pixel).
pub fn score_technique(
    scene: &Scene,
    g: &GBuffer,
    r: &HardReference,
    spec: &shadowtruth::technique::TechniqueSpec,
    resolution: u32,
    format: shadowtruth::raster::DepthFormat,
) -> (shadowtruth::metrics::Counts, Vec<f32>) {
    let v = shade_technique(scene, g, spec, resolution, format);
    (shadowtruth::metrics::score_hard(g, r, &v), v)
}

/// A lone 6×6 plane at 45° to a light from straight above.
pub fn tilted_plane() -> Scene {
    scene_from_json(&serde_json::json!({
        "format": "shadowtruth/scene/v1", "name": "tilted",
        "objects": [{ "name": "plane", "shape": { "type": "plane", "size": [6, 6] },
                      "transform": { "rotate_deg": [45, 0, 0] } }],
        "cameras": [{ "name": "c", "position": [0.5, 6, 6], "look_at": [0, 0, 0], "fov_y_deg": 50, "width": 400, "height": 300 }],
        "lights": [{ "name": "sun", "type": "directional", "direction": [0, -1, 0] }]
    }))
}

/// A unit box resting on a plane: its contact shadow.
pub fn contact_scene() -> Scene {
    scene_from_json(&serde_json::json!({
        "format": "shadowtruth/scene/v1", "name": "contact",
        "objects": [
            { "name": "ground", "shape": { "type": "plane", "size": [10, 10] } },
            { "name": "box", "shape": { "type": "box", "size": [1, 1, 1] }, "closed": true,
              "transform": { "rotate_deg": [0, 20, 0], "translate": [0, 0.5, 0] } }
        ],
        "cameras": [{ "name": "c", "position": [-3, 4, 5], "look_at": [0.5, 0, 0], "fov_y_deg": 45, "width": 480, "height": 360 }],
        "lights": [{ "name": "sun", "type": "directional", "direction": [0.6, -1, 0.3] }]
    }))
}

/// The scene that tests/view_export.rs exports and tests/gltf_import.rs reloads: open and
/// closed objects, two cameras (one with a tilted up vector and a portrait image) and both kinds
/// of light with their sizes.
pub const EXPORT_TEST_SCENE: &str = r#"{
  "format": "shadowtruth/scene/v1",
  "name": "export_test",
  "objects": [
    { "name": "ground", "shape": { "type": "plane", "size": [10, 10] } },
    { "name": "box", "shape": { "type": "box", "size": [1, 1.5, 1] }, "closed": true,
      "transform": { "rotate_deg": [0, 30, 0], "translate": [0.5, 0.75, -0.3] } },
    { "name": "ball", "shape": { "type": "sphere", "radius": 0.6, "segments": 24, "rings": 12 }, "closed": true,
      "transform": { "translate": [-1.3, 0.6, 0.9] } }
  ],
  "cameras": [
    { "name": "wide", "position": [-4, 3, 5], "look_at": [0, 0.5, 0], "fov_y_deg": 45, "width": 96, "height": 54 },
    { "name": "tilted", "position": [3.5, 4, 3], "look_at": [-0.5, 0.2, 0], "up": [0.3, 1, 0.1],
      "fov_y_deg": 60, "width": 40, "height": 64 }
  ],
  "lights": [
    { "name": "sun", "type": "directional", "direction": [-0.3, -1, -0.45], "angular_diameter_deg": 0.5 },
    { "name": "lamp", "type": "spot", "position": [2.5, 5, 1.5], "direction": [-0.4, -1, -0.2],
      "cone_deg": 60, "near": 0.5, "far": 20, "radius": 0.1 },
    { "name": "bulb", "type": "point", "position": [-0.5, 3, 1], "near": 0.1, "far": 15, "radius": 0.05,
      "cube_map": { "guard_texels": 4 } },
    { "name": "bulb_paraboloid", "type": "point", "position": [1, 2.5, -1.5], "near": 0.2, "far": 12,
      "shadow_map": "dual_paraboloid" }
  ]
}"#;

/// Writes to `path` the scene `name`: a plane and a box under `lights` directional lights of 3°
/// (all different), seen by one `width`×`height` camera.
pub fn write_plane_box_scene(path: &Path, name: &str, lights: usize, (width, height): (u32, u32)) {
    let lights: Vec<_> = (0..lights)
        .map(|i| {
            let a = i as f64 * 0.5;
            serde_json::json!({ "name": format!("l{i}"), "type": "directional",
                                "direction": [-0.3 * a.cos(), -1, -0.3 * a.sin()], "angular_diameter_deg": 3.0 })
        })
        .collect();
    let scene = serde_json::json!({
        "format": "shadowtruth/scene/v1", "name": name,
        "objects": [
            { "name": "ground", "shape": { "type": "plane", "size": [10, 10] } },
            { "name": "box", "shape": { "type": "box", "size": [1, 1, 1] }, "closed": true,
              "transform": { "rotate_deg": [0, 30, 0], "translate": [0, 1.5, 0] } }
        ],
        "cameras": [{ "name": "c", "position": [-6, 4, 6.5], "look_at": [0, 0.7, 0], "fov_y_deg": 45,
                      "width": width, "height": height }],
        "lights": lights
    });
    std::fs::create_dir_all(path.parent().expect("a file in a folder")).unwrap();
    std::fs::write(path, scene.to_string()).unwrap();
}
