//! glTF 2.0 import (docs/gltf.md): files written by another tool (pygltflib,
//! tests/fixtures/gltf/make_fixtures.py) load to world positions, cameras and lights computed by
//! hand from the fixture's numbers; bad files name the file and the glTF JSON path; the .glb that
//! `view-export` writes reloads as the same triangles and the same hard reference; a scene file
//! may name a glTF as an object.

#[path = "../../shadowtruth/tests/common/mod.rs"]
mod common;

use glam::Vec3;
use shadowtruth::scene::{LightKind, Scene, load_scene, load_scene_str};
use shadowtruth::{GBuffer, SceneBvh, trace_hard_reference};
use std::path::{Path, PathBuf};
use std::process::Command;

fn fixture(name: &str) -> PathBuf {
    common::repo().join("crates/shadowtruth/tests/fixtures/gltf").join(name)
}

fn v(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(x, y, z)
}

/// World triangles of the fixture, by hand. root: p ↦ (10 − 2x, 2y, −2z) (translation 10 x,
/// 180° about y, scale 2). quad_a adds (0, 1, 0) first: (10 − 2x, 2y + 2, −2z). matrix_node is
/// x ↦ y, y ↦ −x, then z + 3: (10 + 2y, 2x, −2z − 6). tri_node adds (0.5, 0, 0) and mirrors z
/// first: (10 + 2y, 2x + 1, 2z − 6), and its winding is flipped.
fn expected_objects() -> Vec<(&'static str, Vec<[Vec3; 3]>)> {
    let quad_a = [v(10.0, 2.0, 0.0), v(8.0, 2.0, 0.0), v(8.0, 2.0, 2.0), v(10.0, 2.0, 2.0)];
    let matrix = [v(10.0, 0.0, -6.0), v(10.0, 2.0, -6.0), v(10.0, 2.0, -4.0), v(10.0, 0.0, -4.0)];
    let quad = |q: [Vec3; 4]| vec![[q[0], q[1], q[2]], [q[0], q[2], q[3]]];
    let (a, b, c) = (v(10.0, 1.0, -6.0), v(10.0, 5.0, -6.0), v(16.0, 1.0, -6.0));
    vec![("quad_a", quad(quad_a)), ("matrix_node", quad(matrix)), ("tri_node", vec![[a, c, b]])]
}

fn bits(triangles: &[[Vec3; 3]]) -> Vec<[u32; 9]> {
    let flat = |t: &[Vec3; 3]| {
        let mut out = [0; 9];
        for (i, c) in t.iter().flat_map(|p| p.to_array()).enumerate() {
            out[i] = c.to_bits();
        }
        out
    };
    triangles.iter().map(flat).collect()
}

fn object_triangles(scene: &Scene, name: &str) -> Vec<[Vec3; 3]> {
    let o = scene.objects.iter().position(|o| o.name == name).unwrap_or_else(|| panic!("no object {name}"));
    scene.object_triangles(o).collect()
}

fn all_triangles(scene: &Scene) -> Vec<[Vec3; 3]> {
    scene.triangles().map(|(_, t)| t).collect()
}

