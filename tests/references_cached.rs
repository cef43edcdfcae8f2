//! The cached references under references/ are exactly what the tracer computes today, and
//! their manifest records the digest of what each depends on.

mod common;

use common::{bundled, repo};
use shadowtruth::scene::ViewKey;
use shadowtruth::trace::{GBuffer, ReferenceCache, SceneBvh, reference_digest, trace_hard_reference};

const SUITE: [&str; 5] = ["grazing_wall", "l_shape", "plane_box", "rocks", "spot"];

#[test]
fn cached_masks_are_bit_identical_to_fresh_ones() {
    let cache = ReferenceCache::new(repo().join("references"));
    let mut checked = 0;
    for name in SUITE {
        let scene = bundled(name);
        let bvh = SceneBvh::build(&scene);
        for camera in &scene.cameras {
            for light in &scene.lights {
                let digest = reference_digest(&scene, camera, light);
                let view = ViewKey::from_view(&scene, camera, light);
                let recorded = cache.recorded_digest(view);
                assert_eq!(
                    recorded.as_deref(),
                    Some(digest.as_str()),
                    "{name}/{}/{}: the cached reference is stale or missing; run `shadowtruth run` to refresh references/",
                    camera.name,
                    light.name
                );
                let cached = cache.load(view, &digest).expect("cached mask decodes");
                let g = GBuffer::trace(&scene, &bvh, camera, light);
                let fresh = trace_hard_reference(&scene, &bvh, &g, light).mask_codes(&g);
                let differ = fresh.iter().zip(&cached.codes).filter(|(a, b)| a != b).count();
                assert_eq!(
                    differ, 0,
                    "{name}/{}/{}: {differ} pixels differ from the cache",
                    camera.name, light.name
                );
                checked += 1;
            }
        }
    }
    assert_eq!(checked, SUITE.len());
}

#[test]
fn the_suite_is_what_scenes_holds() {
    let mut found: Vec<String> = std::fs::read_dir(repo().join("scenes"))
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.path().extension().is_some_and(|x| x == "json"))
        .map(|e| e.path().file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    found.sort();
    assert_eq!(found, SUITE);
}
