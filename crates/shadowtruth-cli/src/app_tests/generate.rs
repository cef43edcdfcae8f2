//! `shadowtruth generate`: the same arguments give the same bytes, the triangle count is met
//! within the stated tolerance, the scene loads and its lights cast real shadows into the view,
//! and a large mesh is cached and its cache never trusted when stale or corrupt.

use crate::generate::{
    COUNT_TOLERANCE, GenerateOptions, MIN_COUNT_FOR_TOLERANCE, SCENE_FILE, SceneKind, write_generated,
};
use shadowtruth::scene::{MESH_CACHE_DIR, Scene, load_scene, mesh_cache_path};
use shadowtruth::trace::{GBuffer, PixelClass, SceneBvh, trace_hard_reference};
use std::path::Path;

fn options(kind: SceneKind, triangles: u64, seed: u64) -> GenerateOptions {
    GenerateOptions { kind, triangles, seed, width_px: 160, height_px: 120, instanced: false }
}

/// Every file of a scene folder (name, bytes), in name order.
fn folder_bytes(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .map(|p| (p.file_name().unwrap().to_string_lossy().into_owned(), std::fs::read(&p).unwrap()))
        .collect();
    files.sort();
    files
}

fn triangle_bits(scene: &Scene) -> Vec<u32> {
    scene.flat_triangles.iter().flatten().flat_map(|v| v.to_array().map(f32::to_bits)).collect()
}

#[test]
fn generate_same_seed_same_bytes_other_seed_other_scene() {
    for kind in [SceneKind::City, SceneKind::Forest] {
        let dirs: Vec<_> = (0..3).map(|_| tempfile::tempdir().unwrap()).collect();
        for (dir, seed) in dirs.iter().zip([7, 7, 8]) {
            write_generated(dir.path(), &options(kind, 30_000, seed)).unwrap();
        }
        let [a, b, c] = [0, 1, 2].map(|k| folder_bytes(dirs[k].path()));
        assert_eq!(a, b, "{kind:?}: the same seed must give the same bytes");
        assert_ne!(a, c, "{kind:?}: another seed must give another scene");
    }
}

#[test]
fn generate_meets_the_triangle_count_within_the_tolerance() {
    for kind in [SceneKind::City, SceneKind::Forest] {
        for requested in [MIN_COUNT_FOR_TOLERANCE, 65_000, 250_000] {
            let dir = tempfile::tempdir().unwrap();
            let (path, written) = write_generated(dir.path(), &options(kind, requested, 3)).unwrap();
            let off = written.abs_diff(requested) as f64 / requested as f64;
            assert!(
                off <= COUNT_TOLERANCE,
                "{kind:?} {requested}: {written} triangles ({:.2} % off)",
                off * 100.0
            );
            let scene = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(scene.triangle_count() as u64, written, "{kind:?}: no degenerate triangle");
            assert_eq!(scene.dropped_degenerate, 0);
        }
    }
}

#[test]
fn generate_scenes_cast_shadows_into_the_view() {
    for kind in [SceneKind::City, SceneKind::Forest] {
        let dir = tempfile::tempdir().unwrap();
        write_generated(dir.path(), &options(kind, 40_000, 1)).unwrap();
        let scene = load_scene(&dir.path().join(SCENE_FILE)).unwrap_or_else(|e| panic!("{e}"));
        assert!(scene.objects.iter().any(|o| o.closed), "{kind:?}: casters are closed objects");
        let bvh = SceneBvh::build(&scene);
        let camera = &scene.cameras[0];
        for light in &scene.lights {
            let gbuffer = GBuffer::trace(&bvh, camera, light);
            let reference = trace_hard_reference(&scene, &bvh, &gbuffer, light);
            let evaluated = gbuffer.count(PixelClass::Evaluated);
            let lit = gbuffer.evaluated.iter().filter(|&&i| reference.lit[i as usize] != 0).count();
            let shadowed = evaluated - lit;
            let (pixels, name) = (gbuffer.pixel_count(), &light.name);
            assert!(evaluated * 10 > pixels, "{kind:?}/{name}: {evaluated} of {pixels} pixels evaluated");
            assert!(
                lit * 20 > evaluated && shadowed * 20 > evaluated,
                "{kind:?}/{name}: {lit} lit, {shadowed} shadowed"
            );
        }
    }
}

