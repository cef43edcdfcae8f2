//! `shadowtruth view-export`: the .glb reloads with the `gltf` crate into the scene's triangles,
//! cameras and lights; the exported matrices put every evaluated G-buffer point at its pixel's
//! centre and at the light-space coordinates of the CPU rasterizer's `LightView`; the EXRs read
//! back bit for bit as the G-buffer.

#[path = "../../shadowtruth/tests/common/mod.rs"]
mod common;

use exr::prelude::*;
use glam::{DMat4, DVec3, DVec4, Quat, Vec3};
use serde_json::Value;
use shadowtruth::raster::LightView;
use shadowtruth::scene::{LightKind, Scene, load_scene};
use shadowtruth::trace::{GBuffer, PixelClass, SceneBvh};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Largest distance, in pixels, between a projected G-buffer point and its pixel's centre.
const PIXEL_BOUND: f64 = 1e-3;
/// Largest difference between the exported light matrices' (s, t, depth) and `LightView`'s
/// (u, v, d): 1/100 of a texel at the test's 1024² map.
const LIGHT_BOUND: f64 = 1e-5;
const RESOLUTION: u32 = 1024;

struct Export {
    _dir: tempfile::TempDir,
    out: PathBuf,
    scene: Scene,
}

/// Writes the test scene and exports (camera, light) from it with the binary.
fn export(camera: &str, light: &str) -> Export {
    let dir = tempfile::tempdir().unwrap();
    let scene_path = dir.path().join("scene.json");
    std::fs::write(&scene_path, common::EXPORT_TEST_SCENE).unwrap();
    let out = dir.path().join("export");
    let status = Command::new(env!("CARGO_BIN_EXE_shadowtruth"))
        .args(["view-export", scene_path.to_str().unwrap(), "--camera", camera, "--light", light])
        .args(["--resolution", &RESOLUTION.to_string(), "--quiet", "-o", out.to_str().unwrap()])
        .status()
        .unwrap();
    assert!(status.success());
    let scene = load_scene(&scene_path).unwrap();
    Export { _dir: dir, out, scene }
}

fn view_json(out: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(out.join("view.json")).unwrap()).unwrap()
}

/// A matrix from 16 row-major numbers, checked against its column-major twin.
fn matrix(object: &Value, name: &str) -> DMat4 {
    let read = |layout: &str| -> Vec<f32> {
        let key = format!("{name}_{layout}");
        let values = object[&key].as_array().unwrap_or_else(|| panic!("no {key}"));
        values.iter().map(|v| v.as_f64().unwrap() as f32).collect()
    };
    let (rows, cols) = (read("row_major"), read("column_major"));
    assert_eq!(rows.len(), 16);
    for r in 0..4 {
        for c in 0..4 {
            assert_eq!(rows[4 * r + c].to_bits(), cols[4 * c + r].to_bits(), "{name}[{r}][{c}]");
        }
    }
    let f64s: Vec<f64> = rows.iter().map(|&x| x as f64).collect();
    DMat4::from_cols_slice(&f64s).transpose()
}

fn gbuffer(e: &Export, camera: &str, light: &str) -> GBuffer {
    let bvh = SceneBvh::build(&e.scene);
    GBuffer::trace(&bvh, e.scene.camera(camera).unwrap(), e.scene.light(light).unwrap())
}

/// (px, py) from the image's top-left corner where `clip` lands under `api`'s viewport rules.
fn pixel_of(api: &str, clip: DVec4, width: f64, height: f64) -> (f64, f64) {
    let (x, y) = (clip.x / clip.w, clip.y / clip.w);
    let px = (x + 1.0) / 2.0 * width;
    let py = match api {
        // Window y from the bottom, (y + 1)/2·height, read as a row from the top.
        "opengl" => height - (y + 1.0) / 2.0 * height,
        "vulkan" => (y + 1.0) / 2.0 * height,
        "d3d" => (1.0 - y) / 2.0 * height,
        _ => unreachable!(),
    };
    (px, py)
}

