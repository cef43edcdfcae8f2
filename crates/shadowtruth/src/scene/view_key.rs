//! The names of one view, a (scene, camera, light) triple: what a reference is stored and
//! looked up under.

use super::{Camera, Light, Scene};

/// A scene's name with the names of one of its cameras and one of its lights.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ViewKey<'a> {
    pub scene: &'a str,
    pub camera: &'a str,
    pub light: &'a str,
}

impl<'a> ViewKey<'a> {
    pub fn new(scene: &'a str, camera: &'a str, light: &'a str) -> Self {
        ViewKey { scene, camera, light }
    }

    pub fn from_view(scene: &'a Scene, camera: &'a Camera, light: &'a Light) -> Self {
        ViewKey::new(&scene.name, &camera.name, &light.name)
    }

    /// The three names, scene first.
    pub fn parts(&self) -> [&'a str; 3] {
        [self.scene, self.camera, self.light]
    }

    /// The stem of every file named after this view (its cached references, its reference
    /// figure): `<scene>.<camera>.<light>.<digest>`, the names filtered and capped, the digest
    /// that of the exact names, whatever they hold (`src/file_name.rs`).
    pub fn file_stem(&self) -> String {
        crate::file_name::stem(&self.parts())
    }
}
