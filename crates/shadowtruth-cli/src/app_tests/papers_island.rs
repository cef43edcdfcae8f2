//! The island of Ehm et al. (WSCG 2015, Figure 12): the generator is deterministic, the
//! committed scene is exactly its output for `ISLAND_SEED`, and the scene shows what the paper's
//! figure needs (the featured trunk in the front view, a well-lit front, grazing light in the
//! back view, a bounding box that is the island's own).

use super::common;

use crate::papers::{FEATURED_TRUNK, ISLAND_SEED, Island, generate_island, write_island};
use shadowtruth::scene::{LightKind, Scene, load_scene, load_scene_str};
use shadowtruth::trace::{GBuffer, PixelClass, SceneBvh, trace_hard_reference};

/// Loads a generated island through the scene loader, from a temporary folder.
fn load_generated(island: &Island) -> Scene {
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("meshes/island_terrain.obj");
    std::fs::create_dir_all(mesh.parent().unwrap()).unwrap();
    std::fs::write(&mesh, &island.terrain_obj).unwrap();
    load_scene_str(&island.scene_json, &dir.path().join("island.json"), dir.path())
        .unwrap_or_else(|e| panic!("{e}"))
}

fn triangle_bits(scene: &Scene) -> Vec<u32> {
    scene.flat_triangles.iter().flatten().flat_map(|v| v.to_array().map(f32::to_bits)).collect()
}

fn object_index(scene: &Scene, name: &str) -> u32 {
    scene.objects.iter().position(|o| o.name == name).unwrap_or_else(|| panic!("no object {name}")) as u32
}

#[test]
fn papers_island_same_seed_same_bytes_other_seed_other_terrain() {
    let (a, b) = (generate_island(ISLAND_SEED), generate_island(ISLAND_SEED));
    assert_eq!(a, b);
    let (sa, sb) = (load_generated(&a), load_generated(&b));
    assert_eq!(triangle_bits(&sa), triangle_bits(&sb));
    assert_eq!(sa.objects, sb.objects);

    let c = generate_island(ISLAND_SEED + 1);
    assert_ne!(a.terrain_obj, c.terrain_obj);
    let sc = load_generated(&c);
    let terrain = |s: &Scene| {
        let o = &s.objects[object_index(s, "terrain") as usize];
        let range = o.first_triangle as usize..(o.first_triangle + o.triangle_count) as usize;
        s.flat_triangles[range].iter().flatten().map(|v| v.y.to_bits()).collect::<Vec<_>>()
    };
    assert_ne!(terrain(&sa), terrain(&sc));
    // Another seed still gives a valid island with its featured trunk.
    object_index(&sc, FEATURED_TRUNK);
}

#[test]
fn papers_island_committed_scene_is_the_generated_one() {
    let dir = common::repo().join("scenes/papers");
    let island = generate_island(ISLAND_SEED);
    let json = std::fs::read_to_string(dir.join("island.json")).unwrap();
    let obj = std::fs::read_to_string(dir.join("meshes/island_terrain.obj")).unwrap();
    assert!(json == island.scene_json, "scenes/papers/island.json differs: run `shadowtruth island`");
    assert!(obj == island.terrain_obj, "the island's terrain OBJ differs: run `shadowtruth island`");

    let out = tempfile::tempdir().unwrap();
    write_island(out.path(), ISLAND_SEED).unwrap();
    assert_eq!(std::fs::read_to_string(out.path().join("island.json")).unwrap(), json);
    assert_eq!(std::fs::read_to_string(out.path().join("meshes/island_terrain.obj")).unwrap(), obj);
}

#[test]
fn papers_island_loads_with_its_cameras_light_and_featured_trunk_in_view() {
    let scene =
        load_scene(&common::repo().join("scenes/papers/island.json")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.dropped_degenerate, 0);
    assert!(scene.camera("front").is_some() && scene.camera("back").is_some());
    let light = scene.light("sun_spot").expect("light sun_spot");
    let LightKind::Spot { radius, .. } = light.kind else { panic!("sun_spot is a spot light") };
    assert!(radius.is_some_and(|r| r > 0.0), "sun_spot has an area radius");
    let trunk = object_index(&scene, FEATURED_TRUNK);
    assert!(scene.objects[trunk as usize].closed);

    let bvh = SceneBvh::build(&scene);
    let front = GBuffer::trace(&bvh, scene.camera("front").unwrap(), light);
    let on_trunk = |i: usize| front.object(&scene, i) == trunk;
    let trunk_pixels = (0..front.pixel_count()).filter(|&i| on_trunk(i)).count();
    let (xs, ys): (Vec<u32>, Vec<u32>) = (0..front.pixel_count() as u32)
        .filter(|&i| on_trunk(i as usize))
        .map(|i| (i % front.width, i / front.width))
        .unzip();
    eprintln!(
        "featured trunk: {trunk_pixels} pixels in x {:?}..{:?}, y {:?}..{:?}",
        xs.iter().min(),
        xs.iter().max(),
        ys.iter().min(),
        ys.iter().max()
    );
    assert!(trunk_pixels >= 300, "the featured trunk covers {trunk_pixels} pixels of the front view");
    let lit_trunk =
        (0..front.pixel_count()).filter(|&i| on_trunk(i) && front.class[i] == PixelClass::Evaluated).count();
    assert!(lit_trunk >= 100, "the featured trunk faces the light in {lit_trunk} pixels");
}