fn check_camera_matrices(e: &Export, g: &GBuffer, camera: &Value) {
    let (w, h) = (camera["width"].as_f64().unwrap(), camera["height"].as_f64().unwrap());
    assert_eq!((w as u32, h as u32), (g.width, g.height));
    let view = matrix(camera, "view_from_world");
    let mut worst: f64 = 0.0;
    for api in ["opengl", "vulkan", "d3d"] {
        let clip_from_world = matrix(&camera[api], "clip_from_world");
        let product = matrix(&camera[api], "clip_from_view") * view;
        for &i in &g.evaluated {
            let (x, y) = ((i % g.width) as f64 + 0.5, (i / g.width) as f64 + 0.5);
            let p = g.position[i as usize].as_dvec3().extend(1.0);
            for m in [clip_from_world, product] {
                let clip = m * p;
                let (px, py) = pixel_of(api, clip, w, h);
                let err = (px - x).abs().max((py - y).abs());
                assert!(err <= PIXEL_BOUND, "{api}: pixel ({x}, {y}) lands at ({px}, {py})");
                worst = worst.max(err);
                // Depth within the API's range, between near and far.
                let z = clip.z / clip.w;
                let lo = if api == "opengl" { -1.0 } else { 0.0 };
                assert!(z > lo && z < 1.0, "{api}: depth {z}");
            }
        }
    }
    assert!(!g.evaluated.is_empty());
    eprintln!("{}: largest distance to the pixel centre {worst:.2e} px", e.out.display());
}

fn check_light_matrices(e: &Export, g: &GBuffer, light_name: &str, light: &Value) {
    let view = LightView::new(e.scene.light(light_name).unwrap(), e.scene.bounds(), RESOLUTION);
    let map = &light["shadow_map"];
    assert_eq!(map["resolution"].as_u64(), Some(RESOLUTION as u64));
    assert_eq!(map["near"].as_f64().unwrap() as f32, view.near);
    assert_eq!(map["far"].as_f64().unwrap() as f32, view.far);
    // D3D's clip_from_world and the view are the rasterizer's own matrices, bit for bit.
    let bits = |m: DMat4| m.as_mat4().to_cols_array().map(f32::to_bits);
    assert_eq!(
        bits(matrix(&map["d3d"], "clip_from_world")),
        view.clip_from_world.to_cols_array().map(f32::to_bits)
    );
    assert_eq!(bits(matrix(map, "view_from_world")), view.light_from_world.to_cols_array().map(f32::to_bits));
    let light_view = matrix(map, "view_from_world");
    let mut worst: f64 = 0.0;
    for api in ["opengl", "vulkan", "d3d"] {
        let texture = matrix(&map[api], "texture_from_world");
        let clip_from_world = matrix(&map[api], "clip_from_world");
        let product = matrix(&map[api], "clip_from_view") * light_view;
        for &i in &g.evaluated {
            let p = g.position[i as usize];
            let expected = view.project(p).expect("an evaluated point projects").as_dvec3();
            let (u, v, d) = (expected.x, expected.y, expected.z);
            let t = texture * p.as_dvec3().extend(1.0);
            let t = t.truncate() / t.w;
            let v_api = if api == "opengl" { v } else { 1.0 - v };
            let err = (t - DVec3::new(u, v_api, d)).abs().max_element();
            assert!(err <= LIGHT_BOUND, "{api}: texture {t} vs ({u}, {v_api}, {d})");
            worst = worst.max(err);
            // The clip matrices agree with the texture matrix under the API's rules.
            for m in [clip_from_world, product] {
                let c = m * p.as_dvec3().extend(1.0);
                let ndc = c.truncate() / c.w;
                let y_up = if api == "vulkan" { -ndc.y } else { ndc.y };
                let depth = if api == "opengl" { 0.5 * ndc.z + 0.5 } else { ndc.z };
                let err =
                    DVec3::new(0.5 * ndc.x + 0.5 - u, 0.5 * y_up + 0.5 - v, depth - d).abs().max_element();
                assert!(err <= LIGHT_BOUND, "{api}: clip {ndc} vs ({u}, {v}, {d})");
                worst = worst.max(err);
            }
        }
    }
    eprintln!("{light_name}: largest light-space difference {worst:.2e}");
}

#[test]
fn the_matrices_put_every_evaluated_point_at_its_pixel_centre_and_light_coordinates() {
    for (camera, light) in [("wide", "sun"), ("tilted", "lamp")] {
        let e = export(camera, light);
        let json = view_json(&e.out);
        assert_eq!(json["format"], "shadowtruth/view/v1");
        assert_eq!(json["camera"]["name"], camera);
        assert_eq!(json["light"]["name"], light);
        let g = gbuffer(&e, camera, light);
        check_camera_matrices(&e, &g, &json["camera"]);
        check_light_matrices(&e, &g, light, &json["light"]);
    }
}

