//! The world-space OBJ of a scene (`shadowtruth export-obj`).

use shadowtruth::atomic_file::write_atomic;
use shadowtruth::scene::Scene;
use std::fmt::Write as _;
use std::path::Path;

/// The scene's world-space triangles as OBJ text: one `o` group per object. Coordinates are
/// printed as the shortest decimal of the exact f64 value of each f32, so that a reader parsing
/// them as f32, or as f64 then rounding to f32, gets the same bits back.
pub fn world_obj(scene: &Scene) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "# {} — world-space triangles written by shadowtruth", scene.name);
    let mut next_vertex = 1usize;
    for (index, object) in scene.objects.iter().enumerate() {
        let _ = writeln!(out, "o {}", object.name.replace(char::is_whitespace, "_"));
        for tri in scene.object_triangles(index) {
            for v in tri {
                let _ = writeln!(out, "v {} {} {}", v.x as f64, v.y as f64, v.z as f64);
            }
            let _ = writeln!(out, "f {} {} {}", next_vertex, next_vertex + 1, next_vertex + 2);
            next_vertex += 3;
        }
    }
    out
}

pub fn write_world_obj(scene: &Scene, path: &Path) -> std::io::Result<()> {
    write_atomic(path, world_obj(scene).as_bytes())
}
