//! glTF meshes as `IndexedMesh`es: every triangle primitive of a mesh in one vertex list.
//! Accessors are checked against their buffer views and buffers (with overflow-checked
//! arithmetic) before the crate's reader walks the buffer slices, so bad offsets are problems
//! rather than panics or short reads; triangle counts are known, and bounded, before any mesh is
//! read.

use super::placed_mesh::PlacedMesh;
use super::problem::GltfProblem;
use crate::scene::placement::Placement;
use crate::scene::shapes::IndexedMesh;
use glam::DVec3;
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;
use std::collections::HashMap;

/// A triangle primitive, checked and ready to read.
struct Primitive<'a> {
    gltf: gltf::Primitive<'a>,
    /// `meshes[m].primitives[p]`.
    path: String,
    mode: Mode,
    triangles: u64,
}

/// Reads every placed mesh, after checking that the meshes together (each once, however many
/// nodes place it) have at most `max_triangles` triangles.
pub(super) fn read_placed(
    document: &gltf::Document,
    buffers: &[Vec<u8>],
    placed: Vec<(usize, Vec<Placement>)>,
    max_triangles: u64,
    problems: &mut Vec<GltfProblem>,
) -> Vec<PlacedMesh> {
    let meshes: Vec<gltf::Mesh> = document.meshes().collect();
    let mut planned = Vec::new();
    let mut total: u64 = 0;
    for (index, placements) in placed {
        let Some(mesh) = meshes.get(index) else { continue };
        let Some(primitives) = plan_mesh(mesh, buffers, problems) else { continue };
        let count: u64 = primitives.iter().map(|p| p.triangles).sum();
        let before = total;
        // A mesh is held once however many nodes place it (src/scene/placement.rs).
        total = total.saturating_add(count);
        if total > max_triangles {
            if before <= max_triangles {
                let message = format!(
                    "its {count} triangles bring the file's meshes to {total} triangles, over the \
                     {max_triangles} the scene has room for"
                );
                problems.push(GltfProblem::new(format!("meshes[{index}]"), message));
            }
            continue;
        }
        planned.push((index, primitives, placements));
    }
    if !problems.is_empty() {
        return Vec::new();
    }
    let mut out = Vec::with_capacity(planned.len());
    for (index, primitives, placements) in planned {
        match read_mesh(&primitives, buffers) {
            Ok(mesh) => out.push(PlacedMesh { mesh, path: format!("meshes[{index}]"), placements }),
            Err(p) => problems.push(p),
        }
    }
    out
}

/// The mesh's triangle primitives, checked; `None` when any is refused (reported).
fn plan_mesh<'a>(
    mesh: &gltf::Mesh<'a>,
    buffers: &[Vec<u8>],
    problems: &mut Vec<GltfProblem>,
) -> Option<Vec<Primitive<'a>>> {
    let mut out = Vec::new();
    let mut ok = true;
    for primitive in mesh.primitives() {
        let path = format!("meshes[{}].primitives[{}]", mesh.index(), primitive.index());
        match plan_primitive(primitive, path, buffers) {
            Ok(Some(p)) => out.push(p),
            Ok(None) => {}
            Err(p) => {
                problems.push(p);
                ok = false;
            }
        }
    }
    ok.then_some(out)
}

/// A primitive's mode, accessors and triangle count; `None` for one without triangles.
fn plan_primitive<'a>(
    primitive: gltf::Primitive<'a>,
    path: String,
    buffers: &[Vec<u8>],
) -> Result<Option<Primitive<'a>>, GltfProblem> {
    let mode = primitive.mode();
    if !matches!(mode, Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
        let message = format!(
            "mode {mode:?} ({}): only triangles (TRIANGLES, TRIANGLE_STRIP, TRIANGLE_FAN) are supported",
            mode.as_gl_enum()
        );
        return Err(GltfProblem::new(format!("{path}.mode"), message));
    }
    let Some(positions) = primitive.get(&gltf::Semantic::Positions) else {
        // glTF: a primitive without positions is not drawn.
        return Ok(None);
    };
    let indices = primitive.indices();
    let corners = indices.as_ref().map_or(positions.count(), |i| i.count()) as u64;
    let triangles = match mode {
        Mode::Triangles if !corners.is_multiple_of(3) => {
            let at = if indices.is_some() { "indices" } else { "attributes.POSITION" };
            let message = format!("has {corners} triangle corners, not a multiple of 3");
            return Err(GltfProblem::new(format!("{path}.{at}"), message));
        }
        Mode::Triangles => corners / 3,
        _ => corners.saturating_sub(2),
    };
    if triangles == 0 {
        return Ok(None);
    }
    check_accessor(&positions, buffers, &[DataType::F32], Dimensions::Vec3)?;
    if let Some(indices) = &indices {
        check_accessor(indices, buffers, &[DataType::U8, DataType::U16, DataType::U32], Dimensions::Scalar)?;
    }
    Ok(Some(Primitive { gltf: primitive, path, mode, triangles }))
}

