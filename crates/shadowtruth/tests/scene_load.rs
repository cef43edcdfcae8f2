//! Scene loading through the public API: every kind of bad input is reported with its file and
//! JSON path, and good input gives watertight, outward-facing world-space triangles.

use glam::Vec3;
use serde_json::{Value, json};
use shadowtruth::scene::*;
use std::collections::HashMap;
use std::fs;
use std::path::{Path, PathBuf};

const SCENE_FILE: &str = "scene.json";

/// A valid scene: one box, one camera, a directional and a spot light.
fn base() -> Value {
    json!({
        "format": "shadowtruth/scene/v1", "name": "test",
        "objects": [
            { "name": "box", "shape": { "type": "box", "size": [1, 1, 1] }, "closed": true,
              "transform": { "scale": [1, 1, 1], "rotate_deg": [0, 30, 0], "translate": [0, 1.5, 0] } }
        ],
        "cameras": [ { "name": "main", "position": [-6, 4, 6.5], "look_at": [0, 0.7, 0],
                       "up": [0, 1, 0], "fov_y_deg": 45, "width": 64, "height": 48 } ],
        "lights": [
            { "name": "sun", "type": "directional", "direction": [-0.3, -1, -0.2] },
            { "name": "lamp", "type": "spot", "position": [3, 6, 2], "direction": [-0.4, -1, -0.3],
              "cone_deg": 70, "near": 0.5, "far": 30 }
        ]
    })
}

fn load_in(dir: &Path, text: &str) -> Result<Scene, SceneError> {
    load_scene_str(text, &dir.join(SCENE_FILE), dir)
}

fn load(scene: &Value) -> Result<Scene, SceneError> {
    let dir = tempfile::tempdir().unwrap();
    load_in(dir.path(), &scene.to_string())
}

fn problems_in(dir: &Path, text: &str) -> Vec<Problem> {
    match load_in(dir, text) {
        Ok(_) => panic!("expected a SceneError for:\n{text}"),
        Err(e) => {
            for p in &e.problems {
                assert_eq!(p.file, dir.join(SCENE_FILE), "problem names the scene file: {p}");
            }
            e.problems
        }
    }
}

fn problems(text: &str) -> Vec<Problem> {
    let dir = tempfile::tempdir().unwrap();
    problems_in(dir.path(), text)
}

/// Asserts that a problem sits at `path` and its message mentions `needle`.
fn assert_problem(problems: &[Problem], path: &str, needle: &str) {
    assert!(
        problems.iter().any(|p| p.path == path && p.message.contains(needle)),
        "no problem at `{path}` mentioning `{needle}` in:\n{problems:#?}"
    );
}

/// Appends `item` to the array `list`.
fn push(list: &mut Value, item: Value) {
    list.as_array_mut().expect("an array").push(item);
}

fn with(mut scene: Value, edit: impl FnOnce(&mut Value)) -> String {
    edit(&mut scene);
    scene.to_string()
}

fn box_scene(shape: Value, transform: Value) -> Value {
    with(base(), |s| {
        s["objects"][0]["shape"] = shape;
        s["objects"][0]["transform"] = transform;
    })
    .parse()
    .unwrap()
}

/// Every edge of the object is shared by exactly two triangles with opposite directions; vertices
/// are compared bit for bit, as a watertight ray test needs.
fn assert_watertight(tris: &[[Vec3; 3]]) {
    let key = |v: Vec3| v.to_array().map(f32::to_bits);
    let mut edges: HashMap<_, usize> = HashMap::new();
    for t in tris {
        for k in 0..3 {
            *edges.entry((key(t[k]), key(t[(k + 1) % 3]))).or_default() += 1;
        }
    }
    for (&(a, b), &n) in &edges {
        assert_eq!(n, 1, "directed edge used {n} times");
        assert_eq!(edges.get(&(b, a)), Some(&1), "edge without an opposite twin");
    }
}