#[test]
fn external_embedded_and_binary_fixtures_give_the_hand_computed_world_triangles() {
    for file in ["hierarchy.gltf", "embedded.gltf", "hierarchy.glb"] {
        let scene = load_scene(&fixture(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert_eq!(scene.name, Path::new(file).file_stem().unwrap().to_str().unwrap());
        let names: Vec<&str> = scene.objects.iter().map(|o| o.name.as_str()).collect();
        assert_eq!(names, ["quad_a", "matrix_node", "tri_node"], "{file}");
        assert!(scene.objects.iter().all(|o| !o.closed), "{file}: glTF meshes are open by default");
        for (name, triangles) in expected_objects() {
            assert_eq!(bits(&object_triangles(&scene, name)), bits(&triangles), "{file}: {name}");
        }
        assert_eq!(scene.dropped_degenerate, 0);
    }
}

#[test]
fn the_fixture_camera_and_lights_look_down_their_nodes_minus_z() {
    let scene = load_scene(&fixture("hierarchy.glb")).unwrap();
    assert_eq!(scene.cameras.len(), 1);
    let camera = &scene.cameras[0];
    assert_eq!(camera.name, "cam");
    // Translation (20, 2, 0); 90° about y turns −z into −x.
    assert_eq!(camera.position, v(20.0, 2.0, 0.0));
    let forward = (camera.look_at - camera.position).normalize();
    assert!((forward - v(-1.0, 0.0, 0.0)).abs().max_element() < 1e-6, "{forward}");
    assert!((camera.up - Vec3::Y).abs().max_element() < 1e-6, "{}", camera.up);
    assert!((camera.fov_y_deg - 0.8f32.to_degrees()).abs() < 1e-4, "{}", camera.fov_y_deg);
    // No extras: height 720, width from aspectRatio 1.5.
    assert_eq!((camera.width, camera.height), (1080, 720));

    let names: Vec<&str> = scene.lights.iter().map(|l| l.name.as_str()).collect();
    assert_eq!(names, ["sun", "lamp"]);
    // −90° about x turns −z into −y.
    let LightKind::Directional { direction, angular_diameter_deg } = scene.lights[0].kind else {
        panic!("sun is not directional")
    };
    assert!((direction - v(0.0, -1.0, 0.0)).abs().max_element() < 1e-6, "{direction}");
    assert_eq!(angular_diameter_deg, None);
    let LightKind::Spot { position, direction, cone_deg, near, far, radius } = scene.lights[1].kind else {
        panic!("lamp is not a spot light")
    };
    assert_eq!(position, v(10.0, 6.0, 0.0));
    assert!((direction - v(0.0, -1.0, 0.0)).abs().max_element() < 1e-6, "{direction}");
    // outerConeAngle π/6 is half the cone; far is the range, near far/1000.
    assert!((cone_deg - 60.0).abs() < 1e-4, "{cone_deg}");
    assert_eq!(far, 20.0);
    assert!((near - 0.02).abs() < 1e-9, "{near}");
    assert_eq!(radius, None);
}

/// A spot light without `range` reaches 1.01 × the distance to the farthest corner of the box
/// around every placement of every mesh, by hand: the triangle (0,0,0), (1,0,0), (0,0,−1) placed
/// at x = 0 and x = 10 spans x 0..11, y 0, z −1..0; from the light at (0, 5, 0) the farthest
/// corner is (11, 0, −1), √147 away. Bad aspect ratios and ranges name their own fields.
#[test]
fn spot_defaults_come_from_the_placed_bounds_and_bad_views_name_their_fields() {
    use std::f64::consts::FRAC_1_SQRT_2;
    let positions: Vec<u8> =
        [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -1.0].iter().flat_map(|x| x.to_le_bytes()).collect();
    let uri = format!("data:application/octet-stream;base64,{}", base64_of(&positions));
    let gltf = |aspect: f64, range: Option<f64>| {
        let mut light = serde_json::json!({ "type": "spot", "spot": { "outerConeAngle": 0.5 } });
        if let Some(range) = range {
            light["range"] = range.into();
        }
        serde_json::json!({
            "asset": { "version": "2.0" },
            "buffers": [{ "uri": uri, "byteLength": 36 }],
            "bufferViews": [{ "buffer": 0, "byteLength": 36 }],
            "accessors": [{ "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                            "min": [0, 0, -1], "max": [1, 0, 0] }],
            "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 } }] }],
            "cameras": [{ "type": "perspective", "perspective": { "yfov": 0.8, "znear": 0.1, "aspectRatio": aspect } }],
            "extensionsUsed": ["KHR_lights_punctual"],
            "extensions": { "KHR_lights_punctual": { "lights": [light] } },
            "nodes": [
                { "mesh": 0 }, { "mesh": 0, "translation": [10, 0, 0] }, { "camera": 0, "translation": [0, 1, 5] },
                { "translation": [0, 5, 0], "rotation": [-FRAC_1_SQRT_2, 0, 0, FRAC_1_SQRT_2],
                  "extensions": { "KHR_lights_punctual": { "light": 0 } } }
            ]
        })
    };
    let dir = tempfile::tempdir().unwrap();
    let load = |doc: serde_json::Value| {
        let path = dir.path().join("spot.gltf");
        std::fs::write(&path, doc.to_string()).unwrap();
        load_scene(&path)
    };
    let scene = load(gltf(1.5, None)).expect("a spot light without range");
    let LightKind::Spot { near, far, .. } = scene.lights[0].kind else { panic!("a spot light") };
    assert_eq!(far, (1.01 * 147f64.sqrt()) as f32);
    assert_eq!(near, (1.01 * 147f64.sqrt() * 1e-3) as f32);
    assert_eq!((scene.cameras[0].width, scene.cameras[0].height), (1080, 720));
    for (doc, field) in [
        (gltf(-2.0, Some(10.0)), "cameras[0].perspective.aspectRatio"),
        (gltf(0.0, Some(10.0)), "cameras[0].perspective.aspectRatio"),
        (gltf(30.0, Some(10.0)), "cameras[0].perspective.aspectRatio"),
        (gltf(1.5, Some(-1.0)), "extensions.KHR_lights_punctual.lights[0].range"),
    ] {
        let found = load(doc).expect_err(field).problems;
        assert_eq!(found.iter().map(|p| p.path.as_str()).collect::<Vec<_>>(), [field], "{found:?}");
    }
}

/// Standard base64 with padding.
fn base64_of(bytes: &[u8]) -> String {
    const DIGITS: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let word = chunk.iter().enumerate().fold(0u32, |w, (i, &b)| w | (b as u32) << (16 - 8 * i));
        for k in 0..4 {
            let digit = DIGITS[(word >> (18 - 6 * k) & 63) as usize] as char;
            out.push(if k <= chunk.len() { digit } else { '=' });
        }
    }
    out
}

/// The problems of loading `path` (relative to tests/bad_inputs), as displayed.
fn problems(path: &str) -> Vec<(PathBuf, String, String)> {
    let error = load_scene(&common::repo().join("crates/shadowtruth-cli/tests/bad_inputs").join(path))
        .expect_err(path);
    error.problems.into_iter().map(|p| (p.file, p.path, p.message)).collect()
}

#[test]
fn bad_gltf_files_name_the_file_and_the_json_path() {
    let found = problems("scenes/gltf_missing_buffer.gltf");
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(found[0].0.ends_with("scenes/gltf_missing_buffer.gltf"));
    assert_eq!(found[0].1, "buffers[0].uri");
    assert!(found[0].2.contains("missing.bin"), "{}", found[0].2);

    let found = problems("scenes/gltf_lines.gltf");
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(found[0].0.ends_with("scenes/gltf_lines.gltf"));
    assert_eq!(found[0].1, "meshes[0].primitives[0].mode");
    assert!(found[0].2.contains("only triangles"), "{}", found[0].2);

    let found = problems("scenes/gltf_bad_accessor.gltf");
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(found[0].1, "accessors[0]");
    assert!(found[0].2.contains("run past the end of bufferViews[0]"), "{}", found[0].2);

    let found = problems("scenes/gltf_bad_index.gltf");
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(found[0].1, "meshes[0].primitives[0].indices");
    assert!(found[0].2.contains("index 7"), "{}", found[0].2);
}

/// Exports (camera, light) with the binary; returns the original scene and the .glb reloaded.
fn export_and_reload(dir: &Path, camera: &str, light: &str) -> (Scene, Scene) {
    let scene_path = dir.join("scene.json");
    std::fs::write(&scene_path, common::EXPORT_TEST_SCENE).unwrap();
    let out = dir.join(format!("{camera}_{light}"));
    let status = Command::new(env!("CARGO_BIN_EXE_shadowtruth"))
        .args(["view-export", scene_path.to_str().unwrap(), "--camera", camera, "--light", light])
        .args(["--resolution", "256", "--quiet", "-o", out.to_str().unwrap()])
        .status()
        .unwrap();
    assert!(status.success());
    let reloaded = load_scene(&out.join("scene.glb")).unwrap_or_else(|e| panic!("{e}"));
    (load_scene(&scene_path).unwrap(), reloaded)
}

/// The mask of `scene`'s light `light` seen by `camera`.
fn mask(scene: &Scene, camera: &shadowtruth::Camera, light: &str) -> Vec<u8> {
    let bvh = SceneBvh::build(scene);
    let light = scene.light(light).unwrap();
    let g = GBuffer::trace(&bvh, camera, light);
    trace_hard_reference(scene, &bvh, &g, light).mask_codes(&g)
}

#[test]
fn a_view_export_glb_reloads_as_the_same_triangles_and_hard_reference() {
    let dir = tempfile::tempdir().unwrap();
    for (camera, light) in
        [("wide", "sun"), ("tilted", "lamp"), ("wide", "bulb"), ("tilted", "bulb_paraboloid")]
    {
        let (original, reloaded) = export_and_reload(dir.path(), camera, light);
        if original.light(light).unwrap().is_point() {
            // A point light comes back whole: position, near, far, radius and map.
            assert_eq!(reloaded.light(light).unwrap().kind, original.light(light).unwrap().kind);
        }
        assert_eq!(reloaded.name, "scene");
        assert_eq!(reloaded.objects, original.objects, "names, closedness and triangle ranges");
        assert_eq!(bits(&all_triangles(&reloaded)), bits(&all_triangles(&original)));
        let (c, reloaded_camera) = (original.camera(camera).unwrap(), reloaded.camera(camera).unwrap());
        assert_eq!((reloaded_camera.width, reloaded_camera.height), (c.width, c.height));
        assert_eq!(reloaded_camera.position, c.position);
        let forward = |c: &shadowtruth::Camera| (c.look_at - c.position).normalize();
        assert!((forward(reloaded_camera) - forward(c)).abs().max_element() < 1e-6);
        assert_eq!(reloaded.light(light).unwrap().size(), original.light(light).unwrap().size());
        // The reloaded triangles and light under the original camera: the camera's direction
        // round-trips only to within 1e-6 (above), which can move a pixel's point across a
        // spot light's cone.
        let (want, got) = (mask(&original, c, light), mask(&reloaded, c, light));
        let differ = want.iter().zip(&got).filter(|(a, b)| a != b).count();
        assert_eq!(differ, 0, "{camera}/{light}: {differ} of {} mask pixels differ", want.len());
    }
}

#[test]
fn a_scene_file_object_places_a_gltf_under_its_transform() {
    let text = r#"{
      "format": "shadowtruth/scene/v1", "name": "wrapped",
      "objects": [
        { "name": "h", "gltf": "hierarchy.glb", "closed": true,
          "transform": { "scale": [1, 1, -1], "rotate_deg": [0, 90, 0], "translate": [1, 2, 3] } },
        { "name": "floor", "shape": { "type": "plane", "size": [40, 40] } }
      ],
      "cameras": [ { "name": "c", "position": [0, 20, 30], "look_at": [0, 0, 0], "fov_y_deg": 40,
                     "width": 32, "height": 24 } ],
      "lights": [ { "name": "l", "type": "directional", "direction": [0, -1, 0] } ]
    }"#;
    let scene =
        load_scene_str(text, Path::new("wrapped.json"), &fixture("")).unwrap_or_else(|e| panic!("{e}"));
    let names: Vec<&str> = scene.objects.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names, ["h/quad_a", "h/matrix_node", "h/tri_node", "floor"]);
    assert!(scene.objects[..3].iter().all(|o| o.closed));
    // The glTF's own cameras and lights are not read in this form.
    assert_eq!((scene.cameras.len(), scene.lights.len()), (1, 1));
    // Scale z by −1, then 90° about y ((x, y, z) ↦ (z, y, −x)), then translate:
    // p ↦ (1 − z, 2 + y, 3 − x). The object mirrors, so windings flip once more.
    let outer = |p: Vec3| v(1.0 - p.z, 2.0 + p.y, 3.0 - p.x);
    for (name, triangles) in expected_objects() {
        let want: Vec<[Vec3; 3]> =
            triangles.iter().map(|t| [outer(t[0]), outer(t[2]), outer(t[1])]).collect();
        assert_eq!(bits(&object_triangles(&scene, &format!("h/{name}"))), bits(&want), "{name}");
    }
}

#[test]
fn the_command_takes_a_gltf_wherever_it_takes_a_scene() {
    let dir = tempfile::tempdir().unwrap();
    let glb = fixture("hierarchy.glb");
    let mask_png = dir.path().join("mask.png");
    let run = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_shadowtruth")).args(args).output().unwrap();
        assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    };
    run(&["reference", glb.to_str().unwrap(), "--light", "lamp", "-o", mask_png.to_str().unwrap()]);
    let mask = image::open(&mask_png).unwrap().into_luma8();
    assert_eq!(mask.dimensions(), (1080, 720));
    // The camera sees the matrix node's quad and the triangle (the lamp's cone misses them).
    assert!(mask.pixels().any(|p| p.0[0] == 192), "no surface outside the lamp's cone in view");
    run(&["verify", glb.to_str().unwrap(), "--pixels", "2000"]);
}

