//! What to tell someone whose scene has no camera or no light: a view needs both, and how to
//! give one depends on what the file is.

use std::path::Path;

/// "the scene has no camera: …" (or light) with how to add one to `source`: a glTF's own node or
/// light, or the glTF named as an object of a scene file that brings its own; a scene file's
/// `cameras` or `lights`.
pub fn missing_view_item(source: &Path, what: &str) -> String {
    let extension = source.extension().and_then(|e| e.to_str()).unwrap_or_default().to_ascii_lowercase();
    let gltf = extension == "gltf" || extension == "glb";
    let how = match (gltf, what) {
        (true, "camera") => "add a camera node to the glTF, or name the glTF as an object \
             (`\"gltf\": \"model.glb\"`) of a shadowtruth/scene/v1 file that adds `cameras`"
            .to_string(),
        (true, _) => "add a KHR_lights_punctual light to the glTF, or name the glTF as an object \
             (`\"gltf\": \"model.glb\"`) of a shadowtruth/scene/v1 file that adds `lights`"
            .to_string(),
        (false, _) => format!("add one to its `{what}s`"),
    };
    format!("the scene has no {what}: {how}")
}

#[cfg(test)]
mod tests {
    use super::missing_view_item;
    use std::path::Path;

    #[test]
    fn the_advice_fits_the_file() {
        let glb = missing_view_item(Path::new("m/Model.GLB"), "camera");
        assert!(glb.starts_with("the scene has no camera: add a camera node to the glTF"), "{glb}");
        assert!(missing_view_item(Path::new("a.gltf"), "light").contains("KHR_lights_punctual"));
        assert_eq!(
            missing_view_item(Path::new("s.json"), "light"),
            "the scene has no light: add one to its `lights`"
        );
    }
}
