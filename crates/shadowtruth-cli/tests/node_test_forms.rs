//! The forms of the BVH node test (src/trace/bvh/node_test.rs) give the same references: every
//! mask, coverage and area-light reference traced with the 8-lane AVX2 form, and with rays walked
//! eight at a time (src/trace/bvh/packet.rs), is byte for byte the one traced with the portable form
//! (`SHADOWTRUTH_NODE_TEST=portable`, which walks rays one by one). On a processor with AVX-512
//! rays walk sixteen to a packet and the packets of eight closest hits alone (the coverage
//! reference's sub-pixel rays) run compiled for it (src/trace/bvh/packet_isa.rs), and the AVX2
//! compilation with packets of eight (`SHADOWTRUTH_NODE_TEST=avx2`) is compared too. Scenes: the bundled ones (a spot
//! light among them), the forest with instanced trees (whose mesh walks carry a margin), and a
//! sun straight down, whose rays do not move along two axes and so take the portable form in
//! both runs.

#[path = "../../shadowtruth/tests/common/mod.rs"]
mod common;

use std::path::Path;
use std::process::Command;

/// The reference traced with the node test form `form` (`SHADOWTRUTH_NODE_TEST`; `None`: the
/// processor's best).
fn reference(dir: &Path, scene: &Path, light: &str, kind: &str, out: &str, form: Option<&str>) -> Vec<u8> {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_shadowtruth"));
    cmd.args(["reference"]).arg(scene).args(["--light", light, "--kind", kind, "-o", out]).current_dir(dir);
    match form {
        Some(form) => cmd.env("SHADOWTRUTH_NODE_TEST", form),
        None => cmd.env_remove("SHADOWTRUTH_NODE_TEST"),
    };
    let status = cmd.output().unwrap();
    assert!(status.status.success(), "{}", String::from_utf8_lossy(&status.stderr));
    std::fs::read(dir.join(out)).unwrap()
}

fn node_test(dir: &Path, scene: &Path, form: Option<&str>) -> String {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_shadowtruth"));
    cmd.args(["reference"]).arg(scene).args(["-o", "t.png", "--timing", "--repeats", "1"]).current_dir(dir);
    match form {
        Some(form) => cmd.env("SHADOWTRUTH_NODE_TEST", form),
        None => cmd.env_remove("SHADOWTRUTH_NODE_TEST"),
    };
    let out = String::from_utf8_lossy(&cmd.output().unwrap().stdout).into_owned();
    out.lines().find(|l| l.starts_with("node test:")).expect("--timing names the node test").to_string()
}

#[test]
fn both_node_tests_trace_the_same_references() {
    let dir = tempfile::tempdir().unwrap();
    let scenes = common::repo().join("scenes");
    let wide = node_test(dir.path(), &scenes.join("plane_box.json"), None);
    assert_eq!(
        node_test(dir.path(), &scenes.join("plane_box.json"), Some("portable")),
        "node test: 4 children at a time (portable)"
    );
    if wide.contains("AVX-512") {
        assert_eq!(
            node_test(dir.path(), &scenes.join("plane_box.json"), Some("avx2")),
            "node test: 8 children at a time (AVX2)"
        );
    }
    if !wide.contains("AVX2") {
        // Nothing to compare: passing here would claim the 8-lane form agrees without running it.
        let portable_only = std::env::var("SHADOWTRUTH_NODE_TEST").is_ok_and(|v| v == "portable");
        assert!(
            portable_only,
            "this processor has no AVX2 ({wide}), so the 8-lane form under test cannot run: run the \
             tests on one with AVX2, or set SHADOWTRUTH_NODE_TEST=portable to test the portable form alone"
        );
        eprintln!("not run: no AVX2, and SHADOWTRUTH_NODE_TEST=portable tests the portable form alone");
        return;
    }
    let forest = dir.path().join("forest");
    let status = Command::new(env!("CARGO_BIN_EXE_shadowtruth"))
        .args(["generate", "forest", "--instanced", "--triangles", "200K", "--image", "240,180", "-o"])
        .arg(&forest)
        .status()
        .unwrap();
    assert!(status.success());
    let down = dir.path().join("down.json");
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(scenes.join("plane_box.json")).unwrap()).unwrap();
    json["lights"][0]["direction"] = serde_json::json!([0, -1, 0]);
    std::fs::write(&down, json.to_string()).unwrap();
    let mut cases = vec![(forest.join("scene.json"), "sun".to_string()), (down, "sun".to_string())];
    for name in ["plane_box", "l_shape", "grazing_wall", "rocks", "spot"] {
        let path = scenes.join(format!("{name}.json"));
        let scene = common::bundled(name);
        cases.push((path, scene.lights[0].name.clone()));
    }
    for (k, (scene, light)) in cases.iter().enumerate() {
        // The forest's sun has a size: its area-light reference too.
        let area = if k == 0 { Some(("area", "a.exr")) } else { None };
        for (kind, file) in [("hard", "m.png"), ("coverage", "c.exr")].into_iter().chain(area) {
            let portable = reference(dir.path(), scene, light, kind, file, Some("portable"));
            let best = reference(dir.path(), scene, light, kind, file, None);
            assert!(best == portable, "{} ({kind}): {wide} and the portable form disagree", scene.display());
            if wide.contains("AVX-512") {
                let avx2 = reference(dir.path(), scene, light, kind, file, Some("avx2"));
                assert!(
                    avx2 == portable,
                    "{} ({kind}): AVX2 and the portable form disagree",
                    scene.display()
                );
            }
        }
    }
}