/// The cube face OpenGL's table 8.19 picks for direction d: the major axis, ties to x then y;
/// +x, −x, +y, −y, +z, −z.
fn major_axis_face(d: Vec3) -> usize {
    let a = d.abs();
    let (axis, component) = if a.x >= a.y && a.x >= a.z {
        (0, d.x)
    } else if a.y >= a.z {
        (1, d.y)
    } else {
        (2, d.z)
    };
    2 * axis + (component < 0.0) as usize
}

/// (u, v, d) of `p` under the paraboloid mapping view.json states in words, in f64.
fn paraboloid_uvd(view_from_world: DMat4, near: f64, far: f64, p: Vec3) -> DVec3 {
    let q = view_from_world.transform_point3(p.as_dvec3());
    let (length, h) = (q.length(), q.length() - q.z);
    DVec3::new(0.5 * q.x / h + 0.5, 0.5 * q.y / h + 0.5, (length - near) / (far - near))
}

#[test]
fn a_point_lights_faces_and_hemispheres_are_the_rasterizers_views() {
    use shadowtruth::raster::{CubeMap, DualParaboloid};
    let bits = |m: DMat4| m.as_mat4().to_cols_array().map(f32::to_bits);
    let e = export("wide", "bulb");
    let json = view_json(&e.out);
    let (light, map) = (e.scene.light("bulb").unwrap(), &json["light"]["shadow_map"]);
    assert_eq!((json["light"]["type"].as_str(), map["projection"].as_str()), (Some("point"), Some("cube")));
    assert_eq!((map["guard_texels"].as_u64(), map["face_resolution"].as_u64()), (Some(4), Some(1032)));
    let cube = CubeMap::new(light, RESOLUTION);
    let faces = map["faces"].as_array().unwrap();
    assert_eq!(faces.len(), 6);
    for (face, view) in faces.iter().zip(&cube.faces) {
        assert_eq!(
            bits(matrix(&face["d3d"], "clip_from_world")),
            view.clip_from_world.to_cols_array().map(f32::to_bits)
        );
        assert_eq!(face["resolution"].as_u64(), Some(1032));
    }
    // Every evaluated point, through the face the stated rule picks, lands inside that face at
    // the rasterizer's own (u, v, d).
    let g = gbuffer(&e, "wide", "bulb");
    let position = match light.kind {
        LightKind::Point { position, .. } => position,
        _ => unreachable!(),
    };
    for &i in &g.evaluated {
        let p = g.position[i as usize];
        let k = major_axis_face(p - position);
        let expected = cube.faces[k].project(p).unwrap().as_dvec3();
        let t = matrix(&faces[k]["d3d"], "texture_from_world") * p.as_dvec3().extend(1.0);
        let (u, v, d) = (t.x / t.w, 1.0 - t.y / t.w, t.z / t.w);
        assert!((DVec3::new(u, v, d) - expected).abs().max_element() <= LIGHT_BOUND, "face {k}: {p}");
        let inner = 4.0 / 1032.0;
        assert!(u >= inner - 1e-6 && u <= 1.0 - inner + 1e-6 && v >= inner - 1e-6 && v <= 1.0 - inner + 1e-6);
    }

    let e = export("tilted", "bulb_paraboloid");
    let json = view_json(&e.out);
    let map = &json["light"]["shadow_map"];
    assert_eq!(map["projection"].as_str(), Some("dual_paraboloid"));
    let light = e.scene.light("bulb_paraboloid").unwrap();
    let paraboloids = DualParaboloid::new(light, RESOLUTION);
    let hemispheres = map["hemispheres"].as_array().unwrap();
    assert_eq!(hemispheres.len(), 2);
    let g = gbuffer(&e, "tilted", "bulb_paraboloid");
    let mut shaded = [0; 2];
    for (k, (h, view)) in hemispheres.iter().zip(&paraboloids.hemispheres).enumerate() {
        let view_from_world = matrix(h, "view_from_world");
        assert_eq!(bits(view_from_world), view.light_from_world.to_cols_array().map(f32::to_bits));
        let (near, far) = (h["near"].as_f64().unwrap(), h["far"].as_f64().unwrap());
        // The points the stated rule shades through this hemisphere (p.y ≤ the light's for the
        // first), each at the rasterizer's (u, v, d).
        let position = match light.kind {
            LightKind::Point { position, .. } => position,
            _ => unreachable!(),
        };
        for &i in &g.evaluated {
            let p = g.position[i as usize];
            if (p.y > position.y) as usize != k {
                continue;
            }
            assert_eq!(paraboloids.hemisphere_of(p), k);
            shaded[k] += 1;
            let expected = view.project(p).expect("a point of the hemisphere");
            let got = paraboloid_uvd(view_from_world, near, far, p);
            assert!(
                (got - expected.as_dvec3()).abs().max_element() <= LIGHT_BOUND,
                "{p}: {got} vs {expected}"
            );
        }
    }
    assert!(shaded[0] > 100, "{shaded:?}");
}

