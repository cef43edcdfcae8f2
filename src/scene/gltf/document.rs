//! Opening a glTF file: the bytes, the JSON (inside a GLB container or not) and the crate's
//! validation, whose errors come with their JSON paths.

use super::GltfProblem;
use gltf::json::validation::Error as Invalid;
use std::path::Path;

/// The parsed and validated document with its GLB binary chunk, if any.
pub(super) fn open(path: &Path) -> Result<gltf::Gltf, Vec<GltfProblem>> {
    let bytes =
        std::fs::read(path).map_err(|e| vec![GltfProblem::new("", format!("cannot read glTF file: {e}"))])?;
    match gltf::Gltf::from_slice(&bytes) {
        Ok(gltf) => Ok(gltf),
        Err(gltf::Error::Validation(list)) => {
            Err(list.into_iter().map(|(at, e)| GltfProblem::new(at.to_string(), describe(&e))).collect())
        }
        Err(e) => Err(vec![unreadable(e)]),
    }
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
