//! The reference cache under `references/`: one hard mask PNG per (scene, camera, light), one
//! soft reference EXR per (scene, camera, light, kind, sample grid), and a manifest with the
//! digest of everything each file depends on (geometry, camera, light and its area size, kind,
//! sample count, sampling scheme, tracer version) and the SHA-256 of the file's bytes. A file
//! whose digest no longer matches, or whose bytes are not those recorded, is traced again.
//!
//! Names are data, never paths: every file is named by its view's stem (`ViewKey::file_stem`,
//! `src/file_name.rs`), `<scene>.<camera>.<light>.<digest>.png` for a hard mask and
//! `….<KIND>-NxN.exr` for a soft reference, directly in the cache folder, whatever the names
//! hold. A manifest entry names its file, and an entry naming any other file than its view's is
//! ignored, so that the manifest cannot point a read elsewhere.
//!
//! Manifest keys: the view's names, each with `%` written `%25` and `/` written `%2F`, joined by
//! `/` (`scene/camera/light` for plain names, and no two views share a key), then `/KIND-NxN`
//! for soft references (`coverage`, `area`), so that every kind and grid of one view coexists.
//! An entry records its `kind` and `samples` per pixel; both are left out for hard masks (kind
//! `hard`, 1 sample). A manifest of another format (the earlier `references/v1`, whose keys
//! could collide) is ignored as a whole: its views are traced again, never misread.
//!
//! Every read is bounded first: the manifest and each file must be regular files under a size
//! limit (a file's from its recorded size), a file's SHA-256 is checked before its header, and
//! its header's size against the entry before its pixels are decoded.
//!
//! Runs may share one cache folder concurrently. Each writes its file (atomically) before its
//! manifest entry, and records the entry while holding an exclusive lock on `.manifest.lock`:
//! under the lock it re-reads the manifest, merges its entry in and writes the manifest back
//! atomically, so no run's entry is lost and readers (which take no lock) see the old manifest
//! or the new one, never a half-written one. Temporary files that killed runs left in the
//! folders written are removed on the way (`atomic_file::remove_stray_temp_files`).

use super::area_light::{AreaLightError, trace_area_light_reference, validate_area_light};
use super::coverage::trace_coverage_reference;
use super::gbuffer::GBuffer;
use super::hard::{HardReference, trace_hard_reference};
use super::soft_reference::{SoftKind, SoftReference};
use crate::atomic_file::{encode_gray_png, remove_stray_temp_files, write_atomic};
use crate::scene::{Camera, Light, LightKind, LightSize, Scene, ViewKey};
use crate::trace::TRACER_VERSION;
use crate::trace::bvh::scene_bvh::SceneBvh;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::io::Cursor;
use std::path::{Path, PathBuf};

/// The manifest's format: v2 keys cannot collide and entries record their file's SHA-256.
pub const MANIFEST_FORMAT: &str = "shadowtruth/references/v2";

/// The file whose exclusive lock guards the manifest's read-modify-write (never removed: removing
/// a lock file lets two runs lock two different files).
pub const MANIFEST_LOCK_FILE: &str = ".manifest.lock";

/// The manifest's file in the cache folder.
const MANIFEST_FILE: &str = "manifest.json";

/// The largest manifest read (a larger one is ignored, as a broken one is): some 100 000
/// entries.
const MAX_MANIFEST_BYTES: u64 = 64 << 20;

/// The most pixels of a cached file: a camera's most (the scene format's limit).
const MAX_CACHED_PIXELS: u64 = crate::scene::MAX_IMAGE_PIXELS;

#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Manifest {
    format: String,
    /// Key: the view's escaped names (`key`), then `/KIND-NxN` for soft references.
    entries: BTreeMap<String, ManifestEntry>,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ManifestEntry {
    /// File path relative to the cache folder (a PNG mask or a soft reference EXR): always the
    /// view's own (`mask_path`, `soft_path`); an entry naming another file is ignored.
    mask: String,
    digest: String,
    /// The SHA-256 of the file's bytes (hex), checked before the file is decoded.
    sha256: String,
    width: u32,
    height: u32,
    /// `hard` (absent), `coverage` or `area`.
    #[serde(default = "hard_kind", skip_serializing_if = "is_hard")]
    kind: String,
    /// Samples per pixel (absent: 1, a hard mask).
    #[serde(default = "one", skip_serializing_if = "is_one")]
    samples: u32,
}

