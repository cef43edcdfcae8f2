//! Opening a glTF file: the bytes (within a bound), the JSON (inside a GLB container or not) and
//! the crate's validation, whose errors come with their JSON paths.

use super::buffers::MAX_BUFFER_BYTES;
use super::problem::GltfProblem;
use gltf::json::validation::Error as Invalid;
use std::path::Path;

/// Most bytes of JSON besides a glTF's buffers: as for a scene file, a million nodes with a full
/// transform each take about 200 MB.
const MAX_JSON_BYTES: u64 = 512 << 20;

/// Most bytes of a `.gltf` or `.glb` file read: the buffers' limit as base64 `data:` URIs (four
/// bytes for three), and the JSON.
pub(crate) const MAX_GLTF_FILE_BYTES: u64 = MAX_BUFFER_BYTES / 3 * 4 + MAX_JSON_BYTES;

/// The bytes of the glTF file at `path`, at most `MAX_GLTF_FILE_BYTES` of them.
pub(super) fn read(path: &Path) -> Result<Vec<u8>, Vec<GltfProblem>> {
    crate::input_file::read_named(path, MAX_GLTF_FILE_BYTES)
        .map_err(|m| vec![GltfProblem::new("", format!("glTF file: {m}"))])
}

/// The parsed and validated document of a glTF file's bytes, with its GLB binary chunk, if any.
pub(super) fn parse(bytes: &[u8]) -> Result<gltf::Gltf, Vec<GltfProblem>> {
    let gltf = gltf::Gltf::from_slice_without_validation(bytes).map_err(|e| vec![unreadable(e)])?;
    let root = gltf.document.as_json();
    let mut problems = positions_out_of_bounds(root);
    if problems.is_empty() {
        use gltf::json::validation::Validate;
        root.validate(root, gltf::json::Path::new, &mut |at, e| {
            problems.push(GltfProblem::new(at().to_string(), describe(&e)))
        });
    }
    if problems.is_empty() { Ok(gltf) } else { Err(problems) }
}

/// Primitives whose `POSITION` names an accessor that does not exist. The crate's validation
/// (gltf-json 1.4) indexes the accessors with that index unchecked, and so panics, before it
/// reports the index: it runs only once these are ruled out.
fn positions_out_of_bounds(root: &gltf::json::Root) -> Vec<GltfProblem> {
    use gltf::json::mesh::Semantic;
    use gltf::json::validation::Checked;
    let mut problems = Vec::new();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            if let Some(index) = primitive.attributes.get(&Checked::Valid(Semantic::Positions))
                && index.value() >= root.accessors.len()
            {
                let at = format!("meshes[{m}].primitives[{p}].attributes.POSITION");
                problems.push(GltfProblem::new(at, describe(&Invalid::IndexOutOfBounds)));
            }
        }
    }
    problems
}

fn unreadable(e: gltf::Error) -> GltfProblem {
    let message = match e {
        gltf::Error::Deserialize(e) => format!("malformed glTF JSON: {e}"),
        gltf::Error::Binary(e) => format!("malformed GLB container: {e}"),
        other => format!("cannot read glTF: {other}"),
    };
    GltfProblem::new("", message)
}

fn describe(e: &Invalid) -> String {
    match e {
        Invalid::IndexOutOfBounds => "refers to an index that does not exist".into(),
        Invalid::Invalid => "invalid value".into(),
        Invalid::Missing => "missing required value".into(),
        Invalid::Oversize => "a size or offset beyond this machine's limits".into(),
        Invalid::Unsupported => "requires an extension that is not supported".into(),
    }
}