fn read_exr(path: &Path) -> FlatImage {
    read_all_flat_layers_from_file(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn channel<'a>(image: &'a FlatImage, name: &str) -> &'a FlatSamples {
    let layer = &image.layer_data[0];
    &layer
        .channel_data
        .list
        .iter()
        .find(|c| c.name.eq(name))
        .unwrap_or_else(|| panic!("no channel {name}"))
        .sample_data
}

#[test]
fn the_exrs_are_the_gbuffer_bit_for_bit() {
    let e = export("tilted", "lamp");
    let g = gbuffer(&e, "tilted", "lamp");
    for (file, values) in [("position.exr", &g.position), ("normal.exr", &g.normal)] {
        let image = read_exr(&e.out.join(file));
        let size = image.layer_data[0].size;
        assert_eq!((size.width() as u32, size.height() as u32), (g.width, g.height));
        for (axis, name) in ["R", "G", "B"].iter().enumerate() {
            let FlatSamples::F32(samples) = channel(&image, name) else { panic!("{file} {name} is not f32") };
            let expected: Vec<u32> = values.iter().map(|v| v[axis].to_bits()).collect();
            assert_eq!(samples.iter().map(|s| s.to_bits()).collect::<Vec<_>>(), expected, "{file} {name}");
        }
    }
    let ids = read_exr(&e.out.join("ids.exr"));
    let u32s = |name: &str| match channel(&ids, name) {
        FlatSamples::U32(v) => v.clone(),
        _ => panic!("{name} is not u32"),
    };
    assert_eq!(u32s("triangle"), g.triangle);
    // Each pixel's object found from the objects' triangle ranges, not from the G-buffer.
    let object_of = |triangle: u32| {
        let holds = |o: &shadowtruth::scene::Object| {
            (o.first_triangle..o.first_triangle + o.triangle_count).contains(&triangle)
        };
        e.scene.objects.iter().position(holds).map_or(u32::MAX, |k| k as u32)
    };
    let objects: Vec<u32> = g.triangle.iter().map(|&t| object_of(t)).collect();
    assert!(objects.iter().any(|&o| o != u32::MAX) && objects.iter().any(|&o| o != objects[0]));
    assert_eq!(u32s("object"), objects);
    let classes: Vec<u32> = g
        .class
        .iter()
        .map(|c| match c {
            PixelClass::Background => 0,
            PixelClass::FacingAway => 1,
            PixelClass::OutsideLight => 2,
            PixelClass::Evaluated => 3,
            PixelClass::Uncertain => 4,
        })
        .collect();
    assert_eq!(u32s("class"), classes);
    // The view holds every class, and background ids are u32::MAX.
    for code in 0..4 {
        assert!(classes.contains(&code), "class {code} missing from the test view");
    }
    assert!(g.triangle.iter().zip(&classes).all(|(&t, &c)| (c == 0) == (t == u32::MAX)));
    // The same G-buffer gives the same bytes.
    let again = export("tilted", "lamp");
    for file in ["position.exr", "normal.exr", "ids.exr"] {
        assert_eq!(std::fs::read(e.out.join(file)).unwrap(), std::fs::read(again.out.join(file)).unwrap());
    }
}

/// Rotates glTF's local −z (the look direction of cameras and lights) by a node's rotation.
fn look_direction(node: &gltf::Node) -> Vec3 {
    let (_, rotation, scale) = node.transform().decomposed();
    assert_eq!(scale, [1.0; 3]);
    Quat::from_array(rotation) * Vec3::NEG_Z
}

