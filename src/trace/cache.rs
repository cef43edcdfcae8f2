//! The reference cache under `references/`: one hard mask PNG per (scene, camera, light), one
//! soft reference EXR per (scene, camera, light, kind, sample grid), and a manifest with the
//! digest of everything each file depends on (geometry, camera, light and its area size, kind,
//! sample count, sampling scheme, tracer version). A file whose digest no longer matches is
//! traced again.
//!
//! Manifest keys: `scene/camera/light` for hard masks (as before soft references existed, so
//! older manifests stay valid) and `scene/camera/light/KIND-NxN` for soft ones (`coverage`,
//! `area`), so that every kind and grid of one view coexists. An entry records its `kind` and
//! `samples` per pixel; both are left out for hard masks (kind `hard`, 1 sample), so older
//! manifests read unchanged and hard entries are written as before.
//!
//! Runs may share one cache folder concurrently. Each writes its file (atomically) before its
//! manifest entry, and records the entry while holding an exclusive lock on `.manifest.lock`:
//! under the lock it re-reads the manifest, merges its entry in and writes the manifest back
//! atomically, so no run's entry is lost and readers (which take no lock) see the old manifest
//! or the new one, never a half-written one. Temporary files that killed runs left in the
//! folders written are removed on the way (`atomic_file::remove_stray_temp_files`).

use super::soft_reference::{SoftKind, SoftReference};
use super::{AreaLightError, TRACER_VERSION};
use crate::atomic_file::{encode_gray_png, remove_stray_temp_files, write_atomic};
use crate::scene::{Camera, Light, LightKind, LightSize, Scene, ViewKey};
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

pub const MANIFEST_FORMAT: &str = "shadowtruth/references/v1";

/// The file whose exclusive lock guards the manifest's read-modify-write (never removed: removing
/// a lock file lets two runs lock two different files).
pub const MANIFEST_LOCK_FILE: &str = ".manifest.lock";

#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Manifest {
    format: String,
    /// Key `scene/camera/light` (hard masks) or `scene/camera/light/KIND-NxN` (soft references).
    entries: BTreeMap<String, ManifestEntry>,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ManifestEntry {
    /// File path relative to the cache folder (a PNG mask or a soft reference EXR).
    mask: String,
    digest: String,
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
    }
}

/// A cache folder (normally `references/`).
pub struct ReferenceCache {
    dir: PathBuf,
}

/// The manifest key of a view's hard mask: `scene/camera/light`.
fn key(view: ViewKey) -> String {
    format!("{}/{}/{}", view.scene, view.camera, view.light)
}

/// The manifest key of a view's soft reference: `scene/camera/light/KIND-NxN`.
fn soft_key(view: ViewKey, kind: SoftKind, grid: u32) -> String {
    format!("{}/{}-{grid}x{grid}", key(view), kind.name())
}

impl ReferenceCache {
    pub fn new(dir: impl Into<PathBuf>) -> Self {
        ReferenceCache { dir: dir.into() }
    }

    pub fn dir(&self) -> &Path {
        &self.dir
    }

    fn manifest_path(&self) -> PathBuf {
        self.dir.join("manifest.json")
    }

    fn read_manifest(&self) -> Manifest {
        std::fs::read(self.manifest_path())
            .ok()
            .and_then(|b| serde_json::from_slice::<Manifest>(&b).ok())
            .filter(|m| m.format == MANIFEST_FORMAT)
            .unwrap_or_else(|| Manifest { format: MANIFEST_FORMAT.into(), entries: BTreeMap::new() })
    }

    /// The digest recorded for a mask, if any.
    pub fn recorded_digest(&self, view: ViewKey) -> Option<String> {
        self.read_manifest().entries.get(&key(view)).map(|e| e.digest.clone())
    }

    /// The path of a cached mask, relative to the cache folder: `scene/camera__light.png`.
    pub fn mask_path(view: ViewKey) -> String {
        format!("{}/{}__{}.png", view.scene, view.camera, view.light)
    }