fn signed_volume(tris: &[[Vec3; 3]]) -> f64 {
    tris.iter().map(|[a, b, c]| a.as_dvec3().dot(b.as_dvec3().cross(c.as_dvec3())) / 6.0).sum()
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    fs::write(&path, text).unwrap();
    path
}

// ---- bad input ----------------------------------------------------------------------------

#[test]
fn unknown_fields_are_named_with_their_path() {
    let text = with(base(), |s| {
        s["colour"] = json!("red");
        s["objects"][0]["material"] = json!(1);
        s["objects"][0]["transform"]["rotate"] = json!([0, 1, 0]);
        s["lights"][0]["radius"] = json!(1); // only spot lights have a radius
    });
    let p = problems(&text);
    assert_problem(&p, "colour", "unknown field");
    assert_problem(&p, "objects[0].material", "allowed fields");
    assert_problem(&p, "objects[0].transform.rotate", "rotate_deg");
    assert_problem(&p, "lights[0].radius", "unknown field");
    assert_eq!(p.len(), 4, "{p:#?}");
}

/// Another program's JSON (a package.json in a folder of scenes) is one problem that says what
/// the file is not, not one per field it lacks or has.
#[test]
fn foreign_json_is_not_a_scene_in_one_problem() {
    let p = problems(r#"{ "name": "web", "version": "1.0.0", "dependencies": { "x": "1" } }"#);
    assert_eq!(p.len(), 1, "{p:#?}");
    assert_problem(&p, "", "not a shadowtruth scene");
    // A scene with a field missing still has that field named.
    let p = problems(&with(base(), |s| {
        s.as_object_mut().unwrap().remove("format");
    }));
    assert_problem(&p, "format", "missing");
}

#[test]
fn wrong_format_tag_is_rejected() {
    let p = problems(&with(base(), |s| s["format"] = json!("shadowtruth/scene/v2")));
    assert_problem(&p, "format", "shadowtruth/scene/v1");
}

#[test]
fn infinite_numbers_are_rejected_with_their_path() {
    // serde_json cannot represent 1e999; 1e39 is a finite f64 but overflows f32.
    let text = with(base(), |s| s["cameras"][0]["fov_y_deg"] = json!("FOV"))
        .replace("\"FOV\"", "1e999")
        .replace("-6,4,6.5", "-6,-1E+999,6.5");
    let text = text.replace("\"translate\":[0,1.5,0]", "\"translate\":[0,1e39,0]");
    let p = problems(&text);
    assert_problem(&p, "cameras[0].fov_y_deg", "1e999 is not a finite number");
    assert_problem(&p, "cameras[0].position", "not a finite number");
    assert_problem(&p, "objects[0].transform.translate", "f32 range");
    assert_eq!(p.len(), 3, "{p:#?}");
}

#[test]
fn malformed_json_reports_line_and_column() {
    let p = problems("{\n  \"format\": \"shadowtruth/scene/v1\",\n  \"name\": NaN\n}");
    assert_eq!(p.len(), 1);
    assert_eq!(p[0].path, "");
    assert!(p[0].message.contains("line 3"), "{}", p[0].message);
}

#[test]
fn zero_length_light_direction_is_rejected() {
    let p = problems(&with(base(), |s| {
        s["lights"][0]["direction"] = json!([0, 0, 0]);
        s["lights"][1]["direction"] = json!([0.0, -0.0, 0]);
    }));
    assert_problem(&p, "lights[0].direction", "non-zero");
    assert_problem(&p, "lights[1].direction", "non-zero");
}

#[test]
fn degenerate_cameras_are_rejected() {
    let p = problems(&with(base(), |s| {
        let cam = s["cameras"][0].clone();
        s["cameras"][0]["look_at"] = cam["position"].clone();
        let mut down = cam.clone();
        down["name"] = json!("straight_down");
        down["look_at"] = json!([-6, -4, 6.5]);
        push(&mut s["cameras"], down);
        let mut no_up = cam;
        no_up["name"] = json!("no_up");
        no_up["up"] = json!([0, 0, 0]);
        push(&mut s["cameras"], no_up);
    }));
    assert_problem(&p, "cameras[0].look_at", "equals `position`");
    assert_problem(&p, "cameras[1].up", "parallel");
    assert_problem(&p, "cameras[2].up", "zero");
    assert_eq!(p.len(), 3, "{p:#?}");
}

#[test]
fn camera_problems_are_all_reported() {
    let p = problems(&with(base(), |s| {
        s["cameras"][0]["width"] = json!(16384);
        s["cameras"][0]["height"] = json!(8192);
        s["cameras"][0]["up"] = json!([0, 1e-30, 0]); // normalizes fine: not degenerate
        s["cameras"][0]["look_at"] = json!([-6, 4, 6.5]);
    }));
    assert_problem(&p, "cameras[0]", "64 megapixels");
    assert_problem(&p, "cameras[0].look_at", "equals `position`");
    assert_eq!(p.len(), 2, "{p:#?}");
}

#[test]
fn empty_objects_array_is_rejected() {
    let p = problems(&with(base(), |s| s["objects"] = json!([])));
    assert_problem(&p, "objects", "at least one object");
}

#[test]
fn missing_mesh_file_names_the_resolved_path() {
    let dir = tempfile::tempdir().unwrap();
    let text = with(base(), |s| s["objects"][0] = json!({ "name": "m", "mesh": "meshes/nope.obj" }));
    let p = problems_in(dir.path(), &text);
    let resolved = dir.path().join("meshes/nope.obj");
    assert_problem(&p, "objects[0].mesh", &resolved.display().to_string());
    assert_eq!(p.len(), 1, "{p:#?}");
}

/// A mesh path that names a FIFO, a device, or a file outside the scene's folder (directly or
/// through a link) is refused before the file is opened: opening the FIFO would block, and
/// reading the device would never end.
#[cfg(unix)]
#[test]
fn mesh_paths_read_only_regular_files_inside_the_scene_folder() {
    let root = tempfile::tempdir().unwrap();
    let dir = root.path().join("scene");
    fs::create_dir_all(dir.join("meshes")).unwrap();
    write(&dir, "meshes/ground.obj", "v -5 0 -5\nv -5 0 5\nv 5 0 5\nf 1 2 3\n");
    write(root.path(), "outside.obj", "v -5 0 -5\nv -5 0 5\nv 5 0 5\nf 1 2 3\n");
    std::os::unix::fs::symlink(root.path().join("outside.obj"), dir.join("meshes/link.obj")).unwrap();
    assert!(
        std::process::Command::new("mkfifo").arg(dir.join("meshes/pipe.obj")).status().unwrap().success()
    );
    std::os::unix::fs::symlink("/dev/zero", dir.join("meshes/zero.obj")).unwrap();
    let outside = root.path().join("outside.obj").display().to_string();
    for (mesh, needle) in [
        ("meshes/pipe.obj", "a FIFO, not a regular file"),
        ("meshes/zero.obj", "a character device, not a regular file"),
        ("meshes/link.obj", "through a symbolic link"),
        ("../outside.obj", "leaves the folder"),
        (outside.as_str(), "is an absolute path"),
        ("/dev/zero", "is an absolute path"),
        ("meshes", "a folder, not a regular file"),
    ] {
        let text = with(base(), |s| s["objects"][0] = json!({ "name": "m", "mesh": mesh }));
        assert_problem(&problems_in(&dir, &text), "objects[0].mesh", needle);
    }
    // The same mesh, inside the folder, loads.
    let text = with(base(), |s| s["objects"][0] = json!({ "name": "m", "mesh": "meshes/ground.obj" }));
    assert!(load_in(&dir, &text).is_ok());
}

#[test]
fn absurd_image_sizes_are_rejected() {
    let p = problems(&with(base(), |s| {
        s["cameras"][0]["width"] = json!(100000);
        s["cameras"][0]["height"] = json!(0);
        let mut big = s["cameras"][0].clone();
        big["name"] = json!("big");
        big["width"] = json!(16384);
        big["height"] = json!(16384);
        push(&mut s["cameras"], big);
    }));
    assert_problem(&p, "cameras[0].width", "16384");
    assert_problem(&p, "cameras[0].height", "between 1");
    assert_problem(&p, "cameras[1]", "megapixels");
}

#[test]
fn zero_scale_is_rejected() {
    let p = problems(&with(base(), |s| s["objects"][0]["transform"]["scale"] = json!([1, 0, 1])));
    assert_problem(&p, "objects[0].transform.scale", "zero");
}

#[test]
fn wrong_types_and_values_are_explained() {
    let p = problems(&with(base(), |s| {
        s["name"] = json!(3);
        s["objects"][0]["closed"] = json!("yes");
        s["objects"][0]["shape"] = json!({ "type": "sphere", "radius": -1, "segments": 2.5 });
        s["lights"][1]["far"] = json!(0.25);
        s["lights"][1]["cone_deg"] = json!(180);
        s["lights"][0]["type"] = json!("area");
    }));
    assert_problem(&p, "name", "expected a string");
    assert_problem(&p, "objects[0].closed", "expected true or false");
    assert_problem(&p, "objects[0].shape.radius", "greater than 0");
    assert_problem(&p, "objects[0].shape.segments", "whole number");
    assert_problem(&p, "lights[1].far", "greater than `near`");
    assert_problem(&p, "lights[1].cone_deg", "between 0 and 180");
    assert_problem(&p, "lights[0].type", "directional, spot or point");
    assert_eq!(p.len(), 7, "{p:#?}");
}

#[test]
fn duplicate_names_and_geometry_choice_are_checked() {
    let p = problems(&with(base(), |s| {
        let mut twin = s["objects"][0].clone();
        twin["mesh"] = json!("box.obj");
        push(&mut s["objects"], twin);
        push(&mut s["objects"], json!({ "name": "nothing" }));
        s["lights"][1]["name"] = json!("sun");
    }));
    assert_problem(&p, "objects[1].name", "duplicate name \"box\" (already used by objects[0])");
    assert_problem(&p, "objects[1]", "both `mesh` and `shape`");
    assert_problem(&p, "objects[2]", "needs a `mesh`");
    assert_problem(&p, "lights[1].name", "duplicate");
}

#[test]
fn several_problems_are_reported_together() {
    let dir = tempfile::tempdir().unwrap();
    let text = with(base(), |s| {
        s["format"] = json!("v0");
        s["objects"][0]["transform"]["scale"] = json!([0, 1, 1]);
        push(&mut s["objects"], json!({ "name": "ground", "mesh": "missing.obj" }));
        s["cameras"][0]["width"] = json!(100000);
        s["lights"][0]["direction"] = json!([0, 0, 0]);
    });
    let p = problems_in(dir.path(), &text);
    assert!(p.len() >= 3);
    assert_problem(&p, "format", "unsupported format");
    assert_problem(&p, "objects[0].transform.scale", "zero");
    assert_problem(&p, "objects[1].mesh", "missing.obj");
    assert_problem(&p, "cameras[0].width", "between 1 and 16384");
    assert_problem(&p, "lights[0].direction", "non-zero");
    assert_eq!(p.len(), 5, "{p:#?}");
    let shown = SceneError { problems: p }.to_string();
    assert!(shown.contains("5 problems") && shown.contains("objects[1].mesh"), "{shown}");
}

#[test]
fn unreadable_scene_file_is_one_problem() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("absent.json");
    let err = load_scene(&path).unwrap_err();
    assert_eq!(err.problems.len(), 1);
    assert_eq!(err.problems[0].file, path);
    assert_eq!(err.problems[0].path, "");
}