fn hard_kind() -> String {
    "hard".into()
}
fn is_hard(kind: &str) -> bool {
    kind == "hard"
}
fn one() -> u32 {
    1
}
fn is_one(n: &u32) -> bool {
    *n == 1
}

/// Bumped whenever a change to the soft references' sample patterns or estimators could change
/// a bit (hard masks do not depend on it).
const SOFT_SAMPLING_VERSION: &str = "soft-sampling/1";

/// A mask read back from the cache, in the `MaskCode` encoding.
pub struct CachedReference {
    pub width: u32,
    pub height: u32,
    pub codes: Vec<u8>,
}

/// The digest of what the hard reference of (scene, camera, light) depends on.
pub fn reference_digest(scene: &Scene, camera: &Camera, light: &Light) -> String {
    let mut h = Sha256::new();
    h.update(TRACER_VERSION.as_bytes());
    h.update(b"\0hard\0");
    hash_view(&mut h, scene, camera, light);
    crate::scene::hex(&h.finalize())
}

/// The digest of what a soft reference of (scene, camera, light) on an n×n grid (`grid` = n)
/// depends on: the view as for the hard reference, plus the kind, the sample count, the light's
/// area size and the sampling scheme's version.
pub fn soft_reference_digest(
    scene: &Scene,
    camera: &Camera,
    light: &Light,
    kind: SoftKind,
    grid: u32,
) -> String {
    let mut h = Sha256::new();
    h.update(TRACER_VERSION.as_bytes());
    h.update(b"\0");
    h.update(kind.name().as_bytes());
    h.update(b"\0");
    h.update(SOFT_SAMPLING_VERSION.as_bytes());
    h.update(b"\0");
    hash_view(&mut h, scene, camera, light);
    h.update(b"samples");
    h.update(grid.to_le_bytes());
    // Both fields, each present or absent, as when a light could hold both sizes.
    let size = light.size().ok();
    for field in [LightSize::ANGULAR_DIAMETER_FIELD, LightSize::RADIUS_FIELD] {
        h.update(field.as_bytes());
        match size.filter(|s| s.field() == field) {
            Some(s) => {
                h.update([1]);
                h.update(s.value().to_bits().to_le_bytes());
            }
            None => h.update([0]),
        }
    }
    crate::scene::hex(&h.finalize())
}

/// Geometry, camera and light (without its area size): the bytes hashed for every kind.
fn hash_view(h: &mut Sha256, scene: &Scene, camera: &Camera, light: &Light) {
    h.update(scene.geometry_digest().as_bytes());
    let floats = |h: &mut Sha256, xs: &[f32]| xs.iter().for_each(|x| h.update(x.to_bits().to_le_bytes()));
    floats(h, &camera.position.to_array());
    floats(h, &camera.look_at.to_array());
    floats(h, &camera.up.to_array());
    floats(h, &[camera.fov_y_deg]);
    h.update(camera.width.to_le_bytes());
    h.update(camera.height.to_le_bytes());
    match &light.kind {
        LightKind::Directional { direction, .. } => {
            h.update(b"directional");
            floats(h, &direction.to_array());
        }
        LightKind::Spot { position, direction, cone_deg, near, far, .. } => {
            h.update(b"spot");
            floats(h, &position.to_array());
            floats(h, &direction.to_array());
            floats(h, &[*cone_deg, *near, *far]);
        }
        // The map's near plane and cube are no part of the reference: only the range is.
        LightKind::Point { position, far, .. } => {
            h.update(b"point");
            floats(h, &position.to_array());
            floats(h, &[*far]);
        }
    }
}

/// A cache folder (normally `references/`).
pub struct ReferenceCache {
    dir: PathBuf,
}

/// The manifest key of a view's hard mask: its names escaped and joined, `scene/camera/light`
/// for plain names. Escaping `%` and `/` makes the key injective: `a/b` + `c` is `a%2Fb/c`,
/// `a` + `b/c` is `a/b%2Fc`.
fn key(view: ViewKey) -> String {
    view.parts().map(|name| name.replace('%', "%25").replace('/', "%2F")).join("/")
}

/// The manifest key of a view's soft reference: `key/KIND-NxN`.
fn soft_key(view: ViewKey, kind: SoftKind, grid: u32) -> String {
    format!("{}/{}-{grid}x{grid}", key(view), kind.name())
}