/// The accessor's type, and that all its elements lie inside its buffer view and the view inside
/// its buffer's bytes.
fn check_accessor(
    accessor: &gltf::Accessor,
    buffers: &[Vec<u8>],
    types: &[DataType],
    dimensions: Dimensions,
) -> Result<(), GltfProblem> {
    let at = format!("accessors[{}]", accessor.index());
    let problem = |key: &str, message: String| Err(GltfProblem::new(format!("{at}{key}"), message));
    if !types.contains(&accessor.data_type()) || accessor.dimensions() != dimensions || accessor.normalized()
    {
        let (ty, dims) = (accessor.data_type(), accessor.dimensions());
        return problem("", format!("is {dims:?} of {ty:?}; expected {dimensions:?} of one of {types:?}"));
    }
    if accessor.sparse().is_some() {
        return problem(".sparse", "sparse accessors are not supported".into());
    }
    let Some(view) = accessor.view() else {
        return problem("", "has no bufferView (all zeros): not supported".into());
    };
    let element = accessor.size();
    let stride = view.stride().unwrap_or(element);
    if stride < element {
        return problem(
            "",
            format!("its buffer view's byteStride {stride} is below its element size {element}"),
        );
    }
    let end = (accessor.count().checked_sub(1))
        .and_then(|last| last.checked_mul(stride))
        .and_then(|x| x.checked_add(element))
        .and_then(|x| x.checked_add(accessor.offset()));
    if end.is_none_or(|end| end > view.length()) {
        return problem(
            "",
            format!("its {} elements run past the end of bufferViews[{}]", accessor.count(), view.index()),
        );
    }
    let buffer_len = buffers.get(view.buffer().index()).map_or(0, Vec::len);
    if view.offset().checked_add(view.length()).is_none_or(|end| end > buffer_len) {
        let message = format!("runs past the end of buffers[{}] ({buffer_len} bytes)", view.buffer().index());
        return Err(GltfProblem::new(format!("bufferViews[{}]", view.index()), message));
    }
    Ok(())
}

/// Reads a mesh's primitives into one vertex list (primitives that share a POSITION accessor
/// share its vertices); indices are checked against their primitive's vertex count.
fn read_mesh(primitives: &[Primitive], buffers: &[Vec<u8>]) -> Result<IndexedMesh, GltfProblem> {
    let triangles: u64 = primitives.iter().map(|p| p.triangles).sum();
    let mut mesh = IndexedMesh { positions: Vec::new(), triangles: Vec::with_capacity(triangles as usize) };
    // POSITION accessor index → (first vertex in `mesh`, vertex count).
    let mut read: HashMap<usize, (u32, usize)> = HashMap::new();
    for primitive in primitives {
        let reader = primitive.gltf.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
        let accessor = primitive.gltf.get(&gltf::Semantic::Positions).map_or(usize::MAX, |a| a.index());
        let (base, count) = match read.get(&accessor) {
            Some(&known) => known,
            None => {
                let known = read_positions(&reader, &mut mesh.positions, &primitive.path)?;
                read.insert(accessor, known);
                known
            }
        };
        let indices: Vec<u32> = match reader.read_indices() {
            Some(indices) => indices.into_u32().collect(),
            None => (0..count as u32).collect(),
        };
        if let Some(k) = indices.iter().position(|&i| i as usize >= count) {
            let message = format!("index {} at position {k} is out of range ({count} vertices)", indices[k]);
            return Err(GltfProblem::new(format!("{}.indices", primitive.path), message));
        }
        push_triangles(&mut mesh.triangles, primitive.mode, &indices, base);
    }
    Ok(mesh)
}

/// Appends a primitive's positions (f32 in the buffer, widened to f64) straight from its buffer
/// slice; returns the first one's index and their count.
fn read_positions<'a, 's, F>(
    reader: &gltf::mesh::Reader<'a, 's, F>,
    positions: &mut Vec<DVec3>,
    path: &str,
) -> Result<(u32, usize), GltfProblem>
where
    F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
{
    let first = positions.len();
    let too_large = || GltfProblem::new(path, "the mesh has more than 2³² vertices");
    let base = u32::try_from(first).map_err(|_| too_large())?;
    let iter = reader.read_positions().ok_or_else(|| GltfProblem::new(path, "unreadable positions"))?;
    positions.reserve(iter.len());
    for p in iter {
        let p = DVec3::from(p.map(f64::from));
        if !p.is_finite() {
            let message = format!("vertex {} has a non-finite coordinate", positions.len() - first);
            return Err(GltfProblem::new(format!("{path}.attributes.POSITION"), message));
        }
        positions.push(p);
    }
    u32::try_from(positions.len()).map_err(|_| too_large())?;
    Ok((base, positions.len() - first))
}

/// Appends the triangles of a list, strip or fan of corner indices, offset by `base`.
/// Strips alternate their winding so that every triangle keeps the first one's orientation, in
/// the corner order the glTF specification gives (docs/gltf.md).
fn push_triangles(out: &mut Vec<[u32; 3]>, mode: Mode, indices: &[u32], base: u32) {
    let n = indices.len();
    match mode {
        Mode::TriangleStrip => out.extend((0..n.saturating_sub(2)).map(|i| {
            let (a, b, c) = (indices[i], indices[i + 1 + i % 2], indices[i + 2 - i % 2]);
            [base + a, base + b, base + c]
        })),
        Mode::TriangleFan => out.extend(
            (1..n.saturating_sub(1)).map(|i| [base + indices[i], base + indices[i + 1], base + indices[0]]),
        ),
        _ => out.extend(indices.chunks_exact(3).map(|t| [base + t[0], base + t[1], base + t[2]])),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_keep_their_winding() {
        let mut out = Vec::new();
        push_triangles(&mut out, Mode::TriangleStrip, &[0, 1, 2, 3, 4], 10);
        assert_eq!(out, vec![[10, 11, 12], [11, 13, 12], [12, 13, 14]]);
        out.clear();
        push_triangles(&mut out, Mode::TriangleFan, &[0, 1, 2, 3], 0);
        assert_eq!(out, vec![[1, 2, 0], [2, 3, 0]]);
    }
}
