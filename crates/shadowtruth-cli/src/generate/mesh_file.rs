//! The mesh files of a generated scene. One function writes an object's mesh and returns the
//! name the scene file gives it, so that the format can change in one place.

use rayon::prelude::*;
use shadowtruth::scene::IndexedMesh;
use std::fmt::Write as _;
use std::path::Path;

/// Vertices or triangles formatted per parallel chunk (the text is the same whatever the
/// thread count: chunks are joined in order).
const CHUNK: usize = 1 << 16;

/// Writes `mesh` into `dir` as `<name>.obj` (atomically) and returns that file name.
pub(super) fn write_mesh(dir: &Path, name: &str, mesh: &IndexedMesh) -> std::io::Result<String> {
    let file = format!("{name}.obj");
    shadowtruth::atomic_file::write_atomic(&dir.join(&file), obj_text(name, mesh).as_bytes())?;
    Ok(file)
}

/// Wavefront OBJ: one `o` group, `v` records rounded to f32 (printed so that they read back as
/// the same f32), 1-based `f` records.
fn obj_text(name: &str, mesh: &IndexedMesh) -> String {
    let vertices: Vec<String> = mesh
        .positions
        .par_chunks(CHUNK)
        .map(|chunk| {
            let mut s = String::with_capacity(chunk.len() * 32);
            for p in chunk {
                let p = p.as_vec3();
                let _ = writeln!(s, "v {} {} {}", p.x, p.y, p.z);
            }
            s
        })
        .collect();
    let faces: Vec<String> = mesh
        .triangles
        .par_chunks(CHUNK)
        .map(|chunk| {
            let mut s = String::with_capacity(chunk.len() * 24);
            for t in chunk {
                let _ = writeln!(s, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
            }
            s
        })
        .collect();
    let mut out = format!("# shadowtruth generate\no {name}\n");
    out.reserve(vertices.iter().chain(&faces).map(String::len).sum());
    vertices.iter().chain(&faces).for_each(|s| out.push_str(s));
    out
}
