//! The cached references under references/ are exactly what the tracer computes today, their
//! manifest records the digest of what each depends on and the SHA-256 of each file, and the
//! folder holds nothing else.

mod common;

use common::{bundled, repo};
use sha2::{Digest, Sha256};
use shadowtruth::scene::ViewKey;
use shadowtruth::trace::{GBuffer, ReferenceCache, SceneBvh, reference_digest, trace_hard_reference};
use std::collections::BTreeSet;

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
                let g = GBuffer::trace(&bvh, camera, light);
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

#[test]
fn the_folder_holds_exactly_the_files_its_manifest_names() {
    let dir = repo().join("references");
    let manifest: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("manifest.json")).unwrap()).unwrap();
    assert_eq!(manifest["format"], "shadowtruth/references/v2");
    let mut named = BTreeSet::new();
    for (key, entry) in manifest["entries"].as_object().unwrap() {
        let file = entry["mask"].as_str().unwrap();
        let bytes = std::fs::read(dir.join(file)).unwrap_or_else(|e| panic!("{key}: {file}: {e}"));
        let sha256: String = Sha256::digest(&bytes).iter().map(|b| format!("{b:02x}")).collect();
        assert_eq!(entry["sha256"].as_str(), Some(sha256.as_str()), "{key}: {file}: bytes changed");
        named.insert(file.to_string());
    }
    named.insert("manifest.json".into());
    let on_disk: BTreeSet<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| name != ".manifest.lock")
        .collect();
    assert_eq!(on_disk, named, "files the manifest does not name (an earlier layout?) or names but lacks");
}