#[test]
fn a_node_cycle_is_refused_not_followed() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cycle.gltf");
    let text = r#"{ "asset": { "version": "2.0" }, "scene": 0, "scenes": [ { "nodes": [0] } ],
      "nodes": [ { "name": "a", "children": [1] }, { "name": "b", "children": [0] } ] }"#;
    std::fs::write(&path, text).unwrap();
    let error = load_scene(&path).expect_err("a cycle");
    let cycle = error.problems.iter().find(|p| p.message.contains("a second time"));
    assert_eq!(cycle.map(|p| p.path.as_str()), Some("nodes[1].children"), "{error}");
}

#[test]
fn primitives_sharing_their_positions_index_the_same_vertices() {
    // A quad's 4 vertices, then indices 0 1 2 and 0 2 3: two primitives, one POSITION accessor.
    let data = "data:application/octet-stream;base64,\
                AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAACAPwAAAAAAAIC/AAAAAAAAAAAAAIC/AAABAAIAAAACAAMA";
    let text = format!(
        r#"{{ "asset": {{ "version": "2.0" }}, "scenes": [ {{ "nodes": [0] }} ],
          "nodes": [ {{ "name": "q", "mesh": 0, "translation": [0, 0, 5] }} ],
          "meshes": [ {{ "primitives": [ {{ "attributes": {{ "POSITION": 0 }}, "indices": 1 }},
                                         {{ "attributes": {{ "POSITION": 0 }}, "indices": 2 }} ] }} ],
          "accessors": [
            {{ "bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
               "min": [0, 0, -1], "max": [1, 0, 0] }},
            {{ "bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR" }},
            {{ "bufferView": 1, "byteOffset": 6, "componentType": 5123, "count": 3, "type": "SCALAR" }} ],
          "bufferViews": [ {{ "buffer": 0, "byteLength": 48 }}, {{ "buffer": 0, "byteOffset": 48, "byteLength": 12 }} ],
          "buffers": [ {{ "byteLength": 60, "uri": "{data}" }} ] }}"#
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("shared.gltf");
    std::fs::write(&path, text).unwrap();
    let scene = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let q = [v(0.0, 0.0, 5.0), v(1.0, 0.0, 5.0), v(1.0, 0.0, 4.0), v(0.0, 0.0, 4.0)];
    assert_eq!(bits(&all_triangles(&scene)), bits(&[[q[0], q[1], q[2]], [q[0], q[2], q[3]]]));
}
