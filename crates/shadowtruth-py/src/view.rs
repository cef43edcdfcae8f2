//! Cameras and lights by name, the first of the scene when none is named, refused with the
//! command's wording (the file, the name, and the names the scene has).

use pyo3::PyResult;
use pyo3::exceptions::PyValueError;
use shadowtruth::{Camera, Light, Scene};

/// Camera `name` of `scene`, or its first camera.
pub fn camera<'s>(scene: &'s Scene, name: Option<&str>) -> PyResult<&'s Camera> {
    named(scene, &scene.cameras, name, |c| &c.name, "camera")
}

/// Light `name` of `scene`, or its first light.
pub fn light<'s>(scene: &'s Scene, name: Option<&str>) -> PyResult<&'s Light> {
    named(scene, &scene.lights, name, |l| &l.name, "light")
}

fn named<'s, T>(
    scene: &Scene,
    items: &'s [T],
    name: Option<&str>,
    name_of: impl Fn(&T) -> &str,
    what: &str,
) -> PyResult<&'s T> {
    let file = scene.source.display();
    let found = match name {
        Some(n) => items.iter().find(|item| name_of(item) == n),
        None => items.first(),
    };
    found.ok_or_else(|| {
        PyValueError::new_err(match name {
            Some(n) => {
                let have: Vec<&str> = items.iter().map(&name_of).collect();
                format!("{file}: no {what} named '{n}' (have: {})", have.join(", "))
            }
            None => format!("{file}: {}", shadowtruth::scene::missing_view_item(&scene.source, what)),
        })
    })
}
