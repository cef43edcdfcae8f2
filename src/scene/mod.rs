//! Scenes: the `shadowtruth/scene/v1` file format, its validation, OBJ meshes, procedural shapes,
//! cameras and lights. The output is a `Scene` of world-space triangles that every later stage reads.

mod camera;
mod error;
mod format;
mod light;
mod load;
mod mesh_cache;
mod obj;
mod shapes;
mod transform;
mod view_key;

pub use camera::Camera;
pub use error::{Problem, SceneError};
pub use light::{Light, LightKind, LightSize, NoLightSize};
pub(crate) use load::load_scene_str_within;
pub use load::{load_scene, load_scene_str};
pub use mesh_cache::{MESH_CACHE_DIR, MIN_CACHED_BYTES, mesh_cache_path};
pub(crate) use obj::parse_obj;
pub use shapes::{IndexedMesh, Shape};
pub use transform::Transform;
pub use view_key::ViewKey;

use glam::Vec3;

/// The format tag every scene file carries.
pub const SCENE_FORMAT: &str = "shadowtruth/scene/v1";

/// One object of a scene: a contiguous range of `Scene::triangles`.
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
    /// World-space triangles, counter-clockwise seen from the outside of closed objects.
    /// Degenerate triangles (zero area in f32) are already dropped.
    pub triangles: Vec<[Vec3; 3]>,
    /// Object index of every triangle.
    pub triangle_object: Vec<u32>,
    pub cameras: Vec<Camera>,
    pub lights: Vec<Light>,
    /// Degenerate triangles dropped while loading, per the whole scene.
    pub dropped_degenerate: usize,
}

impl Scene {
    /// Axis-aligned bounds (min, max) of all triangles.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for tri in &self.triangles {
            for v in tri {
                lo = lo.min(*v);
                hi = hi.max(*v);
            }
        }
        (lo, hi)
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
        for tri in &self.triangles {
            for v in tri {
                for c in v.to_array() {
                    h.update(c.to_bits().to_le_bytes());
                }
            }
        }
        hex(&h.finalize())
    }
}

pub(crate) fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}