#[test]
fn the_glb_reloads_as_the_scene() {
    let e = export("wide", "sun");
    let bytes = std::fs::read(e.out.join("scene.glb")).unwrap();
    let gltf::Gltf { document, blob } = gltf::Gltf::from_slice(&bytes).expect("a valid glb");
    let buffers = [blob.expect("a binary chunk")];
    assert!(document.extensions_used().any(|x| x == "KHR_lights_punctual"));
    let nodes: Vec<gltf::Node> = document.nodes().collect();
    let scene = &e.scene;
    assert_eq!(nodes.len(), scene.objects.len() + scene.cameras.len() + scene.lights.len());

    for (object, node) in scene.objects.iter().zip(&nodes) {
        assert_eq!(node.name(), Some(object.name.as_str()));
        let mesh = node.mesh().expect("a mesh per object");
        let mut triangles = Vec::new();
        for primitive in mesh.primitives() {
            assert_eq!(primitive.material().double_sided(), !object.closed);
            let reader = primitive.reader(|b| Some(buffers[b.index()].as_slice()));
            let positions: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
            let normals: Vec<[f32; 3]> = reader.read_normals().expect("a NORMAL attribute").collect();
            let indices: Vec<u32> = reader.read_indices().unwrap().into_u32().collect();
            for t in indices.chunks(3) {
                let triangle: Vec<Vec3> = t.iter().map(|&i| Vec3::from(positions[i as usize])).collect();
                // Flat: each corner carries the triangle's own unit geometric normal.
                let (a, b, c) = (triangle[0].as_dvec3(), triangle[1].as_dvec3(), triangle[2].as_dvec3());
                let face = (b - a).cross(c - a).normalize().as_vec3();
                for &i in t {
                    let n = Vec3::from(normals[i as usize]);
                    assert_eq!(n, face, "{}: corner {i}", object.name);
                }
                triangles.push(triangle);
            }
        }
        let first = object.first_triangle as usize;
        let expected = &scene.flat_triangles[first..first + object.triangle_count as usize];
        assert_eq!(triangles.len(), expected.len(), "{}", object.name);
        for (got, want) in triangles.iter().zip(expected) {
            let bits = |v: &[Vec3]| v.iter().flat_map(|p| p.to_array().map(f32::to_bits)).collect::<Vec<_>>();
            assert_eq!(bits(got), bits(want), "{}", object.name);
        }
    }

    let camera_nodes = &nodes[scene.objects.len()..scene.objects.len() + scene.cameras.len()];
    for (camera, node) in scene.cameras.iter().zip(camera_nodes) {
        let (translation, _, _) = node.transform().decomposed();
        assert_eq!(Vec3::from(translation), camera.position);
        let forward = (camera.look_at - camera.position).normalize();
        assert!((look_direction(node) - forward).abs().max_element() < 1e-6, "{}", camera.name);
        let (_, rotation, _) = node.transform().decomposed();
        let up = Quat::from_array(rotation) * Vec3::Y;
        let true_up = forward.cross(camera.up).normalize().cross(forward);
        assert!((up - true_up).abs().max_element() < 1e-6, "{}: up {up} vs {true_up}", camera.name);
        let gltf_camera = node.camera().expect("a camera");
        let gltf::camera::Projection::Perspective(p) = gltf_camera.projection() else {
            panic!("{} is not perspective", camera.name)
        };
        assert_eq!(p.yfov(), (camera.fov_y_deg as f64).to_radians() as f32);
        assert_eq!(p.aspect_ratio(), Some(camera.width as f32 / camera.height as f32));
        assert!(p.znear() > 0.0 && p.zfar().unwrap() > p.znear());
    }

    let light_nodes = &nodes[scene.objects.len() + scene.cameras.len()..];
    for (light, node) in scene.lights.iter().zip(light_nodes) {
        let gltf_light = node.light().expect("a KHR_lights_punctual light");
        assert_eq!(gltf_light.name(), Some(light.name.as_str()));
        match (&light.kind, gltf_light.kind()) {
            (LightKind::Directional { direction, .. }, gltf::khr_lights_punctual::Kind::Directional) => {
                assert!((look_direction(node) - *direction).abs().max_element() < 1e-6);
            }
            (
                LightKind::Spot { position, direction, cone_deg, far, .. },
                gltf::khr_lights_punctual::Kind::Spot { inner_cone_angle, outer_cone_angle },
            ) => {
                let (translation, _, _) = node.transform().decomposed();
                assert_eq!(Vec3::from(translation), *position);
                assert!((look_direction(node) - *direction).abs().max_element() < 1e-6);
                assert_eq!(outer_cone_angle, (*cone_deg as f64 / 2.0).to_radians() as f32);
                assert!(inner_cone_angle < outer_cone_angle && outer_cone_angle - inner_cone_angle < 1e-6);
                assert_eq!(gltf_light.range(), Some(*far));
            }
            (LightKind::Point { position, far, .. }, gltf::khr_lights_punctual::Kind::Point) => {
                let (translation, _, _) = node.transform().decomposed();
                assert_eq!(Vec3::from(translation), *position);
                assert_eq!(gltf_light.range(), Some(*far));
            }
            (kind, _) => panic!("{}: {kind:?} exported as another kind", light.name),
        }
    }
}
