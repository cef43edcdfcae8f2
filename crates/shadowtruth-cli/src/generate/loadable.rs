//! What the scene loader accepts, checked before anything of a generated scene is written: the
//! options against the loader's own limits (the constants of src/scene/format.rs, not copies),
//! and the scene built against them again, since its triangle count may differ from the request
//! by the tolerance. Errors name the option at fault.

use super::generated::GeneratedScene;
use super::request::{GenerateOptions, MIN_INSTANCED_TRIANGLES, MIN_TRIANGLES, SceneKind};
use shadowtruth::scene::{
    MAX_IMAGE_PIXELS, MAX_IMAGE_SIDE, MAX_INSTANCED_TRIANGLES, MAX_INSTANCES, MAX_SCENE_TRIANGLES,
};

/// The options give a scene that the loader can read: the camera's image size, the triangle
/// count, and instancing for forests only.
pub(crate) fn check_options(options: &GenerateOptions) -> Result<(), String> {
    let (w, h) = (options.width_px as u64, options.height_px as u64);
    if !(1..=MAX_IMAGE_SIDE).contains(&w) || !(1..=MAX_IMAGE_SIDE).contains(&h) {
        return Err(format!("--image {w},{h}: each side must be 1 to {MAX_IMAGE_SIDE} pixels"));
    }
    if w * h > MAX_IMAGE_PIXELS {
        return Err(format!(
            "--image {w},{h}: {} pixels, more than the {MAX_IMAGE_PIXELS} a scene's camera may have",
            w * h
        ));
    }
    if options.instanced && options.kind != SceneKind::Forest {
        return Err("--instanced makes a forest of one tree: give `forest`".into());
    }
    if options.instanced && options.triangles < MIN_INSTANCED_TRIANGLES {
        return Err(format!(
            "--triangles {} with --instanced: at least {MIN_INSTANCED_TRIANGLES} (the instanced \
             forest's terrain alone is 131 072); without --instanced from {MIN_TRIANGLES}",
            options.triangles
        ));
    }
    let most = if options.instanced { MAX_INSTANCED_TRIANGLES } else { MAX_SCENE_TRIANGLES };
    if options.triangles > most {
        return Err(format!(
            "--triangles {}: a scene may have at most {most} triangles{}",
            options.triangles,
            { if options.instanced { "" } else { "; --instanced (forest) places more" } }
        ));
    }
    Ok(())
}

/// The scene built holds and places no more triangles, and no more instances per object, than a
/// scene may: the count may exceed the request by the tolerance.
pub(super) fn check_scene(scene: &GeneratedScene, options: &GenerateOptions) -> Result<(), String> {
    let held: u64 = scene.objects.iter().map(|o| o.mesh.triangles.len() as u64).sum();
    let placed = scene.triangle_count();
    let too_many = |count: u64, most: u64, what: &str| {
        format!(
            "--triangles {}: the scene generated {what} {count} triangles, over the {most} a scene may; ask \
             for fewer",
            options.triangles
        )
    };
    if held > MAX_SCENE_TRIANGLES {
        return Err(too_many(held, MAX_SCENE_TRIANGLES, "holds"));
    }
    if placed > MAX_INSTANCED_TRIANGLES {
        return Err(too_many(placed, MAX_INSTANCED_TRIANGLES, "places"));
    }
    if let Some(object) = scene.objects.iter().find(|o| o.instances.len() as u64 > MAX_INSTANCES) {
        return Err(format!(
            "--triangles {}: object {} would have {} instances, over the {MAX_INSTANCES} an object may have",
            options.triangles,
            object.name,
            object.instances.len()
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn options(width_px: u32, height_px: u32, triangles: u64, instanced: bool) -> GenerateOptions {
        GenerateOptions { kind: SceneKind::Forest, triangles, seed: 1, width_px, height_px, instanced }
    }

    #[test]
    fn generate_options_are_checked_against_the_loaders_limits() {
        assert!(check_options(&options(1920, 1080, 5000, false)).is_ok());
        assert!(check_options(&options(16384, 4096, MAX_SCENE_TRIANGLES, false)).is_ok());
        assert!(check_options(&options(16384, 4097, 5000, false)).unwrap_err().starts_with("--image"));
        assert!(check_options(&options(16385, 1, 5000, false)).unwrap_err().starts_with("--image"));
        assert!(check_options(&options(0, 720, 5000, false)).unwrap_err().starts_with("--image"));
        let over = check_options(&options(640, 480, MAX_SCENE_TRIANGLES + 1, false)).unwrap_err();
        assert!(over.starts_with("--triangles"), "{over}");
        assert!(check_options(&options(640, 480, MAX_SCENE_TRIANGLES + 1, true)).is_ok());
        let city = GenerateOptions { kind: SceneKind::City, ..options(640, 480, 5000, true) };
        assert!(check_options(&city).unwrap_err().starts_with("--instanced"));
    }

    /// Refused options leave nothing behind: not even the output folder.
    #[test]
    fn refused_options_write_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("generated");
        let error = super::super::write_generated(&out, &options(16384, 4097, 5000, false)).unwrap_err();
        assert!(error.to_string().starts_with("--image 16384,4097"), "{error}");
        assert!(!out.exists());
    }
}
