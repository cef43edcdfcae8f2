//! Scenes: the `shadowtruth/scene/v1` file format, its validation, OBJ meshes, procedural shapes,
//! cameras and lights. The output is a `Scene` of world-space triangles that every later stage reads.

mod budget;
mod camera;
mod cascade_settings;
mod error;
mod format;
mod format_write;
mod gltf;
mod instance;
mod light;
mod load;
mod load_gltf;
mod mesh_cache;
mod missing_view_item;
mod obj;
mod path;
mod path_format;
mod pixel_footprint;
mod placement;
mod point_map;
mod shapes;
mod transform;
mod triangle_cursor;
mod triangles;
mod view_key;

pub use camera::{Camera, Film, FilmRow};
pub use cascade_settings::{CascadeFit, CascadeSettings, MAX_CASCADES, SplitScheme};
pub use error::{Problem, SceneError};
pub use format::{
    Geometry, MAX_IMAGE_PIXELS, MAX_IMAGE_SIDE, MAX_INSTANCED_TRIANGLES, MAX_INSTANCES, MAX_SCENE_TRIANGLES,
};
pub use format_write::{ObjectPlacement, SceneFile, SceneFileObject, UnwritableScene};
pub use instance::{Instance, SharedMesh, box_corners, is_degenerate, world_vertex};
pub use light::{Light, LightKind, LightSize, NoLightSize};
pub use load::load_scene_str_within;
pub use load::{load_scene, load_scene_str};
pub use load_gltf::load_gltf_within;
pub use mesh_cache::{MESH_CACHE_DIR, MIN_CACHED_BYTES, mesh_cache_path};
pub use missing_view_item::missing_view_item;
pub use obj::parse_obj;
pub use path::{CameraPath, Interpolation, Keyframes, LightPath, frame_times, union_span};
pub use pixel_footprint::PixelFootprint;
pub use point_map::{CubeSettings, MAX_GUARD_TEXELS, PointMap};
pub use shapes::{IndexedMesh, Shape};
pub use transform::Transform;
pub use triangle_cursor::TriangleCursor;
pub use triangles::TriangleSource;
pub use view_key::ViewKey;

use glam::Vec3;

/// The format tag every scene file carries.
pub const SCENE_FORMAT: &str = "shadowtruth/scene/v1";

/// One object of a scene: a contiguous range of scene triangle ids (`Scene::triangle`). A
/// flattened object's range lies in `flat_triangles`; an instance's is its own.
#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    pub name: String,
    /// A solid whose back faces may be culled from the light's view; open objects are two-sided.
    pub closed: bool,
    pub first_triangle: u32,
    pub triangle_count: u32,
}

/// A loaded, validated scene in world space.
#[derive(Clone, Debug)]
pub struct Scene {
    pub name: String,
    /// The file it was read from (empty for scenes built in memory).
    pub source: std::path::PathBuf,
    pub objects: Vec<Object>,
    /// World-space triangles stored one by one, counter-clockwise seen from the outside of
    /// closed objects: scene triangle ids `0 .. flat_triangles.len()`. Degenerate triangles (zero
    /// area in f32) are already dropped.
    pub flat_triangles: Vec<[Vec3; 3]>,
    /// Object index of every flat triangle.
    pub flat_triangle_object: Vec<u32>,
    /// Meshes stored once and placed by `instances` (src/scene/instance.rs).
    pub meshes: Vec<SharedMesh>,
    /// The placements of `meshes`, whose triangle ids follow the flat ones in this order.
    pub instances: Vec<Instance>,
    pub cameras: Vec<Camera>,
    pub lights: Vec<Light>,
    /// Degenerate triangles dropped while loading, per the whole scene.
    pub dropped_degenerate: usize,
}

impl Scene {
    /// Axis-aligned bounds (min, max) of all triangles.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        use rayon::prelude::*;
        let empty = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        let grow = |(lo, hi): (Vec3, Vec3), tri: &[Vec3; 3]| {
            tri.iter().fold((lo, hi), |(lo, hi), v| (lo.min(*v), hi.max(*v)))
        };
        let join = |a: (Vec3, Vec3), b: (Vec3, Vec3)| (a.0.min(b.0), a.1.max(b.1));
        // min and max are exact, so the split into chunks never changes the bounds.
        let flat = self
            .flat_triangles
            .par_chunks(1 << 16)
            .map(|chunk| chunk.iter().fold(empty, grow))
            .reduce(|| empty, join);
        let instanced = self
            .instances
            .par_iter()
            .map(|instance| {
                let mesh = &self.meshes[instance.mesh as usize];
                (0..mesh.triangles.len())
                    .filter_map(|local| instance.world_triangle(mesh, local))
                    .fold(empty, |b, tri| grow(b, &tri))
            })
            .reduce(|| empty, join);
        join(flat, instanced)
    }

    /// A scene without geometry yet.
    pub(crate) fn empty(
        name: String,
        source: &std::path::Path,
        cameras: Vec<Camera>,
        lights: Vec<Light>,
    ) -> Self {
        Scene {
            name,
            source: source.to_path_buf(),
            objects: Vec::new(),
            flat_triangles: Vec::new(),
            flat_triangle_object: Vec::new(),
            meshes: Vec::new(),
            instances: Vec::new(),
            cameras,
            lights,
            dropped_degenerate: 0,
        }
    }

    pub fn camera(&self, name: &str) -> Option<&Camera> {
        self.cameras.iter().find(|c| c.name == name)
    }

    pub fn light(&self, name: &str) -> Option<&Light> {
        self.lights.iter().find(|l| l.name == name)
    }

    /// A stable digest of the scene's geometry (triangle bits, object flags): what a reference
    /// depends on besides its camera and light. Independent of file formatting.
    pub fn geometry_digest(&self) -> String {
        use sha2::{Digest, Sha256};
        let mut h = Sha256::new();
        for o in &self.objects {
            h.update(o.name.as_bytes());
            h.update([o.closed as u8]);
            h.update(o.first_triangle.to_le_bytes());
            h.update(o.triangle_count.to_le_bytes());
        }
        for tri in &self.flat_triangles {
            for v in tri {
                for c in v.to_array() {
                    h.update(c.to_bits().to_le_bytes());
                }
            }
        }
        // Instanced geometry by its meshes and placements; a scene without it keeps the digest
        // it always had.
        for mesh in &self.meshes {
            h.update((mesh.positions.len() as u64).to_le_bytes());
            for c in mesh.positions.iter().flat_map(|p| p.to_array()) {
                h.update(c.to_bits().to_le_bytes());
            }
            for i in mesh.triangles.iter().flatten() {
                h.update(i.to_le_bytes());
            }
        }
        for instance in &self.instances {
            h.update(instance.mesh.to_le_bytes());
            for c in instance.world_from_local.to_cols_array() {
                h.update(c.to_bits().to_le_bytes());
            }
        }
        hex(&h.finalize())
    }
}

pub fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}
