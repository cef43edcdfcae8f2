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
}