#[test]
fn obj_with_nan_vertex_is_rejected_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 nan 1\nf 1 2 3\n");
    let text = with(base(), |s| s["objects"][0] = json!({ "name": "bad", "mesh": "bad.obj" }));
    let p = problems_in(dir.path(), &text);
    assert_problem(&p, "objects[0].mesh", "bad.obj");
    assert_problem(&p, "objects[0].mesh", "vertex 3");
}

#[test]
fn scene_without_triangles_is_rejected() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
    let text = with(base(), |s| s["objects"][0] = json!({ "name": "flat", "mesh": "flat.obj" }));
    let p = problems_in(dir.path(), &text);
    assert_problem(&p, "objects[0].mesh", "no triangles (1 degenerate dropped)");
    assert_eq!(p.len(), 1, "{p:#?}");
}

// ---- good input ---------------------------------------------------------------------------

#[test]
fn example_scene_loads_with_lights_normalized() {
    let dir = tempfile::tempdir().unwrap();
    fs::create_dir(dir.path().join("meshes")).unwrap();
    write(dir.path(), "meshes/ground.obj", "v -5 0 -5\nv -5 0 5\nv 5 0 5\nv 5 0 -5\nf 1 2 3 4\n");
    let text = with(base(), |s| {
        push(&mut s["objects"], json!({ "name": "ground", "mesh": "meshes/ground.obj", "closed": false }));
        s["lights"][1]["radius"] = json!(0.25);
        s["lights"][0]["angular_diameter_deg"] = json!(0.5);
    });
    let path = write(dir.path(), SCENE_FILE, &text);
    let scene = load_scene(&path).unwrap();
    assert_eq!(scene.name, "test");
    assert_eq!(scene.source, path);
    assert_eq!(scene.flat_triangles.len(), 14);
    assert_eq!(scene.objects[1].name, "ground");
    assert!(!scene.objects[1].closed && scene.objects[0].closed);
    assert_eq!((scene.objects[1].first_triangle, scene.objects[1].triangle_count), (12, 2));
    let cam = scene.camera("main").unwrap();
    assert_eq!((cam.width, cam.height, cam.up), (64, 48, Vec3::Y));
    let sun = scene.light("sun").unwrap();
    let LightKind::Directional { direction, angular_diameter_deg } = sun.kind else {
        panic!("sun is directional")
    };
    assert_eq!(angular_diameter_deg, Some(0.5));
    assert!((direction.length() - 1.0).abs() < 1e-6);
    let lamp = scene.light("lamp").unwrap();
    let LightKind::Spot { direction, near, far, radius, .. } = lamp.kind else { panic!("lamp is a spot") };
    assert_eq!(radius, Some(0.25));
    assert!((direction.length() - 1.0).abs() < 1e-6);
    assert_eq!((near, far), (0.5, 30.0));
}

