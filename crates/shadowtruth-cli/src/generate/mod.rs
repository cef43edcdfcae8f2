//! `shadowtruth generate`: procedural scenes of a requested size for measuring scale, built
//! deterministically from a seed (SplitMix64, src/trace/splitmix.rs). A `city` is a terrain with
//! closed buildings of varied heights; a `forest` a terrain with closed trees. Each is written as
//! a scene folder: `scene.json` and one mesh file per object (`mesh_file.rs`).

mod city;
mod count;
mod forest;
mod generated;
mod loadable;
mod mesh_file;
mod request;
mod scene_file;
mod terrain;

pub(crate) use count::parse_triangle_count;
pub(crate) use generated::GeneratedScene;
pub(crate) use loadable::check_options;
pub(crate) use request::{COUNT_TOLERANCE, GenerateOptions, MIN_COUNT_FOR_TOLERANCE, SceneKind};

use std::path::{Path, PathBuf};

/// The name of the scene file written into the output folder.
pub(crate) const SCENE_FILE: &str = "scene.json";

/// Builds the scene of `options` in memory.
pub(crate) fn generate(options: &GenerateOptions) -> GeneratedScene {
    match options.kind {
        SceneKind::City => city::generate_city(options.triangles, options.seed),
        SceneKind::Forest if options.instanced => {
            forest::generate_instanced_forest(options.triangles, options.seed)
        }
        SceneKind::Forest => forest::generate_forest(options.triangles, options.seed),
    }
}

/// Generates and writes the scene folder `dir` (created if missing): the mesh files first, then
/// `scene.json`, each atomically, so that the scene never names a mesh that is not there yet.
/// Returns the scene file's path and the triangle count.
/// Options or a scene the loader would refuse are an `InvalidInput` error naming the option,
/// before anything is written (`loadable.rs`).
pub(crate) fn write_generated(dir: &Path, options: &GenerateOptions) -> std::io::Result<(PathBuf, u64)> {
    let refused = |m: String| std::io::Error::new(std::io::ErrorKind::InvalidInput, m);
    loadable::check_options(options).map_err(refused)?;
    let scene = generate(options);
    loadable::check_scene(&scene, options).map_err(refused)?;
    std::fs::create_dir_all(dir)?;
    let off = scene.triangle_count().abs_diff(options.triangles) as f64 / options.triangles as f64;
    debug_assert!(options.triangles < MIN_COUNT_FOR_TOLERANCE || off <= COUNT_TOLERANCE, "{off}");
    let mut files = Vec::new();
    for object in &scene.objects {
        files.push(mesh_file::write_mesh(dir, object.name, &object.mesh)?);
    }
    let text = scene_file::scene_json(options, &scene, &files);
    let path = dir.join(SCENE_FILE);
    shadowtruth::atomic_file::write_atomic(&path, text.as_bytes())?;
    Ok((path, scene.triangle_count()))
}