    /// The cached mask when its recorded digest equals `digest` and the file decodes.
    pub fn load(&self, view: ViewKey, digest: &str) -> Option<CachedReference> {
        let manifest = self.read_manifest();
        let entry = manifest.entries.get(&key(view))?;
        if entry.digest != digest {
            return None;
        }
        let img = image::open(self.dir.join(&entry.mask)).ok()?.into_luma8();
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
        self.write_file(&rel, &encode_gray_png(width, height, codes)?)?;
        let entry =
            ManifestEntry { mask: rel, digest: digest.into(), width, height, kind: hard_kind(), samples: 1 };
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
        let file = std::fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(self.dir.join(MANIFEST_LOCK_FILE))?;
        fs4::FileExt::lock(&file)?;
        Ok(file)
    }

    /// The digest recorded for a soft reference, if any.
    pub fn recorded_soft_digest(&self, view: ViewKey, kind: SoftKind, grid: u32) -> Option<String> {
        self.read_manifest().entries.get(&soft_key(view, kind, grid)).map(|e| e.digest.clone())
    }

    /// The path of a cached soft reference, relative to the cache folder:
    /// `scene/camera__light.KIND-NxN.exr`.
    pub fn soft_path(view: ViewKey, kind: SoftKind, grid: u32) -> String {
        format!("{}/{}__{}.{}-{grid}x{grid}.exr", view.scene, view.camera, view.light, kind.name())
    }

    /// The cached soft reference when its recorded digest equals `digest` and the file decodes
    /// with the recorded size and sample count.
    pub fn load_soft(&self, view: ViewKey, kind: SoftKind, grid: u32, digest: &str) -> Option<SoftReference> {
        let manifest = self.read_manifest();
        let entry = manifest.entries.get(&soft_key(view, kind, grid))?;
        if entry.digest != digest || entry.kind != kind.name() || entry.samples != grid * grid {
            return None;
        }
        let reference = SoftReference::from_exr(&std::fs::read(self.dir.join(&entry.mask)).ok()?).ok()?;
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
        self.write_file(&rel, &reference.to_exr()?)?;
        let entry = ManifestEntry {
            mask: rel,
            digest: digest.into(),
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
        bvh: &super::SceneBvh,
        gbuffer: &super::GBuffer,
        camera: &Camera,
        light: &Light,
    ) -> std::io::Result<(super::HardReference, bool)> {
        let view = ViewKey::from_view(scene, camera, light);
        let digest = reference_digest(scene, camera, light);
        if let Some(cached) = self.load(view, &digest) {
            let reference = super::HardReference::from_mask_codes(cached.width, cached.height, &cached.codes);
            if reference.mask_codes(gbuffer) == cached.codes {
                return Ok((reference, true));
            }
        }
        let reference = super::trace_hard_reference(scene, bvh, gbuffer, light);
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
        bvh: &super::SceneBvh,
        gbuffer: &super::GBuffer,
        camera: &Camera,
        light: &Light,
        grid: u32,
    ) -> std::io::Result<(SoftReference, bool)> {
        self.soft_reference(scene, gbuffer, camera, light, SoftKind::Coverage, grid, || {
            Ok(super::trace_coverage_reference(scene, bvh, gbuffer, camera, light, grid))
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
        bvh: &super::SceneBvh,
        gbuffer: &super::GBuffer,
        camera: &Camera,
        light: &Light,
        grid: u32,
    ) -> std::io::Result<(SoftReference, bool)> {
        let invalid = |e: AreaLightError| std::io::Error::new(std::io::ErrorKind::InvalidInput, e);
        super::validate_area_light(light, grid).map_err(invalid)?;
        self.soft_reference(scene, gbuffer, camera, light, SoftKind::AreaLight, grid, || {
            super::trace_area_light_reference(scene, bvh, gbuffer, light, grid).map_err(invalid)
        })
    }

    #[allow(clippy::too_many_arguments)]
    fn soft_reference(
        &self,
        scene: &Scene,
        gbuffer: &super::GBuffer,
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
