//! Replays the committed fuzz corpus (fuzz/corpus/<target>/) through the same functions the fuzz
//! targets call (src/fuzzing/), so that every input the fuzzer kept, and every crash it found
//! once, is checked on each test run without the nightly toolchain. See fuzz/README.md.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;

type Entry = fn(&[u8]);

const TARGETS: &[(&str, Entry)] = &[
    ("scene_reader", shadowtruth_cli::fuzzing::scene_reader),
    ("obj_reader", shadowtruth_cli::fuzzing::obj_reader),
    ("plan_reader", shadowtruth_cli::fuzzing::plan_reader),
    ("gate_rules", shadowtruth_cli::fuzzing::gate_rules),
    ("gltf_reader", shadowtruth_cli::fuzzing::gltf_reader),
    ("image_reader", shadowtruth_cli::fuzzing::image_reader),
    ("tune_options", shadowtruth_cli::fuzzing::tune_options),
];

/// Runs every file of `fuzz/corpus/<target>/` and names each one that panics.
fn replay(target: &str, entry: Entry) -> usize {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/corpus").join(target);
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    let failed: Vec<String> = files
        .iter()
        .filter(|path| {
            let data = std::fs::read(path).unwrap();
            catch_unwind(AssertUnwindSafe(|| entry(&data))).is_err()
        })
        .map(|path| path.display().to_string())
        .collect();
    assert!(failed.is_empty(), "{target}: these inputs panic:\n{}", failed.join("\n"));
    files.len()
}

#[test]
fn fuzz_corpus_replays_without_panics() {
    for &(target, entry) in TARGETS {
        let n = replay(target, entry);
        assert!(n > 0, "{target}: the corpus is empty");
    }
}

#[test]
fn fuzz_corpus_bundled_scenes_load_in_the_scene_dir() {
    // The bundled scenes are seeds: their meshes resolve to the cut-down copies in
    // fuzz/scene_dir/meshes/, so the seeds reach past the reader into the loaded scene.
    for name in ["plane_box.json", "l_shape.json", "rocks.json", "spot.json", "grazing_wall.json"] {
        let text =
            std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(name))
                .unwrap();
        let loaded = shadowtruth::scene::load_scene_str(
            &text,
            Path::new(name),
            &shadowtruth_cli::fuzzing::scene_dir(),
        );
        assert!(loaded.is_ok(), "{name}: {}", loaded.err().map(|e| e.to_string()).unwrap_or_default());
    }
}