/// An instanced forest holds one tree and numbers every placement: its count is met, and its
/// trees shadow the view under both lights.
#[test]
fn generate_instanced_forest_holds_one_tree_and_casts_shadows() {
    let dir = tempfile::tempdir().unwrap();
    let requested = 3_000_000;
    let options = GenerateOptions { instanced: true, ..options(SceneKind::Forest, requested, 5) };
    let (path, written) = write_generated(dir.path(), &options).unwrap();
    let off = written.abs_diff(requested) as f64 / requested as f64;
    assert!(off <= COUNT_TOLERANCE, "{written} triangles ({:.2} % off)", off * 100.0);
    let scene = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.meshes.len(), 1);
    assert!(scene.instances.len() > 100, "{} trees", scene.instances.len());
    assert_eq!(scene.triangle_count() as u64, written);
    let held = scene.flat_triangles.len() + scene.meshes[0].triangles.len();
    assert!(held * 10 < written as usize, "{held} triangles held for {written}");
    let bvh = SceneBvh::build(&scene);
    for light in &scene.lights {
        let gbuffer = GBuffer::trace(&bvh, &scene.cameras[0], light);
        let reference = trace_hard_reference(&scene, &bvh, &gbuffer, light);
        let lit = gbuffer.evaluated.iter().filter(|&&i| reference.lit[i as usize] != 0).count();
        let shadowed = gbuffer.evaluated.len() - lit;
        assert!(
            lit * 20 > gbuffer.evaluated.len() && shadowed * 20 > gbuffer.evaluated.len(),
            "{lit} lit, {shadowed} shadowed"
        );
    }
}

/// Every number of a JSON tree, in document order.
fn numbers(value: &serde_json::Value, out: &mut Vec<serde_json::Number>) {
    match value {
        serde_json::Value::Number(n) => out.push(n.clone()),
        serde_json::Value::Array(items) => items.iter().for_each(|v| numbers(v, out)),
        serde_json::Value::Object(map) => map.values().for_each(|v| numbers(v, out)),
        _ => {}
    }
}

/// Where a generated scene's camera and lamp stand, in metres.
struct Placed {
    camera_m: [f64; 3],
    look_at_m: [f64; 3],
    lamp_m: [f64; 3],
    lamp_axis_m: [f64; 3],
    lamp_far_m: f64,
}

/// The scene file of each kind holds the camera, lights and placements derived from the ground
/// and the tallest caster, in millimetres (values of scenes written before the file was
/// serialised from the scene types), and loads as written.
#[test]
fn generate_scene_file_holds_the_scene_in_millimetres() {
    let v3 = |v: &serde_json::Value| -> Vec<f64> {
        v.as_array().unwrap().iter().map(|c| c.as_f64().unwrap()).collect()
    };
    let cases = [
        (GenerateOptions { width_px: 640, height_px: 360, ..options(SceneKind::City, 5_000, 3) }, "city"),
        (
            GenerateOptions { width_px: 1920, height_px: 1080, ..options(SceneKind::Forest, 5_000, 7) },
            "forest",
        ),
        (
            GenerateOptions {
                width_px: 320,
                height_px: 200,
                instanced: true,
                ..options(SceneKind::Forest, 200_000, 2)
            },
            "instanced",
        ),
    ];
    let expected = [
        Placed {
            camera_m: [-66.0, 147.23, 66.0],
            look_at_m: [6.0, 0.0, -6.0],
            lamp_m: [-18.0, 153.23, 12.0],
            lamp_axis_m: [30.0, -153.23, -24.0],
            lamp_far_m: 280.0,
        },
        Placed {
            camera_m: [-11.55, 24.159, 11.55],
            look_at_m: [1.05, 0.0, -1.05],
            lamp_m: [-3.15, 25.209, 2.1],
            lamp_axis_m: [5.25, -25.209, -4.2],
            lamp_far_m: 47.0,
        },
        Placed {
            camera_m: [-23.1, 28.785, 23.1],
            look_at_m: [2.1, 0.0, -2.1],
            lamp_m: [-6.3, 30.885, 4.2],
            lamp_axis_m: [10.5, -30.885, -8.4],
            lamp_far_m: 73.0,
        },
    ];
    for ((options, case), placed) in cases.iter().zip(expected) {
        let Placed {
            camera_m: position,
            look_at_m: look_at,
            lamp_m: lamp,
            lamp_axis_m: axis,
            lamp_far_m: far,
        } = placed;
        let dir = tempfile::tempdir().unwrap();
        let (path, _) = write_generated(dir.path(), options).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let file: serde_json::Value = serde_json::from_str(&text).unwrap();
        let camera = &file["cameras"][0];
        assert_eq!(
            (v3(&camera["position"]), v3(&camera["look_at"])),
            (position.to_vec(), look_at.to_vec()),
            "{case}"
        );
        assert_eq!(v3(&camera["up"]), [0.0, 1.0, 0.0]);
        assert_eq!(
            (camera["fov_y_deg"].as_f64(), camera["width"].as_u64()),
            (Some(50.0), Some(options.width_px as u64))
        );
        let [sun, spot] = [&file["lights"][0], &file["lights"][1]];
        assert_eq!(
            (sun["type"].as_str(), v3(&sun["direction"])),
            (Some("directional"), vec![0.6, -0.45, -0.35])
        );
        assert_eq!(sun["angular_diameter_deg"].as_f64(), Some(0.5));
        assert_eq!((v3(&spot["position"]), v3(&spot["direction"])), (lamp.to_vec(), axis.to_vec()), "{case}");
        let spot_values = ["cone_deg", "near", "far", "radius"].map(|k| spot[k].as_f64().unwrap());
        assert_eq!(spot_values, [70.0, 1.0, far, 0.5], "{case}");
        let mut all = Vec::new();
        numbers(&file, &mut all);
        for n in &all {
            let shown = n.to_string();
            let decimals = shown.split_once('.').map_or(0, |(_, d)| d.trim_end_matches('0').len());
            assert!(decimals <= 3, "{case}: {shown} is finer than millimetres");
            assert_ne!(n.as_f64().map(f64::to_bits), Some((-0.0f64).to_bits()), "{case}: -0 in the file");
        }
        let scene = load_scene(&path).unwrap_or_else(|e| panic!("{case}: {e}"));
        assert_eq!(scene.cameras[0].position, glam::Vec3::from(position.map(|c| c as f32)));
        if options.instanced {
            let first = &file["objects"][1]["instances"][0];
            assert_eq!(v3(&first["scale"]), [1.073; 3]);
            assert_eq!(v3(&first["rotate_deg"]), [0.0, 264.096, 0.0]);
            assert_eq!(v3(&first["translate"]), [-16.481, 0.619, -16.159]);
            assert_eq!(file["objects"][1]["instances"].as_array().unwrap().len(), scene.instances.len());
        } else {
            assert!(file["objects"].as_array().unwrap().iter().all(|o| o.get("instances").is_none()));
        }
    }
}

