//! Wavefront OBJ meshes (positions only), read with `tobj`. All the models of one file form one
//! mesh.

use super::mesh_cache::{SourceKey, read_cached, write_cached};
use super::shapes::IndexedMesh;
use glam::DVec3;
use std::io::Cursor;
use std::path::Path;

/// How many bad vertices are listed before the rest are only counted.
const MAX_LISTED: usize = 5;

/// The largest OBJ file read: one of the most triangles a scene may hold (`MAX_SCENE_TRIANGLES`),
/// with normals and texture coordinates at full precision, takes about 2 GB.
const MAX_OBJ_BYTES: u64 = 4 << 30;

/// Reads the OBJ file `relative`, a path written in a scene file, inside `folder`, the scene's
/// folder (`input_file::open_inside`: no path out of it, regular files only), from its binary
/// cache when that is intact and up to date (mesh_cache.rs), else by parsing it (and caching a
/// large one). Errors are messages that name the file.
pub(crate) fn read_obj(folder: &Path, relative: &str) -> Result<IndexedMesh, Vec<String>> {
    let inside = crate::input_file::open_inside(folder, relative).map_err(|m| vec![m])?;
    let path = inside.path.as_path();
    if inside.len_bytes > MAX_OBJ_BYTES {
        return Err(vec![format!(
            "mesh {} is {} bytes, more than the {MAX_OBJ_BYTES} read",
            path.display(),
            inside.len_bytes
        )]);
    }
    let key = SourceKey::of(path);
    if let Some(mesh) = key.and_then(|k| read_cached(path, k)) {
        return Ok(mesh);
    }
    let mut bytes = Vec::with_capacity(inside.len_bytes as usize);
    std::io::Read::read_to_end(&mut std::io::Read::take(inside.file, MAX_OBJ_BYTES), &mut bytes)
        .map_err(|e| vec![format!("cannot read mesh {}: {e}", path.display())])?;
    let mesh = parse_obj(&bytes, &path.display().to_string())?;
    // The key read before the text: an OBJ rewritten meanwhile gets a cache that never matches.
    if let Some(k) = key {
        write_cached(path, k, &mesh);
    }
    Ok(mesh)
}

/// Parses OBJ text held in memory; `shown` names the mesh in errors. `read_obj` reads through
/// here, and so does the fuzzer (src/fuzzing/).
pub fn parse_obj(bytes: &[u8], shown: &str) -> Result<IndexedMesh, Vec<String>> {
    let text = String::from_utf8_lossy(bytes);
    let bad = non_finite_vertices(&text);
    if !bad.is_empty() {
        return Err(bad.into_iter().map(|m| format!("mesh {shown}: {m}")).collect());
    }
    let positions = positions_only(&text);
    // The update keeps compiling when tobj features add option fields.
    #[allow(clippy::needless_update)]
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    // Materials are irrelevant to shadows: never open them.
    let no_materials = |_: &Path| Err(tobj::LoadError::OpenFileFailed);
    let (models, _) = tobj::load_obj_buf(&mut Cursor::new(positions.as_bytes()), &options, no_materials)
        .map_err(|e| vec![format!("cannot parse mesh {shown}: {e}")])?;

    let mut mesh = IndexedMesh::default();
    for model in &models {
        let first = mesh.positions.len();
        let base = u32::try_from(first).map_err(|_| vec![format!("mesh {shown} is too large")])?;
        for p in model.mesh.positions.chunks_exact(3) {
            let p = DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64);
            if !p.is_finite() {
                // The text scan above should have caught it; never let it through.
                return Err(vec![format!("mesh {shown}: non-finite vertex in `{}`", model.name)]);
            }
            mesh.positions.push(p);
        }
        let count = mesh.positions.len() - first;
        for t in model.mesh.indices.chunks_exact(3) {
            if t.iter().any(|&i| i as usize >= count) {
                return Err(vec![format!("mesh {shown}: face index out of range")]);
            }
            mesh.triangles.push([base + t[0], base + t[1], base + t[2]]);
        }
    }
    Ok(mesh)
}

/// The OBJ text with texture coordinates and normals left out (`vt` and `vn` records, and the
/// `/vt/vn` parts of face vertices): only positions matter to shadows, and tobj's handling of
/// texture-coordinate indices overflows on hostile input.
fn positions_only(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for line in text.lines() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("vt" | "vn") => continue,
            Some("f") => {
                out.push('f');
                for vertex in words {
                    out.push(' ');
                    out.push_str(vertex.split('/').next().unwrap_or(vertex));
                }
            }
            _ => out.push_str(line),
        }
        out.push('\n');
    }
    out
}

/// Finds `v` records with NaN or infinite coordinates (Rust's float parser, like tobj's,
/// accepts `nan`, `inf` and overflowing exponents), naming their 1-based OBJ vertex index.
fn non_finite_vertices(text: &str) -> Vec<String> {
    let mut found = Vec::new();
    let mut index = 0usize;
    for (line_no, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        if words.next() != Some("v") {
            continue;
        }
        index += 1;
        let non_finite = words.take(3).any(|w| w.parse::<f32>().is_ok_and(|x| !x.is_finite()));
        if non_finite {
            found.push((index, line_no + 1, line.trim()));
        }
    }
    let mut messages: Vec<String> = found
        .iter()
        .take(MAX_LISTED)
        .map(|(i, l, text)| format!("vertex {i} (line {l}) has a non-finite coordinate: `{text}`"))
        .collect();
    if found.len() > MAX_LISTED {
        messages.push(format!("{} more vertices have non-finite coordinates", found.len() - MAX_LISTED));
    }
    messages
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texture_and_normal_indices_are_left_out() {
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/-11 2/2/1 3//1\n";
        assert_eq!(positions_only(text), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        let mesh = parse_obj(text.as_bytes(), "t.obj").expect("positions are enough");
        assert_eq!(mesh.triangles, vec![[0, 1, 2]]);
    }

    #[test]
    fn scene_obj_non_finite_vertices_are_named() {
        let text = "# x\nv 0 0 0\nv nan 1 2\nv 1 1e39 0\nvn 0 inf 0\nf 1 2 3\n";
        let found = non_finite_vertices(text);
        assert_eq!(found.len(), 2);
        assert!(found[0].starts_with("vertex 2 (line 3)"), "{found:?}");
        assert!(found[1].starts_with("vertex 3 (line 4)"), "{found:?}");
    }
}
