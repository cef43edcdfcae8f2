//! The bytes of every glTF buffer: the GLB binary chunk, an embedded `data:` URI or a file inside
//! the glTF's folder (docs/gltf.md, "Buffers"). Sizes come before reads: the declared lengths of
//! all buffers together first, then each file's metadata (a regular file inside the folder,
//! through `input_file::open_inside`, no longer than any buffer may be and no shorter than its
//! own), then at most `byteLength` bytes through `Read::take`. Problems name the buffer
//! (`buffers[0].uri`) and the file, never the file's bytes.

use super::data_uri::{decode_data_uri, percent_decode};
use super::problem::GltfProblem;
use crate::input_file::open_inside;
use crate::scene::format::MAX_SCENE_TRIANGLES;
use gltf::buffer::Source;
use std::io::Read;
use std::path::Path;

/// Most bytes the buffers of one glTF file may declare together (2 GiB): 128 for each triangle a
/// scene may hold (`MAX_SCENE_TRIANGLES`), room for every triangle with its three corners
/// unshared, each with a position, a normal and a texture coordinate (96 bytes), and its three
/// 32-bit indices (12). A file over it could never become a scene.
pub(crate) const MAX_BUFFER_BYTES: u64 = MAX_SCENE_TRIANGLES * 128;

/// One byte vector per buffer of the document, in order, each at least `byteLength` long; file
/// buffers are read inside `folder` only.
pub(super) fn load(gltf: &mut gltf::Gltf, folder: &Path) -> Result<Vec<Vec<u8>>, Vec<GltfProblem>> {
    check_declared_total(&gltf.document)?;
    let mut blob = gltf.blob.take();
    let mut problems = Vec::new();
    let mut out = Vec::new();
    for buffer in gltf.document.buffers() {
        let at = format!("buffers[{}]", buffer.index());
        let declared = buffer.length() as u64;
        let data = match buffer.source() {
            // Only the first buffer may be the binary chunk; moved, not copied.
            Source::Bin => blob.take().ok_or_else(|| {
                GltfProblem::new(&at, "refers to the GLB binary chunk, which is missing (or already used)")
            }),
            Source::Uri(uri) => {
                from_uri(uri, folder, declared).map_err(|m| GltfProblem::new(format!("{at}.uri"), m))
            }
        };
        match data {
            Ok(data) if (data.len() as u64) < declared => problems.push(GltfProblem::new(
                format!("{at}.byteLength"),
                format!("is {declared} but the buffer holds only {} bytes", data.len()),
            )),
            Ok(data) => out.push(data),
            Err(p) => problems.push(p),
        }
    }
    if problems.is_empty() { Ok(out) } else { Err(problems) }
}

/// The buffers' declared lengths together are at most `MAX_BUFFER_BYTES`: checked before any
/// buffer is read, at the first buffer over the limit.
fn check_declared_total(document: &gltf::Document) -> Result<(), Vec<GltfProblem>> {
    let mut total: u64 = 0;
    for buffer in document.buffers() {
        total = total.saturating_add(buffer.length() as u64);
        if total > MAX_BUFFER_BYTES {
            let message = format!(
                "brings the file's buffers to {total} bytes, over the {MAX_BUFFER_BYTES} read from one \
                 glTF file"
            );
            return Err(vec![GltfProblem::new(format!("buffers[{}].byteLength", buffer.index()), message)]);
        }
    }
    Ok(())
}

/// An embedded buffer, or a file inside the glTF's folder.
fn from_uri(uri: &str, folder: &Path, declared: u64) -> Result<Vec<u8>, String> {
    if uri.starts_with("data:") {
        // Held to `byteLength` before decoding, as a file is: base64 takes 4 digits for 3 bytes.
        let digits = uri.split_once(',').map_or(0, |(_, data)| data.trim_end_matches('=').len() as u64);
        if digits > declared.div_ceil(3) * 4 {
            return Err(format!(
                "embedded buffer: {digits} base64 digits hold more than the {declared} bytes of byteLength"
            ));
        }
        return decode_data_uri(uri).map_err(|e| format!("embedded buffer: {e}"));
    }
    if let Some((scheme, _)) = uri.split_once(':')
        && scheme.len() > 1
        && scheme.chars().all(|c| c.is_ascii_alphanumeric() || "+-.".contains(c))
    {
        return Err(format!("\"{uri}\": only relative file paths and data: URIs are supported"));
    }
    from_file(&percent_decode(uri)?, folder, declared)
}

/// The first `declared` bytes of the file `relative` inside `folder`, its length checked first.
fn from_file(relative: &str, folder: &Path, declared: u64) -> Result<Vec<u8>, String> {
    let inside = open_inside(folder, relative).map_err(|m| format!("buffer file: {m}"))?;
    let shown = inside.path.display();
    if inside.len_bytes > MAX_BUFFER_BYTES {
        return Err(format!(
            "buffer file {shown} is {} bytes, more than the {MAX_BUFFER_BYTES} read from one glTF file",
            inside.len_bytes
        ));
    }
    if inside.len_bytes < declared {
        return Err(format!(
            "buffer file {shown} is {} bytes, fewer than the buffer's byteLength {declared}",
            inside.len_bytes
        ));
    }
    let mut bytes = Vec::with_capacity(declared as usize);
    (inside.file.take(declared).read_to_end(&mut bytes))
        .map_err(|e| format!("cannot read buffer file {shown}: {e}"))?;
    if (bytes.len() as u64) < declared {
        return Err(format!(
            "buffer file {shown} ended after {} of its byteLength {declared} bytes",
            bytes.len()
        ));
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Only `byteLength` bytes of a longer file are read, and a shorter file is refused by its
    /// length, before reading.
    #[test]
    fn buffer_files_are_read_up_to_their_declared_length() {
        let dir = tempfile::tempdir().unwrap();
        let bytes: Vec<u8> = (0..1000u32).map(|i| i as u8).collect();
        std::fs::write(dir.path().join("long.bin"), &bytes).unwrap();
        assert_eq!(from_uri("long.bin", dir.path(), 168).unwrap(), bytes[..168]);
        assert_eq!(from_uri("long%2Ebin", dir.path(), 0).unwrap(), Vec::<u8>::new());
        let error = from_uri("long.bin", dir.path(), 1001).unwrap_err();
        assert!(error.contains("1000 bytes, fewer than the buffer's byteLength 1001"), "{error}");
        let error = from_uri("../long.bin", &dir.path().join("sub"), 10).unwrap_err();
        assert!(error.contains("leaves the folder"), "{error}");
    }
}