/// The SHA-256 of `bytes`, in hex.
fn sha256_hex(bytes: &[u8]) -> String {
    crate::scene::hex(&Sha256::digest(bytes))
}

/// The bytes of `rel` in the cache folder when it is a regular file inside it (not a FIFO or
/// device, which could block, nor a link out of the folder) of at most `max_bytes`.
fn read_cached_file(dir: &Path, rel: &str, max_bytes: u64) -> Option<Vec<u8>> {
    crate::input_file::read_inside(dir, rel, max_bytes).ok().map(|(_, bytes)| bytes)
}

/// The most bytes a cached file of `entry`'s size may take: its pixels' bytes uncompressed
/// (`bytes_per_pixel` each) twice over, plus room for headers; None for a size no camera has.
fn max_file_bytes(entry: &ManifestEntry, bytes_per_pixel: u64) -> Option<u64> {
    let pixels = entry.width as u64 * entry.height as u64;
    (pixels > 0 && pixels <= MAX_CACHED_PIXELS).then(|| 2 * pixels * bytes_per_pixel + (1 << 20))
}

/// The width and height a PNG's header gives, without decoding its pixels.
fn png_size(bytes: &[u8]) -> Option<(u32, u32)> {
    image::ImageReader::with_format(Cursor::new(bytes), image::ImageFormat::Png).into_dimensions().ok()
}

/// The width and height an EXR's first header gives, without decoding its pixels.
fn exr_size(bytes: &[u8]) -> Option<(u32, u32)> {
    let meta = exr::meta::MetaData::read_from_buffered(Cursor::new(bytes), false).ok()?;
    let size = meta.headers.first()?.layer_size;
    Some((u32::try_from(size.width()).ok()?, u32::try_from(size.height()).ok()?))
}

impl ReferenceCache {
    pub fn new(dir: impl Into<PathBuf>) -> Self {
        ReferenceCache { dir: dir.into() }
    }

    pub fn dir(&self) -> &Path {
        &self.dir
    }

    fn manifest_path(&self) -> PathBuf {
        self.dir.join(MANIFEST_FILE)
    }

    /// The manifest as it is on disk; an empty one when there is none, or it is unreadable, too
    /// large or of another format.
    fn read_manifest(&self) -> Manifest {
        read_cached_file(&self.dir, MANIFEST_FILE, MAX_MANIFEST_BYTES)
            .and_then(|b| serde_json::from_slice::<Manifest>(&b).ok())
            .filter(|m| m.format == MANIFEST_FORMAT)
            .unwrap_or_else(|| Manifest { format: MANIFEST_FORMAT.into(), entries: BTreeMap::new() })
    }

    /// The digest recorded for a mask, if any.
    pub fn recorded_digest(&self, view: ViewKey) -> Option<String> {
        self.read_manifest().entries.get(&key(view)).map(|e| e.digest.clone())
    }

    /// The path of a cached mask, relative to the cache folder: `<view stem>.png`
    /// (`ViewKey::file_stem`).
    pub fn mask_path(view: ViewKey) -> String {
        format!("{}.png", view.file_stem())
    }

    /// The bytes of `entry`'s file when the entry names `rel` (the view's own file), the file
    /// is no larger than its size allows and its SHA-256 is the one recorded.
    fn read_verified(&self, entry: &ManifestEntry, rel: &str, bytes_per_pixel: u64) -> Option<Vec<u8>> {
        if entry.mask != rel {
            return None;
        }
        let bytes = read_cached_file(&self.dir, rel, max_file_bytes(entry, bytes_per_pixel)?)?;
        (sha256_hex(&bytes) == entry.sha256).then_some(bytes)
    }

    /// The cached mask when its recorded digest equals `digest`, its bytes are those recorded
    /// and it decodes at the recorded size.
    pub fn load(&self, view: ViewKey, digest: &str) -> Option<CachedReference> {
        let manifest = self.read_manifest();
        let entry = manifest.entries.get(&key(view))?;
        if entry.digest != digest {
            return None;
        }
        let bytes = self.read_verified(entry, &Self::mask_path(view), 1)?;
        if png_size(&bytes)? != (entry.width, entry.height) {
            return None;
        }
        let img = image::load_from_memory_with_format(&bytes, image::ImageFormat::Png).ok()?.into_luma8();
        if img.width() != entry.width || img.height() != entry.height {
            return None;
        }
        Some(CachedReference { width: img.width(), height: img.height(), codes: img.into_raw() })
    }