/// Every land vertex (above the sea) is inside the light's cone and depth range, so the whole
/// island is scored, not `outside_light`.
#[test]
fn papers_island_light_covers_the_island() {
    let scene = load_scene(&common::repo().join("scenes/papers/island.json")).unwrap();
    let light = scene.light("sun_spot").unwrap();
    let LightKind::Spot { position, direction, cone_deg, near, far, .. } = light.kind else { unreachable!() };
    let cos_half = (0.5 * cone_deg as f64).to_radians().cos();
    // A margin of 2° and 10 % in depth: the island is well inside, not at the edge.
    let cos_inner = (0.5 * cone_deg as f64 - 2.0).to_radians().cos();
    let inside = |v: glam::DVec3| {
        let offset = v - position.as_dvec3();
        let along = offset.dot(direction.as_dvec3().normalize());
        assert!(cos_inner > cos_half);
        offset.normalize().dot(direction.as_dvec3().normalize()) > cos_inner
            && along >= 1.1 * near as f64
            && along <= 0.9 * far as f64
    };
    let mut land = 0;
    for (tri, &o) in scene.flat_triangles.iter().zip(&scene.flat_triangle_object) {
        if scene.objects[o as usize].name == "sea" {
            continue;
        }
        for v in tri.iter().filter(|v| v.y >= 0.0) {
            land += 1;
            assert!(inside(v.as_dvec3()), "{v} is outside sun_spot or at its edge");
        }
    }
    assert!(land > 1000);
}

struct ViewStats {
    background: f64,
    facing_away: f64,
    outside_light: f64,
    evaluated: usize,
    /// Shares of the evaluated pixels.
    grazing: f64,
    shadowed: f64,
}

fn view_stats(scene: &Scene, camera: &str) -> ViewStats {
    let light = scene.light("sun_spot").unwrap();
    let LightKind::Spot { position, .. } = light.kind else { unreachable!() };
    let bvh = SceneBvh::build(scene);
    let g = GBuffer::trace(&bvh, scene.camera(camera).unwrap(), light);
    let r = trace_hard_reference(scene, &bvh, &g, light);
    let n = g.pixel_count() as f64;
    let share = |c| g.count(c) as f64 / n;
    let n_dot_l = |i: usize| g.normal[i].dot((position - g.position[i]).normalize());
    let evaluated = g.evaluated.len();
    let grazing = g.evaluated.iter().filter(|&&i| n_dot_l(i as usize) < 0.2).count();
    let shadowed = g.evaluated.iter().filter(|&&i| r.lit[i as usize] == 0).count();
    ViewStats {
        background: share(PixelClass::Background),
        facing_away: share(PixelClass::FacingAway),
        outside_light: share(PixelClass::OutsideLight),
        evaluated,
        grazing: grazing as f64 / evaluated as f64,
        shadowed: shadowed as f64 / evaluated as f64,
    }
}

/// Ehm et al.'s sceneScale is the scene's bounding-box diagonal: the sea adds nothing to the
/// bounds of the terrain grid and its trees (an 80 m sea made it 113 m).
#[test]
fn papers_island_bounds_are_the_islands_own() {
    let scene = load_scene(&common::repo().join("scenes/papers/island.json")).unwrap();
    let (lo, hi) = scene.bounds();
    let diagonal = (hi - lo).length();
    eprintln!("bounds {lo} .. {hi}, diagonal {diagonal} m");
    assert!((lo.x, lo.z, hi.x, hi.z) == (-6.0, -6.0, 6.0, 6.0), "the sea is as wide as the terrain grid");
    assert!(diagonal < 18.0, "sceneScale {diagonal} m");
}

/// The front view is mostly scored terrain with shadows, lit well; the back view is lit at
/// grazing angles. Both see sky beyond the sea's edge.
#[test]
fn papers_island_views_show_lit_slopes_and_grazing_light() {
    let scene = load_scene(&common::repo().join("scenes/papers/island.json")).unwrap();
    for camera in ["front", "back"] {
        let s = view_stats(&scene, camera);
        eprintln!(
            "{camera}: background {:.3}, facing away {:.3}, outside light {:.3}, evaluated {} \
             (N·L < 0.2: {:.3}, shadowed {:.3})",
            s.background, s.facing_away, s.outside_light, s.evaluated, s.grazing, s.shadowed
        );
        assert!(s.background < 0.3, "{camera}: {:.3} background", s.background);
        assert!(s.evaluated > 300_000, "{camera}: only {} evaluated pixels", s.evaluated);
        assert!(s.shadowed > 0.02, "{camera}: only {:.3} of the evaluated pixels in shadow", s.shadowed);
        if camera == "front" {
            assert!(s.grazing < 0.1, "front: {:.3} of the evaluated pixels have N·L < 0.2", s.grazing);
        } else {
            assert!(s.grazing > 0.25, "back: only {:.3} of the evaluated pixels have N·L < 0.2", s.grazing);
        }
    }
}
