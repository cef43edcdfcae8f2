//! A binary cache of parsed OBJ meshes, so that a large mesh is parsed once: OBJ text is slow
//! to parse, its binary form is read at disk speed (docs/conventions.md, "Mesh cache").
//!
//! The cache of `DIR/name.obj` is `DIR/.shadowtruth-mesh-cache/name.obj.mesh`, written
//! atomically (src/atomic_file.rs) after a successful parse of an OBJ file of at least
//! `MIN_CACHED_BYTES`. It records the OBJ's name, size and modification time and a checksum of
//! its contents; one whose record does not match the OBJ, or that is short, corrupt or of
//! another version, is ignored (and rewritten by the next parse), never trusted.

use super::shapes::IndexedMesh;
use glam::DVec3;
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::time::UNIX_EPOCH;

/// The folder, beside the OBJ files, that holds their caches.
pub const MESH_CACHE_DIR: &str = ".shadowtruth-mesh-cache";
/// Smaller OBJ files parse in a few milliseconds: they are not cached.
pub const MIN_CACHED_BYTES: u64 = 8 << 20;
/// Format and version (any change to the layout changes it).
const MAGIC: &[u8; 16] = b"shadowtruth-msh1";
const HEADER_BYTES: usize = 64;
const VERTEX_BYTES: usize = 12;
const TRIANGLE_BYTES: usize = 12;

/// What a cache entry must match: the OBJ's size and modification time.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) struct SourceKey {
    bytes: u64,
    modified_s: u64,
    modified_ns: u32,
}

impl SourceKey {
    /// The key of the OBJ at `obj`, if it is large enough to be cached and has a modification
    /// time.
    pub fn of(obj: &Path) -> Option<SourceKey> {
        let meta = std::fs::metadata(obj).ok()?;
        let since = meta.modified().ok()?.duration_since(UNIX_EPOCH).ok()?;
        (meta.len() >= MIN_CACHED_BYTES).then_some(SourceKey {
            bytes: meta.len(),
            modified_s: since.as_secs(),
            modified_ns: since.subsec_nanos(),
        })
    }
}

/// The cache file of the OBJ at `obj`.
pub fn mesh_cache_path(obj: &Path) -> Option<PathBuf> {
    let name = obj.file_name()?;
    let mut file = name.to_os_string();
    file.push(".mesh");
    Some(obj.parent().unwrap_or(Path::new("")).join(MESH_CACHE_DIR).join(file))
}

/// The cached mesh of `obj`, if its cache is present, intact and made from this version of it.
pub(super) fn read_cached(obj: &Path, key: SourceKey) -> Option<IndexedMesh> {
    let folder = obj.parent().unwrap_or(Path::new(""));
    let relative = Path::new(MESH_CACHE_DIR).join(mesh_cache_path(obj)?.file_name()?);
    // The cache is read as the OBJ is: a regular file inside the scene's folder (a scene that
    // arrives as an archive may bring a cache that links elsewhere), of a bounded size.
    let (_, bytes) = crate::input_file::read_inside(folder, relative.to_str()?, max_cache_bytes(key)).ok()?;
    decode(&bytes, &name_of(obj), key)
}

/// The largest cache of an OBJ of `key.bytes`: a cached vertex or triangle takes 12 bytes, and
/// the OBJ at least 2 for each (`v 0 0 0` is 8 bytes; each further index ` 9` of a polygon's
/// `f` line adds a triangle).
fn max_cache_bytes(key: SourceKey) -> u64 {
    // Nor more than a mesh of a scene's most triangles, each with three vertices of its own.
    let most = (VERTEX_BYTES * 3 + TRIANGLE_BYTES) as u64 * crate::scene::MAX_SCENE_TRIANGLES;
    HEADER_BYTES as u64 + key.bytes.saturating_mul(6).min(most)
}

/// Stores `mesh` as the cache of `obj`; a cache that cannot be written is only a missed
/// speed-up, so errors are dropped.
pub(super) fn write_cached(obj: &Path, key: SourceKey, mesh: &IndexedMesh) {
    let (Some(path), Some(bytes)) = (mesh_cache_path(obj), encode(mesh, &name_of(obj), key)) else {
        return;
    };
    if let Some(dir) = path.parent() {
        // Never written through a link: the cache folder must be a folder of its own.
        if std::fs::symlink_metadata(dir).is_ok_and(|m| !m.is_dir()) {
            return;
        }
        let _ = std::fs::create_dir_all(dir);
        let _ = crate::atomic_file::remove_stray_temp_files(dir);
    }
    let _ = crate::atomic_file::write_atomic_unsynced(&path, &bytes);
}

fn name_of(obj: &Path) -> Vec<u8> {
    obj.file_name().map(|n| n.to_string_lossy().as_bytes().to_vec()).unwrap_or_default()
}