    /// Writes a mask and records it in the manifest (both atomically).
    pub fn store(
        &self,
        view: ViewKey,
        digest: &str,
        width: u32,
        height: u32,
        codes: &[u8],
    ) -> std::io::Result<()> {
        let rel = Self::mask_path(view);
        let bytes = encode_gray_png(width, height, codes)?;
        self.write_file(&rel, &bytes)?;
        let entry = ManifestEntry {
            mask: rel,
            digest: digest.into(),
            sha256: sha256_hex(&bytes),
            width,
            height,
            kind: hard_kind(),
            samples: 1,
        };
        self.record(key(view), entry)
    }

    /// Writes a cached file (atomically), first removing stray temporary files from its folder.
    fn write_file(&self, rel: &str, bytes: &[u8]) -> std::io::Result<()> {
        let path = self.dir.join(rel);
        remove_stray_temp_files(path.parent().unwrap_or(&self.dir))?;
        write_atomic(&path, bytes)
    }

    /// Adds or replaces one manifest entry: under the manifest lock, the manifest as it is now
    /// (other runs may have added entries since it was last read) with the entry merged in is
    /// rewritten atomically.
    fn record(&self, key: String, entry: ManifestEntry) -> std::io::Result<()> {
        let _lock = self.lock_manifest()?;
        remove_stray_temp_files(&self.dir)?;
        let mut manifest = self.read_manifest();
        manifest.entries.insert(key, entry);
        let mut text = serde_json::to_string_pretty(&manifest).map_err(std::io::Error::other)?;
        text.push('\n');
        write_atomic(&self.manifest_path(), text.as_bytes())
    }

    /// The manifest lock file, exclusively locked (the lock is released when it drops).
    fn lock_manifest(&self) -> std::io::Result<std::fs::File> {
        std::fs::create_dir_all(&self.dir)?;
        let path = self.dir.join(MANIFEST_LOCK_FILE);
        let file = crate::output_lock::open_lock_file(&path)
            .map_err(|e| std::io::Error::new(e.kind(), format!("{}: {e}", path.display())))?;
        fs4::FileExt::lock(&file)?;
        Ok(file)
    }

    /// The path of a cached soft reference, relative to the cache folder:
    /// `<view stem>.KIND-NxN.exr` (`ViewKey::file_stem`).
    pub fn soft_path(view: ViewKey, kind: SoftKind, grid: u32) -> String {
        format!("{}.{}-{grid}x{grid}.exr", view.file_stem(), kind.name())
    }

    /// The cached soft reference when its recorded digest equals `digest`, its bytes are those
    /// recorded and it decodes with the recorded size and sample count.
    pub fn load_soft(&self, view: ViewKey, kind: SoftKind, grid: u32, digest: &str) -> Option<SoftReference> {
        let manifest = self.read_manifest();
        let entry = manifest.entries.get(&soft_key(view, kind, grid))?;
        if entry.digest != digest || entry.kind != kind.name() || entry.samples != grid * grid {
            return None;
        }
        // Two f32 channels, V and E.
        let bytes = self.read_verified(entry, &Self::soft_path(view, kind, grid), 8)?;
        if exr_size(&bytes)? != (entry.width, entry.height) {
            return None;
        }
        let reference = SoftReference::from_exr(&bytes).ok()?;
        (reference.width == entry.width
            && reference.height == entry.height
            && reference.samples == entry.samples)
            .then_some(reference)
    }

    /// Writes a soft reference (EXR) and records it in the manifest (both atomically), under the
    /// n×n grid of its `samples`.
    pub fn store_soft(
        &self,
        view: ViewKey,
        kind: SoftKind,
        digest: &str,
        reference: &SoftReference,
    ) -> std::io::Result<()> {
        let grid = reference.samples.isqrt();
        let rel = Self::soft_path(view, kind, grid);
        let bytes = reference.to_exr()?;
        self.write_file(&rel, &bytes)?;
        let entry = ManifestEntry {
            mask: rel,
            digest: digest.into(),
            sha256: sha256_hex(&bytes),
            width: reference.width,
            height: reference.height,
            kind: kind.name().into(),
            samples: reference.samples,
        };
        self.record(soft_key(view, kind, grid), entry)
    }
}