#[test]
fn closed_shapes_are_watertight_and_outward() {
    let shapes = [
        (json!({ "type": "box", "size": [1, 2, 3] }), Some(12)),
        (json!({ "type": "sphere", "radius": 1.5 }), Some(2 * 32 * 15)),
        (json!({ "type": "sphere", "radius": 1, "segments": 7, "rings": 3 }), Some(28)),
        (json!({ "type": "cylinder", "radius": 0.5, "height": 2, "segments": 12 }), Some(48)),
        (json!({ "type": "cone", "radius": 0.5, "height": 2 }), Some(64)),
    ];
    let transforms =
        [json!({}), json!({ "scale": [2, 0.5, 3], "rotate_deg": [10, 20, 30], "translate": [0.1, -5, 7] })];
    for (shape, count) in shapes {
        for transform in &transforms {
            let scene = load(&box_scene(shape.clone(), transform.clone())).unwrap();
            if let Some(n) = count {
                assert_eq!(scene.flat_triangles.len(), n, "{shape}");
            }
            assert_eq!(scene.dropped_degenerate, 0, "{shape}");
            assert_watertight(&scene.flat_triangles);
            assert!(signed_volume(&scene.flat_triangles) > 0.0, "{shape} {transform}");
        }
    }
}

#[test]
fn box_volume_matches_its_size() {
    let scene = load(&box_scene(json!({ "type": "box", "size": [1, 2, 3] }), json!({}))).unwrap();
    assert_eq!(signed_volume(&scene.flat_triangles), 6.0);
    assert_eq!(scene.bounds(), (Vec3::new(-0.5, -1.0, -1.5), Vec3::new(0.5, 1.0, 1.5)));
}

