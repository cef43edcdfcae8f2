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
            let gbuffer = GBuffer::trace(&scene, &bvh, camera, light);
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
        let gbuffer = GBuffer::trace(&scene, &bvh, &scene.cameras[0], light);
        let reference = trace_hard_reference(&scene, &bvh, &gbuffer, light);
        let lit = gbuffer.evaluated.iter().filter(|&&i| reference.lit[i as usize] != 0).count();
        let shadowed = gbuffer.evaluated.len() - lit;
        assert!(
            lit * 20 > gbuffer.evaluated.len() && shadowed * 20 > gbuffer.evaluated.len(),
            "{lit} lit, {shadowed} shadowed"
        );
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
