//! The glTF reader (src/scene/gltf/): arbitrary bytes loaded as a whole-scene glTF twice, as they
//! are (`.gltf` JSON, or a `.glb` when they start with its magic) and as the JSON chunk of a GLB
//! whose binary chunk holds a triangle, so that JSON inputs reach the binary-chunk path too.
//! Buffer files resolve in `scene_dir()` (its `buffers/`).

use super::{FUZZ_MAX_TRIANGLES, check_scene, scene_dir, strings_stay_inside};
use shadowtruth::scene::{LightKind, MAX_IMAGE_PIXELS, MAX_IMAGE_SIDE, Scene, load_gltf_within};
use std::path::Path;

/// The binary chunk of the wrapped GLB: a triangle's three positions (f32 VEC3), as
/// `scene_dir()/buffers/triangle.bin`.
const TRIANGLE_POSITIONS: [f32; 9] = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -1.0];

/// A glTF file (`.gltf` or `.glb`) as a scene, buffers resolved in `scene_dir()`.
pub fn gltf_reader(data: &[u8]) {
    if !uris_stay_inside(glb_json(data).unwrap_or(data)) {
        return;
    }
    load(data, "fuzz.gltf");
    if !data.starts_with(b"glTF") {
        let bin: Vec<u8> = TRIANGLE_POSITIONS.iter().flat_map(|x| x.to_le_bytes()).collect();
        load(&crate::view_export::glb_container(data, &bin), "fuzz.glb");
    }
}

fn load(bytes: &[u8], name: &str) {
    match load_gltf_within(bytes, Path::new(name), &scene_dir(), FUZZ_MAX_TRIANGLES) {
        Ok(scene) => {
            check_scene(&scene);
            check_views(&scene);
        }
        Err(error) => {
            assert!(!error.problems.is_empty(), "an error without problems");
            let _ = error.to_string();
        }
    }
}

/// What a glTF's cameras and lights promise: image sizes within the scene format's limits,
/// finite positions, and spot depth ranges with 0 < near < far.
fn check_views(scene: &Scene) {
    for camera in &scene.cameras {
        let (w, h) = (camera.width as u64, camera.height as u64);
        assert!((1..=MAX_IMAGE_SIDE).contains(&w) && (1..=MAX_IMAGE_SIDE).contains(&h), "image {w}×{h}");
        assert!(w * h <= MAX_IMAGE_PIXELS, "image {w}×{h}");
        assert!(camera.position.is_finite() && camera.look_at.is_finite() && camera.up.is_finite());
        assert!(camera.fov_y_deg > 0.0 && camera.fov_y_deg < 180.0);
    }
    for light in &scene.lights {
        if let LightKind::Spot { position, direction, cone_deg, near, far, radius } = light.kind {
            assert!(position.is_finite() && direction.is_finite(), "a non-finite spot light");
            assert!(near > 0.0 && near < far && far.is_finite(), "near {near}, far {far}");
            assert!(cone_deg > 0.0 && cone_deg < 180.0, "cone {cone_deg}");
            assert!(radius.is_none_or(|r| r > 0.0 && r.is_finite()), "radius {radius:?}");
        }
    }
}

/// False when a string of the glTF's JSON may name a file outside the folder: a path that leaves
/// it, or one with a percent escape (URIs are percent-decoded before they are resolved), spelt
/// out or as a JSON escape.
fn uris_stay_inside(json: &[u8]) -> bool {
    let text = String::from_utf8_lossy(json);
    strings_stay_inside(&text) && !text.contains('%') && !text.to_ascii_lowercase().contains("\\u0025")
}

/// The JSON chunk of a GLB container, when `data` is one (its declared length clamped to the
/// data).
fn glb_json(data: &[u8]) -> Option<&[u8]> {
    if !data.starts_with(b"glTF") {
        return None;
    }
    let length = u32::from_le_bytes(data.get(12..16)?.try_into().ok()?) as usize;
    data.get(20..).map(|rest| &rest[..length.min(rest.len())])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fuzzing_gltf_uris_outside_the_scene_dir_are_skipped() {
        assert!(uris_stay_inside(br#"{"buffers": [{"uri": "buffers/triangle.bin"}]}"#));
        assert!(!uris_stay_inside(br#"{"buffers": [{"uri": "/dev/zero"}]}"#));
        assert!(!uris_stay_inside(br#"{"buffers": [{"uri": "..%2F..%2Fx"}]}"#));
        assert!(!uris_stay_inside(br#"{"buffers": [{"uri": "\u00252e\u00252e/x"}]}"#));
        let wrapped = crate::view_export::glb_container(br#"{"buffers": [{"uri": "../x"}]}"#, &[]);
        assert!(!uris_stay_inside(glb_json(&wrapped).unwrap()));
        assert_eq!(glb_json(&wrapped).unwrap().len() % 4, 0);
    }
}