#[test]
fn plane_faces_up_and_is_subdivided() {
    let shape = json!({ "type": "plane", "size": [4, 2], "subdivisions": 4 });
    let scene = load(&box_scene(shape, json!({ "translate": [0, 1, 0] }))).unwrap();
    assert_eq!(scene.flat_triangles.len(), 32);
    for [a, b, c] in &scene.flat_triangles {
        assert!((*b - *a).cross(*c - *a).y > 0.0);
    }
    assert_eq!(scene.bounds(), (Vec3::new(-2.0, 1.0, -1.0), Vec3::new(2.0, 1.0, 1.0)));
}

#[test]
fn transform_order_is_scale_then_rotate_xyz_then_translate() {
    let rotate_y =
        Transform { scale: Vec3::ONE, rotate_deg: Vec3::new(0.0, 90.0, 0.0), translate: Vec3::ZERO };
    assert_eq!(rotate_y.apply(Vec3::X), Vec3::new(0.0, 0.0, -1.0));
    // x then y: (0,1,0) → Rx90 → (0,0,1) → Ry90 → (1,0,0); rotating y first would leave it at z.
    let xy = Transform { rotate_deg: Vec3::new(90.0, 90.0, 0.0), ..rotate_y.clone() };
    assert_eq!(xy.apply(Vec3::Y), Vec3::X);
    // Scale before rotation, translation last: the box's long x axis ends up along −z.
    let shape = json!({ "type": "box", "size": [2, 1, 1] });
    let transform = json!({ "scale": [3, 1, 1], "rotate_deg": [0, 90, 0], "translate": [10, 0, 0] });
    let scene = load(&box_scene(shape, transform)).unwrap();
    assert_eq!(scene.bounds(), (Vec3::new(9.5, -0.5, -3.0), Vec3::new(10.5, 0.5, 3.0)));
}