impl ReferenceCache {
    /// The hard reference of (scene, camera, light): read from the cache when its digest matches
    /// and its classes agree with `gbuffer`, traced (and stored) otherwise. Returns whether it
    /// came from the cache.
    pub fn hard_reference(
        &self,
        scene: &Scene,
        bvh: &SceneBvh,
        gbuffer: &GBuffer,
        camera: &Camera,
        light: &Light,
    ) -> std::io::Result<(HardReference, bool)> {
        let view = ViewKey::from_view(scene, camera, light);
        let digest = reference_digest(scene, camera, light);
        if let Some(cached) = self.load(view, &digest)
            && (cached.width, cached.height) == (gbuffer.width, gbuffer.height)
        {
            let reference = HardReference::from_mask_codes(cached.width, cached.height, &cached.codes);
            if reference.mask_codes(gbuffer) == cached.codes {
                return Ok((reference, true));
            }
        }
        let reference = trace_hard_reference(scene, bvh, gbuffer, light);
        let codes = reference.mask_codes(gbuffer);
        self.store(view, &digest, gbuffer.width, gbuffer.height, &codes)?;
        Ok((reference, false))
    }
}

impl ReferenceCache {
    /// The pixel-coverage reference on an n×n sub-pixel grid (`grid` = n): read from the cache
    /// when its digest matches and it fits `gbuffer`, traced (and stored) otherwise. Returns
    /// whether it came from the cache. Panics if `grid` is 0, as `trace_coverage_reference`.
    pub fn coverage_reference(
        &self,
        scene: &Scene,
        bvh: &SceneBvh,
        gbuffer: &GBuffer,
        camera: &Camera,
        light: &Light,
        grid: u32,
    ) -> std::io::Result<(SoftReference, bool)> {
        self.soft_reference(scene, gbuffer, camera, light, SoftKind::Coverage, grid, || {
            Ok(trace_coverage_reference(scene, bvh, gbuffer, camera, light, grid))
        })
    }

    /// The area-light reference with n×n light samples (`grid` = n): read from the cache when
    /// its digest matches and it fits `gbuffer`, traced (and stored) otherwise. Returns whether
    /// it came from the cache. A light without a size (or a zero grid) is an error of kind
    /// `InvalidInput` wrapping the `AreaLightError` (reach it with `get_ref()` and
    /// `downcast_ref`); its message names the light and the missing field.
    pub fn area_light_reference(
        &self,
        scene: &Scene,
        bvh: &SceneBvh,
        gbuffer: &GBuffer,
        camera: &Camera,
        light: &Light,
        grid: u32,
    ) -> std::io::Result<(SoftReference, bool)> {
        let invalid = |e: AreaLightError| std::io::Error::new(std::io::ErrorKind::InvalidInput, e);
        validate_area_light(light, grid).map_err(invalid)?;
        self.soft_reference(scene, gbuffer, camera, light, SoftKind::AreaLight, grid, || {
            trace_area_light_reference(scene, bvh, gbuffer, light, grid).map_err(invalid)
        })
    }

