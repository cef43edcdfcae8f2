//! `shadowtruth depth-map`: the EXR holds exactly the rasterizer's layer, and the sidecar the
//! matrix that maps world points to it.

#[path = "../../shadowtruth/tests/common/mod.rs"]
mod common;

use common::bundled;
use exr::prelude::*;
use shadowtruth::raster::{LightView, RasterSettings, rasterize_nearest};
use std::process::Command;

#[test]
fn the_exr_is_the_layer_and_the_sidecar_its_matrix() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("d.exr");
    let scene_path = common::repo().join("scenes/plane_box.json");
    let status = Command::new(env!("CARGO_BIN_EXE_shadowtruth"))
        .args(["depth-map", scene_path.to_str().unwrap(), "--resolution", "256", "-o", out.to_str().unwrap()])
        .status()
        .unwrap();
    assert!(status.success());
    let image = read_first_flat_layer_from_file(&out).expect("a readable EXR");
    let size = image.layer_data.size;
    assert_eq!((size.width(), size.height()), (256, 256));
    let samples: Vec<f32> = image.layer_data.channel_data.list[0].sample_data.values_as_f32().collect();
    let scene = bundled("plane_box");
    let view = LightView::new(&scene.lights[0], scene.bounds(), 256);
    let layer = rasterize_nearest(&scene, &view, &RasterSettings::default());
    assert!(
        samples.iter().zip(&layer.depth).all(|(a, b)| a.to_bits() == b.to_bits()),
        "EXR differs from the layer"
    );
    assert!(samples.iter().any(|&d| d < 1.0), "the map holds the scene");
    let sidecar: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("d.json")).unwrap()).unwrap();
    let m = &sidecar["clip_from_world"];
    let row = |r: usize| {
        glam::Vec4::new(
            m[r][0].as_f64().unwrap() as f32,
            m[r][1].as_f64().unwrap() as f32,
            m[r][2].as_f64().unwrap() as f32,
            m[r][3].as_f64().unwrap() as f32,
        )
    };
    let p = glam::Vec4::new(0.3, 0.0, -0.2, 1.0);
    let clip = glam::Vec4::new(row(0).dot(p), row(1).dot(p), row(2).dot(p), row(3).dot(p));
    let expected = view.clip_from_world * p;
    assert!((clip - expected).abs().max_element() < 1e-6, "row-major clip_from_world: {clip} vs {expected}");
    assert_eq!(sidecar["near"].as_f64().unwrap() as f32, view.near);
}

#[test]
fn bad_depth_map_arguments_exit_2() {
    let scene_path = common::repo().join("scenes/plane_box.json");
    let s = scene_path.to_str().unwrap();
    for args in [
        vec!["depth-map", s, "--resolution", "0", "-o", "x.exr"],
        vec!["depth-map", s, "--resolution", "64", "--format", "f64", "-o", "x.exr"],
        vec!["depth-map", s, "--resolution", "64", "--layer", "3", "-o", "x.exr"],
        vec!["depth-map", s, "--resolution", "64", "--light", "moon", "-o", "x.exr"],
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_shadowtruth")).args(&args).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(!String::from_utf8_lossy(&out.stderr).contains("panicked"));
    }
}