#[test]
fn mirrored_scale_keeps_closed_objects_outward() {
    for scale in [[-1, 1, 1], [-1, -2, 3], [-1, -1, -1]] {
        let shape = json!({ "type": "box", "size": [1, 2, 3] });
        let scene = load(&box_scene(shape, json!({ "scale": scale }))).unwrap();
        assert_watertight(&scene.flat_triangles);
        let volume = signed_volume(&scene.flat_triangles);
        assert!(volume > 0.0, "scale {scale:?}: volume {volume}");
    }
}

#[test]
fn degenerate_obj_triangles_are_dropped_and_counted() {
    let dir = tempfile::tempdir().unwrap();
    // Two good triangles, one with a repeated vertex, one with collinear vertices; two models.
    let obj = "o first\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 1 3\nf 1 2 4\n\
               o second\nv 0 0 1\nv 1 0 1\nv 0 1 1\nf 5 6 7\n";
    write(dir.path(), "soup.obj", obj);
    let text = with(base(), |s| {
        let shape = s["objects"][0].clone();
        s["objects"][0] = json!({ "name": "soup", "mesh": "soup.obj" });
        push(&mut s["objects"], shape);
    });
    let scene = load_in(dir.path(), &text).unwrap();
    assert_eq!(scene.dropped_degenerate, 2);
    assert_eq!(scene.flat_triangles.len(), 2 + 12);
    let ranges: Vec<_> = scene.objects.iter().map(|o| (o.first_triangle, o.triangle_count)).collect();
    assert_eq!(ranges, [(0, 2), (2, 12)]);
    let expected: Vec<u32> = [0, 0].into_iter().chain([1; 12]).collect();
    assert_eq!(scene.flat_triangle_object, expected);
    assert_eq!(scene.flat_triangles[1], [Vec3::Z, Vec3::new(1.0, 0.0, 1.0), Vec3::new(0.0, 1.0, 1.0)]);
}