    #[allow(clippy::too_many_arguments)]
    fn soft_reference(
        &self,
        scene: &Scene,
        gbuffer: &GBuffer,
        camera: &Camera,
        light: &Light,
        kind: SoftKind,
        grid: u32,
        trace: impl FnOnce() -> std::io::Result<SoftReference>,
    ) -> std::io::Result<(SoftReference, bool)> {
        let view = ViewKey::from_view(scene, camera, light);
        let digest = soft_reference_digest(scene, camera, light, kind, grid);
        if let Some(cached) = self.load_soft(view, kind, grid, &digest)
            && cached.fits(gbuffer)
        {
            return Ok((cached, true));
        }
        let reference = trace()?;
        self.store_soft(view, kind, &digest, &reference)?;
        Ok((reference, false))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entry_of(cache: &ReferenceCache, key: &str) -> ManifestEntry {
        cache.read_manifest().entries[key].clone()
    }

    fn write_manifest(cache: &ReferenceCache, manifest: &Manifest) {
        std::fs::write(cache.manifest_path(), serde_json::to_vec(manifest).unwrap()).unwrap();
    }

    #[test]
    fn keys_and_file_names_cannot_collide() {
        let pairs = [
            (ViewKey::new("s", "a/b", "c"), ViewKey::new("s", "a", "b/c")),
            (ViewKey::new("s", "a__b", "c"), ViewKey::new("s", "a", "b__c")),
            (ViewKey::new("s%2Fa", "b", "c"), ViewKey::new("s/a", "b", "c")),
        ];
        for (one, other) in pairs {
            assert_ne!(key(one), key(other));
            assert_ne!(ReferenceCache::mask_path(one), ReferenceCache::mask_path(other));
        }
        assert_eq!(
            key(ViewKey::new("plane_box", "main", "sun")),
            "plane_box/main/sun",
            "plain names read as they are"
        );
        for hostile in ["../../x", "/abs", "a\0b", ""] {
            let path = ReferenceCache::mask_path(ViewKey::new(hostile, hostile, hostile));
            assert!(!path.contains('/') && !path.starts_with('.'), "{path:?}");
        }
    }

    #[test]
    fn an_entry_naming_another_file_is_ignored() {
        let dir = tempfile::tempdir().unwrap();
        let cache = ReferenceCache::new(dir.path());
        let (one, other) = (ViewKey::new("s", "c", "one"), ViewKey::new("s", "c", "other"));
        cache.store(one, "d1", 2, 1, &[0, 255]).unwrap();
        cache.store(other, "d2", 2, 1, &[255, 0]).unwrap();
        // One's entry now names the other's file, with that file's own SHA-256.
        let mut manifest = cache.read_manifest();
        let theirs = entry_of(&cache, &key(other));
        let mine = manifest.entries.get_mut(&key(one)).unwrap();
        (mine.mask, mine.sha256) = (theirs.mask, theirs.sha256);
        write_manifest(&cache, &manifest);
        assert!(cache.load(one, "d1").is_none());
        assert_eq!(cache.load(other, "d2").unwrap().codes, [255, 0]);
    }

    #[test]
    fn bytes_and_sizes_other_than_recorded_are_not_read() {
        let dir = tempfile::tempdir().unwrap();
        let cache = ReferenceCache::new(dir.path());
        let view = ViewKey::new("s", "c", "l");
        cache.store(view, "d", 2, 1, &[0, 255]).unwrap();
        assert!(cache.load(view, "d").is_some());
        let path = dir.path().join(ReferenceCache::mask_path(view));
        // Another valid PNG of the right size.
        std::fs::write(&path, encode_gray_png(2, 1, &[255, 255]).unwrap()).unwrap();
        assert!(cache.load(view, "d").is_none(), "another PNG of the right size");
        // The right bytes under an entry of another size.
        std::fs::write(&path, encode_gray_png(2, 1, &[0, 255]).unwrap()).unwrap();
        let mut manifest = cache.read_manifest();
        manifest.entries.get_mut(&key(view)).unwrap().width = 1;
        write_manifest(&cache, &manifest);
        assert!(cache.load(view, "d").is_none(), "a header of another size");
    }

    #[test]
    fn a_v1_manifest_is_ignored_and_replaced() {
        let dir = tempfile::tempdir().unwrap();
        let cache = ReferenceCache::new(dir.path());
        let view = ViewKey::new("s", "c", "l");
        cache.store(view, "d", 2, 1, &[0, 255]).unwrap();
        let mut manifest = cache.read_manifest();
        manifest.format = "shadowtruth/references/v1".into();
        write_manifest(&cache, &manifest);
        assert!(cache.load(view, "d").is_none() && cache.recorded_digest(view).is_none());
        cache.store(ViewKey::new("s", "c", "m"), "d", 2, 1, &[0, 255]).unwrap();
        assert_eq!(cache.read_manifest().entries.len(), 1, "only the new entry");
    }

    #[cfg(unix)]
    #[test]
    fn a_fifo_in_place_of_a_file_is_not_opened() {
        let dir = tempfile::tempdir().unwrap();
        let cache = ReferenceCache::new(dir.path());
        let view = ViewKey::new("s", "c", "l");
        cache.store(view, "d", 2, 1, &[0, 255]).unwrap();
        for path in [dir.path().join(ReferenceCache::mask_path(view)), cache.manifest_path()] {
            std::fs::remove_file(&path).unwrap();
            let made = std::process::Command::new("mkfifo").arg(&path).status().unwrap();
            assert!(made.success());
            // Opening a FIFO for reading blocks until a writer comes: this returns at once.
            assert!(cache.load(view, "d").is_none());
        }
    }
}