/// Header (little-endian): magic, OBJ size, modification time (s, ns), vertex and triangle
/// counts, checksum of the OBJ's name, the key and the payload; then f32 positions and u32
/// indices. None when a position is not an f32 (never from `parse_obj`).
fn encode(mesh: &IndexedMesh, name: &[u8], key: SourceKey) -> Option<Vec<u8>> {
    let exact = |p: &DVec3| p.as_vec3().as_dvec3() == *p;
    if !mesh.positions.par_iter().all(exact) {
        return None;
    }
    let payload = mesh.positions.len() * VERTEX_BYTES + mesh.triangles.len() * TRIANGLE_BYTES;
    let mut out = Vec::with_capacity(HEADER_BYTES + payload);
    out.extend_from_slice(MAGIC);
    for word in [key.bytes, key.modified_s, key.modified_ns as u64] {
        out.extend_from_slice(&word.to_le_bytes());
    }
    out.extend_from_slice(&(mesh.positions.len() as u64).to_le_bytes());
    out.extend_from_slice(&(mesh.triangles.len() as u64).to_le_bytes());
    out.extend_from_slice(&[0; 8]); // the checksum, filled in below
    for p in &mesh.positions {
        p.as_vec3().to_array().iter().for_each(|c| out.extend_from_slice(&c.to_le_bytes()));
    }
    for t in &mesh.triangles {
        t.iter().for_each(|i| out.extend_from_slice(&i.to_le_bytes()));
    }
    let sum = checksum(name, &out[..HEADER_BYTES - 8], &out[HEADER_BYTES..]);
    out[HEADER_BYTES - 8..HEADER_BYTES].copy_from_slice(&sum.to_le_bytes());
    Some(out)
}

fn decode(bytes: &[u8], name: &[u8], key: SourceKey) -> Option<IndexedMesh> {
    let header = bytes.get(..HEADER_BYTES)?;
    let word = |at: usize| u64::from_le_bytes(header[at..at + 8].try_into().expect("8 bytes"));
    let recorded = SourceKey { bytes: word(16), modified_s: word(24), modified_ns: word(32) as u32 };
    if &header[..16] != MAGIC || recorded != key || word(32) >> 32 != 0 {
        return None;
    }
    let (vertices, triangles) = (usize::try_from(word(40)).ok()?, usize::try_from(word(48)).ok()?);
    let positions_end = HEADER_BYTES.checked_add(vertices.checked_mul(VERTEX_BYTES)?)?;
    let end = positions_end.checked_add(triangles.checked_mul(TRIANGLE_BYTES)?)?;
    if bytes.len() != end || word(56) != checksum(name, &header[..HEADER_BYTES - 8], &bytes[HEADER_BYTES..]) {
        return None;
    }
    let f32_at = |b: &[u8], k: usize| f32::from_le_bytes(b[4 * k..4 * k + 4].try_into().expect("4 bytes"));
    let u32_at = |b: &[u8], k: usize| u32::from_le_bytes(b[4 * k..4 * k + 4].try_into().expect("4 bytes"));
    let positions: Vec<DVec3> = bytes[HEADER_BYTES..positions_end]
        .par_chunks_exact(VERTEX_BYTES)
        .map(|b| DVec3::new(f32_at(b, 0) as f64, f32_at(b, 1) as f64, f32_at(b, 2) as f64))
        .collect();
    let triangles: Vec<[u32; 3]> = bytes[positions_end..]
        .par_chunks_exact(TRIANGLE_BYTES)
        .map(|b| [0, 1, 2].map(|k| u32_at(b, k)))
        .collect();
    let in_range = |t: &[u32; 3]| t.iter().all(|&i| (i as usize) < vertices);
    let sound = positions.par_iter().all(|p| p.is_finite()) && triangles.par_iter().all(in_range);
    sound.then_some(IndexedMesh { positions, triangles })
}

/// A 64-bit checksum (FNV-style multiply–xor over 8-byte words, chunks combined in order): it
/// catches truncation and corruption, not tampering.
fn checksum(name: &[u8], header: &[u8], payload: &[u8]) -> u64 {
    const PRIME: u64 = 0x0000_0100_0000_01B3;
    let fold = |mut h: u64, bytes: &[u8]| {
        for chunk in bytes.chunks(8) {
            let mut word = [0u8; 8];
            word[..chunk.len()].copy_from_slice(chunk);
            h = (h ^ u64::from_le_bytes(word)).wrapping_mul(PRIME).rotate_left(31);
        }
        h ^ bytes.len() as u64
    };
    let chunks: Vec<u64> = payload.par_chunks(1 << 20).map(|c| fold(0xCBF2_9CE4_8422_2325, c)).collect();
    let head = fold(fold(0xCBF2_9CE4_8422_2325, name), header);
    chunks.iter().fold(head, |h, &c| (h ^ c).wrapping_mul(PRIME).rotate_left(31))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mesh() -> IndexedMesh {
        IndexedMesh {
            positions: vec![DVec3::ZERO, DVec3::X, DVec3::new(0.0, 1.5, -2.25)],
            triangles: vec![[0, 1, 2]],
        }
    }

    const KEY: SourceKey = SourceKey { bytes: 123, modified_s: 456, modified_ns: 789 };

    #[test]
    fn scene_mesh_cache_round_trips_and_refuses_what_does_not_match() {
        let bytes = encode(&mesh(), b"a.obj", KEY).expect("f32 positions");
        assert_eq!(decode(&bytes, b"a.obj", KEY), Some(mesh()));
        assert_eq!(decode(&bytes, b"b.obj", KEY), None, "another file's cache");
        let newer = SourceKey { modified_ns: 790, ..KEY };
        assert_eq!(decode(&bytes, b"a.obj", newer), None, "a modified OBJ");
        assert_eq!(decode(&bytes[..bytes.len() - 1], b"a.obj", KEY), None, "truncated");
        for at in [0, 20, HEADER_BYTES + 3, bytes.len() - 2] {
            let mut corrupt = bytes.clone();
            corrupt[at] ^= 0x10;
            assert_eq!(decode(&corrupt, b"a.obj", KEY), None, "byte {at} flipped");
        }
    }
}