#[test]
fn odd_inputs_give_errors_not_panics() {
    let texts = [
        "",
        "null",
        "[]",
        "{\"format\": \"shadowtruth/scene/v1\"",
        "{\"objects\": {}, \"cameras\": 1, \"lights\": null}",
        r#"{"objects": [null, 1, "x", {"shape": 5}, {"shape": {"type": 3}}, {"mesh": ""}]}"#,
        r#"{"objects": [{"name": "s", "shape": {"type": "sphere", "radius": 1, "segments": 1e9}}]}"#,
        r#"{"objects": [{"name": "s", "shape": {"type": "plane", "size": [1, 1], "subdivisions": 4096}}]}"#,
        r#"{"objects": [{"name": "b", "shape": {"type": "box", "size": [1e-45, 1, 1]}}]}"#,
        r#"{"objects": [{"name": "b", "shape": {"type": "box", "size": [1, 1, 1]},
            "transform": {"scale": [3e38, 3e38, 3e38], "translate": [3e38, 0, 0]}}]}"#,
        r#"{"cameras": [{"width": -1, "height": 1.5, "fov_y_deg": 1e308, "position": [1, 2]}]}"#,
        r#"{"lights": [{"type": "spot", "near": -1, "far": "far", "direction": [1e-300, 0, 0]}]}"#,
    ];
    for text in texts {
        let err = load_in(Path::new("."), text).expect_err(text);
        assert!(!err.problems.is_empty(), "{text}");
    }
}

#[test]
fn procedural_shapes_are_limited_per_scene() {
    // 4 194 304 triangles for the shapes of a scene, alone or together: a few bytes of JSON must
    // not ask for gigabytes (the fuzz corpus holds the same cases: fuzz/corpus/scene_reader/).
    let alone = with(base(), |s| {
        let plane = json!({ "type": "plane", "size": [1, 1], "subdivisions": 1449 });
        push(&mut s["objects"], json!({ "name": "plane", "shape": plane }));
    });
    assert_problem(&problems(&alone), "objects[1].shape", "would have 4199202 triangles");
    let together = with(base(), |s| {
        // Exactly the limit alone, over it with the box before it: refused before it is built.
        let sphere = json!({ "type": "sphere", "radius": 1, "segments": 4096, "rings": 513 });
        push(&mut s["objects"], json!({ "name": "ball", "shape": sphere }));
        push(&mut s["objects"], json!({ "name": "ball2", "shape": sphere }));
    });
    let found = problems(&together);
    assert_problem(&found, "objects[1].shape", "the procedural shapes up to this one have 4194316 triangles");
    assert_eq!(found.len(), 1, "only the first shape over the limit is named: {found:#?}");
}

/// Each bundled scene reads only files inside its own folder, so the scenes of `scenes/papers/`
/// and `scenes/paths/` hold copies of the suite's meshes: they must stay the suite's bytes.
#[test]
fn bundled_mesh_copies_equal_the_suite_meshes() {
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    for copy in ["papers/meshes/l_shape.obj", "paths/meshes/rocks.obj", "paths/meshes/rocks_terrain.obj"] {
        let original = scenes.join("meshes").join(Path::new(copy).file_name().unwrap());
        assert_eq!(fs::read(scenes.join(copy)).unwrap(), fs::read(&original).unwrap(), "{copy}");
    }
}
