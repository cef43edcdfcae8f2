//! The bytes of every glTF buffer: the GLB binary chunk, an embedded `data:` URI or a file next
//! to the glTF. Problems name the buffer (`buffers[0].uri`) and the file.

use super::GltfProblem;
use super::data_uri::{decode_data_uri, percent_decode};
use gltf::buffer::Source;
use std::path::Path;

/// One byte vector per buffer of the document, in order, each at least `byteLength` long.
pub(super) fn load(gltf: &mut gltf::Gltf, path: &Path) -> Result<Vec<Vec<u8>>, Vec<GltfProblem>> {
    let base = path.parent().unwrap_or(Path::new(""));
    let mut blob = gltf.blob.take();
    let mut problems = Vec::new();
    let mut out = Vec::new();
    for buffer in gltf.document.buffers() {
        let at = format!("buffers[{}]", buffer.index());
        let data = match buffer.source() {
            // Only the first buffer may be the binary chunk; moved, not copied.
            Source::Bin => blob.take().ok_or_else(|| {
                GltfProblem::new(&at, "refers to the GLB binary chunk, which is missing (or already used)")
            }),
            Source::Uri(uri) => from_uri(uri, base).map_err(|m| GltfProblem::new(format!("{at}.uri"), m)),
        };
        match data {
            Ok(data) if data.len() < buffer.length() => problems.push(GltfProblem::new(
                format!("{at}.byteLength"),
                format!("is {} but the buffer holds only {} bytes", buffer.length(), data.len()),
            )),
            Ok(data) => out.push(data),
            Err(p) => problems.push(p),
        }
    }
    if problems.is_empty() { Ok(out) } else { Err(problems) }
}

/// An embedded buffer, or a file relative to the glTF's folder.
fn from_uri(uri: &str, base: &Path) -> Result<Vec<u8>, String> {
    if uri.starts_with("data:") {
        return decode_data_uri(uri).map_err(|e| format!("embedded buffer: {e}"));
    }
    if let Some((scheme, _)) = uri.split_once(':')
        && scheme.len() > 1
        && scheme.chars().all(|c| c.is_ascii_alphanumeric() || "+-.".contains(c))
    {
        return Err(format!("\"{uri}\": only relative file paths and data: URIs are supported"));
    }
    let file = base.join(percent_decode(uri)?);
    std::fs::read(&file).map_err(|e| format!("cannot read buffer file {}: {e}", file.display()))
}