#[test]
fn scene_mesh_cache_is_written_reused_and_never_trusted_when_stale() {
    let dir = tempfile::tempdir().unwrap();
    // Large enough that the buildings' OBJ is cached (MIN_CACHED_BYTES).
    let (path, _) = write_generated(dir.path(), &options(SceneKind::City, 500_000, 2)).unwrap();
    let obj = dir.path().join("buildings.obj");
    let cache = mesh_cache_path(&obj).unwrap();
    assert!(cache.starts_with(dir.path().join(MESH_CACHE_DIR)));
    let parsed = load_scene(&path).unwrap();
    assert!(cache.is_file(), "a large OBJ is cached when parsed");
    let cached_bytes = std::fs::read(&cache).unwrap();
    let bits = triangle_bits(&parsed);
    assert_eq!(triangle_bits(&load_scene(&path).unwrap()), bits, "read from the cache");

    // Corrupt (truncated, then a flipped byte): ignored and rewritten.
    std::fs::write(&cache, &cached_bytes[..cached_bytes.len() / 2]).unwrap();
    assert_eq!(triangle_bits(&load_scene(&path).unwrap()), bits);
    assert_eq!(std::fs::read(&cache).unwrap(), cached_bytes, "rewritten after a truncation");
    let mut flipped = cached_bytes.clone();
    let last = flipped.len() - 5;
    flipped[last] ^= 1;
    std::fs::write(&cache, &flipped).unwrap();
    assert_eq!(triangle_bits(&load_scene(&path).unwrap()), bits);
    assert_eq!(std::fs::read(&cache).unwrap(), cached_bytes, "rewritten after a corruption");

    // Stale: the OBJ changes (one vertex moved, same size): its new geometry is read.
    let text = std::fs::read_to_string(&obj).unwrap();
    let first_v = text.find("\nv ").unwrap() + 3;
    let moved = format!("{}9{}", &text[..first_v], &text[first_v + 1..]);
    assert_eq!(moved.len(), text.len());
    std::thread::sleep(std::time::Duration::from_millis(20));
    std::fs::write(&obj, moved).unwrap();
    let reloaded = load_scene(&path).unwrap();
    assert_ne!(triangle_bits(&reloaded), bits, "a modified OBJ is parsed again, not read from its cache");
    assert_ne!(std::fs::read(&cache).unwrap(), cached_bytes, "and its cache rewritten");
}
