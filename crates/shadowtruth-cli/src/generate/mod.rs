//! `shadowtruth generate`: procedural scenes of a requested size for measuring scale, built
//! deterministically from a seed (SplitMix64, src/trace/splitmix.rs). A `city` is a terrain with
//! closed buildings of varied heights; a `forest` a terrain with closed trees. Each is written as
//! a scene folder: `scene.json` and one mesh file per object (`mesh_file.rs`).

mod city;
mod count;
mod forest;
mod loadable;
pub(crate) use loadable::check_options;
mod mesh_file;
mod scene_file;
mod terrain;

pub(crate) use count::parse_triangle_count;

use shadowtruth::scene::{IndexedMesh, Transform};
use std::path::{Path, PathBuf};

/// The name of the scene file written into the output folder.
pub(crate) const SCENE_FILE: &str = "scene.json";

/// How far the generated triangle count may be from the request, as a fraction of it (for
/// requests of at least `MIN_COUNT_FOR_TOLERANCE` triangles).
pub(crate) const COUNT_TOLERANCE: f64 = 0.02;
/// Below this request the tolerance is not promised: buildings and trees come in whole units.
pub(crate) const MIN_COUNT_FOR_TOLERANCE: u64 = 20_000;
/// The smallest request accepted: a terrain and a few casters.
pub(crate) const MIN_TRIANGLES: u64 = 1_000;

/// What kind of scene to generate.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum SceneKind {
    /// Terrain and closed buildings of varied heights in blocks.
    City,
    /// Terrain and closed trees (trunk and crown).
    Forest,
}

/// The request: kind, triangle count, seed and the camera's image size.
#[derive(Clone, Copy, Debug)]
pub(crate) struct GenerateOptions {
    pub kind: SceneKind,
    pub triangles: u64,
    pub seed: u64,
    pub width_px: u32,
    pub height_px: u32,
    /// A forest of one tree mesh placed at every tree by `instances` (src/scene/instance.rs).
    pub instanced: bool,
}

/// One object of a generated scene: its name, mesh, whether it is a closed solid, and its
/// placements when it is instanced (none: the mesh stands where it is).
pub(crate) struct GeneratedObject {
    pub name: &'static str,
    pub mesh: IndexedMesh,
    pub closed: bool,
    pub instances: Vec<Transform>,
}

/// A generated scene before it is written: objects, the side of the square ground in metres,
/// and the height of its tallest caster.
pub(crate) struct GeneratedScene {
    pub objects: Vec<GeneratedObject>,
    pub ground_size_m: f64,
    pub top_m: f64,
}

impl GeneratedScene {
    /// Triangles numbered: every placement of an instanced mesh counts.
    pub fn triangle_count(&self) -> u64 {
        self.objects.iter().map(|o| o.mesh.triangles.len() as u64 * o.instances.len().max(1) as u64).sum()
    }
}

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
